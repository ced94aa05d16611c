"""Image scale: MMD's pixel parameters are relative to the image, and MMD works
at a bounded resolution.

**Relative parameters.**  Every length that MMD uses (the mask's Gaussian
width, the corner spacing, the LK window, the reprojection threshold, the
regions' smallest area, ...) is given for the *reference* image size of
640x480 and multiplied by the image's :func:`image_scale`,
``sqrt(W * H / (640 * 480))``; areas by its square.  The same scene at
1280x960 therefore uses a mask twice as wide and keeps regions four times as
large, and finds the same regions, scaled.

**Working resolution.**  Images of more than ``max_pixels`` pixels
(:data:`MAX_WORK_PIXELS`, the reference size, by default) are reduced with
``INTER_AREA`` to a *working* image of at most that many pixels before any
analysis, so an MMD costs about the same at 640x480 and at 8000x6000.  A
:class:`WorkingFrame` maps points and homographies between the input and the
working image; :func:`~adapt.vision.mmd.mmd` reports the homography, the
matches and the regions in input pixels and its images at the working
resolution.

Examples
--------
>>> image_scale((960, 1280))
2.0
>>> f = working_frame((6000, 8000))
>>> f.shape, f.factor
((480, 640), (12.5, 12.5))
>>> f.to_input([[0.0, 0.0], [639.0, 479.0]]).tolist()     # pixel centres
[[5.75, 5.75], [7993.25, 5993.25]]
>>> working_frame((480, 640)).reduces
False
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import VisionError

__all__ = [
    "REFERENCE_WIDTH",
    "REFERENCE_HEIGHT",
    "REFERENCE_PIXELS",
    "MAX_WORK_PIXELS",
    "MIN_WORK_SIDE",
    "image_scale",
    "odd",
    "WorkingFrame",
    "working_frame",
]

#: The image size MMD's pixel parameters are given for.
REFERENCE_WIDTH, REFERENCE_HEIGHT = 640, 480
REFERENCE_PIXELS = REFERENCE_WIDTH * REFERENCE_HEIGHT
#: Images with more pixels than this are analysed at a reduced working
#: resolution (the reference size: 640x480, or the same area at another aspect).
MAX_WORK_PIXELS = REFERENCE_PIXELS
#: Largest ``max_pixels`` accepted (2560x1920): beyond it the scaled LK windows
#: and Gaussians make one MMD take seconds.
MAX_WORK_PIXELS_LIMIT = 16 * REFERENCE_PIXELS
#: A working image must keep this many pixels on its shorter side.
MIN_WORK_SIDE = 32


def image_scale(shape: tuple[int, ...]) -> float:
    """``sqrt(W * H / (640 * 480))``: how much larger than the reference an
    image of ``shape`` (``(H, W)`` or ``(H, W, C)``) is, as a length.

    Examples
    --------
    >>> image_scale((480, 640)), image_scale((240, 320))
    (1.0, 0.5)
    """
    return math.sqrt(int(shape[0]) * int(shape[1]) / REFERENCE_PIXELS)


def odd(value: float, smallest: int = 3) -> int:
    """The odd integer nearest to ``value`` and at least ``smallest`` (for
    window and kernel sides).

    Examples
    --------
    >>> odd(21 * 2.0), odd(5 * 0.5), odd(0.2)
    (43, 3, 3)
    """
    return max(smallest, 2 * int(math.floor((value - 1) / 2 + 0.5)) + 1)


@dataclass(frozen=True, slots=True)
class WorkingFrame:
    """The working image of an input image: its size and the maps between them.

    Attributes
    ----------
    input_shape : (H, W)
        The input image's size.
    shape : (h, w)
        The working image's size (equal to ``input_shape`` when nothing is
        reduced).
    """

    input_shape: tuple[int, int]
    shape: tuple[int, int]

    @property
    def factor(self) -> tuple[float, float]:
        """Input pixels per working pixel, ``(x, y)`` (``(1.0, 1.0)`` unreduced)."""
        return (self.input_shape[1] / self.shape[1], self.input_shape[0] / self.shape[0])

    @property
    def reduces(self) -> bool:
        """True when the working image is smaller than the input."""
        return self.shape != self.input_shape

    @property
    def scale(self) -> float:
        """:func:`image_scale` of the working image (what MMD's parameters are
        multiplied by)."""
        return image_scale(self.shape)

    def _to_input_matrix(self) -> NDArray[np.float64]:
        # INTER_AREA / resize keep pixel centres: x_in = (x_w + 0.5) f - 0.5
        fx, fy = self.factor
        return np.array([[fx, 0.0, 0.5 * fx - 0.5], [0.0, fy, 0.5 * fy - 0.5], [0.0, 0.0, 1.0]])

    def to_input(self, points: ArrayLike) -> NDArray[np.float64]:
        """Working-image pixels ``(N, 2)`` as input pixels."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        fx, fy = self.factor
        return np.c_[(p[:, 0] + 0.5) * fx - 0.5, (p[:, 1] + 0.5) * fy - 0.5]

    def to_work(self, points: ArrayLike) -> NDArray[np.float64]:
        """Input pixels ``(N, 2)`` as working-image pixels."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        fx, fy = self.factor
        return np.c_[(p[:, 0] + 0.5) / fx - 0.5, (p[:, 1] + 0.5) / fy - 0.5]

    def homography_to_input(self, homography: ArrayLike) -> NDArray[np.float64]:
        """A homography between two working images as one between the inputs
        (``A H A^-1``, normalised so ``H[2, 2] = 1``)."""
        a = self._to_input_matrix()
        h = a @ np.asarray(homography, dtype=np.float64).reshape(3, 3) @ np.linalg.inv(a)
        return h / h[2, 2]

    def homography_to_work(self, homography: ArrayLike) -> NDArray[np.float64]:
        """A homography between two input images as one between the working images
        (``A^-1 H A``, normalised so ``H[2, 2] = 1``): the inverse of
        :meth:`homography_to_input`."""
        a = self._to_input_matrix()
        h = np.linalg.inv(a) @ np.asarray(homography, dtype=np.float64).reshape(3, 3) @ a
        return h / h[2, 2]

    def reduce(self, image: NDArray) -> NDArray:
        """``image`` (of ``input_shape``) at the working size (``INTER_AREA``);
        the image itself when nothing is reduced."""
        if not self.reduces:
            return image
        return cv2.resize(image, (self.shape[1], self.shape[0]), interpolation=cv2.INTER_AREA)


def working_frame(shape: tuple[int, ...], max_pixels: int = MAX_WORK_PIXELS) -> WorkingFrame:
    """The working frame of an image of ``shape``: the input size when it has at
    most ``max_pixels`` pixels, else the same aspect reduced to at most
    ``max_pixels``.

    Raises
    ------
    VisionError
        If ``max_pixels`` is outside ``[32 * 32, MAX_WORK_PIXELS_LIMIT]``, or the
        image is so elongated that its working image would have fewer than
        :data:`MIN_WORK_SIDE` pixels on its shorter side.

    Examples
    --------
    >>> working_frame((960, 1280)).shape, working_frame((960, 1280), 1280 * 960).shape
    ((480, 640), (960, 1280))
    """
    h, w = int(shape[0]), int(shape[1])
    if not MIN_WORK_SIDE * MIN_WORK_SIDE <= max_pixels <= MAX_WORK_PIXELS_LIMIT:
        raise VisionError(
            f"the working resolution must have between {MIN_WORK_SIDE * MIN_WORK_SIDE} and "
            f"{MAX_WORK_PIXELS_LIMIT} pixels, got {max_pixels}"
        )
    if h * w <= max_pixels:
        return WorkingFrame((h, w), (h, w))
    f = math.sqrt(h * w / max_pixels)
    wh, ww = int(h / f), int(w / f)  # rounded down: never more than max_pixels
    if min(wh, ww) < MIN_WORK_SIDE:
        raise VisionError(
            f"a {w}x{h} image would be {ww}x{wh} pixels at the working resolution "
            f"({max_pixels} pixels): expected at least {MIN_WORK_SIDE} pixels on each side "
            "there; crop the image to a less elongated shape"
        )
    return WorkingFrame((h, w), (wh, ww))
