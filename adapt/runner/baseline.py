"""The baseline the mirror is measured against, run in the same run on the same sightings.

A constant-velocity Kalman filter (:class:`~adapt.kalman.ConstantVelocityKF`,
no bounce handling) follows each object from the sightings its perceptual
schema makes; it predicts at the same horizons by straight-line
extrapolation, and drives a simulated robot with the real robot's speed and
acceleration limits and its footprint (it goes round obstacles like the robot's drive schema,
slides along what it still meets, and does not pass where the real robot would not fit), re-planned every frame towards the earliest point of
its own predicted straight path the robot can reach, or, when no point of it
is reachable, towards where the filter has the object now (pursuit).  That is
the tracker the paper argues cannot foresee a bounce ("playing catch-up").

The baseline sees what perception sees, never the truth; the evaluation
scores it against the truth like the mirror.

Examples
--------
>>> from adapt.imagination import RobotSpec
>>> b = Baseline(RobotSpec(position=(0.0, -1.0), max_speed=1.0, max_accel=2.0), reach=0.3,
...              horizons=(0.5, 1.0), dt=1 / 30)
>>> for k in range(20):
...     b.step(k / 30, (0.5 * k / 30, 1.0))
>>> [round(v, 2) for v in b.predict(1.0)]
[0.82, 1.0]
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from adapt.imagination import RobotSpec, SceneSpec
from adapt.imagination.footprint import Footprint
from adapt.imagination.predict import Trajectory, intercept
from adapt.imagination.reach import body_radius
from adapt.kalman import ConstantVelocityKF

__all__ = ["Baseline", "SimulatedRobot"]


class SimulatedRobot:
    """A robot with bounded speed and acceleration, driven towards a target.

    With a ``footprint`` it is the real robot's body: it never stands where that body does
    not fit (a wall, an obstacle, a gap too narrow), and slides along what blocks it (the
    part of the step along x or y that fits); without one it is a point.
    """

    def __init__(self, position: Sequence[float], max_speed: float, max_accel: float,
                 footprint: Footprint | None = None) -> None:
        self.position = np.array(position[:2], float)
        self.velocity = np.zeros(2)
        self.max_speed = max_speed
        self.max_accel = max_accel
        self.footprint = footprint

    def _move(self, h: float) -> None:
        step = self.velocity * h
        fp = self.footprint
        if fp is None or fp.clear(tuple(self.position + step)):
            self.position += step
            return
        for keep in (np.array([1.0, 0.0]), np.array([0.0, 1.0])):
            if fp.clear(tuple(self.position + step * keep)):
                self.position += step * keep
                self.velocity *= keep
                return
        self.velocity[:] = 0.0

    def drive(self, target: Sequence[float] | None, seconds: float, substep: float = 1 / 240) -> None:
        """Move for ``seconds`` towards ``target`` (None: brake), arriving at rest."""
        n = max(1, int(round(seconds / substep)))
        h = seconds / n
        for _ in range(n):
            if target is None:
                want = np.zeros(2)
            else:
                d = np.asarray(target, float) - self.position
                dist = float(np.linalg.norm(d))
                speed = min(self.max_speed, math.sqrt(2.0 * self.max_accel * dist))
                want = d / dist * speed if dist > 1e-9 else np.zeros(2)
            dv = want - self.velocity
            lim = self.max_accel * h
            norm = float(np.linalg.norm(dv))
            if norm > lim:
                dv *= lim / norm
            self.velocity += dv
            self._move(h)


class Baseline:
    """A constant-velocity Kalman filter and the robot it would drive (see the module docstring)."""

    def __init__(self, robot: RobotSpec | None, *, reach: float, horizons: Sequence[float],
                 dt: float, q: float = 0.3, r: float = 0.005, plan: float = 3.0,
                 scene: SceneSpec | None = None) -> None:
        self.kf = ConstantVelocityKF(q=q, r=r)
        #: The simulated robot (None in a world without a robot: predictions only), with the
        #: real robot's footprint in ``scene``'s walls and obstacles when a scene is given.
        self.robot = None if robot is None else SimulatedRobot(
            robot.position, robot.max_speed, robot.max_accel,
            None if scene is None else Footprint(scene, body_radius(robot)))
        self.reach = reach
        self.horizons = tuple(horizons)
        self.dt = dt
        self.plan = plan
        self.target: tuple[float, float] | None = None

    def step(self, time: float, sighting: Sequence[float] | None) -> None:
        """Take this frame's sighting (None: not seen), re-plan, and drive for one frame."""
        self.kf.step(time, sighting)
        self.target = None
        if self.robot is None:
            return
        if self.kf.initialised and self.kf.updates >= 3:
            p, v = np.array(self.kf.position), np.array(self.kf.velocity)
            times = np.linspace(time, time + self.plan, 91)
            path = Trajectory("baseline", times, p[None, :] + (times - time)[:, None] * v[None, :],
                              np.tile(v, (len(times), 1)), ())
            hit = intercept(path, self.robot.position, self.robot.max_speed, self.robot.max_accel,  # type: ignore[arg-type]
                            reach=self.reach, start=time)
            self.target = hit.position if hit is not None else (float(p[0]), float(p[1]))
        self.robot.drive(self._next_point(), self.dt)

    def _next_point(self) -> tuple[float, float] | None:
        """The target, or the next corner on the way round what stands in between (when
        the target is a place the robot fits)."""
        assert self.robot is not None
        fp = self.robot.footprint
        if fp is None or self.target is None:
            return self.target
        way = fp.route(tuple(self.robot.position), self.target)
        return self.target if way is None else way[0]

    def predict(self, horizon: float) -> tuple[float, float]:
        """Where the filter expects the object ``horizon`` seconds after its last time."""
        return self.kf.predict_position(horizon)

    def predictions(self) -> list[dict[str, object]]:
        """The report's form: ``[{"horizon", "position"}]`` (empty before any sighting)."""
        if not self.kf.initialised:
            return []
        return [{"horizon": h, "position": [round(v, 4) for v in self.predict(h)]}
                for h in self.horizons]
