"""The camera loop: turn the synthetic camera until its view agrees with the real one.

:func:`synchronise` repeats: render the synthetic view from the current camera
(through the ``render`` callback, so vision never imports the imagination),
compute the MMD against the real image, measure the remaining pixel error
``e = corner_error(H_e, I)`` (how far ``H_e`` moves the image corners, in the
real image's pixels), stop if ``e < tolerance`` (0.5 px at 640x480 by default,
scaled with the image), otherwise correct the camera with eq. 3 (fractional
rotation, :func:`~adapt.vision.camera_correction.correct_rotation`) or, with
``full_pose=True``, with the floor's plane-induced homography
(:func:`~adapt.vision.camera_correction.correct_pose`).

With a perfect ``H_e`` the error after ``t`` corrections is
``e_0 (1 - g)^t``: from 35 px, g = 0.5 needs 6 corrections to reach 0.5 px.

An ``on_step`` callback sees each :class:`SyncStep` as soon as it is done
(the command line prints a line and writes a strip per step).

Examples
--------
>>> import numpy as np, cv2
>>> from adapt.geometry import Camera, rotation_exp
>>> rng = np.random.default_rng(0)
>>> plane = cv2.GaussianBlur(rng.integers(0, 256, (480, 640), dtype=np.uint8), (0, 0), 2)
>>> base = Camera(500, 500, 159.5, 119.5, 320, 240, np.eye(3), np.zeros(3))
>>> k_plane = np.array([[500, 0, 319.5], [0, 500, 239.5], [0, 0, 1.0]])
>>> def render(cam):
...     h = cam.K @ cam.rotation @ np.linalg.inv(k_plane)
...     return cv2.warpPerspective(plane, h, cam.size)
>>> real = render(base)
>>> start = base.with_rotation(rotation_exp([0.01, -0.015, 0.02]))
>>> result = synchronise(real, start, render, gain=1.0, tolerance=0.3)
>>> result.converged, len(result.steps) <= 3, result.steps[-1].pixel_error < 0.3
(True, True, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Literal

import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera, rotation_log
from adapt.vision.camera_correction import correct_pose, correct_rotation
from adapt.vision.homography import corner_error
from adapt.vision.images import check_image
from adapt.vision.matching import prepare
from adapt.vision.mmd import MMDResult, mmd
from adapt.vision.scale import image_scale

__all__ = ["Render", "SyncStep", "SyncResult", "synchronise", "TOLERANCE", "MAX_ITERATIONS", "GAIN"]

#: Stop when H_e moves the image corners by less than this, pixels at 640x480
#: (scaled with the image).
TOLERANCE = 0.5
#: Give up after this many renders.
MAX_ITERATIONS = 10
#: Default g.
GAIN = 0.5

Render = Callable[[Camera], NDArray]


@dataclass(frozen=True, slots=True, eq=False)
class SyncStep:
    """One iteration of the camera loop.

    Attributes
    ----------
    iteration : int
        0 for the starting camera.
    camera : Camera
        The camera the synthetic image was rendered from.
    pixel_error : float
        Mean corner displacement of ``H_e`` (``nan`` without alignment).
    n_inliers : int
    correction_deg : float
        Angle of the rotation applied after this step (0 when it stopped here).
    synthetic : ndarray
        The rendered image.
    result : MMDResult
        The MMD of the real image against ``synthetic``.
    """

    iteration: int
    camera: Camera
    pixel_error: float
    n_inliers: int
    correction_deg: float
    synthetic: NDArray = field(repr=False)
    result: MMDResult = field(repr=False)

    def as_dict(self) -> dict[str, object]:
        """JSON form: iteration, pixel_error, inliers, correction_deg, camera rotation/position."""
        return {
            "iteration": self.iteration,
            "pixel_error": None if math.isnan(self.pixel_error) else round(self.pixel_error, 4),
            "inliers": self.n_inliers,
            "correction_deg": round(self.correction_deg, 5),
            "rotation": np.round(self.camera.rotation, 8).tolist(),
            "position": np.round(self.camera.position, 8).tolist(),
        }


@dataclass(frozen=True, slots=True, eq=False)
class SyncResult:
    """The camera loop's outcome.

    Attributes
    ----------
    steps : tuple of SyncStep
    camera : Camera
        The best camera: the last rendered one when converged, else the
        camera after the last correction.
    converged : bool
        The pixel error fell below the tolerance.
    reason : str
        Why the loop stopped.
    """

    steps: tuple[SyncStep, ...]
    camera: Camera
    converged: bool
    reason: str

    @property
    def outcome(self) -> Literal["converged", "no alignment", "iteration limit"]:
        """How the loop ended: ``"converged"``, ``"no alignment"`` (a render
        could not be aligned with the real image) or ``"iteration limit"``
        (``max_iterations`` renders without reaching the tolerance)."""
        if self.converged:
            return "converged"
        if self.steps and not self.steps[-1].result.aligned:
            return "no alignment"
        return "iteration limit"


def synchronise(
    real: NDArray,
    camera: Camera,
    render: Render,
    *,
    gain: float = GAIN,
    tolerance: float | None = None,
    max_iterations: int = MAX_ITERATIONS,
    full_pose: bool = False,
    on_step: Callable[[SyncStep], None] | None = None,
    max_pixels: int | None = None,
) -> SyncResult:
    """Synchronise the synthetic camera with the real image.

    Parameters
    ----------
    real : ndarray
        The real image.
    camera : Camera
        The synthetic camera's starting pose (the scenario's nominal one).
    render : callable
        ``render(camera) -> image`` of the same size, dtype and channels as
        ``real``.
    gain : float
        ``g`` in (0, 1].
    tolerance : float, optional
        Stop when the pixel error (real image pixels) is below this;
        :data:`TOLERANCE` scaled with the real image by default.
    max_iterations : int
        Most renders.
    full_pose : bool
        Correct the position as well, from the floor's homography (the scene
        seen must then be the floor plane ``z = 0``).
    on_step : callable, optional
        Called with each :class:`SyncStep` as soon as it is complete.
    max_pixels : int, optional
        The MMD's working resolution (:func:`~adapt.vision.mmd.mmd`).

    Raises
    ------
    VisionError
        If ``real`` and the rendered images cannot be compared.
    """
    if not 0.0 < gain <= 1.0:
        raise ValueError(f"gain must be in (0, 1], got {gain}")
    if max_iterations < 1:
        raise ValueError(f"max_iterations must be at least 1, got {max_iterations}")
    r = prepare(check_image(real, "real"), corners=False, name="real",
                **({} if max_pixels is None else {"max_pixels": max_pixels}))
    if tolerance is None:
        tolerance = TOLERANCE * image_scale(r.shape)
    steps: list[SyncStep] = []

    def done(step: SyncStep) -> None:
        steps.append(step)
        if on_step is not None:
            on_step(step)

    cam = camera
    for it in range(max_iterations):
        synthetic = render(cam)
        res = mmd(r, synthetic)
        if not res.aligned:
            done(SyncStep(it, cam, math.nan, 0, 0.0, synthetic, res))
            return SyncResult(
                tuple(steps), cam, False, f"no alignment at iteration {it}: {res.alignment.reason}"
            )
        h = res.homography
        assert h is not None
        err = corner_error(h, np.eye(3), real.shape)
        if err < tolerance:
            done(SyncStep(it, cam, err, res.n_inliers, 0.0, synthetic, res))
            return SyncResult(tuple(steps), cam, True, f"pixel error {err:.3f} < {tolerance:g}")
        if full_pose:
            pts = res.matches.synthetic_points[res.alignment.inliers]
            new = correct_pose(cam, h, pts, gain=gain)
        else:
            new = correct_rotation(cam, h, gain=gain)
        turn = float(np.degrees(np.linalg.norm(rotation_log(new.rotation @ cam.rotation.T))))
        done(SyncStep(it, cam, err, res.n_inliers, turn, synthetic, res))
        cam = new
    return SyncResult(
        tuple(steps), cam, False, f"pixel error still {steps[-1].pixel_error:.3f} after {max_iterations} renders"
    )

