"""The MMD image and its regions: brightness/colour shifts are not difference,
uncovered pixels are unknown, and an object only in the real view is the one
unexpected region."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from adapt.vision.mmd import mmd
from adapt.vision.regions import find_regions, label_regions

from . import scenes


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / max((a | b).sum(), 1))


@pytest.mark.parametrize("name, seed", [("room", 0), ("coffee", 1), ("brick", 2), ("gravel", 3)])
def test_object_only_in_the_real_view_is_the_one_unexpected_region(name, seed):
    real, synthetic, *_ = scenes.pair(name, seed)
    real, silhouette = scenes.paste_object(real, np.random.default_rng(seed + 100))
    r = mmd(real, synthetic)
    regions = label_regions(find_regions(r.difference), monitored=[])
    assert len(regions) == 1, [x.area for x in regions]
    (found,) = regions
    assert not found.expected
    assert iou(found.to_mask(real.shape), silhouette) >= 0.7
    ys, xs = np.nonzero(silhouette)
    assert found.centroid == pytest.approx((xs.mean(), ys.mean()), abs=6)


def test_monitored_object_is_expected():
    real, synthetic, *_ = scenes.pair("room", 4)
    real, silhouette = scenes.paste_object(real, np.random.default_rng(9))
    ys, xs = np.nonzero(silhouette)
    box = (xs.min() - 5, ys.min() - 5, np.ptp(xs) + 10, np.ptp(ys) + 10)
    regions = label_regions(find_regions(mmd(real, synthetic).difference), [box])
    assert regions and all(r.expected for r in regions)
    far = label_regions(regions, [(0, 0, 20, 20)])
    assert not any(r.expected for r in far)


@pytest.mark.parametrize("gain, bias", [(0.6, 40.0), (0.75, -10.0)])
def test_global_brightness_change_is_not_difference(gain, bias):
    real, synthetic, *_ = scenes.pair("coffee", 5)
    darker = cv2.convertScaleAbs(synthetic, alpha=gain, beta=bias)
    r = mmd(real, darker)
    assert r.aligned
    assert find_regions(r.difference) == ()
    assert np.percentile(r.difference[r.known], 99) < 30


def test_colour_cast_is_not_difference():
    real, synthetic, *_ = scenes.pair("coffee", 6)
    # (a cast that does not clip: clipped highlights are a real difference)
    cast = np.clip(synthetic * np.array([0.8, 1.0, 0.9]) + [30, 0, 20], 0, 255).astype(np.uint8)
    r = mmd(real, cast)
    assert r.aligned and find_regions(r.difference) == ()
    plain = mmd(real, synthetic)
    assert r.gain / plain.gain == pytest.approx([1 / 0.8, 1.0, 1 / 0.9], rel=0.05)


def test_pixels_the_warp_does_not_cover_are_unknown_not_difference():
    real, synthetic, h_true, *_ = scenes.pair("room", 7)
    r = mmd(real, synthetic)
    # where the true homography sends no synthetic pixel, nothing is known
    inv = np.linalg.inv(h_true)
    ys, xs = np.mgrid[0:480:8, 0:640:8]
    p = np.c_[xs.ravel(), ys.ravel(), np.ones(xs.size)] @ inv.T
    p = p[:, :2] / p[:, 2:]
    outside = ((p[:, 0] < -2) | (p[:, 0] > 641) | (p[:, 1] < -2) | (p[:, 1] > 481)).reshape(xs.shape)
    assert outside.any()
    assert not r.known[ys[outside], xs[outside]].any()
    assert not r.difference[~r.known].any()
    assert r.known.mean() > 0.7


def test_exact_and_fast_masks_give_the_same_regions():
    real, synthetic, *_ = scenes.pair("room", 8)
    real, _ = scenes.paste_object(real, np.random.default_rng(3))
    a = find_regions(mmd(real, synthetic).difference)
    b = find_regions(mmd(real, synthetic, exact=True).difference)
    assert len(a) == len(b) == 1
    assert abs(a[0].area - b[0].area) < 0.05 * a[0].area


@pytest.mark.parametrize("max_pixels", [None, 320 * 240])
def test_a_held_homography_is_used_when_the_matches_give_none(max_pixels):
    # (the Scene Background holds H_e from its structure alignment for a frame whose
    # matches give none: an aliased texture, a plain face filling the view)
    real, synthetic, h_true, *_ = scenes.pair("room", 7)
    real, silhouette = scenes.paste_object(real, np.random.default_rng(3))
    none = mmd(real, synthetic, min_inliers=10**6, max_pixels=max_pixels)
    assert not none.aligned and not none.alignment.held
    r = mmd(real, synthetic, min_inliers=10**6, max_pixels=max_pixels, hold=h_true)
    assert r.aligned and r.alignment.held and r.n_inliers == 0
    assert r.alignment.reason == none.alignment.reason
    np.testing.assert_allclose(r.homography, h_true / h_true[2, 2], rtol=1e-6, atol=1e-6)
    # compared through the held H_e: the pasted object is the largest difference
    largest = max(r.regions(), key=lambda x: x.area)
    assert iou(largest.to_mask(real.shape), silhouette) >= 0.5
    # matches that give an H_e win over the held one
    assert not mmd(real, synthetic, max_pixels=max_pixels, hold=np.eye(3)).alignment.held
