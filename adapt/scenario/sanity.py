"""What a scenario's values must be together: places, speeds against the physics step, the
work of a prediction, the real textures' tiles, the true camera.

Each value has its own bound (:mod:`adapt.scenario.bounds`); :func:`check_together`
checks the rules that tie values to one another, once the scenario is read, and
reports a broken one at the position of the value it names:

* **places** -- the robot and every object start on the floor (inside its
  ``extent`` when it has one) and clear of every wall and obstacle (touching is
  allowed): the robot's disc or box at ``world.robot.position``, each ball at
  its ``position``, each thrown object over the whole box its ``throw.x`` and
  ``throw.y`` ranges span;
* **speeds** -- a body moves at most :data:`TRAVEL_RADII` of its radii in one
  physics step (beyond that the physics cannot keep it from passing through a
  wall): a ball's stated speed (``velocity`` or ``throw.speed``, and the drag a
  real ball feels at that speed) and the robot's ``max_speed``, at ``world.dt``
  for the imagination and ``reality.dt`` for a synthetic reality;
* **prediction** -- an ensemble of ``predict.ensemble`` members to the longest
  horizon at ``world.dt`` runs at most
  :data:`~adapt.imagination.predict.MAX_ENSEMBLE_STEPS` physics steps;
* **real textures** -- every tile times ``reality.appearance.texture_scale`` is
  a tile the imagination accepts;
* **the true camera** -- ``camera.position`` plus ``reality.camera_offset`` is
  within the world's coordinates.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Sequence

from adapt.geometry import MAX_COORDINATE, segment_distance
from adapt.imagination.predict import MAX_ENSEMBLE_STEPS
from adapt.imagination.scene import MIN_SIZE, RobotShape, RobotSpec, SceneSpec, Vec2
from adapt.imagination.world import MAX_SUBSTEPS, TRAVEL_FRACTION
from adapt.scenario.records import Creation, Mount, SyntheticReality

if TYPE_CHECKING:  # pragma: no cover
    from adapt.scenario import Scenario

__all__ = ["check_together", "TRAVEL_RADII", "shape_distance"]

#: The most radii a body may move in one physics step (the world's sub-steps resolve that).
TRAVEL_RADII = MAX_SUBSTEPS * TRAVEL_FRACTION

#: How far a body may reach into a wall or an obstacle and still count as touching it, metres.
_TOUCH = 1e-9


def check_together(scenario: "Scenario") -> None:
    """Check the rules of the module docstring.

    Raises
    ------
    ScenarioError
        At the position of the value a broken rule names.
    """
    _check_places(scenario)
    _check_speeds(scenario)
    _check_prediction(scenario)
    _check_textures(scenario)
    _check_camera(scenario)


# -- places --------------------------------------------------------------------------------

def _edges(points: Sequence[Vec2]) -> list[tuple[Vec2, Vec2]]:
    n = len(points)
    if n <= 2:
        return [(points[0], points[-1])]
    return [(points[i], points[(i + 1) % n]) for i in range(n)]


def _side(o: Vec2, a: Vec2, b: Vec2) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _inside(p: Vec2, polygon: Sequence[Vec2]) -> bool:
    """Inside (or on) a convex polygon of either winding."""
    if len(polygon) < 3:
        return False
    sides = [_side(a, b, p) for a, b in _edges(polygon)]
    return all(s >= 0 for s in sides) or all(s <= 0 for s in sides)


def shape_distance(a: Sequence[Vec2], b: Sequence[Vec2]) -> float:
    """The distance between two convex shapes, each a point, a segment or a convex polygon
    (0 when they overlap).

    Examples
    --------
    >>> square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    >>> shape_distance([(2.0, 0.5)], square), shape_distance([(0.5, 0.5)], square)
    (1.0, 0.0)
    >>> shape_distance([(-1.0, 2.0), (2.0, 2.0)], square)
    1.0
    """
    if any(_inside(p, b) for p in a) or any(_inside(p, a) for p in b):
        return 0.0
    return min(segment_distance(p, q, c, d) for p, q in _edges(a) for c, d in _edges(b))


def _robot_shape(robot: RobotSpec) -> tuple[list[Vec2], float]:
    """The robot's footprint at its start: a point and its radius, or its box's corners."""
    x, y = robot.position
    if robot.shape is RobotShape.DISC:
        return [(x, y)], robot.radius
    c, s = math.cos(math.radians(robot.heading_deg)), math.sin(math.radians(robot.heading_deg))
    hl, hw = robot.size[0] / 2, robot.size[1] / 2
    return [(x + c * u - s * v, y + s * u + c * v)
            for u, v in ((hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw))], 0.0


def _clash(scene: SceneSpec, shape: Sequence[Vec2], radius: float) -> str | None:
    """What the shape grown by ``radius`` overlaps or leaves (None: it is in place)."""
    limit = radius - _TOUCH
    for i, wall in enumerate(scene.walls):
        gap = shape_distance(shape, [wall.start, wall.end])
        if gap < limit or (radius == 0 and gap == 0):  # a box: overlapping is meeting
            return f"it crosses the wall {wall.name!r} (world.walls[{i}])"
    for i, ob in enumerate(scene.obstacles):
        gap = shape_distance(shape, ob.polygon)
        if gap < limit or (radius == 0 and gap == 0):
            return f"it overlaps the obstacle {ob.name!r} (world.obstacles[{i}])"
    extent = scene.floor.extent
    if extent is not None:
        x0, y0, x1, y1 = extent
        for x, y in shape:
            if not (x0 <= x <= x1 and y0 <= y <= y1):
                return (f"[{x:g}, {y:g}] is off the floor (world.floor.extent "
                        f"[{x0:g}, {y0:g}, {x1:g}, {y1:g}])")
    return None


def _check_places(sc: "Scenario") -> None:
    scene = sc.scene
    robot = scene.robot
    if robot is not None:
        shape, radius = _robot_shape(robot)
        clash = _clash(scene, shape, radius)
        if clash is not None:
            where = sc.where("world.robot.position")
            x, y = robot.position
            raise where.error(f"the robot at [{x:g}, {y:g}] does not fit where it starts: "
                              f"{clash}; expected a place on the floor clear of every wall "
                              "and obstacle", path="world.robot.position")
    for i, m in enumerate(sc.objects):
        if m.create is Creation.AT_START:
            _place(sc, f"world.objects[{i}].position", m.name, [m.ball.position], m.ball.radius)
    if not isinstance(sc.reality, SyntheticReality):
        return
    for o in sc.reality.objects:
        key = o.source.path if o.source.path.startswith("reality.objects[") else ""
        if o.throw is not None:
            t = o.throw
            xs = sorted({t.x.low, t.x.high})
            ys = sorted({t.y.low, t.y.high})
            box = [(xs[0], ys[0]), (xs[-1], ys[0]), (xs[-1], ys[-1]), (xs[0], ys[-1])]
            box = list(dict.fromkeys(box))  # a fixed throw is a point, a range in x a segment
            # a box that does not fit is blamed on x when its y range alone fits (at the middle x)
            ys_alone = [(t.x.mid, y) for y in dict.fromkeys(ys)]
            path = f"{t.source.path}.{'x' if _clash(sc.scene, ys_alone, o.ball.radius) is None else 'y'}"
            _place(sc, path if path in sc.sources else t.source.path, o.name, box,
                   o.ball.radius, thrown=True)
        elif key and f"{key}.position" in sc.sources:
            _place(sc, f"{key}.position", o.name, [o.ball.position], o.ball.radius)


def _place(sc: "Scenario", path: str, name: str, shape: list[Vec2], radius: float,
           thrown: bool = False) -> None:
    clash = _clash(sc.scene, shape, radius)
    if clash is None:
        return
    what = ("thrown anywhere in its x and y ranges" if thrown and len(shape) > 1
            else "where it starts")
    raise sc.where(path).error(f"the object {name!r} (radius {radius:g} m) does not fit "
                               f"{what}: {clash}; expected a place on the floor clear of "
                               "every wall and obstacle", path=path)


# -- speeds ------------------------------------------------------------------------------------

def _too_fast(sc: "Scenario", path: str, name: str, speed: float, radius: float, dt: float,
              dt_key: str, drag: float = 0.0) -> None:
    effective = speed + drag * speed * speed * dt  # a step's drag counts as speed (the world's)
    if effective * dt <= TRAVEL_RADII * radius:
        return
    dragged = f" (with its drag, {effective:.4g} m/s)" if drag and effective > speed else ""
    raise sc.where(path).error(
        f"{name!r} at {speed:g} m/s{dragged} moves {effective * dt:.4g} m in one physics step "
        f"of {dt:g} s ({dt_key}); expected at most {TRAVEL_RADII:g} of its radii "
        f"({TRAVEL_RADII * radius:.4g} m): give a lower speed or a smaller {dt_key}", path=path)


def _check_speeds(sc: "Scenario") -> None:
    dt = sc.scene.dt
    robot = sc.scene.robot
    if robot is not None:
        _too_fast(sc, "world.robot.max_speed", robot.name, robot.max_speed, robot.inner_radius,
                  dt, "world.dt")
    for i, m in enumerate(sc.objects):
        v = math.hypot(*m.ball.velocity)
        _too_fast(sc, f"world.objects[{i}].velocity", m.name, v, m.ball.radius, dt, "world.dt")
    reality = sc.reality
    if not isinstance(reality, SyntheticReality):
        return
    if robot is not None and reality.robot.max_speed is not None:
        _too_fast(sc, "reality.robot.max_speed", robot.name, reality.robot.max_speed,
                  robot.inner_radius, reality.dt, "reality.dt")
    declared = {m.name: i for i, m in enumerate(sc.objects)}
    for o in reality.objects:
        key = o.source.path if o.source.path.startswith("reality.objects[") else ""
        if o.throw is not None:
            speed, path = o.throw.speed.high, f"{o.throw.source.path}.speed"
        else:
            speed, path = math.hypot(*o.ball.velocity), f"{key}.velocity"
        if path not in sc.sources:
            path = key or f"world.objects[{declared.get(o.name, 0)}].velocity"
        # what the camera sees the imagination takes on at its own step
        _too_fast(sc, path, o.name, speed, o.ball.radius, dt, "world.dt")
        _too_fast(sc, path if o.drag.high == 0 or f"{key}.drag" not in sc.sources
                  else f"{key}.drag", o.name, speed, o.ball.radius, reality.dt, "reality.dt",
                  o.drag.high)


# -- prediction, textures, the true camera ------------------------------------------------------

def _check_prediction(sc: "Scenario") -> None:
    p = sc.predict
    longest = max(p.horizons)
    steps = math.ceil(longest / sc.scene.dt - 1e-9)
    if p.ensemble * steps <= MAX_ENSEMBLE_STEPS:
        return
    path = next((k for k in ("predict.ensemble", "predict.horizons", "world.dt")
                 if k in sc.sources), "predict")
    raise sc.where(path).error(
        f"{p.ensemble} members x {steps:,} physics steps ({longest:g} s ahead at world.dt "
        f"{sc.scene.dt:g} s) is {p.ensemble * steps:,} steps a prediction; expected at most "
        f"{MAX_ENSEMBLE_STEPS:,}: fewer members, a shorter horizon or a larger world.dt",
        path=path)


def _check_textures(sc: "Scenario") -> None:
    reality = sc.reality
    if not isinstance(reality, SyntheticReality) or reality.appearance.texture_scale == 1.0:
        return
    scale = reality.appearance.texture_scale
    tiles = [("world.floor.tile", sc.scene.floor.tile)]
    tiles += [(f"world.walls[{i}].tile", w.tile) for i, w in enumerate(sc.scene.walls)]
    tiles += [(f"world.obstacles[{i}].tile", o.tile) for i, o in enumerate(sc.scene.obstacles)]
    for key, tile in tiles:
        if not MIN_SIZE <= tile * scale <= MAX_COORDINATE:
            path = "reality.appearance.texture_scale"
            raise sc.where(path).error(
                f"{key} {tile:g} m times {scale:g} is a real tile of {tile * scale:g} m; expected "
                f"{MIN_SIZE:g} to {MAX_COORDINATE:g} m", path=path)


def _check_camera(sc: "Scenario") -> None:
    reality = sc.reality
    if not isinstance(reality, SyntheticReality) or sc.mount.kind is Mount.ROBOT:
        return  # a robot's camera moves with it: the world's bound holds wherever it goes
    cam = reality.camera
    offset = cam.position if cam.random_position is None else (cam.random_position,) * 3
    for axis, (c, d) in enumerate(zip(sc.camera.position, offset)):
        if abs(c) + abs(d) > MAX_COORDINATE:
            path = "reality.camera_offset"
            raise sc.where(path).error(
                f"the true camera's {'xyz'[axis]} would be {c:g} + {d:g} m; expected within "
                f"+-{MAX_COORDINATE:g} m", path=path)
