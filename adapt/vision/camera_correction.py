"""Correcting the synthetic camera from ``H_e`` (the paper's eq. 2 and 3).

Conventions (``adapt.geometry``): ``R`` maps world to camera coordinates, and
``H_e`` maps *synthetic* pixels to *real* pixels.

**Rotation (eq. 3).**  For cameras at the same centre, a direction ``d`` is
seen at ``p_s ~ K_s R_s d`` and ``p_r ~ K_r R_r d``, so
``H_e ~ K_r R_r R_s^T K_s^-1`` and

.. math:: R_e = \\operatorname{nearest\\_rotation}(K_r^{-1} H_e K_s) = R_r R_s^T,
          \\qquad R_r = R_e R_s .

The paper's ``R_s <- (g K_r^-1 H_e K_s) R_s`` is read as a *fractional
rotation*: ``R_s <- exp(g log R_e) R_s`` with ``0 < g <= 1`` (``g = 1`` jumps
to the estimate; ``g < 1`` low-passes estimation noise).

**Full pose (beyond the paper).**  For points on a world plane
``n_w . X = c`` (the floor: ``n_w = (0, 0, 1)``, ``c = 0``) seen from
different centres, ``K_r^-1 H_e K_s ~ R + t n^T / d`` where ``R = R_r R_s^T``,
``t = R_r (C_s - C_r)``, ``n = -R_s n_w`` is the plane normal in the synthetic
camera (pointing away from the camera) and ``d = n_w . C_s - c`` its height
above the plane.  With ``n`` and ``d`` known the solution is unique
(:func:`estimate_pose`): ``G = K_r^-1 H_e K_s`` scaled to a middle singular
value of 1, signed so the plane points are in front of both cameras, equals
``R`` on the plane's directions, and ``t = d (G n - R n)``.  If ``G`` is not a
rotation on those directions the matches are not on that plane.  Then
``R_r = R R_s`` and ``C_r = C_s - R_r^T t``.

Examples
--------
>>> import numpy as np
>>> from adapt.geometry import Camera, rotation_exp, rotation_log
>>> syn = Camera(500, 500, 320, 240, 640, 480, np.eye(3), np.zeros(3))
>>> r_real = rotation_exp([0.0, 0.02, 0.01])
>>> h = syn.K @ r_real @ syn.rotation.T @ np.linalg.inv(syn.K)   # synthetic -> real
>>> fixed = correct_rotation(syn, h, gain=1.0)
>>> bool(np.allclose(fixed.rotation, r_real))
True
>>> half = correct_rotation(syn, h, gain=0.5)
>>> round(float(np.linalg.norm(rotation_log(half.rotation))), 4)
0.0112
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import VisionError
from adapt.geometry import Camera, nearest_rotation, rotation_exp, rotation_log

__all__ = [
    "rotation_error",
    "correct_rotation",
    "PoseCorrection",
    "estimate_pose",
    "correct_pose",
    "MAX_PLANE_DISTORTION",
]

#: Largest deviation from 1 of the singular values of the normalised
#: homography restricted to the plane's directions (a rotation for the
#: known plane) before the matches are declared not on that plane.
MAX_PLANE_DISTORTION = 0.02

FloatArray = NDArray[np.float64]


def _k(camera: Camera, intrinsics: ArrayLike | None) -> FloatArray:
    return camera.K if intrinsics is None else np.asarray(intrinsics, float).reshape(3, 3)


def rotation_error(
    homography: ArrayLike, real_intrinsics: ArrayLike, synthetic_intrinsics: ArrayLike
) -> FloatArray:
    """``R_e``, the rotation nearest to ``K_r^-1 H_e K_s`` (``= R_r R_s^T`` for
    a purely rotated camera).

    Raises
    ------
    VisionError
        If the homography is singular or not finite.
    """
    h = np.asarray(homography, float).reshape(3, 3)
    if not np.isfinite(h).all():
        raise VisionError("the homography holds NaN or infinite values")
    a = np.linalg.inv(np.asarray(real_intrinsics, float)) @ h @ np.asarray(synthetic_intrinsics, float)
    try:
        return nearest_rotation(a)
    except ValueError as exc:
        raise VisionError(f"cannot correct the camera: {exc}") from exc


def correct_rotation(
    synthetic: Camera,
    homography: ArrayLike,
    *,
    gain: float = 0.5,
    real_intrinsics: ArrayLike | None = None,
) -> Camera:
    """The synthetic camera turned by the fraction ``gain`` of ``R_e``:
    ``R_s <- exp(gain * log R_e) R_s`` (paper eq. 3).

    Parameters
    ----------
    synthetic : Camera
        The camera that rendered the synthetic image.
    homography : (3, 3) array_like
        ``H_e``, synthetic pixels -> real pixels.
    gain : float
        ``g`` in (0, 1].
    real_intrinsics : (3, 3) array_like, optional
        ``K_r``; the synthetic camera's ``K`` by default.
    """
    if not 0.0 < gain <= 1.0:
        raise ValueError(f"gain must be in (0, 1], got {gain}")
    r_e = rotation_error(homography, _k(synthetic, real_intrinsics), synthetic.K)
    step = rotation_exp(gain * rotation_log(r_e))
    return synthetic.with_rotation(nearest_rotation(step @ synthetic.rotation))


@dataclass(frozen=True, slots=True, eq=False)
class PoseCorrection:
    """A full pose estimate of the real camera from a plane's homography.

    Attributes
    ----------
    rotation : (3, 3) ndarray
        ``R = R_r R_s^T``.
    translation : (3,) ndarray
        ``t = R_r (C_s - C_r)`` in world units.
    normal : (3,) ndarray
        The known plane normal in the synthetic camera frame (pointing away
        from the camera) that the solution uses.
    real : Camera
        The real camera implied (the real intrinsics at ``R_r``, ``C_r``).
    in_front : int
        Points that lie in front of both cameras (cheirality); every point
        on the plane's visible side does for a consistent solution.
    distortion : float
        How far the homography restricted to the plane's directions is from
        a rotation (largest ``|sigma - 1|`` of its two singular values); 0
        for an exact homography of the known plane.
    """

    rotation: FloatArray
    translation: FloatArray
    normal: FloatArray
    real: Camera
    in_front: int
    distortion: float


def estimate_pose(
    synthetic: Camera,
    homography: ArrayLike,
    synthetic_points: ArrayLike,
    *,
    plane_normal: ArrayLike = (0.0, 0.0, 1.0),
    plane_offset: float = 0.0,
    real_intrinsics: ArrayLike | None = None,
    max_distortion: float = MAX_PLANE_DISTORTION,
) -> PoseCorrection:
    """The real camera's pose from the homography a known world plane induces.

    ``G = K_r^-1 H_e K_s`` is scaled so its middle singular value is 1 (true
    of every plane homography ``R + t n^T / d``) and its sign is chosen so the
    plane points are in front of both cameras.  With the normal ``n`` and the
    height ``d`` known, ``G a = R a`` for every ``a`` orthogonal to ``n``:
    ``R`` is the rotation nearest to ``G (I - n n^T) + (G a x G b) n^T`` (``a``,
    ``b``, ``n`` right-handed and orthonormal) and ``t = d (G n - R n)``.
    Unlike a general decomposition (four candidates whose normals become
    arbitrary as the translation goes to 0), this is unique and well
    conditioned for small translations, which is where a camera loop ends.

    Parameters
    ----------
    synthetic : Camera
        The synthetic camera (its pose is the reference).
    homography : (3, 3) array_like
        ``H_e`` (synthetic -> real pixels) fitted to matches on the plane.
    synthetic_points : (N, 2) array_like
        Synthetic pixels of (inlier) matches on the plane, for the
        cheirality check.
    plane_normal, plane_offset
        The world plane ``plane_normal . X = plane_offset`` (the floor by default).
    real_intrinsics : (3, 3) array_like, optional
        ``K_r``; the synthetic camera's ``K`` by default.
    max_distortion : float
        Largest :attr:`PoseCorrection.distortion` accepted.

    Raises
    ------
    VisionError
        If the camera is on the plane, most points are not in front of both
        cameras, or the homography is not one of the known plane (the matches
        are on another surface).

    Examples
    --------
    >>> import numpy as np
    >>> from adapt.geometry import Camera, rotation_exp
    >>> syn = Camera.look_at(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
    ...                      position=(0, -1, 1), look_at=(0, 1, 0))
    >>> real = syn.with_pose(rotation_exp([0.01, -0.02, 0.0]) @ syn.rotation,
    ...                      syn.position + [0.05, 0.02, -0.03])
    >>> h = real.projection[:, [0, 1, 3]] @ np.linalg.inv(syn.projection[:, [0, 1, 3]])
    >>> pts = syn.project([[x, y, 0.0] for x in (-0.5, 0.5) for y in (0.5, 1.5)])
    >>> est = estimate_pose(syn, h, pts)
    >>> bool(np.allclose(est.real.position, real.position)), est.in_front
    (True, 4)
    """
    k_r = _k(synthetic, real_intrinsics)
    h = np.asarray(homography, float).reshape(3, 3)
    if not np.isfinite(h).all():
        raise VisionError("the homography holds NaN or infinite values")
    n_w = np.asarray(plane_normal, float).reshape(3)
    n_w = n_w / np.linalg.norm(n_w)
    d = float(n_w @ synthetic.position - plane_offset)
    if abs(d) < 1e-9:
        raise VisionError("the synthetic camera lies in the plane: the plane homography has no pose")
    n_s = -np.sign(d) * (synthetic.rotation @ n_w)  # from the camera towards the plane
    d = abs(d)
    g = np.linalg.inv(k_r) @ h @ synthetic.K
    sv = np.linalg.svd(g, compute_uv=False)
    if not sv[2] > 1e-12 * sv[0]:
        raise VisionError("the homography is singular: no pose")
    g = g / sv[1]
    # cheirality: rays to the plane (n . m > 0) must stay in front of the real camera
    pts = np.asarray(synthetic_points, float).reshape(-1, 2)
    rays = np.c_[pts, np.ones(len(pts))] @ np.linalg.inv(synthetic.K).T
    on_plane = rays @ n_s > 0
    ahead = (rays @ g.T)[:, 2]
    if (on_plane & (ahead < 0)).sum() > (on_plane & (ahead > 0)).sum():
        g = -g
        ahead = -ahead
    in_front = int((on_plane & (ahead > 0)).sum())
    if in_front * 2 <= len(pts):
        raise VisionError(
            f"only {in_front} of {len(pts)} points are in front of both cameras on the plane: "
            "the matches are not on that plane"
        )
    # an orthonormal, right-handed basis (a, b, n_s)
    helper = np.eye(3)[int(np.argmin(np.abs(n_s)))]
    a = np.cross(helper, n_s)
    a /= np.linalg.norm(a)
    b = np.cross(n_s, a)
    ga, gb = g @ a, g @ b
    distortion = float(np.max(np.abs(np.linalg.svd(np.c_[ga, gb], compute_uv=False) - 1.0)))
    if distortion > max_distortion:
        raise VisionError(
            f"the homography is not one of the known plane (its restriction to the plane's "
            f"directions is {distortion:.3f} from a rotation, over {max_distortion}): "
            "the matches are not on that plane"
        )
    gn = np.cross(ga, gb)
    r = nearest_rotation(np.outer(ga, a) + np.outer(gb, b) + np.outer(gn / np.linalg.norm(gn), n_s))
    t = d * (g @ n_s - r @ n_s)
    r_r = nearest_rotation(r @ synthetic.rotation)
    c_r = synthetic.position - r_r.T @ t
    real = Camera(
        float(k_r[0, 0]), float(k_r[1, 1]), float(k_r[0, 2]), float(k_r[1, 2]),
        synthetic.width, synthetic.height, r_r, c_r,
    )
    return PoseCorrection(r, t, n_s, real, in_front, distortion)


def correct_pose(
    synthetic: Camera,
    homography: ArrayLike,
    synthetic_points: ArrayLike,
    *,
    gain: float = 0.5,
    plane_normal: ArrayLike = (0.0, 0.0, 1.0),
    plane_offset: float = 0.0,
    real_intrinsics: ArrayLike | None = None,
) -> Camera:
    """The synthetic camera moved the fraction ``gain`` towards the pose
    :func:`estimate_pose` finds: ``R_s <- exp(g log R) R_s`` and
    ``C_s <- C_s + g (C_r - C_s)``."""
    if not 0.0 < gain <= 1.0:
        raise ValueError(f"gain must be in (0, 1], got {gain}")
    est = estimate_pose(
        synthetic, homography, synthetic_points, plane_normal=plane_normal,
        plane_offset=plane_offset, real_intrinsics=real_intrinsics,
    )
    rot = nearest_rotation(rotation_exp(gain * rotation_log(est.rotation)) @ synthetic.rotation)
    pos = synthetic.position + gain * (est.real.position - synthetic.position)
    return synthetic.with_pose(rot, pos)
