"""The two-balls plugin: what the robot could catch, for the rules to choose from; and a
robot that always chases the nearest ball, to compare with.

Written only against adapt's public API (``import adapt``).  Named in the scenario's
``plugins:`` key, it registers the perceptual schema type ``reach-options``: it consumes
the ``object`` port of every foreground-object schema and, for each object it predicts,
writes an ``^option`` on the input-link:

``^object``
    the object;
``^reachable yes|no``
    whether the robot (its speed and acceleration limits, from rest) can reach some point
    of the predicted path before the object is there;
``^meet-in``
    seconds until the earliest such point (how soon the robot can have it);
``^confidence``
    the prediction's confidence at that time;
``^caught yes|no``
    the robot has it within its reach now.

The rules (``choose.soar``) pick the option reachable first among the confident ones,
instantiate an ``intercept`` schema for it, and switch to the other ball once it is caught.

:func:`nearest_chaser` is a baseline (``adapt.run(..., baselines={"nearest": ...})``): one
simulated robot, with the real one's limits, that always drives at the ball nearest to it
(the Kalman-filtered sighting), and counts a ball caught when it comes within reach.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

import adapt

#: Extra reach when the robot "has" a ball (metres), beyond touching it.
MARGIN = 0.03


def travel_time(distance: float, max_speed: float, max_accel: float) -> float:
    """Seconds a robot starting at rest needs to cover ``distance`` (accelerating, then at
    ``max_speed``).

    >>> round(travel_time(1.0, 1.0, 2.0), 3), round(travel_time(0.1, 1.0, 2.0), 3)
    (1.25, 0.316)
    """
    ramp = max_speed * max_speed / (2.0 * max_accel)
    if distance <= ramp:
        return math.sqrt(2.0 * distance / max_accel)
    return max_speed / max_accel + (distance - ramp) / max_speed


class ReachOptions(adapt.Schema):
    """The ``reach-options`` schema (see the module docstring)."""

    def __init__(self, name: str, spec: adapt.SchemaSpec, parameters: Mapping[str, Any],
                 network: Any) -> None:
        super().__init__(name, spec, parameters, network)
        if network.robot is None:
            raise ValueError("the world has no robot to reach anything with")
        self.options: dict[str, dict[str, Any]] = {}

    def perceive(self, frame: adapt.Frame) -> None:
        robot = self.network.robot
        pose = self.network.robot_pose()
        self.options = {}
        if pose is None:
            return
        here = pose[0]
        for p in self.network.percepts(self, "object", adapt.ObjectPercept):
            where = p.observed or p.imagined
            if where is None or p.ball is None:
                continue
            reach = robot.radius + p.ball.radius + MARGIN
            option: dict[str, Any] = {"caught": math.dist(where, here) <= reach,
                                      "reachable": False, "meet_in": None, "confidence": 0.0}
            pred = p.prediction
            if pred is not None:
                path = pred.trajectory
                for t, xy in zip(path.times, path.positions):
                    ahead = float(t) - frame.time
                    if ahead < 0:
                        continue
                    gap = max(0.0, math.dist((float(xy[0]), float(xy[1])), here) - reach)
                    if travel_time(gap, robot.max_speed, robot.max_accel) <= ahead:
                        horizons = [h.horizon for h in pred.horizons]
                        confs = [h.confidence for h in pred.horizons]
                        option.update(reachable=True, meet_in=ahead,
                                      confidence=float(np.interp(ahead, horizons, confs)))
                        break
            self.options[p.object] = option

    def write(self, node: adapt.Structure) -> None:
        for name, o in self.options.items():
            c = node.child("option", name)
            c.set("object", name)
            c.set("reachable", o["reachable"])
            c.set("meet-in", None if o["meet_in"] is None else round(o["meet_in"], 3))
            c.set("confidence", round(o["confidence"], 3))
            c.set("caught", o["caught"])
        node.keep_children("option", list(self.options))


def _make(name: str, parameters: Mapping[str, Any], network: Any) -> ReachOptions:
    return ReachOptions(name, REACH_OPTIONS, parameters, network)


REACH_OPTIONS = adapt.REGISTRY.register(adapt.SchemaSpec(
    name="reach-options",
    kind=adapt.SchemaKind.PERCEPTUAL,
    doc="For every predicted object: whether the robot can reach its path in time, how soon, "
        "with what confidence, and whether it has it now.",
    factory=_make,
    consumes=(adapt.Port("object", "the objects' predictions"),),
))


class _Chaser:
    """The one simulated robot of the nearest-ball baseline, shared by its per-object parts."""

    def __init__(self, setup: adapt.BaselineSetup) -> None:
        robot = setup.robot
        assert robot is not None, "the nearest-ball baseline needs a robot"
        self.robot = robot
        self.position = (float(robot.position[0]), float(robot.position[1]))
        self.velocity = (0.0, 0.0)
        self.time: float | None = None
        self.balls: dict[int, tuple[adapt.ConstantVelocityKF, float]] = {}
        self.caught: set[int] = set()

    def move(self, time: float) -> None:
        """Once a frame: drive at the nearest ball not caught yet."""
        if self.time is not None and time <= self.time:
            return
        dt = 0.0 if self.time is None else time - self.time
        self.time = time
        live = [(math.dist(kf.position, self.position), key, kf, radius)
                for key, (kf, radius) in self.balls.items()
                if kf.initialised and key not in self.caught]
        want = (0.0, 0.0)
        if live:
            d, key, kf, radius = min(live, key=lambda x: x[0])
            if d <= self.robot.radius + radius + MARGIN:
                self.caught.add(key)
            elif d > 1e-6:
                speed = min(self.robot.max_speed, math.sqrt(2.0 * self.robot.max_accel * d))
                want = ((kf.position[0] - self.position[0]) / d * speed,
                        (kf.position[1] - self.position[1]) / d * speed)
        dvx, dvy = want[0] - self.velocity[0], want[1] - self.velocity[1]
        dv, cap = math.hypot(dvx, dvy), self.robot.max_accel * dt
        if dv > cap > 0:
            dvx, dvy = dvx * cap / dv, dvy * cap / dv
        self.velocity = (self.velocity[0] + dvx, self.velocity[1] + dvy)
        self.position = (self.position[0] + self.velocity[0] * dt,
                         self.position[1] + self.velocity[1] * dt)


class _Part:
    """One ball as the nearest-ball baseline follows it (an ``ObjectBaseline``)."""

    def __init__(self, chaser: _Chaser, setup: adapt.BaselineSetup) -> None:
        self.chaser = chaser
        self.key = len(chaser.balls)
        self.filter = adapt.ConstantVelocityKF()
        # the catch reach the run computed for this object, less the robot's radius: the ball's
        chaser.balls[self.key] = (self.filter, max(setup.reach - chaser.robot.radius, 0.0))
        self.horizons = setup.horizons

    def step(self, time: float, sighting: Any) -> None:
        self.filter.step(time, sighting)
        self.chaser.move(time)

    def predictions(self) -> tuple[adapt.BaselinePrediction, ...]:
        if not self.filter.initialised:
            return ()
        (px, py), (vx, vy) = self.filter.position, self.filter.velocity
        return tuple(adapt.BaselinePrediction(h, (px + vx * h, py + vy * h)) for h in self.horizons)

    @property
    def robot_position(self) -> tuple[float, float] | None:
        return self.chaser.position

    @property
    def caught(self) -> bool:
        return self.key in self.chaser.caught


def nearest_chaser() -> Any:
    """A baseline factory: the parts of one nearest-ball chaser (made again for each run)."""
    shared: list[_Chaser] = []

    def part(setup: adapt.BaselineSetup) -> _Part:
        if not shared:
            shared.append(_Chaser(setup))
        return _Part(shared[0], setup)

    return part
