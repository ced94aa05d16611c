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


def test_a_fast_balls_path_is_settled_and_its_median_the_floor() -> None:
    # the first look learns what the frames agree on: a ball that crossed each pixel of its
    # path in a few frames between the oldest and the newest leaves the floor there
    frames = frames_with_a_ball(5, speed=12, noise=2.0)  # centres at x = 10, 22, 34, 46, 58
    h = FrameHistory(12)
    for f in frames:
        h.push(f)
    between = np.zeros((60, 120), bool)
    between[30, 19:50] = True  # crossed by the middle three frames only
    assert not h.still(gate=30.0)[between].any()
    assert h.settled(gate=30.0, share=0.55)[between].all()
    floor = np.random.default_rng(0).integers(60, 200, (60, 120, 3), dtype=np.uint8)
    assert np.abs(h.median().astype(int) - floor.astype(int))[between].max() <= 8
    # where it stood at the oldest frame and stands at the newest the frames cannot say
    # whether it left the floor or arrived on it: not settled, though a majority agree
    for x in (10, 58):
        assert not h.settled(gate=30.0, share=0.55)[30, x]
        assert h.settled(gate=30.0, share=0.55, ends=False)[30, x]


def test_a_slow_balls_path_is_not_settled_where_it_stayed_longest() -> None:
    # 2 px a frame, 17 px across: the middle of the path is covered in 8 of 12 frames; the
    # ball's own colour is then the median and most frames agree with it, but neither the
    # oldest frame nor the newest does: not settled (it would be learned as a ghost)
    h = FrameHistory(12)
    for f in frames_with_a_ball(12, speed=2):
        h.push(f)
    middle = (30, 21)
    assert tuple(h.median()[middle]) == (30, 30, 230)
    assert not h.settled(gate=30.0, share=0.55)[middle]
    assert h.settled(gate=30.0, share=0.55, ends=False)[middle]  # the frames agree: on the ball
    # and where it stood at the start (covered in the 5 oldest frames) neither
    assert not h.settled(gate=30.0, share=0.55)[30, 10]


def test_settled_is_still_with_few_frames_and_refuses_a_minority_share() -> None:
    h = FrameHistory(12)
    for f in frames_with_a_ball(2, speed=12):
        h.push(f)
    assert np.array_equal(h.settled(gate=30.0, share=0.55), h.still(gate=30.0))
    with pytest.raises(VisionError, match="share"):
        h.settled(gate=30.0, share=0.5)
    assert FrameHistory(3).settled(gate=30.0, share=0.6).shape == (0, 0)
