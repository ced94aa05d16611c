"""The MMD mask ``I_m``: where matched features explain the image.

The paper's eq. 1 builds the mask from Gaussians centred on the match points,
each weighted by the match quality ``q(p)``.  adapt uses the plain sum, clipped
to ``[0, 1]``:

.. math:: I_m(x) = \\min\\Big(1,\\; \\sum_{p \\in P} q(p)\\,
          e^{-\\lVert x - p \\rVert^2 / 2\\sigma^2}\\Big)

(the paper's ``1/|P|`` factor would make the mask vanish as more matches are
found, so it is dropped; the clip keeps the mask a weight).

:func:`exact_mask` evaluates this sum separably (one matrix product, tens of
milliseconds at 640x480).  :func:`fast_mask` splats the weights bilinearly
onto a grid ``step`` times coarser, blurs it with a Gaussian whose width is
reduced by the variance the splat and the upsampling add, and upsamples; it
takes about a millisecond and stays within 0.1 of the exact mask everywhere
(``tests/vision/test_mask.py`` checks the bound).

Examples
--------
>>> import numpy as np
>>> pts = np.array([[20.0, 10.0]])
>>> m = exact_mask(pts, np.array([1.0]), (100, 120), sigma=12)
>>> round(float(m[10, 20]), 3), round(float(m[10, 32]), 3)
(1.0, 0.607)
>>> bool(np.abs(fast_mask(pts, np.array([1.0]), (100, 120), sigma=12) - m).max() < 0.1)
True
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.vision.scale import image_scale

__all__ = ["exact_mask", "fast_mask", "SIGMA", "FAST_STEP"]

#: Width of each match's Gaussian, pixels at 640x480 (scaled with the image,
#: :mod:`~adapt.vision.scale`).
SIGMA = 12.0
#: Grid step of the fast mask, pixels at 640x480 (scaled with the image).
FAST_STEP = 4
#: Bilinear splatting and bilinear upsampling each widen the Gaussian by about
#: a tent's variance (step^2 / 6); this many tents are taken out of the blur
#: (1.5 measured best: worst error 0.05 against the exact mask).
VARIANCE_TENTS = 1.5

FloatImage = NDArray[np.float32]


def _inputs(points: ArrayLike, quality: ArrayLike) -> tuple[NDArray, NDArray]:
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    q = np.asarray(quality, dtype=np.float64).reshape(-1)
    if len(p) != len(q):
        raise ValueError(f"{len(p)} points but {len(q)} quality values")
    return p, q


def exact_mask(
    points: ArrayLike,
    quality: ArrayLike,
    shape: tuple[int, ...],
    *,
    sigma: float | None = None,
) -> FloatImage:
    """The mask as the exact clipped sum of Gaussians.

    Parameters
    ----------
    points : (N, 2) array_like
        Match points ``(x, y)`` in the frame the mask is for.
    quality : (N,) array_like
        ``q(p)``, the weight of each Gaussian.
    shape : tuple
        ``(H, W)`` (extra trailing dimensions are ignored).
    sigma : float, optional
        Gaussian width in pixels; :data:`SIGMA` scaled with the image by default.

    Returns
    -------
    (H, W) float32 ndarray in [0, 1]
    """
    p, q = _inputs(points, quality)
    h, w = int(shape[0]), int(shape[1])
    sigma = SIGMA * image_scale(shape) if sigma is None else float(sigma)
    if len(p) == 0:
        return np.zeros((h, w), np.float32)
    k = -0.5 / (sigma * sigma)
    gx = np.exp(k * (np.arange(w)[None, :] - p[:, :1]) ** 2)  # (N, W)
    gy = np.exp(k * (np.arange(h)[None, :] - p[:, 1:]) ** 2)  # (N, H)
    m = (gy * q[:, None]).T @ gx
    return np.minimum(m, 1.0).astype(np.float32)


def fast_mask(
    points: ArrayLike,
    quality: ArrayLike,
    shape: tuple[int, ...],
    *,
    sigma: float | None = None,
    step: int | None = None,
) -> FloatImage:
    """The mask approximated on a coarse grid (within 0.1 of :func:`exact_mask`).

    Parameters are those of :func:`exact_mask`, plus ``step``, the grid step
    in pixels (``sigma / step`` should stay at 2 or more); by default
    :data:`FAST_STEP` scaled with the image, at least 1.
    """
    p, q = _inputs(points, quality)
    h, w = int(shape[0]), int(shape[1])
    s = image_scale(shape)
    sigma = SIGMA * s if sigma is None else float(sigma)
    step = max(1, int(round(FAST_STEP * s))) if step is None else int(step)
    if len(p) == 0:
        return np.zeros((h, w), np.float32)
    hs, ws = -(-h // step), -(-w // step)
    # Sub-sampling by resize(), then cropping, keeps x -> (x + 0.5) / step - 0.5;
    # a margin of `pad` cells keeps the Gaussians of points near (or beyond)
    # the border.
    sg = math.sqrt(max(sigma * sigma - VARIANCE_TENTS * step * step / 6.0, 0.25 * step * step)) / step
    pad = int(math.ceil(4.0 * sg)) + 1
    hp, wp = hs + 2 * pad, ws + 2 * pad
    gx = (p[:, 0] + 0.5) / step - 0.5 + pad
    gy = (p[:, 1] + 0.5) / step - 0.5 + pad
    x0 = np.floor(gx)
    y0 = np.floor(gy)
    fx = gx - x0
    fy = gy - y0
    acc = np.zeros(hp * wp, np.float64)
    for dx, dy, wt in (
        (0, 0, (1 - fx) * (1 - fy)),
        (1, 0, fx * (1 - fy)),
        (0, 1, (1 - fx) * fy),
        (1, 1, fx * fy),
    ):
        xi = (x0 + dx).astype(np.int64)
        yi = (y0 + dy).astype(np.int64)
        ok = (xi >= 0) & (xi < wp) & (yi >= 0) & (yi < hp)
        acc += np.bincount(yi[ok] * wp + xi[ok], weights=(q * wt)[ok], minlength=hp * wp)
    grid = acc.reshape(hp, wp).astype(np.float32)
    ksize = 2 * int(math.ceil(4.0 * sg)) + 1
    grid = cv2.GaussianBlur(grid, (ksize, ksize), sg, borderType=cv2.BORDER_CONSTANT)  # type: ignore[assignment]
    # Keep one cell of margin so the upsampling interpolates at the border
    # instead of clamping, and upsample by exactly `step`.
    grid = grid[pad - 1 : pad + hs + 1, pad - 1 : pad + ws + 1] * np.float32(
        2.0 * math.pi * sg * sg
    )
    big = cv2.resize(grid, ((ws + 2) * step, (hs + 2) * step), interpolation=cv2.INTER_LINEAR)
    m = np.ascontiguousarray(big[step : step + h, step : step + w])
    np.minimum(m, 1.0, out=m)
    np.maximum(m, 0.0, out=m)
    return m
