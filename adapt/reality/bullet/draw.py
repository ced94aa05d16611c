"""What a PyBullet reality draws for one run: every number from its range.

:func:`draw` turns a :class:`~adapt.scenario.BulletReality` into a
:class:`BulletDraw` from the run's seed.  Each part draws from its own named
child of a stream (:func:`child`), so adding an object, a wall or a key to a
scenario never changes what the other parts draw:

* ``reality.parameters``: the camera's offset (``camera``), each ball's
  coefficients (``object:<name>``), the surfaces' (``surfaces:<group>``), the
  robot's (``robot``) and the look (``look``, ``look:<surface>``);
* ``reality.events``: each ball's throw (``throw:<name>``); a position that would
  put the ball inside a wall or an obstacle is drawn again (the scenario reader
  has made sure that some position of the range is clear).

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> from adapt.seeds import Streams
>>> sc = loads_scenario('''
... camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
...          position: [0, -2.5, 2.3], look_at: [0, 0, 0]}
... world:
...   walls: [{from: [-1.5, 1.5], to: [1.5, 1.5], height: 0.5}]
...   objects: [{name: ball, radius: 0.1, create: when_seen}]
... reality:
...   kind: bullet
...   objects: [{name: ball, restitution: 0.8, throw: {x: 0, y: 0, speed: [1, 2]}}]
... ''')
>>> d = draw(sc, Streams(3))
>>> d.balls[0].restitution, 1 <= math.hypot(*d.balls[0].velocity) <= 2
(0.8, True)
>>> draw(sc, Streams(3)) == d, draw(sc, Streams(4)) == d
(True, False)
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from adapt.errors import RealityError
from adapt.reality.camera import draw_offset
from adapt.scenario import BulletReality, BulletSurfaces, Range, Scenario, TextureSource
from adapt.scenario.bullet import blocker
from adapt.seeds import Streams

__all__ = ["BulletDraw", "BallDraw", "SurfaceDraw", "SurfaceLook", "LookDraw", "draw", "child",
           "PATTERNS", "MAX_REDRAWS", "FLOOR_PHOTOS", "WALL_PHOTOS"]

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]

#: Procedural patterns a surface may wear (``adapt/reality/bullet/textures.py`` makes them).
PATTERNS = ("checker", "stripes", "blotches", "tiles", "speckle", "planks")
#: Bundled photographs a floor (or the ground round it) may wear, and a wall or an obstacle.
FLOOR_PHOTOS = ("gravel", "grass", "brick")
WALL_PHOTOS = ("brick", "gravel", "grass", "coffee")
#: Throw positions drawn before giving up (the reader checked that the range has clear ones).
MAX_REDRAWS = 1000


def child(stream: np.random.SeedSequence, name: str) -> np.random.Generator:
    """A generator of its own for the part ``name`` of a stream.

    Examples
    --------
    >>> s = Streams(1).sequence("reality.parameters")
    >>> child(s, "a").random() == child(s, "a").random(), child(s, "a").random() == child(s, "b").random()
    (True, False)
    """
    key = int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:8], "little")
    return np.random.default_rng(np.random.SeedSequence(
        entropy=stream.entropy, spawn_key=tuple(stream.spawn_key) + (key,)))


@dataclass(frozen=True, slots=True)
class BallDraw:
    """One ball's drawn values: PyBullet's coefficients and how it enters.

    ``appears`` is None for a ball present from the start at its world position and
    velocity, else the throw's time; ``height`` lifts its bottom above the floor when it
    appears; ``spin`` and ``side_spin`` its angular velocity then (see
    :class:`~adapt.scenario.BulletObject`).
    """

    name: str
    declared: bool
    radius: float
    mass: float
    restitution: float
    friction: float
    rolling_friction: float
    spinning_friction: float
    damping: float
    spin: float
    side_spin: float
    appears: float | None
    position: Vec2
    velocity: Vec2
    height: float

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}


@dataclass(frozen=True, slots=True)
class SurfaceDraw:
    """A group of surfaces' drawn contact parameters (PyBullet's)."""

    restitution: float
    friction: float
    rolling_friction: float
    spinning_friction: float

    def as_json(self) -> dict[str, float]:
        """A JSON-ready dict."""
        return {"restitution": self.restitution, "friction": self.friction,
                "rolling_friction": self.rolling_friction,
                "spinning_friction": self.spinning_friction}


@dataclass(frozen=True, slots=True)
class SurfaceLook:
    """What one surface wears.

    ``kind`` is ``texture`` (an image file or ``builtin:NAME`` in ``ref``),
    ``pattern`` (a procedural pattern named in ``ref``, made from ``seed`` in the
    colours ``color`` and ``color2``) or ``color`` (plain ``color``); ``tile`` is the
    metres one copy of the image covers and ``phase`` where its pattern starts.
    """

    surface: str
    kind: str
    ref: str | None
    color: tuple[int, int, int]
    color2: tuple[int, int, int]
    tile: float
    phase: Vec2
    seed: int

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {"surface": self.surface, "kind": self.kind, "ref": self.ref,
                "color": list(self.color), "tile": round(self.tile, 4)}


@dataclass(frozen=True, slots=True)
class LookDraw:
    """The drawn look: each surface's, the light and the sensor."""

    surfaces: tuple[SurfaceLook, ...]
    light_direction: Vec3
    light_color: Vec3
    ambient: float
    diffuse: float
    specular: float
    shadows: bool
    ball_marks: bool
    gain: float
    vignette: float
    blur: float
    noise: float
    background: tuple[tuple[int, int, int], tuple[int, int, int]]

    def surface(self, name: str) -> SurfaceLook:
        """The look of the surface called ``name``."""
        for s in self.surfaces:
            if s.surface == name:
                return s
        raise KeyError(name)

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {"surfaces": [s.as_json() for s in self.surfaces],
                "light_direction": [round(v, 4) for v in self.light_direction],
                "light_color": [round(v, 4) for v in self.light_color],
                "ambient": self.ambient, "diffuse": self.diffuse, "specular": self.specular,
                "shadows": self.shadows, "gain": self.gain, "vignette": self.vignette,
                "blur": self.blur, "noise": self.noise}


@dataclass(frozen=True, slots=True)
class BulletDraw:
    """Everything a PyBullet reality drew for one run."""

    seed: int
    balls: tuple[BallDraw, ...]
    floor: SurfaceDraw
    walls: SurfaceDraw
    obstacles: SurfaceDraw
    look: LookDraw
    camera_offset: Vec3
    camera_rotation_deg: Vec3
    robot_max_speed: float | None
    robot_max_accel: float | None
    robot_slip: float

    def ball(self, name: str) -> BallDraw:
        """The drawn values of the ball called ``name``."""
        for b in self.balls:
            if b.name == name:
                return b
        raise KeyError(name)

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {"balls": [b.as_json() for b in self.balls], "floor": self.floor.as_json(),
                "walls": self.walls.as_json(), "obstacles": self.obstacles.as_json(),
                "look": self.look.as_json()}


def _surfaces(group: BulletSurfaces, rng: np.random.Generator) -> SurfaceDraw:
    return SurfaceDraw(group.restitution.draw(rng), group.friction.draw(rng),
                       group.rolling_friction.draw(rng), group.spinning_friction.draw(rng))


def _color(rng: np.random.Generator, low: int = 40, high: int = 230) -> tuple[int, int, int]:
    c = rng.integers(low, high, 3)
    return (int(c[0]), int(c[1]), int(c[2]))


def _surface_look(name: str, texture: str | None, color: tuple[int, int, int], tile: float,
                  choice: TextureSource, scale: float, rng: np.random.Generator) -> SurfaceLook:
    """One surface's look: the scenario's own, a bundled photograph or a pattern."""
    kind = choice
    if choice is TextureSource.MIXED:
        kind = (TextureSource.SCENARIO, TextureSource.BUNDLED,
                TextureSource.PROCEDURAL)[int(rng.choice(3, p=(0.4, 0.3, 0.3)))]
    phase = (float(rng.uniform(0, 5)), float(rng.uniform(0, 5)))
    seed = int(rng.integers(0, 2**31 - 1))
    c2 = _color(rng)
    if kind is TextureSource.SCENARIO:
        if texture is None:
            return SurfaceLook(name, "color", None, color, c2, tile * scale, phase, seed)
        return SurfaceLook(name, "texture", texture, color, c2, tile * scale, phase, seed)
    if kind is TextureSource.BUNDLED:
        photos = FLOOR_PHOTOS if name in ("floor", "ground") else WALL_PHOTOS
        ref = f"builtin:{photos[int(rng.integers(len(photos)))]}"
        return SurfaceLook(name, "texture", ref, color, c2, float(rng.uniform(0.4, 1.2)) * scale,
                           phase, seed)
    pattern = PATTERNS[int(rng.integers(len(PATTERNS)))]
    return SurfaceLook(name, "pattern", pattern, _color(rng), c2,
                       float(rng.uniform(0.5, 1.5)) * scale, phase, seed)


def _look(scenario: Scenario, reality: BulletReality, params: np.random.SeedSequence) -> LookDraw:
    look = reality.look
    rng = child(params, "look")
    scale = look.texture_scale.draw(rng)
    scene = scenario.scene
    surfaces = [_surface_look("floor", scene.floor.texture, scene.floor.color, scene.floor.tile,
                              look.textures, scale, child(params, "look:floor"))]
    # the ground around the floor: never the floor's own look
    g = child(params, "look:ground")
    surfaces.append(_surface_look("ground", None, _color(g, 60, 200), 1.0,
                                  TextureSource.PROCEDURAL if look.textures is TextureSource.SCENARIO
                                  else look.textures, scale, g))
    for i, w in enumerate(scene.walls):
        surfaces.append(_surface_look(f"walls[{i}]", w.texture, w.color, w.tile, look.textures,
                                      scale, child(params, f"look:walls[{i}]:{w.name}")))
    for i, o in enumerate(scene.obstacles):
        surfaces.append(_surface_look(f"obstacles[{i}]", o.texture, o.color, o.tile,
                                      look.textures, scale,
                                      child(params, f"look:obstacles[{i}]:{o.name}")))
    elevation = math.radians(look.light_elevation_deg.draw(rng))
    azimuth = math.radians(look.light_azimuth_deg.draw(rng))
    warmth = look.light_warmth.draw(rng)
    direction = (math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                 math.sin(elevation))
    light = (min(1.0, 1.0 + warmth), 1.0 - 0.3 * abs(warmth), min(1.0, 1.0 - warmth))
    top, bottom = _color(rng, 120, 250), _color(rng, 60, 200)
    return LookDraw(tuple(surfaces), direction, light, look.ambient.draw(rng),
                    look.diffuse.draw(rng), look.specular.draw(rng), look.shadows, look.ball_marks,
                    look.gain.draw(rng), look.vignette.draw(rng), look.blur.draw(rng),
                    look.noise.draw(rng), (top, bottom))


def _throw_position(scenario: Scenario, reality: BulletReality, x: Range, y: Range,
                    radius: float, rng: np.random.Generator, name: str) -> Vec2:
    for _ in range(MAX_REDRAWS):
        p = (x.draw(rng), y.draw(rng))
        if blocker(scenario.scene, reality.wall_thickness, p, radius) is None:
            return p
    raise RealityError(f"{scenario.where(f'reality.objects.{name}.throw').location}: no throw "
                       f"position clear of the walls and obstacles found for {name!r} in "
                       f"{MAX_REDRAWS} draws; widen or move the throw's x and y")


def draw(scenario: Scenario, streams: Streams) -> BulletDraw:
    """Draw a PyBullet reality's parameters for the run of ``streams`` (see the module
    docstring)."""
    reality = scenario.reality
    assert isinstance(reality, BulletReality)
    params = streams.sequence("reality.parameters")
    events = streams.sequence("reality.events")
    balls = []
    for o in reality.objects:
        rng = child(params, f"object:{o.name}")
        mass, restitution, friction, rolling, spinning, damping, spin, side = (
            r.draw(rng) for r in (o.mass, o.restitution, o.friction, o.rolling_friction,
                                  o.spinning_friction, o.damping, o.spin, o.side_spin))
        appears: float | None = None
        position, velocity, height = o.ball.position, o.ball.velocity, 0.0
        if o.throw is not None:
            ev = child(events, f"throw:{o.name}")
            th = o.throw
            appears = th.time.draw(ev)
            position = _throw_position(scenario, reality, th.x, th.y, o.ball.radius, ev, o.name)
            speed, heading = th.speed.draw(ev), math.radians(th.heading_deg.draw(ev))
            velocity = (speed * math.cos(heading), speed * math.sin(heading))
            height = th.height.draw(ev)
        balls.append(BallDraw(o.name, o.declared, o.ball.radius, mass, restitution, friction,
                              rolling, spinning, damping, spin, side, appears,
                              (float(position[0]), float(position[1])),
                              (float(velocity[0]), float(velocity[1])), height))
    floor = _surfaces(reality.floor, child(params, "surfaces:floor"))
    walls = _surfaces(reality.walls, child(params, "surfaces:walls"))
    obstacles = _surfaces(reality.obstacles, child(params, "surfaces:obstacles"))
    offset, rotation = draw_offset(reality.camera, child(params, "camera"))
    robot = scenario.scene.robot
    rr = child(params, "robot")
    truth = reality.robot
    top_speed: float | None = None
    top_accel: float | None = None
    if robot is not None:
        top_speed = truth.max_speed.draw(rr) if truth.max_speed is not None else robot.max_speed
        top_accel = truth.max_accel.draw(rr) if truth.max_accel is not None else robot.max_accel
    slip = truth.slip.draw(rr) if robot is not None else 0.0
    return BulletDraw(streams.seed, tuple(balls), floor, walls, obstacles,
                      _look(scenario, reality, params), offset, rotation, top_speed, top_accel,
                      slip)
