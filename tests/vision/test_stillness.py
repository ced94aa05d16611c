"""FrameHistory: which pixels of a fixed camera's recent frames held still, their median."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.errors import VisionError
from adapt.vision.stillness import FrameHistory


def frames_with_a_ball(n: int, speed: int, noise: float = 0.0, seed: int = 0) -> list[np.ndarray]:
    """A textured floor (fixed) with a red disc of radius 8 crossing it, ``speed`` px a frame."""
    rng = np.random.default_rng(seed)
    floor = rng.integers(60, 200, (60, 120, 3), dtype=np.uint8)
    yy, xx = np.mgrid[0:60, 0:120]
    out = []
    for k in range(n):
        f = floor.astype(float) + rng.normal(0, noise, floor.shape)
        disc = (xx - (10 + speed * k)) ** 2 + (yy - 30) ** 2 <= 64
        f[disc] = (30, 30, 230)
        out.append(np.clip(f, 0, 255).astype(np.uint8))
    return out


def test_the_median_of_a_moving_ball_is_the_floor_and_its_path_never_still() -> None:
    frames = frames_with_a_ball(12, speed=8, noise=2.0)
    h = FrameHistory(12)
    for f in frames:
        h.push(f)
    median = h.median().astype(int)
    floor = np.random.default_rng(0).integers(60, 200, (60, 120, 3), dtype=np.uint8).astype(int)
    assert np.abs(median - floor).max() <= 8  # noise of 2 grey levels, no ball anywhere
    still = h.still(gate=30.0)
    path = np.zeros((60, 120), bool)
    path[30, 10:100] = True
    assert not still[path].any()               # every pixel the ball crossed changed
    assert still[5:15, :].all() and still[50:, :].all()  # the floor it never crossed held


def test_a_ball_at_rest_is_still_and_a_slow_one_is_not() -> None:
    for speed, expect in ((0, True), (2, False)):
        h = FrameHistory(3)
        for f in frames_with_a_ball(3, speed=speed, noise=2.0):
            h.push(f)
        changed = h.changed((2, 22, 40, 17), gate=30.0)
        assert (changed < 0.02) is expect, (speed, changed)


def test_clear_and_a_new_size_restart_the_history() -> None:
    h = FrameHistory(4)
    h.push(np.zeros((10, 10, 3), np.uint8))
    h.push(np.zeros((10, 10, 3), np.uint8))
    assert len(h) == 2
    h.push(np.zeros((12, 10, 3), np.uint8))
    assert len(h) == 1
    h.clear()
    assert len(h) == 0 and h.still(10.0).shape == (0, 0) and h.changed((0, 0, 5, 5), 10.0) == 0.0
    with pytest.raises(VisionError, match="no frame"):
        h.median()
    with pytest.raises(VisionError, match="at least 1"):
        FrameHistory(0)
