"""Camera correction (eq. 3) and the camera loop, proven on image round trips."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from adapt.errors import VisionError
from adapt.geometry import Camera, rotation_exp, rotation_log
from adapt.vision.camera_correction import (
    correct_pose,
    correct_rotation,
    estimate_pose,
    rotation_error,
)
from adapt.vision.homography import corner_error
from adapt.vision.mmd import mmd
from adapt.vision.sync import MAX_TURN_MISFIT, sync_step, synchronise, turn_misfit

from . import scenes


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(np.linalg.norm(rotation_log(a @ b.T))))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rotation_correction_order_and_sign_on_images(seed):
    real, synthetic, _, real_cam, syn_cam = scenes.pair("room", seed)
    before = angle_deg(syn_cam.rotation, real_cam.rotation)
    assert before > 0.5
    r = mmd(real, synthetic)
    # R_e = R_r R_s^T, so R_e R_s is the real rotation ...
    r_e = rotation_error(r.homography, real_cam.K, syn_cam.K)
    assert angle_deg(r_e, real_cam.rotation @ syn_cam.rotation.T) < 0.05
    full = correct_rotation(syn_cam, r.homography, gain=1.0)
    assert angle_deg(full.rotation, real_cam.rotation) < 0.05
    # ... while the inverse correction would move away from it.
    assert angle_deg(r_e.T @ syn_cam.rotation, real_cam.rotation) > before
    # g = 0.5 goes half way along the geodesic.
    half = correct_rotation(syn_cam, r.homography, gain=0.5)
    assert angle_deg(half.rotation, real_cam.rotation) == pytest.approx(before / 2, abs=0.05)


def test_rotation_correction_composes_on_the_left():
    # A far-from-identity camera makes R_e R_s and R_s R_e clearly different.
    syn = scenes.camera(rotation_exp([0.3, -0.8, 0.5]))
    real = syn.with_rotation(rotation_exp([0.05, 0.02, -0.04]) @ syn.rotation)
    h = scenes.true_homography(real, syn)
    fixed = correct_rotation(syn, h, gain=1.0)
    assert angle_deg(fixed.rotation, real.rotation) < 1e-6
    r_e = rotation_error(h, real.K, syn.K)
    assert angle_deg(syn.rotation @ r_e, real.rotation) > 1.0


def test_gain_must_be_in_0_1():
    cam = scenes.camera()
    with pytest.raises(ValueError):
        correct_rotation(cam, np.eye(3), gain=0.0)
    with pytest.raises(ValueError):
        synchronise(np.zeros((480, 640), np.uint8), cam, lambda c: np.zeros((480, 640), np.uint8), gain=1.5)


def test_singular_homography_is_a_vision_error():
    with pytest.raises(VisionError):
        rotation_error(np.zeros((3, 3)), np.eye(3), np.eye(3))


def _floor_camera(position, look_at) -> Camera:
    return Camera.look_at(fx=525, fy=525, cx=319.5, cy=239.5, width=640, height=480,
                          position=position, look_at=look_at)


def _floor_view(texture: np.ndarray, cam: Camera, metres_per_px: float) -> np.ndarray:
    """The camera's view of a floor (z = 0) covered by ``texture``, centred on the origin."""
    th, tw = texture.shape[:2]
    # texture pixel (u, v) -> world (x, y, 0)
    a = np.array([[metres_per_px, 0, -tw / 2 * metres_per_px],
                  [0, -metres_per_px, th / 2 * metres_per_px],
                  [0, 0, 1.0]])
    p = cam.projection[:, [0, 1, 3]] @ a
    return cv2.warpPerspective(texture, p, cam.size, flags=cv2.INTER_LINEAR)


def test_full_pose_from_the_floor_homography_on_images():
    texture = cv2.copyMakeBorder(scenes.world("gravel"), 0, 0, 0, 0, cv2.BORDER_REFLECT)
    texture = np.tile(texture, (2, 2))
    syn_cam = _floor_camera((0.0, -1.5, 1.2), (0.0, 0.4, 0.0))
    real_cam = syn_cam.with_pose(
        rotation_exp([0.02, -0.015, 0.01]) @ syn_cam.rotation, syn_cam.position + [0.06, -0.04, 0.03]
    )
    synthetic = _floor_view(texture, syn_cam, 0.003)
    real = _floor_view(texture, real_cam, 0.003)
    r = mmd(real, synthetic)
    assert r.aligned
    pts = r.matches.synthetic_points[r.alignment.inliers]
    est = estimate_pose(syn_cam, r.homography, pts)
    assert np.linalg.norm(est.real.position - real_cam.position) < 0.01
    assert angle_deg(est.real.rotation, real_cam.rotation) < 0.2
    # the rotation-only correction cannot explain the translation; the pose one can
    moved = correct_pose(syn_cam, r.homography, pts, gain=1.0)
    assert np.linalg.norm(moved.position - real_cam.position) < 0.01


def test_full_pose_rejects_matches_off_the_plane():
    syn_cam = _floor_camera((0.0, -1.5, 1.2), (0.0, 0.4, 0.0))
    # a homography of a pure pan (a plane at infinity, not the floor)
    real_cam = syn_cam.with_pose(rotation_exp([0.0, 0.0, 0.0]) @ syn_cam.rotation, syn_cam.position + [0.5, 0, 0])
    rng = np.random.default_rng(0)
    wall = np.c_[rng.uniform(-1, 1, 100), np.full(100, 3.0), rng.uniform(0.2, 2.0, 100)]  # x = ... a wall y = 3
    ps, pr = syn_cam.project(wall), real_cam.project(wall)
    h, _ = cv2.findHomography(ps, pr, 0)
    with pytest.raises(VisionError, match="not on that plane"):
        estimate_pose(syn_cam, h, ps)


class PlanarPhoto:
    """A render callback: a shipped photograph as a plane, seen by any rotated camera."""

    def __init__(self, name: str, seed: int) -> None:
        self.world = scenes.world(name)
        self.rng = np.random.default_rng(seed)
        self.calls = 0

    def __call__(self, cam: Camera) -> np.ndarray:
        self.calls += 1
        return scenes.renderer_look(scenes.view(self.world, cam), self.rng)


@pytest.mark.parametrize("name, seed", [("room", 0), ("coffee", 1), ("brick", 2)])
def test_camera_loop_converges_from_35_px(name, seed):
    rng = np.random.default_rng(seed)
    real_cam = scenes.camera()
    world = scenes.world(name)
    real = scenes.sensor_noise(scenes.view(world, real_cam), rng)
    # a start about 35 px away
    axis = rng.normal(size=3)
    start = real_cam.with_rotation(rotation_exp(axis / np.linalg.norm(axis) * np.radians(3.5)))
    h0 = scenes.true_homography(real_cam, start)
    assert 25 < corner_error(h0, np.eye(3), real.shape) < 50
    render = PlanarPhoto(name, seed)
    result = synchronise(real, start, render, gain=0.5, tolerance=0.5, max_iterations=10)
    assert result.converged, result.reason
    assert len(result.steps) <= 9  # <= 8 corrections, then the check that stops
    assert render.calls == len(result.steps)
    true_err = corner_error(scenes.true_homography(real_cam, result.camera), np.eye(3), real.shape)
    assert true_err < 0.6
    errs = [s.pixel_error for s in result.steps]
    assert all(b < a for a, b in zip(errs, errs[1:]))
    assert result.steps[0].as_dict()["inliers"] == result.steps[0].n_inliers


def test_camera_loop_stops_without_alignment():
    real = np.full((480, 640), 90, np.uint8)
    result = synchronise(real, scenes.camera(), lambda cam: np.full((480, 640), 90, np.uint8))
    assert not result.converged and "no alignment" in result.reason
    assert result.outcome == "no alignment"
    assert len(result.steps) == 1 and np.isnan(result.steps[0].pixel_error)
    assert result.steps[0].as_dict()["pixel_error"] is None


def test_each_step_is_reported_as_soon_as_it_is_done():
    rng = np.random.default_rng(3)
    real_cam = scenes.camera()
    real = scenes.sensor_noise(scenes.view(scenes.world("room"), real_cam), rng)
    start = real_cam.with_rotation(rotation_exp([0.03, -0.02, 0.02]))
    render = PlanarPhoto("room", 3)
    seen = []

    def on_step(step):
        # called before the next render: the loop has rendered exactly this many images
        seen.append((step.iteration, render.calls))

    result = synchronise(real, start, render, gain=0.5, max_iterations=3, on_step=on_step)
    assert seen == [(i, i + 1) for i in range(len(result.steps))] and len(seen) == 3
    assert result.outcome == "iteration limit" and not result.converged


def test_default_tolerance_scales_with_the_image():
    # the same loop at 320x240 stops at 0.25 px, not 0.5 px
    plane = cv2.GaussianBlur(np.random.default_rng(0).integers(0, 256, (480, 640), dtype=np.uint8), (0, 0), 2)
    k_plane = np.array([[250, 0, 319.5], [0, 250, 239.5], [0, 0, 1.0]])
    base = Camera(250, 250, 159.5, 119.5, 320, 240, np.eye(3), np.zeros(3))

    def render(cam):
        return cv2.warpPerspective(plane, cam.K @ cam.rotation @ np.linalg.inv(k_plane), cam.size)

    result = synchronise(render(base), base.with_rotation(rotation_exp([0.01, -0.01, 0.01])), render, gain=0.5)
    assert result.converged and "< 0.25" in result.reason
    assert result.steps[-1].pixel_error < 0.25 <= result.steps[-2].pixel_error


def test_an_H_e_no_turn_of_the_camera_makes_is_no_alignment():
    """A real view a tenth larger than the render (as matches bunched on one band of the
    view can make H_e) is no camera turn: the Scene Background's step (``max_misfit``) takes
    no alignment from it and turns nothing (with ``hold`` it compares through that instead);
    a turn itself is taken, and without ``max_misfit`` (``synchronise``) the zoom is too."""
    rng = np.random.default_rng(5)
    cam = scenes.camera()
    world = scenes.world("room")
    synthetic = scenes.renderer_look(scenes.view(world, cam), rng)
    zoom = np.array([[1.1, 0.0, -0.1 * cam.cx], [0.0, 1.1, -0.1 * cam.cy], [0.0, 0.0, 1.0]])
    real = scenes.sensor_noise(cv2.warpPerspective(scenes.view(world, cam), zoom, cam.size), rng)
    assert mmd(real, synthetic).aligned  # the images alone align ...
    step = sync_step(real, synthetic, cam, tolerance=0.5, max_misfit=MAX_TURN_MISFIT)
    assert not step.result.aligned and step.corrected is None  # ... no turn of the camera does
    assert "no turn makes it" in step.result.alignment.reason
    held = sync_step(real, synthetic, cam, tolerance=0.5, hold=np.eye(3), max_misfit=MAX_TURN_MISFIT)
    assert held.result.alignment.held and held.corrected is None
    turned = cam.with_rotation(rotation_exp([0.01, -0.015, 0.01]))
    real = scenes.sensor_noise(scenes.view(world, turned), rng)
    step = sync_step(real, synthetic, cam, tolerance=0.5, max_misfit=MAX_TURN_MISFIT)
    assert step.result.aligned and step.corrected is not None
    assert turn_misfit(step.result.homography, cam, real.shape) < MAX_TURN_MISFIT
    real = scenes.sensor_noise(cv2.warpPerspective(scenes.view(world, cam), zoom, cam.size), rng)
    assert sync_step(real, synthetic, cam, tolerance=0.5).result.aligned
