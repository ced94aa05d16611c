"""Evaluation against ground truth: the only reader of truth in the runner.

When the reality has ground truth (a synthetic reality always does; a video
may come with a CSV), each frame's record gets ``truth`` (true floor
positions), ``camera_pose_error`` (the synthetic camera against the true
one) and ``errors`` (observed, imagined and uncorrected positions against
the truth), and the summary gets:

* the **tracking** errors' medians (observed, imagined with correction, and
  the uncorrected imagination beside them);
* the **prediction** errors at each horizon, of the mirror and of the
  constant-velocity Kalman baseline, for the predictions made in frames
  where the object was seen and about times before the robot caught it,
  split by whether the true object bounced within the horizon (its velocity
  turned by more than :data:`BOUNCE_TURN_DEG`);
* the **confidence**'s meaning: among the mirror's predictions at the
  largest horizon whose confidence was at least the rules' commit threshold,
  the share that landed within the catch reach;
* the **interception**: whether the true robot came within the catch reach
  of the true object, when, and whether a robot with its limits could have
  reached the object at all (from where the robot stood when the object
  first came into the true camera's view, knowing its whole true path: the
  earliest point of that path it could reach in time, straight, from rest);
  the same for the baseline's simulated robot.

Nothing that perceives may call this module; the runner calls it after each
frame's loop is done.  Statistics over a run of any length use
:class:`Sample`, which keeps at most a fixed number of values (thinning
evenly), so memory stays flat.

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
from typing import Any, Mapping, Sequence

import numpy as np

from adapt.geometry import Camera, rotation_log
from adapt.imagination.predict import Trajectory, intercept_reach
from adapt.imagination.reach import meet
from adapt.scenario import Scenario
from adapt.schemas.intercept import CATCH_SLACK  # a contact's bodies are never quite touching

__all__ = ["Evaluation", "Sample", "camera_error", "COMMIT_CONFIDENCE", "BOUNCE_TURN_DEG"]

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
    rot = float(np.degrees(np.linalg.norm(rotation_log(estimate.rotation @ truth.rotation.T))))
    return pos, rot


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
    """

    def __init__(self, scenario: Scenario, truth: Any, fps: float = 30.0) -> None:
        self.scenario = scenario
        self.truth = truth
        self.fps = fps
        self.camera_position = Sample()
        self.camera_rotation = Sample()
        self.observed: dict[str, Sample] = {}
        self.imagined: dict[str, Sample] = {}
        self.uncorrected: dict[str, Sample] = {}
        self.scores: dict[tuple[str, float], _Scores] = {}
        self._pending: dict[int, list[tuple[str, str, float, tuple[float, float], int, float]]] = {}
        #: The latest scored predictions, for the figure: (time made, source, horizon, error m).
        self.timeline: deque[tuple[float, str, float, float]] = deque(maxlen=TIMELINE)
        self._velocities: dict[str, deque[tuple[int, tuple[float, float]]]] = {}
        self.confident = 0
        self.confident_within = 0
        robot = scenario.scene.robot
        self.target = next((str(g.get("object")) for g in scenario.goals
                            if g.name == "intercept" and g.get("object") is not None), None)
        self.reach: float | None = None
        if robot is not None and self.target is not None:
            try:
                self.reach = intercept_reach(scenario.model(self.target).ball, robot)
            except KeyError:
                self.reach = None
        self.caught: float | None = None
        self.baseline_caught: float | None = None
        self._path: deque[tuple[float, float, float]] = deque(maxlen=PATH_LIMIT)
        self._appeared: tuple[float, tuple[float, float]] | None = None

    @property
    def available(self) -> bool:
        """True when the reality has ground truth."""
        return self.truth is not None

    # -- per frame ---------------------------------------------------------------------

    def add(self, index: int, time: float, record: dict[str, Any], camera: Camera,
            uncorrected: Mapping[str, tuple[float, float]] | None = None,
            baseline_robot: Sequence[float] | None = None) -> None:
        """Score one frame; add ``truth``, ``camera_pose_error`` and ``errors`` to its record."""
        if self.truth is None:
            return
        t = self.truth.at(index)
        if t is None:
            return
        truth_pos: dict[str, list[float] | None] = {}
        for name, obj in t.objects.items():
            truth_pos[name] = None if obj is None else [round(obj.position[0], 4),
                                                         round(obj.position[1], 4)]
            if obj is not None and obj.velocity is not None:
                vel = self._velocities.setdefault(name, deque(maxlen=int(self.fps * 65) + 4))
                vel.append((index, (float(obj.velocity[0]), float(obj.velocity[1]))))
        record["truth"] = truth_pos
        robot = getattr(t, "robot", None)
        if robot is not None:
            record["truth_robot"] = [round(float(robot.position[0]), 4),
                                     round(float(robot.position[1]), 4)]
        if getattr(t, "camera", None) is not None:
            pos, rot = camera_error(camera, t.camera)
            record["camera_pose_error"] = {"position_m": round(pos, 5),
                                           "rotation_deg": round(rot, 5)}
            self.camera_position.add(pos)
            self.camera_rotation.add(rot)
        errors: dict[str, dict[str, float | None]] = {}
        for name, seen in record["objects"].items():
            true = truth_pos.get(name)
            e: dict[str, float | None] = {"observed": None, "imagined": None, "uncorrected": None}
            if true is not None:
                for key, store, p in (("observed", self.observed, seen.get("observed")),
                                      ("imagined", self.imagined, seen.get("imagined")),
                                      ("uncorrected", self.uncorrected,
                                       (uncorrected or {}).get(name))):
                    if p is not None:
                        d = math.dist(p, true)
                        e[key] = round(d, 5)
                        store.setdefault(name, Sample()).add(d)
            errors[name] = e
        record["errors"] = errors
        self._score_predictions(index, truth_pos)
        self._expect(index, time, record)
        self._intercepts(time, t, truth_pos, baseline_robot, record)

    def _expect(self, index: int, time: float, record: dict[str, Any]) -> None:
        """Keep the predictions made from a sighting in this frame, to score when their time
        comes (a prediction made while the object is not seen is the imagination running on:
        it is reported, not scored)."""
        for source, key in (("mirror", "predictions"), ("baseline", "baseline")):
            for name, preds in (record.get(key) or {}).items():
                if (record["objects"].get(name) or {}).get("observed") is None:
                    continue
                for p in preds:
                    h = float(p["horizon"])
                    target = index + int(round(h * self.fps))
                    conf = float(p.get("confidence", math.nan))
                    self._pending.setdefault(target, []).append(
                        (name, source, h, (float(p["position"][0]), float(p["position"][1])),
                         index, conf))

    def _score_predictions(self, index: int, truth_pos: Mapping[str, list[float] | None]) -> None:
        for name, source, h, pos, made, conf in self._pending.pop(index, []):
            true = truth_pos.get(name)
            if true is None or (name == self.target and self.caught is not None):
                continue  # once the robot has the object, its path is the robot's doing
            err = math.dist(pos, true)
            self.scores.setdefault((source, h), _Scores()).add(err, self._bounced(name, made, index))
            self.timeline.append((made / self.fps, source, h, err))
            if source == "mirror" and self.reach is not None and name == self.target and \
                    h == max(self.scenario.predict.horizons) and conf >= COMMIT_CONFIDENCE:
                self.confident += 1
                self.confident_within += err <= self.reach

    def _bounced(self, name: str, start: int, end: int) -> bool:
        vel = [v for i, v in self._velocities.get(name, ()) if start <= i <= end]
        return len(vel) > 1 and max(_turn_deg(vel[0], v) for v in vel[1:]) > BOUNCE_TURN_DEG

    def _intercepts(self, time: float, t: Any, truth_pos: Mapping[str, list[float] | None],
                    baseline_robot: Sequence[float] | None, record: dict[str, Any]) -> None:
        if self.target is None or self.reach is None:
            return
        ball = truth_pos.get(self.target)
        robot = getattr(t, "robot", None)
        if ball is None:
            return
        self._path.append((time, ball[0], ball[1]))
        if self._appeared is None and robot is not None and self._in_view(t, ball):
            self._appeared = (time, (float(robot.position[0]), float(robot.position[1])))
        if robot is not None:
            d = math.dist(robot.position, ball)
            record["robot_distance"] = round(d, 4)
            if d <= self.reach + CATCH_SLACK and self.caught is None:
                self.caught = time
        if baseline_robot is not None:
            d = math.dist(baseline_robot, ball)
            if d <= self.reach + CATCH_SLACK and self.baseline_caught is None:
                self.baseline_caught = time

    def _in_view(self, t: Any, ball: Sequence[float]) -> bool:
        """Is the target's centre inside the true camera's image (True without a camera)?"""
        camera = getattr(t, "camera", None)
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
        true path.)
        """
        robot = self.scenario.scene.robot
        if self._appeared is None or robot is None or self.reach is None or not self._path:
            return None
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
        out["prediction_error_m"] = {
            f"{h:g}": {src: self.scores[(src, h)].summary() for src in ("mirror", "baseline")
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
            out["baseline"] = {"caught": self.baseline_caught is not None,
                               "t": None if self.baseline_caught is None
                               else round(self.baseline_caught, 4)}
        return out
