"""The MMD mask: exact sum of Gaussians and the fast approximation (within 0.1)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.vision.mask import SIGMA, exact_mask, fast_mask


def test_exact_mask_is_the_clipped_sum():
    pts = np.array([[100.0, 50.0], [110.0, 50.0], [300.0, 200.0]])
    q = np.array([0.5, 0.25, 1.0])
    m = exact_mask(pts, q, (240, 320), sigma=SIGMA)
    x, y = 105, 50
    expected = sum(
        qi * np.exp(-((x - px) ** 2 + (y - py) ** 2) / (2 * SIGMA**2)) for (px, py), qi in zip(pts, q)
    )
    assert m[y, x] == pytest.approx(min(expected, 1.0), abs=1e-6)
    assert m.max() == pytest.approx(1.0)
    assert m.min() >= 0 and m.dtype == np.float32
    assert m[0, 319] < 1e-6


@pytest.mark.parametrize("k", [0.5, 2.0])
def test_default_width_scales_with_the_image(k):
    # one match, at the same place relative to the image: the same mask, scaled
    ref = exact_mask([[320.0, 240.0]], [1.0], (480, 640))
    h, w = int(480 * k), int(640 * k)
    m = exact_mask([[(320.5 * k) - 0.5, (240.5 * k) - 0.5]], [1.0], (h, w))
    back = cv2.resize(m, (640, 480), interpolation=cv2.INTER_LINEAR)
    assert np.abs(back - ref).max() < 0.02
    fast = fast_mask([[(320.5 * k) - 0.5, (240.5 * k) - 0.5]], [1.0], (h, w))
    assert np.abs(fast - m).max() < 0.1


def test_empty_mask_is_zero():
    assert not fast_mask(np.zeros((0, 2)), np.zeros(0), (480, 640)).any()
    assert not exact_mask(np.zeros((0, 2)), np.zeros(0), (480, 640)).any()


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(1, 400),
    seed=st.integers(0, 2**32 - 1),
    clustered=st.booleans(),
    size=st.sampled_from([(480, 640), (240, 320), (123, 257)]),
)
def test_fast_mask_is_within_0_1_of_exact_everywhere(n, seed, clustered, size):
    rng = np.random.default_rng(seed)
    h, w = size
    if clustered:
        centre = rng.uniform([0, 0], [w - 1, h - 1])
        pts = np.clip(rng.normal(centre, 25, (n, 2)), 0, [w - 1, h - 1])
    else:
        pts = rng.uniform([0, 0], [w - 1, h - 1], (n, 2))
    q = rng.uniform(0.05, 1.0, n)
    err = np.abs(fast_mask(pts, q, size) - exact_mask(pts, q, size))
    assert err.max() < 0.1


@pytest.mark.parametrize("x, y", [(0.0, 0.0), (639.0, 479.0), (0.0, 240.0), (321.3, 17.8)])
def test_fast_mask_single_points_at_borders(x, y):
    pts, q = np.array([[x, y]]), np.array([1.0])
    assert np.abs(fast_mask(pts, q, (480, 640)) - exact_mask(pts, q, (480, 640))).max() < 0.1
