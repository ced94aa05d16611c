"""The scene: frozen, validated value records that describe a world.

A :class:`SceneSpec` is what a scenario's ``world`` section becomes; the
:class:`~adapt.imagination.world.World` builds its physics from it and the
:class:`~adapt.imagination.render.Renderer` draws it.  Nothing here knows about
pymunk or pixels.

Geometry (see ``docs/conventions.md``): metres, the floor is ``z = 0``, ``z`` up.

* A :class:`Ball` is a sphere of ``radius`` resting on the floor (centre at
  ``z = radius``); ``position`` and ``velocity`` are its centre's ``(x, y)``.
* A :class:`Wall` is a vertical rectangle over the floor segment
  ``start -> end`` from ``z = 0`` to ``height``.  It has no thickness.
* An :class:`Obstacle` is a vertical prism over a convex ``polygon`` from
  ``z = 0`` to ``height``.
* The :class:`RobotSpec` is a vertical prism over a disc or a box, driven by
  velocity commands with a maximum speed and acceleration.

Colours are ``(r, g, b)`` with components in ``0..255``.  A texture is a path
to an image file or ``"builtin:NAME"`` for a texture bundled with adapt
(``brick``, ``gravel``, ``grass``, ``coffee``); ``tile`` is the size in metres
of one copy of the texture image.

Every record checks itself on construction and raises
:class:`~adapt.errors.ImaginationError` whose message starts with the name of
the offending field.

Examples
--------
>>> ball = Ball("ball", radius=0.1, mass=0.4, position=(1.0, 2.0), velocity=(0.5, 0.0))
>>> ball.position
(1.0, 2.0)
>>> Ball("b", radius=-0.1)
Traceback (most recent call last):
...
adapt.errors.ImaginationError: radius: expected a positive number of metres, got -0.1
>>> Obstacle("box", polygon=((0, 0), (1, 0), (1, 1), (0, 1)), height=0.5).area
1.0
"""

from __future__ import annotations

import copy
import enum
import math
from dataclasses import dataclass, field
from typing import Sequence

from adapt.errors import ImaginationError
from adapt.geometry import MAX_COORDINATE

__all__ = [
    "Color",
    "Vec2",
    "Floor",
    "Wall",
    "Obstacle",
    "Ball",
    "RobotSpec",
    "RobotShape",
    "SceneSpec",
    "BUILTIN_TEXTURES",
    "DEFAULT_DT",
    "MAX_COORDINATE",
    "MIN_SIZE",
    "MIN_MASS",
    "MAX_MASS",
    "MAX_SPEED",
    "MAX_ACCEL",
    "MAX_COEFFICIENT",
    "MIN_DT",
    "MAX_DT",
    "MAX_POLYGON_POINTS",
    "polygon_area",
    "check_convex_polygon",
]

Vec2 = tuple[float, float]
Color = tuple[int, int, int]

#: Names of the textures bundled in ``adapt/data/textures``.
BUILTIN_TEXTURES = ("brick", "gravel", "grass", "coffee")

#: The default physics time step in seconds.
DEFAULT_DT = 1.0 / 240.0

# Limits every record checks (``docs/imagination.md``): magnitudes beyond them
# are refused with an error naming the field, never passed on to become an
# overflow, a NaN or an allocation in the physics or the renderer.
# Coordinates and lengths: at most MAX_COORDINATE (10 km, from adapt.geometry).
#: Smallest size (radius, height, tile, robot size), metres.
MIN_SIZE = 1.0e-3
#: Mass range, kilograms.
MIN_MASS = 1.0e-6
MAX_MASS = 1.0e6
#: Largest speed (ball velocity, robot ``max_speed``), m/s.
MAX_SPEED = 1.0e3
#: Largest acceleration (gravity, robot ``max_accel``), m/s^2.
MAX_ACCEL = 1.0e4
#: Largest friction or rolling-resistance coefficient.
MAX_COEFFICIENT = 100.0
#: Range of the physics time step, seconds.
MIN_DT = 1.0e-6
MAX_DT = 1.0
#: Most corners of an obstacle's polygon.
MAX_POLYGON_POINTS = 256


def _finite(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ImaginationError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ImaginationError(f"{name}: expected a finite number, got {value!r}")
    return v


def _positive(name: str, value: float, unit: str, low: float = 0.0,
              high: float = MAX_COORDINATE) -> float:
    """A positive number in ``[low, high]`` (``low = 0`` means only ``> 0``)."""
    v = _finite(name, value)
    if v <= 0:
        raise ImaginationError(f"{name}: expected a positive number of {unit}, got {value!r}")
    if v < low:
        raise ImaginationError(f"{name}: expected at least {low:g} {unit}, got {value!r}")
    if v > high:
        raise ImaginationError(f"{name}: expected at most {high:g} {unit}, got {value!r}")
    return v


def _nonnegative(name: str, value: float, unit: str, high: float = MAX_COEFFICIENT) -> float:
    v = _finite(name, value)
    if v < 0:
        raise ImaginationError(
            f"{name}: expected a non-negative number of {unit}, got {value!r}"
        )
    if v > high:
        raise ImaginationError(f"{name}: expected at most {high:g} {unit}, got {value!r}")
    return v


def _unit_interval(name: str, value: float) -> float:
    v = _finite(name, value)
    if not 0.0 <= v <= 1.0:
        raise ImaginationError(f"{name}: expected a number from 0 to 1, got {value!r}")
    return v


def _vec2(name: str, value: Sequence[float], limit: float = MAX_COORDINATE,
          unit: str = "metres") -> Vec2:
    """``[x, y]`` with both components within ``+-limit``."""
    try:
        items = list(value)
    except TypeError:
        raise ImaginationError(f"{name}: expected [x, y], got {value!r}") from None
    if len(items) != 2:
        raise ImaginationError(f"{name}: expected [x, y], got {value!r}")
    x, y = _finite(name, items[0]), _finite(name, items[1])
    if max(abs(x), abs(y)) > limit:
        raise ImaginationError(
            f"{name}: expected values within +-{limit:g} {unit}, got {[x, y]}"
        )
    return (x, y)


def _velocity(name: str, value: Sequence[float]) -> Vec2:
    v = _vec2(name, value, math.inf, "m/s")
    if math.hypot(*v) > MAX_SPEED:
        raise ImaginationError(
            f"{name}: expected a speed of at most {MAX_SPEED:g} m/s, got {math.hypot(*v):g}"
        )
    return v


def _color(name: str, value: Sequence[int]) -> Color:
    try:
        items = list(value)
    except TypeError:
        raise ImaginationError(f"{name}: expected [r, g, b], got {value!r}") from None
    if len(items) != 3 or not all(
        isinstance(c, (int, float)) and 0 <= c <= 255 for c in items
    ):
        raise ImaginationError(f"{name}: expected [r, g, b] with values 0..255, got {value!r}")
    return (int(round(items[0])), int(round(items[1])), int(round(items[2])))


def _texture(name: str, value: str | None) -> str | None:
    if value is None:
        return None
    if not isinstance(value, str) or not value:
        raise ImaginationError(f"{name}: expected a texture path or builtin:NAME, got {value!r}")
    if value.startswith("builtin:") and value[len("builtin:"):] not in BUILTIN_TEXTURES:
        raise ImaginationError(
            f"{name}: unknown builtin texture {value!r}; expected one of "
            + ", ".join(f"builtin:{t}" for t in BUILTIN_TEXTURES)
        )
    return value


def _name(value: str) -> str:
    if not isinstance(value, str) or not value:
        raise ImaginationError(f"name: expected a non-empty string, got {value!r}")
    return value


def polygon_area(points: Sequence[Vec2]) -> float:
    """Signed area of a polygon (positive when counter-clockwise).

    Examples
    --------
    >>> polygon_area([(0, 0), (2, 0), (2, 1)])
    1.0
    >>> polygon_area([(0, 0), (2, 1), (2, 0)])
    -1.0
    """
    total = 0.0
    n = len(points)
    for i in range(n):
        x0, y0 = points[i]
        x1, y1 = points[(i + 1) % n]
        total += x0 * y1 - x1 * y0
    return total / 2.0


def check_convex_polygon(name: str, points: Sequence[Sequence[float]]) -> tuple[Vec2, ...]:
    """Validate a convex polygon; return it counter-clockwise.

    Raises
    ------
    ImaginationError
        If it has fewer than 3 points, repeated or collinear corners, zero area,
        or is not convex.

    Examples
    --------
    >>> check_convex_polygon("polygon", [(0, 0), (0, 1), (1, 0)])
    ((1.0, 0.0), (0.0, 1.0), (0.0, 0.0))
    >>> check_convex_polygon("polygon", [(0, 0), (2, 0), (1, 0.2), (2, 2), (0, 2)])
    Traceback (most recent call last):
    ...
    adapt.errors.ImaginationError: polygon: expected a convex polygon, but the corner at [1.0, 0.2] turns the other way
    """
    try:
        raw = list(points)
    except TypeError:
        raise ImaginationError(f"{name}: expected a list of [x, y] points, got {points!r}") from None
    if len(raw) > MAX_POLYGON_POINTS:
        raise ImaginationError(
            f"{name}: expected at most {MAX_POLYGON_POINTS} points, got {len(raw)}"
        )
    if len(raw) < 3:
        raise ImaginationError(
            f"{name}: expected a convex polygon with at least 3 points, got {len(raw)}"
        )
    pts = [_vec2(f"{name}[{i}]", p) for i, p in enumerate(raw)]
    area = polygon_area(pts)
    if abs(area) < 1e-12:
        raise ImaginationError(f"{name}: expected a polygon with a non-zero area")
    if area < 0:
        pts.reverse()
    n = len(pts)
    for i in range(n):
        ax, ay = pts[i - 1]
        bx, by = pts[i]
        cx, cy = pts[(i + 1) % n]
        cross = (bx - ax) * (cy - by) - (by - ay) * (cx - bx)
        scale = math.hypot(bx - ax, by - ay) * math.hypot(cx - bx, cy - by)
        if scale < 1e-18:
            raise ImaginationError(f"{name}: repeated point [{bx}, {by}]")
        if cross <= 1e-12 * scale:
            what = "is collinear with its neighbours" if abs(cross) <= 1e-12 * scale else "turns the other way"
            raise ImaginationError(
                f"{name}: expected a convex polygon, but the corner at [{bx}, {by}] {what}"
            )
    return tuple(pts)


@dataclass(frozen=True, slots=True)
class Floor:
    """The floor plane ``z = 0``.

    Parameters
    ----------
    texture : str or None
        Texture image (path or ``builtin:NAME``); ``None`` paints ``color``.
    tile : float
        Metres covered by one copy of the texture.
    color : (r, g, b)
        Colour when there is no texture.
    extent : (xmin, ymin, xmax, ymax) or None
        The floor's rectangle; ``None`` means it reaches the horizon.
    """

    texture: str | None = "builtin:gravel"
    tile: float = 1.0
    color: Color = (128, 128, 128)
    extent: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "texture", _texture("texture", self.texture))
        object.__setattr__(self, "tile", _positive("tile", self.tile, "metres", MIN_SIZE))
        object.__setattr__(self, "color", _color("color", self.color))
        if self.extent is not None:
            e = [_finite("extent", v) for v in self.extent]
            if len(e) != 4 or e[0] >= e[2] or e[1] >= e[3]:
                raise ImaginationError(
                    f"extent: expected [xmin, ymin, xmax, ymax] with min < max, got {self.extent!r}"
                )
            if max(abs(v) for v in e) > MAX_COORDINATE:
                raise ImaginationError(
                    f"extent: expected values within +-{MAX_COORDINATE:g} metres, got {e}"
                )
            object.__setattr__(self, "extent", tuple(e))


@dataclass(frozen=True, slots=True)
class Wall:
    """A vertical rectangle over the floor segment ``start -> end``."""

    name: str
    start: Vec2
    end: Vec2
    height: float = 1.0
    texture: str | None = None
    tile: float = 1.0
    color: Color = (180, 170, 160)
    restitution: float = 1.0
    friction: float = 0.5

    def __post_init__(self) -> None:
        _name(self.name)
        object.__setattr__(self, "start", _vec2("from", self.start))
        object.__setattr__(self, "end", _vec2("to", self.end))
        if math.dist(self.start, self.end) < 1e-9:
            raise ImaginationError(f"to: expected a point away from 'from' {list(self.start)}")
        object.__setattr__(self, "height", _positive("height", self.height, "metres", MIN_SIZE))
        object.__setattr__(self, "texture", _texture("texture", self.texture))
        object.__setattr__(self, "tile", _positive("tile", self.tile, "metres", MIN_SIZE))
        object.__setattr__(self, "color", _color("color", self.color))
        object.__setattr__(self, "restitution", _unit_interval("restitution", self.restitution))
        object.__setattr__(self, "friction", _nonnegative("friction", self.friction, "(coefficient)"))

    @property
    def length(self) -> float:
        """Length of the wall in metres."""
        return math.dist(self.start, self.end)


@dataclass(frozen=True, slots=True)
class Obstacle:
    """A static vertical prism over a convex polygon (stored counter-clockwise)."""

    name: str
    polygon: tuple[Vec2, ...]
    height: float = 0.5
    texture: str | None = None
    tile: float = 1.0
    color: Color = (60, 90, 160)
    restitution: float = 1.0
    friction: float = 0.5

    def __post_init__(self) -> None:
        _name(self.name)
        object.__setattr__(self, "polygon", check_convex_polygon("polygon", self.polygon))
        object.__setattr__(self, "height", _positive("height", self.height, "metres", MIN_SIZE))
        object.__setattr__(self, "texture", _texture("texture", self.texture))
        object.__setattr__(self, "tile", _positive("tile", self.tile, "metres", MIN_SIZE))
        object.__setattr__(self, "color", _color("color", self.color))
        object.__setattr__(self, "restitution", _unit_interval("restitution", self.restitution))
        object.__setattr__(self, "friction", _nonnegative("friction", self.friction, "(coefficient)"))

    @property
    def area(self) -> float:
        """Floor area of the prism in square metres."""
        return polygon_area(self.polygon)


@dataclass(frozen=True, slots=True)
class Ball:
    """A sphere rolling on the floor.

    ``rolling_resistance`` is the dimensionless coefficient ``c`` of a
    resisting force ``c m g`` against the motion (a ball rolling freely at
    speed ``v`` stops after ``v**2 / (2 c g)`` metres); ``drag`` (1/m) adds a
    speed-dependent one, ``drag m v**2`` (air, and a floor that gives more at
    speed).

    ``floor_friction`` says whether the ball has spin of its own.  ``None``
    (the default): it always rolls, its spin following its velocity at once,
    through a bounce too.  A coefficient ``mu``: it is a solid sphere that
    keeps its spin through a bounce but for what the surface's friction
    takes (the contact is at the height of its centre), and slides on the
    floor, with friction ``mu m g``, until spin and velocity agree (see
    :mod:`adapt.imagination.world`).
    """

    name: str
    radius: float = 0.1
    mass: float = 0.4
    restitution: float = 0.8
    friction: float = 0.3
    rolling_resistance: float = 0.0
    position: Vec2 = (0.0, 0.0)
    velocity: Vec2 = (0.0, 0.0)
    color: Color = (220, 60, 40)
    texture: str | None = None
    floor_friction: float | None = None
    drag: float = 0.0

    def __post_init__(self) -> None:
        _name(self.name)
        object.__setattr__(self, "radius", _positive("radius", self.radius, "metres", MIN_SIZE))
        object.__setattr__(self, "mass", _positive("mass", self.mass, "kilograms", MIN_MASS, MAX_MASS))
        object.__setattr__(self, "restitution", _unit_interval("restitution", self.restitution))
        object.__setattr__(self, "friction", _nonnegative("friction", self.friction, "(coefficient)"))
        object.__setattr__(
            self,
            "rolling_resistance",
            _nonnegative("rolling_resistance", self.rolling_resistance, "(coefficient)"),
        )
        object.__setattr__(self, "position", _vec2("position", self.position))
        object.__setattr__(self, "velocity", _velocity("velocity", self.velocity))
        object.__setattr__(self, "color", _color("color", self.color))
        object.__setattr__(self, "texture", _texture("texture", self.texture))
        if self.floor_friction is not None:
            object.__setattr__(self, "floor_friction", _nonnegative(
                "floor_friction", self.floor_friction, "(coefficient)"))
        object.__setattr__(self, "drag", _nonnegative("drag", self.drag, "1/m"))

    def with_parameters(self, **values: float | None) -> "Ball":
        """A copy with new physical parameters (``restitution``, ``friction``,
        ``rolling_resistance``, ``mass``, ``floor_friction``, ``drag``), each checked as on
        construction; cheaper than :func:`dataclasses.replace`, which checks every field.

        Examples
        --------
        >>> Ball("b").with_parameters(restitution=0.5, drag=0.1).restitution
        0.5
        >>> Ball("b").with_parameters(restitution=1.5)
        Traceback (most recent call last):
        ...
        adapt.errors.ImaginationError: restitution: expected a number from 0 to 1, got 1.5
        """
        out = copy.copy(self)
        for key, value in values.items():
            if key == "restitution":
                v: float | None = _unit_interval(key, value)  # type: ignore[arg-type]
            elif key in ("friction", "rolling_resistance"):
                v = _nonnegative(key, value, "(coefficient)")  # type: ignore[arg-type]
            elif key == "drag":
                v = _nonnegative(key, value, "1/m")  # type: ignore[arg-type]
            elif key == "mass":
                v = _positive(key, value, "kilograms", MIN_MASS, MAX_MASS)  # type: ignore[arg-type]
            elif key == "floor_friction":
                v = None if value is None else _nonnegative(key, value, "(coefficient)")
            else:
                raise ImaginationError(
                    f"cannot set {key!r} of a ball; expected restitution, friction, "
                    "rolling_resistance, mass, floor_friction or drag")
            object.__setattr__(out, key, v)
        return out


class RobotShape(enum.Enum):
    """The robot's body: a disc of its ``radius``, or a box of its ``size``."""

    DISC = "disc"
    BOX = "box"


@dataclass(frozen=True, slots=True)
class RobotSpec:
    """A robot driven by velocity commands.

    Its two radii are written here once: :attr:`outer_radius`, the disc its
    body fits in (where it fits on the floor, and the way round what is in its
    way), and :attr:`inner_radius`, the distance from its centre to its
    nearest side (how close it comes to what it touches).

    Parameters
    ----------
    shape : RobotShape
        A disc of ``radius`` or a box of ``size = (length, width)`` (length
        along its heading); the text ``"disc"`` or ``"box"`` is taken too.
    heading_deg : float
        Initial heading, degrees counter-clockwise from ``+x``.
    max_speed, max_accel : float
        Limits of the commanded velocity (m/s) and of the acceleration the
        drive can give (m/s^2).
    """

    name: str = "robot"
    shape: RobotShape = RobotShape.DISC
    radius: float = 0.25
    size: Vec2 = (0.5, 0.4)
    position: Vec2 = (0.0, 0.0)
    heading_deg: float = 0.0
    max_speed: float = 1.0
    max_accel: float = 2.0
    mass: float = 10.0
    height: float = 0.3
    color: Color = (40, 40, 40)

    def __post_init__(self) -> None:
        _name(self.name)
        if not isinstance(self.shape, RobotShape):
            try:
                object.__setattr__(self, "shape", RobotShape(self.shape))
            except ValueError:
                raise ImaginationError(f"shape: expected 'disc' or 'box', got {self.shape!r}") from None
        object.__setattr__(self, "radius", _positive("radius", self.radius, "metres", MIN_SIZE))
        size = _vec2("size", self.size)
        _positive("size", size[0], "metres", MIN_SIZE)
        _positive("size", size[1], "metres", MIN_SIZE)
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "position", _vec2("position", self.position))
        object.__setattr__(self, "heading_deg", _finite("heading_deg", self.heading_deg))
        object.__setattr__(self, "max_speed", _positive("max_speed", self.max_speed, "m/s", high=MAX_SPEED))
        object.__setattr__(self, "max_accel", _positive("max_accel", self.max_accel, "m/s^2", high=MAX_ACCEL))
        object.__setattr__(self, "mass", _positive("mass", self.mass, "kilograms", MIN_MASS, MAX_MASS))
        object.__setattr__(self, "height", _positive("height", self.height, "metres", MIN_SIZE))
        object.__setattr__(self, "color", _color("color", self.color))

    def outline(self) -> tuple[Vec2, ...]:
        """The footprint in the robot's own frame (``+x`` = heading), CCW.

        A disc is approximated by a 16-gon for drawing; the physics uses a
        true circle.

        Examples
        --------
        >>> RobotSpec(shape=RobotShape.BOX, size=(2.0, 1.0)).outline()
        ((-1.0, -0.5), (1.0, -0.5), (1.0, 0.5), (-1.0, 0.5))
        """
        if self.shape is RobotShape.BOX:
            hl, hw = self.size[0] / 2.0, self.size[1] / 2.0
            return ((-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw))
        n = 16
        return tuple(
            (self.radius * math.cos(2 * math.pi * k / n), self.radius * math.sin(2 * math.pi * k / n))
            for k in range(n)
        )

    @property
    def outer_radius(self) -> float:
        """The radius of the disc the body fits in: a disc's radius, half a box's diagonal.

        Examples
        --------
        >>> RobotSpec(radius=0.25).outer_radius, RobotSpec(shape=RobotShape.BOX, size=(0.6, 0.8)).outer_radius
        (0.25, 0.5)
        """
        if self.shape is RobotShape.DISC:
            return self.radius
        return math.hypot(self.size[0], self.size[1]) / 2.0

    @property
    def inner_radius(self) -> float:
        """The distance from the centre to the nearest side: a disc's radius, half a box's
        smaller side.

        Examples
        --------
        >>> RobotSpec(shape=RobotShape.BOX, size=(0.6, 0.8)).inner_radius
        0.3
        """
        return self.radius if self.shape is RobotShape.DISC else min(self.size) / 2.0


@dataclass(frozen=True, slots=True)
class SceneSpec:
    """Everything static about a world plus its initial state.

    Names must be unique across walls, obstacles, balls and the robot: they
    identify bodies in :class:`~adapt.imagination.world.WorldState` and surfaces
    in contact events.

    Examples
    --------
    >>> scene = SceneSpec(balls=(Ball("ball"),), walls=(Wall("north", (0, 2), (4, 2)),))
    >>> [w.name for w in scene.walls], scene.dt
    (['north'], 0.004166666666666667)
    """

    floor: Floor = field(default_factory=Floor)
    walls: tuple[Wall, ...] = ()
    obstacles: tuple[Obstacle, ...] = ()
    balls: tuple[Ball, ...] = ()
    robot: RobotSpec | None = None
    gravity: float = 9.81
    dt: float = DEFAULT_DT

    def __post_init__(self) -> None:
        object.__setattr__(self, "walls", tuple(self.walls))
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(self, "balls", tuple(self.balls))
        object.__setattr__(self, "gravity", _positive("gravity", self.gravity, "m/s^2", high=MAX_ACCEL))
        object.__setattr__(self, "dt", _positive("dt", self.dt, "seconds", MIN_DT, MAX_DT))
        seen: set[str] = set()
        names = [w.name for w in self.walls] + [o.name for o in self.obstacles]
        names += [b.name for b in self.balls]
        if self.robot is not None:
            names.append(self.robot.name)
        for n in names:
            if n in seen:
                raise ImaginationError(f"name: {n!r} is used twice; expected unique names")
            seen.add(n)

    def ball(self, name: str) -> Ball:
        """The ball called ``name``."""
        for b in self.balls:
            if b.name == name:
                return b
        raise ImaginationError(f"no ball called {name!r}; balls: {[b.name for b in self.balls]}")
