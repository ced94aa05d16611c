"""The baselines the mirror is measured against, run in the same run on the same sightings.

Baselines are a keyed collection (:func:`default_baselines`: ``kalman`` and
``mapaware``, :mod:`adapt.runner.mapaware`), each a :class:`BaselineSet`: one baseline per object
(:class:`ObjectBaseline`, made by the set's factory when the object is first
perceived with a size), stepped by the loop every frame on the object's
sighting, returning a :class:`BaselineState` (its predictions and the
robots it drives) that goes into the frame record.  The evaluation, the
report and the figures iterate the collection; the report writes the
``kalman`` baseline under its historic key ``baseline``
(:func:`report_key`).

The Kalman baseline (:class:`Baseline`):

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
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Callable, Mapping, Protocol, Sequence

import numpy as np

from adapt.imagination import Ball, RobotSpec, SceneSpec
from adapt.imagination.footprint import Footprint
from adapt.imagination.predict import Trajectory, intercept, intercept_reach
from adapt.kalman import ConstantVelocityKF
from adapt.schemas.percepts import ObjectPercept

__all__ = ["Baseline", "SimulatedRobot", "BaselinePrediction", "ObjectBaseline", "BaselineSetup",
           "BaselineState", "BaselineSet", "default_baselines", "report_key", "REPORT_KEYS"]

Vec2 = tuple[float, float]

#: The key a baseline's outputs have in ``report.json`` (contract keys), when not its name.
REPORT_KEYS = {"kalman": "baseline"}


def report_key(name: str) -> str:
    """The key of baseline ``name`` in the report and the summary.

    >>> report_key("kalman"), report_key("reflecting")
    ('baseline', 'reflecting')
    """
    return REPORT_KEYS.get(name, name)


@dataclass(frozen=True, slots=True)
class BaselinePrediction:
    """Where a baseline expects the object ``horizon`` seconds ahead."""

    horizon: float
    position: Vec2


class ObjectBaseline(Protocol):
    """A baseline for one object: what it predicts and the robot it drives."""

    def step(self, time: float, sighting: Sequence[float] | None) -> None:
        """Take this frame's sighting (None: not seen) and drive for one frame."""
        ...

    def predictions(self) -> tuple[BaselinePrediction, ...]:
        """Its predictions at the horizons (empty before it can predict)."""
        ...

    @property
    def robot_position(self) -> Vec2 | None:
        """Where its simulated robot is (None without a robot)."""
        ...


@dataclass(frozen=True, slots=True)
class BaselineSetup:
    """What a baseline for one object is made with: the real robot's model (None without
    a robot), the catch reach for this object, the horizons, the frame interval, the
    scene (its walls and obstacles) and the object's model (its size and nominal
    parameters, as perception knows them)."""

    robot: RobotSpec | None
    reach: float
    horizons: tuple[float, ...]
    dt: float
    scene: SceneSpec
    ball: Ball | None = None


#: Makes a baseline for one object.
BaselineFactory = Callable[[BaselineSetup], ObjectBaseline]


@dataclass(frozen=True, slots=True, eq=False)
class BaselineState:
    """One baseline in one frame: its predictions and its robot's position, per object."""

    name: str
    predictions: Mapping[str, tuple[BaselinePrediction, ...]] = field(
        default_factory=lambda: MappingProxyType({}))
    robots: Mapping[str, Vec2 | None] = field(default_factory=lambda: MappingProxyType({}))


class BaselineSet:
    """One named baseline over every object (see the module docstring)."""

    def __init__(self, name: str, factory: BaselineFactory, *, robot: RobotSpec | None,
                 horizons: Sequence[float], dt: float, scene: SceneSpec) -> None:
        self.name = name
        self.factory = factory
        self.robot = robot
        self.horizons = tuple(horizons)
        self.dt = dt
        self.scene = scene
        self.objects: dict[str, ObjectBaseline] = {}

    def step(self, time: float, objects: Sequence[ObjectPercept]) -> BaselineState:
        """Step each object's baseline on its sighting (an object is followed from the
        first frame its size is known)."""
        preds: dict[str, tuple[BaselinePrediction, ...]] = {}
        robots: dict[str, Vec2 | None] = {}
        for p in objects:
            if p.ball is None:
                continue
            b = self.objects.get(p.object)
            if b is None:
                reach = 0.0 if self.robot is None else intercept_reach(p.ball, self.robot)
                b = self.objects[p.object] = self.factory(BaselineSetup(
                    self.robot, reach, self.horizons, self.dt, self.scene, p.ball))
            b.step(time, None if p.sighting is None else p.sighting.position)
            preds[p.object] = b.predictions()
            robots[p.object] = b.robot_position
        return BaselineState(self.name, MappingProxyType(preds), MappingProxyType(robots))


def kalman(setup: BaselineSetup) -> "Baseline":
    """The constant-velocity Kalman baseline for one object (:class:`Baseline`)."""
    return Baseline(setup.robot, reach=setup.reach, horizons=setup.horizons, dt=setup.dt,
                    scene=setup.scene)


def default_baselines(robot: RobotSpec | None, *, horizons: Sequence[float], dt: float,
                      scene: SceneSpec) -> dict[str, BaselineSet]:
    """The baselines every run has, by name: ``kalman`` and ``mapaware``."""
    from adapt.runner.mapaware import mapaware  # it derives from Baseline, below

    return {name: BaselineSet(name, factory, robot=robot, horizons=horizons, dt=dt, scene=scene)
            for name, factory in (("kalman", kalman), ("mapaware", mapaware))}


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
            None if scene is None else Footprint(scene, robot.outer_radius))
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
            p = self.kf.position
            times = np.linspace(0.0, self.plan, 91)
            positions, velocities = self.path(times)
            path = Trajectory("baseline", time + times, positions, velocities, ())
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

    def path(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities ``(N, 2)`` the baseline expects ``times`` seconds after
        the filter's time: a straight line at the filtered velocity."""
        p, v = np.array(self.kf.position), np.array(self.kf.velocity)
        t = np.asarray(times, float)
        return p[None, :] + t[:, None] * v[None, :], np.tile(v, (len(t), 1))

    def predict(self, horizon: float) -> tuple[float, float]:
        """Where the baseline expects the object ``horizon`` seconds after the filter's time."""
        x, y = self.path(np.array([horizon]))[0][0]
        return (float(x), float(y))

    def predictions(self) -> tuple[BaselinePrediction, ...]:
        """Predictions at the horizons along :meth:`path` (empty before any sighting)."""
        if not self.kf.initialised:
            return ()
        return tuple(BaselinePrediction(h, self.predict(h)) for h in self.horizons)

    @property
    def robot_position(self) -> Vec2 | None:
        """Where its simulated robot is (None without a robot)."""
        if self.robot is None:
            return None
        return (float(self.robot.position[0]), float(self.robot.position[1]))
