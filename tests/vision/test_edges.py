"""Edge agreement peaks where the image's seams are, whatever the surfaces' textures."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from adapt.vision.edges import edge_agreement, seams


def _scene(rng: np.random.Generator, shift: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Labels of a floor, two walls and a box; an image of them with random textures,
    warped by ``shift`` pixels, blurred and noisy."""
    h, w = 120, 160
    labels = np.zeros((h, w), np.int32)
    labels[50:] = 1
    labels[20:50, 90:] = 2
    cv2.fillConvexPoly(labels, np.array([[40, 70], [80, 66], [84, 100], [44, 104]], np.int32), 3)
    image = np.zeros((h, w, 3), np.float32)
    for k in range(4):
        colour = rng.uniform(30, 220, 3)
        texture = rng.normal(0.0, 12.0, (h, w, 1))  # per-pixel grain, unrelated to the seams
        image[labels == k] = (colour + texture[labels == k])
    m = np.float32([[1, 0, shift[0]], [0, 1, shift[1]]])
    moved = cv2.warpAffine(image, m, (w, h), borderMode=cv2.BORDER_REFLECT)
    moved = cv2.GaussianBlur(moved, (0, 0), 0.8) + rng.normal(0, 3, moved.shape)
    return np.clip(moved, 0, 255).astype(np.uint8), labels


@pytest.mark.parametrize("true_shift", [(0.0, 0.0), (3.0, -2.0), (-4.0, 1.5)])
def test_agreement_is_highest_at_the_known_warp(rng: np.random.Generator,
                                                true_shift: tuple[float, float]) -> None:
    image, labels = _scene(rng, true_shift)
    h, w = labels.shape

    def at(dx: float, dy: float) -> float:
        m = np.float32([[1, 0, dx], [0, 1, dy]])
        warped = cv2.warpAffine(labels.astype(np.float32), m, (w, h), flags=cv2.INTER_NEAREST,
                                borderMode=cv2.BORDER_REPLICATE).astype(np.int32)
        return edge_agreement(image, warped)

    best = at(*true_shift)
    for dx in (-3.0, 0.0, 3.0):
        for dy in (-3.0, 0.0, 3.0):
            if (dx, dy) != (0.0, 0.0):
                off = at(true_shift[0] + dx, true_shift[1] + dy)
                assert off < best
                if dy != 0.0:  # off the long floor seam: most seam pixels miss their edge
                    assert off < 0.6 * best


def test_no_seams_say_nothing_and_sizes_must_match() -> None:
    image = np.zeros((10, 12, 3), np.uint8)
    assert math.isnan(edge_agreement(image, np.zeros((10, 12), np.int32)))
    with pytest.raises(ValueError, match="differ in size"):
        edge_agreement(image, np.zeros((12, 10), np.int32))
    assert not seams(np.ones((3, 3), np.int32)).any()
