"""Closed-form checks of the physics world."""

from __future__ import annotations

import math
from dataclasses import replace

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


# -- step hooks ----------------------------------------------------------------------


def test_a_hook_runs_before_every_step_so_a_force_acts_on_every_step() -> None:
    world = World(SceneSpec(balls=(Ball("b", mass=2.0),)))
    seen: list[int] = []

    def spring(w: World) -> None:
        seen.append(w.steps)
        w.apply_force("b", (4.0, 0.0))  # a = 2 m/s^2

    world.add_step_hook(spring)
    world.run(1.0)
    world.run_until(1.5)
    world.step(3)
    n = 360 + 3
    assert seen == list(range(n))
    assert world.velocity("b")[0] == pytest.approx(2.0 * n * world.dt, abs=1e-9)
    # pymunk moves with the velocity before the step's update: x = a dt^2 n (n - 1) / 2.
    assert world.position("b")[0] == pytest.approx(2.0 * world.dt**2 * n * (n - 1) / 2, rel=1e-9)
    world.remove_step_hook(spring)
    world.step(10)
    assert len(seen) == n and world.step_hooks == ()
    with pytest.raises(ImaginationError, match="not registered"):
        world.remove_step_hook(spring)
    with pytest.raises(ImaginationError, match="^hook: expected a callable"):
        world.add_step_hook(3)  # type: ignore[arg-type]


def test_a_spring_damper_hook_pulls_the_ball_to_a_target(bundled: Scenario) -> None:
    world = World(bundled.scene)
    target = np.array([0.5, 1.5])
    k, m = 40.0, bundled.scene.balls[0].mass
    c = 2.0 * math.sqrt(k * m)

    def spring(w: World) -> None:
        p, v = np.array(w.position("ball")), np.array(w.velocity("ball"))
        w.apply_force("ball", k * (target - p) - c * v)

    world.add_step_hook(spring)
    world.run(4.0)
    assert world.position("ball") == pytest.approx(tuple(target), abs=0.01)


def test_forks_have_no_hooks_and_hooks_may_add_balls() -> None:
    world = World(SceneSpec())
    added: list[float] = []

    def thrower(w: World) -> None:
        if w.steps == 10:
            w.add_ball(Ball("late", radius=0.05), position=(0.0, 0.0), velocity=(1.0, 0.0))
            added.append(w.time)

    world.add_step_hook(thrower)
    world.step(20)
    assert world.names == ("late",) and added == [pytest.approx(10 * world.dt)]
    assert world.position("late")[0] == pytest.approx(10 * world.dt)
    assert world.fork().step_hooks == ()


# -- balls at run time ---------------------------------------------------------------


def test_add_and_remove_balls_at_run_time(bundled: Scenario) -> None:
    from adapt.imagination import ensemble, rollout

    world = World(bundled.scene, seed=1)
    world.run(0.5)
    world.add_ball(Ball("thrown", radius=0.08, mass=0.2), position=(1.0, 0.0),
                   velocity=(0.0, 1.0))
    assert world.names == ("ball", "thrown", "robot")
    assert [b.name for b in world.balls] == ["ball", "thrown"]
    assert world.balls[1].position == (1.0, 0.0)
    snap = world.snapshot()
    assert snap.body("thrown").position == (1.0, 0.0)
    fork = world.fork()
    world.run(1.0)
    fork.run(1.0)
    assert fork.snapshot() == world.snapshot()
    assert world.position("thrown")[1] == pytest.approx(1.0, abs=1e-6)
    path = rollout(world, 0.5, body="thrown", times=[0.5])
    assert path.positions[-1, 1] == pytest.approx(1.5, abs=1e-6)
    e = ensemble(world, 0.5, {"speed_scale": (0.5, 1.5)}, n=5, body="thrown", seed=2)
    assert e.samples.shape == (5, 21, 2)
    # Setting a snapshot back restores the run-time ball too.
    world.set_state(snap)
    assert world.position("thrown") == (1.0, 0.0)
    world.remove_ball("thrown")
    assert world.names == ("ball", "robot") and [b.name for b in world.balls] == ["ball"]
    assert len(world.space.bodies) == len(World(bundled.scene).space.bodies)
    with pytest.raises(ImaginationError, match="add a ball with add_ball"):
        world.set_state(snap)
    with pytest.raises(ImaginationError, match="no ball called 'thrown'"):
        world.remove_ball("thrown")
    with pytest.raises(ImaginationError, match="used twice"):
        world.add_ball(Ball("ball"))
    with pytest.raises(ImaginationError, match="^velocity: expected a speed"):
        world.add_ball(Ball("x"), velocity=(5000.0, 0.0))


def test_removing_a_ball_with_rolling_resistance_removes_its_joints() -> None:
    world = World(SceneSpec(balls=(Ball("a", rolling_resistance=0.1),
                                   Ball("b", rolling_resistance=0.1, position=(1, 0)))))
    assert len(world.space.constraints) == 4
    world.remove_ball("a")
    assert len(world.space.constraints) == 2 and len(world.space.shapes) == 1
    world.run(0.1)


def test_contacts_of_a_ball_added_at_run_time_are_recorded() -> None:
    world = World(SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),)))
    world.add_ball(Ball("late", radius=0.1), velocity=(2.0, 0.0))
    world.run(1.0)
    assert [(c.ball, c.surface) for c in world.contacts] == [("late", "east")]


# -- fast bodies and limits ---------------------------------------------------------------


@pytest.mark.parametrize("speed", [20.0, 80.0, 300.0])
def test_a_fast_ball_bounces_off_a_wall_instead_of_passing_through(speed: float) -> None:
    scene = SceneSpec(
        balls=(Ball("b", radius=0.05, restitution=0.9, velocity=(speed, 0.0)),),
        walls=(Wall("east", (2.0, -1.0), (2.0, 1.0), restitution=1.0),),
    )
    world = World(scene)
    world.run(1.9 / speed + 0.01)
    assert [c.surface for c in world.contacts] == ["east"]
    assert world.velocity("b")[0] == pytest.approx(-0.9 * speed, rel=0.02)
    assert world.position("b")[0] < 2.0


def test_a_ball_at_80_m_s_stays_in_the_room(bundled: Scenario) -> None:
    ball = replace(bundled.scene.balls[0], velocity=(80.0, 30.0))
    world = World(replace(bundled.scene, balls=(ball,)))
    world.run(3.0)
    x, y = world.position("ball")
    assert -2.5 < x < 2.5 and -1.0 < y < 3.0
    assert len({c.surface for c in world.contacts}) >= 3


def test_sub_steps_depend_on_the_state_only_so_chunks_do_not_matter(bundled: Scenario) -> None:
    ball = replace(bundled.scene.balls[0], velocity=(30.0, 12.0))
    scene = replace(bundled.scene, balls=(ball,))
    whole = World(scene)
    whole.run(2.0)
    pieces = World(scene)
    for _ in range(480):
        pieces.step()
    assert whole.snapshot() == pieces.snapshot()
    halfway = World(scene)
    halfway.run(1.0)
    fork = halfway.fork()
    fork.run(1.0)
    assert fork.snapshot() == whole.snapshot()


def test_a_force_lasts_the_whole_step_when_it_is_sub_divided() -> None:
    world = World(SceneSpec(balls=(Ball("b", radius=0.01, mass=1.0, velocity=(40.0, 0.0)),)))
    world.apply_force("b", (0.0, 10.0))
    world.step()
    assert world.velocity("b") == pytest.approx((40.0, 10.0 * world.dt), abs=1e-12)
    world.step()
    assert world.velocity("b")[1] == pytest.approx(10.0 * world.dt, abs=1e-12)


def test_speeds_beyond_what_sub_steps_resolve_are_refused() -> None:
    world = World(SceneSpec(balls=(Ball("b", radius=0.001, velocity=(1000.0, 0.0)),)))
    with pytest.raises(ImaginationError, match="'b' moves at 1000 m/s.*use a smaller dt"):
        world.step()
    slow = World(SceneSpec(balls=(Ball("b", radius=0.001, velocity=(1000.0, 0.0)),)), dt=1e-5)
    slow.step(10)
    assert slow.position("b")[0] == pytest.approx(0.1)


def test_step_counts_are_bounded_per_call() -> None:
    from adapt.imagination import MAX_STEPS

    world = World(SceneSpec(balls=(Ball("b"),)))
    with pytest.raises(ImaginationError, match="^run: 1e\\+09 s is .* at most 1,000,000 steps"):
        world.run(1e9)
    with pytest.raises(ImaginationError, match="^run_until: "):
        world.run_until(1e9)
    with pytest.raises(ImaginationError, match="^steps: expected 0 to"):
        world.step(MAX_STEPS + 1)
    with pytest.raises(ImaginationError, match="^steps: expected 0 to"):
        world.step(-1)
    with pytest.raises(ImaginationError, match="^steps: expected a whole number"):
        world.step(1.5)  # type: ignore[arg-type]
    with pytest.raises(ImaginationError, match="^run_until: expected a finite"):
        world.run_until(float("nan"))
    with pytest.raises(ImaginationError, match="^dt: expected a number of seconds from 1e-06"):
        World(SceneSpec(), dt=1e-9)
    with pytest.raises(ImaginationError, match="^dt: "):
        SceneSpec(dt=1e-9)
    assert world.time == 0.0


def test_bad_forces_and_commands_are_errors() -> None:
    world = World(SceneSpec(balls=(Ball("b"),), robot=RobotSpec()))
    with pytest.raises(ImaginationError, match="^force: expected finite"):
        world.apply_force("b", (float("inf"), 0.0))
    with pytest.raises(ImaginationError, match="^force: expected"):
        world.apply_force("b", "up")  # type: ignore[arg-type]
    with pytest.raises(ImaginationError, match="^command: expected finite"):
        world.command_robot((float("nan"), 0.0))
