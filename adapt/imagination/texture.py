"""Textures: images tiled over the floor, walls and obstacles.

A texture reference is a path to an image file or ``"builtin:NAME"`` for one
of the CC0 photographs bundled in ``adapt/data/textures`` (see the
``LICENSE.md`` there).  :func:`load_texture` returns a :class:`Texture`: the
image mirrored into a 2x2 tile (so wrapping it has no seams) and a mip pyramid
of that tile, so distant surfaces do not shimmer.  Loaded textures are cached
per reference.

Examples
--------
>>> t = load_texture("builtin:brick")
>>> t.size, len(t.levels) > 1, t.levels[0].shape
((512, 512), True, (1024, 1024, 3))
>>> load_texture("no/such/file.png")
Traceback (most recent call last):
...
adapt.errors.ImageError: texture file 'no/such/file.png' is missing or not a readable image
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import ImageError
from adapt.imagination.scene import BUILTIN_TEXTURES
from adapt.native import native_messages

__all__ = ["Texture", "load_texture", "texture_path", "mip_levels", "TEXTURE_DIR"]

#: Where the bundled textures live.
TEXTURE_DIR = Path(__file__).resolve().parent.parent / "data" / "textures"

#: How a bundled photograph is turned at load so that its "up" is the image's up.
#: scikit-image's ``brick`` was rotated 90 degrees by its source, so its brick
#: courses run vertically; walls need them horizontal.
_UPRIGHT: dict[str, int] = {"brick": cv2.ROTATE_90_COUNTERCLOCKWISE}

#: Smallest mip level kept, in pixels.
_MIN_LEVEL = 8


@dataclass(frozen=True, eq=False)
class Texture:
    """A seamless (mirror-tiled) texture with its mip pyramid.

    ``size`` is ``(width, height)`` in pixels of the original image; ``levels[k]``
    is the 2x2 mirrored tile at ``1 / 2**k`` of full resolution, BGR uint8.
    ``mean`` is the average BGR colour.
    """

    ref: str
    size: tuple[int, int]
    levels: tuple[NDArray[np.uint8], ...]
    mean: tuple[float, float, float]

    @functools.cached_property
    def levels_bgra(self) -> tuple[NDArray[np.uint8], ...]:
        """``levels`` with a fourth (opaque) channel: OpenCV warps four-channel
        images about twice as fast as three-channel ones."""
        out = []
        for level in self.levels:
            four = np.asarray(cv2.cvtColor(level, cv2.COLOR_BGR2BGRA), np.uint8)
            four.setflags(write=False)
            out.append(four)
        return tuple(out)

    @functools.cached_property
    def levels_tiled(self) -> tuple[NDArray[np.uint8], ...]:
        """``levels_bgra`` repeated 2x2 (about 21 MB for a 512-pixel image):
        a warp whose texels span less than one period reads inside this image,
        which OpenCV does several times faster than wrapping at the border."""
        out = []
        for level in self.levels_bgra:
            big = np.asarray(cv2.repeat(level, 2, 2), np.uint8)
            big.setflags(write=False)
            out.append(big)
        return tuple(out)


def texture_path(ref: str) -> Path:
    """The file of a texture reference.

    Examples
    --------
    >>> texture_path("builtin:grass").name
    'grass.png'
    """
    if ref.startswith("builtin:"):
        name = ref[len("builtin:"):]
        if name not in BUILTIN_TEXTURES:
            raise ImageError(f"unknown builtin texture {ref!r}; expected one of {BUILTIN_TEXTURES}")
        return TEXTURE_DIR / f"{name}.png"
    return Path(ref)


@functools.lru_cache(maxsize=32)
def load_texture(ref: str) -> Texture:
    """Load (once) and prepare a texture.

    Bundled photographs are turned upright first (the ``brick`` image ships
    with vertical courses; it is rotated 90 degrees so walls show horizontal
    ones).

    Raises
    ------
    ImageError
        If the file is missing or not an image.
    """
    path = texture_path(ref)
    with native_messages() as said:  # libpng's own complaint goes into the message
        image = cv2.imread(str(path), cv2.IMREAD_COLOR) if path.is_file() else None
    if image is None or image.size == 0:
        raise ImageError(f"texture file {str(path)!r} is missing or not a readable image"
                         f"{said.detail()}")
    turn = _UPRIGHT.get(ref[len("builtin:"):]) if ref.startswith("builtin:") else None
    if turn is not None:
        image = cv2.rotate(image, turn)
    h, w = image.shape[:2]
    top = np.hstack([image, image[:, ::-1]])
    tile = np.ascontiguousarray(np.vstack([top, top[::-1]]))
    mean = tuple(float(c) for c in image.reshape(-1, 3).mean(axis=0))
    return Texture(ref, (w, h), mip_levels(tile), (mean[0], mean[1], mean[2]))


def mip_levels(image: NDArray[np.uint8], max_levels: int = 8, *, box: bool = False
               ) -> tuple[NDArray[np.uint8], ...]:
    """A read-only mip pyramid of ``image``, down to about 8 pixels a side.

    Level ``k + 1`` halves level ``k``: by ``cv2.pyrDown`` (a Gaussian; the
    default, for textures), or, with ``box``, by averages of 2 x 2 pixels (an
    odd last row or column is repeated first), for appearances.  With ``box``
    the centre of pixel ``i`` of level ``k`` lies at ``(i + 0.5) * 2**k - 0.5``
    in level-0 pixels, where :func:`~adapt.imagination.appearance.level_matrix`
    samples it.  ``cv2.pyrDown`` centres its pixel ``i`` on pixel ``2 i`` of its
    source instead, so a texture's level ``k`` is sampled ``(2**k - 1) / 2``
    level-0 pixels off: nothing shows it in a tiled pattern whose phase is
    arbitrary anyway, but an appearance's texels must land where they were
    seen (a learned one was drawn 0.4 px off at 320x240 with pyrDown levels).

    Examples
    --------
    >>> [lv.shape for lv in mip_levels(np.zeros((64, 40, 3), np.uint8))]
    [(64, 40, 3), (32, 20, 3), (16, 10, 3)]
    >>> ramp = np.tile(np.arange(64, dtype=np.uint8) * 2, (16, 1))
    >>> mip_levels(ramp, box=True)[1][0, :3].tolist()   # pixel i: the mean of 2i and 2i + 1
    [1, 5, 9]
    """
    levels = [np.ascontiguousarray(image)]
    while min(levels[-1].shape[:2]) >= 2 * _MIN_LEVEL and len(levels) < max_levels:
        levels.append(_halve(levels[-1]) if box else cv2.pyrDown(levels[-1]))  # type: ignore[arg-type]
    levels[0] = levels[0].copy() if levels[0] is image else levels[0]
    for level in levels:
        level.setflags(write=False)
    return tuple(levels)


def _halve(image: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Averages of 2 x 2 pixels (an odd last row or column repeated)."""
    h, w = image.shape[:2]
    if h % 2 or w % 2:
        image = np.asarray(cv2.copyMakeBorder(image, 0, h % 2, 0, w % 2, cv2.BORDER_REPLICATE),
                           np.uint8)
        h, w = image.shape[:2]
    return np.asarray(cv2.resize(image, (w // 2, h // 2), interpolation=cv2.INTER_AREA), np.uint8)
