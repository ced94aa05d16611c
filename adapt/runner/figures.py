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
  paths, and the robot's paths (odometry, truth, each baseline's);
* ``correction.png`` -- the paper's Figures 7 and 8: after an object was
  created in the imagination, the difference between the real frame and the
  uncorrected imagination (top row) and the corrected one (bottom row), on
  the same crop around the object;
* ``prediction.png`` -- for runs with predictions and ground truth: the
  mirror's and the baselines' prediction errors against the time they were
  made, and the mirror's confidence;
* ``appearance.png`` -- for runs whose Scene Background learned the surfaces'
  look: the real frame it learned from, the render before and after
  learning, and how far each differs from the real frame.

The data are collected by :class:`FigureCollector`, a listener on the frame
records, into :class:`Snapshots` (a few frames kept by reference),
:class:`Comparisons` and :class:`Paths` (decimated series), so nothing grows
with the run's length; :func:`write_figures` draws a :class:`FigureData`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from adapt.figures.strips import Panel, write_strip
from adapt.files import atomic_path
from adapt.geometry import Camera
from adapt.imagination import SceneSpec
from adapt.runner.baseline import report_key
from adapt.runner.evaluation import MIRROR
from adapt.schemas import EventKind
from adapt.schemas.percepts import FirstLook

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.evaluation import Evaluation, FrameScore
    from adapt.runner.record import FrameRecord

__all__ = ["Snapshot", "Snapshots", "Comparison", "Comparisons", "Paths", "FigureCollector",
           "FigureData", "write_figures", "PLANNED", "COMPARED_AFTER", "RenderTwin"]

Vec2 = tuple[float, float]
BBox = tuple[int, int, int, int]

#: Renders the uncorrected twin through a camera (for ``correction.png``).
RenderTwin = Callable[[Camera], NDArray[np.uint8]]

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
    #: The camera loop's tolerance in the frame's pixels (the last frame's; NaN: none seen).
    tolerance: float = math.nan
    camera_position: list[float] = field(default_factory=list)
    camera_rotation: list[float] = field(default_factory=list)
    observed: dict[str, list[Vec2 | None]] = field(default_factory=dict)
    imagined: dict[str, list[Vec2 | None]] = field(default_factory=dict)
    truth: dict[str, list[Vec2 | None]] = field(default_factory=dict)
    uncorrected: dict[str, list[Vec2 | None]] = field(default_factory=dict)
    robot: list[Vec2 | None] = field(default_factory=list)
    robot_truth: list[Vec2 | None] = field(default_factory=list)
    #: Each baseline's simulated robot, by baseline name.
    robot_baselines: dict[str, list[Vec2 | None]] = field(default_factory=dict)
    #: The mirror's confidence in its longest-horizon prediction of the target (NaN: none).
    confidence: list[float] = field(default_factory=list)
    #: A few of the mirror's predicted paths: (time made, (T, 2) positions).
    predicted: list[tuple[float, NDArray[np.float64]]] = field(default_factory=list)

    def add(self, record: "FrameRecord", score: "FrameScore | None", target: str | None) -> None:
        """Take one frame's record and score (every ``stride``-th one is kept)."""
        self.count += 1
        if (self.count - 1) % self.stride:
            return
        n = len(self.time)
        self.time.append(record.time)
        bg = record.background
        self.pixel_error.append(math.nan if bg is None else bg.pixel_error)
        if bg is not None:
            self.tolerance = bg.tolerance
        cam = None if score is None else score.camera_error
        self.camera_position.append(math.nan if cam is None else cam[0])
        self.camera_rotation.append(math.nan if cam is None else cam[1])
        self.robot.append(None if record.robot is None else record.robot.position)
        self.robot_truth.append(None if score is None else score.robot)
        for name, state in record.baselines.items():
            series = self.robot_baselines.setdefault(name, [None] * n)
            series.append(None if target is None or record.robot is None
                          else state.robots.get(target))
        self.confidence.append(_confidence(record))
        truth = {} if score is None else score.truth
        for obj in record.tracked:
            for store, value in ((self.observed, obj.observed), (self.imagined, obj.imagined),
                                 (self.uncorrected, record.uncorrected.get(obj.name)),
                                 (self.truth, truth.get(obj.name))):
                series = store.setdefault(obj.name, [None] * n)
                series.append(value)
        for store in (self.observed, self.imagined, self.uncorrected, self.truth,
                      self.robot_baselines):
            for series in store.values():
                while len(series) < n + 1:
                    series.append(None)
        if len(self.time) > self.limit:
            self._thin()

    def _thin(self) -> None:
        self.stride *= 2
        for key in ("time", "pixel_error", "camera_position", "camera_rotation", "robot",
                    "robot_truth", "confidence"):
            setattr(self, key, getattr(self, key)[::2])
        for store in (self.observed, self.imagined, self.uncorrected, self.truth,
                      self.robot_baselines):
            for name in store:
                store[name] = store[name][::2]

    def predicted_path(self, time: float, positions: NDArray[np.float64], limit: int = 4) -> None:
        """Keep one of the mirror's predicted paths (the first ``limit`` offered)."""
        if len(self.predicted) < limit:
            self.predicted.append((time, np.array(positions, float)))


def _confidence(record: "FrameRecord") -> float:
    """The confidence of the longest-horizon prediction of the first predicted object."""
    for obj in record.tracked:
        p = record.percept_of(obj.name)
        if p is not None and p.prediction is not None and p.prediction.horizons:
            last = max(p.prediction.horizons, key=lambda h: h.horizon)
            return last.confidence
    return math.nan


@dataclass(eq=False)
class FigureData:
    """Everything the figures draw (see :func:`write_figures`)."""

    snapshots: Snapshots
    comparisons: Comparisons
    series: Paths
    scene: SceneSpec
    fps: float
    timeline: Sequence[tuple[float, str, float, float]] = ()
    reach: float | None = None
    caught: float | None = None
    #: When each baseline's robot caught the target, by baseline name (None: it did not).
    baselines_caught: Mapping[str, float | None] = field(default_factory=dict)
    first_look: FirstLook | None = None
    floor_texture: Any = None
    #: Where a fixed camera stands (None: on the robot).
    camera: Vec2 | None = None


class FigureCollector:
    """Collects the figures' data from the frame records (see the module docstring).

    ``render_twin`` renders the uncorrected twin through a camera (as the frame's
    record stands), ``twin_radius`` gives a twin object's radius, for the crops of
    ``correction.png``; ``target`` is the object the baselines' robots chase.
    """

    def __init__(self, *, fps: float, evaluation: "Evaluation", target: str | None,
                 render_twin: RenderTwin, twin_radius: Callable[[str], float | None]) -> None:
        self.fps = fps
        self.evaluation = evaluation
        self.target = target
        self.render_twin = render_twin
        self.twin_radius = twin_radius
        self.snapshots = Snapshots()
        self.comparisons = Comparisons()
        self.series = Paths()
        self.first_look: FirstLook | None = None
        self._last_path_kept = -math.inf

    def frame(self, record: "FrameRecord") -> None:
        """Take what the figures need of one frame."""
        for event in record.events:
            if event.kind is EventKind.SPAWNED:
                self.snapshots.spawned(max(event.frame, 0))
            elif event.kind is EventKind.CREATED:
                self.comparisons.created_at(str(event.data["body"]), max(event.frame, 0),
                                            self.fps)
        after = self.comparisons.wants(record.index)
        if after is not None:
            self._compare(record, after)
        bg = record.background
        res = None if bg is None else bg.mmd
        if bg is not None and bg.first_look is not None:
            self.first_look = bg.first_look
        self.snapshots.add(Snapshot(
            record.index, record.time, record.frame.image, None if bg is None else bg.synthetic,
            None if res is None else res.matches.synthetic_points[res.alignment.inliers],
            None if res is None else res.warped, None if res is None else res.mask,
            None if res is None else res.difference, math.nan if bg is None else bg.pixel_error,
            () if bg is None else tuple(r.bbox for r in bg.unexpected), record.monitored))
        self.series.add(record, self.evaluation.score(record.index), self.target)
        if record.time - self._last_path_kept >= 1.0:
            for p in record.objects:
                pred = p.prediction
                if pred is not None and abs(pred.time - record.time) < 0.5 / self.fps:
                    self.series.predicted_path(pred.time, pred.trajectory.positions[::3])
                    self._last_path_kept = record.time
                    break

    def _compare(self, record: "FrameRecord", after: float) -> None:
        """Keep, for ``correction.png``, this frame's differences from the uncorrected twin and
        from the mirror (both through the frame's ``H_e``, on one crop around the object)."""
        bg = record.background
        created = self.comparisons.created
        if bg is None or bg.synthetic is None or created is None:
            return
        camera = bg.camera_before
        uncorrected = bg.difference_with(record.frame.image, self.render_twin(camera))
        corrected = bg.difference_with(record.frame.image, bg.synthetic)
        if uncorrected is None or corrected is None:
            return
        name = created[0]
        obj = record.tracked_object(name)
        radius = self.twin_radius(name)
        found = [_ball_box(camera, p, radius) for p in
                 (record.uncorrected.get(name), None if obj is None else obj.imagined)]
        percept = record.percept_of(name)
        found.append(None if percept is None or percept.sighting is None
                     else percept.sighting.bbox)
        boxes = [b for b in found if b is not None]
        if not boxes:
            return  # the object is out of view: nothing to compare
        h, w = record.frame.image.shape[:2]
        x, y, cw, ch = _crop(boxes, w, h)
        self.comparisons.add(Comparison(
            record.index, record.time, after, record.frame.image[y:y + ch, x:x + cw].copy(),
            np.asarray(uncorrected[y:y + ch, x:x + cw], np.float32),
            np.asarray(corrected[y:y + ch, x:x + cw], np.float32)))

    def data(self, scene: SceneSpec, *, floor_texture: Any = None,
             camera: Vec2 | None = None) -> FigureData:
        """What was collected, with the evaluation's results, for :func:`write_figures`."""
        ev = self.evaluation
        return FigureData(self.snapshots, self.comparisons, self.series, scene, self.fps,
                          tuple(ev.timeline), ev.reach, ev.caught, dict(ev.baselines_caught),
                          self.first_look, floor_texture, camera)


def _ball_box(camera: Camera, position: Vec2 | None, radius: float | None) -> BBox | None:
    """The image box of a ball of ``radius`` at ``position`` (None: behind the camera or
    off the image)."""
    if position is None or radius is None:
        return None
    point = np.array([[position[0], position[1], radius]])
    depth = float(camera.to_camera(point)[0, 2])
    if depth <= 1e-3:
        return None
    u, v = camera.project(point)[0]
    r = camera.fx * radius / depth
    w, h = camera.size
    if not (-r < u < w + r and -r < v < h + r):
        return None
    return int(u - r), int(v - r), int(2 * r) + 1, int(2 * r) + 1


def _crop(boxes: list[BBox], width: int, height: int, least: int = 96) -> BBox:
    """A window ``(x, y, w, h)`` of the image holding every box with a margin, at least
    ``least`` pixels a side (the whole image when there is no box)."""
    if not boxes:
        return 0, 0, width, height
    x0 = min(b[0] for b in boxes)
    y0 = min(b[1] for b in boxes)
    x1 = max(b[0] + b[2] for b in boxes)
    y1 = max(b[1] + b[3] for b in boxes)
    pad = max(max(b[2], b[3]) for b in boxes)
    x0, y0, x1, y1 = x0 - pad, y0 - pad, x1 + pad, y1 + pad
    side_w, side_h = max(x1 - x0, least), max(y1 - y0, least)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    x = int(min(max(cx - side_w / 2, 0), max(width - side_w, 0)))
    y = int(min(max(cy - side_h / 2, 0), max(height - side_h, 0)))
    return x, y, int(min(side_w, width)), int(min(side_h, height))


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


def write_figures(data: FigureData, folder: Path) -> dict[str, Path]:
    """Write the run's figures; returns name -> path of each file written."""
    out: dict[str, Path] = {}
    folder.mkdir(parents=True, exist_ok=True)
    snaps = data.snapshots
    kept = sorted(snaps.kept.values(), key=lambda s: s.index)
    if snaps.last is not None and (not kept or kept[-1].index != snaps.last.index):
        kept.append(snaps.last)
    kept = [s for s in kept if s.synthetic is not None and s.difference is not None]
    if kept:
        first = kept[0]
        # (kept frames come from the Scene Background, whose percepts set the tolerance)
        synced = next((s for s in kept if s.pixel_error <= data.series.tolerance), kept[-1])
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
    compared = data.comparisons.kept
    if compared:
        name = data.comparisons.created[0] if data.comparisons.created else "object"
        top = [Panel(f"+{c.after:g} s (t={c.time:.2f} s)\nuncorrected: |real - imagined|",
                     c.uncorrected) for c in compared]
        bottom = [Panel("corrected: |real - imagined|", c.corrected) for c in compared]
        reals = [Panel("real", c.real) for c in compared]
        out["correction"] = write_strip(
            folder / "correction.png", [reals, top, bottom],
            title=f"{name}: the uncorrected imagination (middle) drifts from the real object, "
                  "the corrected one (bottom) stays on it (paper Figs. 7-8)")
    if data.first_look is not None:
        out["appearance"] = _appearance_strip(data.first_look, data.floor_texture,
                                              folder / "appearance.png")
    if data.series.time:
        out["camera"] = _camera_plot(data, folder / "camera.png")
        out["floor"] = _floor_plot(data, folder / "floor.png")
    if data.timeline or any(math.isfinite(c) for c in data.series.confidence):
        out["prediction"] = _prediction_plot(data, folder / "prediction.png")
    return out


def _prediction_plot(data: FigureData, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from adapt.runner.evaluation import COMMIT_CONFIDENCE

    p = data.series
    timeline = list(data.timeline)
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 5.6), sharex=True,
                             gridspec_kw={"height_ratios": [2, 1]})
    ax = axes[0]
    horizons = sorted({h for _, _, h, _ in timeline})
    sources = [MIRROR, *(report_key(name) for name in data.baselines_caught)]
    palette = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:brown"]
    styles = ["-", "--", ":", "-."]
    for i, h in enumerate(horizons):
        for k, source in enumerate(sources):
            pts = sorted((t, e) for t, s, hh, e in timeline if s == source and hh == h)
            if pts:
                ax.plot([t for t, _ in pts], [100 * e for _, e in pts], styles[i % 4], lw=1.1,
                        color=palette[k % len(palette)], label=f"{source}, {h:g} s ahead")
    reach = data.reach
    if reach is not None:
        ax.axhline(100 * reach, color="gray", lw=0.8, ls="--", label="catch reach")
    ax.set_yscale("symlog", linthresh=10.0)
    ax.set_ylim(bottom=0.0)  # errors are distances: no negative decades
    ax.set_ylabel("prediction error (cm)")
    ax.set_title("predictions against the truth, by the time they were made")
    if horizons or reach is not None:
        ax.legend(fontsize=7, loc="upper right")
    ax2 = axes[1]
    ax2.plot(p.time, p.confidence, color="tab:blue", lw=1.2, label="mirror's confidence")
    ax2.axhline(COMMIT_CONFIDENCE, color="gray", lw=0.8, ls="--", label="rules commit")
    caught = data.caught
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


def _appearance_strip(look: FirstLook, floor: Any, path: Path) -> Path:
    """The real frame, the render before and after learning its look, their
    differences, and the floor's learned image at the end of the run."""
    index, t, real, before, after = look.frame, look.time, look.real, look.before, look.after

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


def _camera_plot(data: FigureData, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = data.series
    has_truth = any(math.isfinite(v) for v in p.camera_position)
    fig, axes = plt.subplots(1, 2 if has_truth else 1, figsize=(10 if has_truth else 5.5, 3.4),
                             squeeze=False)
    ax = axes[0][0]
    ax.plot(p.time, p.pixel_error, lw=1.2, color="tab:blue")
    finite = [v for v in p.pixel_error if math.isfinite(v)]
    top = max(finite, default=0.0)
    tolerance = p.tolerance  # the schema's, in the frame's pixels
    if top > 5.0:  # a few jumps of tens of pixels beside a settled error of a fraction of one
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_ylim(bottom=0.0)
    else:  # all small: linear, with the tolerance in view
        ax.set_ylim(0.0, max(1.0, 1.15 * top, 1.15 * tolerance if math.isfinite(tolerance) else 0.0))
    if math.isfinite(tolerance):
        ax.axhline(tolerance, color="gray", lw=0.8, ls="--", label=f"tolerance {tolerance:g} px")
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


def _floor_plot(data: FigureData, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = data.scene
    p = data.series
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
    fps = data.fps
    robots = [("robot (imagined)", p.robot, "lightsteelblue", 4.0, None),
              ("robot (truth)", p.robot_truth, "tab:blue", 1.8, data.caught)]
    colours = ["tab:orange", "tab:green", "tab:red", "tab:brown"]
    for i, (name, series) in enumerate(p.robot_baselines.items()):
        robots.append((f"{report_key(name)} robot", series, colours[i % len(colours)], 1.8,
                       data.baselines_caught.get(name)))
    for label, series, color, lw, caught in robots:
        pts = np.array([v if v is not None else (np.nan, np.nan) for v in series], float)
        if len(pts) and np.isfinite(pts).any():
            ax.plot(pts[:, 0], pts[:, 1], "-", color=color, lw=lw, alpha=0.8, label=label)
            last = pts[np.isfinite(pts[:, 0])][-1]
            ax.plot([last[0]], [last[1]], "s", color=color, ms=5)
            k = None if caught is None else min(int(round(caught * fps)), len(pts) - 1)
            if k is not None and np.isfinite(pts[k]).all():
                ax.plot([pts[k, 0]], [pts[k, 1]], "*", color=color, ms=13, mec="black", mew=0.6,
                        label=f"{label.split(' (')[0]} caught the ball, t={caught:.2f} s")
    if data.camera is not None:
        ax.plot([data.camera[0]], [data.camera[1]], "^", color="purple", label="camera")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("floor plan")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    out = _save(fig, path)
    plt.close(fig)
    return out
