"""Where the robot meets a path it must go round an obstacle to reach
(:func:`adapt.imagination.reach.meet`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import adapt.imagination.reach as reach_module
from adapt.imagination import Obstacle, RobotSpec, SceneSpec
from adapt.imagination.footprint import Footprint
from adapt.imagination.predict import Trajectory
from adapt.imagination.reach import meet

WALL = Obstacle("wall", ((-0.6, 0.5), (0.6, 0.5), (0.6, 0.7), (-0.6, 0.7)), 0.3)
ROBOT = RobotSpec(radius=0.2, max_speed=1.0, max_accel=2.0)


def slow_path() -> Trajectory:
    """A ball creeping along behind the wall, millimetres a sample (120 samples a second)."""
    t = np.arange(0.0, 4.0, 1.0 / 120.0)
    pos = np.stack([-0.3 + 0.1 * t, np.full_like(t, 1.2)], axis=1)
    return Trajectory("ball", t, pos, np.tile([0.1, 0.0], (len(t), 1)), ())


def test_standing_points_a_few_mm_apart_share_one_way_round(
        monkeypatch: pytest.MonkeyPatch) -> None:
    scene = SceneSpec(obstacles=(WALL,))
    calls: list[int] = []
    real = Footprint.route

    def counted(self: Footprint, start: object, goal: object) -> object:
        calls.append(1)
        return real(self, start, goal)  # type: ignore[arg-type]

    monkeypatch.setattr(Footprint, "route", counted)
    shared = meet(slow_path(), scene, ROBOT, (0.0, 0.0), reach=0.3, start=0.0)
    n_shared = len(calls)
    calls.clear()
    monkeypatch.setattr(reach_module, "ROUTE_CELL", 1e-9)   # a way for every point
    each = meet(slow_path(), scene, ROBOT, (0.0, 0.0), reach=0.3, start=0.0)
    assert shared is not None and each is not None
    assert len(calls) > 3 * n_shared >= 3                  # far fewer ways worked out
    # the same meeting, to a sample or two; the way round as long, to the cell
    assert shared.time == pytest.approx(each.time, abs=2.5 / 120)
    assert math.dist(shared.stand, each.stand) < 0.02
    assert shared.travel == pytest.approx(each.travel, abs=0.03)
    assert shared.travel > math.dist((0.0, 0.0), shared.stand) + 0.05   # it went round


def test_no_room_at_the_approach_stands_farther_within_reach() -> None:
    """A ball resting in the gap between a wall and an obstacle's corner (bench/mirror.py's
    throw 11): no room for the robot's body at APPROACH of the reach all round it, room
    farther off but still within reach -- a meeting, not "cannot reach"."""
    from adapt.imagination import Wall
    from adapt.imagination.reach import APPROACH, FARTHER, standing_point

    wedge = Obstacle("wedge", ((0.35, 2.6), (0.95, 2.75), (0.55, 2.25)), 0.3)
    scene = SceneSpec(walls=(Wall("north", (-2.5, 3.0), (2.5, 3.0)),), obstacles=(wedge,))
    robot = RobotSpec(radius=0.25, max_speed=0.8, max_accel=1.5)
    fp = Footprint(scene, robot.outer_radius)
    ball, reach, start = (0.389, 2.879), 0.36, (0.045, 0.8)
    ring = [(ball[0] + APPROACH * reach * math.cos(a), ball[1] + APPROACH * reach * math.sin(a))
            for a in np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)]
    assert not any(fp.clear(p) for p in ring)              # no room where it used to look
    stand = standing_point(scene, robot, ball, reach, start)
    assert stand is not None and fp.clear(stand)
    assert APPROACH * reach < math.dist(stand, ball) <= max(FARTHER) * reach + 1e-9
    path = Trajectory("ball", np.array([0.0, 10.0]), np.array([ball, ball]),
                      np.zeros((2, 2)), ())
    met = meet(path, scene, robot, start, reach=reach, start=0.0)
    assert met is not None and math.dist(met.stand, ball) <= reach
    # a box whose edge is 38 cm from the wall: no room for the 25 cm body anywhere within reach
    tight = SceneSpec(walls=(Wall("north", (-2.5, 3.0), (2.5, 3.0)),),
                      obstacles=(Obstacle("box", ((-0.5, 2.3), (0.5, 2.3), (0.5, 2.62),
                                                  (-0.5, 2.62)), 0.3),))
    assert standing_point(tight, robot, (0.0, 2.89), reach, start) is None
