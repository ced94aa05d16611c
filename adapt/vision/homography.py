"""The homography ``H_e`` mapping synthetic pixels to real ones, or an explicit
"no alignment".

``H_e`` is estimated from :class:`~adapt.vision.matching.Matches` with OpenCV's
USAC_MAGSAC (RANSAC when MAGSAC finds nothing).  The estimate is accepted only
when

* at least :data:`MIN_INLIERS` matches agree with it,
* those inliers are spread over the image (their bounding box covers at least
  :data:`MIN_SPREAD` of each image side), so ``H_e`` is not an extrapolation
  from one corner, and
* ``H_e`` is finite, orientation preserving and not near-singular.

Otherwise the :class:`Alignment` has ``homography=None`` and a ``reason``;
there is never a bad ``H`` presented as good.

Examples
--------
>>> import numpy as np
>>> from adapt.vision.matching import Matches
>>> rng = np.random.default_rng(1)
>>> src = rng.uniform(0, 300, (60, 2))
>>> m = Matches(src + [4.0, -2.0], src, np.ones(60), "lk")
>>> a = estimate_homography(m, (300, 300))
>>> a.aligned, a.n_inliers, a.homography[:2, 2].round(3).tolist()
(True, 60, [4.0, -2.0])
>>> estimate_homography(Matches(src[:5], src[:5], np.ones(5), "lk"), (300, 300)).reason
'5 matches, fewer than the 12 needed'
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.vision.matching import Matches
from adapt.vision.scale import image_scale

__all__ = [
    "Alignment",
    "estimate_homography",
    "corner_error",
    "MIN_INLIERS",
    "MIN_SPREAD",
    "REPROJECTION_THRESHOLD",
]

#: Fewer inliers than this is "no alignment".
MIN_INLIERS = 12
#: Inliers must span at least this fraction of the image width and of its height.
MIN_SPREAD = 0.25
#: Inlier threshold of the robust estimator, pixels at 640x480 (scaled with
#: the image, :mod:`~adapt.vision.scale`).
REPROJECTION_THRESHOLD = 3.0
#: Largest acceptable condition number of the normalised H (degenerate beyond).
MAX_CONDITION = 1e4

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True, eq=False)
class Alignment:
    """The result of fitting ``H_e``.

    Attributes
    ----------
    homography : (3, 3) float64 ndarray or None
        Maps synthetic pixels to real ones (``H[2, 2] == 1``); ``None`` when
        there is no alignment.
    inliers : (N,) bool ndarray
        Which of the matches agree with ``homography`` (all False without one).
    method : {"magsac", "ransac", "held", "none"}
        How ``homography`` was found; ``"held"``: this frame's matches gave none and
        the caller's was used (:func:`~adapt.vision.mmd.mmd`'s ``hold``).
    reason : str
        Why there is no alignment, or why it was held ("" when estimated).
    """

    homography: FloatArray | None
    inliers: NDArray[np.bool_] = field(repr=False)
    method: Literal["magsac", "ransac", "held", "none"]
    reason: str = ""

    @property
    def held(self) -> bool:
        """True when the homography was held, not estimated from this frame's matches."""
        return self.method == "held"

    @property
    def aligned(self) -> bool:
        """True when a homography was accepted."""
        return self.homography is not None

    @property
    def n_inliers(self) -> int:
        """Number of inlier matches."""
        return int(np.count_nonzero(self.inliers))


def _reject(n: int, reason: str) -> Alignment:
    return Alignment(None, np.zeros(n, bool), "none", reason)


def _check(h: NDArray, pts: FloatArray, shape: tuple[int, int]) -> str:
    """Why ``h`` with inlier points ``pts`` is not acceptable ('' if it is)."""
    if h is None or h.shape != (3, 3) or not np.isfinite(h).all() or abs(h[2, 2]) < 1e-12:
        return "the estimator returned no finite homography"
    hh, ww = shape
    span = pts.max(axis=0) - pts.min(axis=0)
    if span[0] < MIN_SPREAD * ww or span[1] < MIN_SPREAD * hh:
        return (
            f"the inliers span only {span[0]:.0f}x{span[1]:.0f} pixels, "
            f"less than {MIN_SPREAD:.0%} of the {ww}x{hh} image"
        )
    # Condition in normalised coordinates (pixel scale removed).
    t = np.array([[1.0 / ww, 0, 0], [0, 1.0 / hh, 0], [0, 0, 1.0]])
    hn = t @ (h / h[2, 2]) @ np.linalg.inv(t)
    if np.linalg.det(hn) <= 0:
        return "the homography flips the image (negative determinant)"
    if np.linalg.cond(hn) > MAX_CONDITION:
        return "the homography is nearly singular"
    corners = np.array([[0, 0, 1], [ww - 1, 0, 1], [ww - 1, hh - 1, 1], [0, hh - 1, 1]], float)
    if ((corners @ h.T)[:, 2] / h[2, 2] <= 0).any():
        return "the homography sends an image corner to infinity"
    return ""


def estimate_homography(
    matches: Matches,
    shape: tuple[int, ...],
    *,
    min_inliers: int = MIN_INLIERS,
    threshold: float | None = None,
) -> Alignment:
    """Fit ``H_e`` (synthetic -> real) robustly to ``matches``.

    Parameters
    ----------
    matches : Matches
    shape : tuple
        The images' shape (``(H, W)`` or ``(H, W, C)``).
    min_inliers : int
        Below this many inliers the result is "no alignment".
    threshold : float, optional
        Reprojection threshold of the robust estimator, pixels;
        :data:`REPROJECTION_THRESHOLD` scaled with the image by default.
    """
    if threshold is None:
        threshold = REPROJECTION_THRESHOLD * image_scale(shape)
    n = len(matches)
    if n < max(min_inliers, 4):
        return _reject(n, f"{n} matches, fewer than the {max(min_inliers, 4)} needed")
    src = matches.synthetic_points.astype(np.float32)
    dst = matches.real_points.astype(np.float32)
    hw = (int(shape[0]), int(shape[1]))
    reason = ""
    for method, flag in (("magsac", cv2.USAC_MAGSAC), ("ransac", cv2.RANSAC)):
        try:
            h, inl = cv2.findHomography(src, dst, flag, threshold, maxIters=2000, confidence=0.999)
        except cv2.error as exc:  # degenerate input (e.g. collinear points)
            reason = f"the estimator failed ({str(exc).splitlines()[-1].strip()})"
            continue
        if h is None or inl is None:
            reason = "the estimator found no consistent homography"
            continue
        inliers = inl.ravel().astype(bool)
        k = int(inliers.sum())
        if k < min_inliers:
            reason = f"{k} inliers, fewer than the {min_inliers} needed"
            continue
        reason = _check(h, matches.real_points[inliers], hw)
        if reason:
            continue
        return Alignment(np.asarray(h / h[2, 2], np.float64), inliers, method)  # type: ignore[arg-type]
    return _reject(n, reason)


def corner_error(homography: NDArray, reference: NDArray, shape: tuple[int, ...]) -> float:
    """Mean displacement, in pixels, between where ``homography`` and
    ``reference`` send the four image corners.

    ``corner_error(H, np.eye(3), shape)`` is the pixel offset that ``H``
    represents (the sync loop's error measure).

    Examples
    --------
    >>> t = np.array([[1, 0, 3.0], [0, 1, 4.0], [0, 0, 1]])
    >>> corner_error(t, np.eye(3), (480, 640))
    5.0
    """
    hh, ww = int(shape[0]), int(shape[1])
    c = np.array([[0, 0, 1], [ww, 0, 1], [ww, hh, 1], [0, hh, 1]], float)
    a = c @ np.asarray(homography, float).T
    b = c @ np.asarray(reference, float).T
    a = a[:, :2] / a[:, 2:]
    b = b[:, :2] / b[:, 2:]
    return float(np.linalg.norm(a - b, axis=1).mean())
