"""The intercept motor schema: where the robot can meet a moving object, and going there.

The paper's *Intercept Rolling Object* (Figure 2B): it uses what the object's
perceptual schema predicts and what the robot can do.  Every frame it plans
the **earliest point of the predicted trajectory the robot can reach in
time and stand at** (:func:`adapt.imagination.reach.meet`: the robot's speed
and acceleration limits, the catch reach, and room for its body clear of
walls and obstacles), which is after a bounce when only that one is
reachable; a path that ends at rest is waited for where it stops, and reports the plan on the input-link with the
prediction's confidence at the meeting time.  It drives like the ``drive``
schema (``^x ^y`` or ``^stop yes``): the rules decide when to commit to a
plan (a confident one) and when to re-plan (``^plan-shift``, the distance
between the plan and the target they gave, grows); they also see when the
robot cannot reach the object in time (``^reachable no``) and do not chase.
When no point of the predicted path (its planning horizon, a few seconds)
can be reached but the object is still moving at the path's end, it is not
out of reach yet, only not within the horizon: ``^reachable later``, and the
plan is the place to stand by where the path ends (``^approach yes``), which
the rules may head for while the prediction catches up.

The robot's camera is its own: while the schema runs it turns the robot, at
most ``turn_rate``, to face the object (its sighting, else the imagined
body), so that the object stays in view while the robot drives (the robot
is holonomic: turning does not change where it goes).  The object is
``^caught`` when the robot touches it (the sighting or the imagined body
within the catch reach; not an imagined body that is doubted: it showed in the
view since the object was last seen, and the object was not there).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from adapt.imagination.predict import Trajectory, intercept_reach, meets
from adapt.imagination.reach import meet, standing_point
from adapt.schemas.drive import Drive
from adapt.schemas.links import Structure
from adapt.schemas.percepts import ObjectPercept
from adapt.schemas.predictor import REST_PLAN, REST_SPEED
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.schemas.network import SchemaNetwork

__all__ = ["Intercept", "INTERCEPT", "Plan", "Reachable", "GAZE_GAIN", "GAZE_START_STOP"]

#: Turn rate per radian of heading error when facing the object (1/s).
GAZE_GAIN = 4.0
#: Heading errors (degrees) at which the robot starts turning to face the object, and at
#: which it stops: a camera on it facing the object within a degree or two holds still
#: rather than creep after it at a vanishing turn rate for ever (a camera turned at all
#: is a moving camera, whose view is another every frame).
GAZE_START_STOP = (2.0, 0.5)


class Reachable(enum.Enum):
    """Whether the robot can meet the object (``^reachable`` on the input-link)."""

    YES = "yes"      #: a point of the predicted path can be reached in time
    NO = "no"        #: none can, and the path ends with the object at rest (or stuck)
    LATER = "later"  #: none within the horizon, but the object is still moving at its end


@dataclass(frozen=True, slots=True)
class Plan:
    """Where and when the robot can first meet the object.

    ``time`` is the meeting's world time, ``position`` where the robot stops
    (within reach of the object, with room to stand), ``object`` where the
    object is then, ``after_bounce`` whether the object touches something
    before, ``confidence`` the prediction's at that horizon; ``approach``
    marks a plan that only heads for where the predicted path ends
    (:attr:`Reachable.LATER`).
    """

    time: float
    position: tuple[float, float]
    object: tuple[float, float]
    after_bounce: bool
    confidence: float
    travel: float
    approach: bool = False


class Intercept(Drive):
    """See the module docstring."""

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        super().__init__(name, spec, parameters, network)
        self.object_name = str(parameters["object"])
        self.plan: Plan | None = None
        self.reachable: Reachable | None = None

    def watched(self) -> ObjectPercept | None:
        """What the object's perceptual schema perceives of it, on the ``object`` port (None
        while no schema monitors it)."""
        for p in self.network.percepts(self, "object", ObjectPercept):
            if p.object == self.object_name:
                return p
        return None

    def act(self, time: float) -> None:
        self._plan(time)
        super().act(time)
        self._gaze()

    def _gaze(self) -> None:
        """Turn towards the object (see the module docstring)."""
        limit = float(self.parameters["turn_rate"])
        obj = self.watched()
        pose = self.network.mirror.robot_pose()
        where = None if obj is None else obj.observed or obj.imagined
        turn = 0.0
        if limit > 0 and where is not None and pose is not None:
            (x, y), heading = pose
            if math.dist(where, (x, y)) > 1e-6:
                error = math.atan2(where[1] - y, where[0] - x) - heading
                error = (error + math.pi) % (2.0 * math.pi) - math.pi
                start, stop = GAZE_START_STOP
                if abs(error) > math.radians(stop if self._turn else start):
                    turn = max(-limit, min(limit, GAZE_GAIN * error))
        if turn != self._turn:
            self._send(self._velocity, turn)

    def _plan(self, time: float) -> None:
        obj = self.watched()
        pose = self.network.mirror.robot_pose()
        pred = None if obj is None else obj.prediction
        if obj is None or pred is None or pose is None or obj.ball is None:
            self.plan, self.reachable = None, None
            return
        (x, y), _ = pose
        reach = intercept_reach(obj.ball, self.robot) * float(self.parameters["reach"])
        speed = self.robot.max_speed * float(self.parameters["speed"])
        scene = self.network.mirror.scene
        hit = meet(pred.trajectory, scene, self.robot, (x, y), reach=reach, start=time,
                   max_speed=speed, footprint=self.footprint)
        path = pred.trajectory
        moving = len(path.times) > 0 and float(np.hypot(*path.velocities[-1])) >= REST_SPEED
        if hit is None and len(path.times) and not moving:
            # the path ends with the object (nearly) at rest: it will wait there
            end = path.positions[-1]
            t_end = float(path.times[-1])
            rest = Trajectory(path.body, np.array([t_end, t_end + REST_PLAN]),
                              np.array([end, end]), np.zeros((2, 2)), ())
            hit = meet(rest, scene, self.robot, (x, y), reach=reach, start=time, max_speed=speed,
                       footprint=self.footprint)
        horizons = [h.horizon for h in pred.horizons]
        confs = [h.confidence for h in pred.horizons]
        if hit is None and moving:
            end = (float(path.positions[-1][0]), float(path.positions[-1][1]))
            stand = standing_point(scene, self.robot, end, reach, approach_from=(x, y),
                                   footprint=self.footprint)
            if stand is not None:
                t_end = float(path.times[-1])
                self.plan = Plan(t_end, stand, end, bool(pred.contacts), confs[-1],
                                 math.dist(stand, (x, y)), approach=True)
                self.reachable = Reachable.LATER
                return
        if hit is None:
            self.plan, self.reachable = None, Reachable.NO
            return
        ahead = hit.time - pred.time
        conf = float(np.interp(ahead, horizons, confs)) if ahead >= horizons[0] else confs[0]
        after = any(pred.time < c.time <= hit.time for c in pred.contacts)
        self.plan = Plan(hit.time, hit.stand, hit.object, after, conf, hit.travel)
        self.reachable = Reachable.YES

    def plan_shift(self) -> float | None:
        """Distance between the plan and the commanded target, metres."""
        if self.plan is None or self.target is None:
            return None
        return math.dist(self.plan.position, self.target)

    def write(self, node: Structure) -> None:
        super().write(node)
        node.set("object", self.object_name)
        obj = self.watched()
        node.set("reach", None if obj is None or obj.ball is None
                 else round(intercept_reach(obj.ball, self.robot), 4))
        node.set("reachable", None if self.reachable is None else self.reachable.value)
        p = self.plan
        node.set("plan-x", None if p is None else round(p.position[0], 4))
        node.set("plan-y", None if p is None else round(p.position[1], 4))
        node.set("plan-time", None if p is None else round(p.time, 4))
        node.set("meet-x", None if p is None else round(p.object[0], 4))
        node.set("meet-y", None if p is None else round(p.object[1], 4))
        node.set("plan-in", None if p is None else round(p.time - self.network.time, 4))
        node.set("plan-confidence", None if p is None else round(p.confidence, 3))
        node.set("after-bounce", None if p is None else p.after_bounce)
        node.set("approach", None if p is None else p.approach)
        shift = self.plan_shift()
        node.set("plan-shift", None if shift is None else round(shift, 4))
        d = self.object_distance()
        node.set("object-distance", None if d is None else round(d, 4))
        node.set("caught", None if d is None or obj is None or obj.ball is None
                 else meets(d, intercept_reach(obj.ball, self.robot)))

    def object_distance(self) -> float | None:
        """How far the robot is from the object: the sighting when there is one this frame,
        else the imagined body (a ball at the robot's feet is below its camera's view) unless
        it is doubted (it showed in the view since the last sighting, and the object was not
        there: a catch of it would be a catch of the imagination's error)."""
        obj = self.watched()
        pose = self.network.mirror.robot_pose()
        if obj is None or pose is None:
            return None
        where = obj.observed or (None if obj.doubted else obj.imagined)
        return None if where is None else math.dist(where, pose[0])

    def summary(self) -> dict[str, Any]:
        out = super().summary()
        p = self.plan
        out["plan"] = None if p is None else {
            "t": round(p.time, 4), "position": [round(v, 4) for v in p.position],
            "object": [round(v, 4) for v in p.object],
            "after_bounce": p.after_bounce, "confidence": round(p.confidence, 3),
            "approach": p.approach}
        out["reachable"] = None if self.reachable is None else self.reachable.value
        return out


def _make(name: str, parameters: Mapping[str, Any], network: "SchemaNetwork") -> Intercept:
    return Intercept(name, INTERCEPT, parameters, network)


INTERCEPT = SchemaSpec(
    name="intercept",
    kind=SchemaKind.MOTOR,
    doc=("Plans, every frame, the earliest point of an object's predicted path the robot can "
         "reach in time (after a bounce when that is the one it can reach), reports it with "
         "the prediction's confidence there, and drives the robot to the point the rules "
         "commit to."),
    factory=_make,
    consumes=(Port("object", "the object's prediction"),
              Port("camera", "the synchronised camera (the robot's own pose)")),
    parameters=(
        Parameter("object", str, "ball", "the world object to intercept"),
        Parameter("tolerance", float, 0.05, "arrived when this close to the target", unit="m",
                  low=0.0, high=100.0, low_open=True),
        Parameter("speed", float, 1.0, "fraction of the robot's max_speed to use", low=0.0,
                  high=1.0, low_open=True),
        Parameter("timeout", float, 30.0, "give up a target after this long", unit="s",
                  low=0.0, high=86400.0, low_open=True),
        Parameter("reach", float, 1.0, "plan with this fraction of the catch reach (the robot "
                  "stops at 0.9 of what it plans with)", low=0.0, high=1.0, low_open=True),
        Parameter("turn_rate", float, 1.5, "turn the robot to face the object at most this fast "
                  "(0: never turn)", unit="rad/s", low=0.0, high=20.0),
    ),
)
