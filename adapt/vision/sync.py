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

from adapt.errors import VisionError
from adapt.geometry import Camera
from adapt.vision.camera_correction import correct_pose, correct_rotation, rotation_error
from adapt.vision.homography import corner_error
from adapt.vision.images import check_image
from adapt.vision.matching import PreparedImage, prepare
from adapt.vision.mmd import MMDResult, mmd
from adapt.vision.scale import image_scale

__all__ = ["Render", "SyncStep", "SyncResult", "synchronise", "sync_step", "correction",
           "TOLERANCE", "MAX_ITERATIONS", "GAIN", "MIN_PLANE_POINTS", "MAX_TURN_MISFIT",
           "turn_misfit"]

#: Stop when H_e moves the image corners by less than this, pixels at 640x480
#: (scaled with the image).
TOLERANCE = 0.5
#: Give up after this many renders.
MAX_ITERATIONS = 10
#: Default g.
GAIN = 0.5
#: Fewest inlier matches on the floor the full pose is corrected from (fewer: the rotation).
MIN_PLANE_POINTS = 12
#: The Scene Background's ``max_misfit`` (:func:`sync_step`): an ``H_e`` that the nearest
#: turn of the camera leaves this far off (pixels at 640x480, scaled; :func:`turn_misfit`)
#: is no alignment: a camera that only turns cannot make it (a zoom of a tenth, from
#: matches bunched on one band of the view), and corrected by its nearest turn the camera
#: walks off, frame after frame.  (On the foreign throws: at most 2.7 px where the matches
#: are right, 7-13 px on the frames that turned an outside camera 10-15 px off.)
MAX_TURN_MISFIT = 3.0

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
    corrected : Camera or None
        The camera after this step's correction; None when there is none (no
        alignment, within the tolerance, not trusted, or no rotation to be had).
    trusted : bool
        Aligned, and the caller's ``trust`` filter took the alignment.
    """

    iteration: int
    camera: Camera
    pixel_error: float
    n_inliers: int
    correction_deg: float
    synthetic: NDArray = field(repr=False)
    result: MMDResult = field(repr=False)
    corrected: Camera | None = field(default=None, repr=False)
    trusted: bool = True

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
        step = sync_step(r, synthetic, cam, gain=gain, tolerance=tolerance, full_pose=full_pose,
                         iteration=it, shape=real.shape)
        done(step)
        if not step.result.aligned:
            return SyncResult(tuple(steps), cam, False,
                              f"no alignment at iteration {it}: {step.result.alignment.reason}")
        if step.corrected is None:
            if step.pixel_error <= tolerance:
                return SyncResult(tuple(steps), cam, True,
                                  f"pixel error {step.pixel_error:.3f} < {tolerance:g}")
            return SyncResult(tuple(steps), cam, False,
                              f"no correction at iteration {it}: the homography gives no rotation")
        cam = step.corrected
    return SyncResult(
        tuple(steps), cam, False, f"pixel error still {steps[-1].pixel_error:.3f} after {max_iterations} renders"
    )


def correction(camera: Camera, result: MMDResult, *, gain: float = GAIN, full_pose: bool = False,
               on_plane: NDArray[np.bool_] | None = None) -> Camera | None:
    """The camera corrected from an aligned MMD ``result``: the one rule for the full pose
    and the rotation.

    With ``full_pose``, the position is corrected too, from the inlier matches on the
    floor (``on_plane`` marks them among the inliers; all of them when None): with at
    least :data:`MIN_PLANE_POINTS` of them and a homography that is the floor's
    (:func:`~adapt.vision.camera_correction.correct_pose`).  Otherwise, or when the
    pose cannot be solved, the rotation alone (eq. 3,
    :func:`~adapt.vision.camera_correction.correct_rotation`); None when even that
    cannot be computed (a degenerate homography).

    Examples
    --------
    >>> import numpy as np
    >>> from adapt.geometry import rotation_exp
    >>> from adapt.vision.mmd import mmd
    >>> rng = np.random.default_rng(0)
    >>> img = (rng.random((240, 320)) * 255).astype(np.uint8)
    >>> cam = Camera(300, 300, 159.5, 119.5, 320, 240, np.eye(3), np.zeros(3))
    >>> res = mmd(img, img)
    >>> correction(cam, res, gain=0.5).angle_to(cam) < 1e-6
    True
    """
    h = result.homography
    if h is None:
        return None
    if full_pose:
        pts = result.matches.synthetic_points[result.alignment.inliers]
        if on_plane is not None:
            pts = pts[on_plane]
        if len(pts) >= MIN_PLANE_POINTS:
            try:
                return correct_pose(camera, h, pts, gain=gain)
            except VisionError:
                pass
    try:
        return correct_rotation(camera, h, gain=gain)
    except VisionError:
        return None


def turn_misfit(homography: NDArray[np.float64], camera: Camera, shape: tuple[int, ...]) -> float:
    """How far (mean corner displacement, pixels of an image of ``shape``) ``homography``
    is from the one the nearest turn of ``camera`` makes, ``K R_e K^-1``
    (:func:`~adapt.vision.camera_correction.rotation_error`); ``inf`` for a homography no
    rotation can be taken from.

    Examples
    --------
    >>> from adapt.geometry import rotation_exp
    >>> cam = Camera(300, 300, 159.5, 119.5, 320, 240, np.eye(3), np.zeros(3))
    >>> turn = cam.K @ rotation_exp([0.01, -0.02, 0.005]) @ np.linalg.inv(cam.K)
    >>> round(turn_misfit(turn, cam, (240, 320)), 6)
    0.0
    >>> zoom = np.diag([1.1, 1.1, 1.0]); zoom[:2, 2] = -0.1 * np.array([159.5, 119.5])
    >>> round(turn_misfit(zoom, cam, (240, 320)), 1)  # a tenth's zoom about the centre
    20.0
    """
    try:
        r = rotation_error(homography, camera.K, camera.K)
    except VisionError:
        return math.inf
    return corner_error(np.asarray(homography, float), camera.K @ r @ np.linalg.inv(camera.K),
                        shape)


def sync_step(
    real: NDArray | PreparedImage,
    synthetic: NDArray | PreparedImage,
    camera: Camera,
    *,
    gain: float = GAIN,
    tolerance: float,
    full_pose: bool = False,
    on_plane: Callable[[NDArray[np.float64]], NDArray[np.bool_]] | None = None,
    trust: Callable[[float], bool] | None = None,
    max_pixels: int | None = None,
    iteration: int = 0,
    shape: tuple[int, ...] | None = None,
    hold: NDArray | None = None,
    reacquire: bool = True,
    max_misfit: float | None = None,
) -> SyncStep:
    """One step of the camera loop: the MMD of ``real`` and ``synthetic`` (rendered from
    ``camera``), its pixel error, and the corrected camera.

    The pixel error is how far ``H_e`` moves the corners of the real image (its pixels;
    ``shape`` is the real image's when ``real`` is prepared at a reduced resolution).
    The camera is corrected (:func:`correction`) when the images are aligned, the error
    is above ``tolerance``, and ``trust(error)`` allows it (a caller's filter of false
    alignments; ``SyncStep.trusted`` says what it said).  ``on_plane`` marks, among the
    inlier matches' synthetic points, those on the floor (for ``full_pose``).  ``hold``
    is the ``H_e`` to use when the matches give none (:func:`~adapt.vision.mmd.mmd`);
    a held ``H_e`` corrects nothing.  ``reacquire`` allows the MMD's SIFT re-acquisition
    (:func:`~adapt.vision.mmd.mmd`).

    With ``max_misfit`` (pixels at 640x480, scaled; :data:`MAX_TURN_MISFIT` is the Scene
    Background's) and without ``full_pose``, an ``H_e`` further than that from the nearest
    turn of the camera (:func:`turn_misfit`) is no alignment (``hold`` then applies): where
    the render differs from the frame only by how the camera turned (a fixed camera whose
    look was learned through its pose), no turn makes it.  (A camera moved off the model's
    position makes such an ``H_e`` in earnest: :func:`synchronise` takes it.)

    This is the step both :func:`synchronise` and the Scene Background schema take.
    """
    if shape is None:
        shape = real.shape
    refuse: Callable[[NDArray[np.float64]], str] | None = None
    if max_misfit is not None and not full_pose:
        limit = max_misfit * image_scale(shape)
        size = shape

        def not_a_turn(h: NDArray[np.float64]) -> str:
            off = turn_misfit(h, camera, size)
            return (f"H_e is {off:.1f} px from the nearest turn of the camera: no turn makes it"
                    if off > limit else "")
        refuse = not_a_turn
    res = mmd(real, synthetic, max_pixels=max_pixels, hold=hold, reacquire=reacquire,
              refuse=refuse)
    image = synthetic.image if isinstance(synthetic, PreparedImage) else synthetic
    if not res.aligned:
        return SyncStep(iteration, camera, math.nan, 0, 0.0, image, res, None, False)
    h = res.homography
    assert h is not None
    err = corner_error(h, np.eye(3), shape)
    if trust is not None and not trust(err):
        return SyncStep(iteration, camera, err, res.n_inliers, 0.0, image, res, None, False)
    new = None
    if err > tolerance and not res.alignment.held:  # a held H_e has no matches to correct by
        plane = None
        if full_pose and on_plane is not None:
            plane = on_plane(res.matches.synthetic_points[res.alignment.inliers])
        new = correction(camera, res, gain=gain, full_pose=full_pose, on_plane=plane)
    turn = 0.0 if new is None else camera.angle_to(new)
    return SyncStep(iteration, camera, err, res.n_inliers, turn, image, res, new, True)
