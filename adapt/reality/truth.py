"""Ground truth: what really happened, for evaluation only.

A reality source that knows the truth (a synthetic reality always; a video
when the scenario gives a ground-truth CSV) exposes it as ``source.truth``, a
:class:`GroundTruth`: ``truth.at(index)`` is the :class:`FrameTruth` of frame
``index`` (or None).  Nothing on the perceiving side -- schemas, the mirror,
rules, the imagination -- may read it; :class:`~adapt.frames.Frame` carries
only the image, and ``tests/test_architecture.py`` keeps the perceiving layers
from importing :mod:`adapt.reality`.

The ground-truth file of a video is a CSV with the header ``t,object,x,y`` and
optionally ``vx,vy`` (any column order; metres and seconds, in the
scenario's floor frame).  Each object's rows are linearly interpolated at
the frame times.  An object is present between two of its rows that both
give a position, and within half a frame period of such a row (where that
row holds); elsewhere -- before its first row, after its last, and next to
a row whose ``x`` and ``y`` are empty (which says it is not present at
``t``) -- it is absent.  Velocities come from ``vx, vy`` when the file has
them (None otherwise).

Examples
--------
>>> import io
>>> text = "t,object,x,y\\n0.0,ball,0.0,1.0\\n1.0,ball,2.0,1.0\\n"
>>> truth = CsvTruth(read_truth_csv(io.StringIO(text), "gt.csv"), fps=4.0)
>>> truth.at(2).objects["ball"].position, truth.at(2).time
((1.0, 1.0), 0.5)
>>> truth.at(9).objects["ball"] is None
True
>>> read_truth_csv(io.StringIO("t,object,x,y\\n0.0,ball,zero,1\\n"), "gt.csv")
Traceback (most recent call last):
...
adapt.errors.GroundTruthError: gt.csv:2:10: column 'x': expected a number of metres, got 'zero'
...
"""

from __future__ import annotations

import bisect
import collections
import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import IO, Any, Iterable, Mapping, Protocol, runtime_checkable

from adapt.errors import GroundTruthError
from adapt.geometry import MAX_COORDINATE, Camera
from adapt.imagination.scene import MAX_SPEED

__all__ = [
    "ObjectTruth",
    "RobotState",
    "ObjectParameters",
    "TrueParameters",
    "FrameTruth",
    "GroundTruth",
    "RecordedTruth",
    "TruthRow",
    "CsvTruth",
    "read_truth_csv",
    "load_truth_csv",
    "TRUTH_COLUMNS",
    "DEFAULT_HISTORY",
]

Vec2 = tuple[float, float]

#: Columns of a ground-truth CSV: required, then optional.
TRUTH_COLUMNS = (("t", "object", "x", "y"), ("vx", "vy"))

#: Frames a :class:`RecordedTruth` keeps by default (a robot runs for hours).
DEFAULT_HISTORY = 1024


@dataclass(frozen=True, slots=True)
class ObjectTruth:
    """Where an object really is.

    ``position`` and ``velocity`` are its centre's ``(x, y)`` on the floor,
    metres and m/s; ``velocity`` is None when the source does not know it (a
    ground-truth CSV without ``vx, vy``).  ``height`` is its centre's height
    and ``pixels`` how many pixels of it the true camera shows (a PyBullet
    reality's; None where the source does not know).
    """

    position: Vec2
    velocity: Vec2 | None
    height: float | None = None
    pixels: int | None = None


@dataclass(frozen=True, slots=True)
class RobotState:
    """The true pose and motion of the robot: ``position`` (m), ``heading``
    (radians counter-clockwise from ``+x``), ``velocity`` (m/s, world frame)
    and ``angular_velocity`` (rad/s)."""

    position: Vec2
    heading: float
    velocity: Vec2
    angular_velocity: float


@dataclass(frozen=True, slots=True)
class ObjectParameters:
    """The values drawn for one true object in this run.

    ``appears`` is the time the object enters reality (None: present from
    the start), at ``position`` with ``velocity``.
    """

    name: str
    declared: bool
    restitution: float
    friction: float
    rolling_resistance: float
    mass: float
    drag: float
    spin: float
    appears: float | None
    position: Vec2
    velocity: Vec2

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {
            "name": self.name, "declared": self.declared, "restitution": self.restitution,
            "friction": self.friction, "rolling_resistance": self.rolling_resistance,
            "mass": self.mass, "drag": self.drag, "spin": self.spin, "appears": self.appears,
            "position": list(self.position), "velocity": list(self.velocity),
        }


@dataclass(frozen=True, slots=True)
class TrueParameters:
    """Everything a synthetic reality drew for this run.

    Attributes
    ----------
    seed : int
        The run's seed.
    objects : tuple of ObjectParameters
        One per true object, in the reality's order.
    camera_offset : (dx, dy, dz)
        Metres added to the nominal camera position (world frame; the robot's
        frame for a camera on the robot).
    camera_rotation_deg : (pan, tilt, roll)
        Degrees turned from the nominal camera orientation.
    robot_max_speed, robot_max_accel : float or None
        The real robot's limits (None: no robot).
    robot_slip : float
        Wheel-slip standard deviation, a fraction of the commanded velocity.
    details : mapping
        What else a reality drew or measured (a PyBullet reality: its own
        coefficients, the look, the contacts' measured effects), JSON-ready.
    """

    seed: int
    objects: tuple[ObjectParameters, ...]
    camera_offset: tuple[float, float, float]
    camera_rotation_deg: tuple[float, float, float]
    robot_max_speed: float | None = None
    robot_max_accel: float | None = None
    robot_slip: float = 0.0
    details: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))

    def object(self, name: str) -> ObjectParameters:
        """The drawn values of the object called ``name``."""
        for o in self.objects:
            if o.name == name:
                return o
        raise KeyError(name)

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {
            "seed": self.seed,
            "objects": [o.as_json() for o in self.objects],
            "camera_offset": list(self.camera_offset),
            "camera_rotation_deg": list(self.camera_rotation_deg),
            "robot": None if self.robot_max_speed is None else {
                "max_speed": self.robot_max_speed, "max_accel": self.robot_max_accel,
                "slip": self.robot_slip},
            **({"details": dict(self.details)} if self.details else {}),
        }


@dataclass(frozen=True, slots=True, eq=False)
class FrameTruth:
    """The truth at one frame.

    Attributes
    ----------
    index : int
        The frame's index.
    time : float
        The frame's time, seconds.
    objects : mapping of str to ObjectTruth or None
        Every object the source knows of; None while it is not present.
    camera : Camera or None
        The true camera (None when unknown, as for a video).
    robot : RobotState or None
        The true robot (None without a robot, or when unknown).
    parameters : TrueParameters or None
        What was drawn for the run (synthetic reality only).
    """

    index: int
    time: float
    objects: Mapping[str, ObjectTruth | None]
    camera: Camera | None = None
    robot: RobotState | None = None
    parameters: TrueParameters | None = None

    def position(self, name: str) -> Vec2 | None:
        """The true position of object ``name``, or None when it is not present."""
        o = self.objects.get(name)
        return None if o is None else o.position


@runtime_checkable
class GroundTruth(Protocol):
    """What a reality source knows of the truth: ``at(index)`` is the
    :class:`FrameTruth` of a frame, or None when the frame is unknown."""

    def at(self, index: int) -> FrameTruth | None:
        """The truth at frame ``index``."""
        ...


class RecordedTruth:
    """The truth of a synthetic reality, recorded as its frames are made.

    ``at(index)`` is None for a frame not produced yet, or produced more than
    ``history`` frames ago (memory stays flat on long runs).
    """

    def __init__(self, parameters: TrueParameters, history: int = DEFAULT_HISTORY) -> None:
        if history < 1:
            raise ValueError(f"history must be at least 1 frame, got {history}")
        self.parameters = parameters
        self.history = int(history)
        self._frames: collections.deque[FrameTruth] = collections.deque(maxlen=self.history)

    def record(self, truth: FrameTruth) -> None:
        """Keep the truth of the next frame (frames arrive in order)."""
        if self._frames and truth.index != self._frames[-1].index + 1:
            raise ValueError(f"frame {truth.index} recorded after frame {self._frames[-1].index}")
        self._frames.append(truth)

    @property
    def latest(self) -> FrameTruth | None:
        """The truth of the last frame made."""
        return self._frames[-1] if self._frames else None

    def at(self, index: int) -> FrameTruth | None:
        """The truth at frame ``index``, or None."""
        if not self._frames:
            return None
        k = index - self._frames[0].index
        if 0 <= k < len(self._frames):
            return self._frames[k]
        return None


# -- ground-truth files -----------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class TruthRow:
    """One row of a ground-truth CSV (``x``/``y`` None: not present at ``t``)."""

    t: float
    object: str
    x: float | None
    y: float | None
    vx: float | None = None
    vy: float | None = None
    line: int = 0


#: The largest magnitude of each number column: positions within the world's coordinates,
#: speeds a ball may have, times of at most a million seconds.
LIMITS = {"t": 1.0e6, "x": MAX_COORDINATE, "y": MAX_COORDINATE, "vx": MAX_SPEED, "vy": MAX_SPEED}


def _cell_column(source_line: str | None, index: int) -> int:
    """1-based character column of cell ``index`` in a plain (unquoted) CSV line."""
    if source_line is None or '"' in source_line:
        return 1
    parts = source_line.split(",")
    if index >= len(parts):
        return 1
    return 1 + sum(len(p) + 1 for p in parts[:index])


def _number(text: str, column: str, unit: str, file: str, line: int,
            source_line: str | None, index: int) -> float:
    """A finite number within the column's bound (:data:`LIMITS`)."""
    col = _cell_column(source_line, index)
    try:
        v = float(text)
    except ValueError:
        raise GroundTruthError(f"column {column!r}: expected a number of {unit}, got {text!r}",
                               file=file, line=line, col=col, source_line=source_line) from None
    if not math.isfinite(v):
        raise GroundTruthError(f"column {column!r}: expected a finite number of {unit}, "
                               f"got {text!r}", file=file, line=line, col=col,
                               source_line=source_line)
    limit = LIMITS[column]
    if abs(v) > limit:
        raise GroundTruthError(f"column {column!r}: expected at most {limit:g} {unit} either "
                               f"way, got {text!r}", file=file, line=line, col=col,
                               source_line=source_line)
    return v


def read_truth_csv(stream: IO[str] | Iterable[str], file: str) -> tuple[TruthRow, ...]:
    """Read and check a ground-truth CSV (``file`` names it in errors).

    The header must hold ``t``, ``object``, ``x``, ``y`` and may hold ``vx``
    and ``vy`` (both or neither), in any order; no other column.  Each row
    needs a time ``t >= 0``, an object name and either both of ``x, y`` or
    neither (not present); ``vx, vy`` may be empty too.  An object's times
    must increase from row to row.

    Raises
    ------
    GroundTruthError
        At ``file:line`` for a bad header or row, saying what was expected.
    """
    lines = list(stream)
    if not lines or not lines[0].strip():
        raise GroundTruthError("expected a header line 't,object,x,y' (optionally ',vx,vy')",
                               file=file, line=1)
    text_of = {i + 1: ln.rstrip("\r\n") for i, ln in enumerate(lines)}
    reader = csv.reader(lines)
    header = [h.strip().lstrip("\ufeff") for h in next(reader)]
    required, optional = TRUTH_COLUMNS
    unknown = [h for h in header if h not in required + optional]
    if unknown:
        raise GroundTruthError(
            f"unknown column {unknown[0]!r}; expected the columns t,object,x,y and optionally "
            "vx,vy", file=file, line=1, source_line=text_of[1])
    missing = [h for h in required if h not in header]
    if missing:
        raise GroundTruthError(f"missing column {missing[0]!r}; expected the header "
                               "t,object,x,y (optionally ,vx,vy)", file=file, line=1,
                               source_line=text_of[1])
    if len(set(header)) != len(header):
        raise GroundTruthError("a column is named twice in the header", file=file, line=1,
                               source_line=text_of[1])
    if ("vx" in header) != ("vy" in header):
        raise GroundTruthError("expected both 'vx' and 'vy' columns, or neither", file=file,
                               line=1, source_line=text_of[1])
    col = {h: i for i, h in enumerate(header)}
    rows: list[TruthRow] = []
    last: dict[str, float] = {}
    for cells in reader:
        line = reader.line_num
        src = text_of.get(line)
        if not cells or all(not c.strip() for c in cells):
            continue
        if len(cells) != len(header):
            raise GroundTruthError(f"expected {len(header)} values ({','.join(header)}), got "
                                   f"{len(cells)}", file=file, line=line, source_line=src)
        get = {h: cells[i].strip() for h, i in col.items()}
        t = _number(get["t"], "t", "seconds", file, line, src, col["t"])
        if t < 0:
            raise GroundTruthError(f"column 't': expected a time >= 0, got {get['t']!r}",
                                   file=file, line=line, col=_cell_column(src, col["t"]),
                                   source_line=src)
        name = get["object"]
        if not name:
            raise GroundTruthError("column 'object': expected an object name", file=file,
                                   line=line, col=_cell_column(src, col["object"]),
                                   source_line=src)
        pair: list[float | None] = []
        for a, b, unit in (("x", "y", "metres"), ("vx", "vy", "m/s")):
            if a not in get:
                pair += [None, None]
                continue
            if bool(get[a]) != bool(get[b]):
                raise GroundTruthError(f"columns {a!r} and {b!r}: expected both or neither, got "
                                       f"{get[a]!r} and {get[b]!r}", file=file, line=line,
                                       col=_cell_column(src, col[a if not get[a] else b]),
                                       source_line=src)
            if not get[a]:
                pair += [None, None]
                continue
            pair += [_number(get[a], a, unit, file, line, src, col[a]),
                     _number(get[b], b, unit, file, line, src, col[b])]
        if name in last and t <= last[name]:
            raise GroundTruthError(f"column 't': expected the times of {name!r} to increase, got "
                                   f"{t:g} after {last[name]:g}", file=file, line=line,
                                   col=_cell_column(src, col["t"]), source_line=src)
        last[name] = t
        rows.append(TruthRow(t, name, pair[0], pair[1], pair[2], pair[3], line))
    return tuple(rows)


def load_truth_csv(path: str | Path) -> tuple[TruthRow, ...]:
    """Read a ground-truth CSV file (see :func:`read_truth_csv`).

    Raises
    ------
    GroundTruthError
        If the file cannot be read or is not UTF-8 text, or has a bad row.
    """
    p = Path(path)
    try:
        with open(p, encoding="utf-8", newline="") as f:
            return read_truth_csv(f, str(p))
    except UnicodeDecodeError as exc:
        raise GroundTruthError(f"expected UTF-8 text ({exc.reason})", file=str(p),
                               line=1) from None
    except OSError as exc:
        raise GroundTruthError(f"cannot read the ground-truth file ({exc.strerror})",
                               file=str(p), line=1) from None


@dataclass(slots=True)
class _Track:
    """One object's rows, in time order."""

    times: list[float] = field(default_factory=list)
    rows: list[TruthRow] = field(default_factory=list)


class CsvTruth:
    """The truth of a video from its ground-truth rows, at the video's frame times."""

    def __init__(self, rows: Iterable[TruthRow], fps: float) -> None:
        if not (fps > 0 and math.isfinite(fps)):
            raise ValueError(f"fps must be positive, got {fps}")
        self.fps = float(fps)
        self._tracks: dict[str, _Track] = {}
        for r in rows:
            tr = self._tracks.setdefault(r.object, _Track())
            tr.times.append(r.t)
            tr.rows.append(r)
        self.parameters: TrueParameters | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """The objects the file names, in order of first appearance."""
        return tuple(self._tracks)

    def _object(self, track: _Track, t: float) -> ObjectTruth | None:
        times, rows = track.times, track.rows
        tol = 0.5 / self.fps
        k = bisect.bisect_right(times, t)  # rows[k-1].t <= t < rows[k].t
        before = rows[k - 1] if k > 0 else None
        after = rows[k] if k < len(rows) else None
        if before is not None and after is not None and before.x is not None \
                and after.x is not None:
            f = (t - before.t) / (after.t - before.t)
            return ObjectTruth(_lerp2(before.x, before.y, after.x, after.y, f),
                               None if before.vx is None or after.vx is None
                               else _lerp2(before.vx, before.vy, after.vx, after.vy, f))
        # Outside a run of present rows: the nearest row within half a frame holds.
        near = [r for r in (before, after) if r is not None and abs(r.t - t) <= tol]
        near.sort(key=lambda r: abs(r.t - t))
        if near and near[0].x is not None:
            r = near[0]
            vel = None if r.vx is None else (float(r.vx), float(r.vy))  # type: ignore[arg-type]
            return ObjectTruth((float(r.x), float(r.y)), vel)  # type: ignore[arg-type]
        return None

    def at(self, index: int) -> FrameTruth | None:
        """The truth at frame ``index`` (time ``index / fps``)."""
        if index < 0:
            return None
        t = index / self.fps
        objects = {name: self._object(tr, t) for name, tr in self._tracks.items()}
        return FrameTruth(index, t, MappingProxyType(objects))


def _lerp2(ax: float | None, ay: float | None, bx: float | None, by: float | None,
           f: float) -> Vec2:
    assert ax is not None and ay is not None and bx is not None and by is not None
    return (ax + f * (bx - ax), ay + f * (by - ay))
