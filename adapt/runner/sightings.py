"""Whether the goals' objects were seen: a listener on the frame records.

A goal that names an object (``goals: [{name: intercept, object: ball}]``)
is only as good as the run's sight of that object.  :class:`GoalSightings`
counts, per goal object and from what the schemas observed (never the
truth), the frames it was seen, when it was first seen, and every stretch in
which it was lost after that (missed for longer than ``grace`` seconds);
its summary is ``report.json``'s ``summary.goal_objects`` and the printed
summary's line about them (``docs/runner.md``).

Examples
--------
>>> from adapt.frames import Frame
>>> from adapt.geometry import Camera
>>> from adapt.runner.record import FrameRecord, TrackedObject
>>> import numpy as np
>>> cam = Camera.look_at(fx=100, fy=100, cx=31.5, cy=23.5, width=64, height=48,
...                      position=(0, -2, 1), look_at=(0, 0, 0))
>>> s = GoalSightings(("ball",), fps=10.0)
>>> for k in range(20):
...     seen = (0.0, 0.0) if 5 <= k < 10 or k >= 15 else None
...     s.frame(FrameRecord(Frame(k, k / 10, np.zeros((48, 64, 3), np.uint8)), 0, (), cam,
...                         tracked=(TrackedObject("ball", seen, None),)))
>>> g = s.summary()["ball"]
>>> g["first_seen_s"], g["frames_seen"], g["lost"], g["lost_s"], g["never_seen"]
(0.5, 10, 1, 0.5, False)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.record import FrameRecord

__all__ = ["GoalSightings", "GRACE_S"]

#: Misses shorter than this (seconds) are not a loss: a frame or two without a sighting.
GRACE_S = 0.2


class _Seen:
    """One goal object's sightings."""

    def __init__(self) -> None:
        self.frames = 0
        self.first: float | None = None
        self.last: float | None = None
        self.lost: list[float] = []  # the stretches lost so far (seconds)
        self.missing_since: float | None = None


class GoalSightings:
    """See the module docstring.

    Parameters
    ----------
    objects : sequence of str
        The objects the goals name.
    fps : float
        Frames per second (a frame's share of time).
    grace : float
        Seconds missed before an object counts as lost.
    """

    def __init__(self, objects: Sequence[str], fps: float, grace: float = GRACE_S) -> None:
        self.fps = fps
        self.grace = grace
        self.seen = {name: _Seen() for name in dict.fromkeys(objects)}
        self.time = 0.0

    def frame(self, record: "FrameRecord") -> None:
        """Count one frame's sightings."""
        self.time = record.time
        for name, s in self.seen.items():
            tracked = record.tracked_object(name)
            if tracked is not None and tracked.observed is not None:
                if s.first is None:
                    s.first = record.time
                if s.missing_since is not None and self._gone(s, record.time):
                    s.lost.append(record.time - s.missing_since)
                s.frames += 1
                s.last = record.time
                s.missing_since = None
            elif s.first is not None and s.missing_since is None:
                s.missing_since = record.time

    def _gone(self, s: _Seen, now: float) -> bool:
        return s.missing_since is not None and now - s.missing_since > self.grace + 0.5 / self.fps

    def summary(self) -> dict[str, dict[str, Any]]:
        """Per goal object: ``never_seen``, ``first_seen_s``, ``frames_seen``, ``lost`` (times
        lost after it was first seen), ``lost_s`` (seconds lost in all, to the end),
        ``longest_lost_s``, ``lost_at_end`` and ``unseen_s`` (seconds before the first
        sighting, or the whole run)."""
        out = {}
        end = self.time + 1.0 / self.fps
        for name, s in self.seen.items():
            lost = list(s.lost)
            at_end = s.missing_since is not None and end - s.missing_since > self.grace
            if at_end:
                lost.append(end - s.missing_since)  # type: ignore[operator]
            out[name] = {
                "never_seen": s.first is None,
                "first_seen_s": None if s.first is None else round(s.first, 4),
                "frames_seen": s.frames,
                "lost": len(lost),
                "lost_s": round(sum(lost), 4),
                "longest_lost_s": round(max(lost), 4) if lost else 0.0,
                "lost_at_end": at_end,
                "unseen_s": round(end if s.first is None else s.first, 4),
            }
        return out
