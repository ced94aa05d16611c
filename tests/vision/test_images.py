"""Bad input: a clear error or an explicit "no alignment", never a crash and
never a wrong homography presented as good."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from adapt.errors import ImageError, VisionError
from adapt.vision.homography import corner_error
from adapt.vision.images import as_uint8, check_image, check_pair, conform, read_image, write_image
from adapt.vision.mmd import mmd

from . import scenes


@pytest.fixture(scope="module")
def photo_pair():
    real, synthetic, *_ = scenes.pair("coffee", 1)
    return real, synthetic


@pytest.mark.parametrize(
    "make, words",
    [
        (lambda r, s: (r, cv2.resize(s, (320, 240))), "320x240"),
        (lambda r, s: (r, s.astype(np.float32)), r"values from 0 to 255: expected values in \[0, 1\]"),
        (lambda r, s: (r, np.dstack([s, s[:, :, :1]])), "4 channels"),
        (lambda r, s: (r[:10, :10], s[:10, :10]), "10x10 pixels: expected at least 32x32"),
        (lambda r, s: (r.astype(np.int32), s.astype(np.int32)), "dtype int32"),
        (lambda r, s: (r.tolist(), s), "NumPy array"),
        (lambda r, s: (np.full(r.shape, np.nan, np.float32), s.astype(np.float32)), "NaN"),
    ],
)
def test_incompatible_images_raise_a_clear_vision_error(photo_pair, make, words):
    real, synthetic = make(*photo_pair)
    with pytest.raises(VisionError, match=words):
        mmd(real, synthetic)


@pytest.mark.parametrize(
    "real_kind, synthetic_kind",
    [("blank", "photo"), ("photo", "blank"), ("blank", "blank"), ("photo", "other photo"),
     ("noise", "other noise")],
)
def test_no_alignment_is_explicit(photo_pair, real_kind, synthetic_kind):
    real_photo, synthetic_photo = photo_pair
    rng = np.random.default_rng(7)
    other = scenes.view(scenes.world("brick"), scenes.camera())
    kinds = {
        "blank": np.full_like(real_photo, 128),
        "photo": real_photo,
        "other photo": cv2.cvtColor(other, cv2.COLOR_GRAY2BGR),
        "noise": rng.integers(0, 256, real_photo.shape, dtype=np.uint8),
        "other noise": rng.integers(0, 256, real_photo.shape, dtype=np.uint8),
    }
    r = mmd(kinds[real_kind], kinds[synthetic_kind])
    assert not r.aligned
    assert r.homography is None and r.n_inliers == 0
    assert r.alignment.reason
    assert not r.known.any() and not r.difference.any()


def test_dtypes_other_than_uint8_are_accepted_when_they_agree(photo_pair):
    real, synthetic = photo_pair
    a = mmd(real, synthetic)
    b = mmd(real.astype(np.uint16) * 257, synthetic.astype(np.uint16) * 257)
    c = mmd(real.astype(np.float64) / 255.0, synthetic.astype(np.float64) / 255.0)
    assert a.aligned and b.aligned and c.aligned
    assert np.allclose(a.homography, b.homography, atol=1e-6)
    assert np.abs(a.homography - c.homography).max() < 1e-3


@pytest.mark.parametrize(
    "convert",
    [
        lambda r, s: (cv2.cvtColor(r, cv2.COLOR_BGR2GRAY), s),                      # grey camera
        lambda r, s: (r, cv2.cvtColor(s, cv2.COLOR_BGR2GRAY)),                      # grey rendering
        lambda r, s: (r.astype(np.uint16) * 257, s),                                # 16-bit camera
        lambda r, s: (cv2.cvtColor(r, cv2.COLOR_BGR2GRAY).astype(np.uint16) * 257, s),
        lambda r, s: (r, s.astype(np.float32) / 255.0),                             # float rendering
    ],
    ids=["grey-real", "grey-synthetic", "uint16-real", "grey-uint16-real", "float-synthetic"],
)
def test_mixed_dtypes_and_channels_are_converted_by_one_rule(photo_pair, convert):
    real, synthetic = photo_pair
    plain = mmd(real, synthetic)
    r, s = convert(real, synthetic)
    mixed = mmd(r, s)
    assert mixed.aligned
    assert corner_error(mixed.homography, plain.homography, real.shape) < 0.3
    grey = r.ndim == 2 or s.ndim == 2
    assert mixed.difference.shape == real.shape[:2]
    assert mixed.warped.ndim == (2 if grey else 3) and mixed.warped.dtype == np.uint8
    # the conversion mmd uses is conform(): 8-bit, grey when either is grey
    cr, cs = conform(r, s)
    assert cr.dtype == cs.dtype == np.uint8 and cr.shape == cs.shape
    assert cr.ndim == (2 if grey else 3)


def test_conform_does_not_copy_what_needs_no_conversion(photo_pair):
    real, synthetic = photo_pair
    r, s = conform(real, synthetic)
    assert r is real and s is synthetic


def test_messages_name_the_file_and_the_minimum_size():
    with pytest.raises(VisionError) as err:
        check_image(np.zeros((1, 1, 3), np.uint8), "real", source="shots/one.png")
    assert str(err.value) == "shots/one.png: real image is 1x1 pixels: expected at least 32x32 pixels"
    with pytest.raises(VisionError) as err:
        check_image(np.zeros((1, 1), np.uint8))
    assert str(err.value) == "image is 1x1 pixels: expected at least 32x32 pixels"
    with pytest.raises(VisionError, match="real image a.png is 40x40 but synthetic image b.png is 50x40"):
        check_pair(np.zeros((40, 40), np.uint8), np.zeros((40, 50), np.uint8), sources=("a.png", "b.png"))


def test_inputs_are_not_modified(photo_pair):
    real, synthetic = photo_pair
    r0, s0 = real.copy(), synthetic.copy()
    mmd(real, synthetic)
    assert np.array_equal(real, r0) and np.array_equal(synthetic, s0)


def test_as_uint8_scales_each_dtype():
    assert as_uint8(np.array([[0, 65535]], np.uint16)).tolist() == [[0, 255]]
    assert as_uint8(np.array([[-1.0, 2.0]])).tolist() == [[0, 255]]


def test_check_pair_returns_the_arrays_unchanged(photo_pair):
    real, synthetic = photo_pair
    r, s = check_pair(real, synthetic)
    assert r is real and s is synthetic


def test_unreadable_files_raise_image_error(tmp_path):
    with pytest.raises(ImageError, match="no such file"):
        read_image(tmp_path / "missing.png")
    with pytest.raises(ImageError, match="directory"):
        read_image(tmp_path)
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"not a png at all")
    with pytest.raises(ImageError, match="decode"):
        read_image(bad)
    empty = tmp_path / "empty.png"
    empty.write_bytes(b"")
    with pytest.raises(ImageError, match="decode"):
        read_image(empty)


def test_write_image_is_atomic_and_round_trips(tmp_path, photo_pair):
    real, _ = photo_pair
    out = write_image(tmp_path / "x.png", real)
    assert np.array_equal(read_image(out), real)
    with pytest.raises(ImageError):
        write_image(tmp_path / "x.notanimageformat", real)
    with pytest.raises(ImageError):
        write_image(tmp_path / "no" / "dir" / "x.png", real)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.png"]
