"""The Scene Background schema: keep the synthetic camera synchronised, report
what the imagination does not explain.

Every frame (paper section 4.1, Figure 3) it renders the imagination through
the synthetic camera, takes the camera loop's step against the real frame
(:func:`adapt.vision.sync.sync_step`: the match-mediated difference, its
pixel error, and the camera corrected with ``H_e``, eq. 3, or the full pose
from the floor's homography), and turns the difference into regions.  A
region a schema claims (the one it was spawned for) or monitors is
*expected*; any other is *unexpected*, and the rules decide whether to spawn
a perceptual schema for it.  Regions are followed over frames
(:mod:`adapt.schemas.tracks`) so each has an age.  What it perceives is
published as a :class:`~adapt.schemas.percepts.BackgroundPercept` on its
ports; the schema itself keeps only the policy: when to correct, the filter
of false alignments, the learning schedule.

Each region is reported with its bounding box, centroid and area (real-image
pixels), its floor position (the bottom of its box back-projected onto the
floor) and width on the floor (metres), its age in frames, its mean colour and
the declared object it looks like (colour and size:
:func:`~adapt.schemas.percepts.looks_like`).

**Appearance learning** (``appearance``: ``on``; ``auto``, the default, is on
for any reality but a synthetic one: a video, a PyBullet reality).  The scenario gives the room's geometry but rarely the
exact look of its surfaces, and the MMD only works where the render looks
like the camera's image.  The schema then teaches the mirror the surfaces'
look (:mod:`adapt.mirror.appearance`) in two stages:

1. ``structure``: before anything is learned, the camera is aligned to what
   the geometry alone decides, the edges between surfaces
   (:mod:`adapt.mirror.structure`): per frame, up to
   :data:`STRUCTURE_ITERATIONS` rounds of fitting each surface's smooth
   colour, registering it to the frame and correcting the camera, with a fit
   margin that shrinks with the error.  No MMD and no regions meanwhile
   (status ``waiting``).  Once the error is within ``tolerance`` (or stops
   falling below :data:`STRUCTURE_ACCEPT` pixels), the camera's whole pose is
   fitted to the frame's edges at the structure's seams, from where the
   scenario puts it (``edge_fit``, :mod:`adapt.vision.edge_pose`: the
   registration is a turn of the image, and trades a wall's parallel seams
   for each other); then the
   per-pixel median of the frames kept since the start (up to ``still_s``
   seconds of them, :class:`~adapt.vision.stillness.FrameHistory`: an object
   that moved through the view is gone from it) is back-projected onto every
   surface seen, but for the pixels whose median is not settled (an object
   stayed there in most of the frames, stood there at the oldest or stands
   there at the newest: :meth:`~adapt.vision.stillness.FrameHistory.settled`);
   while in more than :data:`MOVING_SHARE` of the pixels no majority of the
   frames agree, it waits for up to ``still_s`` seconds of frames, so that a
   ball rolling from the first frame is gone from their median and never
   painted into the floor, and the path it rolled over is learned with the
   rest (where it started and where it is, and what a slow one covered, are
   learned later, below);
2. ``learned``: the usual MMD with the learned look, the camera corrected as
   always; every ``learn_every`` frames in which the camera is synchronised,
   the frame refines the look (``learn_rate``, ``learn_gate``), never where a
   schema monitors the image, where an unexpected region moves, where a
   pixel changed over the last ``still_s`` seconds (a moving object is never
   learned), or where the MMD differs -- unless the pixel held still there
   for the whole ``still_s`` outside every monitored box and every region that
   looks like a declared object on texels the look learned (one at rest that
   nothing follows is not learned into the look, where no schema could find it
   again): that is background
   the look has wrong or never saw (a ghost of an object learned at rest that
   has left, what a ball covered at the first look), learned afresh there.
   An unexpected region whose pixels have not changed over its last
   :data:`STILL_REGION_FRAMES` frames (but for :data:`STILL_SHARE` of them, or
   fewer than :data:`STILL_PIXELS`: the camera's noise) is reported ``still``: the perception
   rules spawn no schema for it (nothing arrived there; it is the look's
   error, repaired as above).  A fixed camera's first look cannot see what the
   imagined bodies hid (the floor under the robot's starting place): once they
   leave, that floor is a difference of the look's ignorance, not an object.  The
   pixels kept are the bodies' with a margin, which the first look does not learn
   (:meth:`~adapt.mirror.appearance.AppearanceModel.unseen`), but the refinements
   can, from the real body where it shows past the imagined outline while it
   stands (a pose a little off, another shape): once it leaves, a dark rim.  An
   unexpected region at least :data:`UNSEEN_SHARE` of whose pixels are there and
   held still over its last :data:`STILL_REGION_FRAMES` frames is reported
   ``unseen`` (so is one mostly on texels the first look left unlearned because
   something moved over them: :meth:`~adapt.mirror.appearance.AppearanceModel.hidden`,
   a ball rolling through it): the rules spawn no schema for it either; and those texels that are
   still unlearned are learned as soon as their pixels held
   still for ``still_s``, whatever box or region covers them (what the imagination
   draws there now, the robot come back, is never learned).
   A camera on the robot restarts its history whenever the robot's odometry moves
   it (never for this schema's own corrections of where the robot stands), and is
   ``camera-moving`` while the robot is driven and for ``still_s`` after the odometry
   last moved it (the real robot sets off before the odometry has gone far): its
   difference then holds its own
   motion's errors (the perception rules spawn only for a region that looks like a
   declared object no schema follows yet, and find a lost object again only once the
   camera holds still).  A camera that held still that long and has been far from
   synchronised (more than :data:`STRUCTURE_ACCEPT` pixels) for
   :data:`UNSYNCHRONISED_RELEARN` frames learns afresh what held still: its
   corrections do not settle, so its look is what is wrong (a texture the renderer
   aliases anew since the camera turned, a change of light).  While it moves, what
   its view shows for the first time is learned every frame it is in step
   (:meth:`SceneBackground._explore`).
   A frame whose matches give no ``H_e`` (a texture the renderer aliases
   differently as a robot's camera turns, a plain face filling the view) is
   aligned by the structure instead, keeping the look, and compared through
   that (the MMD's ``H_e`` held at the identity): the object schemas search it,
   but a camera on the robot reports no region, since without matches the
   difference's own errors cannot be told from objects (``structure_held``
   counts such frames); a fixed camera whose matches last left it within
   :data:`HELD_IN_STEP` pixels of synchronised has not moved since, and reports
   its regions as with matches.
   After :data:`REACQUIRE_AFTER` frames that neither aligns the structure is
   aligned again from a wide margin and the look learned afresh.

Learning the look with a wrong pose would hide the pose error in the
textures (a render of what was learned reproduces the frame whatever the
pose), which is why the structure comes first.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import time
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import VisionError
from adapt.geometry import MAX_PIXELS
from adapt.imagination import LABEL_BALL, LABEL_SKY
from adapt.mirror.structure import face_labels
from adapt.scenario import RealityKind
from adapt.schemas.base import BBox, Schema, Status
from adapt.schemas.links import Structure
from adapt.schemas.percepts import (
    AppearanceStage,
    BackgroundPercept,
    FirstLook,
    RegionReport,
    colour_like,
    looks_like,
    mean_color,
)
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec
from adapt.schemas.tracks import RegionTracker
from adapt.vision.camera_correction import correct_rotation
from adapt.vision.edge_pose import EdgePose, apply_pose, fit_edges, relative_pose, seam_points
from adapt.vision.edges import edge_agreement
from adapt.vision.homography import corner_error
from adapt.vision.matching import PreparedImage, prepare
from adapt.vision.mmd import MMDResult
from adapt.vision.regions import Region, best_overlap, find_regions, to_input
from adapt.vision.registration import structure_homography
from adapt.vision.scale import MAX_WORK_PIXELS_LIMIT, image_scale, working_frame
from adapt.vision.stillness import FrameHistory
from adapt.vision.sync import MAX_TURN_MISFIT, SyncStep, sync_step

if TYPE_CHECKING:  # pragma: no cover
    from adapt.frames import Frame
    from adapt.geometry import Camera
    from adapt.mirror import Learning
    from adapt.schemas.network import SchemaNetwork

__all__ = ["SceneBackground", "SCENE_BACKGROUND", "RegionReport", "AppearanceStage",
           "AppearanceMode", "STRUCTURE_ITERATIONS", "STRUCTURE_ACCEPT", "REACQUIRE_AFTER"]

#: Fit-align-correct rounds per frame while the camera is aligned to the structure.
STRUCTURE_ITERATIONS = 3
#: The structure's fit margin (pixels at 640x480): twice the last error, within these bounds.
STRUCTURE_MARGIN = (2.0, 24.0)
#: Below this fit margin (pixels at 640x480) small surfaces are fitted to their own pixels.
STRUCTURE_OWN_COLOURS = 6.0
#: A structure error (pixels at 640x480) accepted once it stops falling.
STRUCTURE_ACCEPT = 1.5
#: Frames without alignment, once learned, before the structure is aligned again.
REACQUIRE_AFTER = 10
#: Frames in a row aligned but farther than :data:`STRUCTURE_ACCEPT` from synchronised, by a
#: camera that held still, before what held still is learned afresh (the look is wrong, not
#: the pose).
UNSYNCHRONISED_RELEARN = 10
#: Pixels (at 640x480) around monitored boxes, regions and differences that are never learned.
EXCLUDE_PAD = 6
#: Label of the floor in a render (the full pose is corrected from matches on it).
FLOOR_LABEL = 1
#: A moving camera on the robot learns what it sees for the first time once it sees at least
#: this many such pixels (at 640x480): the scenario's guess drawn there, not the scene.
EXPLORE_PIXELS = 400
#: Frames over which an unexpected region is judged still (its box's pixels unchanged).
STILL_REGION_FRAMES = 3
#: A region whose box changed in less than this share of its pixels over those frames is still
#: -- or in fewer than :data:`STILL_PIXELS` pixels: a small box's share is its sensor noise.
STILL_SHARE = 0.02
#: Changed pixels a still region's box may hold whatever its size (a camera's noise flips a few
#: isolated pixels past the threshold: one is 3 % of a 7 x 5 box).
STILL_PIXELS = 4
#: An unexpected region at least this share of whose pixels show surfaces where the look
#: was never learned, and held still, is reported ``unseen`` (see the module docstring).
UNSEEN_SHARE = 0.5
#: The first look waits for up to a full history while in more than this share of the pixels
#: no majority of the frames agree.
MOVING_SHARE = 0.001
#: The first look learns a pixel that changed over its frames from their median where more
#: than this share of them agree with it, the oldest and the newest among them
#: (:meth:`~adapt.vision.stillness.FrameHistory.settled`): a majority.
SETTLED_SHARE = 0.55
#: A fixed camera whose matches last left it within this many pixels (at 640x480) of
#: synchronised reports regions in a frame without matches too (the perception rules spawn
#: only below 4 px).
HELD_IN_STEP = 3.0
#: A camera on the robot has moved (its frame history restarts) once the robot's odometry
#: carried it past these (m, degrees) since it last did.
MOUNT_MOVED = (0.005, 0.3)
#: A camera on the robot is carried by the odometry: a step whose H_e moves its image by more
#: than this (pixels at 640x480, about 12 degrees of turn) is a false alignment, synchronised or not.
MOUNTED_JUMP = 100.0


class AppearanceMode(enum.Enum):
    """The ``appearance`` parameter: learn the surfaces' look, or not, or for a video."""

    AUTO = "auto"  # on for any reality but a synthetic one (a video, PyBullet's)
    ON = "on"
    OFF = "off"


class SceneBackground(Schema):
    """See the module docstring."""

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        super().__init__(name, spec, parameters, network)
        self.tracker = RegionTracker()
        #: the declared objects' colours and radii, for what a region looks like
        self._looks = {name: (m.ball.color, m.ball.radius) for name, m in network.models.items()}
        #: ... and their colours alone, for the pixels that could show one
        self._colours = [c for c, _ in self._looks.values()]
        self.result: MMDResult | None = None
        self.synthetic: NDArray[np.uint8] | None = None
        self.background_image: NDArray[np.uint8] | None = None
        self.labels: NDArray[np.int32] | None = None
        self.regions: list[RegionReport] = []
        self.pixel_error = math.nan
        self.correction_deg = 0.0
        self.corrections = 0
        #: The last fit of the camera's pose to the frame's edges (``edge_fit``), if any.
        self.edge_fit: EdgePose | None = None
        #: Structure corrections refused because they moved the seams off the image's edges.
        self.refused_corrections = 0
        #: Frames whose matches gave no H_e, compared through the structure's alignment.
        self.structure_held = 0
        self.ms = 0.0
        self._prepared_for: tuple[int, ...] | None = None
        self._background: PreparedImage | None = None
        self._label_of: dict[str, int] = {}
        self._robot_box: BBox | None = None
        #: The frame's alignment can be believed (aligned, and not a sudden false jump).
        self.trusted = False
        self._settled = 1e9   # a smoothed pixel error of the trusted frames
        self._glitches = 0
        mode = AppearanceMode(self.parameters["appearance"])
        # auto: learn the look of any reality the imagination's renderer did not draw
        learn = mode is AppearanceMode.ON or (mode is AppearanceMode.AUTO
                                              and network.reality is not RealityKind.SYNTHETIC)
        if not learn:
            self.stage = AppearanceStage.OFF
        elif network.mirror.appearance.learned or not self.parameters["correct"]:
            self.stage = AppearanceStage.LEARNED  # a loaded look, or no pose to align first
        else:
            self.stage = AppearanceStage.STRUCTURE
        self.learning: "Learning | None" = None
        self.learn_ms = 0.0
        self.learn_passes = 0
        self.structure_error = math.nan
        self._margin = STRUCTURE_MARGIN[1]
        self._structure_errors: list[float] = []
        self._since_learn = 0
        self._unaligned = 0
        self._unsynchronised = 0  # frames in a row aligned but far from synchronised
        #: The frame the look was first learned from (for the figures); None before.
        self.first_look: FirstLook | None = None
        #: The percept last published.
        self.percept: BackgroundPercept | None = None
        self._warped: tuple[MMDResult, NDArray[np.uint16]] | None = None
        #: The camera's recent frames while it did not move (what held still).
        self.history = FrameHistory(max(3, int(round(float(self.parameters["still_s"])
                                                       / network.frame_interval))))
        #: A camera on the robot: the imagined robot's pose at the end of the last frame (after
        #: this schema's own corrections, which are no motion of the camera)
        self._last_pose: tuple[tuple[float, float], float] | None = None
        #: ... how far its odometry carried it since it last moved past MOUNT_MOVED (m, radians)
        self._travelled = (0.0, 0.0)
        self._moved_at = -math.inf  # ... and when it last did (s)
        #: A camera on the robot that its odometry moved in the last ``still_s`` seconds (its
        #: difference holds its own motion's errors: parallax, blur, texture aliased anew).
        self.camera_moving = False
        self._held = 0  # frames the first look has waited, once aligned
        #: A fixed camera's pixels that imagined bodies hid from the first look (None: none).
        self._covered: NDArray[np.bool_] | None = None

    # -- perception ---------------------------------------------------------------------

    def _prepared_synthetic(self, image: NDArray[np.uint8]) -> PreparedImage:
        """The synthetic frame with the corners of the current background (computed once
        per camera pose and scene)."""
        mirror = self.network.mirror
        pixels = int(self.parameters["mmd_pixels"])
        # a learned look changes the background without moving the camera
        key = (id(mirror.renderer), mirror.camera_changes, pixels,
               mirror.renderer.backdrop.version, mirror.appearance.sky_version)
        if self._prepared_for != key or self._background is None:
            self._background = prepare(mirror.background.image, max_pixels=pixels)
            self._prepared_for = key
        frame = prepare(image, corners=False, max_pixels=pixels)
        # the frame's own images (its moving objects drawn), the background's corners
        return dataclasses.replace(frame, corners=self._background.corners)

    def _rendered(self, background: bool = True) -> None:
        """Render the imagination through the camera as it stands (before this frame's
        correction moves it)."""
        mirror = self.network.mirror
        rendered = mirror.render()
        self.synthetic, self.labels = rendered.image, rendered.labels
        if background:
            # the background through this frame's camera, before any correction moves it:
            # what H_e maps onto the real frame (an object's difference is taken against it)
            self.background_image = mirror.background.image
        self._label_of = {name: label for label, name in rendered.names.items()}
        robot = mirror.scene.robot
        self._robot_box = None if robot is None else rendered.boxes.get(robot.name)

    def perceive(self, frame: "Frame") -> None:
        mirror = self.network.mirror
        if self._odometry_moved():
            self.history.clear()  # what the camera saw before is another view
            self._moved_at = frame.time
        self.camera_moving = mirror.mounted and (
            frame.time - self._moved_at < float(self.parameters["still_s"])
            or mirror.robot_driven())
        self._perceive(frame)
        if mirror.mounted:
            self._last_pose = mirror.robot_pose()

    def _odometry_moved(self) -> bool:
        """A camera on the robot: whether the robot's odometry has carried it past
        :data:`MOUNT_MOVED` since it last did (this schema's own corrections of where the
        robot stands move no camera, and are not counted)."""
        mirror = self.network.mirror
        pose = mirror.robot_pose() if mirror.mounted else None
        if pose is None or self._last_pose is None:
            return False
        (x0, y0), h0 = self._last_pose
        (x1, y1), h1 = pose
        turn = abs((h1 - h0 + math.pi) % (2 * math.pi) - math.pi)
        total = (self._travelled[0] + math.dist((x0, y0), (x1, y1)), self._travelled[1] + turn)
        if total[0] > MOUNT_MOVED[0] or math.degrees(total[1]) > MOUNT_MOVED[1]:
            self._travelled = (0.0, 0.0)
            return True
        self._travelled = total
        return False

    def _perceive(self, frame: "Frame") -> None:
        started = time.perf_counter()
        mirror = self.network.mirror
        self.learning = None
        self.learn_ms = 0.0
        if self.stage is not AppearanceStage.OFF:
            self._remember(frame)
        if self.stage is AppearanceStage.STRUCTURE:
            if not self._align_structure(frame):
                self._waiting(frame, started)
                return
            if self._moving():
                self._held += 1
                self._waiting(frame, started, gathering=True)
                return
            self._held = 0
            if self.parameters["edge_fit"] and self.parameters["correct"]:
                self._fit_edges(frame)
            self._learn(frame, mirror.render().labels, fresh=True)
            self.stage = AppearanceStage.LEARNED
        self._rendered()
        camera = mirror.camera
        self.correction_deg = 0.0
        correct = bool(self.parameters["correct"])
        step = self._sync(frame, camera, correct)
        if not step.result.aligned and correct and self.stage is AppearanceStage.LEARNED \
                and self._align_structure(frame):
            # no H_e from the matches (texture the renderer aliases differently as the camera
            # turns, a plain face filling the view), but the structure aligned the camera:
            # compare through it
            self._rendered()
            camera = mirror.camera
            # (its matches again, but no SIFT: SIFT found nothing in this frame a moment ago)
            step = self._sync(frame, camera, correct, hold=np.eye(3))
            self.structure_held += 1
        res = self.result = step.result
        self.trusted = step.trusted
        if not res.aligned:
            self.status = Status.LOST
            self.message = res.alignment.reason
            self.pixel_error = math.nan
        elif not step.trusted:
            self.status = Status.LOST
            self.message = (f"H_e moves the image by {step.pixel_error:.1f} px after "
                            f"{self._settled:.1f} px: a false alignment, ignored")
            self._glitches += 1
            self.pixel_error = step.pixel_error
            self.tracker.update([], frame.index)
            self.regions = []
            self._publish(frame.index, frame.time, camera, started)
            return
        else:
            self._glitches = 0
            self.status = Status.RUNNING
            self.message = (f"H_e from the structure's alignment: {res.alignment.reason}"
                            if res.alignment.held else "")
            self.pixel_error = step.pixel_error
            if not res.alignment.held:  # a held H_e's error is no measurement of the camera's
                self._settled = (step.pixel_error if self._settled >= 1e9
                                 else 0.8 * self._settled + 0.2 * step.pixel_error)
            elif self._fixed_in_step(frame.image.shape):
                # a fixed camera has not moved since its matches last measured it: that error
                self.pixel_error = self._settled
            if step.corrected is not None:
                self.correction_deg = step.correction_deg
                self.corrections += 1
                mirror.set_camera(step.corrected)
        # published once the camera step is done: the boxes the other schemas monitor are
        # asked for in this frame's alignment
        early = self._publish(frame.index, frame.time, camera, started)
        if res.alignment.held and not self._fixed_in_step(frame.image.shape):
            # without matches the difference's own errors (a texture aliased differently as
            # a camera on the robot turns, a view the look has not seen) cannot be told from
            # objects: the schemas search for the objects they follow, but no region is
            # reported to spawn one for.  (A fixed camera in step compares the frame through
            # the camera its matches last corrected, which has not moved: as good as then.)
            self.tracker.update([], frame.index)
            self.regions = []
        else:
            self.regions = self._regions(frame, early)
        if self.stage is AppearanceStage.LEARNED:
            self._refine(frame, res)
        self._publish(frame.index, frame.time, camera, started)

    def _on_floor(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which synthetic pixels (of the render) show the floor."""
        assert self.labels is not None
        ix = np.clip(points[:, 0].round().astype(int), 0, self.labels.shape[1] - 1)
        iy = np.clip(points[:, 1].round().astype(int), 0, self.labels.shape[0] - 1)
        return np.asarray(self.labels[iy, ix] == FLOOR_LABEL)

    def joined(self) -> None:
        """Publish what it knows before its first frame: nothing aligned, no regions."""
        self._publish(self.network.frame_index, self.network.time, self.network.mirror.camera)

    def _publish(self, index: int, time_s: float, camera: "Camera",
                 started: float | None = None) -> BackgroundPercept:
        """This frame's percept, published on both ports."""
        from adapt.imagination import LABEL_BALL

        if started is not None:
            self.ms = (time.perf_counter() - started) * 1000.0
        res = self.result
        moving = any(lab >= LABEL_BALL for lab in self._label_of.values())  # balls, robot
        if not (self.trusted and res is not None and res.aligned and moving
                and self.labels is not None):
            self._warped = None
        elif self._warped is None or self._warped[0] is not res:
            h, w = self.labels.shape
            warped = cv2.warpPerspective(
                self.labels.astype(np.uint16), res.homography, (w, h),  # type: ignore[arg-type]
                flags=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            self._warped = (res, np.asarray(warped, np.uint16))
        percept = BackgroundPercept(
            frame=index, time=time_s, camera_before=camera,
            camera_after=self.network.mirror.camera, mmd=res, trusted=self.trusted,
            pixel_error=self.pixel_error, threshold=float(self.parameters["threshold"]),
            tolerance=self._tolerance((camera.height, camera.width)),
            synthetic=self.synthetic, background=self.background_image, labels=self.labels,
            drawn=MappingProxyType(dict(self._label_of)),
            warped_labels=None if self._warped is None else self._warped[1],
            regions=tuple(self.regions), ms=self.ms, stage=self.stage,
            learn_passes=self.learn_passes, learn_ms=self.learn_ms, first_look=self.first_look,
            structure_error=self.structure_error)
        self.percept = percept
        self.network.publish(self, percept)
        return percept

    def _sync(self, frame: "Frame", camera: "Camera", correct: bool,
              hold: NDArray[np.float64] | None = None) -> SyncStep:
        """This frame's step of the camera loop (:func:`~adapt.vision.sync.sync_step`)."""
        return sync_step(frame.image, self._prepared_synthetic(self.synthetic),  # type: ignore[arg-type]
                         camera, gain=self.parameters["gain"],
                         tolerance=self._tolerance(frame.image.shape) if correct else math.inf,
                         full_pose=bool(self.parameters["full_pose"]), on_plane=self._on_floor,
                         trust=lambda error: not self._implausible(error, frame),
                         max_pixels=int(self.parameters["mmd_pixels"]), hold=hold,
                         reacquire=hold is None,
                         # a learned look differs from the frame only by how the camera turned
                         max_misfit=MAX_TURN_MISFIT if self.stage is AppearanceStage.LEARNED
                         else None)

    def _tolerance(self, shape: tuple[int, ...]) -> float:
        """``tolerance`` in pixels of a frame of ``shape``: the parameter counts pixels
        of the image the MMD works on (a frame reduced to ``mmd_pixels`` measures its
        error no finer than that image's pixels, so a finer tolerance would correct
        the camera by the matches' noise, and render the background anew for it)."""
        factor = working_frame(shape, int(self.parameters["mmd_pixels"])).factor
        return float(self.parameters["tolerance"]) * max(factor)

    def _implausible(self, error: float, frame: "Frame") -> bool:
        """A sudden large jump of a camera that was synchronised is a false alignment
        (repetitive texture filling the view, a fast turn) more often than a real move: it is
        ignored for up to ``glitches`` frames in a row, then believed.  A camera on the robot
        is carried by the odometry, synchronised or not: a step that would turn it by more
        than :data:`MOUNTED_JUMP` pixels is one too."""
        scale = image_scale(frame.image.shape)
        jump = float(self.parameters["max_jump"]) * scale
        if self._glitches >= int(self.parameters["glitches"]):
            return False
        if self.network.mirror.mounted and error > MOUNTED_JUMP * scale:
            return True
        return self._settled < 2.0 * scale and error > jump

    # -- appearance learning ------------------------------------------------------------

    def _fixed_in_step(self, shape: tuple[int, ...]) -> bool:
        """A fixed camera whose look is learned and whose matches, when they last aligned
        it, left it within :data:`HELD_IN_STEP` pixels (at 640x480) of synchronised: a frame
        without matches is compared through that camera as well as through an ``H_e``."""
        if self.network.mirror.mounted or self.stage is not AppearanceStage.LEARNED:
            return False
        return self._settled <= HELD_IN_STEP * image_scale(shape)

    def _remember(self, frame: "Frame") -> None:
        """Keep the frame in the history of a camera that has not moved (a camera on the
        robot starts it again whenever the robot's odometry moves it: :meth:`perceive`)."""
        self.history.push(frame.image)

    def _moving(self) -> bool:
        """Whether the first look must wait for more frames: until two are kept, and while
        in more than :data:`MOVING_SHARE` of the pixels no majority of them agree (something
        moving crossed them in about half the frames,
        :meth:`~adapt.vision.stillness.FrameHistory.settled` without its ends) until
        ``still_s`` seconds of them are -- at most that many frames (a camera on a robot
        that keeps driving keeps none).  What the look learns is stricter: the pixels where
        the oldest and the newest frame agree with the majority too (see :meth:`_learn`)."""
        h = self.history
        if len(h) >= h.depth or self._held >= h.depth:
            return False
        if len(h) < 2:
            return True
        agreed = h.settled(float(self.parameters["threshold"]), SETTLED_SHARE, ends=False)
        return 1.0 - float(np.count_nonzero(agreed)) / max(agreed.size, 1) > MOVING_SHARE

    def _waiting(self, frame: "Frame", started: float, gathering: bool = False) -> None:
        """A frame of the structure stage: the render for the figures, no MMD, no regions."""
        self._rendered(background=False)
        self.result = None
        self.trusted = False
        self.pixel_error = math.nan
        self.status = Status.WAITING
        err = self.structure_error
        if gathering:
            self.message = (f"aligned; something moves: keeping up to {self.history.depth} "
                            f"frames to learn the look from their median ({len(self.history)} "
                            "so far)")
        else:
            self.message = ("aligning the camera to the scene's structure before learning its "
                            "look" + ("" if math.isnan(err) else f" ({err:.2f} px)"))
        self.tracker.update([], frame.index)
        self.regions = []
        self._publish(frame.index, frame.time, self.network.mirror.camera, started)

    def _align_structure(self, frame: "Frame") -> bool:
        """Rounds of structure alignment and camera correction; True once aligned."""
        mirror = self.network.mirror
        shape = frame.image.shape
        scale = image_scale(shape)
        tolerance = self.parameters["tolerance"]
        self.correction_deg = 0.0
        for _ in range(STRUCTURE_ITERATIONS):
            cam = mirror.camera
            bg = mirror.background
            labels = face_labels(bg.labels, mirror.renderer.surfaces, cam)
            # While the error is large, small surfaces take the scenario's colours
            # (fitted to their own pixels they would hide the offset); once it is
            # small, their own pixels say their colour best.
            coarse = self._margin > STRUCTURE_OWN_COLOURS * scale
            hom = structure_homography(frame.image, labels, (cam.cx, cam.cy), margin=self._margin,
                                       reference=bg.image if coarse else None)
            if hom is None and coarse:
                # the scenario's colours can be unlike the surfaces' (bright wall tops where
                # it says dark brick: the look is unknown) and turn the correlation negative;
                # the small surfaces' own pixels then
                hom = structure_homography(frame.image, labels, (cam.cx, cam.cy),
                                           margin=self._margin)
            if hom is None:
                self._margin = STRUCTURE_MARGIN[1] * scale
                self.structure_error = math.nan
                self._structure_errors.clear()
                return False
            err = corner_error(hom, np.eye(3), shape)
            self.structure_error = err
            self._margin = float(np.clip(2.0 * err, STRUCTURE_MARGIN[0] * scale,
                                         STRUCTURE_MARGIN[1] * scale))
            history = self._structure_errors
            history.append(err)
            del history[:-4]
            stalled = len(history) == 4 and history[-1] > 0.9 * history[0]
            if err <= tolerance or (stalled and err <= STRUCTURE_ACCEPT * scale):
                self._structure_errors.clear()
                return True
            try:
                new = correct_rotation(cam, hom, gain=1.0)
            except VisionError:
                return False
            if not self._seams_agree(frame.image, bg.labels, new):
                # the fitted colours pull the camera off the surfaces' seams in the
                # image: the pose it has agrees with the frame better than that
                self.refused_corrections += 1
                self._structure_errors.clear()
                return True
            self.correction_deg += cam.angle_to(new)
            self.corrections += 1
            mirror.set_camera(new)
        return False

    def _fit_edges(self, frame: "Frame") -> None:
        """Fit the camera's pose to the frame's edges at the structure's seams
        (:func:`~adapt.vision.edge_pose.fit_edges`), once the structure is aligned and
        before the look is learned through it (a look learned through a wrong pose hides
        the error: see the module docstring)."""
        mirror = self.network.mirror
        current = mirror.camera
        # from where the scenario puts the camera (the fit's prior on the turn is centred
        # there: the structure's alignment can trade one seam for its parallel neighbour),
        # and from where the structure aligned it
        cam = mirror.declared_camera()
        renderer = mirror.renderer.with_camera(cam)
        labels = face_labels(renderer.background.labels, renderer.surfaces, cam)
        fit = fit_edges(frame.image, seam_points(labels, renderer.background_depth, cam.K), cam.K,
                        starts=(relative_pose(cam, current),))
        self.edge_fit = fit
        if fit is None:
            return
        new = apply_pose(cam, fit)
        self.correction_deg += current.angle_to(new)
        self.corrections += 1
        mirror.set_camera(new)

    def _seams_agree(self, image: NDArray[np.uint8], labels: NDArray[np.integer],
                     new: "Camera") -> bool:
        """Whether the render's seams through ``new`` agree with ``image``'s edges at least
        as well as through the current camera (:func:`~adapt.vision.edges.edge_agreement`)."""
        here = edge_agreement(image, labels)
        there = edge_agreement(image, self.network.mirror.renderer.with_camera(new).background.labels)
        return not there < here  # NaN (no seams in view) says nothing: agree

    def _refine(self, frame: "Frame", res: MMDResult) -> None:
        """Once learned: count frames without alignment (re-acquire after too many)
        and refine the look every ``learn_every`` synchronised frames."""
        if not res.aligned:
            self._unaligned += 1
            if self._unaligned >= REACQUIRE_AFTER and self.parameters["correct"]:
                self.stage = AppearanceStage.STRUCTURE
                self._margin = STRUCTURE_MARGIN[1] * image_scale(frame.image.shape)
                self._unaligned = 0
                self._settled = 1e9  # the camera will jump: nothing to compare with
                self.network.mirror.appearance.forget()
                self.history.clear()  # what the lost view showed is not the scene's look
            return
        self._unaligned = 0
        if self.learning is not None:
            return  # learned this frame already (the structure's first look)
        self._since_learn += 1
        synchronised = self.trusted and (self.pixel_error <= self._tolerance(frame.image.shape)
                                         or not self.parameters["correct"])
        far = self.trusted and self.pixel_error > STRUCTURE_ACCEPT * image_scale(frame.image.shape)
        self._unsynchronised = self._unsynchronised + 1 if far else 0
        # a camera that stood still for still_s (a camera on the robot: by its odometry)
        # and has been far from synchronised for UNSYNCHRONISED_RELEARN frames: its
        # corrections do not converge, so the look is wrong, not the pose (a texture the
        # renderer aliases differently since the camera turned, the light changed): what
        # held still over those frames is learned afresh
        stuck = (self._unsynchronised >= UNSYNCHRONISED_RELEARN
                 and len(self.history) >= self.history.depth)
        if (synchronised or stuck) and self._since_learn >= self.parameters["learn_every"] \
                and self.labels is not None:
            self._learn(frame, self.labels, fresh=False)
        elif self.camera_moving and self.trusted and self.labels is not None and (
                res.alignment.held  # aligned by the structure this frame: no matches
                or self.pixel_error <= self._tolerance(frame.image.shape)):
            self._explore(frame, self.labels)

    def _explore(self, frame: "Frame", labels: NDArray[np.int32]) -> None:
        """A camera on the robot that moves, in step: learn what its view shows for the
        first time (the scenario's guess is drawn there until then, a difference that
        hides objects and spoils the matches), and the sky's faces it never saw, every
        frame; never where a pixel's colour could be a declared object's
        (:func:`~adapt.schemas.percepts.colour_like`), near an imagined body (within its
        image's width and height), in the box of a schema whose object is not drawn yet,
        or in a region that looks like a declared object no schema follows; what was
        learned stays as it is (:meth:`~adapt.mirror.appearance.AppearanceModel.learn`'s
        ``new_only``)."""
        shape = frame.image.shape
        h, w = int(shape[0]), int(shape[1])
        if labels.shape != (h, w):
            return
        mirror = self.network.mirror
        new = mirror.appearance.unseen(mirror.camera, labels)
        if np.count_nonzero(new) < EXPLORE_PIXELS * image_scale(shape) ** 2:
            return
        new |= labels == LABEL_SKY  # (new_only: the sky's faces never seen)
        pad, kernel = _margin(shape)
        # a pixel that could show a declared object (its colour under some light): the
        # object itself, seen where nothing follows it yet, is never learned
        ys, xs = np.nonzero(new)
        like = np.zeros((h, w), np.uint8)
        like[ys, xs] = colour_like(frame.image[ys, xs], self._colours)
        # only there (a pixel around it: a texel straddles pixels): what was learned stays
        near = np.asarray(cv2.dilate(new.view(np.uint8), np.ones((3, 3), np.uint8)), np.uint8)
        mask = (near ^ 1) | np.asarray(cv2.dilate(like, kernel), np.uint8)
        boxes = []
        bodies = (labels >= LABEL_BALL).astype(np.uint8)
        if bodies.any():
            n, _, stats, _ = cv2.connectedComponentsWithStats(bodies)
            for x, y, bw, bh, _area in stats[1:n].tolist():
                # an imagined body and a body's width or height around it: where the real
                # one is, a little off
                boxes.append((x - bw, y - bh, 3 * bw, 3 * bh))
        # an object's schema whose object the imagination does not draw yet: where it looks
        boxes += [b for name, b in self.network.monitored_boxes(exclude=self.name)
                  if name not in self._label_of]
        # what looks like a declared object no schema follows yet
        boxes += [r.bbox for r in self.regions if not r.expected and r.looks_like is not None]
        for x, y, bw, bh in boxes:
            mask[max(0, y - pad):max(0, y + bh + pad), max(0, x - pad):max(0, x + bw + pad)] = 1
        p = self.parameters
        learned = mirror.learn_appearance(
            frame.image, labels, exclude=mask.astype(bool), rate=p["learn_rate"],
            gate=p["learn_gate"], new_only=True)
        if learned.new:
            self.learning = learned
            self.learn_ms = learned.ms
            self.learn_passes += 1

    def _learn(self, frame: "Frame", labels: NDArray[np.int32], *, fresh: bool) -> None:
        """One learning pass of the mirror's appearance model on ``frame``."""
        p = self.parameters
        mirror = self.network.mirror
        before = mirror.render().image if self.first_look is None else None
        gate = float(p["threshold"])
        still = None
        if len(self.history) >= 2:
            # the first look: where an object crossed a pixel in a few of the frames the
            # others agree on what lies under it, learned from the median, not left for a
            # later pass (the path the ball rolled during the first look is no difference
            # then); a refinement: the pixels that held still
            still = (self.history.settled(gate, SETTLED_SHARE) if fresh
                     else self.history.still(gate))
        covered = None
        _, kernel = _margin(frame.image.shape)
        if fresh:  # what the view showed most of the time: a passing object is gone from it
            image = self.history.median() if len(self.history) else frame.image
            exclude, relearn = self._exclusion(frame.image.shape, still=still)
            if still is not None and still.shape == exclude.shape \
                    and image.shape == frame.image.shape:
                # where something moved through the frames and has gone (the newest frame
                # agrees with the median there): texels to learn once it held still -- not
                # where it is now (the object itself, for its schema)
                now = cv2.absdiff(frame.image, image)
                if now.ndim == 3:
                    now = now.max(axis=2)
                moving = (~still).view(np.uint8)
                here = np.asarray(cv2.dilate(moving & (now > gate).view(np.uint8), kernel),
                                  np.uint8)
                covered = (np.asarray(cv2.dilate(moving, kernel), np.uint8) > 0) & (here == 0)
            self._covered = None
            if not mirror.mounted and labels.shape == frame.image.shape[:2]:
                # what the imagined bodies (the robot) hid from this look, with a margin
                self._covered = np.asarray(
                    cv2.dilate((labels >= LABEL_BALL).astype(np.uint8), kernel), bool)
        else:
            image = frame.image
            full = len(self.history) >= self.history.depth
            exclude, relearn = self._exclusion(frame.image.shape, still=still, repair=full,
                                               labels=labels)
        learned = mirror.learn_appearance(
            image, labels, exclude=exclude, rate=p["learn_rate"],
            gate=None if fresh else p["learn_gate"], relearn=relearn, covered=covered)
        if before is not None:
            self.first_look = FirstLook(frame.index, frame.time, image, before,
                                        mirror.render().image)
        self.learning = learned
        self.learn_ms = learned.ms
        self.learn_passes += 1
        self._since_learn = 0

    def _exclusion(self, shape: tuple[int, ...], still: NDArray[np.bool_] | None,
                   repair: bool = False, labels: NDArray[np.int32] | None = None
                   ) -> tuple[NDArray[np.bool_], NDArray[np.bool_] | None]:
        """Frame pixels never to learn -- every monitored box, every region that is not
        still or looks like a declared object (but for one on unlearned texels: ``unseen``),
        every pixel that changed over the history (``still`` False) and every pixel
        the MMD finds different, each with a margin -- and, with ``repair``, the pixels to
        learn afresh: different from the look but still for the whole history, outside
        every monitored box and moving region, or (given the render's ``labels``) where the
        imagined bodies hid the surfaces from a fixed camera's first look and the look there
        is still unlearned, whatever box covers them (see the module docstring)."""
        h, w = int(shape[0]), int(shape[1])
        pad, kernel = _margin(shape)
        mask = np.zeros((h, w), np.uint8)
        boxes = [b for _, b in self.network.monitored_boxes(exclude=self.name)]
        # (a still region that looks like a declared object, on texels the look learned, may
        # be one at rest that nothing follows: never learned into the look, where no schema
        # could find it again; on texels the look never learned it is the look's error)
        boxes += [r.bbox for r in self.regions
                  if r.expected or not r.still or (r.looks_like is not None and not r.unseen)]
        for x, y, bw, bh in boxes:
            mask[max(0, y - pad):max(0, y + bh + pad), max(0, x - pad):max(0, x + bw + pad)] = 1
        moved = None
        if still is not None and still.shape == (h, w):
            moved = np.asarray(cv2.dilate((~still).view(np.uint8), kernel), np.uint8)
            mask |= moved
        res = self.result
        relearn = None
        if res is not None and res.aligned:
            differs = (res.difference >= self.parameters["threshold"]).view(np.uint8)
            if differs.shape != (h, w):
                differs = cv2.resize(differs, (w, h), interpolation=cv2.INTER_NEAREST)
            differs = np.asarray(cv2.dilate(differs, kernel), np.uint8)
            if repair and moved is not None:
                anew = (differs > 0) & (mask == 0)
                covered = self._covered
                if labels is not None and covered is not None and covered.shape == (h, w) \
                        and labels.shape == (h, w) and covered.any():
                    mirror = self.network.mirror
                    bx, by, bw, bh = cv2.boundingRect(covered.view(np.uint8))
                    fresh = np.zeros((h, w), bool)
                    fresh[by:by + bh, bx:bx + bw] = mirror.appearance.unseen(
                        mirror.camera, labels, (bx, by, bw, bh))
                    anew |= (moved == 0) & fresh & covered
                if labels is not None and labels.shape == (h, w):
                    # what an object covered when the look was learned (a ball rolling
                    # through the first look) and held still since, in a box or region:
                    # never what the imagination draws there now, with a margin
                    boxed = (mask > 0) & (moved == 0)
                    if boxed.any():
                        mirror = self.network.mirror
                        bx, by, bw, bh = cv2.boundingRect(boxed.view(np.uint8))
                        left = np.zeros((h, w), bool)
                        left[by:by + bh, bx:bx + bw] = mirror.appearance.hidden(
                            mirror.camera, labels, (bx, by, bw, bh))
                        if left.any():
                            bodies = cv2.dilate((labels >= LABEL_BALL).astype(np.uint8), kernel)
                            anew |= boxed & left & (bodies == 0)
                relearn = anew if anew.any() else None
                differs[anew] = 0
                mask[anew] = 0
            mask |= differs
        return mask.astype(bool), relearn

    def _regions(self, frame: "Frame", percept: BackgroundPercept) -> list[RegionReport]:
        """This frame's difference regions, tracked: each owned by the schema that claims it,
        else by the schema whose monitored box holds most of it (``expected``), or by
        nobody (``unexpected``)."""
        res = percept.mmd
        if res is None or not res.aligned:
            self.tracker.update([], frame.index)
            return []
        found = to_input(find_regions(res.difference, threshold=self.parameters["threshold"],
                                      min_area=max(1, int(round(self._min_area(
                                          res.difference.shape))))),
                         res.frame)
        tracks = self.tracker.update(found, frame.index)
        claims = self.network.claims()
        for t in tracks:
            if t.owner is not None and claims.get(t.id) != t.owner:
                t.owner = None  # its claimant let it go (it found its object) or is gone
        for region, claimant in claims.items():
            track = self.tracker.get(region)
            if track is not None and (track.owner is None or track.owner not in self.network):
                self.tracker.assign(region, claimant)  # one owner per region: the first holds
        monitored = self.network.monitored_boxes(exclude=self.name)
        own = self._own_robot(res)
        if own is not None:
            monitored.append(own)
        boxes = [b for _, b in monitored]
        h_inv = np.linalg.inv(res.homography)  # type: ignore[arg-type]
        out = []
        for t in tracks:
            owner = t.owner
            if owner is not None and owner not in self.network:
                t.owner = owner = None
            if owner is None:
                best = best_overlap(t.region.bbox, boxes)
                owner = None if best is None else monitored[best][0]
            floor, size = _floor_of(t.region.bbox, h_inv, percept.camera_before)
            r = t.region
            x, y, w, h = r.bbox
            edge = x <= 0 or y <= 0 or x + w >= frame.image.shape[1] or y + h >= frame.image.shape[0]
            color = mean_color(frame.image, r.bbox, r.silhouette)
            out.append(RegionReport(t.id, r.bbox, r.centroid, r.area, t.age, owner is not None,
                                    owner, floor, size, percept.imagined_in(r), edge,
                                    owner is None and self._still(r.bbox), color,
                                    looks_like(color, size, self._looks),
                                    owner is None and self._unseen(r, frame.image)))
        return out

    def _still(self, bbox: BBox) -> bool:
        """Whether the camera's pixels in ``bbox`` held still over the last
        :data:`STILL_REGION_FRAMES` frames, with a learned look (see the module docstring)."""
        if self.stage is not AppearanceStage.LEARNED or len(self.history) < STILL_REGION_FRAMES:
            return False
        held = self.history.still(float(self.parameters["threshold"]),
                                  frames=STILL_REGION_FRAMES, box=bbox)
        changed = held.size - int(np.count_nonzero(held))
        return changed < max(STILL_SHARE * held.size, STILL_PIXELS)

    def _unseen(self, region: Region, image: NDArray[np.uint8]) -> bool:
        """Whether at least :data:`UNSEEN_SHARE` of ``region``'s pixels are where the look
        is the scenario's guess, not the scene's, and held still over the last
        :data:`STILL_REGION_FRAMES` frames: where imagined bodies hid the surfaces from a
        fixed camera's first look (with a margin), or where the first look left texels
        unlearned because something moved over them
        (:meth:`~adapt.mirror.appearance.AppearanceModel.hidden`: a ball rolling through
        it).  The look's ignorance there, whether its texels are still
        unlearned or were learned from the real body's rim past the imagined outline (see
        the module docstring) -- unless what changed in it over those frames shows a
        declared object's colour in ``image`` (the frame) in ``min_area`` pixels or more:
        that object, moving on from where it stood while the look was learned (the two
        differences make one region)."""
        labels = self.labels
        if self.stage is not AppearanceStage.LEARNED or labels is None \
                or len(self.history) < STILL_REGION_FRAMES:
            return False
        x, y, w, h = region.bbox
        mask = region.silhouette
        mirror = self.network.mirror
        left = mirror.appearance.hidden(mirror.camera, labels, region.bbox)
        covered = self._covered
        if covered is not None and covered.shape == labels.shape \
                and covered[y:y + h, x:x + w].shape == left.shape:
            left |= covered[y:y + h, x:x + w]
        if not left.any():
            return False
        still = self.history.still(float(self.parameters["threshold"]),
                                   frames=STILL_REGION_FRAMES, box=region.bbox)
        if not still.shape == mask.shape == left.shape:  # cut by the edge
            return False
        # the texels there were never learned, or learned past the imagined body's outline
        # from the real one (a pose a little off, another shape: a dark rim of it once it
        # has driven off)
        mine = still & mask & left
        if int(np.count_nonzero(mine)) < UNSEEN_SHARE * max(int(mask.sum()), 1):
            return False
        moving = mask & ~still
        if not moving.any() or not self._looks:
            return True
        pixels = image[y:y + h, x:x + w][moving]
        like = colour_like(pixels, self._colours)
        return int(np.count_nonzero(like)) < self._min_area(image.shape)

    def _min_area(self, shape: tuple[int, ...]) -> float:
        """``min_area`` (given at 640x480) for an image of ``shape``, in pixels."""
        scale = image_scale(shape)
        return float(self.parameters["min_area"]) * scale * scale

    def _own_robot(self, res: MMDResult) -> tuple[str, BBox] | None:
        """The robot's own body in the real frame: the robot knows where it is, so a
        difference there (its odometry slipped) is not an unexpected object."""
        robot = self.network.mirror.scene.robot
        if robot is None or self._robot_box is None or res.homography is None:
            return None
        x, y, w, h = self._robot_box
        corners = np.array([[x, y, 1.0], [x + w, y, 1.0], [x, y + h, 1.0], [x + w, y + h, 1.0]])
        p = corners @ res.homography.T
        p = p[:, :2] / p[:, 2:]
        x0, y0 = p.min(axis=0)
        x1, y1 = p.max(axis=0)
        m = 0.25 * max(x1 - x0, y1 - y0)
        return robot.name, (int(x0 - m), int(y0 - m), int(x1 - x0 + 2 * m), int(y1 - y0 + 2 * m))

    # -- the input-link -------------------------------------------------------------------

    def write(self, node: Structure) -> None:
        aligned = self.result is not None and self.result.aligned
        node.set("aligned", aligned)
        node.set("pixel-error", round(self.pixel_error, 2) if aligned else None)
        node.set("inliers", 0 if self.result is None else self.result.n_inliers)
        cam = self.network.mirror.camera
        node.set("synchronised", aligned and self.pixel_error
                 <= self._tolerance((cam.height, cam.width)))
        node.set("camera-moving", self.camera_moving)
        node.set("mounted", self.network.mirror.mounted)
        unexpected = [r for r in self.regions if not r.expected]
        node.set("unexpected", len(unexpected))
        node.set("appearance", self.stage.value)
        node.set("structure-error", None if self.stage is not AppearanceStage.STRUCTURE
                 or math.isnan(self.structure_error) else round(self.structure_error, 2))
        for r in self.regions:
            c = node.child("region", r.id)
            c.set("id", r.id)
            c.set("expected", r.expected)
            c.set("monitored-by", r.owner)
            c.set("area", r.area)
            x, y, w, h = r.bbox
            c.set("x", x)
            c.set("y", y)
            c.set("width", w)
            c.set("height", h)
            c.set("centroid-x", round(r.centroid[0], 2))
            c.set("centroid-y", round(r.centroid[1], 2))
            c.set("floor-x", None if r.floor is None else round(r.floor[0], 4))
            c.set("floor-y", None if r.floor is None else round(r.floor[1], 4))
            c.set("size", None if r.size is None else round(r.size, 4))
            c.set("imagined", r.imagined)
            for key, v in zip(("color-r", "color-g", "color-b"), r.color or (None,) * 3):
                c.set(key, v)
            c.set("looks-like", r.looks_like)
            c.set("at-edge", r.at_edge)
            c.set("still", r.still)
            c.set("unseen", r.unseen)
            c.set("age", r.age)
        node.keep_children("region", [r.id for r in self.regions])

    def summary(self) -> dict[str, Any]:
        out = super().summary()
        aligned = self.result is not None and self.result.aligned
        out.update({"aligned": aligned,
                    "pixel_error": round(self.pixel_error, 3) if aligned else None,
                    "inliers": 0 if self.result is None else self.result.n_inliers,
                    "regions": len(self.regions),
                    "unexpected": sum(not r.expected for r in self.regions),
                    "appearance": self.stage.value,
                    "learned": len(self.network.mirror.appearance.learned),
                    "structure_held": self.structure_held})
        return out


def _margin(shape: tuple[int, ...]) -> tuple[int, NDArray[np.uint8]]:
    """:data:`EXCLUDE_PAD` in pixels of a frame of ``shape``, and the disc that dilates a
    mask by it."""
    pad = int(math.ceil(EXCLUDE_PAD * image_scale(shape)))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * pad + 1, 2 * pad + 1))
    return pad, np.asarray(kernel, np.uint8)


def _floor_of(bbox: BBox, h_inv: NDArray[np.float64], camera: "Camera"
              ) -> tuple[tuple[float, float] | None, float | None]:
    x, y, w, h = bbox
    real = np.array([[x + w / 2.0, y + h, 1.0], [x, y + h, 1.0], [x + w, y + h, 1.0]])
    syn = real @ h_inv.T
    syn = syn[:, :2] / syn[:, 2:]
    pts = camera.pixel_to_plane(syn, 0.0)
    if not np.isfinite(pts).all():
        return None, None
    return (float(pts[0, 0]), float(pts[0, 1])), float(np.linalg.norm(pts[2, :2] - pts[1, :2]))


def _make(name: str, parameters: Mapping[str, Any], network: "SchemaNetwork") -> SceneBackground:
    return SceneBackground(name, SCENE_BACKGROUND, parameters, network)


SCENE_BACKGROUND = SchemaSpec(
    name="scene-background",
    kind=SchemaKind.PERCEPTUAL,
    doc=("Keeps the synthetic camera synchronised with the real one by MMD every frame "
         "(paper eq. 3), and reports every difference region the imagination does not "
         "explain, with its box, centroid, area, floor position and age."),
    factory=_make,
    provides=(Port("regions", "difference regions of the frame, tracked, expected or not"),
              Port("camera", "the synchronised synthetic camera and H_e")),
    parameters=(
        Parameter("gain", float, 0.5, "fraction g of the camera correction applied per frame",
                  low=0.0, high=1.0, low_open=True),
        Parameter("tolerance", float, 0.5, "no correction below this pixel error (pixels of "
                  "the image the MMD works on: see mmd_pixels)", unit="px",
                  low=0.0, high=1000.0),
        Parameter("correct", bool, True, "correct the synthetic camera (off: only compare)"),
        Parameter("full_pose", bool, False,
                  "correct the position too, from the floor's homography"),
        Parameter("threshold", float, 30.0, "MMD difference that counts", unit="grey levels",
                  low=0.0, high=255.0, low_open=True),
        Parameter("min_area", int, 40, "smallest region reported, at 640x480 (scaled with the "
                  "image's area)", unit="px", low=1, high=MAX_PIXELS),
        Parameter("max_jump", float, 12.0, "once synchronised, a pixel error above this (at "
                  "640x480, scaled) is a false alignment, ignored", unit="px", low=0.0,
                  high=10000.0, low_open=True),
        Parameter("glitches", int, 5, "frames in a row a false alignment is ignored before it "
                  "is believed", low=0, high=1000),
        Parameter("mmd_pixels", int, 640 * 480, "largest image the MMD works on (a larger "
                  "frame is reduced first; fewer pixels: faster, a coarser H_e)", unit="px",
                  low=32 * 32, high=MAX_WORK_PIXELS_LIMIT),
        Parameter("appearance", str, "auto", "learn the surfaces' look from the frames: on, off, "
                  "or auto (on for any reality but a synthetic one)", choices=("auto", "on", "off")),
        Parameter("learn_every", int, 10, "once learned, refine the look every this many "
                  "synchronised frames", unit="frames", low=1,
                  high=1_000_000),
        Parameter("learn_rate", float, 0.1, "fraction a learned pixel moves towards the frame "
                  "per refinement (slow lighting drift is absorbed)", low=0.0, high=1.0,
                  low_open=True),
        Parameter("learn_gate", float, 40.0, "a learned pixel that differs from the frame by more "
                  "than this is not refined", unit="grey levels", low=0.0, high=255.0,
                  low_open=True),
        Parameter("edge_fit", bool, True, "before the first look is learned, fit the camera's "
                  "pose (turn and shift) to the frame's edges at the structure's seams"),
        Parameter("still_s", float, 0.4, "a pixel is learned only once it held still this long "
                  "(the first look: the median of this many seconds of frames)", unit="s",
                  low=0.0, high=2.0, low_open=True),
    ),
    singleton=True,
)
