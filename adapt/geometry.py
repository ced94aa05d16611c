"""Coordinate conventions, the pinhole camera and rotation helpers.

The conventions (also in ``docs/conventions.md``):

* **World**: metres, right-handed, the floor is the plane ``z = 0``, ``z`` up.
  The physics is 2D in ``(x, y)`` on the floor.
* **Camera frame**: OpenCV's: ``x`` right, ``y`` down, ``z`` forward (the
  viewing direction).
* **Pose**: ``R`` is the world-to-camera rotation and ``C`` the camera centre in
  world coordinates, so a world point ``X`` has camera coordinates
  ``R (X - C)`` and projects to the pixel ``p ~ K R (X - C)``.
* **Pixels**: ``(x, y)`` with ``x`` to the right and ``y`` down, the centre of
  the top-left pixel at ``(0, 0)``; NumPy images are indexed ``[row, col]`` =
  ``[y, x]``.

This module imports only NumPy.

Examples
--------
>>> import numpy as np
>>> cam = Camera.look_at(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
...                      position=(0.0, -2.0, 1.0), look_at=(0.0, 0.0, 1.0))
>>> cam.project(np.array([[0.0, 0.0, 1.0]])).round(6).tolist()
[[320.0, 240.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import ImaginationError

__all__ = [
    "Camera",
    "look_at_rotation",
    "rotation_exp",
    "rotation_log",
    "nearest_rotation",
    "WORLD_UP",
    "MAX_IMAGE_SIDE",
    "MIN_IMAGE_SIDE",
    "MAX_PIXELS",
    "MAX_FOCAL",
    "MAX_COORDINATE",
    "point_segment_distance",
    "segment_distance",
]

#: World up direction.
WORLD_UP = np.array([0.0, 0.0, 1.0])

FloatArray = NDArray[np.float64]

#: Largest image side a :class:`Camera` accepts, pixels.
MAX_IMAGE_SIDE = 8192
#: Smallest image side vision works on (a scenario's camera has at least this), pixels.
MIN_IMAGE_SIDE = 32
#: Largest image a :class:`Camera` accepts, pixels (4096 x 4096; a 4K UHD frame fits).
MAX_PIXELS = 4096 * 4096
#: Largest focal length and principal-point offset a :class:`Camera` accepts, pixels.
MAX_FOCAL = 1.0e6
#: Largest world coordinate (any axis) the imagination accepts, metres.
MAX_COORDINATE = 1.0e4


def _number(name: str, value: object) -> float:
    """``value`` as a finite float, or an :class:`ImaginationError` naming ``name``."""
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ImaginationError(f"{name}: expected a number, got {value!r}") from None
    if not np.isfinite(v):
        raise ImaginationError(f"{name}: expected a finite number, got {value!r}")
    return v


def _vector3(name: str, value: ArrayLike) -> FloatArray:
    try:
        v = np.array(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise ImaginationError(f"{name}: expected [x, y, z], got {value!r}") from None
    if not np.all(np.isfinite(v)) or np.abs(v).max() > MAX_COORDINATE:
        raise ImaginationError(
            f"{name}: expected coordinates within +-{MAX_COORDINATE:g} metres, got {v.tolist()}"
        )
    return v


def point_segment_distance(p: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    """The distance from point ``p`` to the segment from ``a`` to ``b`` (2D; ``a`` when the
    segment is a point).

    Examples
    --------
    >>> point_segment_distance((0.0, 1.0), (-1.0, 0.0), (1.0, 0.0))
    1.0
    >>> point_segment_distance((3.0, 4.0), (0.0, 0.0), (-1.0, 0.0))
    5.0
    """
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy)
                                               / length2))
    return math.hypot(p[0] - (a[0] + t * dx), p[1] - (a[1] + t * dy))


def _side(o: Sequence[float], u: Sequence[float], v: Sequence[float]) -> float:
    """Which side of the line ``o-u`` point ``v`` is on (the cross product's sign)."""
    return (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])


def segment_distance(p: Sequence[float], q: Sequence[float], a: Sequence[float],
                     b: Sequence[float]) -> float:
    """The shortest distance between the segments ``p-q`` and ``a-b`` (2D; 0 when they
    cross).

    Examples
    --------
    >>> segment_distance((0.0, -1.0), (0.0, 1.0), (-1.0, 0.0), (1.0, 0.0))
    0.0
    >>> segment_distance((0.0, 1.0), (0.0, 2.0), (-1.0, 0.0), (1.0, 0.0))
    1.0
    """
    if _side(a, b, p) * _side(a, b, q) < 0 and _side(p, q, a) * _side(p, q, b) < 0:
        return 0.0
    return min(point_segment_distance(p, a, b), point_segment_distance(q, a, b),
               point_segment_distance(a, p, q), point_segment_distance(b, p, q))


def look_at_rotation(
    position: ArrayLike, target: ArrayLike, roll_deg: float = 0.0
) -> FloatArray:
    """World-to-camera rotation for a camera at ``position`` looking at ``target``.

    World up is ``+z``; the camera's ``y`` axis points as far down as it can.
    ``roll_deg`` turns the camera about its viewing axis: a positive roll turns
    the camera's ``x`` axis towards its ``y`` axis, so the scene appears rotated
    counter-clockwise in the image.

    Raises
    ------
    ImaginationError
        If the target equals the position, or the camera looks straight up or
        straight down (the image's up direction is then undefined).

    Examples
    --------
    >>> look_at_rotation((0, 0, 1), (0, 1, 1)).round(6).tolist()
    [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]
    """
    c = _vector3("position", position)
    t = _vector3("look_at", target)
    roll_deg = _number("roll_deg", roll_deg)
    forward = t - c
    norm = float(np.linalg.norm(forward))
    if not np.isfinite(norm) or norm < 1e-12:
        raise ImaginationError(
            f"look_at: {t.tolist()} equals its position {c.tolist()}: "
            "expected a look_at point away from the camera"
        )
    z = forward / norm
    if abs(float(z @ WORLD_UP)) > 1.0 - 1e-9:
        raise ImaginationError(
            "look_at: the camera looks straight "
            + ("up" if z[2] > 0 else "down")
            + ": expected a viewing direction that is not parallel to world up (+z)"
        )
    x = np.cross(z, WORLD_UP)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    r0 = np.stack([x, y, z])
    a = np.deg2rad(roll_deg)
    ca, sa = np.cos(a), np.sin(a)
    roll = np.array([[ca, sa, 0.0], [-sa, ca, 0.0], [0.0, 0.0, 1.0]])
    return roll @ r0


def rotation_exp(rotvec: ArrayLike) -> FloatArray:
    """Rotation matrix of an axis-angle vector (Rodrigues' formula).

    Examples
    --------
    >>> rotation_exp([0, 0, np.pi / 2]).round(6).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    w = np.asarray(rotvec, dtype=float).reshape(3)
    theta = float(np.linalg.norm(w))
    if theta < 1e-15:
        return np.eye(3)
    k = w / theta
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(theta) * kx + (1.0 - np.cos(theta)) * (kx @ kx)


def rotation_log(rotation: ArrayLike) -> FloatArray:
    """Axis-angle vector of a rotation matrix (inverse of :func:`rotation_exp`).

    Examples
    --------
    >>> v = np.array([0.1, -0.2, 0.3])
    >>> bool(np.allclose(rotation_log(rotation_exp(v)), v))
    True
    """
    r = np.asarray(rotation, dtype=float).reshape(3, 3)
    cos = np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)
    theta = float(np.arccos(cos))
    if theta < 1e-12:
        return np.zeros(3)
    if np.pi - theta < 1e-6:
        # Near pi: the axis is the eigenvector of R with eigenvalue 1.
        vals, vecs = np.linalg.eigh((r + r.T) / 2.0)
        axis = vecs[:, int(np.argmax(vals))]
        return axis * theta
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return w * (theta / (2.0 * np.sin(theta)))


def nearest_rotation(matrix: ArrayLike) -> FloatArray:
    """The rotation nearest to ``matrix`` in the Frobenius norm (SVD projection).

    The determinant is normalised first (``A / cbrt(det A)``) so that a
    homography-derived matrix with an arbitrary scale maps to its rotation.

    Examples
    --------
    >>> r = rotation_exp([0.0, 0.1, 0.0])
    >>> bool(np.allclose(nearest_rotation(3.0 * r), r))
    True
    """
    a = np.asarray(matrix, dtype=float).reshape(3, 3)
    det = float(np.linalg.det(a))
    if not np.isfinite(det) or abs(det) < 1e-300:
        raise ValueError("matrix is singular: it has no nearest rotation")
    a = a / np.cbrt(det)
    u, _, vt = np.linalg.svd(a)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return r


@dataclass(frozen=True, eq=False)
class Camera:
    """A pinhole camera without distortion.

    Parameters
    ----------
    fx, fy, cx, cy : float
        Intrinsics in pixels.
    width, height : int
        Image size in pixels.
    rotation : (3, 3) ndarray
        World-to-camera rotation ``R``.
    position : (3,) ndarray
        Camera centre ``C`` in world coordinates (metres).

    The camera keeps read-only copies of ``rotation`` and ``position``, so
    changing the arrays it was given later does not move it.  Limits (errors
    name the field): ``fx``, ``fy`` in ``(0, MAX_FOCAL]``; ``width`` and
    ``height`` whole numbers up to :data:`MAX_IMAGE_SIDE` with at most
    :data:`MAX_PIXELS` pixels; coordinates within :data:`MAX_COORDINATE`
    metres.

    Examples
    --------
    >>> r = np.eye(3)
    >>> cam = Camera(500, 500, 320, 240, 640, 480, r, np.zeros(3))
    >>> r[0, 0] = 5.0
    >>> float(cam.rotation[0, 0]), cam.rotation.flags.writeable
    (1.0, False)
    >>> Camera(500, 500, 320, 240, 33000, 480, np.eye(3), np.zeros(3))
    Traceback (most recent call last):
    ...
    adapt.errors.ImaginationError: width: expected 1 to 8192 pixels, got 33000
    """

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int
    rotation: FloatArray = field(repr=False)
    position: FloatArray

    def __post_init__(self) -> None:
        for name in ("fx", "fy"):
            v = _number(name, getattr(self, name))
            if not 0 < v <= MAX_FOCAL:
                raise ImaginationError(
                    f"{name}: expected a positive number of pixels up to {MAX_FOCAL:g}, got {v!r}"
                )
            object.__setattr__(self, name, v)
        for name in ("cx", "cy"):
            v = _number(name, getattr(self, name))
            if abs(v) > MAX_FOCAL:
                raise ImaginationError(
                    f"{name}: expected a number of pixels within +-{MAX_FOCAL:g}, got {v!r}"
                )
            object.__setattr__(self, name, v)
        for name in ("width", "height"):
            v = getattr(self, name)
            if (isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating))
                    or not float(v).is_integer()):
                raise ImaginationError(f"{name}: expected a whole number of pixels, got {v!r}")
            if not 0 < int(v) <= MAX_IMAGE_SIDE:
                raise ImaginationError(
                    f"{name}: expected 1 to {MAX_IMAGE_SIDE} pixels, got {v!r}"
                )
            object.__setattr__(self, name, int(v))
        if self.width * self.height > MAX_PIXELS:
            raise ImaginationError(
                f"width: {self.width}x{self.height} is {self.width * self.height:,} pixels; "
                f"expected at most {MAX_PIXELS:,} (for example 4096x4096)"
            )
        try:
            r = np.array(self.rotation, dtype=float).reshape(3, 3)
        except (TypeError, ValueError):
            raise ImaginationError(
                f"rotation: expected a 3x3 rotation matrix, got {self.rotation!r}"
            ) from None
        if (not np.all(np.isfinite(r)) or not np.allclose(r @ r.T, np.eye(3), atol=1e-6)
                or np.linalg.det(r) < 0):
            raise ImaginationError(
                "rotation: expected a proper rotation matrix (orthonormal, determinant +1)"
            )
        try:
            c = np.array(self.position, dtype=float).reshape(3)
        except (TypeError, ValueError):
            raise ImaginationError(f"position: expected [x, y, z], got {self.position!r}") from None
        if not np.all(np.isfinite(c)) or np.abs(c).max() > MAX_COORDINATE:
            raise ImaginationError(
                f"position: expected coordinates within +-{MAX_COORDINATE:g} metres, "
                f"got {c.tolist()}"
            )
        r.setflags(write=False)
        c.setflags(write=False)
        object.__setattr__(self, "rotation", r)
        object.__setattr__(self, "position", c)

    @classmethod
    def look_at(
        cls,
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        width: int,
        height: int,
        position: Sequence[float] | ArrayLike,
        look_at: Sequence[float] | ArrayLike,
        roll_deg: float = 0.0,
    ) -> "Camera":
        """A camera at ``position`` looking at ``look_at`` (world up ``+z``)."""
        r = look_at_rotation(position, look_at, roll_deg)
        return cls(fx, fy, cx, cy, width, height, r, np.asarray(position, dtype=float))

    @property
    def K(self) -> FloatArray:  # noqa: N802 - the conventional name
        """The 3x3 intrinsic matrix."""
        return np.array(
            [[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]]
        )

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` as OpenCV wants it."""
        return (self.width, self.height)

    @property
    def projection(self) -> FloatArray:
        """The 3x4 projection matrix ``K [R | -R C]``."""
        return self.K @ np.hstack([self.rotation, (-self.rotation @ self.position)[:, None]])

    def with_rotation(self, rotation: ArrayLike) -> "Camera":
        """The same camera turned to a new world-to-camera rotation."""
        return replace(self, rotation=np.asarray(rotation, dtype=float))

    def with_pose(self, rotation: ArrayLike, position: ArrayLike) -> "Camera":
        """The same intrinsics at a new pose."""
        return replace(
            self,
            rotation=np.asarray(rotation, dtype=float),
            position=np.asarray(position, dtype=float),
        )

    def angle_to(self, other: "Camera") -> float:
        """The angle, in degrees, of the rotation between this camera's orientation and
        ``other``'s (the norm of ``log(R_other R^T)``).

        Examples
        --------
        >>> a = Camera(500, 500, 320, 240, 640, 480, np.eye(3), np.zeros(3))
        >>> round(a.angle_to(a.with_rotation(rotation_exp([0.0, 0.0, np.radians(2.0)]))), 9)
        2.0
        """
        return float(np.degrees(np.linalg.norm(rotation_log(other.rotation @ self.rotation.T))))

    def to_camera(self, points: ArrayLike) -> FloatArray:
        """World points ``(N, 3)`` in camera coordinates ``R (X - C)``."""
        x = np.asarray(points, dtype=float).reshape(-1, 3)
        return (x - self.position) @ self.rotation.T

    def project(self, points: ArrayLike) -> FloatArray:
        """Pixels ``(N, 2)`` of world points ``(N, 3)``; points behind the camera
        give ``nan``."""
        pc = self.to_camera(points)
        z = pc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = self.fx * pc[:, 0] / z + self.cx
            v = self.fy * pc[:, 1] / z + self.cy
        out = np.stack([u, v], axis=1)
        out[z <= 1e-9] = np.nan
        return out

    def pixel_ray(self, pixels: ArrayLike) -> FloatArray:
        """Unit viewing directions ``(N, 3)`` in world coordinates of pixels ``(N, 2)``."""
        p = np.asarray(pixels, dtype=float).reshape(-1, 2)
        d = np.stack(
            [(p[:, 0] - self.cx) / self.fx, (p[:, 1] - self.cy) / self.fy, np.ones(len(p))],
            axis=1,
        )
        w = d @ self.rotation  # R^T d for each row
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    def pixel_to_plane(self, pixels: ArrayLike, z: float = 0.0) -> FloatArray:
        """World points ``(N, 3)`` where the rays of ``pixels`` meet the plane at
        height ``z`` (the floor by default); ``nan`` where the ray never does."""
        rays = self.pixel_ray(pixels)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (z - self.position[2]) / rays[:, 2]
        pts = self.position + rays * t[:, None]
        pts[~(t > 0)] = np.nan
        return pts


def look_at_parameters(
    rotation: ArrayLike, position: ArrayLike, distance: float = 1.0
) -> tuple[FloatArray, float]:
    """The ``look_at`` point and ``roll_deg`` of a camera pose: the inverse of
    :func:`look_at_rotation`.

    ``look_at`` is the point ``distance`` metres along the viewing axis
    (the third row of ``rotation``); ``roll_deg`` turns
    ``look_at_rotation(position, look_at)`` into ``rotation``, so
    ``look_at_rotation(position, *look_at_parameters(R, position))`` is ``R``.
    These are the scenario's ``camera`` keys.

    Raises
    ------
    ImaginationError
        If ``rotation`` is not a rotation matrix, ``distance`` is not positive,
        or the camera looks straight up or down (no roll is defined).

    Examples
    --------
    >>> r = look_at_rotation((0.0, -0.6, 0.6), (0.5, 3.0, 0.3), roll_deg=2.5)
    >>> target, roll = look_at_parameters(r, (0.0, -0.6, 0.6), distance=3.0)
    >>> round(roll, 6), bool(np.allclose(look_at_rotation((0.0, -0.6, 0.6), target, roll), r))
    (2.5, True)
    """
    r = np.asarray(rotation, dtype=float).reshape(3, 3)
    if not np.isfinite(r).all() or not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or np.linalg.det(r) < 0:
        raise ImaginationError("expected a proper rotation matrix (orthonormal, determinant +1)")
    if not (np.isfinite(distance) and distance > 0):
        raise ImaginationError(f"the look_at distance must be a positive number, got {distance}")
    c = np.asarray(position, dtype=float).reshape(3)
    target = c + float(distance) * r[2]
    r0 = look_at_rotation(c, target, 0.0)
    m = r @ r0.T  # the roll about the viewing axis: [[cos, sin, 0], [-sin, cos, 0], [0, 0, 1]]
    roll = float(np.degrees(np.arctan2(m[0, 1], m[0, 0])))
    return target, roll
