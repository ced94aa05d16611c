"""The drive motor schema: take the robot to a floor point.

Commands come from the output-link (``^command`` with ``^schema <name>``):
``^x`` and ``^y`` set a target (metres, floor frame), ``^stop yes`` stops.
Each frame the schema commands a velocity towards the target, no faster than
the robot's ``max_speed`` and slowing so that ``max_accel`` can stop it
there, to both the real robot (when reality has one) and the imagined one
(the commanded motion: odometry).  When an obstacle or a wall stands on the
straight line, it goes round, through points just off the obstacles'
corners (:meth:`Footprint.route <adapt.imagination.footprint.Footprint.route>`,
re-planned from where the robot is whenever it passes one of them, and
every half second).  The robot moves without turning.  Its
status is ``idle``, ``executing``, ``complete`` (within ``tolerance``) or
``failed`` (a target off the floor, inside an obstacle, or not reached
within ``timeout``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping

from adapt.imagination.footprint import Footprint
from adapt.imagination.scene import Vec2
from adapt.schemas.base import Schema, Status
from adapt.schemas.links import Structure
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.schemas.network import SchemaNetwork

__all__ = ["Drive", "DRIVE", "REPLAN_S"]

#: The way round is planned again this often (seconds) while driving.
REPLAN_S = 0.5


class Drive(Schema):
    """See the module docstring."""

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        super().__init__(name, spec, parameters, network)
        robot = network.mirror.scene.robot
        if robot is None:
            raise ValueError("the world has no robot to drive")
        self.robot = robot
        self.target: Vec2 | None = None
        #: the robot's footprint in the scene: where it fits, and the way round
        self.footprint = Footprint(network.mirror.scene, robot.outer_radius)
        #: the points still to drive through, ending at the target
        self.way: list[Vec2] = []
        self._way_for: Vec2 | None = None
        self._way_time = -math.inf
        self.started = 0.0
        self.commands = 0
        self._velocity = (0.0, 0.0)
        self._turn = 0.0

    def command(self, attributes: Mapping[str, Any]) -> str | None:
        if attributes.get("stop") in ("yes", "true"):
            self.target = None
            self.status = Status.IDLE
            self._send((0.0, 0.0))
            return None
        try:
            x, y = float(attributes["x"]), float(attributes["y"])
        except (KeyError, TypeError, ValueError):
            return "a drive command needs ^x and ^y (metres) or ^stop yes"
        if not (math.isfinite(x) and math.isfinite(y)):
            return "^x and ^y must be finite numbers"
        self.commands += 1
        reason = self._unreachable((x, y))
        if reason:
            self.target = None
            self.status = Status.FAILED
            self.message = reason
            self._send((0.0, 0.0))
            return None
        if self.target is None or self.status is not Status.EXECUTING:
            self.started = self.network.time
        self.target = (x, y)
        self.status = Status.EXECUTING
        self.message = ""
        return None

    def _unreachable(self, p: Vec2) -> str:
        scene = self.network.mirror.scene
        margin = self.robot.inner_radius
        if scene.floor.extent is not None:
            x0, y0, x1, y1 = scene.floor.extent
            if not (x0 + margin <= p[0] <= x1 - margin and y0 + margin <= p[1] <= y1 - margin):
                return f"target ({p[0]:g}, {p[1]:g}) is off the floor for a robot this size"
        ob = self.footprint.obstacle_at(p)
        if ob is not None:
            return f"target ({p[0]:g}, {p[1]:g}) is inside obstacle {ob.name!r}"
        return ""

    def act(self, time: float) -> None:
        if self.status is not Status.EXECUTING or self.target is None:
            return
        pose = self.network.mirror.robot_pose()
        assert pose is not None
        (x, y), _ = pose
        tolerance = float(self.parameters["tolerance"])
        if math.hypot(self.target[0] - x, self.target[1] - y) <= tolerance:
            self.status = Status.COMPLETE
            self.way = []
            self._send((0.0, 0.0))
            return
        if time - self.started > float(self.parameters["timeout"]):
            self.status = Status.FAILED
            self.message = f"not there after {self.parameters['timeout']:g} s"
            self._send((0.0, 0.0))
            return
        nx, ny = self._next_point((x, y), time, tolerance)
        dx, dy = nx - x, ny - y
        dist = math.hypot(dx, dy)
        if dist <= 1e-9:
            self._send((0.0, 0.0))
            return
        speed = min(self.robot.max_speed * float(self.parameters["speed"]),
                    math.sqrt(2.0 * self.robot.max_accel * dist))
        self._send((dx / dist * speed, dy / dist * speed))

    def _next_point(self, here: Vec2, time: float, tolerance: float) -> Vec2:
        """The point to head for now: the target, or the next corner on the way round."""
        assert self.target is not None
        if self.way and len(self.way) > 1 and math.dist(here, self.way[0]) <= max(tolerance, 0.05):
            self.way.pop(0)
            self._way_time = -math.inf  # passed a corner: look again from here
        if self._way_for != self.target or time - self._way_time >= REPLAN_S or not self.way:
            way = self.footprint.route(here, self.target)
            # no way round (the target does not fit, or all is blocked): head straight for it
            self.way = way if way is not None else [self.target]
            self._way_for, self._way_time = self.target, time
        return self.way[0]

    def _send(self, velocity: Vec2, turn: float | None = None) -> None:
        """Command the robot's velocity (world frame, m/s) and, when given, its turn rate
        (rad/s; otherwise the last one), in the imagination and the reality alike."""
        self._velocity = velocity
        if turn is not None:
            self._turn = turn
        self.network.command_robot(velocity, self._turn)

    def distance(self) -> float | None:
        """Odometry distance to the target, or None."""
        pose = self.network.mirror.robot_pose()
        if self.target is None or pose is None:
            return None
        (x, y), _ = pose
        return math.hypot(self.target[0] - x, self.target[1] - y)

    def write(self, node: Structure) -> None:
        node.set("target-x", None if self.target is None else round(self.target[0], 4))
        node.set("target-y", None if self.target is None else round(self.target[1], 4))
        d = self.distance()
        node.set("distance", None if d is None else round(d, 4))
        node.set("message", self.message or None)

    def stop(self) -> None:
        self._send((0.0, 0.0))

    def summary(self) -> dict[str, Any]:
        out = super().summary()
        out["target"] = None if self.target is None else [round(v, 4) for v in self.target]
        return out


def _make(name: str, parameters: Mapping[str, Any], network: "SchemaNetwork") -> Drive:
    return Drive(name, DRIVE, parameters, network)


DRIVE = SchemaSpec(
    name="drive",
    kind=SchemaKind.MOTOR,
    doc=("Drives the robot to a commanded floor point within its speed and acceleration "
         "limits, in reality and in the imagination (odometry)."),
    factory=_make,
    consumes=(Port("camera", "the synchronised camera (the robot's own pose)"),),
    parameters=(
        Parameter("tolerance", float, 0.05, "arrived when this close", unit="m", low=0.0,
                  high=100.0, low_open=True),
        Parameter("speed", float, 1.0, "fraction of the robot's max_speed to use", low=0.0,
                  high=1.0, low_open=True),
        Parameter("timeout", float, 30.0, "give up after this long", unit="s", low=0.0,
                  high=86400.0, low_open=True),
    ),
    singleton=False,
)
