"""The frozen records a scenario file is read into.

The ``camera`` and ``world`` sections become the imagination's own records
(:class:`~adapt.geometry.Camera`, :class:`~adapt.imagination.scene.SceneSpec`);
this module holds the rest: how the camera is mounted, what is known of each
object before it is seen, where the "real" frames come from (``reality``),
the ``goals``, the ``rules``, schema parameters (``schemas``), and the
``run``, ``predict`` and ``outputs`` settings.  Every record keeps the
:class:`~adapt.scenario.source.Source` of its YAML node, so a layer that
finds a problem later reports it at ``file:line:col`` with the key path.

Numbers that reality may draw per run are :class:`Range` s: a fixed value is
a range whose ends are equal.

Examples
--------
>>> import numpy as np
>>> r = Range(0.6, 0.8)
>>> 0.6 <= r.draw(np.random.default_rng(1)) <= 0.8, Range.fixed(2.0).draw(None)
(True, 2.0)
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike

from adapt.geometry import Camera
from adapt.imagination.scene import Ball, Vec2
from adapt.scenario.source import UNKNOWN, Source

__all__ = [
    "Range",
    "Mount",
    "CameraMount",
    "Creation",
    "ObjectModel",
    "RealityKind",
    "Throw",
    "TrueObject",
    "CameraOffset",
    "RealAppearance",
    "RobotTruth",
    "SyntheticReality",
    "PluginReality",
    "PluginRef",
    "VideoReality",
    "CameraReality",
    "VideoCodec",
    "BulletSurfaces",
    "BulletObject",
    "BulletLook",
    "BulletRobot",
    "BulletReality",
    "TextureSource",
    "Reality",
    "Goal",
    "GoalKind",
    "RuleFile",
    "SchemaSettings",
    "RunSettings",
    "PredictSettings",
    "OutputSettings",
    "MODEL_RANGE_PARAMETERS",
]

#: Ball parameters an object model may give as ranges (what is known before it is seen).
MODEL_RANGE_PARAMETERS = ("restitution", "friction", "rolling_resistance", "floor_friction",
                          "drag")


@dataclass(frozen=True, slots=True)
class Range:
    """A number, or an interval to draw it from uniformly (``low == high``: fixed)."""

    low: float
    high: float

    @classmethod
    def fixed(cls, value: float) -> "Range":
        """The range holding only ``value``."""
        return cls(float(value), float(value))

    @property
    def is_fixed(self) -> bool:
        """True when both ends are equal."""
        return self.low == self.high

    @property
    def mid(self) -> float:
        """The middle of the range."""
        return 0.5 * (self.low + self.high)

    def draw(self, rng: np.random.Generator | None) -> float:
        """A value from the range (the value itself when fixed; ``rng`` may then be None)."""
        if self.is_fixed:
            return self.low
        assert rng is not None, "a range needs a generator to draw from"
        return float(rng.uniform(self.low, self.high))

    def as_json(self) -> float | list[float]:
        """The fixed value, or ``[low, high]``."""
        return self.low if self.is_fixed else [self.low, self.high]


# -- the camera mount -------------------------------------------------------------

class Mount(enum.Enum):
    """Where the camera is: fixed in the world, or carried by the robot."""

    FIXED = "fixed"
    ROBOT = "robot"


@dataclass(frozen=True, slots=True)
class CameraMount:
    """How the camera moves.

    For :attr:`Mount.ROBOT`, ``position`` and ``look_at`` are in the robot's
    frame (origin at the robot's centre on the floor, ``x`` along its heading,
    ``y`` to its left, ``z`` up) and the camera turns and moves with the robot.
    For :attr:`Mount.FIXED` they are world coordinates, as in the scenario.
    """

    kind: Mount
    position: tuple[float, float, float]
    look_at: tuple[float, float, float]
    roll_deg: float = 0.0
    source: Source = UNKNOWN

    def world_pose(self, robot_position: Vec2, robot_heading: float) -> tuple[np.ndarray, np.ndarray]:
        """World ``(position, look_at)`` of the camera for a robot pose
        (``robot_heading`` in radians); the fixed mount ignores the pose.

        Examples
        --------
        >>> m = CameraMount(Mount.ROBOT, (0.1, 0.0, 0.5), (1.1, 0.0, 0.3))
        >>> p, t = m.world_pose((2.0, 1.0), math.pi / 2)
        >>> p.round(6).tolist(), t.round(6).tolist()
        ([2.0, 1.1, 0.5], [2.0, 2.1, 0.3])
        """
        p = np.array(self.position, float)
        t = np.array(self.look_at, float)
        if self.kind is Mount.FIXED:
            return p, t
        rot, offset = _robot_frame(robot_position, robot_heading)
        return rot @ p + offset, rot @ t + offset

    def mount_pose(self, position: ArrayLike, look_at: ArrayLike,
                   robot_position: Vec2, robot_heading: float) -> tuple[np.ndarray, np.ndarray]:
        """The inverse of :meth:`world_pose`: world ``position`` and ``look_at`` in the
        mount's frame (the robot's, for :attr:`Mount.ROBOT`; unchanged when fixed).

        Examples
        --------
        >>> m = CameraMount(Mount.ROBOT, (0.1, 0.0, 0.5), (1.1, 0.0, 0.3))
        >>> p, t = m.mount_pose(*m.world_pose((2.0, 1.0), 0.3), (2.0, 1.0), 0.3)
        >>> (p.round(6) + 0.0).tolist(), (t.round(6) + 0.0).tolist()
        ([0.1, 0.0, 0.5], [1.1, 0.0, 0.3])
        """
        p = np.asarray(position, float)
        t = np.asarray(look_at, float)
        if self.kind is Mount.FIXED:
            return p, t
        rot, offset = _robot_frame(robot_position, robot_heading)
        return rot.T @ (p - offset), rot.T @ (t - offset)

    def camera_at(self, base: Camera, robot_position: Vec2, robot_heading: float) -> Camera:
        """The camera ``base`` (its intrinsics) where the mount puts it for a robot pose
        (``robot_heading`` in radians): the one place a robot's camera is posed.

        Examples
        --------
        >>> base = Camera.look_at(fx=100, fy=100, cx=40, cy=30, width=80, height=60,
        ...                       position=(0, 0, 1), look_at=(1, 0, 1))
        >>> m = CameraMount(Mount.ROBOT, (0.0, 0.0, 0.6), (1.0, 0.0, 0.6))
        >>> m.camera_at(base, (2.0, 1.0), math.pi / 2).position.round(6).tolist()
        [2.0, 1.0, 0.6]
        """
        p, t = self.world_pose(robot_position, robot_heading)
        return Camera.look_at(fx=base.fx, fy=base.fy, cx=base.cx, cy=base.cy, width=base.width,
                              height=base.height, position=p, look_at=t, roll_deg=self.roll_deg)


def _robot_frame(position: Vec2, heading: float) -> tuple[np.ndarray, np.ndarray]:
    """The rotation and offset that take the robot's frame to the world's."""
    c, s = math.cos(heading), math.sin(heading)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return rot, np.array([position[0], position[1], 0.0])


# -- object models -----------------------------------------------------------------

class Creation(enum.Enum):
    """When an object enters the imagination."""

    AT_START = "at_start"
    WHEN_SEEN = "when_seen"


@dataclass(frozen=True, slots=True, eq=False)
class ObjectModel:
    """What the robot knows of an object before it sees it.

    Attributes
    ----------
    ball : Ball
        The nominal model: radius, mass, colour and nominal parameters (and
        the initial position and velocity when created at the start).
    create : Creation
        ``AT_START``: in the imagination from the first frame;
        ``WHEN_SEEN``: instantiated where it is first perceived, by the schema
        spawned for it.
    ranges : mapping of str to Range
        The plausible values of ``restitution``, ``friction``,
        ``rolling_resistance``, ``floor_friction`` (a ball with spin) and ``drag``
        (a fixed range at the nominal value when the scenario gives none);
        identification starts from them and prediction ensembles draw from them.
    """

    ball: Ball
    create: Creation = Creation.AT_START
    ranges: Mapping[str, Range] = field(default_factory=lambda: MappingProxyType({}))
    source: Source = UNKNOWN

    @property
    def name(self) -> str:
        """The object's name."""
        return self.ball.name

    def range(self, parameter: str) -> Range | None:
        """The range of a ball parameter (the nominal value when none was given; None for
        ``floor_friction`` of a ball without spin)."""
        if parameter in self.ranges:
            return self.ranges[parameter]
        value = getattr(self.ball, parameter)
        return None if value is None else Range.fixed(float(value))


# -- reality ---------------------------------------------------------------------

class RealityKind(enum.Enum):
    """Where the "real" frames come from."""

    SYNTHETIC = "synthetic"
    VIDEO = "video"
    CAMERA = "camera"
    BULLET = "bullet"


@dataclass(frozen=True, slots=True)
class Throw:
    """When and how an object enters reality: at a time, a place and a velocity,
    each drawn per run from its range (fixed values are ranges of one value).

    ``x``, ``y`` are the floor position (metres); ``speed`` (m/s) and
    ``heading_deg`` (degrees counter-clockwise from ``+x``) the velocity.
    ``height`` (a PyBullet reality only) lifts the ball's bottom that far
    above the floor, so it falls and bounces before it rolls.
    """

    time: Range
    x: Range
    y: Range
    speed: Range
    heading_deg: Range
    source: Source = UNKNOWN
    height: Range = Range(0.0, 0.0)


@dataclass(frozen=True, slots=True, eq=False)
class TrueObject:
    """An object as it really is (synthetic reality).

    Attributes
    ----------
    name : str
    ball : Ball
        Its look and size (for an object of the world, the world's model).
    declared : bool
        True when the world declares it (``world.objects``); False for an
        object that exists in reality only (something unexpected).
    restitution, friction, rolling_resistance, mass : Range
        The true parameters, drawn once per run.
    drag : Range
        Speed-dependent rolling drag: a deceleration ``drag * v**2`` (1/m) on
        top of the rolling resistance; the imagination's model has none.
    spin : Range
        Fraction (0..1) of the tangential velocity at a bounce that goes into
        spin and comes back over the following tenths of a second, so the
        rebound speed settles instead of jumping.
    throw : Throw or None
        When it appears; None: present from the start (at the world's
        position and velocity for a declared object).
    """

    name: str
    ball: Ball
    declared: bool
    restitution: Range
    friction: Range
    rolling_resistance: Range
    mass: Range
    drag: Range
    spin: Range
    throw: Throw | None
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True)
class CameraOffset:
    """How the true camera differs from the scenario's nominal one.

    ``position`` is metres ``[dx, dy, dz]`` in the world; ``rotation_deg`` is
    ``[pan, tilt, roll]`` degrees (pan about world up, tilt about the
    camera's ``x`` axis, roll about its viewing axis).  A scalar given in the
    scenario means that magnitude in a direction drawn from the run's seed;
    ``random_position`` / ``random_rotation`` hold it then.
    """

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
    random_position: float | None = None
    random_rotation: float | None = None
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True)
class RealAppearance:
    """How the true camera image differs from the imagination's render.

    Attributes
    ----------
    brightness : float
        Added to every channel, grey levels.
    contrast : float
        Gain on the image about mid-grey.
    color_shift : (b, g, r)
        Added per channel, grey levels.
    gradient : float
        Lighting falls off by this fraction from one side of the image to
        the other (0: even lighting).
    gradient_deg : float
        Direction of the fall-off in the image, degrees.
    blur : float
        Gaussian blur sigma, pixels (0: none).
    noise : float
        Sensor noise sigma, grey levels.
    texture_scale : float
        The real surfaces' texture tiles are this many times the model's.
    texture_phase : (s, t)
        Where the real textures' pattern starts, metres.
    tint : (b, g, r)
        Per-channel gain of the real surfaces (1: none).
    spin_marker : bool
        Real balls carry a marker that shows their spin.
    """

    brightness: float = 0.0
    contrast: float = 1.0
    color_shift: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gradient: float = 0.0
    gradient_deg: float = 0.0
    blur: float = 0.0
    noise: float = 0.0
    texture_scale: float = 1.0
    texture_phase: tuple[float, float] = (0.0, 0.0)
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)
    spin_marker: bool = False
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True)
class RobotTruth:
    """How the real robot obeys motor commands.

    ``max_speed`` and ``max_accel`` default to the model's (None);
    ``slip`` is the standard deviation of the wheel slip, as a fraction of
    the commanded velocity, drawn afresh every ``slip_interval`` seconds; the
    odometry does not see it.
    """

    max_speed: float | None = None
    max_accel: float | None = None
    slip: float = 0.0
    slip_interval: float = 0.2
    source: Source = UNKNOWN


class _BuiltinKind:
    """What the built-in reality records share: their ``name`` is the kind the scenario
    writes (a plugin's reality has the name it registered instead)."""

    __slots__ = ()
    kind: RealityKind

    @property
    def name(self) -> str:
        """``reality.kind`` as the scenario writes it."""
        return self.kind.value


@dataclass(frozen=True, slots=True, eq=False)
class SyntheticReality(_BuiltinKind):
    """A ground-truth world that differs from the imagination as reality does.

    ``dt`` is reality's own (finer) physics step; ``objects`` holds every
    object of reality, declared or not; ground truth is recorded per frame.
    """

    dt: float
    camera: CameraOffset
    appearance: RealAppearance
    objects: tuple[TrueObject, ...]
    robot: RobotTruth
    source: Source = UNKNOWN
    kind: RealityKind = RealityKind.SYNTHETIC

    def object(self, name: str) -> TrueObject:
        """The true object called ``name``."""
        for o in self.objects:
            if o.name == name:
                return o
        raise KeyError(name)


@dataclass(frozen=True, slots=True)
class VideoReality(_BuiltinKind):
    """Frames from a video file or an image sequence.

    Attributes
    ----------
    path : Path
        The video file, or the first directory part of an image glob.
    pattern : str or None
        The glob (``frames/*.png``), resolved relative to the scenario; None
        for a video file.
    fps : float or None
        Frames per second (required for an image sequence; a video file's
        own rate when None).
    ground_truth : Path or None
        A CSV file ``t,object,x,y[,vx,vy]`` in metres in the floor frame, for
        evaluation only.
    """

    path: Path
    pattern: str | None
    fps: float | None
    ground_truth: Path | None
    source: Source = UNKNOWN
    kind: RealityKind = RealityKind.VIDEO


class TextureSource(enum.Enum):
    """What the real surfaces of a PyBullet reality wear."""

    SCENARIO = "scenario"      # the scenario's own textures and colours
    BUNDLED = "bundled"        # a bundled photograph drawn per surface
    PROCEDURAL = "procedural"  # a pattern made from the seed per surface
    MIXED = "mixed"            # per surface, one of the three above


@dataclass(frozen=True, slots=True)
class BulletSurfaces:
    """Contact parameters of a group of real surfaces (the floor, the walls or the
    obstacles) in a PyBullet reality, PyBullet's own coefficients, each drawn once per
    run for the whole group.  PyBullet combines them with the ball's: restitution and
    friction multiply, rolling and spinning friction are ``ball.rolling * surface.friction
    + surface.rolling * ball.friction``.
    """

    restitution: Range
    friction: Range
    rolling_friction: Range
    spinning_friction: Range
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True, eq=False)
class BulletObject:
    """A ball as it really is in a PyBullet reality: its look and size (``ball``) and
    PyBullet's coefficients, each a :class:`Range` drawn per run.

    ``spin`` is the ball's angular velocity when it enters, as a share of rolling
    without slip (1: rolling, 0: sliding, negative: back-spin); ``side_spin`` its
    angular velocity about the vertical, rad/s; ``damping`` PyBullet's linear and
    angular damping (the share of velocity lost per second).
    """

    name: str
    ball: Ball
    declared: bool
    mass: Range
    restitution: Range
    friction: Range
    rolling_friction: Range
    spinning_friction: Range
    damping: Range
    spin: Range
    side_spin: Range
    throw: Throw | None
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True)
class BulletLook:
    """How a PyBullet reality's images look: textures, light and the sensor, each number
    drawn per run from its range."""

    textures: TextureSource = TextureSource.MIXED
    texture_scale: Range = Range(0.7, 1.5)
    light_elevation_deg: Range = Range(35.0, 80.0)
    light_azimuth_deg: Range = Range(0.0, 360.0)
    light_warmth: Range = Range(-0.15, 0.15)
    ambient: Range = Range(0.45, 0.7)
    diffuse: Range = Range(0.3, 0.55)
    specular: Range = Range(0.0, 0.3)
    shadows: bool = False
    ball_marks: bool = True
    gain: Range = Range(0.85, 1.15)
    vignette: Range = Range(0.0, 0.3)
    blur: Range = Range(0.3, 1.0)
    noise: Range = Range(1.0, 4.0)
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True)
class BulletRobot:
    """How the real robot of a PyBullet reality obeys motor commands (None: the
    model's limits); each number drawn per run."""

    max_speed: Range | None = None
    max_accel: Range | None = None
    slip: Range = Range(0.0, 0.0)
    slip_interval: float = 0.2
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True, eq=False)
class BulletReality(_BuiltinKind):
    """A reality made by another physics engine and renderer: PyBullet in 3D, its
    TinyRenderer with its own textures, light, blur and noise (``docs/reality.md``).

    ``dt`` is PyBullet's step; ``wall_thickness`` how thick the real walls are (they
    stand behind the scenario's wall line, away from the floor's centre); ``floor``,
    ``walls`` and ``obstacles`` the surfaces' contact parameters; ``objects`` every ball
    of reality.
    """

    dt: float
    camera: CameraOffset
    wall_thickness: float
    floor: BulletSurfaces
    walls: BulletSurfaces
    obstacles: BulletSurfaces
    look: BulletLook
    robot: BulletRobot
    objects: tuple[BulletObject, ...]
    source: Source = UNKNOWN
    kind: RealityKind = RealityKind.BULLET

    def object(self, name: str) -> BulletObject:
        """The true object called ``name``."""
        for o in self.objects:
            if o.name == name:
                return o
        raise KeyError(name)


@dataclass(frozen=True, slots=True)
class CameraReality(_BuiltinKind):
    """Frames from a camera: a device, a stream URL, or a video file played as a camera.

    Attributes
    ----------
    device : int or str
        A device index (``0``), a stream URL (``rtsp://...``) or a video file's path
        (resolved relative to the scenario).
    fps : float or None
        The frame rate the run assumes (None: the camera's stated rate).
    stall_s : float
        Seconds without a frame after which the camera has stalled and the run ends.
    """

    device: int | str
    fps: float | None
    stall_s: float
    source: Source = UNKNOWN
    kind: RealityKind = RealityKind.CAMERA


@dataclass(frozen=True, slots=True, eq=False)
class PluginReality:
    """A reality of a kind a plugin registered (:mod:`adapt.scenario.kinds`).

    Attributes
    ----------
    name : str
        ``reality.kind`` (the registered name).
    values : mapping
        Every parameter the kind declares, checked (defaults filled in); the ones
        the kind names as files are absolute paths.
    files : tuple of (str, Path)
        The files it names (parameter, path), for :meth:`Scenario.inputs`.
    kind : RealityKind
        What the schemas may assume of its frames (``video``: a camera's images, looks
        to be learned; ``synthetic``: rendered like the imagination).
    source : Source
        Where the section is; ``sources`` where each of its keys is.
    """

    name: str
    values: Mapping[str, Any]
    files: tuple[tuple[str, Path], ...] = ()
    kind: RealityKind = RealityKind.VIDEO
    source: Source = UNKNOWN
    sources: Mapping[str, Source] = field(default_factory=lambda: MappingProxyType({}))

    def get(self, key: str) -> Any:
        """The value of parameter ``key``."""
        return self.values[key]

    def where(self, key: str) -> Source:
        """The position of ``reality.<key>`` (the section's when it was not given)."""
        return self.sources.get(key, self.source)


Reality = SyntheticReality | VideoReality | BulletReality | CameraReality | PluginReality


@dataclass(frozen=True, slots=True)
class PluginRef:
    """One entry of the scenario's ``plugins`` list, imported.

    ``name`` as written (a module name or a ``.py`` file), ``module`` the imported
    module's name, ``file`` its file (None for a namespace package), ``origin`` the label
    of what it registered (``adapt schemas list``).
    """

    name: str
    module: str
    file: Path | None
    origin: str
    source: Source = UNKNOWN


# -- goals, rules, schemas ------------------------------------------------------------

class GoalKind(enum.Enum):
    """The goals the bundled rules act on (a goal may have any other name too)."""

    WATCH = "watch"          #: keep the imagination in step with what is seen
    INTERCEPT = "intercept"  #: meet the goal's ``object`` with the robot


@dataclass(frozen=True, slots=True, eq=False)
class Goal:
    """A goal placed in working memory (``^goal`` on the input-link).

    ``name`` is required; ``attributes`` are the other keys in file order,
    each a string or a number (``object`` names a world object).
    """

    name: str
    attributes: tuple[tuple[str, str | int | float], ...]
    source: Source = UNKNOWN
    attribute_sources: Mapping[str, Source] = field(default_factory=lambda: MappingProxyType({}))

    def get(self, key: str) -> str | int | float | None:
        """The value of an attribute, or None."""
        for k, v in self.attributes:
            if k == key:
                return v
        return None

    @property
    def kind(self) -> GoalKind | None:
        """The goal's kind when the bundled rules know its name, else None.

        Examples
        --------
        >>> Goal("intercept", (("object", "ball"),)).kind, Goal("dance", ()).kind
        (<GoalKind.INTERCEPT: 'intercept'>, None)
        """
        return next((k for k in GoalKind if k.value == self.name), None)


@dataclass(frozen=True, slots=True)
class RuleFile:
    """A rule file of the scenario, resolved relative to the YAML file."""

    path: Path
    source: Source = UNKNOWN


@dataclass(frozen=True, slots=True, eq=False)
class SchemaSettings:
    """Parameters for one schema type (``schemas.<type>``), checked against the
    type's declared parameters when the network is built."""

    type: str
    parameters: Mapping[str, Any]
    source: Source = UNKNOWN
    parameter_sources: Mapping[str, Source] = field(default_factory=lambda: MappingProxyType({}))


# -- run, predict, outputs -----------------------------------------------------------

@dataclass(frozen=True, slots=True)
class RunSettings:
    """How long and how fast the runner goes.

    ``fps`` is the frame rate of a synthetic reality (a video has its own);
    the run ends after ``duration`` seconds or ``max_frames`` frames,
    whichever is given (the default is 10 s), or when the video ends.
    ``decisions_per_frame`` decision cycles run between two frames.
    """

    fps: float = 30.0
    duration: float | None = None
    max_frames: int | None = None
    decisions_per_frame: int = 3
    source: Source = UNKNOWN

    @property
    def frames(self) -> int:
        """Frames the run will take at most at ``fps`` (a synthetic reality's rate)."""
        return self.frames_at(self.fps)

    def frames_at(self, fps: float) -> int:
        """Frames the run will take at most at ``fps`` frames per second (a video's own
        rate): ``max_frames``, or ``duration`` (10 s when not given) at ``fps``.  The one
        computation of a run's length; a source that ends earlier ends the run earlier.

        Examples
        --------
        >>> RunSettings().frames_at(15.0), RunSettings(max_frames=7).frames_at(15.0)
        (150, 7)
        """
        if self.max_frames is not None:
            return self.max_frames
        seconds = 10.0 if self.duration is None else self.duration
        return max(1, int(math.floor(seconds * fps + 1e-9)))


@dataclass(frozen=True, slots=True)
class PredictSettings:
    """Prediction: rollouts to each of ``horizons`` (seconds) every ``every``
    frames, as an ensemble of ``ensemble`` members over the parameter ranges;
    a horizon's confidence takes its residual at its word after ``evidence``
    scored predictions (0: from the first)."""

    horizons: tuple[float, ...] = (0.5, 1.0)
    every: int = 1
    ensemble: int = 8
    evidence: int = 3
    source: Source = UNKNOWN


class VideoCodec(enum.Enum):
    """How ``mmd.mp4`` is encoded."""

    #: MPEG-4 Part 2 (the default): fast to encode; browsers do not play it.
    MPEG4 = "mpeg4"
    #: VP9 in MP4: browsers (and the trace viewer) play it; 4 to 45 times slower to encode.
    VP9 = "vp9"


@dataclass(frozen=True, slots=True)
class OutputSettings:
    """Which outputs ``adapt run`` writes into its output folder (``video_codec``: how
    ``mmd.mp4`` is encoded)."""

    report: bool = True
    trace: bool = True
    video: bool = True
    figures: bool = True
    trace_level: int = 4
    video_codec: VideoCodec = VideoCodec.MPEG4
    source: Source = UNKNOWN
