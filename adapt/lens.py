"""A camera's lens: pinhole intrinsics with OpenCV's distortion model, and undistortion.

A :class:`Lens` holds what a calibration says about a camera: the camera
matrix ``K`` of the raw (distorted) image, the distortion coefficients in
OpenCV's order ``(k1, k2, p1, p2[, k3[, k4, k5, k6]])`` (ROS calls the
5-coefficient model ``plumb_bob`` and the 8-coefficient one
``rational_polynomial``), the rectification ``R`` (the identity for a
single camera) and the camera matrix ``P`` of the undistorted image -- the
one adapt's pinhole camera uses (``K`` itself unless a ROS file gives a
``projection_matrix``).

:class:`Undistorter` computes OpenCV's remap tables once
(``cv2.initUndistortRectifyMap``) and undistorts each frame with
``cv2.remap``; pixels that fall outside the raw image repeat its border, so
they add no hard edge to the Match-Mediated Difference.
:class:`Distorter` is the inverse map (an ideal image seen through the lens),
what a synthetic reality applies to look like a real camera.
:func:`undistorted` wraps any :class:`~adapt.frames.FrameSource` so that
the runner's perception sees undistorted frames, :func:`distorted` so that a
synthetic reality's frames look as through the lens (:class:`LensSource`
forwards everything else: the real robot, ground truth, the source's status).

Examples
--------
>>> import cv2, numpy as np
>>> lens = Lens.pinhole(200.0, 200.0, 79.5, 59.5, (160, 120), (-0.25, 0.05, 0.0, 0.0, 0.0))
>>> lens.distorted, lens.size
(True, (160, 120))
>>> y, x = np.mgrid[0:120, 0:160]
>>> board = ((x // 16 + y // 16) % 2 * 200 + 20).astype(np.uint8)
>>> ideal = cv2.GaussianBlur(cv2.merge([board] * 3), (0, 0), 2)
>>> raw = Distorter(lens)(ideal)                 # as the lens shows it
>>> back = Undistorter(lens)(raw)                # and undistorted again
>>> def error(a): return round(float(np.abs(a.astype(int) - ideal).mean()))
>>> error(raw), error(back)                      # mean grey levels off
(13, 1)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterator

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import ImageError
from adapt.frames import Frame, FrameSource

__all__ = ["Lens", "Undistorter", "Distorter", "LensSource", "DISTORTION_LENGTHS",
           "undistorted", "distorted"]

#: How many distortion coefficients OpenCV's model takes (``k1 k2 p1 p2``, ``+ k3``, ``+ k4 k5 k6``).
DISTORTION_LENGTHS = (4, 5, 8)


def _matrix(values: Any, shape: tuple[int, int]) -> NDArray[np.float64]:
    m = np.array(values, dtype=np.float64).reshape(shape)
    m.setflags(write=False)
    return m


@dataclass(frozen=True, slots=True, eq=False)
class Lens:
    """Intrinsics and distortion of a camera (see the module docstring).

    Attributes
    ----------
    matrix : (3, 3) ndarray
        ``K``, the camera matrix of the raw image.
    distortion : tuple of float
        4, 5 or 8 coefficients in OpenCV's order.
    size : (int, int)
        ``(width, height)`` of the images, pixels.
    rectification : (3, 3) ndarray
        ``R``; the identity for a single camera.
    projection : (3, 3) ndarray
        ``P``, the camera matrix of the undistorted image (adapt's pinhole camera).
    file : str or None
        The calibration file it was read from.
    """

    matrix: NDArray[np.float64]
    distortion: tuple[float, ...]
    size: tuple[int, int]
    rectification: NDArray[np.float64] = field(default_factory=lambda: _matrix(np.eye(3), (3, 3)))
    projection: NDArray[np.float64] | None = None
    file: str | None = None

    def __post_init__(self) -> None:
        if len(self.distortion) not in DISTORTION_LENGTHS:
            raise ImageError(f"expected 4, 5 or 8 distortion coefficients, got "
                             f"{len(self.distortion)}")
        object.__setattr__(self, "matrix", _matrix(self.matrix, (3, 3)))
        object.__setattr__(self, "rectification", _matrix(self.rectification, (3, 3)))
        p = self.matrix if self.projection is None else self.projection
        object.__setattr__(self, "projection", _matrix(p, (3, 3)))

    @classmethod
    def pinhole(cls, fx: float, fy: float, cx: float, cy: float, size: tuple[int, int],
                distortion: tuple[float, ...]) -> "Lens":
        """A lens whose undistorted image keeps the raw image's camera matrix."""
        k = [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
        return cls(_matrix(k, (3, 3)), tuple(float(d) for d in distortion), (int(size[0]), int(size[1])))

    @property
    def distorted(self) -> bool:
        """True unless every coefficient is 0 and ``P`` is ``K`` with ``R`` the identity
        (undistortion would then change nothing)."""
        assert self.projection is not None
        return (any(d != 0.0 for d in self.distortion)
                or not np.array_equal(self.projection, self.matrix)
                or not np.array_equal(self.rectification, np.eye(3)))

    @property
    def intrinsics(self) -> tuple[float, float, float, float]:
        """``(fx, fy, cx, cy)`` of the undistorted image (from ``P``)."""
        p = self.projection
        assert p is not None
        return float(p[0, 0]), float(p[1, 1]), float(p[0, 2]), float(p[1, 2])

    def as_json(self) -> dict[str, Any]:
        """The lens as JSON values (for a run's report)."""
        assert self.projection is not None
        return {"camera_matrix": self.matrix.tolist(), "distortion": list(self.distortion),
                "projection": self.projection.tolist(), "size": list(self.size)}


class _LensMap:
    """A pixel map of one lens, made once: one ``cv2.remap`` per image of the lens's size."""

    #: What the map does, for the message about an image of the wrong size.
    _doing = ""

    def __init__(self, lens: Lens, maps: tuple[Any, Any]) -> None:
        self.lens = lens
        self._maps = maps

    def __call__(self, image: NDArray[np.uint8]) -> NDArray[np.uint8]:
        """The image through the map (a new array)."""
        w, h = self.lens.size
        if image.ndim < 2 or (image.shape[1], image.shape[0]) != (w, h):
            raise ImageError(f"{self._doing} expects an image of {w}x{h} pixels, got "
                             f"{image.shape[1] if image.ndim > 1 else '?'}x{image.shape[0]}")
        out = cv2.remap(image, self._maps[0], self._maps[1], cv2.INTER_LINEAR,
                        borderMode=cv2.BORDER_REPLICATE)
        return np.asarray(out, np.uint8)


class Undistorter(_LensMap):
    """Undistorts images of one lens: maps made once, one ``cv2.remap`` per image."""

    _doing = "undistortion"

    def __init__(self, lens: Lens) -> None:
        k = np.asarray(lens.matrix)
        d = np.asarray(lens.distortion, np.float64)
        super().__init__(lens, cv2.initUndistortRectifyMap(
            k, d, np.asarray(lens.rectification), np.asarray(lens.projection), lens.size,
            cv2.CV_16SC2))


class Distorter(_LensMap):
    """Shows an ideal (undistorted) image through a lens: the inverse of :class:`Undistorter`.

    Each raw pixel's ideal position is found with ``cv2.undistortPoints`` (iterated to convergence) (once).
    """

    _doing = "distortion"

    def __init__(self, lens: Lens) -> None:
        w, h = lens.size
        u, v = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
        pts = np.stack([u.ravel(), v.ravel()], axis=1).reshape(-1, 1, 2)
        criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 40, 1e-6)
        ideal = cv2.undistortPoints(pts, np.asarray(lens.matrix),
                                    np.asarray(lens.distortion, np.float64),
                                    R=np.asarray(lens.rectification),
                                    P=np.asarray(lens.projection), criteria=criteria)
        ideal = ideal.reshape(h, w, 2)
        super().__init__(lens, cv2.convertMaps(  # fixed point: as fast as the undistorter's
            np.ascontiguousarray(ideal[..., 0], np.float32),
            np.ascontiguousarray(ideal[..., 1], np.float32), cv2.CV_16SC2))


class LensSource:
    """A frame source whose images go through a lens map (everything else forwarded):
    :func:`undistorted` for perception, :func:`distorted` for a synthetic camera.

    Examples
    --------
    >>> import numpy as np
    >>> from adapt.frames import Frame
    >>> class Two:
    ...     size, fps = (32, 24), 10.0
    ...     def __iter__(self):
    ...         return iter([Frame(i, i / 10, np.full((24, 32, 3), 9, np.uint8)) for i in range(2)])
    ...     def close(self): pass
    >>> s = undistorted(Two(), Lens.pinhole(30, 30, 15.5, 11.5, (32, 24), (0.1, 0, 0, 0)))
    >>> [(f.index, f.time, int(f.image[5, 5, 0]), f.image.flags.writeable) for f in s], s.fps
    ([(0, 0.0, 9, False), (1, 0.1, 9, False)], 10.0)
    """

    def __init__(self, source: FrameSource, lens: Lens, mapping: Undistorter | Distorter) -> None:
        self._source = source
        self._map = mapping
        self.lens = lens

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` of every frame."""
        return self._source.size

    @property
    def fps(self) -> float:
        """Frames per second."""
        return self._source.fps

    def __iter__(self) -> Iterator[Frame]:
        for frame in self._source:
            image = self._map(frame.image)
            image.setflags(write=False)
            yield Frame(frame.index, frame.time, image)

    def close(self) -> None:
        """Close the source."""
        self._source.close()

    def __getattr__(self, name: str) -> Any:
        # robot, truth, length, status, stalled, ...: the source's own
        if name.startswith("__") or name in ("_source", "_map", "lens"):
            raise AttributeError(name)
        return getattr(self._source, name)


def undistorted(source: FrameSource, lens: Lens | None) -> FrameSource:
    """``source``'s frames undistorted through ``lens`` (``source`` itself when there is
    nothing to undistort)."""
    if lens is None or not lens.distorted:
        return source
    return LensSource(source, lens, Undistorter(lens))


def distorted(source: FrameSource, lens: Lens | None) -> FrameSource:
    """``source``'s ideal frames as ``lens`` shows them (``source`` itself when it changes
    nothing)."""
    if lens is None or not lens.distorted:
        return source
    return LensSource(source, lens, Distorter(lens))
