"""Evaluation against ground truth: the only reader of truth in the runner.

When the reality has ground truth (a synthetic reality always does; a video
may come with a CSV), each frame's record gets ``truth`` (true floor
positions), ``camera_pose_error`` (the synthetic camera against the true
one) and ``errors`` (observed, imagined and uncorrected positions against
the truth), and the summary gets:

* the **tracking** errors' medians (observed, imagined with correction, and
  the uncorrected imagination beside them);
* the **prediction** errors at each horizon, of the mirror and of each
  baseline (the constant-velocity Kalman filter, the map-aware one), for the predictions made in frames
  where the object was seen and about times before the robot caught it,
  split by whether the true object bounced within the horizon (its velocity
  turned by more than :data:`BOUNCE_TURN_DEG`);
* the **confidence**'s meaning: among the mirror's predictions at the
  largest horizon whose confidence was at least the rules' commit threshold,
  the share that landed within the catch reach;
* the **interception**: whether the true robot's body met the true object
  (:func:`~adapt.imagination.predict.meets`, what the agent's ``^caught``
  means too), when, and whether a robot with its limits could have
  reached the object at all (from where the robot stood when the object
  first came into the true camera's view, knowing its whole true path: the
  earliest point of that path it could reach in time, straight, from rest);
  the same for each baseline's simulated robot.

Nothing that perceives may call this module: it is the first listener on
the frame records (:mod:`adapt.runner.record`), and scores each one into a
typed :class:`FrameScore` that the report and the figures read.  It scores
positions and confidences at the report's precision (metres and
confidences to four decimals, :func:`reported`), so that every number of the
summary can be recomputed from the frames of ``report.json``.  Statistics
over a run of any length use :class:`Sample`, which keeps at most a fixed
number of values (thinning evenly), so memory stays flat.

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
from collections import deque
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from adapt.geometry import Camera
from adapt.imagination.predict import Trajectory, intercept_reach, meets
from adapt.imagination.reach import meet
from adapt.runner.baseline import report_key
from adapt.runner.record import FrameRecord, Vec2
from adapt.scenario import Scenario

if TYPE_CHECKING:  # pragma: no cover
    from adapt.reality import FrameTruth, GroundTruth

__all__ = ["Evaluation", "FrameScore", "ObjectErrors", "Sample", "camera_error", "reported",
           "COMMIT_CONFIDENCE", "BOUNCE_TURN_DEG", "MIRROR"]

#: The name of the mirror's predictions among the sources scored (the baselines' are theirs).
MIRROR = "mirror"

#: The confidence the mirror's rules commit at (``rules/mirror/intercept.soar``).
COMMIT_CONFIDENCE = 0.7
#: A true path that turns by more than this within a horizon bounced there.
BOUNCE_TURN_DEG = 20.0
#: True positions kept per object for the reachability oracle.
PATH_LIMIT = 20_000
#: Scored predictions kept for ``prediction.png`` (the latest ones).
TIMELINE = 20000


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
    return pos, truth.angle_to(estimate)


def reported(p: Sequence[float] | None) -> Vec2 | None:
    """A floor position at the report's precision (metres to four decimals).

    >>> reported((0.123456, 1.0)), reported(None)
    ((0.1235, 1.0), None)
    """
    return None if p is None else (round(float(p[0]), 4), round(float(p[1]), 4))


@dataclass(frozen=True, slots=True)
class ObjectErrors:
    """How far an object's observed, imagined and uncorrected positions are from the
    truth in one frame (metres; None where there is no position)."""

    observed: float | None = None
    imagined: float | None = None
    uncorrected: float | None = None


@dataclass(frozen=True, slots=True, eq=False)
class FrameScore:
    """One frame against the truth: the true positions (None while an object is not
    present), the true robot, the synthetic camera's error (position m, rotation deg),
    each object's errors, and the true robot's distance to the target."""

    truth: Mapping[str, Vec2 | None] = field(default_factory=lambda: MappingProxyType({}))
    robot: Vec2 | None = None
    camera_error: tuple[float, float] | None = None
    errors: Mapping[str, ObjectErrors] = field(default_factory=lambda: MappingProxyType({}))
    robot_distance: float | None = None

    def as_json(self) -> dict[str, Any]:
        """The keys a frame of ``report.json`` gets from the truth (``docs/runner.md``)."""
        out: dict[str, Any] = {"truth": {n: None if p is None else list(p)
                                         for n, p in self.truth.items()}}
        if self.robot is not None:
            out["truth_robot"] = list(self.robot)
        if self.camera_error is not None:
            out["camera_pose_error"] = {"position_m": round(self.camera_error[0], 5),
                                        "rotation_deg": round(self.camera_error[1], 5)}
        out["errors"] = {n: {"observed": _r5(e.observed), "imagined": _r5(e.imagined),
                             "uncorrected": _r5(e.uncorrected)} for n, e in self.errors.items()}
        if self.robot_distance is not None:
            out["robot_distance"] = round(self.robot_distance, 4)
        return out


def _r5(v: float | None) -> float | None:
    return None if v is None else round(v, 5)


def _turn_deg(a: Sequence[float], b: Sequence[float]) -> float:
    na, nb = math.hypot(*a), math.hypot(*b)
    if na < 1e-3 or nb < 1e-3:
        return 0.0
    c = (a[0] * b[0] + a[1] * b[1]) / (na * nb)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


class _Scores:
    """Prediction errors at one horizon of one predictor, split by bounce."""

    def __init__(self) -> None:
        self.all = Sample()
        self.bounce = Sample()
        self.no_bounce = Sample()

    def add(self, error: float, bounced: bool) -> None:
        self.all.add(error)
        (self.bounce if bounced else self.no_bounce).add(error)

    def summary(self) -> dict[str, Any]:
        def med(s: Sample) -> float | None:
            m = s.median()
            return None if m is None else round(m, 4)

        return {"median": med(self.all), "p90": None if not self.all.values else
                round(self.all.percentile(90) or 0.0, 4), "n": self.all.count,
                "bounce_median": med(self.bounce), "bounce_n": self.bounce.count,
                "no_bounce_median": med(self.no_bounce), "no_bounce_n": self.no_bounce.count}


class Evaluation:
    """Per-frame truth comparison and its running statistics (see the module docstring).

    Parameters
    ----------
    scenario : Scenario
    truth : GroundTruth or None
        ``truth.at(index) -> FrameTruth | None``.
    fps : float
        Frames per second (to find the frame a prediction is about).
    baselines : sequence of str
        The baselines' names, in the order their scores are listed.
    """

    def __init__(self, scenario: Scenario, truth: "GroundTruth | None", fps: float = 30.0,
                 baselines: Sequence[str] = ("kalman",)) -> None:
        self.scenario = scenario
        self.truth = truth
        self.fps = fps
        self.baselines = tuple(baselines)
        self.camera_position = Sample()
        self.camera_rotation = Sample()
        self.observed: dict[str, Sample] = {}
        self.imagined: dict[str, Sample] = {}
        self.uncorrected: dict[str, Sample] = {}
        self.scores: dict[tuple[str, float], _Scores] = {}
        self._pending: dict[int, list[tuple[str, str, float, Vec2, int, float]]] = {}
        #: The latest scored predictions, for the figure: (time made, source, horizon, error m).
        self.timeline: deque[tuple[float, str, float, float]] = deque(maxlen=TIMELINE)
        self._velocities: dict[str, deque[tuple[int, tuple[float, float]]]] = {}
        self.confident = 0
        self.confident_within = 0
        robot = scenario.scene.robot
        self.target = scenario.target
        self.reach: float | None = None
        if robot is not None and self.target is not None:
            try:
                self.reach = intercept_reach(scenario.model(self.target).ball, robot)
            except KeyError:
                self.reach = None
        self.caught: float | None = None
        #: When each baseline's robot caught the target (None: not yet), by baseline name.
        self.baselines_caught: dict[str, float | None] = {name: None for name in self.baselines}
        self._path: deque[tuple[float, float, float]] = deque(maxlen=PATH_LIMIT)
        self._appeared: tuple[float, tuple[float, float]] | None = None
        #: The latest frame's score (None without truth for it).
        self.latest: FrameScore | None = None
        self._latest_index = -1

    @property
    def available(self) -> bool:
        """True when the reality has ground truth."""
        return self.truth is not None

    def score(self, index: int) -> FrameScore | None:
        """The score of frame ``index`` when it is the latest scored, else None."""
        return self.latest if index == self._latest_index else None

    # -- per frame ---------------------------------------------------------------------

    def frame(self, record: FrameRecord) -> None:
        """Score one frame's record (the listener's call)."""
        self.latest = None
        self._latest_index = record.index
        if self.truth is None:
            return
        t = self.truth.at(record.index)
        if t is None:
            return
        truth_pos: dict[str, Vec2 | None] = {}
        for name, obj in t.objects.items():
            truth_pos[name] = None if obj is None else reported(obj.position)
            if obj is not None and obj.velocity is not None:
                vel = self._velocities.setdefault(name, deque(maxlen=int(self.fps * 65) + 4))
                vel.append((record.index, (float(obj.velocity[0]), float(obj.velocity[1]))))
        robot = t.robot
        cam = None
        if t.camera is not None:
            cam = camera_error(record.camera, t.camera)
            self.camera_position.add(cam[0])
            self.camera_rotation.add(cam[1])
        errors = self._errors(record, truth_pos)
        self._score_predictions(record.index, truth_pos)
        self._expect(record)
        distance = self._intercepts(record, t, truth_pos)
        self.latest = FrameScore(
            MappingProxyType(truth_pos),
            None if robot is None else reported(robot.position), cam,
            MappingProxyType(errors), distance)

    def _errors(self, record: FrameRecord, truth_pos: Mapping[str, Vec2 | None]
                ) -> dict[str, ObjectErrors]:
        errors: dict[str, ObjectErrors] = {}
        for obj in record.tracked:
            true = truth_pos.get(obj.name)
            found: dict[str, float | None] = {"observed": None, "imagined": None,
                                              "uncorrected": None}
            if true is not None:
                for key, store, p in (("observed", self.observed, reported(obj.observed)),
                                      ("imagined", self.imagined, reported(obj.imagined)),
                                      ("uncorrected", self.uncorrected,
                                       record.uncorrected.get(obj.name))):
                    if p is not None:
                        d = math.dist(p, true)
                        found[key] = d
                        store.setdefault(obj.name, Sample()).add(d)
            errors[obj.name] = ObjectErrors(**found)
        return errors

    def _expect(self, record: FrameRecord) -> None:
        """Keep the predictions made from a sighting in this frame, to score when their time
        comes (a prediction made while the object is not seen is the imagination running on:
        it is reported, not scored)."""
        seen = {t.name for t in record.tracked if t.observed is not None}
        for obj in record.tracked:
            p = record.percept_of(obj.name)
            if obj.name not in seen or p is None or p.prediction is None:
                continue
            for h in p.prediction.horizons:
                self._expect_one(record.index, obj.name, MIRROR, h.horizon, h.position,
                                 round(h.confidence, 4))
        for name in self.baselines:
            state = record.baselines.get(name)
            if state is None:
                continue
            for obj_name, preds in state.predictions.items():
                if obj_name in seen:
                    for b in preds:
                        self._expect_one(record.index, obj_name, report_key(name), b.horizon,
                                         b.position, math.nan)

    def _expect_one(self, index: int, name: str, source: str, horizon: float,
                    position: Sequence[float], confidence: float) -> None:
        target = index + int(round(horizon * self.fps))
        self._pending.setdefault(target, []).append(
            (name, source, horizon, reported(position), index, confidence))  # type: ignore[arg-type]

    def _score_predictions(self, index: int, truth_pos: Mapping[str, Vec2 | None]) -> None:
        for name, source, h, pos, made, conf in self._pending.pop(index, []):
            true = truth_pos.get(name)
            if true is None or (name == self.target and self.caught is not None):
                continue  # once the robot has the object, its path is the robot's doing
            err = math.dist(pos, true)
            self.scores.setdefault((source, h), _Scores()).add(err, self._bounced(name, made, index))
            self.timeline.append((made / self.fps, source, h, err))
            if source == MIRROR and self.reach is not None and name == self.target and \
                    h == max(self.scenario.predict.horizons) and conf >= COMMIT_CONFIDENCE:
                self.confident += 1
                self.confident_within += err <= self.reach

    def _bounced(self, name: str, start: int, end: int) -> bool:
        vel = [v for i, v in self._velocities.get(name, ()) if start <= i <= end]
        return len(vel) > 1 and max(_turn_deg(vel[0], v) for v in vel[1:]) > BOUNCE_TURN_DEG

    def _intercepts(self, record: FrameRecord, t: "FrameTruth",
                    truth_pos: Mapping[str, Vec2 | None]) -> float | None:
        if self.target is None or self.reach is None:
            return None
        ball = truth_pos.get(self.target)
        robot = t.robot
        if ball is None:
            return None
        time = record.time
        self._path.append((time, ball[0], ball[1]))
        if self._appeared is None and robot is not None and self._in_view(t, ball):
            self._appeared = (time, (float(robot.position[0]), float(robot.position[1])))
        distance = None
        if robot is not None:
            distance = math.dist(robot.position, ball)
            if meets(distance, self.reach) and self.caught is None:
                self.caught = time
        for name in self.baselines:
            state = record.baselines.get(name)
            where = None if state is None else state.robots.get(self.target)
            if where is not None and self.baselines_caught.get(name) is None and \
                    meets(math.dist(where, ball), self.reach):
                self.baselines_caught[name] = time
        return distance

    def _in_view(self, t: "FrameTruth", ball: Sequence[float]) -> bool:
        """Is the target's centre inside the true camera's image (True without a camera)?"""
        camera = t.camera
        if camera is None or self.target is None:
            return True
        radius = self.scenario.model(self.target).ball.radius
        point = np.array([[float(ball[0]), float(ball[1]), radius]])
        if float(camera.to_camera(point)[0, 2]) <= 1e-3:
            return False
        u, v = camera.project(point)[0]
        w, h = camera.size
        return bool(0 <= u < w and 0 <= v < h)

    def reachable(self) -> bool | None:
        """Could a robot with the scenario's limits have reached the object at all?

        From where the robot stood when the object first came into the true
        camera's view (when first there, without a true camera), at rest,
        knowing the object's whole true path: is there a point of it the robot
        could drive to in time (straight, or round what is in its way) and stand at (room for its body clear
        of walls and obstacles)?  (:func:`adapt.imagination.reach.meet` on the
        true path.)  A robot that met it -- the real one or a baseline's -- is the proof that
        one could: and the true path after the real robot met it is the robot's doing, which
        may have pushed it where no robot could reach it in time.
        """
        robot = self.scenario.scene.robot
        if self._appeared is None or robot is None or self.reach is None or not self._path:
            return None
        if self.caught is not None or any(t is not None for t in self.baselines_caught.values()):
            return True
        t0, start = self._appeared
        path = np.array(self._path)
        true_path = Trajectory(self.target or "", path[:, 0], path[:, 1:3],
                               np.zeros((len(path), 2)), ())
        return meet(true_path, self.scenario.scene, robot, start, reach=self.reach,
                    start=t0) is not None

    # -- the end ---------------------------------------------------------------------------

    def summary(self) -> dict[str, Any]:
        """The statistics above (``{"ground_truth": False}`` without truth)."""
        if self.truth is None:
            return {"ground_truth": False}
        out: dict[str, Any] = {
            "ground_truth": True,
            "camera_position_error_m": self.camera_position.summary(5),
            "camera_rotation_error_deg": self.camera_rotation.summary(5),
            "tracking_error_m": {name: s.summary() for name, s in sorted(self.observed.items())},
            "imagination_error_m": {name: s.summary() for name, s in sorted(self.imagined.items())},
            "uncorrected_error_m": {name: s.summary()
                                    for name, s in sorted(self.uncorrected.items())},
        }
        drawn = getattr(self.truth, "parameters", None)
        if drawn is not None:
            out["true_parameters"] = {
                o.name: {k: round(getattr(o, k), 4) for k in ("restitution", "friction",
                                                              "rolling_resistance", "drag", "spin")}
                for o in drawn.objects}
        horizons = sorted({h for _, h in self.scores})
        sources = (MIRROR, *(report_key(name) for name in self.baselines))
        out["prediction_error_m"] = {
            f"{h:g}": {src: self.scores[(src, h)].summary() for src in sources
                       if (src, h) in self.scores} for h in horizons}
        if self.target is not None:
            out["confidence"] = {
                "threshold": COMMIT_CONFIDENCE, "horizon": max(self.scenario.predict.horizons),
                "confident": self.confident,
                "within_reach": None if not self.confident else
                round(self.confident_within / self.confident, 4)}
            out["intercept"] = {"object": self.target, "reach": self.reach,
                                "caught": self.caught is not None,
                                "t": None if self.caught is None else round(self.caught, 4),
                                "reachable": self.reachable()}
            for name in self.baselines:
                caught = self.baselines_caught.get(name)
                out[report_key(name)] = {"caught": caught is not None,
                                         "t": None if caught is None else round(caught, 4)}
        return out
