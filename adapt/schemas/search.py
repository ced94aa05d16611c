"""The search motor schema: turn the robot round until its own camera sees an object.

A camera on the robot sees a sixth of the room.  A goal's object that left its
view before anything monitored it (a ball rolled across while the first look
was learned, or from behind the robot) is found only by looking round.  While
the schema runs it waits ``delay`` seconds (an object in view is spawned for
in a few frames), then turns the robot in place at ``turn_rate``: first
towards the middle of the floor (the side where more of the room lies), and
on round, for as long as it runs -- but holds still while a difference region
looks like the object (its colour and size, on the ``regions`` port): a
turning camera's difference holds its motion's errors and is rarely in step
enough for the rules to spawn a schema for it.  A region that looks like the object but
is cut by the frame's left or right side holds nothing (the rules spawn no schema for a
region at the frame's edge): the robot turns towards where it stands on the floor, which
brings it into the view.  The rules (``rules/mirror/intercept.soar``)
put it in place for a goal's object that no perceptual schema follows (none
monitors it, or the one that does lost it before the imagination had it), seen
from a camera on the robot, and remove it once one does: the intercept schema
then turns the robot to face the object.  On removal the robot stops turning.

Status: ``idle`` while it waits, ``executing`` while it turns or holds.  It
writes ``^turned`` (radians turned so far), ``^direction`` (``left``:
counter-clockwise, or ``right``) and ``^holding`` (a region looks like the
object).

Examples
--------
>>> from adapt.schemas.search import SEARCH
>>> [p.name for p in SEARCH.parameters]
['object', 'turn_rate', 'delay']
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping

from adapt.schemas.base import Schema, Status
from adapt.schemas.links import Structure
from adapt.schemas.percepts import BackgroundPercept
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.schemas.network import SchemaNetwork

__all__ = ["Search", "SEARCH", "turn_direction"]


def turn_direction(position: tuple[float, float], heading: float,
                   towards: tuple[float, float]) -> float:
    """``+1.0`` (counter-clockwise) when ``towards`` lies to the left of a robot at
    ``position`` facing ``heading`` (radians from +x), else ``-1.0``; left when it is
    straight ahead or behind, or where the robot stands.

    >>> turn_direction((0.0, 0.0), 0.0, (1.0, 1.0)), turn_direction((0.0, 0.0), 0.0, (1.0, -1.0))
    (1.0, -1.0)
    >>> turn_direction((1.0, 1.0), math.pi / 2, (0.0, 0.0))   # facing +y, the point behind-left
    1.0
    """
    dx, dy = towards[0] - position[0], towards[1] - position[1]
    side = math.cos(heading) * dy - math.sin(heading) * dx  # the cross product: left > 0
    return -1.0 if side < 0.0 else 1.0


class Search(Schema):
    """See the module docstring."""

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        super().__init__(name, spec, parameters, network)
        if network.mirror.scene.robot is None:
            raise ValueError("the world has no robot to turn")
        self.object_name = str(parameters["object"])
        self.started = network.time
        #: +1 counter-clockwise, -1 clockwise; None until it turns
        self.direction: float | None = None
        self.turned = 0.0
        #: a difference region looks like the object: not turning
        self.holding = False
        self._heading: float | None = None

    def act(self, time: float) -> None:
        pose = self.network.mirror.robot_pose()
        if pose is None:
            return
        (x, y), heading = pose
        if self._heading is not None:
            step = (heading - self._heading + math.pi) % (2.0 * math.pi) - math.pi
            self.turned += abs(step)
        self._heading = heading
        rate = float(self.parameters["turn_rate"])
        if time - self.started < float(self.parameters["delay"]) or rate <= 0.0:
            return
        if self.direction is None:
            self.direction = turn_direction((x, y), heading, self._middle((x, y)))
            self.status = Status.EXECUTING
        bg = self.network.percept(self, "regions", BackgroundPercept)
        looks = [] if bg is None else [r for r in bg.regions if r.looks_like == self.object_name]
        width = 0 if bg is None else bg.camera_before.width
        cut = [r for r in looks if r.bbox[0] <= 0 or r.bbox[0] + r.bbox[2] >= width]
        self.holding = len(looks) > len(cut)
        turn = 0.0 if self.holding else self.direction * rate
        if not self.holding and cut and cut[0].floor is not None:
            # only cut by the view's side: turn towards it, which brings it into the view
            # (the rules spawn no schema for a region at the frame's edge)
            turn = turn_direction((x, y), heading, cut[0].floor) * rate
        # every frame: another motor schema (the intercept's gaze) may have stopped the turn
        self.network.command_robot((0.0, 0.0), turn)

    def _middle(self, here: tuple[float, float]) -> tuple[float, float]:
        """The middle of the floor (where the robot is, on a floor without bounds)."""
        extent = self.network.mirror.scene.floor.extent
        if extent is None:
            return here
        return ((extent[0] + extent[2]) / 2.0, (extent[1] + extent[3]) / 2.0)

    def write(self, node: Structure) -> None:
        node.set("object", self.object_name)
        node.set("turned", round(self.turned, 4))
        node.set("direction", None if self.direction is None
                 else ("left" if self.direction > 0 else "right"))
        node.set("holding", self.holding)

    def stop(self) -> None:
        if self.direction is not None:
            self.network.command_robot((0.0, 0.0), 0.0)

    def summary(self) -> dict[str, Any]:
        out = super().summary()
        out["turned"] = round(self.turned, 4)
        return out


def _make(name: str, parameters: Mapping[str, Any], network: "SchemaNetwork") -> Search:
    return Search(name, SEARCH, parameters, network)


SEARCH = SchemaSpec(
    name="search",
    kind=SchemaKind.MOTOR,
    doc=("Turns the robot in place, first towards the middle of the floor, so that its own "
         "camera finds an object it does not see, holding still while a region looks like "
         "it; the rules remove it once a perceptual schema follows the object."),
    factory=_make,
    consumes=(Port("regions", "difference regions: one that looks like the object holds the "
                   "turn"),
              Port("camera", "the synchronised camera (the robot's own pose)")),
    parameters=(
        Parameter("object", str, "ball", "the world object looked for"),
        Parameter("turn_rate", float, 1.5, "turn this fast", unit="rad/s", low=0.0, high=20.0),
        Parameter("delay", float, 1.0, "wait this long before turning (an object in view is "
                  "spawned for in a few frames)", unit="s", low=0.0, high=86400.0),
    ),
)
