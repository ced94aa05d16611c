"""Parameter estimates from sightings of a simulated ball whose parameters are known."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.imagination import Ball, SceneSpec, Wall, World
from adapt.schemas.estimator import ParameterEstimator, nearest_surface

WALLS = (Wall("north", (-3, 2), (3, 2), restitution=0.9, friction=0.5),
         Wall("east", (2, -3), (2, 3), restitution=1.0, friction=0.5))


def sightings(ball: Ball, seconds: float, noise: float, seed: int = 0):  # type: ignore[no-untyped-def]
    scene = SceneSpec(walls=WALLS, balls=(ball,))
    world = World(scene)
    rng = np.random.default_rng(seed)
    for k in range(int(seconds * 30)):
        world.run_until(k / 30)
        x, y = world.position(ball.name)
        yield k / 30, (x + rng.normal(0, noise), y + rng.normal(0, noise)), scene


def run(ball: Ball, seconds: float = 2.5, noise: float = 0.003, seed: int = 0,
        ranges: dict[str, tuple[float, float]] | None = None) -> ParameterEstimator:
    est = None
    known = {"restitution": (0.5, 0.95), "friction": (0.1, 0.6), "rolling_resistance": (0.0, 0.08)}
    known.update(ranges or {})
    for t, p, scene in sightings(ball, seconds, noise, seed):
        if est is None:
            est = ParameterEstimator(known, scene=scene, radius=ball.radius)
        est.observe(t, p, noise=noise)
    assert est is not None
    return est


@pytest.mark.parametrize("e", [0.6, 0.75, 0.9])
def test_restitution_from_a_head_on_bounce(e: float) -> None:
    ball = Ball("b", radius=0.1, restitution=e, rolling_resistance=0.0, position=(0.0, 0.5),
                velocity=(0.0, 1.6))
    est = run(ball, 2.0)
    assert [b.surface for b in est.bounces][:1] == ["north"]
    r = est.estimate("restitution")
    assert abs(r.mean - e) < 0.04 and r.count >= 1 and r.std < 0.05


def test_rolling_resistance_from_deceleration() -> None:
    ball = Ball("b", radius=0.1, rolling_resistance=0.04, position=(-1.0, -1.0),
                velocity=(1.2, 0.3))
    est = run(ball, 2.0)
    rr = est.estimate("rolling_resistance")
    # one measurement for the stretch, refitted as it grew: within 2 mm/s² per g of the truth
    assert abs(rr.mean - 0.04) < 0.004 and rr.count == 1 and rr.std < 0.005


def test_rolling_far_outside_the_range_is_learned_not_held_back_by_the_prior() -> None:
    ball = Ball("b", radius=0.1, rolling_resistance=0.01, position=(-1.0, -1.0),
                velocity=(1.0, 0.25))
    est = run(ball, 2.5, ranges={"rolling_resistance": (0.04, 0.08)})
    rr = est.estimate("rolling_resistance")
    assert abs(rr.mean - 0.01) < 0.004 and rr.surprise > 2.0


def test_an_oblique_bounce_measures_friction_in_range() -> None:
    ball = Ball("b", radius=0.1, restitution=0.8, friction=0.3, position=(0.5, 0.0),
                velocity=(1.5, 1.0))
    est = run(ball, 1.5)
    (first, *_) = est.bounces
    assert first.surface == "east" and first.restitution is not None
    assert abs(first.restitution - 0.8) < 0.08


def test_estimates_may_leave_the_range_and_say_so() -> None:
    est = ParameterEstimator({"restitution": (0.6, 0.9)})
    for _ in range(5):
        est.measure("restitution", 0.3, 0.02)
    e = est.estimate("restitution")
    assert e.mean < 0.4 and e.surprise > 2


def test_no_bounce_no_measurement_of_restitution() -> None:
    ball = Ball("b", radius=0.1, position=(-1.0, 0.0), velocity=(0.8, 0.0))
    est = run(ball, 1.0)
    assert est.bounces == [] and est.estimate("restitution").count == 0


def test_nearest_surface_of_an_obstacle() -> None:
    from adapt.imagination import Obstacle

    s = SceneSpec(obstacles=(Obstacle("box", ((0, 0), (1, 0), (1, 1), (0, 1)), 0.5,
                                      restitution=0.7),))
    name, d, n, e, _ = nearest_surface(s, (0.5, 1.2))  # type: ignore[misc]
    assert name == "box" and abs(d - 0.2) < 1e-9 and n == (0.0, 1.0) and e == 0.7
