"""``adapt.figures.write_strip``: what is drawn is what was given (colour order,
grey ranges, overlays), every supported image kind draws, and a failed write
leaves nothing behind."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from adapt.errors import ImageError
from adapt.figures import Panel, write_strip


def centre_colour(png: np.ndarray, fx: float, fy: float) -> np.ndarray:
    """BGR of the written figure at a fraction (fx, fy) of its size."""
    h, w = png.shape[:2]
    return png[int(fy * h), int(fx * w)].astype(int)


def test_bgr_panels_keep_their_colours_and_grey_ranges(tmp_path):
    blue = np.zeros((100, 100, 3), np.uint8)
    blue[:] = (255, 0, 0)  # BGR blue
    mid_grey8 = np.full((100, 100), 128, np.uint8)
    mask = np.full((100, 100), 0.5, np.float32)  # a [0, 1] float: shown from 0 to 1
    out = write_strip(tmp_path / "s.png", [[("blue", blue), ("grey", mid_grey8), ("mask", mask)]])
    png = cv2.imread(str(out))
    assert png is not None
    b, g, r = centre_colour(png, 1 / 6, 0.6)
    assert b > 200 and g < 40 and r < 40
    for fx in (0.5, 5 / 6):
        b, g, r = centre_colour(png, fx, 0.6)
        assert abs(b - 128) < 12 and b == g == r


def test_every_image_kind_draws(tmp_path):
    rng = np.random.default_rng(0)
    kinds = [
        ("bgr uint8", rng.integers(0, 256, (48, 64, 3), dtype=np.uint8)),
        ("bgra", rng.integers(0, 256, (48, 64, 4), dtype=np.uint8)),
        ("uint16 colour", rng.integers(0, 65536, (48, 64, 3), dtype=np.uint16)),
        ("grey uint16", rng.integers(0, 65536, (48, 64), dtype=np.uint16)),
        ("bool", rng.random((48, 64)) > 0.5),
        ("grey levels", rng.uniform(0, 200, (48, 64)).astype(np.float32)),
        ("with nan", np.where(rng.random((48, 64)) > 0.5, np.nan, 1.0)),
        ("flat", np.full((48, 64), 7.0)),
        ("one channel", rng.integers(0, 256, (48, 64, 1), dtype=np.uint8)),
        ("another size", rng.integers(0, 256, (96, 128), dtype=np.uint8)),
    ]
    rows = [kinds[:5], kinds[5:8], kinds[8:]]  # rows of different lengths
    out = write_strip(tmp_path / "all.png", rows, title="every kind\nin three rows")
    png = cv2.imread(str(out))
    assert png is not None and png.shape[1] > png.shape[0]


def test_overlays_are_drawn(tmp_path):
    black = np.zeros((100, 100), np.uint8)
    plain = cv2.imread(str(write_strip(tmp_path / "a.png", [[("x", black)]])))
    marked = cv2.imread(str(write_strip(
        tmp_path / "b.png",
        [[Panel("x", black, points=[(np.array([[50.0, 50.0]]), "lime")], boxes=[((10, 10, 30, 20), "red")])]],
    )))
    assert plain.shape == marked.shape
    diff = np.abs(marked.astype(int) - plain.astype(int)).sum(axis=2) > 60
    changed = marked[diff]
    assert (changed[:, 1] > 150).any()  # green circle
    assert ((changed[:, 2] > 150) & (changed[:, 1] < 80)).any()  # red box


@pytest.mark.parametrize("suffix, magic", [(".pdf", b"%PDF"), (".svg", b"<?xml")])
def test_vector_formats(tmp_path, suffix, magic):
    out = write_strip(tmp_path / f"s{suffix}", [[("x", np.zeros((20, 30), np.uint8))]])
    assert out.read_bytes().startswith(magic)


def test_errors_leave_nothing_behind(tmp_path):
    img = np.zeros((20, 30), np.uint8)
    keep = tmp_path / "keep.png"
    write_strip(keep, [[("x", img)]])
    before = keep.read_bytes()
    with pytest.raises(ImageError, match="expected one of .png, .pdf, .svg"):
        write_strip(tmp_path / "s.gif", [[("x", img)]])
    with pytest.raises(ImageError, match="cannot write"):
        write_strip(tmp_path / "no" / "dir" / "s.png", [[("x", img)]])
    with pytest.raises(TypeError, match="row 0 panel 1"):
        write_strip(keep, [[("x", img), img]])
    with pytest.raises(ValueError, match="expected \\(H, W\\)"):
        write_strip(keep, [[("x", np.zeros((4, 4, 2)))]])
    with pytest.raises(ValueError, match="at least one panel"):
        write_strip(keep, [[]])
    assert keep.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.png"]


def test_long_labels_are_wrapped_not_overlapping(tmp_path):
    img = np.zeros((60, 80), np.uint8)
    label = "a label much longer than the panel it stands above, several times over"
    png = cv2.imread(str(write_strip(tmp_path / "s.png", [[(label, img)] * 3], panel_width=80)))
    h, w = png.shape[:2]
    # the label band: dark text pixels never reach the white gaps between panels
    band = png[: int(0.55 * h)]
    dark = (band.sum(axis=2) < 300).any(axis=0)
    cols = np.nonzero(dark)[0]
    gaps = [int((i + 1) * w / 3) for i in range(2)]
    assert all(not dark[g - 2 : g + 2].any() for g in gaps), (cols.min(), cols.max(), gaps)
