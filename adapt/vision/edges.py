"""Edge agreement: how strongly an image has edges where a label image says surfaces meet.

Whatever a reality's textures and light, the seams between its surfaces (the
floor-wall line, a wall's top against what lies beyond, an obstacle's outline)
are edges of its image where the camera is where the model says.  A camera off
by a degree moves the rendered seams off those edges by a few pixels, and the
image's gradient sampled along them falls sharply.  :func:`edge_agreement`
measures that: the mean gradient magnitude of the lightly blurred grey image on
the pixels of :func:`seams`.  It needs no fitted colours, so it checks an
alignment found from them (the Scene Background refuses a structure correction
that lowers it, :mod:`adapt.schemas.background`).

Examples
--------
>>> labels = np.zeros((60, 80), np.int32)
>>> labels[30:] = 1                                   # the model: a seam at row 30
>>> image = np.full((60, 80, 3), 200, np.uint8)
>>> image[30:] = 60                                   # the image agrees
>>> moved = np.full((60, 80, 3), 200, np.uint8)
>>> moved[36:] = 60                                   # the image's seam 6 px lower
>>> edge_agreement(image, labels) > 3 * edge_agreement(moved, labels)
True
>>> int(seams(labels).sum())
80
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["seams", "edge_agreement", "EDGE_SIGMA"]

#: The blur before the gradient (pixels at 640x480): a seam is found within about this.
EDGE_SIGMA = 2.0


def seams(labels: NDArray[np.integer]) -> NDArray[np.bool_]:
    """The pixels whose label differs from the one below or to the right of them.

    Examples
    --------
    >>> labels = np.zeros((4, 4), np.int32); labels[:, 2:] = 1
    >>> seams(labels).astype(int).tolist()
    [[0, 1, 0, 0], [0, 1, 0, 0], [0, 1, 0, 0], [0, 1, 0, 0]]
    """
    lab = np.asarray(labels)
    out = np.zeros(lab.shape, bool)
    out[:, :-1] |= lab[:, :-1] != lab[:, 1:]
    out[:-1] |= lab[:-1] != lab[1:]
    return out


def edge_agreement(image: NDArray[np.uint8], labels: NDArray[np.integer], *,
                   sigma: float | None = None) -> float:
    """Mean gradient magnitude (grey levels a pixel) of ``image`` on the seams of ``labels``.

    Parameters
    ----------
    image : (H, W, 3) or (H, W) uint8
    labels : (H, W) integer array
        A label image of the same size (a render's surface labels).
    sigma : float, optional
        The Gaussian blur before the gradient, pixels (default :data:`EDGE_SIGMA`
        scaled to the image's size).

    Returns
    -------
    float
        NaN when ``labels`` has no seams.

    Raises
    ------
    ValueError
        When the sizes differ.
    """
    img = np.asarray(image)
    lab = np.asarray(labels)
    if img.shape[:2] != lab.shape:
        raise ValueError(f"image {img.shape[:2]} and labels {lab.shape} differ in size")
    mask = seams(lab)
    if not mask.any():
        return math.nan
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY) if img.ndim == 3 else img
    if sigma is None:
        sigma = EDGE_SIGMA * math.sqrt(lab.size / (640.0 * 480.0))
    blurred = cv2.GaussianBlur(grey.astype(np.float32), (0, 0), max(0.5, float(sigma)))
    gx = cv2.Sobel(blurred, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(blurred, cv2.CV_32F, 0, 1, ksize=3)
    return float(np.hypot(gx, gy)[mask].mean()) / 8.0
