"""The images a PyBullet reality's surfaces and balls wear.

:func:`surface_image` makes the image of one :class:`~adapt.reality.bullet.draw.SurfaceLook`:
an image file or a bundled photograph as it is, a plain colour, or a procedural
pattern (``checker``, ``stripes``, ``blotches``, ``tiles``, ``speckle``,
``planks``) made from the surface's seed in its two colours.  :func:`ball_image`
makes a ball's: its colour, with two light bands along meridians when it carries
marks (so its spin shows, as the seams of a real ball do).

Images are BGR ``uint8`` as OpenCV writes them; PyBullet's ``loadTexture`` reads
the files written by :func:`write_textures`, which are removed as soon as they
are loaded.

Examples
--------
>>> from adapt.reality.bullet.draw import SurfaceLook
>>> look = SurfaceLook("floor", "pattern", "checker", (200, 40, 40), (20, 20, 200), 0.5,
...                    (0.0, 0.0), seed=3)
>>> image = surface_image(look)
>>> image.shape, image.dtype.name
((256, 256, 3), 'uint8')
>>> ball_image((230, 60, 30), marks=True).shape
(64, 128, 3)
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path
from typing import Callable, Iterable

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import RealityError
from adapt.imagination.texture import texture_path
from adapt.reality.bullet.draw import SurfaceLook

__all__ = ["surface_image", "ball_image", "write_textures", "SIZE", "MAX_SIDE"]

#: Side of a procedural pattern's image, pixels.
SIZE = 256
#: Longest side of a texture image handed to PyBullet, pixels (larger ones are shrunk).
MAX_SIDE = 1024

Image = NDArray[np.uint8]
RGB = tuple[int, int, int]


def _bgr(color: RGB) -> NDArray[np.float64]:
    return np.array([color[2], color[1], color[0]], float)


def _mix(weight: NDArray[np.float64], a: RGB, b: RGB) -> Image:
    """Per pixel ``a`` where ``weight`` is 0 and ``b`` where it is 1."""
    w = np.clip(weight, 0.0, 1.0)[..., None]
    return np.clip(_bgr(a) * (1.0 - w) + _bgr(b) * w, 0, 255).astype(np.uint8)


def _smooth_noise(rng: np.random.Generator, cells: int) -> NDArray[np.float64]:
    """A smooth random field in 0..1 that wraps around (``cells`` blobs a side)."""
    small = rng.random((cells, cells))
    big = cv2.resize(np.tile(small, (3, 3)), (3 * SIZE, 3 * SIZE), interpolation=cv2.INTER_CUBIC)
    field = big[SIZE:2 * SIZE, SIZE:2 * SIZE]
    lo, hi = float(field.min()), float(field.max())
    return np.asarray((field - lo) / max(hi - lo, 1e-9), np.float64)


def _checker(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    n = int(rng.choice([2, 4]))
    idx = np.arange(SIZE) * n // SIZE
    w = ((idx[:, None] + idx[None, :]) % 2).astype(float)
    return _mix(w + 0.08 * rng.standard_normal((SIZE, SIZE)), a, b)


def _stripes(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    n = int(rng.choice([1, 2, 3]))
    duty = float(rng.uniform(0.2, 0.6))
    x = (np.arange(SIZE) * n / SIZE) % 1.0
    w = np.tile((x < duty).astype(float), (SIZE, 1))
    if rng.random() < 0.5:
        w = w.T
    return _mix(w + 0.06 * rng.standard_normal((SIZE, SIZE)), a, b)


def _blotches(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    field = _smooth_noise(rng, int(rng.integers(3, 9)))
    fine = _smooth_noise(rng, 32)
    return _mix(0.8 * field + 0.2 * fine, a, b)


def _tiles(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    n = int(rng.choice([2, 4]))
    grout = max(2, SIZE // (n * int(rng.integers(10, 20))))
    cell = SIZE // n
    shade = 1.0 + 0.15 * rng.standard_normal((n, n))
    idx = np.arange(SIZE) // cell
    base = np.asarray(_bgr(a) * shade[idx[:, None], idx[None, :]][..., None], np.float64)
    line = ((np.arange(SIZE) % cell) < grout)
    g = line[:, None] | line[None, :]
    out = np.where(g[..., None], _bgr(b), base)
    out = out + 6.0 * rng.standard_normal(out.shape)
    return np.clip(out, 0, 255).astype(np.uint8)


def _speckle(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    w = (rng.random((SIZE, SIZE)) < 0.08).astype(float)
    w = np.asarray(cv2.GaussianBlur(w, (0, 0), 0.8), np.float64) * 2.5
    return _mix(w + 0.1 * rng.standard_normal((SIZE, SIZE)), a, b)


def _planks(rng: np.random.Generator, a: RGB, b: RGB) -> Image:
    n = int(rng.choice([3, 4, 6]))
    rows = np.arange(SIZE) * n // SIZE
    shade = rng.uniform(0.0, 0.6, n)
    grain = _smooth_noise(rng, 48)
    grain = np.asarray(cv2.resize(grain[:, :8], (SIZE, SIZE), interpolation=cv2.INTER_LINEAR),
                       np.float64)
    w = shade[rows][:, None] + 0.3 * grain.T
    edge = (np.arange(SIZE) % (SIZE // n)) < 2
    w[edge, :] = 1.0
    return _mix(w, a, b)


_PATTERNS: dict[str, Callable[[np.random.Generator, RGB, RGB], Image]] = {
    "checker": _checker, "stripes": _stripes, "blotches": _blotches, "tiles": _tiles,
    "speckle": _speckle, "planks": _planks}


def surface_image(look: SurfaceLook) -> Image:
    """The image one surface wears (BGR), see the module docstring.

    Raises
    ------
    RealityError
        For a texture file that cannot be read.
    """
    if look.kind == "pattern":
        assert look.ref is not None
        return _PATTERNS[look.ref](np.random.default_rng(look.seed), look.color, look.color2)
    if look.kind == "texture":
        assert look.ref is not None
        path = texture_path(look.ref)
        image = cv2.imread(str(path), cv2.IMREAD_COLOR) if path.is_file() else None
        if image is None or image.size == 0:
            raise RealityError(f"texture file {str(path)!r} is missing or not a readable image")
        side = max(image.shape[:2])
        if side > MAX_SIDE:  # TinyRenderer samples it texel by texel: more is only memory
            f = MAX_SIDE / side
            image = cv2.resize(image, (max(1, round(image.shape[1] * f)),
                                       max(1, round(image.shape[0] * f))),
                               interpolation=cv2.INTER_AREA)
        return np.asarray(image, np.uint8)
    rng = np.random.default_rng(look.seed)
    flat = np.tile(_bgr(look.color), (16, 16, 1)) + 3.0 * rng.standard_normal((16, 16, 3))
    return np.clip(flat, 0, 255).astype(np.uint8)


def ball_image(color: RGB, marks: bool) -> Image:
    """A ball's image (``u`` around, ``v`` pole to pole): its colour, with two light
    bands along meridians when it carries ``marks``."""
    image = np.tile(_bgr(color), (64, 128, 1))
    if marks:
        light = 0.45 * _bgr(color) + 0.55 * 245.0
        for u in (0, 64):
            image[:, u:u + 5] = light
    return np.clip(image, 0, 255).astype(np.uint8)


def write_textures(images: Iterable[tuple[str, Image]], load: Callable[[str], int]) -> dict[str, int]:
    """Write each ``(name, image)`` to a temporary PNG, ``load`` it (PyBullet's
    ``loadTexture``), and remove the files; returns name -> texture id."""
    folder = Path(tempfile.mkdtemp(prefix="adapt-bullet-"))
    try:
        out = {}
        for i, (name, image) in enumerate(images):
            path = folder / f"{i}.png"
            if not cv2.imwrite(str(path), image):
                raise RealityError(f"cannot write a texture image to {str(path)!r}")
            out[name] = int(load(str(path)))
        return out
    finally:
        shutil.rmtree(folder, ignore_errors=True)
