"""The lens: a frame distorted with known coefficients and undistorted again comes back, the
maps agree with OpenCV's point functions, and the wrapped sources forward what they wrap."""

from __future__ import annotations

from typing import Any, Iterator

import cv2
import numpy as np
import pytest

from adapt.errors import ImageError
from adapt.frames import Frame
from adapt.lens import Distorter, Lens, LensSource, Undistorter, distorted, undistorted

SIZE = (320, 240)
FX, FY, CX, CY = 300.0, 300.0, 159.5, 119.5

#: Barrel, pincushion, tangential and OpenCV's rational 8-coefficient model.
LENSES = {
    "barrel": (-0.28, 0.09, 0.0, 0.0, 0.0),
    "pincushion": (0.2, 0.05, 0.0, 0.0),
    "tangential": (-0.1, 0.02, 0.004, -0.003, 0.0),
    "rational": (-0.3, 0.1, 0.001, 0.001, 0.0, 0.05, 0.0, 0.0),
}


def board(size: tuple[int, int] = SIZE, square: int = 20) -> np.ndarray:
    """A softened chessboard with a colour ramp: every region has structure to misplace."""
    w, h = size
    y, x = np.mgrid[0:h, 0:w]
    grey = ((x // square + y // square) % 2 * 180 + 30).astype(np.uint8)
    img = cv2.merge([grey, (x * 255 // w).astype(np.uint8), (y * 255 // h).astype(np.uint8)])
    return np.asarray(cv2.GaussianBlur(img, (0, 0), 1.5), np.uint8)


def lens(coeffs: tuple[float, ...]) -> Lens:
    return Lens.pinhole(FX, FY, CX, CY, SIZE, coeffs)


def mean_error(a: np.ndarray, b: np.ndarray, margin: int = 16) -> float:
    m = margin
    return float(np.abs(a[m:-m, m:-m].astype(int) - b[m:-m, m:-m]).mean())


@pytest.mark.parametrize("name", sorted(LENSES))
def test_a_frame_distorted_with_known_coefficients_comes_back_when_undistorted(name: str) -> None:
    ideal = board()
    lz = lens(LENSES[name])
    raw = Distorter(lz)(ideal)
    back = Undistorter(lz)(raw)
    assert mean_error(raw, ideal) > 5.0  # the lens moves the board visibly
    assert mean_error(back, ideal) < 2.0  # and undistortion puts it back (two bilinear samplings)


def centroid(img: np.ndarray) -> tuple[float, float]:
    g = img[..., 0].astype(float)
    ys, xs = np.nonzero(g > 40)
    w = g[ys, xs]
    return float((xs * w).sum() / w.sum()), float((ys * w).sum() / w.sum())


def dot(at: tuple[float, float]) -> np.ndarray:
    img = np.zeros((SIZE[1], SIZE[0], 3), np.uint8)
    cv2.circle(img, (round(at[0] * 16), round(at[1] * 16)), 2 * 16, (255, 255, 255), -1,
               cv2.LINE_AA, shift=4)
    return img


@pytest.mark.parametrize("ideal", [(40.0, 30.0), (280.0, 200.0), (159.5, 30.0), (60.0, 180.0)])
def test_the_maps_put_a_point_where_opencvs_projection_does(ideal: tuple[float, float]) -> None:
    coeffs = LENSES["tangential"]
    lz = lens(coeffs)
    k = np.array([[FX, 0, CX], [0, FY, CY], [0, 0, 1]])
    ray = np.array([[(ideal[0] - CX) / FX, (ideal[1] - CY) / FY, 1.0]])
    expected, _ = cv2.projectPoints(ray, np.zeros(3), np.zeros(3), k, np.array(coeffs))
    seen = centroid(Distorter(lz)(dot(ideal)))
    assert seen == pytest.approx(tuple(expected.ravel()), abs=0.25)
    # and the undistorter takes the raw point back to the ideal one
    back = centroid(Undistorter(lz)(dot(tuple(expected.ravel()))))  # type: ignore[arg-type]
    assert back == pytest.approx(ideal, abs=0.25)


def test_a_ros_projection_gives_the_undistorted_images_camera() -> None:
    k = np.array([[FX, 0, CX], [0, FY, CY], [0, 0, 1]])
    p = np.array([[250.0, 0, 150.0], [0, 250.0, 110.0], [0, 0, 1]])
    lz = Lens(k, LENSES["barrel"], SIZE, np.eye(3), p)
    assert lz.intrinsics == (250.0, 250.0, 150.0, 110.0) and lz.distorted
    ray = np.array([[0.2, -0.1, 1.0]])
    raw, _ = cv2.projectPoints(ray, np.zeros(3), np.zeros(3), k, np.array(LENSES["barrel"]))
    back = centroid(Undistorter(lz)(dot(tuple(raw.ravel()))))  # type: ignore[arg-type]
    assert back == pytest.approx((150.0 + 250.0 * 0.2, 110.0 - 250.0 * 0.1), abs=0.25)


def test_a_lens_without_distortion_changes_nothing_and_bad_input_is_refused() -> None:
    class Source:
        size, fps = SIZE, 10.0
        robot, truth = "robot", "truth"

        def __iter__(self) -> Iterator[Frame]:
            return iter([Frame(0, 0.0, board())])

        def close(self) -> None:
            pass

        def status(self) -> dict[str, Any]:
            return {"frames_dropped": 3}

    src = Source()
    assert undistorted(src, None) is src and distorted(src, lens((0.0, 0.0, 0.0, 0.0))) is src
    wrapped = undistorted(src, lens(LENSES["barrel"]))
    assert isinstance(wrapped, LensSource)
    assert (wrapped.robot, wrapped.truth, wrapped.status(), wrapped.size) == (  # type: ignore[attr-defined]
        "robot", "truth", {"frames_dropped": 3}, SIZE)
    assert not hasattr(wrapped, "nothing")
    with pytest.raises(ImageError, match="expected 4, 5 or 8 distortion coefficients, got 3"):
        lens((0.1, 0.0, 0.0))
    with pytest.raises(ImageError, match="expects an image of 320x240 pixels, got 160x120"):
        Undistorter(lens(LENSES["barrel"]))(np.zeros((120, 160, 3), np.uint8))
