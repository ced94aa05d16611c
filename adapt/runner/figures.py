"""The run's figures, drawn with matplotlib into ``figures/``.

* ``sync.png`` -- the paper's Figure 4: real, synthetic (with its matched
  corners), warped synthetic, MMD mask and MMD image at the start of the run
  and after the camera synchronised;
* ``unexpected.png`` -- the paper's Figure 5, for runs where a schema was
  spawned for an unexpected difference: real, synthetic and MMD before the
  spawn, at it and after;
* ``camera.png`` -- the camera loop's pixel error over the run, and the
  synthetic camera's error against the true camera when there is ground truth;
* ``floor.png`` -- the floor plan: walls, obstacles, the observed, imagined,
  uncorrected and true paths of every object, a few of the mirror's predicted
  paths, and the robot's paths (odometry, truth, the Kalman baseline's);
* ``correction.png`` -- the paper's Figures 7 and 8: after an object was
  created in the imagination, the difference between the real frame and the
  uncorrected imagination (top row) and the corrected one (bottom row), on
  the same crop around the object;
* ``prediction.png`` -- for runs with predictions and ground truth: the
  mirror's and the baseline's prediction errors against the time they were
  made, and the mirror's confidence;
* ``appearance.png`` -- for runs whose Scene Background learned the surfaces'
  look: the real frame it learned from, the render before and after
  learning, and how far each differs from the real frame.

The data come from :class:`Snapshots` (a few frames kept by reference) and
:class:`Paths` (decimated series), so nothing grows with the run's length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from adapt.figures.strips import Panel, write_strip
from adapt.files import atomic_path
from adapt.scenario import Mount

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.runner import Runner

__all__ = ["Snapshot", "Snapshots", "Comparison", "Comparisons", "Paths", "write_figures",
           "PLANNED", "COMPARED_AFTER"]

#: Frames kept for the strips, besides spawns and the last frame.
PLANNED = (0, 1, 2, 3, 5, 8, 13, 21, 34)

#: Seconds after an object's creation at which the uncorrected and corrected imaginations
#: are compared (``correction.png``).
COMPARED_AFTER = (0.2, 0.6, 1.2, 2.0, 3.0)


@dataclass(frozen=True, slots=True, eq=False)
class Snapshot:
    """The images of one frame (references, not copies)."""

    index: int
    time: float
    real: NDArray[np.uint8]
    synthetic: NDArray[np.uint8] | None
    corners: NDArray[np.float64] | None
    warped: NDArray[np.uint8] | None
    mask: NDArray[np.float32] | None
    difference: NDArray[np.float32] | None
    pixel_error: float
    unexpected: tuple[tuple[int, int, int, int], ...]
    monitored: tuple[tuple[str, tuple[int, int, int, int]], ...]


class Snapshots:
    """The frames the strips need: the planned ones, a few around each spawn, the last."""

    def __init__(self, limit: int = 16) -> None:
        self.limit = limit
        self.kept: dict[int, Snapshot] = {}
        self.last: Snapshot | None = None
        self.spawns: list[int] = []
        self._want: set[int] = set(PLANNED)

    def wants(self, index: int) -> bool:
        """True when frame ``index`` should be kept."""
        return index in self._want

    def spawned(self, index: int) -> None:
        """A schema was spawned at frame ``index``: keep it and a few after."""
        if len(self.spawns) < 3:
            self.spawns.append(index)
            self._want.update({index, index + 5, index + 15})

    def add(self, snap: Snapshot) -> None:
        """Keep ``snap`` if wanted; always remember it as the last."""
        self.last = snap
        if snap.index in self._want and len(self.kept) < self.limit:
            self.kept[snap.index] = snap


@dataclass(frozen=True, slots=True, eq=False)
class Comparison:
    """One column of ``correction.png``: a crop of the real frame and its differences from
    the uncorrected and the corrected imagination (grey levels, same crop)."""

    index: int
    time: float
    after: float
    real: NDArray[np.uint8]
    uncorrected: NDArray[np.float32]
    corrected: NDArray[np.float32]


class Comparisons:
    """The frames compared after the first object created in the imagination."""

    def __init__(self) -> None:
        self.created: tuple[str, int] | None = None
        self.kept: list[Comparison] = []
        self._want: dict[int, float] = {}

    def created_at(self, name: str, index: int, fps: float) -> None:
        """Object ``name`` was created at frame ``index``: compare it at the planned times."""
        if self.created is None:
            self.created = (name, index)
            self._want = {index + max(1, round(a * fps)): a for a in COMPARED_AFTER}

    def wants(self, index: int) -> float | None:
        """Seconds after creation when frame ``index`` is to be compared, else None."""
        return self._want.get(index)

    def add(self, item: Comparison) -> None:
        self.kept.append(item)


@dataclass
class Paths:
    """Decimated series for the plots (at most ``limit`` points each)."""

    limit: int = 4000
    stride: int = 1
    count: int = 0
    time: list[float] = field(default_factory=list)
    pixel_error: list[float] = field(default_factory=list)
    camera_position: list[float] = field(default_factory=list)
    camera_rotation: list[float] = field(default_factory=list)
    observed: dict[str, list[tuple[float, float] | None]] = field(default_factory=dict)
    imagined: dict[str, list[tuple[float, float] | None]] = field(default_factory=dict)
    truth: dict[str, list[tuple[float, float] | None]] = field(default_factory=dict)
    uncorrected: dict[str, list[tuple[float, float] | None]] = field(default_factory=dict)
    robot: list[tuple[float, float] | None] = field(default_factory=list)
    robot_truth: list[tuple[float, float] | None] = field(default_factory=list)
    robot_baseline: list[tuple[float, float] | None] = field(default_factory=list)
    #: The mirror's confidence in its longest-horizon prediction of the target (NaN: none).
    confidence: list[float] = field(default_factory=list)
    #: A few of the mirror's predicted paths: (time made, (T, 2) positions).
    predicted: list[tuple[float, NDArray[np.float64]]] = field(default_factory=list)

    def add(self, record: dict[str, Any], pixel_error: float,
            robot: tuple[float, float] | None) -> None:
        """Take one frame's record (every ``stride``-th one is kept)."""
        self.count += 1
        if (self.count - 1) % self.stride:
            return
        n = len(self.time)
        self.time.append(float(record["t"]))
        self.pixel_error.append(pixel_error)
        cam = record.get("camera_pose_error") or {}
        self.camera_position.append(cam.get("position_m", math.nan) if cam else math.nan)
        self.camera_rotation.append(cam.get("rotation_deg", math.nan) if cam else math.nan)
        self.robot.append(robot)
        rob = record.get("robot") or {}
        self.robot_truth.append(_point(record.get("truth_robot")))
        self.robot_baseline.append(_point(rob.get("baseline")))
        self.confidence.append(_confidence(record))
        truth = record.get("truth") or {}
        uncorrected = record.get("uncorrected") or {}
        for name, obj in record["objects"].items():
            for store, value in ((self.observed, obj.get("observed")),
                                 (self.imagined, obj.get("imagined")),
                                 (self.uncorrected, uncorrected.get(name)),
                                 (self.truth, truth.get(name))):
                series = store.setdefault(name, [None] * n)
                series.append(_point(value))
        for store in (self.observed, self.imagined, self.uncorrected, self.truth):
            for series in store.values():
                while len(series) < n + 1:
                    series.append(None)
        if len(self.time) > self.limit:
            self._thin()

    def _thin(self) -> None:
        self.stride *= 2
        for key in ("time", "pixel_error", "camera_position", "camera_rotation", "robot",
                    "robot_truth", "robot_baseline", "confidence"):
            setattr(self, key, getattr(self, key)[::2])
        for store in (self.observed, self.imagined, self.uncorrected, self.truth):
            for name in store:
                store[name] = store[name][::2]


    def predicted_path(self, time: float, positions: NDArray[np.float64], limit: int = 4) -> None:
        """Keep one of the mirror's predicted paths (the first ``limit`` offered)."""
        if len(self.predicted) < limit:
            self.predicted.append((time, np.array(positions, float)))


def _point(value: Any) -> tuple[float, float] | None:
    return None if value is None else (float(value[0]), float(value[1]))


def _confidence(record: dict[str, Any]) -> float:
    """The confidence of the longest-horizon prediction of the first predicted object."""
    for preds in (record.get("predictions") or {}).values():
        if preds:
            last = max(preds, key=lambda p: float(p["horizon"]))
            return float(last.get("confidence", math.nan))
    return math.nan


def _save(fig: Any, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=100)
    return path


def _sync_rows(snaps: list[Snapshot]) -> list[list[Panel]]:
    rows = []
    for s in snaps:
        err = "no alignment" if math.isnan(s.pixel_error) else f"{s.pixel_error:.2f} px"
        head = f"t={s.time:.2f} s ({err})"
        corners = [] if s.corners is None or not len(s.corners) else [(s.corners, "yellow")]
        rows.append([Panel(f"{head}\nreal", s.real),
                     Panel("synthetic + matched corners", s.synthetic, points=corners),  # type: ignore[arg-type]
                     Panel("warped synthetic", s.warped), Panel("MMD mask", s.mask),  # type: ignore[arg-type]
                     Panel("MMD image", s.difference)])  # type: ignore[arg-type]
    return rows


def _boxed(label: str, image: NDArray[Any] | None, snap: Snapshot) -> Panel:
    boxes = [(b, "red") for b in snap.unexpected] + [(b, "cyan") for _, b in snap.monitored]
    if image is not None and image.shape[:2] != snap.real.shape[:2]:
        boxes = []  # an MMD image at a reduced working resolution: no boxes in input pixels
    return Panel(label, image, boxes=boxes)  # type: ignore[arg-type]


def write_figures(runner: "Runner", folder: Path) -> dict[str, Path]:
    """Write the run's figures; returns name -> path of each file written."""
    out: dict[str, Path] = {}
    folder.mkdir(parents=True, exist_ok=True)
    snaps = runner.snapshots
    kept = sorted(snaps.kept.values(), key=lambda s: s.index)
    if snaps.last is not None and (not kept or kept[-1].index != snaps.last.index):
        kept.append(snaps.last)
    kept = [s for s in kept if s.synthetic is not None and s.difference is not None]
    if kept:
        first = kept[0]
        synced = next((s for s in kept if s.pixel_error <= 0.5), kept[-1])
        chosen = [first] if synced is first else [first, synced]
        out["sync"] = write_strip(folder / "sync.png", _sync_rows(chosen),
                                  title="Scene Background synchronisation (paper Fig. 4)")
    if snaps.spawns:
        at = snaps.spawns[0]
        chosen = [s for s in kept if s.index in (at - 0, at + 5, at + 15)] or [kept[-1]]
        before = [s for s in kept if s.index < at]
        if before:
            chosen = [before[-1], *chosen]
        rows = [[_boxed(f"t={s.time:.2f} s\nreal", s.real, s),
                 Panel("synthetic", s.synthetic), _boxed("MMD image", s.difference, s)]  # type: ignore[arg-type]
                for s in chosen]
        out["unexpected"] = write_strip(
            folder / "unexpected.png", rows,
            title="Unexpected object: found (red), then monitored by a spawned schema (cyan) "
                  "(paper Fig. 5)")
    compared = runner.comparisons.kept
    if compared:
        name = runner.comparisons.created[0] if runner.comparisons.created else "object"
        top = [Panel(f"+{c.after:g} s (t={c.time:.2f} s)\nuncorrected: |real - imagined|",
                     c.uncorrected) for c in compared]
        bottom = [Panel("corrected: |real - imagined|", c.corrected) for c in compared]
        reals = [Panel("real", c.real) for c in compared]
        out["correction"] = write_strip(
            folder / "correction.png", [reals, top, bottom],
            title=f"{name}: the uncorrected imagination (middle) drifts from the real object, "
                  "the corrected one (bottom) stays on it (paper Figs. 7-8)")
    bg = runner.network.background
    if bg is not None and bg.first_look is not None:
        floor = runner.mirror.appearance.texture("floor")
        out["appearance"] = _appearance_strip(bg.first_look, floor, folder / "appearance.png")
    if runner.series.time:
        out["camera"] = _camera_plot(runner, folder / "camera.png")
        out["floor"] = _floor_plot(runner, folder / "floor.png")
    if runner.evaluation.timeline or any(math.isfinite(c) for c in runner.series.confidence):
        out["prediction"] = _prediction_plot(runner, folder / "prediction.png")
    return out


def _prediction_plot(runner: "Runner", path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from adapt.runner.evaluation import COMMIT_CONFIDENCE

    p = runner.series
    timeline = list(runner.evaluation.timeline)
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 5.6), sharex=True,
                             gridspec_kw={"height_ratios": [2, 1]})
    ax = axes[0]
    horizons = sorted({h for _, _, h, _ in timeline})
    colours = {"mirror": "tab:blue", "baseline": "tab:orange"}
    styles = ["-", "--", ":", "-."]
    for i, h in enumerate(horizons):
        for source in ("mirror", "baseline"):
            pts = sorted((t, e) for t, s, hh, e in timeline if s == source and hh == h)
            if pts:
                ax.plot([t for t, _ in pts], [100 * e for _, e in pts], styles[i % 4], lw=1.1,
                        color=colours[source], label=f"{source}, {h:g} s ahead")
    reach = runner.evaluation.reach
    if reach is not None:
        ax.axhline(100 * reach, color="gray", lw=0.8, ls="--", label="catch reach")
    ax.set_yscale("symlog", linthresh=10.0)
    ax.set_ylabel("prediction error (cm)")
    ax.set_title("predictions against the truth, by the time they were made")
    if horizons or reach is not None:
        ax.legend(fontsize=7, loc="upper right")
    ax2 = axes[1]
    ax2.plot(p.time, p.confidence, color="tab:blue", lw=1.2, label="mirror's confidence")
    ax2.axhline(COMMIT_CONFIDENCE, color="gray", lw=0.8, ls="--", label="rules commit")
    caught = runner.evaluation.caught
    for a in axes:
        if caught is not None:
            a.axvline(caught, color="green", lw=1.0)
    ax2.set_ylim(-0.05, 1.05)
    ax2.set_xlabel("time (s)" + ("; green: caught" if caught is not None else ""))
    ax2.set_ylabel("confidence")
    ax2.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    out = _save(fig, path)
    plt.close(fig)
    return out


def _appearance_strip(look: tuple[int, float, NDArray[np.uint8], NDArray[np.uint8],
                                  NDArray[np.uint8]], floor: Any, path: Path) -> Path:
    """The real frame, the render before and after learning its look, their
    differences, and the floor's learned image at the end of the run."""
    index, t, real, before, after = look

    def differs(render: NDArray[np.uint8]) -> NDArray[np.float32]:
        return np.abs(real.astype(np.float32) - render.astype(np.float32)).max(axis=2)

    d0, d1 = differs(before), differs(after)
    rows = [[Panel(f"frame {index} (t={t:.2f} s)\nreal", real),
             Panel("render: the scenario's look", before),
             Panel("render: the learned look", after)],
            [Panel("the floor's learned image, end of run\n(black: never seen)",
                   floor.preview(640) if floor is not None else np.zeros(real.shape[:2], np.uint8)),
             Panel(f"|real - render| before, 0-80 (mean {d0.mean():.1f})", d0, vmin=0.0, vmax=80.0),
             Panel(f"|real - render| after, 0-80 (mean {d1.mean():.1f})", d1, vmin=0.0, vmax=80.0)]]
    return write_strip(path, rows, title="The surfaces' look, learned from the camera")


def _camera_plot(runner: "Runner", path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = runner.series
    has_truth = any(math.isfinite(v) for v in p.camera_position)
    fig, axes = plt.subplots(1, 2 if has_truth else 1, figsize=(10 if has_truth else 5.5, 3.4),
                             squeeze=False)
    ax = axes[0][0]
    ax.plot(p.time, p.pixel_error, lw=1.2, color="tab:blue")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.axhline(0.5, color="gray", lw=0.8, ls="--", label="tolerance 0.5 px")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("pixel error of H_e (px)")
    ax.set_title("camera synchronisation (MMD)")
    ax.legend(fontsize=8)
    if has_truth:
        ax2 = axes[0][1]
        ax2.plot(p.time, [v * 100 for v in p.camera_position], lw=1.2, label="position (cm)")
        ax2.plot(p.time, p.camera_rotation, lw=1.2, label="rotation (deg)")
        ax2.set_xlabel("time (s)")
        ax2.set_title("synthetic camera vs the true camera")
        ax2.legend(fontsize=8)
    fig.tight_layout()
    out = _save(fig, path)
    plt.close(fig)
    return out


def _floor_plot(runner: "Runner", path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = runner.scenario.scene
    p = runner.series
    fig, ax = plt.subplots(figsize=(8.6, 5.2))
    for w in scene.walls:
        ax.plot([w.start[0], w.end[0]], [w.start[1], w.end[1]], color="saddlebrown", lw=3)
    for ob in scene.obstacles:
        xs = [q[0] for q in ob.polygon] + [ob.polygon[0][0]]
        ys = [q[1] for q in ob.polygon] + [ob.polygon[0][1]]
        ax.fill(xs, ys, color=np.array(ob.color) / 255.0, alpha=0.8)
    for i, (_made, pts) in enumerate(p.predicted):
        ax.plot(pts[:, 0], pts[:, 1], ":", color="tab:purple", lw=1.0, alpha=0.8,
                label="predicted (from t=" + ", ".join(f"{t:.1f}" for t, _ in p.predicted)
                + " s)" if i == 0 else None)
        ax.plot(pts[:1, 0], pts[:1, 1], "o", color="tab:purple", ms=3)
    styles = (("truth", p.truth, "-", "black"), ("observed", p.observed, ".", None),
              ("imagined", p.imagined, "--", None), ("uncorrected", p.uncorrected, "-.", "red"))
    for label, store, style, color in styles:
        for name, series in store.items():
            pts = np.array([v if v is not None else (np.nan, np.nan) for v in series], float)
            if np.isfinite(pts).any():
                ax.plot(pts[:, 0], pts[:, 1], style, ms=2.5, lw=1.2, color=color,
                        label=f"{name} {label}")
    for label, series, style, color in (("robot (imagined)", p.robot, "-", "dimgray"),
                                        ("robot (truth)", p.robot_truth, "-", "black"),
                                        ("baseline robot", p.robot_baseline, "-", "tab:orange")):
        pts = np.array([v if v is not None else (np.nan, np.nan) for v in series], float)
        if len(pts) and np.isfinite(pts).any():
            ax.plot(pts[:, 0], pts[:, 1], style, color=color, lw=2.2, alpha=0.55, label=label)
            last = pts[np.isfinite(pts[:, 0])][-1]
            ax.plot([last[0]], [last[1]], "s", color=color, ms=5)
    if runner.scenario.mount.kind is not Mount.ROBOT:
        cam = runner.scenario.camera.position
        ax.plot([cam[0]], [cam[1]], "^", color="purple", label="camera")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("floor plan")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    out = _save(fig, path)
    plt.close(fig)
    return out
