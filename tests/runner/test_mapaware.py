"""The map-aware analytic predictor and its baseline, on closed-form cases: a straight
reflection off a wall, a corner, an obstacle's edge and corner, deceleration to rest."""

from __future__ import annotations

import math

import pytest

from adapt.imagination.scene import Ball, Obstacle, RobotSpec, SceneSpec, Wall
from adapt.reflection import Reflector
from adapt.runner.baseline import Baseline, BaselineSetup, default_baselines
from adapt.runner.mapaware import MapAwareBaseline, mapaware

BALL = Ball("ball", radius=0.1, restitution=0.8, rolling_resistance=0.0)


def test_a_straight_reflection_off_a_wall_with_the_combined_restitution() -> None:
    scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0), restitution=0.5),))
    model = Reflector(scene, BALL)
    # meets the wall (centre at x = 0.9) at t = 0.45 s, leaves at 0.8 x 0.5 x 2 = 0.8 m/s
    p, v = model.path((0.0, 0.0), (2.0, 0.0), [0.45, 0.95])
    assert p[0] == pytest.approx([0.9, 0.0])
    assert p[1] == pytest.approx([0.9 - 0.8 * 0.5, 0.0])
    assert v[1] == pytest.approx([-0.8, 0.0])


def test_an_oblique_reflection_keeps_the_tangential_velocity() -> None:
    scene = SceneSpec(walls=(Wall("north", (-5.0, 1.0), (5.0, 1.0)),))
    p, v = Reflector(scene, BALL).path((0.0, 0.0), (1.0, 1.0), [0.9, 1.9])
    assert p[0] == pytest.approx([0.9, 0.9])
    assert v[1] == pytest.approx([1.0, -0.8])
    assert p[1] == pytest.approx([1.9, 0.9 - 0.8])


def test_into_a_corner_both_walls_reflect_it() -> None:
    scene = SceneSpec(walls=(Wall("north", (-5.0, 1.0), (1.0, 1.0)),
                             Wall("east", (1.0, 1.0), (1.0, -5.0))))
    model = Reflector(scene, BALL)
    # heading along the diagonal into the corner: both reflections at (0.9, 0.9)
    p, v = model.path((0.0, 0.0), (1.0, 1.0), [2.0])
    assert v[0] == pytest.approx([-0.8, -0.8], abs=1e-9)
    assert p[0] == pytest.approx([0.9 - 0.8 * 1.1, 0.9 - 0.8 * 1.1], abs=1e-9)


def test_an_obstacle_reflects_off_its_face_and_its_corner() -> None:
    crate = Obstacle("crate", polygon=((1.0, -0.5), (2.0, -0.5), (2.0, 0.5), (1.0, 0.5)),
                     height=0.3, restitution=1.0)
    model = Reflector(SceneSpec(obstacles=(crate,)), BALL)
    _, v = model.path((0.0, 0.0), (1.0, 0.0), [1.0])   # the face x = 1
    assert v[0] == pytest.approx([-0.8, 0.0])
    # aimed at the corner (1, 0.5) from the left, 0.05 above it: it meets the round corner where
    # its centre is 0.1 from (1, 0.5), i.e. at (1 - sqrt(0.1^2 - 0.05^2), 0.55): normal (-0.866, 0.5)
    hit = model.first_hit((0.0, 0.55), (1.0, 0.0))
    assert hit is not None and hit.name == "crate"
    assert hit.distance == pytest.approx(1.0 - math.sqrt(0.01 - 0.0025))
    assert hit.normal == pytest.approx((-math.sqrt(0.75), 0.5))
    # passing 0.11 above the corner: no contact
    assert model.first_hit((0.0, 0.61), (1.0, 0.0)) is None


def test_it_decelerates_to_rest_at_the_nominal_rolling_resistance() -> None:
    ball = Ball("ball", radius=0.1, rolling_resistance=0.05)
    scene = SceneSpec(gravity=10.0)
    p, v = Reflector(scene, ball).path((0.0, 0.0), (1.0, 0.0), [0.5, 2.0, 5.0])
    # a = 0.5 m/s^2: at 0.5 s, x = 0.5 - 0.0625, v = 0.75; stops at 2 s after 1 m
    assert p[0] == pytest.approx([0.4375, 0.0]) and v[0] == pytest.approx([0.75, 0.0])
    assert p[1] == pytest.approx([1.0, 0.0]) and v[1] == pytest.approx([0.0, 0.0], abs=1e-9)
    assert p[2] == pytest.approx([1.0, 0.0])


def test_a_ball_that_stops_before_the_wall_never_reflects() -> None:
    ball = Ball("ball", radius=0.1, rolling_resistance=0.05)
    scene = SceneSpec(walls=(Wall("east", (1.2, -1.0), (1.2, 1.0)),), gravity=10.0)
    p, _ = Reflector(scene, ball).path((0.0, 0.0), (1.0, 0.0), [3.0])
    assert p[0] == pytest.approx([1.0, 0.0])


def test_slowing_to_the_wall_the_reflection_starts_from_the_speed_there() -> None:
    ball = Ball("ball", radius=0.1, restitution=1.0, rolling_resistance=0.05)
    scene = SceneSpec(walls=(Wall("east", (0.85, -1.0), (0.85, 1.0)),), gravity=10.0)
    # hits at x = 0.75 when v^2 = 1 - 2 (0.5)(0.75) = 0.25: v = 0.5, at t = 1 s
    _, v = Reflector(scene, ball).path((0.0, 0.0), (1.0, 0.0), [1.0 + 1e-9])
    assert v[0] == pytest.approx([-0.5, 0.0], abs=1e-6)


def feed(baseline: Baseline, frames: int = 20, speed: float = 1.0) -> None:
    for k in range(frames):
        baseline.step(k / 30, (speed * k / 30, 0.0))


def test_the_map_aware_baseline_predicts_the_bounce_the_kalman_baseline_misses() -> None:
    scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
    mapaware = MapAwareBaseline(None, reach=0.3, horizons=(0.5, 1.0), dt=1 / 30, scene=scene,
                                ball=BALL)
    kalman = Baseline(None, reach=0.3, horizons=(0.5, 1.0), dt=1 / 30, scene=scene)
    feed(mapaware)
    feed(kalman)
    x0 = mapaware.kf.position[0]
    straight = kalman.predict(1.0)[0]
    reflected = mapaware.predict(1.0)[0]
    assert straight == pytest.approx(x0 + 1.0, abs=0.02)
    assert reflected == pytest.approx(0.9 - 0.8 * (1.0 - (0.9 - x0)), abs=0.02)
    assert [p.horizon for p in mapaware.predictions()] == [0.5, 1.0]
    assert mapaware.predictions()[1].position == pytest.approx(mapaware.predict(1.0))


def test_the_map_aware_robot_goes_where_the_ball_will_come_back() -> None:
    scene = SceneSpec(walls=(Wall("east", (1.0, -2.0), (1.0, 2.0)),
                             Wall("west", (-3.0, 2.0), (-3.0, -2.0))))
    robot = RobotSpec(position=(-1.0, -1.0), max_speed=0.5, max_accel=2.0, radius=0.2)
    ball = Ball("ball", radius=0.1, restitution=0.9)
    mapaware = MapAwareBaseline(robot, reach=0.3, horizons=(1.0,), dt=1 / 30, scene=scene,
                                ball=ball)
    kalman = Baseline(robot, reach=0.3, horizons=(1.0,), dt=1 / 30, scene=scene)
    for k in range(10):   # the ball runs away from the robot towards the east wall
        t, x = k / 30, -0.5 + 1.5 * k / 30
        mapaware.step(t, (x, 0.0))
        kalman.step(t, (x, 0.0))
    assert mapaware.target is not None and kalman.target is not None
    # the straight line runs away faster than the robot drives: the Kalman robot chases the
    # ball where it is; the map-aware one waits for it on its way back from the wall
    assert kalman.target == pytest.approx(kalman.kf.position)
    assert mapaware.target[1] == pytest.approx(0.0, abs=0.01)
    assert mapaware.target[0] < kalman.kf.position[0] - 0.3
    assert mapaware.robot is not None and mapaware.robot.footprint is not None


def test_every_run_has_both_baselines_and_the_map_aware_one_gets_the_objects_model() -> None:
    scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0), restitution=0.5),))
    sets = default_baselines(None, horizons=(1.0,), dt=1 / 30, scene=scene)
    assert list(sets) == ["kalman", "mapaware"]
    b = mapaware(BaselineSetup(None, 0.3, (1.0,), 1 / 30, scene, BALL))
    assert b.reflector.radius == 0.1 and b.reflector.faces[0].restitution == pytest.approx(0.4)
