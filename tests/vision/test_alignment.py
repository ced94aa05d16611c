"""Round trips: the shipped photographs seen through cameras rotated by known
amounts; H_e must match the exact H_true = K R_r R_s^T K^-1."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.vision.homography import MIN_INLIERS, corner_error, estimate_homography
from adapt.vision.matching import Matches, match, match_descriptors, prepare
from adapt.vision.mmd import mmd

from . import scenes


@pytest.mark.parametrize("name", ["room", "coffee", "brick", "gravel", "grass"])
def test_recovered_homography_matches_the_true_one(name):
    errors = []
    for seed in range(4):
        real, synthetic, h_true, *_ = scenes.pair(name, seed)
        r = mmd(real, synthetic)
        assert r.aligned, r.alignment.reason
        assert r.n_inliers >= MIN_INLIERS
        errors.append(corner_error(r.homography, h_true, real.shape))
    assert max(errors) < 2.0, errors
    assert float(np.median(errors)) < 0.6, errors


def test_prepared_synthetic_gives_the_same_answer():
    real, synthetic, h_true, *_ = scenes.pair("room", 2)
    a = mmd(real, synthetic)
    b = mmd(real, prepare(synthetic))
    assert np.allclose(a.homography, b.homography)


def test_tracking_quality_is_in_0_1_and_matches_point_the_right_way():
    real, synthetic, h_true, *_ = scenes.pair("gravel", 3, look=False, noise=False)
    m = match(real, synthetic)
    assert m.method == "lk" and len(m) > 100
    assert ((m.quality > 0) & (m.quality <= 1)).all()
    p = np.c_[m.synthetic_points, np.ones(len(m))] @ h_true.T
    p = p[:, :2] / p[:, 2:]
    assert np.median(np.linalg.norm(p - m.real_points, axis=1)) < 0.2


def test_large_offsets_are_reacquired_with_descriptors():
    # 12 degrees of pan: far beyond LK's reach (about 110 px).
    real, synthetic, h_true, *_ = scenes.pair("room", 5, pan_tilt_deg=12.0, roll_deg=10.0)
    offset = corner_error(h_true, np.eye(3), real.shape)
    assert offset > 60
    r = mmd(real, synthetic)
    assert r.aligned and r.matches.method == "sift"
    assert corner_error(r.homography, h_true, real.shape) < 2.0
    assert len(match_descriptors(real, synthetic)) > 50


def test_estimator_rejects_clustered_inliers():
    rng = np.random.default_rng(0)
    src = rng.uniform(300, 340, (50, 2))  # all within 40 px: H would be extrapolated
    a = estimate_homography(Matches(src + 3.0, src, np.ones(50), "lk"), (480, 640))
    assert not a.aligned and "span" in a.reason


def test_estimator_rejects_random_matches():
    rng = np.random.default_rng(1)
    src = rng.uniform(0, 640, (200, 2)) * [1, 0.75]
    dst = rng.uniform(0, 640, (200, 2)) * [1, 0.75]
    a = estimate_homography(Matches(dst, src, np.ones(200), "lk"), (480, 640))
    assert not a.aligned and a.homography is None and a.n_inliers == 0
