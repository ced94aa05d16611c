"""Where a robot can meet an object: standing room, and the earliest meeting on a path.

:func:`intercept <adapt.imagination.predict.intercept>` answers "when can a
robot of these limits first be within reach of a point of this path"; it
knows nothing of the room.  A robot is a body: its centre must stay its own
radius away from walls and obstacles and on the floor, so it cannot stand
everywhere within reach of an object that lies against a wall or in a gap
behind an obstacle.  :func:`standing_point` finds where it can stand,
:func:`meet` the earliest point of a path it can reach and stand at in time
(driving straight, from rest, without turning), and where to stand then.

Examples
--------
>>> from adapt.imagination.scene import RobotSpec, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 1), (2, 1)),))
>>> robot = RobotSpec(radius=0.25, max_speed=1.0, max_accel=2.0)
>>> p = standing_point(scene, robot, (0.0, 0.95), 0.35, (0.0, -1.0))
>>> [round(v, 3) for v in p]             # short of the ball, clear of the wall
[0.0, 0.635]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from adapt.imagination.predict import Trajectory, time_to_reach
from adapt.imagination.scene import RobotSpec, SceneSpec, Vec2

__all__ = ["Meeting", "Footprint", "standing_point", "meet", "body_radius", "APPROACH"]

#: The robot plans to stop this fraction of the reach short of the object's centre.
APPROACH = 0.9
#: Directions tried around the object for standing room.
DIRECTIONS = 24


@dataclass(frozen=True, slots=True)
class Meeting:
    """Where and when the robot meets the object.

    ``time`` is the meeting's world time, ``object`` the object's position
    then, ``stand`` where the robot's centre stops, ``travel`` its distance
    from the robot and ``drive`` the time it takes.
    """

    time: float
    object: Vec2
    stand: Vec2
    travel: float
    drive: float


def body_radius(robot: RobotSpec) -> float:
    """The radius of the robot's footprint (a box: half its diagonal)."""
    if robot.shape == "disc":
        return robot.radius
    return math.hypot(robot.size[0], robot.size[1]) / 2.0


def _segments(scene: SceneSpec) -> list[tuple[Vec2, Vec2]]:
    out = [(w.start, w.end) for w in scene.walls]
    for ob in scene.obstacles:
        poly = ob.polygon
        out.extend((poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly)))
    return out


def _inside(p: Vec2, polygon: Sequence[Vec2]) -> bool:
    n = len(polygon)
    for i in range(n):
        (ax, ay), (bx, by) = polygon[i], polygon[(i + 1) % n]
        if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) < 0:
            return False
    return True


def _clear(scene: SceneSpec, p: Vec2, radius: float, segments: list[tuple[Vec2, Vec2]]) -> bool:
    if scene.floor.extent is not None:
        x0, y0, x1, y1 = scene.floor.extent
        if not (x0 + radius <= p[0] <= x1 - radius and y0 + radius <= p[1] <= y1 - radius):
            return False
    for (ax, ay), (bx, by) in segments:
        dx, dy = bx - ax, by - ay
        length2 = dx * dx + dy * dy
        t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy)
                                                  / length2))
        if math.hypot(p[0] - (ax + t * dx), p[1] - (ay + t * dy)) < radius:
            return False
    return not any(_inside(p, ob.polygon) for ob in scene.obstacles)


class Footprint:
    """Where a disc of ``radius`` (a robot's footprint) may stand: on the floor, clear of the
    walls and obstacles.

    >>> from adapt.imagination.scene import SceneSpec, Wall
    >>> room = Footprint(SceneSpec(walls=(Wall("north", (-2.0, 1.0), (2.0, 1.0)),)), 0.25)
    >>> room.clear((0.0, 0.5)), room.clear((0.0, 0.8))
    (True, False)
    """

    def __init__(self, scene: SceneSpec, radius: float) -> None:
        self.scene = scene
        self.radius = float(radius)
        self._segments = _segments(scene)

    def clear(self, p: Sequence[float]) -> bool:
        """Whether the disc fits at ``p``."""
        return _clear(self.scene, (float(p[0]), float(p[1])), self.radius, self._segments)


def standing_point(scene: SceneSpec, robot: RobotSpec, target: Sequence[float], reach: float,
                   approach_from: Sequence[float]) -> Vec2 | None:
    """Where the robot's centre can stand within ``reach`` of ``target`` (at
    :data:`APPROACH` of it), clear of the walls and obstacles and on the floor,
    preferring the side it comes from; None when there is no room.

    A robot already within reach of the target stays where it is.
    """
    radius = body_radius(robot)
    segments = _segments(scene)
    tx, ty = float(target[0]), float(target[1])
    fx, fy = float(approach_from[0]), float(approach_from[1])
    if math.hypot(fx - tx, fy - ty) <= reach and _clear(scene, (fx, fy), radius, segments):
        return (fx, fy)
    d = APPROACH * reach
    base = math.atan2(fy - ty, fx - tx)
    for k in range(DIRECTIONS):
        # 0, +1, -1, +2, -2, ... steps away from the approach direction
        step = (k + 1) // 2 * (1 if k % 2 else -1)
        a = base + step * 2.0 * math.pi / DIRECTIONS
        p = (tx + d * math.cos(a), ty + d * math.sin(a))
        if _clear(scene, p, radius, segments):
            return p
    return None


def meet(path: Trajectory, scene: SceneSpec, robot: RobotSpec, position: Sequence[float], *,
         reach: float, start: float, max_speed: float | None = None) -> Meeting | None:
    """The earliest point of ``path`` (from ``start`` on) the robot, starting at rest at
    ``position``, can reach and stand at in time; None when there is none.

    Parameters
    ----------
    path : Trajectory
        The object's predicted path (samples in time order).
    reach : float
        How close the robot's centre must come to the object's.
    max_speed : float, optional
        The speed to plan with (default the robot's own).
    """
    speed = robot.max_speed if max_speed is None else max_speed
    rx, ry = float(position[0]), float(position[1])
    times = path.times
    pts = path.positions
    ok = times >= start
    if not ok.any():
        return None
    # a necessary condition first, vectorised: the straight distance less the reach
    dist = np.maximum(np.hypot(pts[:, 0] - rx, pts[:, 1] - ry) - reach, 0.0)
    need = np.array([time_to_reach(float(v), speed, robot.max_accel) for v in dist])
    for k in np.flatnonzero(ok & (need <= times - start + 1e-9)):
        target = (float(pts[k, 0]), float(pts[k, 1]))
        stand = standing_point(scene, robot, target, reach, (rx, ry))
        if stand is None:
            continue
        travel = math.hypot(stand[0] - rx, stand[1] - ry)
        drive = time_to_reach(travel, speed, robot.max_accel)
        if drive <= float(times[k]) - start + 1e-9:
            return Meeting(float(times[k]), target, stand, travel, drive)
    return None
