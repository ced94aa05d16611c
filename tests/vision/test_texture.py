"""flat_over_texture: a smooth object over a textured floor, found by its texture."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.errors import VisionError
from adapt.vision.texture import flat_over_texture, local_contrast


def gravel(seed: int, shape: tuple[int, int] = (80, 100), blur: float = 0.0) -> np.ndarray:
    """Grey gravel: grains of 2x2 px with grey levels 70-190 (mean 130), optionally blurred
    as a learned look is."""
    rng = np.random.default_rng(seed)
    grains = rng.integers(70, 190, (shape[0] // 2, shape[1] // 2), dtype=np.uint8)
    g = cv2.resize(grains, (shape[1], shape[0]), interpolation=cv2.INTER_NEAREST)
    if blur > 0:
        g = cv2.GaussianBlur(g, (0, 0), blur)
    return np.dstack([g, g, g])


def disc(shape: tuple[int, int], centre: tuple[int, int], radius: int) -> np.ndarray:
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]]
    return (xx - centre[0]) ** 2 + (yy - centre[1]) ** 2 <= radius ** 2


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), noise=st.floats(0.0, 3.0), blur=st.floats(0.0, 1.0),
       cx=st.integers(25, 75), cy=st.integers(25, 55))
def test_a_ball_of_the_gravels_colour_shows_whole_and_the_gravel_never(
        seed: int, noise: float, blur: float, cx: int, cy: int) -> None:
    # the reference is the gravel as a learned look has it (blurred up to 1 px); the real
    # frame has a smooth ball of the gravel's mean grey on it, with sensor noise.  (A look
    # blurred 1.2 px with noise of 3 levels a channel: 88 % of the ball is found)
    look = gravel(seed, blur=blur)
    rng = np.random.default_rng(seed + 1)
    real = gravel(seed).astype(float)
    ball = disc(real.shape[:2], (cx, cy), 14)
    real[ball] = 130.0
    real = np.clip(real + rng.normal(0, noise, real.shape), 0, 255).astype(np.uint8)
    flat = flat_over_texture(real, look)
    # (a window that reaches over the ball's edge onto grains near its grey may be flat
    # too: the flat area can spill up to a window's width, 5 px, past the outline)
    inside = disc(real.shape[:2], (cx, cy), 14 - 1)
    outside = ~disc(real.shape[:2], (cx, cy), 14 + 5)
    assert flat[inside].mean() >= 0.95
    assert not flat[outside].any()


@pytest.mark.parametrize("shift", [(0, 1), (1, 0), (1, 1), (0, 2), (2, 2), (0, 3)])
def test_a_look_a_few_pixels_off_is_not_flat(shift: tuple[int, int]) -> None:
    # the alignment is off: a per-pixel difference fires all over the gravel, its texture
    # does not change.  A pixel off, no pixel is flat; a whole grain or more off, a few
    # neighbourhoods of the look happen to be twice as rough as the real one's, single
    # pixels that an opening (as the object's search makes) removes
    look = gravel(3, blur=0.7)
    real = np.roll(gravel(3), shift, axis=(0, 1))
    flat = flat_over_texture(real, look)
    if max(shift) == 1:
        assert not flat.any()
    assert flat.mean() < 0.001
    opened = cv2.morphologyEx(flat.view(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    assert not opened.any()


def test_the_faces_of_bricks_are_not_objects() -> None:
    # a brick floor: flat faces 14x6 px between joints of 2 px.  The look learned while the
    # camera moved is blurred and half a brick off, so over many faces it is the rougher:
    # the faces are flat over "texture", but each a strip too narrow to hold an object
    rng = np.random.default_rng(1)
    bricks = np.full((96, 128), 60, np.uint8)
    for row, y in enumerate(range(0, 96, 8)):
        for x in range(-8 * (row % 2), 128, 16):
            bricks[y:y + 6, max(x, 0):max(x + 14, 0)] = rng.integers(110, 170)
    real = np.dstack([bricks] * 3)
    look = cv2.GaussianBlur(np.roll(real, (4, 8), axis=(0, 1)), (0, 0), 2.0)
    assert flat_over_texture(real, look, block=1).any()        # the faces, one by one
    assert not flat_over_texture(real, look, mean_within=30.0).any()


def test_a_smooth_floor_says_nothing() -> None:
    # the look itself is smooth (a painted floor): a smooth object over it is not flat
    # "over texture", whatever its colour -- the per-pixel difference is for that
    look = np.full((40, 40, 3), 120, np.uint8)
    real = look.copy()
    real[10:30, 10:30] = 121
    assert not flat_over_texture(real, look).any()


def test_only_a_patch_of_the_textures_mean_is_camouflage() -> None:
    # a smooth patch far darker than the gravel (a ghost in the look, an object the
    # per-pixel difference sees anyway) is flat over texture, but not of its mean
    look = gravel(7)
    real = look.copy()
    real[20:50, 30:60] = 40
    real[20:50, 65:95] = 130
    assert flat_over_texture(real, look)[30:40, 40:50].all()
    flat = flat_over_texture(real, look, mean_within=30.0)
    assert not flat[:, :62].any()
    assert flat[25:45, 70:90].all()


def test_grey_and_colour_images_agree() -> None:
    look = gravel(5)
    real = look.copy()
    real[20:50, 30:60] = 130
    assert (flat_over_texture(real, look) == flat_over_texture(real[..., 0], look[..., 0])).all()
    assert local_contrast(real).shape == real.shape[:2]


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"window": 4}, "odd number"),
    ({"window": 1}, "odd number"),
    ({"share": 1.0}, "flat share"),
    ({"share": 0.0}, "flat share"),
    ({"texture_min": -1.0}, "texture minimum"),
    ({"mean_within": -1.0}, "mean's tolerance"),
    ({"block": 0}, "flat block"),
])
def test_bad_parameters_are_refused(kwargs: dict[str, float], message: str) -> None:
    look = gravel(0)
    with pytest.raises(VisionError, match=message):
        flat_over_texture(look, look, **kwargs)  # type: ignore[arg-type]


def test_images_of_different_shapes_are_refused() -> None:
    with pytest.raises(VisionError, match="differ in shape"):
        flat_over_texture(gravel(0), gravel(0, shape=(80, 98)))
