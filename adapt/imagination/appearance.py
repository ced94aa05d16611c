"""Appearances: images of surfaces that replace the scenario's look.

An :class:`Appearance` is an image of one
:class:`~adapt.imagination.surface.Surface` in its own face coordinates
(``docs/conventions.md``) with a validity mask, such as the texture the Scene
Background schema learns by back-projecting camera frames onto the surface.
Where it is valid it is drawn as given; elsewhere the scenario's texture or
colour shows.

:func:`prepare_atlas` turns an appearance into what the renderers draw: a mip
pyramid of the appearance image in which the invalid pixels hold the
scenario's shaded texture (sampled at the appearance's resolution) or colour.
The renderers then draw the whole extent from it with one warp, and the
boundary between learned and scenario pixels is as smooth as any texture.
It runs once per appearance update, at the appearance image's resolution.

Examples
--------
>>> from adapt.imagination.scene import SceneSpec, Wall
>>> from adapt.imagination.surface import scene_surfaces
>>> wall = scene_surfaces(SceneSpec(walls=(Wall("w", (0, 0), (2, 0), height=1.0),)))[1]
>>> look = Appearance(np.full((50, 100, 3), 200, np.uint8), None, wall.extent)
>>> atlas = prepare_atlas(wall, look)
>>> atlas.covers, atlas.levels[0].shape, atlas.polygon == wall.polygon
(True, (50, 100, 4), True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import ImaginationError
from adapt.geometry import MAX_IMAGE_SIDE, MAX_PIXELS
from adapt.imagination.surface import Extent, Surface, check_extent
from adapt.imagination.texture import load_texture, mip_levels

__all__ = ["Appearance", "Atlas", "prepare_atlas", "texel_matrix"]

FloatArray = NDArray[np.float64]

@dataclass(frozen=True, slots=True, eq=False)
class Appearance:
    """An image of one surface in its own face coordinates, with a validity mask.

    Where ``mask`` is true the image replaces the scenario's texture or
    colour; elsewhere the scenario's shows, at the image's resolution.  The
    image is drawn as given (the renderer's fixed light does not shade it: it
    is what a camera saw).

    Parameters
    ----------
    image : (H, W, 3) uint8 ndarray
        BGR, covering ``extent`` edge to edge (``docs/conventions.md``).
    mask : (H, W) bool or uint8 ndarray, or None
        Valid pixels (non-zero); ``None`` means all.
    extent : (s_min, t_min, s_max, t_max)
        Face coordinates the image covers, metres.
    aligned : bool
        Draw it from mip levels of 2 x 2 averages, whose pixels lie exactly
        where the renderer samples them (an appearance learned from a camera,
        whose texels must land where they were seen); the default Gaussian
        levels, like a texture's, are sampled up to half a coarse texel off
        (see :func:`~adapt.imagination.texture.mip_levels`).

    The arrays are copied and kept read-only.

    Examples
    --------
    >>> a = Appearance(np.zeros((20, 40, 3), np.uint8), None, (0.0, 0.0, 2.0, 1.0))
    >>> a.pixels_per_metre, bool(a.mask.all()), a.image.flags.writeable
    ((20.0, 20.0), True, False)
    >>> Appearance(np.zeros((20, 40), np.uint8), None, (0, 0, 2, 1))
    Traceback (most recent call last):
    ...
    adapt.errors.ImaginationError: image: expected a BGR uint8 image of shape (H, W, 3), got shape (20, 40) and dtype uint8
    """

    image: NDArray[np.uint8]
    mask: NDArray[np.bool_]
    extent: Extent
    aligned: bool

    def __init__(self, image: ArrayLike, mask: ArrayLike | None, extent: Sequence[float],
                 aligned: bool = False) -> None:
        img = np.asarray(image)
        if img.ndim != 3 or img.shape[2] != 3 or img.dtype != np.uint8:
            raise ImaginationError(
                "image: expected a BGR uint8 image of shape (H, W, 3), got shape "
                f"{img.shape} and dtype {img.dtype}"
            )
        h, w = img.shape[:2]
        if not (0 < w <= MAX_IMAGE_SIDE and 0 < h <= MAX_IMAGE_SIDE and w * h <= MAX_PIXELS):
            raise ImaginationError(
                f"image: expected 1 to {MAX_IMAGE_SIDE} pixels a side and at most "
                f"{MAX_PIXELS:,} pixels, got {w}x{h}"
            )
        if mask is None:
            m = np.ones((h, w), bool)
        else:
            m0 = np.asarray(mask)
            if m0.shape != (h, w):
                raise ImaginationError(
                    f"mask: expected shape {(h, w)} (the image's), got {m0.shape}"
                )
            m = m0 != 0
        img = np.array(img, copy=True)
        img.setflags(write=False)
        m.setflags(write=False)
        object.__setattr__(self, "image", img)
        object.__setattr__(self, "mask", m)
        object.__setattr__(self, "extent", check_extent(extent))
        object.__setattr__(self, "aligned", bool(aligned))

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` in pixels."""
        return (int(self.image.shape[1]), int(self.image.shape[0]))

    @property
    def pixels_per_metre(self) -> tuple[float, float]:
        """Resolution along ``s`` and along ``t``."""
        e = self.extent
        return (self.size[0] / (e[2] - e[0]), self.size[1] / (e[3] - e[1]))


@dataclass(frozen=True, slots=True, eq=False)
class Atlas:
    """A prepared appearance (see :func:`prepare_atlas`).

    Attributes
    ----------
    levels : tuple of (H, W, 4) uint8 ndarray
        Mip pyramid (BGRA, opaque): the appearance where valid and the
        scenario's shaded texture or colour elsewhere.
    face_to_texel : (3, 3) ndarray
        Face coordinates ``(s, t, 1)`` to level-0 pixel coordinates.
    polygon : tuple of (s, t)
        The part of the surface the appearance covers (surface polygon and
        extent intersected), counter-clockwise.
    covers : bool
        The extent covers the whole surface: nothing of it is drawn from the
        scenario's texture directly.
    """

    levels: tuple[NDArray[np.uint8], ...]
    face_to_texel: FloatArray
    polygon: tuple[tuple[float, float], ...]
    covers: bool


def texel_matrix(surface: Surface) -> FloatArray | None:
    """Face coordinates ``(s, t, 1)`` to level-0 texel coordinates of the
    surface's texture (``None`` without one): one copy of the image per
    ``tile`` metres, image rows running down with ``t``."""
    if surface.texture is None:
        return None
    w, h = load_texture(surface.texture).size
    return np.array([[w / surface.tile, 0.0, 0.0], [0.0, -h / surface.tile, 0.0], [0.0, 0.0, 1.0]])


def level_matrix(k: int) -> FloatArray:
    """Level-0 pixel coordinates to level-``k`` ones (``(c + 0.5) / 2**k - 0.5``)."""
    f = 2.0 ** -k
    return np.array([[f, 0.0, 0.5 * f - 0.5], [0.0, f, 0.5 * f - 0.5], [0.0, 0.0, 1.0]])


def _clip_to_rect(poly: Sequence[tuple[float, float]], e: Extent) -> list[tuple[float, float]]:
    """Clip a convex polygon to the rectangle ``e`` (Sutherland-Hodgman)."""
    pts = list(poly)
    for axis, bound, keep_above in ((0, e[0], True), (0, e[2], False), (1, e[1], True),
                                    (1, e[3], False)):
        out: list[tuple[float, float]] = []
        n = len(pts)
        for i in range(n):
            p, q = pts[i], pts[(i + 1) % n]
            fp = (p[axis] - bound) if keep_above else (bound - p[axis])
            fq = (q[axis] - bound) if keep_above else (bound - q[axis])
            if fp >= 0:
                out.append(p)
            if (fp >= 0) != (fq >= 0):
                f = fp / (fp - fq)
                out.append((p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])))
        pts = out
        if not pts:
            break
    return pts


def prepare_atlas(surface: Surface, appearance: Appearance) -> Atlas | None:
    """What the renderers draw for ``appearance`` on ``surface``; ``None`` if
    nothing of it is valid or it does not overlap the surface."""
    e = appearance.extent
    if not appearance.mask.any():
        return None
    if surface.polygon is None:
        poly = [(e[0], e[1]), (e[2], e[1]), (e[2], e[3]), (e[0], e[3])]
        covers = False
    else:
        poly = _clip_to_rect(surface.polygon, e)
        se = surface.extent
        assert se is not None
        covers = se[0] >= e[0] and se[1] >= e[1] and se[2] <= e[2] and se[3] <= e[3]
    if len(poly) < 3 or abs(_area(poly)) < 1e-12:
        return None
    w, h = appearance.size
    to_face = surface.image_to_face((w, h), e)
    base = np.empty((h, w, 4), np.uint8)
    shade = surface.shade
    tex = texel_matrix(surface)
    if tex is None or surface.texture is None:
        b, g, r = (c * shade for c in surface.color[::-1])
        base[:] = (min(round(b), 255), min(round(g), 255), min(round(r), 255), 255)
    else:
        texture = load_texture(surface.texture)
        to_tex = tex @ to_face
        foot = max(abs(to_tex[0, 0]), abs(to_tex[1, 1]))
        k = int(np.clip(math.floor(math.log2(max(foot, 1.0))), 0, len(texture.levels) - 1))
        m = level_matrix(k) @ to_tex  # axis-aligned: u by column, v by row
        src = texture.levels_bgra[k]
        lh, lw = src.shape[:2]
        mx = np.mod(m[0, 0] * np.arange(w) + m[0, 2], lw).astype(np.float32)
        my = np.mod(m[1, 1] * np.arange(h) + m[1, 2], lh).astype(np.float32)
        # Sample at coordinates folded into the image: OpenCV's fast path.
        cv2.remap(src, np.repeat(mx[None, :], h, axis=0), np.repeat(my[:, None], w, axis=1),
                  cv2.INTER_LINEAR, dst=base, borderMode=cv2.BORDER_WRAP)
        cv2.convertScaleAbs(base, dst=base, alpha=shade)
    valid = appearance.mask.view(np.uint8) * np.uint8(255)
    cv2.copyTo(cv2.cvtColor(appearance.image, cv2.COLOR_BGR2BGRA), valid, base)
    return Atlas(mip_levels(base, box=appearance.aligned),
                 np.asarray(np.linalg.inv(to_face), np.float64), tuple(poly), covers)


def _area(poly: Sequence[tuple[float, float]]) -> float:
    return 0.5 * sum(poly[i][0] * poly[(i + 1) % len(poly)][1]
                     - poly[(i + 1) % len(poly)][0] * poly[i][1] for i in range(len(poly)))
