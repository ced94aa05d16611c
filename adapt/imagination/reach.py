"""Where a robot can meet an object: standing room, and the earliest meeting on a path.

:func:`intercept <adapt.imagination.predict.intercept>` answers "when can a
robot of these limits first be within reach of a point of this path"; it
knows nothing of the room.  A robot is a body: its centre must stay its own
radius away from walls and obstacles and on the floor, so it cannot stand
everywhere within reach of an object that lies against a wall or in a gap
behind an obstacle.  :func:`standing_point` finds where it can stand,
:func:`meet` the earliest point of a path it can reach and stand at in time
(straight, or round what is in the way; from rest, without turning), and where to stand then.

Examples
--------
>>> from adapt.imagination.scene import RobotSpec, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 1), (2, 1)),))
>>> robot = RobotSpec(radius=0.25, max_speed=1.0, max_accel=2.0)
>>> p = standing_point(scene, robot, (0.0, 0.95), 0.35, (0.0, -1.0))
>>> [round(v, 3) for v in p]             # short of the ball, clear of the wall
[0.0, 0.688]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from adapt.imagination.footprint import Footprint, path_length
from adapt.imagination.predict import Trajectory, time_to_reach
from adapt.imagination.scene import RobotSpec, SceneSpec, Vec2

__all__ = ["Meeting", "standing_point", "meet", "APPROACH", "FARTHER"]

#: The robot plans to stop this fraction of the reach short of the object's centre: well
#: inside it, so that a few centimetres of error in where it sees the object and in its
#: own odometry still leave the bodies touching (0.9 left 5 cm gaps on PyBullet realities).
APPROACH = 0.75
#: Where there is no room at :data:`APPROACH` of the reach (an object against a wall, in a gap
#: behind an obstacle), the robot stands farther off, at these fractions of it, before it
#: gives the object up: a tighter meeting is still one.
FARTHER = (0.85, 0.95)
#: Standing points this close (m) share one way round what is in the robot's way.
ROUTE_CELL = 0.02
#: Directions tried around the object for standing room.
DIRECTIONS = 72


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


def standing_point(scene: SceneSpec, robot: RobotSpec, target: Sequence[float], reach: float,
                   approach_from: Sequence[float], *,
                   footprint: Footprint | None = None) -> Vec2 | None:
    """Where the robot's centre can stand within ``reach`` of ``target`` (at
    :data:`APPROACH` of it, or where there is no room for that at :data:`FARTHER`
    of it), clear of the walls and obstacles and on the floor, preferring the side
    it comes from; None when there is no room.

    A robot already within reach of the target stays where it is. ``footprint`` is the
    robot's in ``scene``, built when not given.
    """
    fp = footprint if footprint is not None else Footprint(scene, robot.outer_radius)
    return _standing_point(fp, target, reach, approach_from)


def _standing_point(fp: Footprint, target: Sequence[float], reach: float,
                    approach_from: Sequence[float]) -> Vec2 | None:
    tx, ty = float(target[0]), float(target[1])
    fx, fy = float(approach_from[0]), float(approach_from[1])
    if math.hypot(fx - tx, fy - ty) <= reach and fp.clear((fx, fy)):
        return (fx, fy)
    base = math.atan2(fy - ty, fx - tx)
    for share in (APPROACH, *FARTHER):
        d = share * reach
        for k in range(DIRECTIONS):
            # 0, +1, -1, +2, -2, ... steps away from the approach direction
            step = (k + 1) // 2 * (1 if k % 2 else -1)
            a = base + step * 2.0 * math.pi / DIRECTIONS
            p = (tx + d * math.cos(a), ty + d * math.sin(a))
            if fp.clear(p):
                return p
    return None


def meet(path: Trajectory, scene: SceneSpec, robot: RobotSpec, position: Sequence[float], *,
         reach: float, start: float, max_speed: float | None = None,
         footprint: Footprint | None = None) -> Meeting | None:
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
    footprint : Footprint, optional
        The robot's footprint in ``scene`` (built when not given; pass one to reuse its
        way-round graph).

    When the straight line to where it would stand is blocked, the robot goes round
    (:meth:`Footprint.route <adapt.imagination.footprint.Footprint.route>`), from rest
    to rest between corners (a bound on the time it takes, not the best it could do).
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
    fp = footprint if footprint is not None else Footprint(scene, robot.outer_radius)
    # the ways round, by standing point to ROUTE_CELL: the path's samples are millimetres
    # apart, and their standing points share a way (its last leg ends at each one's own)
    ways: dict[tuple[int, int], list[Vec2] | None] = {}
    for k in np.flatnonzero(ok & (need <= times - start + 1e-9)):
        target = (float(pts[k, 0]), float(pts[k, 1]))
        stand = _standing_point(fp, target, reach, (rx, ry))
        if stand is None:
            continue
        travel = math.hypot(stand[0] - rx, stand[1] - ry)
        drive = time_to_reach(travel, speed, robot.max_accel)
        if drive > float(times[k]) - start + 1e-9:
            continue
        cell = (round(stand[0] / ROUTE_CELL), round(stand[1] / ROUTE_CELL))
        if cell in ways:
            known = ways[cell]
            if known is None:
                continue
            way = known[:-1] + [stand]
        elif (rx, ry) == stand or fp.path_clear((rx, ry), stand):
            ways[cell] = [stand]
            way = [stand]
        else:
            # the straight line is blocked: the way round, slowing at each corner
            ways[cell] = found = fp.route((rx, ry), stand)
            if found is None:
                continue
            way = found
        if len(way) > 1:
            travel = path_length((rx, ry), way)
            drive = sum(time_to_reach(math.dist(a, b), speed, robot.max_accel)
                        for a, b in zip([(rx, ry)] + way[:-1], way))
            if drive > float(times[k]) - start + 1e-9:
                continue
        return Meeting(float(times[k]), target, stand, travel, drive)
    return None
