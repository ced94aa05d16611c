"""Texture: where the real frame is flat over a textured background.

A per-pixel difference misses an object whose colour is its background's mean: a grey
ball on grey gravel differs from the gravel only where a grain is lighter or darker than
the ball, so its difference comes in fragments.  What does tell it from the gravel is its
texture: the ball is smooth, the gravel is not.  :func:`flat_over_texture` marks the
pixels of the neighbourhoods that in the real frame have far less contrast (local
standard deviation) than the same neighbourhoods of the reference (the learned background,
aligned to the real frame): something smooth covers a textured surface there.

The test is one-sided.  A learned look is smoother than the frames it was learned from
(a temporal median, resampled through the alignment), so a real frame over a textured
floor is, if anything, rougher than its reference; only an object that hides the texture
makes it flatter.  A textured object over a smooth floor is not found this way -- its
colour differs from the floor's, and the per-pixel difference finds it.

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> gravel = rng.integers(80, 180, (40, 40, 3)).astype(np.uint8)
>>> real = gravel.copy()
>>> real[10:30, 10:30] = 130               # a smooth patch of the gravel's mean colour
>>> flat = flat_over_texture(real, gravel)
>>> bool(flat[20, 20]), bool(flat[2, 2]), bool(flat[20, 2])
(True, False, False)
>>> int(flat.sum()) > 0.6 * 20 * 20 and not flat[:8].any()
True
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import VisionError

__all__ = ["FLAT_BLOCK", "FLAT_SHARE", "TEXTURE_MIN", "TEXTURE_WINDOW", "flat_over_texture", "local_contrast"]

#: The side of the square neighbourhood the local contrast is measured over, pixels.
TEXTURE_WINDOW = 5
#: Flat: the real frame's local contrast below this share of the reference's.  Over a
#: textured floor the real frame's contrast is rarely below 0.9 of its learned look's (the
#: look is the smoother); over a smooth object it is its sensor noise, a third or less.
FLAT_SHARE = 0.5
#: Flat windows count only in blocks of this many of their centres across: a lone window
#: of gravel that happens to be smooth is not an object.
FLAT_BLOCK = 3
#: Textured: the reference's local contrast (grey levels) at least this -- below it the
#: reference is smooth itself (a painted floor, the sky) and flatness says nothing.
TEXTURE_MIN = 4.0


def local_contrast(image: NDArray[np.uint8], window: int = TEXTURE_WINDOW) -> NDArray[np.float32]:
    """The standard deviation of the grey levels in each pixel's ``window`` x ``window``
    neighbourhood about the plane that fits them best; for a colour image, of the colours
    (the root of the channels' variances summed: two stripes of one brightness and two
    hues are contrast too).

    Texture is contrast on the scale of a few pixels; shading is a slope across them.  The
    plane takes the slope out: the band between a ball's highlight and its shaded side is
    as flat as the rest of it.

    >>> import numpy as np
    >>> flat = np.full((6, 6), 100, np.uint8)
    >>> float(local_contrast(flat).max())
    0.0
    >>> ramp = np.tile(np.arange(0, 120, 20, dtype=np.uint8), (6, 1))   # shading
    >>> float(local_contrast(ramp, 3)[2:4, 2:4].max())
    0.0
    >>> stripes = np.tile(np.array([0, 200], np.uint8), (6, 3))
    >>> round(float(local_contrast(stripes, 3)[3, 3]), 1)     # 200, 0, 200 across: 94.3
    94.3
    """
    return _moments(image, window)[1]


def _moments(image: NDArray[np.uint8], window: int
             ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Each neighbourhood's mean (per channel: ``(h, w)`` or ``(h, w, c)``) and
    :func:`local_contrast` (``(h, w)``)."""
    if window < 3 or window % 2 == 0:
        raise VisionError(f"the texture window must be an odd number of pixels, at least 3, "
                          f"got {window}")
    # about mid-grey: float32's E[x^2] - E[x]^2 keeps a hundredth of a level then
    g = image.astype(np.float32) - np.float32(128.0)
    border = cv2.BORDER_REFLECT
    mean = cv2.boxFilter(g, -1, (window, window), borderType=border)
    mean_sq = cv2.boxFilter(g * g, -1, (window, window), borderType=border)
    # the best plane's slopes: the levels' covariance with the offset across (down) over the
    # offset's variance, (window**2 - 1) / 12
    half = window // 2
    ramp = np.arange(-half, half + 1, dtype=np.float32)
    ramp_var = float((ramp * ramp).mean())
    weights = ramp / np.float32(window * window * ramp_var)   # the ramp's, one way
    flat = np.ones(window, np.float32)                         # the other way, summed
    slope_x = cv2.sepFilter2D(g, -1, weights, flat, borderType=border)
    slope_y = cv2.sepFilter2D(g, -1, flat, weights, borderType=border)
    residual = mean_sq - mean * mean - ramp_var * (slope_x * slope_x + slope_y * slope_y)
    residual = np.maximum(residual, 0.0)
    if residual.ndim == 3:
        residual = residual.sum(axis=2)
    return mean + np.float32(128.0), np.sqrt(residual)


def flat_over_texture(real: NDArray[np.uint8], reference: NDArray[np.uint8], *,
                      window: int = TEXTURE_WINDOW, share: float = FLAT_SHARE,
                      texture_min: float = TEXTURE_MIN, block: int = FLAT_BLOCK,
                      mean_within: float | None = None) -> NDArray[np.bool_]:
    """Pixels where ``real`` is flat and ``reference`` (the same view, aligned) is textured:
    those of every ``window`` x ``window`` neighbourhood whose :func:`local_contrast` in the
    real frame is below ``share`` of the reference's, the reference's at least
    ``texture_min`` grey levels, and (given ``mean_within``) whose mean grey levels in the
    two differ by at most ``mean_within`` (in every channel).

    The last is camouflage: an object whose grey differs from its background's by more
    than a difference threshold shows in the per-pixel difference anyway.  What is flat
    over texture but of another mean is mostly the reference's own error -- a ghost, an
    edge a few pixels off -- and the per-pixel difference has it already.

    Parameters
    ----------
    real, reference : ndarray of uint8
        The same shape, grey or colour (``(h, w)`` or ``(h, w, c)``).
    window : int
        The neighbourhood's side, odd, at least 3.
    share : float
        In (0, 1).
    texture_min : float
        Grey levels, at least 0.
    block : int
        Pixels, at least 1: the flat neighbourhoods' centres are kept where a square of
        ``block`` x ``block`` of them is whole (an opening).
    mean_within : float or None
        Grey levels, at least 0; None: any mean.

    Returns
    -------
    ndarray of bool
        ``(h, w)``.
    """
    if real.shape != reference.shape:
        raise VisionError(f"real {real.shape} and reference {reference.shape} differ in shape")
    if not 0.0 < share < 1.0:
        raise VisionError(f"the flat share must be in (0, 1), got {share}")
    if texture_min < 0.0:
        raise VisionError(f"the texture minimum must be at least 0, got {texture_min}")
    if block < 1:
        raise VisionError(f"the flat block must be at least 1 pixel, got {block}")
    if mean_within is not None and mean_within < 0.0:
        raise VisionError(f"the mean's tolerance must be at least 0, got {mean_within}")
    real_mean, real_contrast = _moments(real, window)
    ref_mean, ref_contrast = _moments(reference, window)
    centres = (real_contrast < share * ref_contrast) & (ref_contrast >= texture_min)
    # a neighbourhood past the image's edge is its mirror image there: not measured
    half = window // 2
    centres[:half], centres[len(centres) - half:] = False, False
    centres[:, :half], centres[:, centres.shape[1] - half:] = False, False
    if mean_within is not None:
        off = np.abs(real_mean - ref_mean)
        centres &= (off.max(axis=2) if off.ndim == 3 else off) <= mean_within
    # a window of the texture that happens to be twice as rough in the reference as in the
    # frame (the alignment a grain off) is alone; an object's flat windows come in blocks
    flat = cv2.morphologyEx(centres.view(np.uint8), cv2.MORPH_OPEN,
                            np.ones((block, block), np.uint8))
    # a flat neighbourhood is flat throughout: the union of the flat windows reaches the
    # object's outline (their centres alone stop half a window inside it, and a highlight
    # on its top, found by the per-pixel difference, would be cut off from its body)
    return cv2.dilate(flat, np.ones((window, window), np.uint8)).astype(bool)
