"""Validation and conversion of the images MMD compares, and image files.

Every vision function takes ``real`` then ``synthetic``: NumPy arrays of shape
``(H, W)`` (grey) or ``(H, W, 3)`` (BGR, OpenCV's channel order), of dtype
``uint8``, ``uint16`` (full range, 0-65535) or floating point in ``[0, 1]``.
The two must have the same size; anything else is a
:class:`~adapt.errors.VisionError` that says what differs and what was
expected.  They may differ in dtype and in channels: :func:`conform` is the
one conversion both ``adapt mmd`` and ``adapt sync`` (and
:func:`~adapt.vision.mmd.mmd` itself) use; it makes both 8-bit and, when one
is grey and the other colour, compares them in grey.  Inputs are never
modified.

Examples
--------
>>> import numpy as np
>>> real = np.zeros((40, 60, 3), np.uint8)
>>> r, s = conform(real, np.zeros((40, 60), np.uint16))
>>> r.shape, s.shape, s.dtype.name
((40, 60), (40, 60), 'uint8')
>>> check_image(np.zeros((1, 1), np.uint8), "real", source="tiny.png")
Traceback (most recent call last):
...
adapt.errors.VisionError: tiny.png: real image is 1x1 pixels: expected at least 32x32 pixels
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import ImageError, VisionError
from adapt.files import write_atomic
from adapt.geometry import MIN_IMAGE_SIDE
from adapt.native import native_messages

__all__ = [
    "check_image",
    "check_pair",
    "conform",
    "as_uint8",
    "encode_image",
    "to_grey",
    "describe",
    "read_image",
    "write_image",
    "MIN_SIDE",
]

#: Smallest image side MMD accepts (the LK pyramid and the mask need some room).
MIN_SIDE = MIN_IMAGE_SIDE
#: Float images may stray this far outside [0, 1] (rounding in a conversion).
FLOAT_SLACK = 1.0 / 512.0

_SUPPORTED_INTS = (np.uint8, np.uint16)


def describe(image: NDArray) -> str:
    """``"grey (HxW)"`` or ``"colour (HxWx3)"`` for messages.

    Examples
    --------
    >>> describe(np.zeros((2, 3), np.uint8))
    'grey (2x3)'
    """
    if image.ndim == 2:
        return f"grey ({image.shape[0]}x{image.shape[1]})"
    return "colour (" + "x".join(str(s) for s in image.shape) + ")"


def _what(name: str, source: str | None) -> tuple[str, str]:
    """(prefix, subject) of a message: ``("a.png: ", "real image")``."""
    subject = f"{name} image" if name else "image"
    return (f"{source}: " if source else ""), subject


def check_image(image: object, name: str = "", *, source: str | None = None) -> NDArray:
    """Return ``image`` as an array after checking it is an image MMD can use.

    Parameters
    ----------
    image : object
        The candidate image.
    name : str
        Its role in messages (``"real"``, ``"synthetic"``; empty for none).
    source : str, optional
        The file it was read from; messages then start with it.

    Raises
    ------
    VisionError
        If it is not a 2-D grey or 3-channel colour array of a supported dtype,
        is smaller than ``MIN_SIDE`` pixels on a side, or is a float image
        holding NaN, infinite values or values outside ``[0, 1]``.

    Examples
    --------
    >>> check_image(np.zeros((40, 40, 4), np.uint8), "real")
    Traceback (most recent call last):
    ...
    adapt.errors.VisionError: real image has 4 channels: expected grey (HxW) or BGR colour (HxWx3)
    """
    pre, what = _what(name, source)
    if not isinstance(image, np.ndarray):
        raise VisionError(f"{pre}{what} is a {type(image).__name__}, expected a NumPy array")
    if image.ndim == 3 and image.shape[2] == 1:
        image = image[:, :, 0]
    if image.ndim == 3 and image.shape[2] != 3:
        raise VisionError(
            f"{pre}{what} has {image.shape[2]} channels: expected grey (HxW) or BGR colour (HxWx3)"
        )
    if image.ndim not in (2, 3):
        raise VisionError(f"{pre}{what} has {image.ndim} dimensions: expected (HxW) or (HxWx3)")
    if min(image.shape[:2]) < MIN_SIDE:
        raise VisionError(
            f"{pre}{what} is {image.shape[1]}x{image.shape[0]} pixels: "
            f"expected at least {MIN_SIDE}x{MIN_SIDE} pixels"
        )
    if image.dtype.type in _SUPPORTED_INTS:
        return image
    if np.issubdtype(image.dtype, np.floating):
        lo, hi = float(np.min(image)), float(np.max(image))
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise VisionError(f"{pre}{what} holds NaN or infinite values")
        if lo < -FLOAT_SLACK or hi > 1.0 + FLOAT_SLACK:
            raise VisionError(
                f"{pre}{what} is float with values from {lo:g} to {hi:g}: expected values in "
                "[0, 1] (divide 8-bit values by 255)"
            )
        return image
    raise VisionError(
        f"{pre}{what} has dtype {image.dtype}: expected uint8, uint16 or float in [0, 1]"
    )


def check_pair(
    real: object,
    synthetic: object,
    *,
    sources: tuple[str | None, str | None] = (None, None),
) -> tuple[NDArray, NDArray]:
    """Check ``real`` and ``synthetic`` separately, and that they have the same
    size (dtype and channels may differ: see :func:`conform`).

    Parameters
    ----------
    real, synthetic : object
        The candidate images.
    sources : (str or None, str or None)
        The files they were read from, for messages.

    Raises
    ------
    VisionError
        If either is not a usable image, or their sizes differ (the message
        names both).

    Examples
    --------
    >>> check_pair(np.zeros((40, 40), np.uint8), np.zeros((40, 50), np.uint8))
    Traceback (most recent call last):
    ...
    adapt.errors.VisionError: real image is 40x40 but synthetic image is 50x40 pixels: render the synthetic view at the real camera's size
    """
    r = check_image(real, "real", source=sources[0])
    s = check_image(synthetic, "synthetic", source=sources[1])
    if r.shape[:2] != s.shape[:2]:
        rn = "real image" + (f" {sources[0]}" if sources[0] else "")
        sn = "synthetic image" + (f" {sources[1]}" if sources[1] else "")
        raise VisionError(
            f"{rn} is {r.shape[1]}x{r.shape[0]} but {sn} is "
            f"{s.shape[1]}x{s.shape[0]} pixels: render the synthetic view at the real camera's size"
        )
    return r, s


def conform(real: NDArray, synthetic: NDArray) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
    """The one conversion of a checked pair before comparison: both 8-bit
    (:func:`as_uint8`), and both grey when either is grey (a grey camera
    against a colour rendering is compared in grey: the grey image holds no
    colour to compare).  Images that need no conversion are returned as they
    are (not copied).

    Examples
    --------
    >>> r, s = conform(np.full((2, 2, 3), 65535, np.uint16), np.full((2, 2, 3), 0.5))
    >>> r.dtype.name, int(r.max()), int(s.max())
    ('uint8', 255, 128)
    """
    r8, s8 = as_uint8(real), as_uint8(synthetic)
    if r8.ndim != s8.ndim:
        r8, s8 = to_grey(r8), to_grey(s8)
    return r8, s8


def as_uint8(image: NDArray) -> NDArray[np.uint8]:
    """An 8-bit copy (or the array itself when it already is ``uint8``).

    ``uint16`` is scaled by 1/257; floats are taken as ``[0, 1]`` and clipped.

    Examples
    --------
    >>> as_uint8(np.array([[0.0, 0.5, 1.0]])).tolist()
    [[0, 128, 255]]
    """
    if image.dtype == np.uint8:
        return image
    if image.dtype == np.uint16:
        return ((image.astype(np.uint32) + 128) // 257).astype(np.uint8)
    return np.clip(np.rint(image * 255.0), 0, 255).astype(np.uint8)


def to_grey(image: NDArray) -> NDArray[np.uint8]:
    """The 8-bit grey version of a grey or BGR image (never a view of the input
    when a conversion happens).

    Examples
    --------
    >>> to_grey(np.full((2, 2, 3), 100, np.uint8)).tolist()
    [[100, 100], [100, 100]]
    """
    u8 = as_uint8(image)
    if u8.ndim == 3:
        return cv2.cvtColor(u8, cv2.COLOR_BGR2GRAY)  # type: ignore[return-value]
    return u8


def read_image(path: str | os.PathLike[str]) -> NDArray[np.uint8]:
    """Read an image file as it is stored (grey stays grey, colour is BGR).

    Raises
    ------
    ImageError
        If the file is missing, is a directory, or cannot be decoded.

    Examples
    --------
    >>> read_image("no/such/file.png")
    Traceback (most recent call last):
    ...
    adapt.errors.ImageError: no/such/file.png: no such file
    """
    p = Path(path)
    if not p.exists():
        raise ImageError(f"{path}: no such file")
    if p.is_dir():
        raise ImageError(f"{path}: is a directory, expected an image file")
    try:
        data = np.fromfile(p, dtype=np.uint8)
    except OSError as exc:
        raise ImageError(f"{path}: cannot read ({exc.strerror or exc})") from exc
    with native_messages() as said:  # libpng's own complaint goes into the message
        image = cv2.imdecode(data, cv2.IMREAD_UNCHANGED) if data.size else None
    if image is None:
        raise ImageError(f"{path}: not an image OpenCV can decode (PNG, JPEG, ...)"
                         f"{said.detail()}")
    if image.ndim == 3 and image.shape[2] == 4:
        image = cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
    return image  # type: ignore[return-value]


def encode_image(path: str | os.PathLike[str], image: NDArray) -> bytes:
    """``image`` encoded for a file called ``path`` (its extension; ``.png`` without one),
    as it is: 8-bit, or 16-bit for a format that keeps it (a label image as PNG).

    Raises
    ------
    ImageError
        If OpenCV cannot encode it in that format.

    Examples
    --------
    >>> data = encode_image("labels.png", np.full((2, 3), 3000, np.uint16))
    >>> int(cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED).max())
    3000
    """
    ext = Path(path).suffix.lower() or ".png"
    try:
        ok, buf = cv2.imencode(ext, image)
    except cv2.error:
        ok = False
    if not ok:
        raise ImageError(f"cannot encode an image as {ext!r} for {str(path)!r}")
    return bytes(buf)


def write_image(path: str | os.PathLike[str], image: NDArray) -> Path:
    """Write ``image`` atomically: encode in memory, write a temporary file
    beside the target, then rename it over the target.

    Raises
    ------
    ImageError
        If the extension is not one OpenCV can encode or the directory is not
        writable; no partial file is left behind.
    """
    p = Path(path)
    data = encode_image(p, as_uint8(image))
    try:
        write_atomic(p, data)
    except OSError as exc:
        raise ImageError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return p
