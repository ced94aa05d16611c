"""Evaluation against ground truth: the only reader of truth in the runner.

When the reality has ground truth (a synthetic reality always does; a video
may come with a CSV), each frame's record gets ``truth`` (true floor
positions), ``camera_pose_error`` (the synthetic camera against the true
one) and ``errors`` (observed and imagined positions against the truth),
and the summary gets their medians.  Nothing that perceives may call this
module; the runner calls it after the frame's loop is done.

Statistics over a run of any length use :class:`Sample`, which keeps at
most a fixed number of values (thinning evenly), so memory stays flat.

Examples
--------
>>> s = Sample(limit=8)
>>> for v in range(100):
...     s.add(float(v))
>>> len(s.values) <= 8, s.count, 40 <= s.median() <= 60
(True, 100, True)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from adapt.geometry import Camera, rotation_log
from adapt.scenario import Scenario

__all__ = ["Evaluation", "Sample", "camera_error"]


class Sample:
    """Up to ``limit`` values of a stream, evenly thinned (every ``stride``-th value)."""

    def __init__(self, limit: int = 4096) -> None:
        self.limit = limit
        self.values: list[float] = []
        self.stride = 1
        self.count = 0
        self.last: float | None = None

    def add(self, value: float) -> None:
        """Take one value (non-finite values are ignored)."""
        if not math.isfinite(value):
            return
        self.last = value
        if self.count % self.stride == 0:
            self.values.append(value)
            if len(self.values) > self.limit:
                self.values = self.values[::2]
                self.stride *= 2
        self.count += 1

    def median(self) -> float | None:
        """Median of the kept values, or None."""
        return float(np.median(self.values)) if self.values else None

    def percentile(self, q: float) -> float | None:
        """Percentile ``q`` of the kept values, or None."""
        return float(np.percentile(self.values, q)) if self.values else None

    def summary(self, digits: int = 4) -> dict[str, Any] | None:
        """``{"median", "p90", "max", "last", "n"}`` or None when empty."""
        if not self.values:
            return None
        return {"median": round(self.median() or 0.0, digits),
                "p90": round(self.percentile(90) or 0.0, digits),
                "max": round(max(self.values), digits),
                "last": None if self.last is None else round(self.last, digits),
                "n": self.count}


def camera_error(estimate: Camera, truth: Camera) -> tuple[float, float]:
    """``(position error in metres, rotation error in degrees)`` of a camera.

    Examples
    --------
    >>> from adapt.geometry import rotation_exp
    >>> a = Camera.look_at(fx=100, fy=100, cx=50, cy=50, width=100, height=100,
    ...                    position=(0, 0, 1), look_at=(0, 1, 1))
    >>> b = a.with_pose(rotation_exp([0, 0, math.radians(2)]) @ a.rotation, a.position + [0.03, 0, 0])
    >>> [round(v, 6) for v in camera_error(a, b)]
    [0.03, 2.0]
    """
    pos = float(np.linalg.norm(estimate.position - truth.position))
    rot = float(np.degrees(np.linalg.norm(rotation_log(estimate.rotation @ truth.rotation.T))))
    return pos, rot


class Evaluation:
    """Per-frame truth comparison and its running statistics."""

    def __init__(self, scenario: Scenario, truth: Any) -> None:
        self.scenario = scenario
        self.truth = truth
        self.camera_position = Sample()
        self.camera_rotation = Sample()
        self.observed: dict[str, Sample] = {}
        self.imagined: dict[str, Sample] = {}

    @property
    def available(self) -> bool:
        """True when the reality has ground truth."""
        return self.truth is not None

    def add(self, index: int, time: float, record: dict[str, Any], camera: Camera) -> None:
        """Add ``truth``, ``camera_pose_error`` and ``errors`` to a frame's record."""
        if self.truth is None:
            return
        t = self.truth.at(index)
        if t is None:
            return
        truth_pos: dict[str, list[float] | None] = {}
        for name, obj in t.objects.items():
            truth_pos[name] = None if obj is None else [round(obj.position[0], 4),
                                                         round(obj.position[1], 4)]
        record["truth"] = truth_pos
        if getattr(t, "camera", None) is not None:
            pos, rot = camera_error(camera, t.camera)
            record["camera_pose_error"] = {"position_m": round(pos, 5),
                                           "rotation_deg": round(rot, 5)}
            self.camera_position.add(pos)
            self.camera_rotation.add(rot)
        errors: dict[str, dict[str, float | None]] = {}
        for name, seen in record["objects"].items():
            true = truth_pos.get(name)
            e: dict[str, float | None] = {"observed": None, "imagined": None}
            if true is not None:
                for key, store in (("observed", self.observed), ("imagined", self.imagined)):
                    p = seen.get(key)
                    if p is not None:
                        d = math.dist(p, true)
                        e[key] = round(d, 5)
                        store.setdefault(name, Sample()).add(d)
            errors[name] = e
        record["errors"] = errors

    def summary(self) -> dict[str, Any]:
        """Medians and percentiles of the errors (empty without truth)."""
        if self.truth is None:
            return {"ground_truth": False}
        return {
            "ground_truth": True,
            "camera_position_error_m": self.camera_position.summary(5),
            "camera_rotation_error_deg": self.camera_rotation.summary(5),
            "tracking_error_m": {name: s.summary() for name, s in sorted(self.observed.items())},
            "imagination_error_m": {name: s.summary() for name, s in sorted(self.imagined.items())},
        }
