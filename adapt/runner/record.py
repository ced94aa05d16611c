"""The frame record: one typed, frozen record of each frame, and its listeners.

The loop (:mod:`adapt.runner.runner`) makes one :class:`FrameRecord` a frame,
once the motor schemas have acted and before the imagination steps on, and
hands it to its listeners in order: the evaluation first (it scores the
frame against the truth), then the outputs (the report, the trace, the MMD
video, the figures' data), like pymunk's post-step callbacks.  A listener
reads the record; it never reaches into the schemas, the agent or the
mirror.  Everything in it is as of the frame's time.

Examples
--------
>>> import numpy as np
>>> from adapt.frames import Frame
>>> from adapt.geometry import Camera
>>> cam = Camera(100, 100, 40, 30, 80, 60, np.eye(3), np.zeros(3))
>>> r = FrameRecord(frame=Frame(4, 0.4, np.zeros((60, 80, 3), np.uint8)), decisions=12,
...                 schemas=("scene-background",), camera=cam,
...                 tracked=(TrackedObject("ball", (0.5, 1.0), None),))
>>> r.index, r.time, r.tracked_object("ball").observed, r.unexpected_regions
(4, 0.4, (0.5, 1.0), 0)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Protocol

from adapt.frames import Frame
from adapt.geometry import Camera
from adapt.schemas import SchemaEvent
from adapt.schemas.percepts import BackgroundPercept, ObjectPercept

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.baseline import BaselineState

__all__ = ["FrameRecord", "TrackedObject", "RobotPose", "FrameListener", "Vec2", "BBox"]

Vec2 = tuple[float, float]
BBox = tuple[int, int, int, int]


@dataclass(frozen=True, slots=True)
class TrackedObject:
    """An object of the run: its floor position as observed this frame (None when not
    seen) and in the imagination (None when the imagination has no body)."""

    name: str
    observed: Vec2 | None
    imagined: Vec2 | None


@dataclass(frozen=True, slots=True)
class RobotPose:
    """The imagined robot's pose (odometry): position (m) and heading (rad)."""

    position: Vec2
    heading: float


@dataclass(frozen=True, slots=True, eq=False)
class FrameRecord:
    """What happened in one frame (see the module docstring).

    Attributes
    ----------
    frame : Frame
        The real frame.
    decisions : int
        The agent's decision cycles so far.
    schemas : tuple of str
        The names in the network, providers first.
    camera : Camera
        The synthetic camera as the record is made (after this frame's correction).
    background : BackgroundPercept or None
        The Scene Background's percept, when there is one.
    objects : tuple of ObjectPercept
        Every object schema's percept, in the network's order.
    tracked : tuple of TrackedObject
        Every object of the run: the declared ones, those the schemas follow,
        those in the imagination.
    robot : RobotPose or None
        The imagined robot (odometry), with a robot.
    uncorrected : mapping of str to (x, y)
        The uncorrected twin's objects (evaluation only).
    baselines : mapping of str to BaselineState
        Each baseline's predictions and robots this frame, by name.
    monitored : tuple of (str, box)
        The image boxes the schemas explain.
    events : tuple of SchemaEvent
        What happened to the network since the previous record.
    subscene : mapping or None
        The network (its trace form) when it changed this frame, else None.
    """

    frame: Frame
    decisions: int
    schemas: tuple[str, ...]
    camera: Camera
    background: BackgroundPercept | None = None
    objects: tuple[ObjectPercept, ...] = ()
    tracked: tuple[TrackedObject, ...] = ()
    robot: RobotPose | None = None
    uncorrected: Mapping[str, Vec2] = field(default_factory=lambda: MappingProxyType({}))
    baselines: Mapping[str, "BaselineState"] = field(default_factory=lambda: MappingProxyType({}))
    monitored: tuple[tuple[str, BBox], ...] = ()
    events: tuple[SchemaEvent, ...] = ()
    subscene: Mapping[str, Any] | None = None

    @property
    def index(self) -> int:
        """The frame's index."""
        return self.frame.index

    @property
    def time(self) -> float:
        """The frame's time, seconds."""
        return self.frame.time

    @property
    def unexpected_regions(self) -> int:
        """How many difference regions no schema explains."""
        return 0 if self.background is None else len(self.background.unexpected)

    def tracked_object(self, name: str) -> TrackedObject | None:
        """The tracked object called ``name``, or None."""
        return next((t for t in self.tracked if t.name == name), None)

    def percept_of(self, name: str) -> ObjectPercept | None:
        """The percept of the object called ``name`` (the first schema's), or None."""
        return next((p for p in self.objects if p.object == name), None)


class FrameListener(Protocol):
    """Takes each frame's record (the evaluation and every output)."""

    def frame(self, record: FrameRecord) -> None:
        """One frame's record, in frame order."""
        ...
