"""The constant-velocity Kalman filter's measurement noise, fixed or estimated from the
measurements' scatter (``window``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.kalman import ConstantVelocityKF

DT = 1 / 30


def _roll(kf: ConstantVelocityKF, n: int, sigma: float, seed: int,
          velocity: tuple[float, float] = (1.0, 0.0)) -> list[float]:
    """Feed ``n`` sightings of a straight roll, scattered ``sigma`` m; the filter's velocity
    error after each."""
    rng = np.random.default_rng(seed)
    errors = []
    for k in range(n):
        t = k * DT
        z = (velocity[0] * t + rng.normal(0, sigma), 1.0 + velocity[1] * t + rng.normal(0, sigma))
        kf.step(t, z)
        errors.append(math.dist(kf.velocity, velocity))
    return errors


@settings(max_examples=30, deadline=None)
@given(vx=st.floats(-3, 3), vy=st.floats(-3, 3), n=st.integers(3, 60))
def test_exact_sightings_leave_the_noise_at_r_and_the_filter_as_it_was(vx: float, vy: float,
                                                                       n: int) -> None:
    fixed = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0)
    adaptive = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=15)
    _roll(fixed, n, 0.0, 0, (vx, vy))
    _roll(adaptive, n, 0.0, 0, (vx, vy))
    assert adaptive.noise == pytest.approx(0.005)
    assert np.allclose(adaptive.x, fixed.x) and np.allclose(adaptive.P, fixed.P)


@pytest.mark.parametrize("sigma", [0.01, 0.02, 0.04])
def test_the_noise_is_measured_from_the_scatter(sigma: float) -> None:
    estimates = []
    for seed in range(10):
        kf = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=40)
        _roll(kf, 80, sigma, seed)
        estimates.append(kf.noise)
    assert float(np.median(estimates)) == pytest.approx(sigma, rel=0.25)


def test_scattered_sightings_no_longer_restart_the_filter_nor_throw_its_velocity() -> None:
    fixed_restarts, adaptive_restarts, fixed_err, adaptive_err = [], [], [], []
    for seed in range(10):
        fixed = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0)
        adaptive = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=15)
        fixed_err += _roll(fixed, 90, 0.03, seed)[30:]
        adaptive_err += _roll(adaptive, 90, 0.03, seed)[30:]
        fixed_restarts.append(fixed.restarts)
        adaptive_restarts.append(adaptive.restarts)
    assert min(fixed_restarts) > 20
    assert max(adaptive_restarts) <= 2
    assert np.median(adaptive_err) < 0.5 * np.median(fixed_err)


def test_a_bounce_among_precise_sightings_still_restarts_the_filter_at_once() -> None:
    rng = np.random.default_rng(1)
    kf = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=15)
    for k in range(60):
        t = k * DT
        x = t if t < 1.0 else 2.0 - t  # off a wall at x = 1 after 1 s
        kf.step(t, (x + rng.normal(0, 0.002), 1.0 + rng.normal(0, 0.002)))
        if k == 29:
            assert kf.restarts == 0
        if k == 31:
            assert kf.restarts == 1 and kf.velocity[0] < -0.8
    assert kf.restarts == 1 and kf.noise < 0.006
    assert kf.velocity[0] == pytest.approx(-1.0, abs=0.1)


def test_a_copy_carries_the_measured_noise_on() -> None:
    kf = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=15)
    _roll(kf, 30, 0.03, 3)
    twin = kf.copy()
    assert twin.noise == kf.noise and twin.window == 15
    rng = np.random.default_rng(4)
    for k in range(30, 40):
        z = (k * DT + rng.normal(0, 0.03), 1.0 + rng.normal(0, 0.03))
        kf.step(k * DT, z)
        twin.step(k * DT, z)
    assert np.allclose(kf.x, twin.x) and twin.noise == kf.noise


def test_a_negative_window_is_refused() -> None:
    with pytest.raises(ValueError, match="window"):
        ConstantVelocityKF(window=-1)
