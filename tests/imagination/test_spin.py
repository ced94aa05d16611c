"""Closed-form checks of a spinning ball (``Ball.floor_friction``): sliding, rolling, bounces."""

from __future__ import annotations

import math

import pytest

from adapt.imagination import Ball, SceneSpec, Wall, World
from adapt.imagination.world import BodyState, WorldState

G = 9.81


def _wall_scene(restitution: float, friction: float, floor: float, speed: float = 2.0,
                resistance: float = 0.0) -> SceneSpec:
    return SceneSpec(balls=(Ball("b", radius=0.1, restitution=restitution, friction=friction,
                                 rolling_resistance=resistance, floor_friction=floor,
                                 velocity=(speed, 0.0)),),
                     walls=(Wall("east", (1.0, -2.0), (1.0, 2.0), restitution=1.0,
                                 friction=1.0),))


def test_a_sliding_ball_without_spin_rolls_at_five_sevenths_after_mu_g_time() -> None:
    # a ball launched sliding (no spin) speeds its spin up and slows down at mu g
    # until v = 5/7 v0, which takes (2/7) v0 / (mu g)
    mu, v0 = 0.4, 2.0
    world = World(SceneSpec(balls=(Ball("b", floor_friction=mu),)))
    world.set_state(WorldState(0.0, 0, (BodyState("b", (0.0, 0.0), (v0, 0.0), slip=(-v0, 0.0)),)))
    t_roll = (2.0 / 7.0) * v0 / (mu * G)
    world.run(t_roll / 2)
    assert world.velocity("b")[0] == pytest.approx(v0 - mu * G * t_roll / 2, rel=0.01)
    world.run(t_roll / 2 + 0.2)
    assert world.velocity("b")[0] == pytest.approx(5.0 / 7.0 * v0, rel=0.005)
    assert world.slip("b") == pytest.approx((0.0, 0.0), abs=1e-9)


def test_a_rolling_spinning_ball_slows_at_c_g_like_one_without_spin() -> None:
    c, v0 = 0.03, 1.5
    spin = World(SceneSpec(balls=(Ball("b", rolling_resistance=c, floor_friction=0.5,
                                       velocity=(v0, 0.0)),)))
    plain = World(SceneSpec(balls=(Ball("b", rolling_resistance=c, velocity=(v0, 0.0)),)))
    spin.run(2.0)
    plain.run(2.0)
    assert spin.velocity("b")[0] == pytest.approx(v0 - c * G * 2.0, rel=0.01)
    assert spin.position("b")[0] == pytest.approx(plain.position("b")[0], rel=0.002)
    assert spin.slip("b") == pytest.approx((0.0, 0.0), abs=1e-9)


@pytest.mark.parametrize("e", [0.5, 0.7, 0.9])  # below 2/5 it rolls back into the wall
def test_a_frictionless_wall_keeps_the_spin_and_the_ball_settles_at_5e_minus_2_over_7(
        e: float) -> None:
    # head-on at V: out at e V with the spin still V forwards; the floor brings them together
    # at v = (2/7)(V) + (5/7)(-e V) -- momentum about the contact point
    world = World(_wall_scene(e, 0.0, 0.6))
    world.run(0.5)
    assert [c.surface for c in world.contacts] == ["east"]
    world.run(1.5)
    v = world.velocity("b")[0]
    # one physics step of sliding friction acts during the contact's step: within 2% of V
    assert v == pytest.approx(-(5.0 * e - 2.0) / 7.0 * 2.0, abs=0.04)
    assert world.slip("b") == pytest.approx((0.0, 0.0), abs=1e-9)


def test_a_gripping_wall_takes_five_sevenths_of_the_spin() -> None:
    # friction 1 x 1 with a normal impulse of (1 + e) m V sticks: 5/7 of the spin goes
    e, v0 = 0.7, 2.0
    world = World(_wall_scene(e, 1.0, 0.0, speed=v0))  # no floor friction: the spin stays put
    world.run(1.0)
    vx, _ = world.velocity("b")
    ux, _ = world.slip("b")
    assert vx == pytest.approx(-e * v0, rel=0.01)
    assert vx + ux == pytest.approx(2.0 / 7.0 * v0, rel=0.01)


def test_a_slipping_wall_takes_five_halves_mu_j_over_m() -> None:
    e, mu, v0 = 0.5, 0.05, 2.0
    world = World(_wall_scene(e, mu, 0.0, speed=v0))
    world.run(1.0)
    vx, _ = world.velocity("b")
    ux, _ = world.slip("b")
    assert vx + ux == pytest.approx(v0 - 2.5 * mu * (1 + e) * v0, rel=0.01)


def test_snapshots_forks_and_parameter_changes_keep_the_slip() -> None:
    world = World(_wall_scene(0.6, 0.2, 0.3))
    world.run(0.5)
    state = world.snapshot()
    u = state.body("b").slip
    assert math.hypot(*u) > 0.5
    fork = world.fork()
    assert fork.slip("b") == pytest.approx(u, abs=1e-12)
    fork.run(0.3)
    world.run(0.3)
    assert fork.position("b") == pytest.approx(world.position("b"), abs=1e-12)
    world.set_ball_parameters("b", floor_friction=0.9, rolling_resistance=0.02)
    assert world.slip("b") == pytest.approx(fork.slip("b"), abs=1e-12)
    world.set_ball_parameters("b", rolling_resistance=0.0)  # rebuilds the ball's joints
    assert world.slip("b") == pytest.approx(fork.slip("b"), abs=1e-12)
    world.set_ball_parameters("b", floor_friction=None)     # no spin: rolls as it moves
    assert world.slip("b") == (0.0, 0.0)
    assert world.snapshot().body("b").slip == (0.0, 0.0)


def test_a_ball_without_floor_friction_is_the_model_without_spin() -> None:
    plain = World(_wall_scene(0.6, 0.3, 0.5))
    old = World(SceneSpec(balls=(Ball("b", radius=0.1, restitution=0.6, friction=0.3,
                                      velocity=(2.0, 0.0)),), walls=plain.scene.walls))
    plain.set_ball_parameters("b", floor_friction=None)
    plain.run(1.5)
    old.run(1.5)
    assert plain.position("b") == pytest.approx(old.position("b"), abs=1e-12)


def test_copies_that_do_not_collide_run_as_if_alone() -> None:
    balls = tuple(Ball(f"c{k}", radius=0.1, restitution=0.5, floor_friction=0.4,
                       velocity=(1.0 + 0.5 * k, 0.0)) for k in range(3))
    walls = (Wall("east", (1.0, -2.0), (1.0, 2.0)),)
    together = World(SceneSpec(balls=balls, walls=walls), ball_collisions=False)
    together.run(2.0)
    for b in balls:
        alone = World(SceneSpec(balls=(b,), walls=walls))
        alone.run(2.0)
        assert together.position(b.name) == pytest.approx(alone.position(b.name), abs=1e-9)
    touching = World(SceneSpec(balls=balls, walls=walls))  # the same balls do meet otherwise
    touching.run(2.0)
    assert touching.position("c0") != pytest.approx(together.position("c0"), abs=1e-3)


def test_floor_friction_is_checked() -> None:
    from adapt.errors import ImaginationError

    with pytest.raises(ImaginationError, match="floor_friction: expected a non-negative"):
        Ball("b", floor_friction=-0.1)
    world = World(SceneSpec(balls=(Ball("b"),)))
    with pytest.raises(ImaginationError, match="floor_friction"):
        world.set_ball_parameters("b", floor_friction=float("nan"))


@pytest.mark.parametrize("floor", [None, 0.5])
def test_drag_slows_as_v_squared(floor: float | None) -> None:
    # dv/dt = -d v**2: v = v0 / (1 + d v0 t), with or without spin (rolling, the pair slows so)
    d, v0 = 0.3, 2.0
    world = World(SceneSpec(balls=(Ball("b", drag=d, floor_friction=floor, velocity=(v0, 0.0)),)))
    world.run(2.0)
    assert world.velocity("b")[0] == pytest.approx(v0 / (1 + d * v0 * 2.0), rel=0.01)
    assert world.position("b")[0] == pytest.approx(math.log(1 + d * v0 * 2.0) / d, rel=0.01)


def test_drag_is_the_same_run_in_one_call_or_step_by_step() -> None:
    scene = SceneSpec(balls=(Ball("b", drag=0.2, rolling_resistance=0.01, velocity=(1.5, 0.5)),),
                      walls=(Wall("east", (1.0, -2.0), (1.0, 2.0)),))
    once, steps = World(scene), World(scene)
    once.run(1.5)
    for _ in range(once.steps):
        steps.step(1)
    assert steps.position("b") == once.position("b")
    steps.set_ball_parameters("b", drag=0.0)
    assert steps.scene.balls[0].drag == 0.0
