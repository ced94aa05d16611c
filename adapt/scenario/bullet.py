"""Reading a ``reality`` section of ``kind: bullet``: a reality on PyBullet.

Every number of it may be a range ``[low, high]`` that the reality draws once per
run from the run's seed; the defaults are wide ranges (``docs/scenario.md`` and
``docs/reality.md`` list every key).  Besides the checks every value gets, a
PyBullet reality refuses, at the YAML position of the value:

* a camera inside a wall (as thick as ``wall_thickness``, standing behind the
  wall's line), inside an obstacle, inside the robot's body (a camera on the
  robot), or not above the floor;
* a throw whose every position puts the ball inside a wall or an obstacle (a
  position drawn there is drawn again; one that is always there is an error).

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> text = '''
... camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
...          position: [0, -2.5, 2.3], look_at: [0, 0, 0]}
... world:
...   walls: [{from: [-1.5, -1.5], to: [1.5, -1.5], height: 0.12}]
...   objects: [{name: ball, radius: 0.1, create: when_seen}]
... reality:
...   kind: bullet
...   objects: [{name: ball, throw: {x: [-1, 1], y: 0, speed: 2}}]
... '''
>>> r = loads_scenario(text).reality
>>> r.kind.value, r.object("ball").restitution, r.walls.restitution.low
('bullet', Range(low=0.7, high=0.9), 0.75)
>>> loads_scenario(text.replace("0, -2.5, 2.3", "0, -1.55, 0.1"))
Traceback (most recent call last):
...
adapt.errors.ScenarioError: <string>:3:20: camera.position: the camera at [0, -1.55, 0.1] is inside the wall 'wall0' (world.walls[0]: 0.12 m high, its real body 0.1 m thick behind its line); expected a camera clear of every wall
...
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Callable, Sequence

import numpy as np
import yaml

from adapt.geometry import Camera
from adapt.imagination.scene import Ball, Obstacle, RobotShape, RobotSpec, SceneSpec, Wall
from adapt.scenario.bounds import bound_of, bullet_bound
from adapt.scenario.nodes import Node, join
from adapt.scenario.records import (
    BulletLook,
    BulletObject,
    BulletReality,
    BulletRobot,
    BulletSurfaces,
    CameraMount,
    CameraOffset,
    Creation,
    Mount,
    ObjectModel,
    Range,
    TextureSource,
    Throw,
)
from adapt.scenario.source import Source
from adapt.scenario.world import WorldReader

__all__ = ["BulletReader", "BULLET_KEYS", "BULLET_SURFACE_KEYS", "BULLET_OBJECT_KEYS",
           "BULLET_THROW_KEYS", "LOOK_KEYS", "BULLET_ROBOT_KEYS", "DEFAULT_BULLET_DT",
           "DEFAULT_WALL_THICKNESS", "SURFACE_DEFAULTS", "OBJECT_DEFAULTS", "wall_body",
           "inside_wall", "inside_obstacle", "arena_centre"]

BULLET_KEYS = ("kind", "dt", "camera_offset", "camera_offset_deg", "wall_thickness", "floor",
               "walls", "obstacles", "look", "robot", "objects")
BULLET_SURFACE_KEYS = ("restitution", "friction", "rolling_friction", "spinning_friction")
BULLET_OBJECT_KEYS = ("name", "radius", "color", "texture", "mass", "restitution", "friction",
                      "rolling_friction", "spinning_friction", "damping", "spin", "side_spin",
                      "throw")
BULLET_THROW_KEYS = ("t", "x", "y", "speed", "heading_deg", "height")
LOOK_KEYS = ("textures", "texture_scale", "light_elevation_deg", "light_azimuth_deg",
             "light_warmth", "ambient", "diffuse", "specular", "shadows", "ball_marks", "gain",
             "vignette", "blur", "noise")
BULLET_ROBOT_KEYS = ("max_speed", "max_accel", "slip", "slip_interval")

#: PyBullet's step when the scenario gives none (restitution needs fine steps).
DEFAULT_BULLET_DT = 1.0 / 960.0
#: How thick the real walls are by default, metres.
DEFAULT_WALL_THICKNESS = 0.1

#: Default contact parameters of the floor, the walls and the obstacles (PyBullet's).
SURFACE_DEFAULTS: dict[str, dict[str, Range]] = {
    "floor": {"restitution": Range(0.3, 0.6), "friction": Range(0.5, 1.0),
              "rolling_friction": Range.fixed(0.0), "spinning_friction": Range.fixed(0.0)},
    "walls": {"restitution": Range(0.75, 0.95), "friction": Range(0.3, 0.7),
              "rolling_friction": Range.fixed(0.0), "spinning_friction": Range.fixed(0.0)},
    "obstacles": {"restitution": Range(0.6, 0.95), "friction": Range(0.3, 0.7),
                  "rolling_friction": Range.fixed(0.0), "spinning_friction": Range.fixed(0.0)},
}

#: Default parameters of a real ball (PyBullet's; the mass is the world's).
OBJECT_DEFAULTS: dict[str, Range] = {
    "restitution": Range(0.7, 0.9), "friction": Range(0.3, 0.7),
    "rolling_friction": Range(0.001, 0.005), "spinning_friction": Range(0.0005, 0.005),
    "damping": Range(0.0, 0.03), "spin": Range(0.5, 1.0), "side_spin": Range(-6.0, 6.0),
}

#: The look's numbers (each a number or a range; bounds in adapt/scenario/bounds.py).
_LOOK_NUMBERS = ("texture_scale", "light_elevation_deg", "light_azimuth_deg", "light_warmth",
                 "ambient", "diffuse", "specular", "gain", "vignette", "blur", "noise")
#: A reality object's parameters (each a number or a range).
_OBJECT_NUMBERS = ("mass", "restitution", "friction", "rolling_friction", "spinning_friction",
                   "damping", "spin", "side_spin")

Vec2 = tuple[float, float]


# -- the real bodies' geometry (the reader's checks and the reality share it) ---------------

def arena_centre(scene: SceneSpec) -> Vec2:
    """The point the walls' thickness turns away from: the floor's centre when it has an
    extent, else the mean of the walls' midpoints (the origin without walls)."""
    if scene.floor.extent is not None:
        x0, y0, x1, y1 = scene.floor.extent
        return (0.5 * (x0 + x1), 0.5 * (y0 + y1))
    if not scene.walls:
        return (0.0, 0.0)
    mids = [(0.5 * (w.start[0] + w.end[0]), 0.5 * (w.start[1] + w.end[1])) for w in scene.walls]
    return (sum(m[0] for m in mids) / len(mids), sum(m[1] for m in mids) / len(mids))


def wall_body(wall: Wall, thickness: float, centre: Sequence[float]) -> tuple[Vec2, ...]:
    """The floor rectangle of a real wall: its line and the line ``thickness`` behind it
    (away from ``centre``), counter-clockwise.

    Examples
    --------
    >>> from adapt.imagination.scene import Wall
    >>> wall_body(Wall("n", (-1.0, 2.0), (1.0, 2.0)), 0.1, (0.0, 0.0))
    ((-1.0, 2.0), (1.0, 2.0), (1.0, 2.1), (-1.0, 2.1))
    """
    (ax, ay), (bx, by) = wall.start, wall.end
    length = math.hypot(bx - ax, by - ay)
    nx, ny = (by - ay) / length, -(bx - ax) / length
    mx, my = 0.5 * (ax + bx), 0.5 * (ay + by)
    if nx * (centre[0] - mx) + ny * (centre[1] - my) > 0:
        nx, ny = -nx, -ny
    a2 = (ax + thickness * nx, ay + thickness * ny)
    b2 = (bx + thickness * nx, by + thickness * ny)
    corners = [(ax, ay), (bx, by), b2, a2]
    area = sum(corners[i][0] * corners[(i + 1) % 4][1] - corners[(i + 1) % 4][0] * corners[i][1]
               for i in range(4))
    if area < 0:
        corners.reverse()
        corners = corners[-1:] + corners[:-1]
    return tuple((float(x), float(y)) for x, y in corners)


def _inside_polygon(p: Sequence[float], polygon: Sequence[Vec2], margin: float = 0.0) -> bool:
    """Whether ``p`` lies inside a counter-clockwise convex polygon grown by ``margin``."""
    n = len(polygon)
    for i in range(n):
        ax, ay = polygon[i]
        bx, by = polygon[(i + 1) % n]
        length = math.hypot(bx - ax, by - ay)
        # signed distance to the edge's line, positive inside
        if ((bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax)) / length < -margin:
            return False
    return True


def inside_wall(scene: SceneSpec, thickness: float, point: Sequence[float],
                margin: float = 0.0) -> int | None:
    """Index of the first real wall whose body holds ``point`` (``(x, y)`` or ``(x, y,
    z)``; with ``z`` the wall's height counts), grown by ``margin`` metres, or None."""
    centre = arena_centre(scene)
    for i, wall in enumerate(scene.walls):
        if len(point) > 2 and not point[2] < wall.height + margin:
            continue
        if _inside_polygon(point, wall_body(wall, thickness, centre), margin):
            return i
    return None


def inside_obstacle(obstacles: Sequence[Obstacle], point: Sequence[float],
                    margin: float = 0.0) -> int | None:
    """Index of the first obstacle whose prism holds ``point`` (with its height when
    ``point`` has a ``z``), grown by ``margin`` metres, or None."""
    for i, o in enumerate(obstacles):
        if len(point) > 2 and not point[2] < o.height + margin:
            continue
        if _inside_polygon(point, o.polygon, margin):
            return i
    return None


class BulletReader(WorldReader):
    """The ``reality`` section of ``kind: bullet`` (on top of the world reader)."""

    def bullet(self, node: Node, path: str, models: tuple[ObjectModel, ...], scene: SceneSpec,
               camera: tuple[Camera, CameraMount] | None) -> BulletReality:
        """Read a PyBullet reality and check its geometry against ``scene``."""
        items = self.mapping(node, path)
        self.check_keys(items, BULLET_KEYS, path)
        src = self.source(node, path)
        dt = DEFAULT_BULLET_DT
        if "dt" in items:  # restitution needs fine steps: at most 0.01 s
            dt = self.bullet_number(items["dt"][1], join(path, "dt"))
        thickness = DEFAULT_WALL_THICKNESS
        if "wall_thickness" in items:
            thickness = self.bullet_number(items["wall_thickness"][1], join(path, "wall_thickness"))
        offset = self.camera_offset(items, path)
        surfaces = {}
        for key in ("floor", "walls", "obstacles"):
            surfaces[key] = self.surfaces(items[key][1] if key in items else None, join(path, key),
                                          SURFACE_DEFAULTS[key])
        look = self.look(items["look"][1], join(path, "look")) if "look" in items else \
            BulletLook(source=src)
        robot = BulletRobot(source=src)
        if "robot" in items:
            if scene.robot is None:
                raise self.error(items["robot"][0], join(path, "robot"),
                                 "the world has no robot for reality.robot to describe")
            robot = self.bullet_robot(items["robot"][1], join(path, "robot"))
        objects = self.reality_objects(
            items["objects"][1] if "objects" in items else None, join(path, "objects"), models,
            lambda n, p, by_name: self.bullet_object(n, p, by_name, scene, thickness),
            lambda m: self._bullet_from_model(m, None, {}, src))
        reality = BulletReality(dt, offset, thickness, surfaces["floor"], surfaces["walls"],
                                surfaces["obstacles"], look, robot, objects, src)
        if camera is not None:
            self._check_camera(camera[0], camera[1], scene, thickness)
        return reality

    # -- parts ---------------------------------------------------------------------------

    def bullet_number(self, node: Node, path: str) -> float:
        """A number within its bound in a PyBullet reality (:func:`~adapt.scenario.bounds.bullet_bound`)."""
        return self.number(node, path, bullet_bound(path))

    def bullet_range(self, node: Node, path: str) -> Range:
        """A number or ``[low, high]``, each within its bound in a PyBullet reality."""
        return self.range(node, path, bullet_bound(path))

    def camera_offset(self, items: dict[str, tuple[Node, Node]], path: str) -> CameraOffset:
        """``camera_offset`` and ``camera_offset_deg`` of a synthetic or PyBullet reality."""
        kw: dict[str, Any] = {"source": self.source(None, path)}
        for key, field, rand in (("camera_offset", "position", "random_position"),
                                 ("camera_offset_deg", "rotation_deg", "random_rotation")):
            if key not in items:
                continue
            knode, vnode = items[key]
            p = join(path, key)
            if isinstance(vnode, yaml.SequenceNode):
                kw[field] = self.vector(vnode, p, 3)
            else:  # a magnitude in a direction drawn from the seed
                kw[rand] = self.number(vnode, p, replace(bound_of(p), low=0.0))
            kw["source"] = self.source(knode, p)
        return CameraOffset(**kw)

    def surfaces(self, node: Node | None, path: str, defaults: dict[str, Range]) -> BulletSurfaces:
        """``floor``, ``walls`` or ``obstacles``: contact parameters, each a number or a range."""
        values = dict(defaults)
        src = self.source(node, path)
        if node is not None:
            spec: dict[str, Callable[[Node, str], Any]] = {
                key: self.bullet_range for key in BULLET_SURFACE_KEYS}
            values.update(self.fields(node, path, spec))
        return BulletSurfaces(values["restitution"], values["friction"],
                              values["rolling_friction"], values["spinning_friction"], src)

    def look(self, node: Node, path: str) -> BulletLook:
        """``look``: textures, light and the sensor."""
        spec: dict[str, Callable[[Node, str], Any]] = {
            "textures": lambda n, p: TextureSource(self.choice(n, p, [t.value for t in TextureSource])),
            "shadows": self.boolean,
            "ball_marks": self.boolean,
        }
        for key in _LOOK_NUMBERS:
            spec[key] = self.bullet_range
        kw = self.fields(node, path, {k: spec[k] for k in LOOK_KEYS})
        return BulletLook(**kw, source=self.source(node, path))

    def bullet_robot(self, node: Node, path: str) -> BulletRobot:
        """``robot``: the real robot's limits and wheel slip."""
        spec: dict[str, Callable[[Node, str], Any]] = {
            "max_speed": self.bullet_range,
            "max_accel": self.bullet_range,
            "slip": self.bullet_range,
            "slip_interval": self.bullet_number,
        }
        kw = self.fields(node, path, spec)
        return BulletRobot(**kw, source=self.source(node, path))

    def bullet_throw(self, node: Node, path: str) -> Throw:
        """``throw``: when, where and how fast a ball enters, and from how high."""
        spec: dict[str, Callable[[Node, str], Any]] = {
            key: self.bullet_range for key in BULLET_THROW_KEYS}
        kw = self.fields(node, path, spec, required=("x", "y"))
        return Throw(kw.get("t", Range.fixed(0.0)), kw["x"], kw["y"],
                     kw.get("speed", Range.fixed(0.0)), kw.get("heading_deg", Range.fixed(0.0)),
                     self.source(node, path), kw.get("height", Range.fixed(0.0)))

    def bullet_object(self, node: Node, path: str, models: dict[str, ObjectModel],
                      scene: SceneSpec, thickness: float) -> BulletObject:
        """One ``reality.objects[i]``: a world object's truth, or a ball of reality only."""
        items, name, model, look = self.reality_object(node, path, BULLET_OBJECT_KEYS, models,
                                                       self.bullet_number)
        params: dict[str, Range] = {}
        for key in _OBJECT_NUMBERS:
            if key in items:
                params[key] = self.bullet_range(items[key][1], join(path, key))
        throw = None
        if "throw" in items:
            throw = self.bullet_throw(items["throw"][1], join(path, "throw"))
        src = self.source(node, path)
        if model is not None:
            if model.create is Creation.WHEN_SEEN and throw is None:
                raise self.error(node, path, f"object {name!r} is created when seen: give a throw "
                                 "(when and how it appears)")
            obj = self._bullet_from_model(model, throw, params, src, look)
        else:
            if "radius" not in look:
                raise self.error(node, path, f"{name!r} is not a world object, so it exists in "
                                 "reality only: give its radius (and a colour)")
            ball = self.build(Ball, node, path, {"name": name, **look})
            obj = self._bullet_object(ball, False, throw, params, src)
        if throw is not None:
            self._check_throw(obj, items["throw"][1], join(path, "throw"), scene, thickness)
        return obj

    def _bullet_from_model(self, model: ObjectModel, throw: Throw | None,
                           params: dict[str, Range], source: Source,
                           look: dict[str, Any] | None = None) -> BulletObject:
        ball = model.ball
        if look:
            ball = replace(ball, **look)
        return self._bullet_object(ball, True, throw, params, source)

    def _bullet_object(self, ball: Ball, declared: bool, throw: Throw | None,
                       params: dict[str, Range], source: Source) -> BulletObject:
        v = {**OBJECT_DEFAULTS, "mass": Range.fixed(ball.mass), **params}
        return BulletObject(ball.name, ball, declared, v["mass"], v["restitution"], v["friction"],
                            v["rolling_friction"], v["spinning_friction"], v["damping"], v["spin"],
                            v["side_spin"], throw, source)

    # -- geometry ------------------------------------------------------------------------

    def _check_throw(self, obj: BulletObject, node: Node, path: str, scene: SceneSpec,
                     thickness: float) -> None:
        """Refuse a throw whose every position (on a grid over its ranges) puts the ball
        inside a wall or an obstacle."""
        assert obj.throw is not None
        th = obj.throw
        r = obj.ball.radius
        xs = np.linspace(th.x.low, th.x.high, 1 if th.x.is_fixed else 9)
        ys = np.linspace(th.y.low, th.y.high, 1 if th.y.is_fixed else 9)
        blocked = None
        for x in xs:
            for y in ys:
                what = blocker(scene, thickness, (float(x), float(y)), r)
                if what is None:
                    return
                blocked = blocked or (what, float(x), float(y))
        assert blocked is not None
        (kind, i), x, y = blocked
        body = scene.walls[i] if kind == "walls" else scene.obstacles[i]
        every = "every position of the throw puts" if not (th.x.is_fixed and th.y.is_fixed) \
            else "the throw puts"
        raise self.error(node, path, f"{every} the ball {obj.name!r} (radius {r:g} m) inside "
                         f"{'the wall' if kind == 'walls' else 'the obstacle'} {body.name!r} "
                         f"(world.{kind}[{i}]), e.g. at [{x:g}, {y:g}]; expected a ball clear of "
                         "every wall and obstacle")

    def _check_camera(self, camera: Camera, mount: CameraMount, scene: SceneSpec,
                      thickness: float) -> None:
        where = mount.source
        at = self.sources.get("camera.position", where)
        p = (float(camera.position[0]), float(camera.position[1]), float(camera.position[2]))
        text = f"[{p[0]:g}, {p[1]:g}, {p[2]:g}]"
        if mount.kind is Mount.ROBOT:
            text += " (on the robot at its start)"
        i = inside_wall(scene, thickness, p)
        if i is not None:
            w = scene.walls[i]
            raise at.error(f"the camera at {text} is inside the wall {w.name!r} (world.walls[{i}]: "
                           f"{w.height:g} m high, its real body {thickness:g} m thick behind its "
                           "line); expected a camera clear of every wall", path="camera.position")
        i = inside_obstacle(scene.obstacles, p)
        if i is not None:
            o = scene.obstacles[i]
            raise at.error(f"the camera at {text} is inside the obstacle {o.name!r} "
                           f"(world.obstacles[{i}], {o.height:g} m high); expected a camera clear "
                           "of every obstacle", path="camera.position")
        robot = scene.robot
        if mount.kind is Mount.ROBOT and robot is not None and _in_robot(robot, mount.position):
            raise at.error(f"the camera at {list(mount.position)} in the robot's frame is inside "
                           f"the robot's body ({robot.height:g} m high); expected it above the "
                           "robot or outside its footprint", path="camera.position")


def blocker(scene: SceneSpec, thickness: float, position: Sequence[float],
            radius: float) -> tuple[str, int] | None:
    """``("walls", i)`` or ``("obstacles", i)`` for the first body a ball of ``radius`` at
    ``position`` would overlap, or None when it is clear of all."""
    i = inside_wall(scene, thickness, position, radius)
    if i is not None:
        return ("walls", i)
    i = inside_obstacle(scene.obstacles, position, radius)
    if i is not None:
        return ("obstacles", i)
    return None


def _in_robot(robot: RobotSpec, p: Sequence[float]) -> bool:
    """Whether a point in the robot's frame is inside its body."""
    if not 0 <= p[2] < robot.height:
        return False
    if robot.shape is RobotShape.DISC:
        return math.hypot(p[0], p[1]) < robot.radius
    length, width = robot.size
    return abs(p[0]) < length / 2 and abs(p[1]) < width / 2
