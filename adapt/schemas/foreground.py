"""The foreground object schema: find one object, follow it, mirror it.

Spawned by the rules for an unexpected difference region (or instantiated
for a named object), it owns that object's part of the image and of the
imagination (paper section 4.4, Figure 6):

* **finding it.**  In a window around where the object should be (the
  imagined body, the last sighting, or the region it was spawned for), the
  real object is what differs from the imagination's *background*: the
  background render warped by ``H_e``, with the frame's gain and bias, outside
  the MMD mask.  All of it is read from the Scene Background's percept on the
  ``regions`` port (:class:`~adapt.schemas.percepts.BackgroundPercept`); what
  this schema perceives is published as an
  :class:`~adapt.schemas.percepts.ObjectPercept` on its ``object`` port.  The imagination's label image (warped by ``H_e``) says which
  pixels other imagined objects cover; they are left out, and so is the
  imagined robot, grown by :data:`ROBOT_MARGIN` pixels (the robot knows where
  it is), but for the pixels of another colour than the robot's in the frame
  (a ball resting against the robot shows past its real edge, which the
  imagined one, a few pixels off, covers).  The blobs left are tried nearest and largest first, up to
  :data:`MAX_BLOBS`, until one has the object's size and stands where it can.  (Comparing with
  the full render instead would hide the object wherever the imagined body
  already covers it, and mistake background of the object's colour for the
  object.)
* **where it is.**  The blob's silhouette, seen through the synchronised
  camera, is fitted with a sphere resting on the floor (the ground-plane
  assumption; :func:`adapt.schemas.silhouette.fit_ball`, exact under
  perspective, from the upper outline so a contact shadow does not bias it;
  the radius is measured for an object the scenario does not know; a blob is
  a declared ball's only when its area and outline are those of the ball's
  image where it is fitted); a constant-velocity Kalman filter
  (:mod:`adapt.kalman`) smooths position and estimates velocity, restarted
  from the fitted line after a recognised bounce.
* **what it is like.**  :class:`~adapt.mirror.identify.Identifier` fits
  the ball's state and parameters by imagined rollouts to its last sightings
  (``identify``, every ``identify_every`` frames over ``identify_window``
  seconds), and the imagined body takes the parameters on (``adapt``);
  without it :class:`~adapt.schemas.estimator.ParameterEstimator` turns
  bounces and free rolling into estimates of restitution, friction and
  rolling resistance by line fits (it also notes the bounces it sees either
  way).  :class:`~adapt.schemas.predictor.Predictor` forks the imagination
  to predict, with a confidence (``predict``), from the identified state (or
  the filter's).
* **in the imagination.**  An object declared ``create: when_seen`` (or one
  the scenario does not know) is created in the imagination after
  ``confirm`` sightings, where it is perceived and with the estimated
  velocity.  On every physics step the body is pulled towards the
  observation with the paper's spring plus a damper,
  ``a = k (p_real - p_sim) + c (v_real - v_sim)`` with ``c = 2 ζ sqrt(k)``
  (``k = 0``: uncorrected, for comparison); ``p_real`` is the filtered
  position extrapolated to the step's time.  Against the imagined robot the
  pull is no more than half what the robot's drive holds (:data:`ROBOT_PUSH`),
  and across the robot there is none: the imagined robot is where the robot
  believes it stands, and a target beyond it must not shove it away.
* **when the imagination has lost it.**  A frame in which the object is not
  found while its imagined body shows in the view (half of its image or more,
  clear of what the search leaves out, away from the imagined robot) is
  evidence against the body; more than ``lost_after`` of them since the last
  sighting and the body is ``doubted`` (:data:`DOUBT_SHOWN`): the intercept
  schema's ``^caught`` does not take it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping

import cv2
import numpy as np

from adapt.errors import SchemaError
from adapt.geometry import MAX_PIXELS, point_segment_distance
from adapt.imagination import Ball
from adapt.imagination.scene import MAX_ACCEL
from adapt.imagination.sight import hidden_by
from adapt.kalman import ConstantVelocityKF
from adapt.mirror.identify import Fit, Identifier
from adapt.scenario.records import MODEL_RANGE_PARAMETERS
from adapt.schemas.base import BBox, Schema, Status
from adapt.schemas.estimator import PARAMETERS, Estimate, ParameterEstimator, surprise
from adapt.schemas.events import EventKind
from adapt.schemas.links import Structure
from adapt.schemas.percepts import (
    BackgroundPercept,
    ObjectPercept,
    Sighting,
    colour_like,
    looks_like,
    mean_color,
)
from adapt.schemas.predictor import Prediction, Predictor
from adapt.schemas.silhouette import (
    BallFit,
    fit_ball,
    fit_small_ball,
    image_area,
    limb_points,
    silhouette_length,
    visible_area,
)
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec
from adapt.vision.regions import Region, find_regions

if TYPE_CHECKING:  # pragma: no cover
    from adapt.frames import Frame
    from adapt.schemas.network import SchemaNetwork

__all__ = ["ForegroundObject", "FOREGROUND_OBJECT"]

#: A sighting of an object the scenario does not declare fitted with a larger radius (m)
#: is a misfit, refused (the mirror's perception rules spawn objects up to 1.5 m across).
MAX_UNKNOWN_RADIUS = 1.0
#: The imagined robot's pixels, grown by this many (its odometry slips), are left out of
#: the search: the robot knows where it is, and its image is no object's.
ROBOT_MARGIN = 3
#: An imagined ball closer than this (m) to the imagined robot's outer disc is pulled by its
#: spring with at most this share of the force the robot's drive holds the robot with (and one
#: whose target lies across the robot, not at all).
ROBOT_TOUCH = 0.02
ROBOT_PUSH = 0.5
#: At most this many blobs of a search are tried, nearest and largest first.
MAX_BLOBS = 4
#: Colour of an object the scenario does not declare until its own is measured (BGR).
UNKNOWN_COLOR = (128, 128, 128)
#: A blob is a known ball's image when its area is within this range of the area the ball's
#: image has where its outline is fitted (the contact shadow merged below it adds, a wall
#: or an obstacle in front of its lower part takes away) ...
AREA_RANGE = (0.3, 2.2)
#: ... and that outline fits the ball's to this RMS (pixels), or this share of the image's
#: radius when that is more.  (The radius fitted freely is no test: from the upper outline
#: of a ball 4 px across, one pixel of blur makes it half as large again.)
OUTLINE_RMS_PX = 0.6
OUTLINE_RMS_SHARE = 0.1
#: A ball of which less than this share of its image can show (the imagined robot or
#: another object in front of the rest) is not taken: a sliver does not say where it is.
MIN_SHOWN = 0.2
#: A blob is no ball's image when it is longer
#: (:func:`~adapt.schemas.silhouette.silhouette_length`) than this many times the image's
#: diameter, plus the ball's travel in a frame (motion blur) and :data:`LENGTH_SLACK_PX`: a
#: streak of a ghost in the look, the ball merged with something beside it.  (A ball's image
#: is an ellipse off the optical axis, and its contact shadow adds below it: well within.)
MAX_LENGTH = 1.6
LENGTH_SLACK_PX = 2.0
#: A blob at most this many pixels across whose outline is too short to fit is placed by
#: its centroid (:func:`~adapt.schemas.silhouette.fit_small_ball`).
SMALL_BLOB = 8
#: A ball cut by the frame's side is placed only where its image's top and uncut side are
#: within this share of its image's width (and a pixel) of the blob's.
CUT_EDGE_SHARE = 0.15
#: ... and only within this many radii (and 3 sigma) of where its track goes.
CUT_REACH_RADII = 2.0
#: The rows of an image whose bottom edge is not counted (:meth:`ForegroundObject._ball_shaped`).
UNBOUNDED_ROWS = 1 << 20
#: An object is created in the imagination only once its estimated speed is below this (m/s):
#: faster is a filter started on bad sightings.
MAX_SPEED = 20.0
#: A prediction starts from the identified state when the fit is at most this old (seconds)
#: and its path passes the sightings within this chi-square per degree of freedom (2 noise
#: sigmas); otherwise (a contact whose parameters are still being learned, say) from the filter's.
FIT_AGE = 0.2
FIT_CHI2 = 4.0
#: What is known of an object nobody described: anything plausible.
UNKNOWN_RANGES = {"restitution": (0.2, 0.95), "friction": (0.0, 1.0),
                  "rolling_resistance": (0.0, 0.2)}

#: An object seen before and missed this many frames in a row is searched for along its path
#: (wide), not around its imagined body and last sighting, and found again only by a blob of
#: its declared colour (not one of its size and outline only).
FOLLOWING_MISSES = 3
#: Side of the opening that cleans an object's blob of specks (pixels).
BLOB_OPEN = 3
#: Without a floor extent, sightings fitted farther than this from the camera are refused (m).
FLOOR_REACH = 200.0
#: Standard deviations of the track's position searched around its predicted path.
SEARCH_SIGMAS = 3.0
#: How fast an object never seen may have moved away from the region it was spawned for
#: once that region is no longer tracked (m/s): the search widens at this speed.  It is
#: also how much faster than its track an object seen before may have gone since (a push
#: by the robot): a sighting farther from the last one is something else (see ``_reaches``).
SEARCH_SPEED = 4.0
#: A track holds its object (``_reaches``) once it has followed it this many radii without
#: the filter restarting: before, it may be on a ghost, which stays put or jumps between
#: fragments, and the object is taken wherever it shows.  A restart on a jump this long from
#: where the filter had the object lets it go again; a restart on a shorter one does not.
MOVED_RADII = 3.0
#: The imagined body is doubted (:attr:`ObjectPercept.doubted`) once, since the object was last
#: seen, it showed at least this share of its image in the view -- clear of what the search
#: leaves out there, and farther than :data:`DOUBT_CLEAR` from the imagined robot, where the
#: ball's image merges with the robot's -- in more than ``lost_after`` frames, and the object was
#: not found there: the imagination has lost it.
DOUBT_SHOWN = 0.5
#: How far beyond touching the imagined robot a ball's imagined body must be for a frame in which
#: it shows and is not found to count against it (m).
DOUBT_CLEAR = 0.1


class ForegroundObject(Schema):
    """See the module docstring."""

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        super().__init__(name, spec, parameters, network)
        declared = str(parameters["object"])
        if declared:
            if declared not in network.models:
                raise SchemaError(f"no object called {declared!r}; the world declares "
                                  + (", ".join(sorted(network.models)) or "none"))
            if network.monitor_of(declared) is not None:
                raise SchemaError(f"object {declared!r} is already monitored")
        self.object_name = declared or name
        model = network.models.get(self.object_name)
        self.declared = model is not None
        self.ball: Ball | None = model.ball if model is not None else None
        self.kf = ConstantVelocityKF(q=float(parameters["process_noise"]),
                                     r=float(parameters["measurement_noise"]),
                                     gate=float(parameters["gate"]),
                                     window=int(parameters["noise_window"]))
        self.last: Sighting | None = None
        self.sightings = 0
        self.misses = 0
        #: sightings refused because a wall stands between the camera and where they fit
        self.refused = 0
        self.status = Status.WAITING
        self.region = int(parameters["region"])
        self._window: BBox | None = None
        self._window_time = network.time  # when the region it waits for was last tracked
        self._hooked = False
        self._radii: list[float] = []
        #: where the filter's current run (since it last restarted) began, its restarts then,
        #: and whether the track holds its object: it moved away from where a run began, and
        #: no restart since was on a jump that long (see ``_follow`` and ``_reaches``)
        self._run: tuple[tuple[float, float], int] | None = None
        self._moved = False
        #: frames since the last sighting in which the imagined body showed and was not found
        self.unexplained = 0
        self.model = model
        self.estimator: ParameterEstimator | None = None
        self.identifier: Identifier | None = None
        self.fit: Fit | None = None
        self._ranges: dict[str, tuple[float, float]] = {}
        self.prediction: Prediction | None = None
        self.bounces_seen = 0
        settings = network.predict
        self.predictor = Predictor(settings.horizons, members=settings.ensemble,
                                   catch_radius=self._catch_radius(), seed=network.rng,
                                   evidence=settings.evidence)
        if self.ball is not None:
            self._start_estimator()

    def joined(self) -> None:
        """The region it was spawned for, in its provider's regions: where to look first,
        and the region it claims."""
        bg = self._background()
        found = None if bg is None or self.region <= 0 else bg.region(self.region)
        if found is not None:
            self._window = found.bbox
            self._window_time = self.network.time
        self._publish(self.network.frame_index, self.network.time)

    def _background(self) -> BackgroundPercept | None:
        """The Scene Background's percept (on the ``regions`` port), or None."""
        return self.network.percept(self, "regions", BackgroundPercept)

    def claimed_regions(self) -> tuple[int, ...]:
        """The region it was spawned for, until it finds its object: from then on what it
        explains is its object's box (a region the object left, the learned look's error
        where it was at the first look, is then nobody's, and repaired)."""
        return (self.region,) if self._window is not None and self.region > 0 \
            and self.sightings == 0 else ()

    def monitored_object(self) -> str | None:
        return self.object_name

    # -- helpers ---------------------------------------------------------------------------

    def _catch_radius(self) -> float:
        """The confidence's scale: how close the robot must come (twice the radius without one)."""
        from adapt.imagination.predict import intercept_reach

        robot = self.network.mirror.scene.robot
        ball = self.ball if self.ball is not None else Ball(self.body, radius=0.1)
        return intercept_reach(ball, robot) if robot is not None else 2.0 * ball.radius

    def _start_estimator(self) -> None:
        assert self.ball is not None
        ranges: dict[str, tuple[float, float]] = {}
        if self.model is not None:
            for name in MODEL_RANGE_PARAMETERS:
                r = self.model.range(name)
                if r is not None:
                    ranges[name] = (r.low, r.high)
        else:
            ranges = dict(UNKNOWN_RANGES)
        self._ranges = ranges
        nominal = {name: float(getattr(self.ball, name)) for name in PARAMETERS}
        self.estimator = ParameterEstimator({k: ranges[k] for k in PARAMETERS}, nominal=nominal,
                                            scene=self.network.mirror.scene,
                                            gravity=self.network.mirror.scene.gravity,
                                            radius=self.ball.radius)
        if self.parameters["identify"]:
            # the parameters with a range are fitted (unless adapt is off: the state only)
            priors = {name: (float(getattr(self.ball, name)), (hi - lo) / math.sqrt(12.0))
                      for name, (lo, hi) in ranges.items()
                      if hi > lo and self.parameters["adapt"]}
            mirror = self.network.mirror
            self.identifier = Identifier(mirror.scene, self.ball, priors,
                                         window=float(self.parameters["identify_window"]),
                                         every=int(self.parameters["identify_every"]),
                                         noise=float(self.parameters["measurement_noise"]),
                                         dt=mirror.world.dt)
        self.predictor.catch_radius = self._catch_radius()

    @property
    def body(self) -> str:
        """The imagined body's name."""
        return self.object_name

    @property
    def in_imagination(self) -> bool:
        """True when the imagination has the body."""
        return self.network.mirror.has_body(self.body)

    def _radius(self) -> float:
        return self.ball.radius if self.ball is not None else 0.1

    def _imagined_real_box(self) -> tuple[tuple[float, float], float] | None:
        """Centre (real pixels) and radius (pixels) of the imagined body, or None."""
        if not self.in_imagination:
            return None
        return self._in_image(self.network.mirror.world.position(self.body))

    def _in_image(self, at: tuple[float, float]) -> tuple[tuple[float, float], float] | None:
        """Centre (real pixels) and radius (pixels) of the object on the floor at ``at``,
        or None behind the camera."""
        r = self._radius()
        cam = self.network.mirror.camera
        pc = cam.to_camera(np.array([[at[0], at[1], r]]))[0]
        if pc[2] <= 1e-6:
            return None
        px = cam.fx * pc[0] / pc[2] + cam.cx
        py = cam.fy * pc[1] / pc[2] + cam.cy
        bg = self._background()
        centre = bg.to_real((px, py)) if bg is not None else (px, py)
        return centre, cam.fx * r / pc[2]

    def _predicted(self, frame: "Frame") -> tuple[tuple[float, float], float] | None:
        """Where to look (real pixels) and how far (pixels)."""
        imagined = self._imagined_real_box()
        if imagined is not None and self.sightings > 0 and self.misses < FOLLOWING_MISSES:
            centre, rpx = imagined
            if self.last is not None:
                # the imagined body may lag the real one: look around both
                lx, ly = self.last.centroid
                span = math.dist(centre, (lx, ly))
                return ((centre[0] + lx) / 2.0, (centre[1] + ly) / 2.0), span / 2.0 + 3.0 * rpx + 8.0
            return centre, 3.0 * rpx + 8.0
        if self.last is not None:
            return self._along_track(frame, imagined)
        if self._window is not None:
            # never seen: the region it was spawned for, as long as it is tracked; then a
            # search widening at the speed an object may have gone from there
            bg = self._background()
            found = None if bg is None or self.region <= 0 else bg.region(self.region)
            if found is not None:
                self._window, self._window_time = found.bbox, frame.time
            x, y, w, h = self._window
            metres = max(frame.time - self._window_time, 0.0) * SEARCH_SPEED
            return (x + w / 2.0, y + h / 2.0), max(w, h) * (1.0 + metres / (2.0 * self._radius())) + 16.0
        if imagined is not None:
            centre, rpx = imagined
            return centre, 4.0 * rpx + 16.0
        return None

    def _along_track(self, frame: "Frame", imagined: tuple[tuple[float, float], float] | None
                     ) -> tuple[tuple[float, float], float]:
        """An object seen before and missed since: search along its predicted path -- the
        filter's constant-velocity extrapolation and the imagined body (which bounces off
        the walls) -- as far as the track's uncertainty reaches (``SEARCH_SIGMAS`` of its
        position's standard deviation, grown with every frame missed), and around the
        last sighting."""
        assert self.last is not None
        x, y, w, h = self.last.bbox
        last = (x + w / 2.0, y + h / 2.0)
        points = [(last, max(w, h) / 2.0)]
        sigma = 0.0
        if self.kf.initialised:
            ahead = max(frame.time - (self.kf.time or frame.time), 0.0)
            sigma = self.kf.position_sigma + self.kf.velocity_sigma * ahead
            seen = self._in_image(self.kf.predict_position(ahead))
            if seen is not None:
                points.append(seen)
        if imagined is not None:
            points.append(imagined)
        cx = sum(p[0][0] for p in points) / len(points)
        cy = sum(p[0][1] for p in points) / len(points)
        reach = max(math.dist((cx, cy), p[0]) + 3.0 * p[1] for p in points)
        # metres to pixels at the object's distance: its radius in both
        rpx = max(p[1] for p in points[1:]) if len(points) > 1 else max(w, h) / 2.0
        grow = 1.0 + 0.5 * self.misses
        reach = max(reach + SEARCH_SIGMAS * sigma * rpx / self._radius(),
                    max(w, h) * 1.5 * grow) + 16.0
        return (cx, cy), reach

    # -- perception ------------------------------------------------------------------------------

    def perceive(self, frame: "Frame") -> None:
        obs = self._observe(frame)
        if obs is None:
            self.misses += 1
            if self.misses == 1:
                self._let_go()
            if not self.doubted and self._shows(frame):  # (doubted until the next sighting)
                self.unexplained += 1
            self.kf.step(frame.time, None)
            if self.sightings == 0:
                self.status = Status.WAITING
            elif self.misses > int(self.parameters["lost_after"]):
                self.status = Status.LOST
        else:
            self.sightings += 1
            self.misses = 0
            self.unexplained = 0
            self.status = Status.RUNNING
            self._follow(obs)
            if self.ball is not None and self.estimator is None:
                self._start_estimator()
            if self.estimator is not None:
                self._learn(frame.time, obs.position)
            self.predictor.residuals.observe(frame.time, obs.position,
                                             0.5 * self.network.frame_interval)
            if (not self.in_imagination and self.ball is not None
                    and self.sightings >= int(self.parameters["confirm"])):
                self._create_body(frame)
            if not self._hooked and self.in_imagination:
                self.network.mirror.add_hook(self.before_step)
                self._hooked = True
        if self.parameters["predict"] and frame.index % self.network.predict.every == 0:
            self.prediction = self._predict()
        self._publish(frame.index, frame.time)

    @property
    def doubted(self) -> bool:
        """Whether the imagined body has lost the object: it showed in more than
        ``lost_after`` frames since the last sighting and the object was not found there
        (:data:`DOUBT_SHOWN`)."""
        return self.unexplained > int(self.parameters["lost_after"])

    def _shows(self, frame: "Frame") -> bool:
        """Whether the imagined body shows at least :data:`DOUBT_SHOWN` of its image in
        ``frame`` clear of what the search leaves out there (the imagined robot's margin,
        other imagined objects), away from the imagined robot (:data:`DOUBT_CLEAR`)."""
        bg = self._background()
        here = self.imagined()
        box = None if here is None else self._in_image(here)
        label = None if bg is None else bg.drawn.get(self.body)
        if bg is None or not bg.trusted or here is None or box is None or label is None:
            return False
        pose = self.network.robot_pose()
        robot = self.network.robot
        if pose is not None and robot is not None and \
                math.dist(here, pose[0]) <= robot.outer_radius + self._radius() + DOUBT_CLEAR:
            return False
        mask = bg.imagined_mask(label)
        (cx, cy), r = box
        h, w = frame.image.shape[:2]
        x0, y0 = max(int(cx - r) - 2, 0), max(int(cy - r) - 2, 0)
        x1, y1 = min(int(cx + r) + 3, w), min(int(cy + r) + 3, h)
        if mask is None or x0 >= x1 or y0 >= y1 or mask.shape != (h, w):
            return False
        mine = mask[y0:y1, x0:x1]
        hidden = self._hidden(frame, bg, (x0, y0, x1 - x0, y1 - y0))
        if hidden is not None:
            mine = mine & ~hidden
        return int(np.count_nonzero(mine)) >= DOUBT_SHOWN * math.pi * r * r

    def _publish(self, index: int, time: float) -> None:
        """What it perceives of its object, on its ``object`` port."""
        est = self.kf.initialised
        seen = self.misses == 0 and self.sightings > 0
        self.network.publish(self, ObjectPercept(
            frame=index, time=time, object=self.object_name, declared=self.declared,
            ball=self.ball, sighting=self.last if seen else None,
            position=self.kf.position if est else None,
            velocity=self.kf.velocity if est else None, imagined=self.imagined(),
            doubted=self.doubted, prediction=self.prediction,
            estimates=self.estimate_records(),
            rollouts=(self.predictor.simulated_s, self.predictor.wall_s)))

    def _learn(self, time: float, position: tuple[float, float]) -> None:
        """Bounces and rolling: update the estimates, restart the filter after a bounce, and
        give the imagined ball the estimated parameters."""
        assert self.estimator is not None
        bounce = self.estimator.observe(time, position)
        if self.identifier is not None:
            self.identifier.noise = self.kf.noise  # never below measurement_noise
            self.fit = self.identifier.observe(time, position)
        if bounce is not None:
            self.bounces_seen += 1
            after = self.estimator.last_after
            if after is not None:
                t0, p0, v0 = after
                p = p0 + v0 * (time - t0)
                self.kf.reset(time, p, v0, self.estimator.noise, 0.1)  # type: ignore[arg-type]
            self.network.note(self, EventKind.BOUNCE, {
                "t": round(bounce.time, 4), "surface": bounce.surface,
                "position": [round(v, 4) for v in bounce.position],
                "restitution": None if bounce.restitution is None else round(bounce.restitution, 4),
                "friction": None if bounce.friction is None else round(bounce.friction, 4)})
        if self.parameters["adapt"] and self.in_imagination and self.ball is not None:
            changes = {}
            for name, est in self.estimate_records().items():
                value = min(max(est.mean, 0.0), 1.0) if name == "restitution" else max(est.mean, 0.0)
                if abs(value - float(getattr(self.ball, name))) > (
                        0.002 if name in ("rolling_resistance", "drag") else 0.01):
                    changes[name] = value
            if changes:
                self.ball = self.ball.with_parameters(**changes)
                self.network.mirror.replace_ball(self.ball)

    def estimate_records(self) -> dict[str, Estimate]:
        """Each estimated parameter's :class:`~adapt.schemas.estimator.Estimate`: the
        identification's for the parameters it fits, the estimator's for the others."""
        if self.estimator is None:
            return {}
        out = self.estimator.estimates()
        fit, ident = self.fit, self.identifier
        if fit is not None and ident is not None:
            for name, mean in fit.parameters.items():
                lo, hi = self._ranges[name]
                out[name] = Estimate(name, mean, fit.std[name], ident.counts[name],
                                     surprise(mean, lo, hi))
        return dict(sorted(out.items()))

    def estimates(self) -> dict[str, tuple[float, float]]:
        """``(mean, std)`` of each estimated parameter (the model's values before any)."""
        return {name: (e.mean, e.std) for name, e in self.estimate_records().items()}

    def _fitted(self, age: float = FIT_AGE) -> tuple[Fit, float] | None:
        """The identification's answer and how long ago it was, when it may stand for the
        object's state: at most ``age`` seconds old and fitting its sightings."""
        fit = self.fit
        if fit is None:
            return None
        since = self.network.mirror.world.time - fit.time
        return (fit, since) if -1e-9 <= since <= age and fit.chi2 <= FIT_CHI2 else None

    def _let_go(self) -> None:
        """The object has just been missed: its imagined body goes on with the object's
        estimated velocity (the identification's, else the filter's), not with the one the
        spring gave it -- a correction towards noisy sightings, which would carry it off
        (a ball at rest, seen by a camera on the robot, left at half a metre a second)."""
        if not self.in_imagination or not self.kf.initialised or self.parameters["k"] <= 0:
            return
        world = self.network.mirror.world
        found = self._fitted(FIT_AGE + self.network.frame_interval)  # the sighting a frame back
        if found is not None:
            world.set_velocity(self.body, found[0].velocity, found[0].slip)
        else:
            world.set_velocity(self.body, self.kf.velocity)

    def _predict(self) -> Prediction | None:
        """Roll the imagination forward from the object's state (filtered while seen; the
        imagined body's while it is not)."""
        mirror = self.network.mirror
        if not self.in_imagination:
            return None
        found = self._fitted() if self.misses == 0 else None
        if found is not None:
            fit, since = found
            # the identified state (its time may be a frame back: identify_every)
            return self.predictor.predict(mirror.world, self.body, fit.position, fit.velocity,
                                          self.estimates(), velocity_std=self.kf.velocity_sigma,
                                          slip=fit.slip, since=max(since, 0.0))
        if self.kf.initialised and self.misses == 0:
            position, velocity, vstd = self.kf.position, self.kf.velocity, self.kf.velocity_sigma
        else:
            position, velocity = mirror.world.position(self.body), mirror.world.velocity(self.body)
            vstd = max(self.kf.velocity_sigma, 0.2)
        return self.predictor.predict(mirror.world, self.body, position, velocity,
                                      self.estimates(), velocity_std=vstd)

    def _observe(self, frame: "Frame") -> Sighting | None:
        bg = self._background()
        if bg is None or not bg.trusted:
            return None
        where = self._predicted(frame)
        if where is None:
            return None
        (cx, cy), reach = where
        h, w = frame.image.shape[:2]
        x0, y0 = max(int(cx - reach), 0), max(int(cy - reach), 0)
        x1, y1 = min(int(cx + reach) + 1, w), min(int(cy + reach) + 1, h)
        if x0 >= x1 or y0 >= y1:
            return None
        window = (x0, y0, x1 - x0, y1 - y0)
        hidden = self._hidden(frame, bg, window)
        refused = False
        # the difference per pixel first; only when it shows no sighting, with where the frame
        # is flat over the look's texture too (an object of its floor's mean colour shows in
        # pieces per pixel; the texture costs a few milliseconds a frame, spent only then) --
        # but only for an object not seen yet or seen in the frame before: searching for one
        # missed, a flat patch of a flaw in the look, still, would be taken for it
        searching = self.sightings > 0 and self.misses > 0
        for flat in (False,) if searching else (False, True):
            d = bg.object_difference(frame.image, window, flat=flat)
            if d is None:
                return None
            if hidden is not None:
                d = np.array(d)
                d[hidden] = 0  # what another imagined object explains
            found, refused_here = self._search(frame, bg, d, (x0, y0), hidden, (cx, cy))
            if found is not None:
                return found
            refused = refused or refused_here
            if not flat and self.ball is not None:
                # the object merged with a difference beside it -- its ghost, the look's error
                # where it stood or rolled while the look was first learned, which shows the
                # floor in the frame -- is apart in the pixels of its own colour
                found, refused_here = self._search(frame, bg, self._own_colour(frame, d, window),
                                                   (x0, y0), hidden, (cx, cy))
                if found is not None:
                    return found
                refused = refused or refused_here
        if refused:
            self.refused += 1
        return None

    def _own_colour(self, frame: "Frame", d: np.ndarray, window: BBox) -> np.ndarray:
        """The difference ``d`` of ``window`` where the frame could show the declared
        object's colour (:func:`~adapt.schemas.percepts.colour_like`, a pixel around it:
        its outline blurs into what lies behind), nothing elsewhere."""
        assert self.ball is not None
        x0, y0, ww, wh = window
        pixels = frame.image[y0:y0 + wh, x0:x0 + ww].reshape(-1, 3)
        like = colour_like(pixels, [self.ball.color]).reshape(wh, ww).view(np.uint8)
        near = cv2.dilate(like, np.ones((3, 3), np.uint8)) > 0
        return np.where(near, d, 0)

    def _hidden(self, frame: "Frame", bg: BackgroundPercept, window: BBox) -> np.ndarray | None:
        """The pixels of ``window`` other imagined objects and the imagined robot explain."""
        x0, y0, ww, wh = window
        x1, y1 = x0 + ww, y0 + wh
        others = [m[y0:y1, x0:x1] for m in (bg.imagined_mask(lab)
                                            for lab in bg.balls_except(self.body))
                  if m is not None]
        # (what shows past the real robot's edge in another colour is not the robot's image: a
        # ball resting against it, the imagined robot a few pixels off)
        robot = bg.robot_mask(margin=ROBOT_MARGIN, box=window, real=frame.image)
        if robot is not None:
            own = bg.drawn.get(self.body)
            mine = None if own is None else bg.imagined_mask(own)
            if mine is not None:
                # where the imagination shows this object, the robot's margin is not the
                # robot's: a ball just behind it or at its side keeps its pixels
                robot = robot & ~mine[y0:y1, x0:x1]
            others.append(robot)
        return np.logical_or.reduce(others) if others else None

    def _search(self, frame: "Frame", bg: BackgroundPercept, d: np.ndarray,
                offset: tuple[int, int], hidden: np.ndarray | None,
                centre: tuple[float, float]) -> tuple[Sighting | None, bool]:
        """The sighting among the blobs of the difference ``d`` (found at ``offset``), and
        whether a blob was refused as something else."""
        x0, y0 = offset
        # large blobs near the prediction first; the first that is the object is it (the
        # nearest may be something else: a part of the robot's image, another object)
        blobs = sorted(find_regions(d, threshold=bg.threshold,
                                    min_area=int(self.parameters["min_area"]),
                                    open_size=BLOB_OPEN, close=False),
                       key=lambda r: math.dist((r.centroid[0] + x0, r.centroid[1] + y0),
                                               centre) / math.sqrt(r.area))
        refused = False
        unlike: Sighting | None = None
        for blob in blobs[:MAX_BLOBS]:
            found = self._sighting(frame, bg, blob, offset, hidden)
            if isinstance(found, Sighting):
                if self._looks_unlike(frame, blob, offset):
                    # the object's size and outline but not its colour (the look's error
                    # where it rolled while the look was first learned): one of its colour
                    # further on is taken first, and an object lost is found again only by
                    # its look (a search along its path spans much of the view: the floor a
                    # moving robot uncovers, which the look never learned, has a ball's size)
                    if self.sightings == 0 or self.misses < FOLLOWING_MISSES:
                        unlike = unlike or found
                    continue
                return found, refused
            refused = refused or found
        return unlike, refused

    def _looks_unlike(self, frame: "Frame", blob: Region, offset: tuple[int, int]) -> bool:
        """Whether ``blob`` (found at ``offset``) does not look like the declared object's
        colour (:func:`~adapt.schemas.percepts.looks_like`); False for an object the
        scenario does not know."""
        if self.ball is None:
            return False
        x, y, w, h = blob.bbox
        color = mean_color(frame.image, (x + offset[0], y + offset[1], w, h), blob.silhouette)
        return looks_like(color, None, {self.name: (self.ball.color, self.ball.radius)}) is None

    def _sighting(self, frame: "Frame", bg: BackgroundPercept, blob: Region,
                  offset: tuple[int, int], hidden: np.ndarray | None = None) -> Sighting | bool:
        """The sighting ``blob`` (found at ``offset`` in the frame, where ``hidden`` masks
        the pixels other imagined objects took from the search) is, or whether it was
        refused as something else (True: off the floor, behind a wall, a misfit) or is not
        the object (False: its size is not, or its outline cannot be fitted)."""
        x0, y0 = offset
        h, w = frame.image.shape[:2]
        bx, by, bw, bh = blob.bbox
        mask = blob.silhouette
        bbox = (bx + x0, by + y0, bw, bh)
        if bbox[1] == 0:
            return False  # cut by the image's top: its upper outline is the image's edge
        # cut by a side of the image: the upper outline of the columns that show is the
        # object's still; a ball of known size is fitted to it, and counted by what of its
        # image the frame holds (an object of unknown size is not: a part would fit a
        # smaller one)
        cut = bbox[0] == 0 or bbox[0] + bw >= w
        if cut and (self.ball is None or self.misses > 0 or self.last is None
                    or not self.kf.initialised):
            return False  # only an object followed up to the frame before, of known size
        cam = self.network.mirror.camera
        known = None if self.ball is None else self.ball.radius
        fit = fit_ball(mask, (bx + x0, by + y0), cam, radius=known, to_camera=bg.to_synthetic)
        if fit is not None and cut and not (self._fits_cut(fit, bg, bbox, w)
                                            and self._continues(fit.position, frame.time)):
            # less than about half of it shows, the fit strays from the blob's uncut edges
            # (an arc this short fits a ball deeper and off to the side as well), or it is
            # not where the track goes (a fragment by the frame's side: a camera on the
            # robot out of step shows many)
            return False
        if fit is None and known is not None and max(bw, bh) <= SMALL_BLOB and not cut:
            # too few columns for an outline: a ball a few pixels across is where its
            # centroid is (its area is still tested below; a cut one's centroid is not)
            fit = fit_small_ball((blob.centroid[0] + x0, blob.centroid[1] + y0), cam, known,
                                 to_camera=bg.to_synthetic)
        if fit is None:
            return False
        if known is None:
            if not fit.radius <= MAX_UNKNOWN_RADIUS:
                # a misfit (a blob near the horizon fits a sphere kilometres wide, and a
                # radius that large would pass any test of where it stands)
                return True
        elif not self._ball_shaped(blob, fit, bg, hidden, offset, width=w if cut else None):
            # not the ball's image (a fragment, something else's, the ball merged with
            # something else): do not let it move the estimate
            return False
        if not self._on_floor(fit.position, fit.radius):
            # fitted off the floor (a blob near the horizon, fitted kilometres away): a ball
            # rests on the floor, so this is something else
            return True
        eye = (float(cam.position[0]), float(cam.position[1]), float(cam.position[2]))
        if hidden_by(self.network.mirror.scene, eye, fit.position, fit.radius) is not None:
            # a wall or an obstacle hides whatever is behind it (in 3D: a camera above a low
            # wall sees over it): the blob is something else (a fragment merged with the
            # wall's difference, a misfit near the horizon)
            return True
        if not self._reaches(fit.position, frame.time):
            # farther from the last sighting than the object can have gone: something
            # else of its size (a ghost the look has not repaired, another ball)
            return False
        if self.ball is None:
            self._measure_unknown(frame, fit.radius, mask, bbox)
        centre = (blob.centroid[0] + x0, blob.centroid[1] + y0)
        return Sighting(frame.index, frame.time, bbox, centre, blob.area, fit.position)

    def _ball_shaped(self, blob: Region, fit: BallFit, bg: BackgroundPercept,
                     hidden: np.ndarray | None, offset: tuple[int, int],
                     width: int | None = None) -> bool:
        """Whether ``blob``, whose upper outline ``fit`` fitted with the known radius, is that
        ball's image: of the area its image can show there (:data:`AREA_RANGE`; less what
        the imagined robot and other objects hide, ``hidden`` at ``offset``, and what is
        beyond the sides of a frame ``width`` pixels wide when given -- a blob cut by one --
        and at least :data:`MIN_SHOWN` of it), no longer than a ball's image
        (:data:`MAX_LENGTH`), and with an outline that fits it (:data:`OUTLINE_RMS_PX`,
        :data:`OUTLINE_RMS_SHARE`; a blob placed by its centroid has none, and is tested by
        its area and length only)."""
        cam = self.network.mirror.camera
        centre = (fit.position[0], fit.position[1], fit.radius)
        whole = image_area(cam, centre, fit.radius)
        if not math.isfinite(whole):
            return False
        # the frame's bottom edge is not counted: a fragment by it would fit a ball mostly
        # below it (a blob cut by the top is refused before: _sighting)
        size = None if width is None else (width, UNBOUNDED_ROWS)
        area = visible_area(cam, centre, fit.radius, size, hidden=hidden, hidden_at=offset,
                            to_camera=bg.to_synthetic)
        if area < MIN_SHOWN * whole or not AREA_RANGE[0] * area <= blob.area <= AREA_RANGE[1] * area:
            return False
        diameter = 2.0 * math.sqrt(whole / math.pi)
        speed = math.hypot(*self.kf.velocity) if self.kf.initialised else 0.0
        blur = speed * self.network.frame_interval * diameter / (2.0 * fit.radius)
        if silhouette_length(blob.silhouette) > MAX_LENGTH * diameter + blur + LENGTH_SLACK_PX:
            return False
        if fit.points == 0:
            return True  # placed by its centroid: no outline to test
        rms_px = math.radians(fit.rms_deg) * cam.fx
        return rms_px <= max(OUTLINE_RMS_PX, OUTLINE_RMS_SHARE * math.sqrt(whole / math.pi))

    def _continues(self, at: tuple[float, float], time: float) -> bool:
        """Whether ``at`` is within :data:`CUT_REACH_RADII` radii and 3 sigma of where the
        track, which followed the object up to its last sighting, puts it at ``time``."""
        assert self.last is not None
        ahead = self.kf.predict_position(max(time - self.last.time, 0.0))
        reach = CUT_REACH_RADII * self._radius() + 3.0 * self.kf.position_sigma
        return math.dist(at, ahead) <= reach

    def _fits_cut(self, fit: BallFit, bg: BackgroundPercept, bbox: BBox, width: int) -> bool:
        """Whether the ball ``fit`` places, in a frame ``width`` pixels wide whose side cuts
        the blob ``bbox`` (frame pixels), has its centre in view (about half of its image,
        or more) and its image's top and uncut side where the blob's are (within
        :data:`CUT_EDGE_SHARE` of its image's width, and a pixel)."""
        cam = self.network.mirror.camera
        centre = np.array([fit.position[0], fit.position[1], fit.radius])
        limb = limb_points(cam.position, centre, fit.radius)
        if limb is None:
            return False
        points = np.vstack([centre, limb])
        if not (cam.to_camera(points)[:, 2] > 0.0).all():
            return False
        pix = cam.project(points)
        real = np.array([bg.to_real((float(u), float(v))) for u, v in pix])
        if not np.isfinite(real).all() or not 0.0 <= real[0, 0] <= width - 1.0:
            return False
        left, right = float(real[1:, 0].min()), float(real[1:, 0].max())
        top = float(real[1:, 1].min())
        bx, by, bw, _ = bbox
        side = bx + bw - 1.0 - right if bx == 0 else bx - left
        tolerance = CUT_EDGE_SHARE * (right - left) + 1.0
        return abs(by - top) <= tolerance and abs(side) <= tolerance

    def _follow(self, seen: Sighting) -> None:
        """Take ``seen`` into the track: the filter, and whether the object has moved
        :data:`MOVED_RADII` radii in a run of the filter -- held until a restart on a jump
        that long from where the filter had it (a restart on a smaller one, a bounce or a
        sighting's noise, keeps it: a camera on the robot near the ball restarts the filter
        every few frames)."""
        self.last = seen
        ahead = None
        if self.kf.initialised and self.kf.time is not None:
            ahead = self.kf.predict_position(max(seen.time - self.kf.time, 0.0))
        self.kf.step(seen.time, seen.position)
        if self._run is None or self._run[1] != self.kf.restarts:
            self._run = (seen.position, self.kf.restarts)
            if ahead is None or math.dist(seen.position, ahead) > MOVED_RADII * self._radius():
                self._moved = False
        elif math.dist(seen.position, self._run[0]) > MOVED_RADII * self._radius():
            self._moved = True

    def _reaches(self, at: tuple[float, float], time: float) -> bool:
        """Whether the object, last seen at ``self.last``, can be at ``at`` by ``time``: no
        farther than its track's speed and :data:`SEARCH_SPEED` (a bounce turns it, never
        speeds it up; a push by the robot may) carry it in the time since, plus
        :data:`SEARCH_SIGMAS` of the track's position uncertainty and its diameter (the
        fits' errors).  Anywhere before the track has followed it :data:`MOVED_RADII`
        radii (it may be on a ghost: the object is taken where it shows)."""
        last = self.last
        if last is None or not self._moved:
            return True
        since = max(time - last.time, 0.0)
        speed, sigma = 0.0, 0.0
        if self.kf.initialised:
            speed = math.hypot(*self.kf.velocity)
            sigma = self.kf.position_sigma + self.kf.velocity_sigma * since
        reach = (speed + SEARCH_SPEED) * since + SEARCH_SIGMAS * sigma + 2.0 * self._radius()
        return math.dist(at, last.position) <= reach

    def _on_floor(self, at: tuple[float, float], radius: float) -> bool:
        """Whether a ball of ``radius`` at ``at`` is over the floor (its extent, when the scenario
        gives one; else within :data:`FLOOR_REACH` of the camera)."""
        if not all(math.isfinite(v) for v in (*at, radius)):
            return False
        extent = self.network.mirror.scene.floor.extent
        if extent is None:
            cam = self.network.mirror.camera.position
            return math.dist(at, (float(cam[0]), float(cam[1]))) <= FLOOR_REACH
        x0, y0, x1, y1 = extent
        return x0 - radius <= at[0] <= x1 + radius and y0 - radius <= at[1] <= y1 + radius

    def _measure_unknown(self, frame: "Frame", radius: float, mask: np.ndarray, bbox: BBox) -> None:
        """An object the scenario does not declare gets its size and colour from its sightings:
        the radius is the median of the first ``confirm`` fits, then it is fixed."""
        self._radii.append(radius)
        if len(self._radii) < int(self.parameters["confirm"]):
            return
        x, y, w, h = bbox
        patch = frame.image[y:y + h, x:x + w][mask[:h, :w]].reshape(-1, 3)
        # the lit side's colour: shading darkens most of a sphere, the highlight whitens a spot
        bgr = (np.percentile(patch, 75, axis=0) if len(patch)
               else np.array(UNKNOWN_COLOR, float))
        self.ball = Ball(self.body, radius=float(np.median(self._radii)),
                         color=(int(bgr[2]), int(bgr[1]), int(bgr[0])))

    def overlaps(self, position: tuple[float, float], radius: float) -> str | None:
        """The imagined body (a ball or the robot) that a body of ``radius`` at ``position``
        would overlap, or None: two solid things are never in one place, so a sighting there
        is part of that one (a fragment, its shadow), not an object of its own."""
        mirror = self.network.mirror
        world = mirror.world
        for other in world.balls:
            if other.name != self.body and other.name in world.names:
                if math.dist(position, world.position(other.name)) < radius + other.radius:
                    return other.name
        pose = mirror.robot_pose()
        robot = mirror.scene.robot
        if pose is not None and robot is not None:
            if math.dist(position, pose[0]) < radius + robot.outer_radius:
                return robot.name
        return None

    def _create_body(self, frame: "Frame") -> None:
        mirror = self.network.mirror
        ball = self.ball if self.ball is not None else Ball(self.body, radius=0.1)
        if self.overlaps(self.kf.position, ball.radius) is not None:
            return  # not yet, and not there (see overlaps)
        mirror.add_ball(ball, self.kf.position, self.kf.velocity)
        self.network.note(self, EventKind.CREATED, {"body": self.body,
                                            "position": [round(v, 4) for v in self.kf.position],
                                            "velocity": [round(v, 4) for v in self.kf.velocity]})

    # -- the spring ------------------------------------------------------------------------------

    def before_step(self, time: float) -> None:
        k = float(self.parameters["k"])
        if k <= 0 or not self.kf.initialised or self.misses > 0:
            return
        world = self.network.mirror.world
        if self.body not in world.names:
            return
        body = world.body(self.body)
        dt = time - (self.kf.time or time)
        vx, vy = self.kf.velocity
        px, py = self.kf.position
        px, py = px + vx * dt, py + vy * dt
        c = 2.0 * float(self.parameters["damping"]) * math.sqrt(k)
        ax = k * (px - body.position[0]) + c * (vx - body.velocity[0])
        ay = k * (py - body.position[1]) + c * (vy - body.velocity[1])
        # bounded: a target the body cannot reach (a wall between them) must not pump
        # energy into the contact solver without end
        limit = float(self.parameters["max_accel"])
        mirror = self.network.mirror
        robot, pose = mirror.scene.robot, mirror.robot_pose()
        if robot is not None and pose is not None:
            # the imagined robot is where the robot believes it stands, and the spring is a
            # correction, not a force of the world: against the robot it pushes no harder than
            # a part of what the robot's drive holds, and it does not pull the ball across the
            # robot at all (a target beyond it would shove the robot away)
            clear = robot.outer_radius + self._radius() + ROBOT_TOUCH
            here = (float(body.position[0]), float(body.position[1]))
            if math.dist(here, pose[0]) < clear:
                limit = min(limit, ROBOT_PUSH * robot.mass * robot.max_accel / body.mass)
            elif point_segment_distance(pose[0], here, (px, py)) < clear:
                return
        a = math.hypot(ax, ay)
        if a > limit:
            ax, ay = ax * limit / a, ay * limit / a
        world.apply_force(self.body, (body.mass * ax, body.mass * ay))

    # -- the input-link and the image ------------------------------------------------------------

    def monitored_box(self) -> BBox | None:
        """The object's sighting and its imagined body, with room for their contact shadows
        (a box half as wide again on each side, and as much again below)."""
        boxes = []
        if self.last is not None and self.misses <= int(self.parameters["lost_after"]):
            boxes.append(self.last.bbox)
        elif self._window is not None and self.sightings == 0:
            boxes.append(self._window)
        imagined = self._imagined_real_box()
        if imagined is not None:
            (cx, cy), r = imagined
            boxes.append((int(cx - r) - 2, int(cy - r) - 2, int(2 * r) + 5, int(2 * r) + 5))
        if not boxes:
            return None
        x0 = min(b[0] for b in boxes)
        y0 = min(b[1] for b in boxes)
        x1 = max(b[0] + b[2] for b in boxes)
        y1 = max(b[1] + b[3] for b in boxes)
        mx, my = (x1 - x0) // 2, (y1 - y0) // 2
        return (x0 - mx, y0 - my // 2, (x1 - x0) + 2 * mx, (y1 - y0) + my // 2 + 2 * my)

    def observed(self) -> tuple[float, float] | None:
        """The filtered floor position when the object is seen in this frame."""
        return self.kf.position if self.kf.initialised and self.misses == 0 else None

    def imagined(self) -> tuple[float, float] | None:
        """The imagined body's position, or None."""
        return self.network.mirror.world.position(self.body) if self.in_imagination else None

    def write(self, node: Structure) -> None:
        node.set("object", self.object_name)
        node.set("declared", self.declared)
        node.set("seen", self.misses == 0 and self.sightings > 0)
        node.set("frames-seen", self.sightings)
        node.set("frames-missed", self.misses)
        node.set("moved", self._moved)
        node.set("region", self.region if self.region > 0 else None)
        est = self.kf.initialised
        node.set("x", round(self.kf.position[0], 4) if est else None)
        node.set("y", round(self.kf.position[1], 4) if est else None)
        node.set("vx", round(self.kf.velocity[0], 4) if est else None)
        node.set("vy", round(self.kf.velocity[1], 4) if est else None)
        node.set("speed", round(math.hypot(*self.kf.velocity), 4) if est else None)
        node.set("radius", round(self._radius(), 4) if self.ball is not None else None)
        imagined = self.imagined()
        node.set("imagined", imagined is not None)
        node.set("imagined-x", None if imagined is None else round(imagined[0], 4))
        node.set("imagined-y", None if imagined is None else round(imagined[1], 4))
        node.set("doubted", self.doubted)
        error = None
        if imagined is not None and est:
            error = round(math.dist(imagined, self.kf.position), 4)
        node.set("error", error)
        node.set("bounces-seen", self.bounces_seen)
        self._write_estimates(node)
        self._write_prediction(node)

    def _write_estimates(self, node: Structure) -> None:
        if self.estimator is None:
            node.keep_children("parameters", [])
            return
        p = node.child("parameters", 0)
        consistent = True
        for name, e in self.estimate_records().items():
            key = name.replace("_", "-")
            p.set(key, round(e.mean, 4))
            p.set(f"{key}-std", round(e.std, 4))
            p.set(f"{key}-observations", e.count)
            consistent = consistent and e.surprise <= 3.0
        node.set("consistent", consistent)

    def _write_prediction(self, node: Structure) -> None:
        pred = self.prediction
        if pred is None:
            node.set("confidence", None)
            node.keep_children("prediction", [])
            node.keep_children("contact", [])
            return
        for h in pred.horizons:
            c = node.child("prediction", h.horizon)
            c.set("horizon", h.horizon)
            c.set("x", round(h.position[0], 4))
            c.set("y", round(h.position[1], 4))
            c.set("spread", round(h.spread, 4))
            c.set("confidence", round(h.confidence, 3))
            c.set("bounce", h.bounce)
        node.keep_children("prediction", [h.horizon for h in pred.horizons])
        node.set("confidence", round(pred.horizons[-1].confidence, 3))
        upcoming = [c for c in pred.contacts if c.time > pred.time][:3]
        for i, contact in enumerate(upcoming):
            c = node.child("contact", i)
            c.set("time", round(contact.time, 4))
            c.set("in", round(contact.time - pred.time, 4))
            c.set("x", round(contact.position[0], 4))
            c.set("y", round(contact.position[1], 4))
            c.set("surface", contact.surface)
        node.keep_children("contact", list(range(len(upcoming))))

    def stop(self) -> None:
        """Release the step hook.  A declared object's body stays in the imagination (the
        world has it); the body of an object the scenario does not know goes with its schema:
        nothing else would pull it, and what the schema took for a new object may be one the
        rules now know by its name (``rules/mirror/perception.soar``, ``recognise``)."""
        if self._hooked:
            self.network.mirror.remove_hook(self.before_step)
            self._hooked = False
        if not self.declared and self.in_imagination:
            self.network.mirror.remove_ball(self.body)

    def summary(self) -> dict[str, Any]:
        out = super().summary()
        out.update({"object": self.object_name, "seen": self.misses == 0 and self.sightings > 0,
                    "observed": None if self.observed() is None else
                    [round(v, 4) for v in self.kf.position],
                    "imagined": None if self.imagined() is None else
                    [round(v, 4) for v in self.imagined()],  # type: ignore[union-attr]
                    "refused": self.refused})
        return out


def _make(name: str, parameters: Mapping[str, Any], network: "SchemaNetwork") -> ForegroundObject:
    return ForegroundObject(name, FOREGROUND_OBJECT, parameters, network)


FOREGROUND_OBJECT = SchemaSpec(
    name="foreground-object",
    kind=SchemaKind.PERCEPTUAL,
    doc=("Finds one object in the real image (what differs from the imagination's "
         "background), fits its floor position from its silhouette, estimates its velocity, creates it in the imagination where it "
         "is first perceived, and pulls the imagined body towards it on every physics step "
         "(paper eq. 4 with a damper)."),
    factory=_make,
    provides=(Port("object", "the object's observed and imagined floor position and velocity"),),
    consumes=(Port("regions", "difference regions and the synthetic camera's H_e"),),
    parameters=(
        Parameter("object", str, "", "the world object it monitors (empty: an object the "
                  "scenario does not declare, named after the schema)"),
        Parameter("region", int, 0, "the tracked difference region it was spawned for "
                  "(0: none)", low=0, high=2**31 - 1),
        Parameter("k", float, 632.0, "spring stiffness (acceleration per metre of error); "
                  "0 leaves the imagination uncorrected", unit="1/s^2", low=0.0, high=1.0e5),
        Parameter("damping", float, 1.0, "damping ratio of the spring (1: critical)", low=0.0,
                  high=100.0),
        Parameter("max_accel", float, 400.0, "the spring's largest acceleration (a target "
                  "behind a wall or far off pulls no harder)", unit="m/s^2", low=0.0,
                  high=MAX_ACCEL, low_open=True),
        Parameter("confirm", int, 2, "sightings before the object is created in the imagination",
                  low=1, high=1000),
        Parameter("lost_after", int, 5, "frames without a sighting before it is lost", low=0,
                  high=1000),
        Parameter("min_area", int, 12, "smallest blob taken for the object", unit="px", low=1,
                  high=MAX_PIXELS),
        Parameter("process_noise", float, 0.3, "Kalman white-acceleration density",
                  unit="m^2/s^3", low=0.0, high=1.0e4, low_open=True),
        Parameter("measurement_noise", float, 0.005, "Kalman position noise", unit="m",
                  low=0.0, high=10.0, low_open=True),
        Parameter("noise_window", int, 15, "sightings whose scatter estimates the Kalman "
                  "position noise (never below measurement_noise; 0: fixed)", low=0, high=1000),
        Parameter("gate", float, 6.0, "innovation (sigmas) beyond which the filter restarts "
                  "from the last two sightings (a bounce)", low=0.0, high=1000.0, low_open=True),
        Parameter("adapt", bool, True, "estimate restitution, friction and rolling resistance "
                  "(and floor friction and drag, given ranges) online and give them to the "
                  "imagined body"),
        Parameter("identify", bool, True, "fit the state and the parameters by imagined "
                  "rollouts to the last sightings (false: the Kalman filter's state, line fits "
                  "at bounces and quadratic fits of rolling)"),
        Parameter("identify_window", float, 0.9, "seconds of sightings the identification "
                  "fits", unit="s", low=0.2, high=10.0),
        Parameter("identify_every", int, 2, "frames with a sighting between two steps of the "
                  "identification", low=1, high=1000),
        Parameter("predict", bool, True, "predict at the scenario's horizons (predict section)"),
    ),
)
