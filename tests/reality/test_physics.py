"""Reality's own physics against closed forms: drag, spin through a bounce, throws;
and reality against the imagination."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adapt.imagination import World
from adapt.imagination.scene import Ball, SceneSpec, Wall
from adapt.reality.physics import ROLLING_SHARE, SPIN_TIME, RealWorld
from adapt.reality.truth import ObjectParameters
from adapt.scenario import loads_scenario

from .conftest import bundled, scenario, source

DT = 1.0 / 960.0
G = 9.81


def one_ball(v: tuple[float, float], *, drag: float = 0.0, spin: float = 0.0, rr: float = 0.0,
             e: float = 0.8, walls: tuple[Wall, ...] = (), appears: float | None = None,
             position: tuple[float, float] = (0.0, 0.0)) -> RealWorld:
    p = ObjectParameters("b", True, e, 0.0, rr, 0.4, drag, spin, appears, position, v)
    scene = SceneSpec(balls=(Ball("b", radius=0.1, restitution=e, friction=0.0,
                                  rolling_resistance=rr, position=position, velocity=v),),
                      walls=walls, gravity=G)
    return RealWorld(scene, (p,), dt=DT)


@pytest.mark.parametrize("drag, v0", [(0.05, 2.0), (0.3, 1.0)])
def test_drag_decelerates_as_drag_times_speed_squared(drag: float, v0: float) -> None:
    w = one_ball((v0, 0.0), drag=drag)
    for t in (0.5, 1.0, 2.0):
        w.run_until(t)
        v = v0 / (1.0 + drag * v0 * t)
        x = math.log(1.0 + drag * v0 * t) / drag
        assert w.velocity("b")[0] == pytest.approx(v, rel=2e-3)
        assert w.position("b")[0] == pytest.approx(x, rel=2e-3)


def test_drag_adds_to_the_rolling_resistance() -> None:
    # dv/dt = -c g - k v^2  =>  v(t) = a tan(atan(v0 / a) - k a t),  a = sqrt(c g / k)
    c, k, v0 = 0.03, 0.2, 2.0
    w = one_ball((0.0, v0), drag=k, rr=c)
    a = math.sqrt(c * G / k)
    for t in (0.5, 1.5):
        w.run_until(t)
        v = a * math.tan(math.atan(v0 / a) - k * a * t)
        assert w.velocity("b")[1] == pytest.approx(v, rel=5e-3)
    w.run_until(6.0)  # stops and stays stopped (never reversed)
    assert w.velocity("b") == pytest.approx((0.0, 0.0), abs=1e-9)


def bounce(spin: float, e: float = 0.8, speed: float = 2.0) -> tuple[RealWorld, float]:
    """A ball rolling head-on into a wall 1 m away; returns the world just after the
    bounce and the bounce time."""
    w = one_ball((speed, 0.0), spin=spin, e=e, walls=(Wall("w", (1.1, -1.0), (1.1, 1.0)),))
    while w.velocity("b")[0] > 0:
        w.step()
    return w, w.time


@pytest.mark.parametrize("spin", [0.25, 0.6, 1.0])
def test_spin_carries_through_a_head_on_bounce_and_the_rebound_settles(spin: float) -> None:
    e, speed = 0.8, 2.0
    w, tb = bounce(spin, e, speed)
    u0 = spin * (1 + e) * speed            # slip just after the bounce
    assert w.slip("b")[0] == pytest.approx(u0, rel=1e-3)
    assert -w.velocity("b")[0] == pytest.approx(e * speed, rel=1e-3)  # leaves at e V
    for dt in (0.05, SPIN_TIME, 0.3, 0.6):
        w.run_until(tb + dt)
        t = w.time - tb
        expected = -e * speed + ROLLING_SHARE * u0 * (1.0 - math.exp(-t / SPIN_TIME))
        assert w.velocity("b")[0] == pytest.approx(expected, abs=2e-3 * speed)
    # Settled after a few tenths of a second, to e V - (2/7) spin (1 + e) V.
    w.run_until(tb + 1.0)
    settled = e * speed - ROLLING_SHARE * spin * (1 + e) * speed
    assert -w.velocity("b")[0] == pytest.approx(settled, rel=1e-3)
    assert abs(w.slip("b")[0]) < 0.01 * u0


def test_without_spin_the_rebound_is_the_models() -> None:
    w, tb = bounce(0.0)
    w.run_until(tb + 0.5)
    assert -w.velocity("b")[0] == pytest.approx(0.8 * 2.0, rel=1e-6)
    assert w.slip("b") == (0.0, 0.0)


def test_an_oblique_bounce_off_a_frictionless_wall_keeps_the_slip_normal() -> None:
    w = one_ball((1.0, 1.0), spin=0.5, walls=(Wall("w", (1.0, -5.0), (1.0, 5.0)),))
    while w.velocity("b")[0] > 0:
        w.step()
    ux, uy = w.slip("b")
    assert ux == pytest.approx(0.5 * 1.8, rel=1e-3) and abs(uy) < 1e-9
    assert w.velocity("b")[1] == pytest.approx(1.0, rel=1e-9)


def test_free_rolling_with_resistance_is_never_taken_for_a_bounce() -> None:
    w = one_ball((1.5, 0.5), spin=1.0, rr=0.08)
    w.run_until(3.0)
    assert w.slip("b") == (0.0, 0.0) and w.velocity("b") == (0.0, 0.0)


def test_the_spin_marker_turns_with_the_rolling() -> None:
    # Rolling 2 pi r along +x turns the ball once about +y.
    r = 0.1
    w = one_ball((2 * math.pi * r, 0.0))
    w.run_until(0.25)
    o = w.orientation("b")
    assert np.allclose(o @ [0, 0, 1], [1, 0, 0], atol=1e-3)  # top went forward a quarter turn
    w.run_until(1.0)
    assert np.allclose(w.orientation("b"), np.eye(3), atol=5e-3)


# -- throws ------------------------------------------------------------------------------

THROW = """  objects:
    - {name: ball, drag: 0, rolling_resistance: 0, spin: 0,
       throw: {t: [0.2, 0.4], x: [-0.5, 0.5], y: [0.0, 0.5], speed: [0.5, 1.0], heading_deg: [60, 120]}}
"""


def test_a_thrown_object_appears_at_its_drawn_time_and_place() -> None:
    sc = scenario(THROW, run="run: {fps: 20, max_frames: 16}\n")
    for seed in (1, 2, 3):
        src = source(sc, seed)
        p = src.parameters.object("ball")
        assert 0.2 <= p.appears <= 0.4 and -0.5 <= p.position[0] <= 0.5
        assert 0.5 <= math.hypot(*p.velocity) <= 1.0
        appear_step = math.ceil(p.appears / src.reality.dt - 1e-9)
        t_appear = appear_step * src.reality.dt
        for frame in src:
            truth = src.truth.at(frame.index)
            pos = truth.position("ball")
            if frame.time < t_appear - 1e-9:
                assert pos is None
            else:
                dt = frame.time - t_appear
                assert pos == pytest.approx((p.position[0] + p.velocity[0] * dt,
                                             p.position[1] + p.velocity[1] * dt), abs=1e-6)
                assert truth.objects["ball"].velocity == pytest.approx(p.velocity, abs=1e-9)


def test_throws_differ_between_seeds_and_repeat_with_one() -> None:
    sc = scenario(THROW)
    draws = [source(sc, seed).parameters.object("ball") for seed in (1, 2, 1)]
    assert draws[0] == draws[2] and draws[0] != draws[1]


def test_an_object_of_reality_only_is_drawn_independently_of_the_others() -> None:
    one = scenario(THROW)
    two = scenario(THROW + "    - {name: box, radius: 0.2, throw: {t: [0, 1], x: 1, y: 1}}\n")
    a, b = source(one, 4).parameters, source(two, 4).parameters
    assert a.object("ball") == b.object("ball")
    assert not b.object("box").declared and 0 <= b.object("box").appears <= 1


# -- reality is not the imagination --------------------------------------------------------

def test_reality_diverges_from_the_imagination_from_the_same_start() -> None:
    sc = bundled("room.yaml")
    ball = sc.scene.balls[0]
    model = World(sc.scene)
    real = source(sc).world
    gaps = []
    for t in np.arange(0.5, 4.01, 0.5):
        model.run_until(t)
        real.run_until(t)
        gaps.append(math.dist(model.position("ball"), real.position("ball")))
    # The same initial state; reality's drag and spin pull it away (several ball radii).
    assert gaps[0] < 0.02 and max(gaps) > 3 * ball.radius


def test_without_drag_and_spin_and_at_the_models_step_reality_is_the_model() -> None:
    path = bundled("room.yaml").path
    assert path is not None
    exact = loads_scenario(path.read_text() + "reality:\n  dt: 0.004166666666666667\n"
                           "  objects: [{name: ball, drag: 0, spin: 0}]\n")
    model = World(exact.scene)
    real = source(exact).world
    for t in (1.0, 2.0, 4.0):
        model.run_until(t)
        real.run_until(t)
        assert math.dist(model.position("ball"), real.position("ball")) < 1e-9
