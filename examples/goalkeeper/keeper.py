"""The goalkeeper plugin: a motor schema that keeps the robot on a goal line, and a keeper
driven by a Kalman filter to compare it with.

Written only against adapt's public API (``import adapt``).  Named in the scenario's
``plugins:`` key (``keeper.py``), it registers the schema type ``goal-keeper``:

* it consumes the ``object`` port (a foreground-object schema's
  :class:`adapt.ObjectPercept`) and, every frame, finds where the object's predicted path
  first crosses the goal line ``y = line_y``, with the prediction's confidence there;
* on the input-link it writes ``^keeps`` (the object), ``^crossing yes|no``, ``^crossing-x``, ``^crossing-in``
  (seconds) and ``^confidence``, and ``^committed yes|no``;
* the rules decide when to commit (``^command`` with ``^commit yes``); until then the robot
  guards the middle of the goal, then it goes along the line to the crossing point (never
  past a post), and follows the prediction as it changes.

:func:`kalman_keeper` is a baseline (``adapt.run(..., baselines={"kalman-keeper": ...})``):
the same keeper, but its crossing point comes from a constant-velocity Kalman filter on
the same sightings, extrapolated in a straight line (no bounce), driving a simulated robot
with the real one's limits.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

import adapt

#: Where the robot stands when it has no plan: this far in front of the goal's middle.
GUARD = 0.0


def line_crossing(times: np.ndarray, positions: np.ndarray, line_y: float
                  ) -> tuple[float, float] | None:
    """``(time, x)`` where a path first crosses ``y = line_y`` going down, or None.

    >>> line_crossing(np.array([0.0, 1.0, 2.0]), np.array([[0.0, 2.0], [0.5, 1.0], [1.0, 0.0]]), 0.5)
    (1.5, 0.75)
    """
    y = positions[:, 1] - line_y
    for i in range(1, len(y)):
        if y[i - 1] > 0.0 >= y[i]:
            f = y[i - 1] / (y[i - 1] - y[i])
            return (float(times[i - 1] + f * (times[i] - times[i - 1])),
                    float(positions[i - 1, 0] + f * (positions[i, 0] - positions[i - 1, 0])))
    return None


def along_line(here: tuple[float, float], x: float, line_y: float, max_speed: float,
               max_accel: float) -> tuple[float, float]:
    """The velocity that takes a robot at ``here`` to ``(x, line_y)``, no faster than
    ``max_speed`` and slow enough to stop there.

    >>> along_line((0.0, 0.0), 1.0, 0.0, 0.5, 2.0)
    (0.5, 0.0)
    """
    dx, dy = x - here[0], line_y - here[1]
    dist = math.hypot(dx, dy)
    if dist < 0.01:
        return (0.0, 0.0)
    speed = min(max_speed, math.sqrt(2.0 * max_accel * dist))
    return (dx / dist * speed, dy / dist * speed)


class GoalKeeper(adapt.Schema):
    """The ``goal-keeper`` schema (see the module docstring)."""

    def __init__(self, name: str, spec: adapt.SchemaSpec, parameters: Mapping[str, Any],
                 network: Any) -> None:
        super().__init__(name, spec, parameters, network)
        if network.robot is None:
            raise ValueError("the world has no robot to keep the goal with")
        self.object_name = str(parameters["object"])
        self.committed = False
        self.crossing: tuple[float, float] | None = None   # (time, x)
        self.confidence = 0.0

    def command(self, attributes: Mapping[str, Any]) -> str | None:
        if attributes.get("commit") in ("yes", "no"):
            self.committed = attributes["commit"] == "yes"
            self.status = adapt.Status.EXECUTING if self.committed else adapt.Status.IDLE
            return None
        return "a goal-keeper command is ^commit yes or ^commit no"

    def watched(self) -> adapt.ObjectPercept | None:
        for p in self.network.percepts(self, "object", adapt.ObjectPercept):
            if p.object == self.object_name:
                return p
        return None

    def act(self, time: float) -> None:
        line_y = float(self.parameters["line_y"])
        left, right = float(self.parameters["left"]), float(self.parameters["right"])
        obj = self.watched()
        self.crossing, self.confidence = None, 0.0
        pred = None if obj is None else obj.prediction
        if pred is not None:
            path = pred.trajectory
            self.crossing = line_crossing(path.times, path.positions, line_y)
            if self.crossing is not None:
                ahead = [h.horizon for h in pred.horizons]
                conf = [h.confidence for h in pred.horizons]
                self.confidence = float(np.interp(self.crossing[0] - pred.time, ahead, conf))
        x = (left + right) / 2.0 + GUARD
        if self.committed and self.crossing is not None:
            x = min(max(self.crossing[1], left), right)
        pose = self.network.robot_pose()
        robot = self.network.robot
        if pose is None or robot is None:
            return
        speed = robot.max_speed * float(self.parameters["speed"])
        self.network.command_robot(along_line(pose[0], x, line_y, speed, robot.max_accel))

    def write(self, node: adapt.Structure) -> None:
        node.set("keeps", self.object_name)  # not ^object: that says a schema monitors it
        node.set("committed", self.committed)
        node.set("crossing", self.crossing is not None)
        node.set("crossing-x", None if self.crossing is None else round(self.crossing[1], 4))
        node.set("crossing-in", None if self.crossing is None
                 else round(self.crossing[0] - self.network.time, 4))
        node.set("confidence", round(self.confidence, 3))

    def stop(self) -> None:
        self.network.command_robot((0.0, 0.0))


def _make(name: str, parameters: Mapping[str, Any], network: Any) -> GoalKeeper:
    return GoalKeeper(name, GOAL_KEEPER, parameters, network)


GOAL_KEEPER = adapt.REGISTRY.register(adapt.SchemaSpec(
    name="goal-keeper",
    kind=adapt.SchemaKind.MOTOR,
    doc="Keeps the robot on the goal line between the predicted ball and the goal; goes to "
        "where the predicted path crosses the line once the rules commit.",
    factory=_make,
    consumes=(adapt.Port("object", "the object's prediction"),),
    parameters=(
        adapt.Parameter("object", str, "ball", "the world object to keep out"),
        adapt.Parameter("line_y", float, 0.0, "the goal line, y", unit="m"),
        adapt.Parameter("left", float, -1.0, "the left post, x", unit="m"),
        adapt.Parameter("right", float, 1.0, "the right post, x", unit="m"),
        adapt.Parameter("speed", float, 1.0, "fraction of the robot's max_speed to use",
                        low=0.0, high=1.0, low_open=True),
    ),
))


class KalmanKeeper:
    """The baseline keeper for one object (see the module docstring)."""

    def __init__(self, setup: adapt.BaselineSetup, line_y: float, left: float,
                 right: float) -> None:
        self.filter = adapt.ConstantVelocityKF()
        self.setup = setup
        self.line = (line_y, left, right)
        robot = setup.robot
        assert robot is not None, "the keeper baseline needs a robot"
        self.position = (float(robot.position[0]), float(robot.position[1]))
        self.velocity = (0.0, 0.0)
        self.time: float | None = None

    def step(self, time: float, sighting: Any) -> None:
        self.filter.step(time, sighting)
        dt = 0.0 if self.time is None else time - self.time
        self.time = time
        line_y, left, right = self.line
        x = (left + right) / 2.0 + GUARD
        if self.filter.initialised:
            (px, py), (vx, vy) = self.filter.position, self.filter.velocity
            if vy < -1e-3 and py > line_y:
                x = min(max(px + vx * (line_y - py) / vy, left), right)
        robot = self.setup.robot
        assert robot is not None
        want = along_line(self.position, x, line_y, robot.max_speed, robot.max_accel)
        # the robot's acceleration limit, then its motion over the frame
        dvx, dvy = want[0] - self.velocity[0], want[1] - self.velocity[1]
        dv = math.hypot(dvx, dvy)
        cap = robot.max_accel * dt
        if dv > cap > 0:
            dvx, dvy = dvx * cap / dv, dvy * cap / dv
        self.velocity = (self.velocity[0] + dvx, self.velocity[1] + dvy)
        self.position = (self.position[0] + self.velocity[0] * dt,
                         self.position[1] + self.velocity[1] * dt)

    def predictions(self) -> tuple[adapt.BaselinePrediction, ...]:
        if not self.filter.initialised:
            return ()
        (px, py), (vx, vy) = self.filter.position, self.filter.velocity
        return tuple(adapt.BaselinePrediction(h, (px + vx * h, py + vy * h))
                     for h in self.setup.horizons)

    @property
    def robot_position(self) -> tuple[float, float] | None:
        return self.position


def kalman_keeper(line_y: float, left: float, right: float) -> Any:
    """A baseline factory: a :class:`KalmanKeeper` on this goal for each object."""
    return lambda setup: KalmanKeeper(setup, line_y, left, right)
