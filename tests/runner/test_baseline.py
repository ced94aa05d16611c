"""The Kalman baseline's robot has the real robot's body: it neither passes through walls nor
squeezes through gaps the real one could not."""

from __future__ import annotations

import numpy as np

from adapt.imagination import Obstacle, SceneSpec, Wall
from adapt.imagination.footprint import Footprint
from adapt.runner.baseline import SimulatedRobot

ROOM = SceneSpec(walls=(Wall("north", (-3.0, 2.0), (3.0, 2.0)),))


def drive(robot: SimulatedRobot, target: tuple[float, float], seconds: float) -> None:
    for _ in range(int(seconds * 30)):
        robot.drive(target, 1 / 30)


def test_a_point_robot_goes_through_the_wall_and_a_body_stops_at_it() -> None:
    point = SimulatedRobot((0.0, 0.0), 1.0, 2.0)
    body = SimulatedRobot((0.0, 0.0), 1.0, 2.0, Footprint(ROOM, 0.25))
    for r in (point, body):
        drive(r, (0.0, 3.0), 6.0)
    assert np.allclose(point.position, (0.0, 3.0), atol=1e-3)
    assert 1.7 < body.position[1] <= 1.75 + 1e-9 and abs(body.position[0]) < 1e-9


def test_a_body_slides_along_the_wall_towards_a_target_behind_it() -> None:
    body = SimulatedRobot((0.0, 1.7), 1.0, 2.0, Footprint(ROOM, 0.25))
    drive(body, (1.0, 2.5), 6.0)
    assert body.position[1] <= 1.75 + 1e-9 and abs(body.position[0] - 1.0) < 0.05


def test_a_gap_narrower_than_the_body_stops_it() -> None:
    gap = SceneSpec(obstacles=(Obstacle("left", ((-1.0, 1.0), (-0.2, 1.0), (-0.2, 1.4), (-1.0, 1.4)), 0.5),
                               Obstacle("right", ((0.2, 1.0), (1.0, 1.0), (1.0, 1.4), (0.2, 1.4)), 0.5)))
    body = SimulatedRobot((0.0, 0.0), 1.0, 2.0, Footprint(gap, 0.25))
    drive(body, (0.0, 2.5), 6.0)
    assert body.position[1] < 0.9  # touching the corners at (±0.2, 1.0), not in the gap
    thin = SimulatedRobot((0.0, 0.0), 1.0, 2.0, Footprint(gap, 0.15))
    drive(thin, (0.0, 2.5), 6.0)
    assert np.allclose(thin.position, (0.0, 2.5), atol=1e-2)
