"""Corner matches from the synthetic image to the real one.

Corners are detected on the *synthetic* image (rendered, so its corners are
stable) with Shi–Tomasi ``goodFeaturesToTrack`` and tracked into the real image
with pyramidal Lucas–Kanade.  Each track is run backwards as well; a match is
kept only when the backward track lands within ``fb_max`` pixels of where it
started.  The match quality is

.. math:: q(p) = \\max(1 - e_{fb}(p) / e_{max},\\; q_{min}) \\in (0, 1]

so perfectly consistent tracks weigh 1 in the MMD mask.

When fewer than :data:`MIN_TRACKED` tracks survive (large offsets, a blurred or
very different view), :func:`match` re-acquires with SIFT descriptors and
Lowe's ratio test (:func:`match_descriptors`); the caller
(:func:`adapt.vision.mmd.mmd`) also re-acquires when the tracked matches give too
few homography inliers.

Either image may be passed as a :class:`PreparedImage` (its working image,
grey version and, for the synthetic side, its corners), which is how a
rendered background or a fixed real frame is reused across calls.

Matching runs on the *working* image (:mod:`~adapt.vision.scale`: the input
itself up to 640x480 pixels, else the input reduced to that many pixels), and
its pixel parameters (corner spacing and block size, LK window and levels,
the forward-backward bound) are given for 640x480 and scaled with the
working image's size.  :class:`Matches` are in working-image pixels;
:func:`~adapt.vision.mmd.mmd` maps them back to the input.  (OpenCV 5's Python binding of
``calcOpticalFlowPyrLK`` does not accept a pyramid built by
``buildOpticalFlowPyramid``, so LK rebuilds the pyramids on every call.)

Examples
--------
>>> import numpy as np, cv2
>>> rng = np.random.default_rng(0)
>>> synthetic = cv2.GaussianBlur(rng.integers(0, 256, (120, 160), dtype=np.uint8), (0, 0), 2)
>>> real = np.roll(synthetic, (2, 3), axis=(0, 1))          # moved 3 px right, 2 down
>>> m = match(real, synthetic)
>>> m.method, len(m) > 20
('lk', True)
>>> d = np.median(m.real_points - m.synthetic_points, axis=0)
>>> [round(float(v), 1) for v in d]
[3.0, 2.0]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.vision.images import as_uint8, check_image, check_pair, to_grey
from adapt.vision.scale import MAX_WORK_PIXELS, WorkingFrame, odd, working_frame

__all__ = [
    "PreparedImage",
    "Matches",
    "prepare",
    "prepare_pair",
    "track",
    "match_descriptors",
    "match",
    "MIN_TRACKED",
    "MAX_CORNERS",
]

#: Fewer surviving LK tracks than this triggers descriptor re-acquisition.
MIN_TRACKED = 40
#: Corners detected on the synthetic image.
MAX_CORNERS = 300
#: Shi–Tomasi quality level (fraction of the best corner's response).
QUALITY_LEVEL = 0.01
# Lengths below are in pixels at the reference 640x480 and are scaled with
# the working image (adapt.vision.scale).
#: Minimum distance between corners, pixels.
MIN_DISTANCE = 8
#: Shi–Tomasi block size.
BLOCK_SIZE = 5
#: LK window (pixels) and pyramid levels above the base.
LK_WINDOW = 21
LK_LEVELS = 3
#: Forward-backward consistency bound, pixels.
FB_MAX = 0.5
#: Floor of q(p), so every kept match still counts a little.
Q_MIN = 0.05
#: Standard deviation the grey working images are stretched to before matching.
GREY_STD = 50.0
#: Lowe's ratio for descriptor re-acquisition.
RATIO = 0.75
#: SIFT features per image during re-acquisition.
SIFT_FEATURES = 1000

_LK_CRITERIA = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 20, 0.03)

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True, eq=False)
class PreparedImage:
    """An image with what matching needs from it, computed once.

    Attributes
    ----------
    image : ndarray
        The original image (not copied; do not modify it afterwards).
    frame : WorkingFrame
        The working resolution and the maps between it and ``image``.
    work : ndarray
        The 8-bit working image (``image`` reduced to ``frame.shape``; the
        array itself when it is already 8-bit and small enough).
    grey : (h, w) uint8 ndarray
        The grey working image, standardised to mean 128 and deviation ``GREY_STD``.
    corners : (N, 2) float32 ndarray
        Shi–Tomasi corners ``(x, y)`` in working pixels; empty when the image
        is textureless.
    max_pixels : int
        The ``max_pixels`` it was prepared for.
    """

    image: NDArray
    frame: WorkingFrame
    work: NDArray[np.uint8] = field(repr=False)
    grey: NDArray[np.uint8] = field(repr=False)
    corners: NDArray[np.float32] = field(repr=False)
    max_pixels: int = MAX_WORK_PIXELS

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the original image."""
        return tuple(self.image.shape)


@dataclass(frozen=True, slots=True, eq=False)
class Matches:
    """Point correspondences ``synthetic_points[i] -> real_points[i]``.

    Attributes
    ----------
    real_points, synthetic_points : (N, 2) float64 ndarray
        Pixel coordinates ``(x, y)``.
    quality : (N,) float64 ndarray
        q(p) in (0, 1].
    method : {"lk", "sift", "none"}
        How the matches were found ("none" when nothing could be matched).
    corners : int
        Corners detected on the synthetic image (before tracking).
    """

    real_points: FloatArray
    synthetic_points: FloatArray
    quality: FloatArray
    method: Literal["lk", "sift", "none"]
    corners: int = 0

    def __len__(self) -> int:
        return int(self.quality.shape[0])


def _empty(method: Literal["lk", "sift", "none"] = "none", corners: int = 0) -> Matches:
    z = np.zeros((0, 2))
    return Matches(z, z.copy(), np.zeros(0), method, corners)


def _standardise(grey: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Map grey levels to mean 128 and standard deviation :data:`GREY_STD`
    (LK assumes constant brightness; a renderer and a camera disagree on
    gain and bias).  A flat image stays flat."""
    mean, std = cv2.meanStdDev(grey)
    m, sd = float(mean.ravel()[0]), float(std.ravel()[0])
    if sd < 1e-6:
        return np.full_like(grey, 128)
    a = GREY_STD / sd
    return cv2.convertScaleAbs(grey, alpha=a, beta=128.0 - a * m)  # type: ignore[return-value]


def prepare(
    image: NDArray | PreparedImage,
    *,
    corners: bool = True,
    max_corners: int = MAX_CORNERS,
    max_pixels: int = MAX_WORK_PIXELS,
    name: str = "",
) -> PreparedImage:
    """Working image, grey version and (optionally) Shi–Tomasi corners of ``image``.

    Parameters
    ----------
    image : ndarray or PreparedImage
        A grey or BGR image (see :mod:`~adapt.vision.images`); a prepared one
        is returned as it is unless it lacks corners that are asked for or
        was prepared for another ``max_pixels``.
    corners : bool
        Detect corners (the synthetic side needs them).
    max_corners : int
        Most corners kept.
    max_pixels : int
        Largest working image, pixels (:func:`~adapt.vision.scale.working_frame`).
    name : str
        The image's role in error messages (``"real"``, ``"synthetic"``).

    Examples
    --------
    >>> p = prepare(np.zeros((64, 64), np.uint8))
    >>> p.grey.shape, p.corners.shape
    ((64, 64), (0, 2))
    >>> prepare(np.zeros((1200, 1600), np.uint8)).work.shape    # the working image
    (480, 640)
    """
    if isinstance(image, PreparedImage):
        frame = working_frame(image.frame.input_shape, max_pixels)
        stale = frame != image.frame or (corners and len(image.corners) == 0 and image.grey.any())
        if not stale:
            return image
        image = image.image
    img = check_image(image, name)
    frame = working_frame(img.shape, max_pixels)
    work = as_uint8(frame.reduce(img))
    grey = _standardise(to_grey(work))
    pts = np.zeros((0, 2), np.float32)
    if corners:
        s = frame.scale
        found = cv2.goodFeaturesToTrack(
            grey, max_corners, QUALITY_LEVEL, MIN_DISTANCE * s, blockSize=odd(BLOCK_SIZE * s)
        )
        if found is not None:
            pts = found.reshape(-1, 2).astype(np.float32)
    return PreparedImage(img, frame, work, grey, pts, max_pixels)


def _lk_parameters(scale: float) -> tuple[tuple[int, int], int]:
    """LK window and pyramid levels for a working image of ``scale``: the window
    scales with the image up to the reference and levels are added above it
    (a larger window costs its area on every level)."""
    if scale <= 1.0:
        win = odd(LK_WINDOW * scale, 7)
        levels = max(1, LK_LEVELS + int(round(np.log2(max(scale, 1e-3)))))
    else:
        win = LK_WINDOW
        levels = LK_LEVELS + int(round(np.log2(scale)))
    return (win, win), levels


def prepare_pair(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    *,
    corners: bool = True,
    max_pixels: int | None = None,
) -> tuple[PreparedImage, PreparedImage]:
    """Both images prepared for one working resolution (the synthetic one with
    corners when ``corners``).

    ``max_pixels`` defaults to that of a prepared ``real`` (else
    :data:`~adapt.vision.scale.MAX_WORK_PIXELS`).

    Raises
    ------
    VisionError
        If either is not a usable image or their sizes differ.
    """
    check_pair(
        real.image if isinstance(real, PreparedImage) else real,
        synthetic.image if isinstance(synthetic, PreparedImage) else synthetic,
    )
    if max_pixels is None:
        max_pixels = real.max_pixels if isinstance(real, PreparedImage) else MAX_WORK_PIXELS
    r = prepare(real, corners=False, max_pixels=max_pixels, name="real")
    s = prepare(synthetic, corners=corners, max_pixels=max_pixels, name="synthetic")
    return r, s


def track(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    *,
    fb_max: float | None = None,
) -> Matches:
    """Track the synthetic image's corners into the real image (pyramidal LK
    with a forward-backward check), on the working images.

    Parameters
    ----------
    real, synthetic : ndarray or PreparedImage
    fb_max : float, optional
        Forward-backward bound in working pixels; :data:`FB_MAX` scaled with
        the working image by default.

    Returns
    -------
    Matches
        ``method == "lk"``, in working pixels; possibly empty.
    """
    r, s = prepare_pair(real, synthetic)
    ps = s.corners
    if len(ps) == 0:
        return _empty("lk", 0)
    scale = r.frame.scale
    fb_max = FB_MAX * scale if fb_max is None else fb_max
    p0 = ps.reshape(-1, 1, 2)
    win, levels = _lk_parameters(scale)
    p1, st1, _ = cv2.calcOpticalFlowPyrLK(  # type: ignore[call-overload]
        s.grey, r.grey, p0, None, winSize=win, maxLevel=levels, criteria=_LK_CRITERIA
    )
    ok = st1.ravel() == 1
    if not ok.any():
        return _empty("lk", len(ps))
    p0k, p1k = p0[ok], p1[ok]
    pb, st2, _ = cv2.calcOpticalFlowPyrLK(
        r.grey, s.grey, p1k, p0k.copy(), winSize=win, maxLevel=levels,
        criteria=_LK_CRITERIA, flags=cv2.OPTFLOW_USE_INITIAL_FLOW,
    )
    fb = np.linalg.norm((pb - p0k).reshape(-1, 2), axis=1)
    h, w = r.grey.shape
    dst = p1k.reshape(-1, 2)
    keep = (
        (st2.ravel() == 1)
        & (fb < fb_max)
        & (dst[:, 0] >= 0) & (dst[:, 0] <= w - 1)
        & (dst[:, 1] >= 0) & (dst[:, 1] <= h - 1)
    )
    q = np.maximum(1.0 - fb[keep] / fb_max, Q_MIN)
    return Matches(
        dst[keep].astype(np.float64),
        p0k.reshape(-1, 2)[keep].astype(np.float64),
        q.astype(np.float64),
        "lk",
        len(ps),
    )


def match_descriptors(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    *,
    ratio: float = RATIO,
    n_features: int = SIFT_FEATURES,
) -> Matches:
    """Re-acquire matches with SIFT descriptors and Lowe's ratio test.

    Slower than :func:`track` (about 0.2 s at 640x480) but works for offsets
    far beyond LK's reach.  q(p) is ``1 - d1/d2`` rescaled to ``(0, 1]`` over
    the accepted ratio range.  Runs on the working images; the matches are in
    working pixels.
    """
    r, s = prepare_pair(real, synthetic, corners=False)
    rg, sg = r.grey, s.grey
    sift = cv2.SIFT_create(nfeatures=n_features)  # type: ignore[attr-defined]
    ks, ds = sift.detectAndCompute(sg, None)
    kr, dr = sift.detectAndCompute(rg, None)
    if ds is None or dr is None or len(ks) < 2 or len(kr) < 2:
        return _empty("sift", len(ks) if ks is not None else 0)
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(ds, dr, k=2)
    src, dst, q = [], [], []
    for pair in pairs:
        if len(pair) < 2:
            continue
        a, b = pair
        if b.distance > 0 and a.distance < ratio * b.distance:
            src.append(ks[a.queryIdx].pt)
            dst.append(kr[a.trainIdx].pt)
            q.append(max(1.0 - (a.distance / b.distance) / ratio, Q_MIN))
    if not src:
        return _empty("sift", len(ks))
    return Matches(
        np.asarray(dst, np.float64), np.asarray(src, np.float64), np.asarray(q), "sift", len(ks)
    )


def match(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    *,
    min_tracked: int = MIN_TRACKED,
    reacquire: bool = True,
) -> Matches:
    """LK tracks from synthetic to real; SIFT re-acquisition when fewer than
    ``min_tracked`` tracks survive (and ``reacquire`` is true).

    Raises
    ------
    VisionError
        If the images cannot be compared (see :func:`~adapt.vision.images.check_pair`).
    """
    m = track(real, synthetic)
    if len(m) >= min_tracked or not reacquire:
        return m
    d = match_descriptors(real, synthetic)
    return d if len(d) > len(m) else m
