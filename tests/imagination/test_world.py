"""Closed-form checks of the physics world."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adapt.errors import ImaginationError
from adapt.imagination import Ball, RobotSpec, SceneSpec, Wall, World
from adapt.scenario import Scenario


def test_ball_without_resistance_keeps_its_velocity() -> None:
    scene = SceneSpec(balls=(Ball("b", velocity=(0.7, -0.4), rolling_resistance=0.0),))
    world = World(scene)
    world.run(3.0)
    assert world.velocity("b") == pytest.approx((0.7, -0.4), abs=1e-12)
    assert world.position("b") == pytest.approx((2.1, -1.2), abs=1e-9)


@pytest.mark.parametrize("restitution", [0.5, 0.8, 1.0])
@pytest.mark.parametrize("speed", [0.5, 2.0, 5.0])
def test_head_on_wall_hit_leaves_with_restitution_times_speed(restitution: float, speed: float) -> None:
    scene = SceneSpec(
        balls=(Ball("b", radius=0.1, restitution=restitution, velocity=(speed, 0.0)),),
        walls=(Wall("east", (2.0, -1.0), (2.0, 1.0), restitution=1.0),),
    )
    world = World(scene)
    world.run(1.9 / speed + 0.5)
    vx, vy = world.velocity("b")
    assert [c.surface for c in world.contacts] == ["east"]
    assert -vx == pytest.approx(restitution * speed, rel=0.02)
    assert abs(vy) < 1e-9


def test_rolling_resistance_stops_the_ball_at_v2_over_2cg() -> None:
    c, v, g = 0.05, 1.5, 9.81
    world = World(SceneSpec(balls=(Ball("b", rolling_resistance=c, velocity=(v, 0.0)),), gravity=g))
    world.run(v / (c * g) + 0.5)
    assert world.velocity("b") == pytest.approx((0.0, 0.0), abs=1e-9)
    assert world.position("b")[0] == pytest.approx(v * v / (2 * c * g), rel=0.01)


def test_rolling_resistance_is_a_constraint_not_damping() -> None:
    world = World(SceneSpec(balls=(Ball("b", rolling_resistance=0.1),)))
    assert world.space.damping == 1.0
    assert len(world.space.constraints) == 2


def test_same_seed_gives_the_same_trajectory(bundled: Scenario) -> None:
    def run() -> list[tuple[float, float]]:
        w = World(bundled.scene, seed=bundled.seed)
        out = []
        for _ in range(60):
            w.step(12)
            out.append(w.position("ball"))
        return out

    assert run() == run()


def test_a_fork_leaves_the_original_untouched(bundled: Scenario) -> None:
    world = World(bundled.scene)
    world.run(0.5)
    before = world.snapshot()
    contacts = list(world.contacts)
    fork = world.fork()
    fork.apply_force("ball", (5.0, 0.0))
    fork.command_robot((0.5, 0.0))
    fork.run(3.0)
    assert fork.contacts and fork.position("ball") != before.body("ball").position
    assert world.snapshot() == before
    assert world.contacts == contacts
    # ... and the original continues exactly as an untouched twin.
    twin = World(bundled.scene)
    twin.run(0.5)
    world.run(2.0)
    twin.run(2.0)
    assert world.snapshot() == twin.snapshot()


def test_fork_from_snapshot_continues_like_the_original(bundled: Scenario) -> None:
    world = World(bundled.scene)
    world.run(1.0)
    fork = world.fork()
    world.run(1.0)
    fork.run(1.0)
    assert fork.position("ball") == pytest.approx(world.position("ball"), abs=1e-6)
    assert fork.time == pytest.approx(world.time)


def test_set_state_and_apply_force() -> None:
    world = World(SceneSpec(balls=(Ball("b", mass=2.0),)))
    state = world.snapshot()
    world.apply_force("b", (4.0, 0.0))  # a = 2 m/s^2 for one step
    world.step()
    assert world.velocity("b")[0] == pytest.approx(2.0 * world.dt)
    world.step()
    assert world.velocity("b")[0] == pytest.approx(2.0 * world.dt)  # forces last one step
    world.set_state(state)
    assert world.velocity("b") == (0.0, 0.0) and world.time == 0.0


def test_robot_respects_max_speed_and_acceleration() -> None:
    robot = RobotSpec(position=(0.0, 0.0), max_speed=0.5, max_accel=1.0)
    world = World(SceneSpec(robot=robot))
    world.command_robot((3.0, 0.0))
    world.run(0.25)
    assert world.velocity("robot")[0] == pytest.approx(0.25, rel=0.02)
    world.run(1.0)
    assert world.velocity("robot")[0] == pytest.approx(0.5, rel=1e-3)
    assert world.snapshot().command[:2] == (0.5, 0.0)


def test_contact_event_names_surface_position_and_time() -> None:
    scene = SceneSpec(balls=(Ball("b", radius=0.1, velocity=(1.0, 0.0)),),
                      walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
    world = World(scene)
    world.run(1.2)
    (c,) = world.contacts
    assert (c.ball, c.surface) == ("b", "east")
    assert c.time == pytest.approx(0.9, abs=2 * world.dt)
    assert c.position == pytest.approx((1.0, 0.0), abs=0.01)


def test_unknown_body_and_bad_dt() -> None:
    world = World(SceneSpec(balls=(Ball("b"),)))
    with pytest.raises(ImaginationError, match="no moving body called 'x'"):
        world.position("x")
    with pytest.raises(ImaginationError, match="no robot"):
        world.command_robot((1.0, 0.0))
    with pytest.raises(ImaginationError, match="dt"):
        World(SceneSpec(), dt=0.0)
    assert math.isclose(World(SceneSpec()).dt, 1 / 240)
    assert np.isfinite(world.snapshot().time)
