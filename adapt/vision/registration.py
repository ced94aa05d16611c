"""Image registration: aligning two images by their intensities, not by matched corners.

Where corners cannot be matched (the scenario's textures differ from the real
ones in tint, scale and phase, so nothing in the render looks like the frame),
what still agrees is the *structure* of the image: where each surface lies,
and so the edges between surfaces of different appearance (the skyline, the
floor-wall seam, the outlines of the obstacles).  This module registers that
structure:

1. :func:`flat_look` paints each region of a label image with a smooth colour
   field fitted to the real image: per region and channel, an affine function
   of the pixel position (a lighting gradient is affine to first order; a
   region smaller than 5% of the image gets one colour, the median), least
   squares on the region's pixels at least ``margin`` pixels from its edge (so
   a misalignment of up to ``margin`` pixels does not mix regions), with one
   round of outlier rejection;
2. :func:`align_structure` registers that flat image to the real one, both
   blurred so that the real textures average out, by the enhanced
   correlation coefficient (``cv2.findTransformECC``) with a Euclidean motion
   about the principal point -- the image motion of a small camera rotation
   (pan and tilt shift the image, roll turns it) -- coarse to fine, started
   also from the shift phase correlation finds (``cv2.phaseCorrelate``);
3. :func:`structure_homography` does both at a bounded working resolution.

It returns ``H`` (synthetic pixels to real pixels) as :func:`adapt.vision.mmd.mmd`
does, so the same camera correction applies
(:mod:`adapt.vision.camera_correction`).  The Scene Background schema uses it
to align the camera before the surfaces' look is learned (``docs/appearance.md``);
the label image it registers comes from the mirror
(:func:`adapt.mirror.structure.face_labels`).

Examples
--------
>>> labels = np.zeros((120, 160), np.int32)
>>> labels[60:] = 1
>>> labels[40:80, 50:90] = 2
>>> real = np.zeros((120, 160, 3), np.uint8)
>>> real[:] = (200, 170, 140)
>>> real[63:] = (90, 90, 90)                      # the floor, 3 px lower
>>> real[43:83, 54:94] = (40, 90, 200)            # the box, moved by (4, 3)
>>> flat = flat_look(real, labels, margin=6)
>>> h = align_structure(flat, real, centre=(79.5, 59.5))
>>> np.round(h[:2, 2], 1).tolist()                # synthetic -> real: the shift
[4.0, 3.0]
"""

from __future__ import annotations

import math
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["flat_look", "align_structure", "structure_homography", "STRUCTURE_PIXELS", "BLUR",
           "LEVELS"]

FloatArray = NDArray[np.float64]


#: The structure is aligned at a working resolution of at most this many pixels.
STRUCTURE_PIXELS = 320 * 240
#: Gaussian blur (sigma, working pixels) of both images at each pyramid level.
BLUR = 2.0
#: Pyramid levels of the alignment (each half the size of the one before).
LEVELS = 3
#: Smallest share of a surface's pixels (after the margin) that its fit needs;
#: a smaller surface is painted with the fit of its unshrunk pixels.
_MIN_FIT_PIXELS = 30
#: Fit points are taken on every ``_FIT_STEP``-th row and column.
_FIT_STEP = 2
#: A region covering less than this share of the image is fitted with one colour.
_AFFINE_SHARE = 0.05


def _coordinates(shape: tuple[int, int]) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    h, w = shape
    xs = (np.arange(w, dtype=np.float32) / max(w - 1, 1))[None, :]
    ys = (np.arange(h, dtype=np.float32) / max(h - 1, 1))[:, None]
    return np.broadcast_to(xs, (h, w)), np.broadcast_to(ys, (h, w))


def _fit(values: NDArray[np.float32], xs: NDArray[np.float32], ys: NDArray[np.float32],
         affine: bool = True) -> FloatArray:
    """Affine coefficients ``(3, channels)`` of ``values`` over ``(x, y)`` (or a
    constant, with zero slopes), with one round of rejecting points beyond 2.5
    robust sigmas."""
    v = values.astype(np.float64)
    if not affine:
        med = np.median(v, axis=0)
        return np.vstack([med, np.zeros_like(med), np.zeros_like(med)])
    a = np.stack([np.ones_like(xs), xs, ys], axis=1).astype(np.float64)
    coef, *_ = np.linalg.lstsq(a, v, rcond=None)
    r = np.abs(v - a @ coef).max(axis=1)
    s = 1.4826 * float(np.median(r)) + 1e-6
    keep = r <= 2.5 * s
    if keep.sum() >= 3 and not keep.all():
        coef, *_ = np.linalg.lstsq(a[keep], v[keep], rcond=None)
    return np.asarray(coef)


def flat_look(image: NDArray[np.uint8], labels: NDArray[np.integer], margin: float,
              reference: NDArray[np.uint8] | None = None) -> NDArray[np.uint8]:
    """Each labelled region of ``image`` as a smooth colour field.

    Parameters
    ----------
    image : (H, W, 3) uint8 ndarray
        The real image (BGR).
    labels : (H, W) int ndarray
        The synthetic label image (the same size): which surface each pixel
        shows according to the imagination.
    margin : float
        Pixels near a region's edge that its fit leaves out (about the pose
        error expected).
    reference : (H, W, 3) uint8 ndarray, optional
        The render the labels belong to (the scenario's look).  A small region
        (less than 5% of the image: an obstacle's face) then takes the
        reference's colour there, mapped through the per-channel gain and
        bias that take the large regions' reference colours to their real
        ones: fitted to its own pixels while the pose is off, it would take
        the colour of whatever lies there in the real image and hide the
        offset it should show.

    Returns
    -------
    (H, W, 3) uint8 ndarray
        Per region and channel, the affine function of the pixel position
        fitted to the region's pixels at least ``margin`` from its edge
        (small regions: one colour).
    """
    h, w = labels.shape
    xs, ys = _coordinates((h, w))
    ids, inverse = np.unique(labels, return_inverse=True)
    inverse = inverse.reshape(h, w)
    coefs = np.zeros((len(ids), 3, 3), np.float32)
    m = max(0, int(math.ceil(margin)))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * m + 1, 2 * m + 1)) if m else None
    sub = (slice(None, None, _FIT_STEP), slice(None, None, _FIT_STEP))
    small: list[tuple[int, NDArray[np.bool_]]] = []
    pairs: list[tuple[FloatArray, FloatArray, int]] = []  # reference, real, weight
    for k in range(len(ids)):
        region = (inverse == k).view(np.uint8)
        large = np.count_nonzero(region) >= _AFFINE_SHARE * region.size
        if not large and reference is not None:
            small.append((k, region[sub] != 0))
            continue
        core = cv2.erode(region, kernel) if kernel is not None else region
        use = core[sub] != 0
        if np.count_nonzero(use) < _MIN_FIT_PIXELS:
            use = region[sub] != 0
        if not use.any():
            continue
        coefs[k] = _fit(image[sub][use], xs[sub][use], ys[sub][use], large)
        if reference is not None:
            pairs.append((np.median(reference[sub][use].astype(np.float64), axis=0),
                          np.median(image[sub][use].astype(np.float64), axis=0), int(use.sum())))
    if small:
        gain, bias = _colour_map(pairs)
        for k, use in small:
            if use.any():
                colour = gain * np.median(reference[sub][use].astype(np.float64), axis=0) + bias  # type: ignore[index]
                coefs[k, 0] = np.clip(colour, 0, 255)
    c = coefs[inverse]  # (H, W, 3 terms, 3 channels)
    out = c[:, :, 0] + c[:, :, 1] * xs[:, :, None] + c[:, :, 2] * ys[:, :, None]
    return np.asarray(np.clip(out + 0.5, 0, 255), np.uint8)


def _colour_map(pairs: list[tuple[FloatArray, FloatArray, int]]) -> tuple[FloatArray, FloatArray]:
    """Per-channel gain and bias taking reference colours to real ones, weighted
    least squares over ``pairs``; a gain alone with fewer than three pairs."""
    if not pairs:
        return np.ones(3), np.zeros(3)
    ref = np.array([p[0] for p in pairs])
    real = np.array([p[1] for p in pairs])
    wt = np.sqrt(np.array([p[2] for p in pairs], float))[:, None]
    gain, bias = np.ones(3), np.zeros(3)
    for c in range(3):
        if len(pairs) >= 3 and np.ptp(ref[:, c]) > 10.0:
            a = np.c_[ref[:, c], np.ones(len(pairs))] * wt
            (g, b), *_ = np.linalg.lstsq(a, real[:, c] * wt[:, 0], rcond=None)
            if 0.25 <= g <= 4.0:
                gain[c], bias[c] = g, b
                continue
        gain[c] = float(np.sum(real[:, c] * wt[:, 0]) / max(np.sum(ref[:, c] * wt[:, 0]), 1e-6))
    return gain, bias



def _grey(image: NDArray[np.uint8]) -> NDArray[np.float32]:
    g = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY) if image.ndim == 3 else image
    return np.asarray(g, np.float32)


def _scale(f: float) -> FloatArray:
    """Pixel coordinates of an image to those of one ``f`` times its size
    (pixel centres kept: ``x' = f (x + 0.5) - 0.5``)."""
    return np.array([[f, 0.0, 0.5 * f - 0.5], [0.0, f, 0.5 * f - 0.5], [0.0, 0.0, 1.0]])


def align_structure(flat: NDArray[np.uint8], real: NDArray[np.uint8],
                    centre: Sequence[float], *, blur: float = BLUR, levels: int = LEVELS,
                    max_pixels: int = STRUCTURE_PIXELS, iterations: int = 60,
                    ) -> FloatArray | None:
    """``H`` (flat-image pixels to real pixels) that registers ``flat`` to ``real``,
    or None when the alignment does not converge.

    The motion is Euclidean about ``centre`` (the principal point): a shift
    and a turn, the image motion of a small rotation of the camera.  Both
    images are reduced to at most ``max_pixels``, turned grey and blurred by
    ``blur`` working pixels; the alignment runs coarse to fine over
    ``levels`` pyramid levels.
    """
    if flat.shape[:2] != real.shape[:2]:
        raise ValueError(f"flat {flat.shape[:2]} and real {real.shape[:2]} differ in size")
    h, w = real.shape[:2]
    f0 = min(1.0, math.sqrt(max_pixels / float(h * w)))
    a, b = _grey(flat), _grey(real)
    if f0 < 1.0:
        size = (max(8, int(round(w * f0))), max(8, int(round(h * f0))))
        a = np.asarray(cv2.resize(a, size, interpolation=cv2.INTER_AREA), np.float32)
        b = np.asarray(cv2.resize(b, size, interpolation=cv2.INTER_AREA), np.float32)
        f0 = size[0] / w
    pyramid = [(a, b)]
    for _ in range(levels - 1):
        if min(pyramid[-1][0].shape) < 32:
            break
        pyramid.append((np.asarray(cv2.pyrDown(pyramid[-1][0]), np.float32),
                        np.asarray(cv2.pyrDown(pyramid[-1][1]), np.float32)))
    cx, cy = float(centre[0]), float(centre[1])
    # Work in coordinates centred on the principal point, so Euclidean = rotation.
    to_centred = np.array([[1.0, 0.0, -cx], [0.0, 1.0, -cy], [0.0, 0.0, 1.0]])
    blurred = [(np.asarray(cv2.GaussianBlur(ga, (0, 0), blur), np.float32),
                np.asarray(cv2.GaussianBlur(gb, (0, 0), blur), np.float32)) for ga, gb in pyramid]
    starts = [np.eye(3)]
    # A second start: the shift phase correlation finds at the coarsest level
    # (it reaches offsets far beyond the alignment's own basin).
    ga, gb = blurred[-1]
    fc = f0 * 0.5 ** (len(pyramid) - 1)
    window = cv2.createHanningWindow(ga.shape[::-1], cv2.CV_32F)
    (dx, dy), response = cv2.phaseCorrelate(ga, gb, window)
    if response > 0.05 and math.isfinite(dx) and math.isfinite(dy) and math.hypot(dx, dy) >= 1.0:
        starts.append(np.array([[1.0, 0.0, dx / fc], [0.0, 1.0, dy / fc], [0.0, 0.0, 1.0]]))
    criteria = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, iterations, 1e-5)
    best: tuple[float, FloatArray] | None = None
    for warp in starts:  # in centred input pixels
        score = -1.0
        for level in reversed(range(len(pyramid))):
            ga, gb = blurred[level]
            f = f0 * 0.5 ** level
            c = _scale(f) @ np.linalg.inv(to_centred)  # centred input pixels -> level pixels
            ci = np.linalg.inv(c)
            lw = c @ warp @ ci
            try:
                score, m = cv2.findTransformECC(  # type: ignore[call-overload]
                    ga, gb, lw[:2].astype(np.float32), cv2.MOTION_EUCLIDEAN, criteria, None, 1)
            except cv2.error:
                score = -1.0
                break
            warp = ci @ np.vstack([np.asarray(m, np.float64), [0.0, 0.0, 1.0]]) @ c
        if score > -1.0 and np.isfinite(warp).all() and (best is None or score > best[0]):
            best = (float(score), warp)
    if best is None:
        return None
    return np.asarray(np.linalg.inv(to_centred) @ best[1] @ to_centred)


def structure_homography(real: NDArray[np.uint8], labels: NDArray[np.integer],
                         centre: Sequence[float], *, margin: float,
                         reference: NDArray[np.uint8] | None = None,
                         max_pixels: int = STRUCTURE_PIXELS) -> FloatArray | None:
    """``H`` (synthetic pixels to real pixels) from the structure alone: the real
    image and the synthetic label image (and the render they belong to,
    ``reference``) reduced to at most ``max_pixels``, :func:`flat_look` with
    ``margin`` (input pixels), then :func:`align_structure`; None when the
    alignment does not converge.

    Examples
    --------
    >>> labels = np.zeros((240, 320), np.int32)
    >>> labels[120:] = 1
    >>> labels[80:160, 100:180] = 2
    >>> real = np.full((240, 320, 3), (200, 170, 140), np.uint8)
    >>> real[125:] = 90
    >>> real[85:165, 106:186] = (40, 90, 200)           # moved by (6, 5)
    >>> h = structure_homography(real, labels, (159.5, 119.5), margin=10)
    >>> np.round(h[:2, 2]).tolist()
    [6.0, 5.0]
    """
    h, w = labels.shape
    f = min(1.0, math.sqrt(max_pixels / float(h * w)))
    if f < 1.0:
        size = (max(8, int(round(w * f))), max(8, int(round(h * f))))
        f = size[0] / w
        small_labels = np.asarray(cv2.resize(labels.astype(np.int32), size,
                                             interpolation=cv2.INTER_NEAREST), np.int32)
        small_real = np.asarray(cv2.resize(real, size, interpolation=cv2.INTER_AREA), np.uint8)
        small_ref = (None if reference is None else np.asarray(
            cv2.resize(reference, size, interpolation=cv2.INTER_AREA), np.uint8))
    else:
        small_labels, small_real, small_ref = np.asarray(labels, np.int32), real, reference
    flat = flat_look(small_real, small_labels, margin * f, small_ref)
    to_small = _scale(f)
    c = to_small @ np.array([float(centre[0]), float(centre[1]), 1.0])
    hs = align_structure(flat, small_real, (c[0], c[1]), max_pixels=max_pixels)
    if hs is None:
        return None
    return np.asarray(np.linalg.inv(to_small) @ hs @ to_small)
