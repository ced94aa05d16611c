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
above the plane.  ``cv2.decomposeHomographyMat`` gives up to four ``(R, t/d,
n)``; the physically consistent one is kept: every inlier point in front of
both cameras (``cv2.filterHomographyDecompByVisibleRefpoints``) and the normal
closest to the known ``n``.  Then ``R_r = R R_s`` and ``C_r = C_s - R_r^T t``.

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

import cv2
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
    "MIN_NORMAL_AGREEMENT",
]

#: Cosine between the decomposed and the known plane normal below which no
#: decomposition is physically consistent (about 25 degrees).
MIN_NORMAL_AGREEMENT = 0.9

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
        The plane normal in the synthetic camera frame that was chosen.
    real : Camera
        The real camera implied (the synthetic intrinsics at ``R_r``, ``C_r``).
    candidates : int
        Decompositions that passed the visibility (cheirality) check.
    """

    rotation: FloatArray
    translation: FloatArray
    normal: FloatArray
    real: Camera
    candidates: int


def estimate_pose(
    synthetic: Camera,
    homography: ArrayLike,
    synthetic_points: ArrayLike,
    *,
    plane_normal: ArrayLike = (0.0, 0.0, 1.0),
    plane_offset: float = 0.0,
    real_intrinsics: ArrayLike | None = None,
) -> PoseCorrection:
    """The real camera's pose from the homography a world plane induces.

    Parameters
    ----------
    synthetic : Camera
        The synthetic camera (its pose is the reference).
    homography : (3, 3) array_like
        ``H_e`` (synthetic -> real pixels) fitted to matches on the plane.
    synthetic_points : (N, 2) array_like
        Synthetic pixels of (inlier) matches on the plane, for the visibility
        check.
    plane_normal, plane_offset
        The world plane ``plane_normal . X = plane_offset`` (the floor by default).
    real_intrinsics : (3, 3) array_like, optional
        ``K_r``; the synthetic camera's ``K`` by default.

    Raises
    ------
    VisionError
        If the camera is on the plane, or no decomposition is physically
        consistent with the known plane.
    """
    k_r = _k(synthetic, real_intrinsics)
    n_w = np.asarray(plane_normal, float).reshape(3)
    n_w = n_w / np.linalg.norm(n_w)
    d = float(n_w @ synthetic.position - plane_offset)
    if abs(d) < 1e-9:
        raise VisionError("the synthetic camera lies in the plane: the plane homography has no pose")
    n_s = -np.sign(d) * (synthetic.rotation @ n_w)
    d = abs(d)
    g = np.linalg.inv(k_r) @ np.asarray(homography, float).reshape(3, 3) @ synthetic.K
    g = g / np.linalg.svd(g, compute_uv=False)[1]  # scale so the middle singular value is 1
    _, rots, trans, norms = cv2.decomposeHomographyMat(g, np.eye(3))
    pts = np.asarray(synthetic_points, float).reshape(-1, 2)
    before = cv2.undistortPoints(pts.reshape(-1, 1, 2), synthetic.K, None)
    after_h = np.c_[pts, np.ones(len(pts))] @ (np.linalg.inv(k_r) @ np.asarray(homography, float).reshape(3, 3)).T
    after = (after_h[:, :2] / after_h[:, 2:]).reshape(-1, 1, 2)
    keep = cv2.filterHomographyDecompByVisibleRefpoints(
        rots, norms, before.astype(np.float32), after.astype(np.float32)
    )
    idx = [int(i) for i in np.asarray(keep).ravel()] if keep is not None else list(range(len(rots)))
    if not idx:
        idx = list(range(len(rots)))
    best = max(idx, key=lambda i: float(norms[i].ravel() @ n_s))
    agree = float(norms[best].ravel() @ n_s)
    if agree < MIN_NORMAL_AGREEMENT:
        raise VisionError(
            f"no decomposition of the homography has the known plane normal "
            f"(best agreement cos = {agree:.2f}): the matches are not on that plane"
        )
    r = nearest_rotation(np.asarray(rots[best]))
    t = np.asarray(trans[best], float).ravel() * d
    r_r = r @ synthetic.rotation
    c_r = synthetic.position - r_r.T @ t
    real = Camera(
        float(k_r[0, 0]), float(k_r[1, 1]), float(k_r[0, 2]), float(k_r[1, 2]),
        synthetic.width, synthetic.height, r_r, c_r,
    )
    return PoseCorrection(r, t, np.asarray(norms[best], float).ravel(), real, len(idx))


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
