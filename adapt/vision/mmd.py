"""The Match-Mediated Difference (MMD): what the imagination does not explain.

:func:`mmd` compares a real image ``I_r`` with a synthetic (rendered) one
``I_s`` of the same scene:

1. corners of ``I_s`` are matched into ``I_r``
   (:func:`~adapt.vision.matching.track`; SIFT re-acquisition when fewer than
   :data:`REACQUIRE_INLIERS` tracked matches, or less than
   :data:`REACQUIRE_RATIO` of them, fit the homography);
2. ``H_e`` maps synthetic pixels to real ones
   (:func:`~adapt.vision.homography.estimate_homography`; below its minimum
   inlier count the result says "no alignment" and every pixel is unknown);
3. ``W = warp(I_s, H_e)`` is the synthetic image seen in the real frame;
4. the mask ``I_m`` (:mod:`~adapt.vision.mask`) is the clipped sum of
   Gaussians on the inlier matches' real positions, weighted by ``q(p)``;
5. a per-channel gain and bias ``a_c W_c + b_c`` is fitted by least squares to
   ``I_r`` over the pixels the matches explain (``I_m >= 0.5``), so a global
   brightness or colour difference between renderer and camera is not a
   difference;
6. ``I_d = max_c |I_r,c - (a_c W_c + b_c)| * (1 - I_m)``, in grey levels
   (0-255), and ``0`` at *unknown* pixels: those the warped synthetic image
   does not cover (``MMDResult.known`` is False there).  Unknown is not
   difference.

The result is a frozen :class:`MMDResult`; :meth:`MMDResult.regions` (through
:mod:`~adapt.vision.regions`) turns ``difference`` into regions.

**Scale.**  The inputs are converted by :func:`~adapt.vision.images.conform`
and analysed at a working resolution of at most 640x480 pixels (larger
images are reduced, :mod:`~adapt.vision.scale`); every pixel parameter is
given for 640x480 and scaled with the working image.  ``H_e``, the matches
and the regions are reported in the inputs' pixels.

Examples
--------
>>> import numpy as np, cv2
>>> from adapt.vision.homography import corner_error
>>> rng = np.random.default_rng(0)
>>> scene = cv2.GaussianBlur(rng.integers(0, 256, (240, 320), dtype=np.uint8), (0, 0), 1.5)
>>> synthetic = scene[20:220, 20:300]
>>> real = scene[22:222, 25:305]                       # the camera moved a little
>>> real = cv2.convertScaleAbs(real, alpha=0.8, beta=30)  # and sees it dimmer
>>> r = mmd(real, synthetic)
>>> shift = np.array([[1, 0, -5.0], [0, 1, -2.0], [0, 0, 1]])   # synthetic -> real
>>> r.aligned, corner_error(r.homography, shift, real.shape) < 0.3
(True, True)
>>> float(r.gain[0]).__round__(2), float(np.percentile(r.difference[r.known], 99)) < 10
(0.8, True)
>>> bool(r.known[:, -3:].any())                       # the uncovered strip
False
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.vision.homography import MIN_INLIERS, Alignment, estimate_homography
from adapt.vision.images import conform
from adapt.vision.mask import exact_mask, fast_mask
from adapt.vision.matching import Matches, PreparedImage, match_descriptors, prepare_pair, track
from adapt.vision.regions import MIN_OVERLAP, THRESHOLD, Region, find_regions, label_regions, to_input
from adapt.vision.scale import WorkingFrame

__all__ = ["MMDResult", "mmd", "REACQUIRE_INLIERS", "REACQUIRE_RATIO", "EXPLAINED"]

#: Fewer tracked inliers than this: re-acquire with SIFT and keep the better fit.
REACQUIRE_INLIERS = 40
#: A smaller share of tracked matches agreeing with H_e (repetitive texture,
#: where LK can lock onto the neighbouring period) also triggers re-acquisition.
REACQUIRE_RATIO = 0.5
#: Mask level above which a pixel counts as explained (used for the gain/bias fit).
EXPLAINED = 0.5
#: Gain/bias fit uses every FIT_STEP-th pixel in each direction (at 640x480;
#: scaled with the working image).
FIT_STEP = 4
#: Bounds of the fitted gain.
GAIN_RANGE = (0.25, 4.0)


@dataclass(frozen=True, slots=True, eq=False)
class MMDResult:
    """The match-mediated difference of a real and a synthetic image.

    ``alignment`` and ``matches`` are in the input images' pixels; the images
    (``warped``, ``mask``, ``known``, ``difference``) are at the working
    resolution ``frame.shape`` (the input's own size up to 640x480 pixels, see
    :mod:`~adapt.vision.scale`); :meth:`regions` gives regions in input pixels.

    Attributes
    ----------
    alignment : Alignment
        ``H_e`` (synthetic -> real pixels) and its inliers, or "no alignment".
    matches : Matches
        The matches ``H_e`` was fitted to.
    warped : ndarray
        The synthetic image warped into the real frame (uint8, zeros where
        unknown; grey when either input is grey).
    mask : (h, w) float32 ndarray
        ``I_m`` in [0, 1], in the real frame.
    known : (h, w) bool ndarray
        Pixels the warped synthetic image covers.
    difference : (h, w) float32 ndarray
        ``I_d`` in grey levels, 0 where unknown.
    gain, bias : (C,) float64 ndarray
        The per-channel fit ``real ~ gain * warped + bias``.
    frame : WorkingFrame
        The working resolution and its maps to the input.
    """

    alignment: Alignment
    matches: Matches = field(repr=False)
    warped: NDArray[np.uint8] = field(repr=False)
    mask: NDArray[np.float32] = field(repr=False)
    known: NDArray[np.bool_] = field(repr=False)
    difference: NDArray[np.float32] = field(repr=False)
    gain: NDArray[np.float64]
    bias: NDArray[np.float64]
    frame: WorkingFrame

    @property
    def aligned(self) -> bool:
        """True when ``H_e`` was found."""
        return self.alignment.aligned

    @property
    def homography(self) -> NDArray[np.float64] | None:
        """``H_e`` mapping synthetic pixels to real ones (input pixels), or None."""
        return self.alignment.homography

    @property
    def n_inliers(self) -> int:
        """Number of inlier matches."""
        return self.alignment.n_inliers

    def regions(
        self,
        monitored: Sequence[Sequence[float]] = (),
        *,
        threshold: float = THRESHOLD,
        min_overlap: float = MIN_OVERLAP,
    ) -> tuple[Region, ...]:
        """The difference regions in input pixels, labelled expected when they
        overlap a ``monitored`` box (input pixels): :func:`find_regions` on
        ``difference`` (its default, scaled, area and cleaning),
        :func:`~adapt.vision.regions.to_input`, then :func:`label_regions`."""
        found = to_input(find_regions(self.difference, threshold=threshold), self.frame)
        return label_regions(found, monitored, min_overlap=min_overlap)


def _align(
    real: PreparedImage, synthetic: PreparedImage, min_inliers: int, reacquire: bool
) -> tuple[Matches, Alignment]:
    shape = real.frame.shape
    m = track(real, synthetic)
    a = estimate_homography(m, shape, min_inliers=min_inliers)
    ratio = a.n_inliers / max(len(m), 1)
    if reacquire and (a.n_inliers < REACQUIRE_INLIERS or ratio < REACQUIRE_RATIO):
        d = match_descriptors(real, synthetic)
        b = estimate_homography(d, shape, min_inliers=min_inliers)
        if b.aligned and (not a.aligned or b.n_inliers > a.n_inliers):
            return d, b
    return m, a


def _known(h: NDArray, shape: tuple[int, int]) -> NDArray[np.bool_]:
    """Real-frame pixels inside the warped synthetic image (1 px inset, so the
    interpolated border is excluded)."""
    hh, ww = shape
    quad = np.array([[1, 1, 1], [ww - 2, 1, 1], [ww - 2, hh - 2, 1], [1, hh - 2, 1]], float)
    p = quad @ h.T
    p = p[:, :2] / p[:, 2:]
    out = np.zeros((hh, ww), np.uint8)
    cv2.fillConvexPoly(out, np.round(p * 16).astype(np.int32), 1, lineType=cv2.LINE_8, shift=4)
    return out.astype(bool)


def _fit_gain(
    real: NDArray[np.uint8], warped: NDArray[np.uint8], use: NDArray[np.bool_], step: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    sel = use[::step, ::step]
    r = real[::step, ::step][sel].astype(np.float64).reshape(-1, real.shape[2] if real.ndim == 3 else 1)
    w = warped[::step, ::step][sel].astype(np.float64).reshape(r.shape)
    c = r.shape[1]
    gain = np.ones(c)
    bias = np.zeros(c)
    if len(r) < 16:
        return gain, bias
    mw, mr = w.mean(axis=0), r.mean(axis=0)
    var = ((w - mw) ** 2).mean(axis=0)
    cov = ((w - mw) * (r - mr)).mean(axis=0)
    for k in range(c):
        gain[k] = np.clip(cov[k] / var[k], *GAIN_RANGE) if var[k] > 1.0 else 1.0
        bias[k] = mr[k] - gain[k] * mw[k]
    return gain, bias


def mmd(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    *,
    sigma: float | None = None,
    exact: bool = False,
    reacquire: bool = True,
    min_inliers: int = MIN_INLIERS,
    max_pixels: int | None = None,
    hold: NDArray | None = None,
    refuse: Callable[[NDArray[np.float64]], str] | None = None,
) -> MMDResult:
    """Match-mediated difference of ``real`` and ``synthetic``.

    Parameters
    ----------
    real, synthetic : ndarray or PreparedImage
        The same size; grey or BGR; ``uint8``, ``uint16`` or float in
        ``[0, 1]``; converted by :func:`~adapt.vision.images.conform` (a grey
        and a colour image are compared in grey).  Pass a
        :class:`~adapt.vision.matching.PreparedImage` to reuse a rendered
        background's corners across frames.
    sigma : float, optional
        Width of the mask's Gaussians in working pixels;
        :data:`~adapt.vision.mask.SIGMA` (12 px at 640x480) scaled with the
        working image by default.
    exact : bool
        Use :func:`~adapt.vision.mask.exact_mask` instead of the fast one.
    reacquire : bool
        Allow SIFT re-acquisition when tracking gives too few inliers.
    min_inliers : int
        Fewer inliers than this is "no alignment".
    max_pixels : int, optional
        Largest working image in pixels: larger inputs are reduced to it
        (:mod:`~adapt.vision.scale`); 640x480 by default, or what a prepared
        ``real`` was prepared for.
    hold : (3, 3) ndarray, optional
        ``H_e`` (input pixels) to use when this frame's matches give none: the
        caller knows the images are aligned another way (the Scene Background's
        structure alignment).  The result's alignment is then ``held`` (no
        inliers; its ``reason`` says why none was found), and the difference is
        not masked by matches.
    refuse : callable, optional
        Why the matches' ``H_e`` (input pixels) is not to be believed, or ``""``:
        a caller's test that knows more than the images (the camera loop's: no turn
        of the camera makes it, :func:`~adapt.vision.sync.sync_step`).  A refused
        ``H_e`` is no alignment (its ``reason`` says why); ``hold`` then applies.

    Raises
    ------
    VisionError
        If the images cannot be compared.
    """
    r, s = prepare_pair(real, synthetic, max_pixels=max_pixels)
    frame = r.frame
    real8, syn8 = conform(r.work, s.work)
    hh, ww = frame.shape
    channels = real8.shape[2] if real8.ndim == 3 else 1
    matches, alignment = _align(r, s, min_inliers, reacquire)
    if alignment.aligned and refuse is not None:
        h = alignment.homography
        assert h is not None
        why = refuse(frame.homography_to_input(h) if frame.reduces else h)
        if why:
            alignment = replace(alignment, homography=None, inliers=np.zeros_like(alignment.inliers),
                                method="none", reason=why)
    if not alignment.aligned and hold is not None:
        kept = frame.homography_to_work(hold) if frame.reduces else np.asarray(hold, np.float64)
        alignment = replace(alignment, homography=kept, method="held")
    if not alignment.aligned:
        zero = np.zeros((hh, ww), np.float32)
        return MMDResult(
            alignment, _to_input(matches, frame), np.zeros_like(real8), zero,
            np.zeros((hh, ww), bool), zero.copy(), np.ones(channels), np.zeros(channels), frame,
        )
    h = alignment.homography
    assert h is not None
    warped = cv2.warpPerspective(syn8, h, (ww, hh), flags=cv2.INTER_LINEAR,
                                 borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    known = _known(h, (hh, ww))
    pts = matches.real_points[alignment.inliers]
    q = matches.quality[alignment.inliers]
    mask = (exact_mask if exact else fast_mask)(pts, q, (hh, ww), sigma=sigma)
    explained = known & (mask >= EXPLAINED)
    step = max(1, int(round(FIT_STEP * frame.scale)))
    gain, bias = _fit_gain(real8, warped, explained if np.count_nonzero(explained) > 0 else known, step)  # type: ignore[arg-type]
    if channels == 1:
        adjusted = cv2.convertScaleAbs(warped, alpha=float(gain[0]), beta=float(bias[0]))
        diff = cv2.absdiff(real8, adjusted)
    else:
        m = np.zeros((channels, channels + 1), np.float64)
        m[np.arange(channels), np.arange(channels)] = gain
        m[:, -1] = bias
        adjusted = cv2.transform(warped, m)
        per_channel = cv2.split(cv2.absdiff(real8, adjusted))
        diff = per_channel[0]
        for d in per_channel[1:]:
            diff = cv2.max(diff, d)
    difference = diff.astype(np.float32)
    difference *= 1.0 - mask
    difference[~known] = 0.0
    warped[~known] = 0
    if frame.reduces:
        alignment = replace(alignment, homography=frame.homography_to_input(h))
    return MMDResult(
        alignment, _to_input(matches, frame), warped, mask, known, difference, gain, bias, frame  # type: ignore[arg-type]
    )


def _to_input(matches: Matches, frame: WorkingFrame) -> Matches:
    """Matches in working pixels as matches in input pixels."""
    if not frame.reduces:
        return matches
    return replace(
        matches,
        real_points=frame.to_input(matches.real_points),
        synthetic_points=frame.to_input(matches.synthetic_points),
    )
