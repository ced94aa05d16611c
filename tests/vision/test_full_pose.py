"""The full-pose camera loop end to end: the bundled scene rendered through a
"real" camera that is translated and rotated from the nominal one, and the
synthetic camera synchronised to it with ``synchronise(..., full_pose=True)``.

The real and synthetic images both come from the imagination renderer (only
the library package ``adapt.vision`` must not import it; tests may).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from adapt.geometry import Camera, rotation_exp, rotation_log
from adapt.imagination import Renderer
from adapt.scenario import load_scenario
from adapt.vision.camera_correction import estimate_pose
from adapt.vision.sync import SyncResult, synchronise

SCENARIO = Path(__file__).resolve().parents[2] / "scenarios" / "room.yaml"
#: A floor-dominated view: the scenario's camera (0.6 m above the floor),
#: looking down at a point 1.8 m ahead of it instead of at the wall.
LOOK_AT = (0.0, 1.2, 0.0)


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(np.linalg.norm(rotation_log(a @ b.T))))


def reprojection_px(cam: Camera, true_cam: Camera) -> float:
    """Mean pixel distance between where ``cam`` and ``true_cam`` see the floor
    points that ``true_cam`` sees on a grid over the lower 3/4 of its image."""
    us, vs = np.meshgrid(np.linspace(20, true_cam.width - 20, 12), np.linspace(140, true_cam.height - 20, 9))
    floor = true_cam.pixel_to_plane(np.c_[us.ravel(), vs.ravel()], 0.0)
    return float(np.linalg.norm(cam.project(floor) - true_cam.project(floor), axis=1).mean())


@pytest.fixture(scope="module")
def setup() -> tuple[Renderer, Camera]:
    scenario = load_scenario(SCENARIO)
    c = scenario.camera
    nominal = Camera.look_at(fx=c.fx, fy=c.fy, cx=c.cx, cy=c.cy, width=c.width, height=c.height,
                             position=c.position, look_at=LOOK_AT)
    return Renderer(scenario.scene, nominal), nominal


class Render:
    """The render callback: the scene's initial state through any camera."""

    def __init__(self, base: Renderer) -> None:
        self.base = base
        self.calls = 0

    def __call__(self, cam: Camera) -> np.ndarray:
        self.calls += 1
        return self.base.with_camera(cam).render().image


def run(setup: tuple[Renderer, Camera], shift: tuple[float, float, float], turn_deg: tuple[float, float, float],
        *, full_pose: bool, gain: float) -> tuple[SyncResult, Camera, Render]:
    base, nominal = setup
    real_cam = nominal.with_pose(rotation_exp(np.radians(turn_deg)) @ nominal.rotation,
                                 nominal.position + np.asarray(shift))
    render = Render(base)
    real = base.with_camera(real_cam).render().image
    result = synchronise(real, nominal, render, full_pose=full_pose, gain=gain, tolerance=0.5,
                         max_iterations=10)
    return result, real_cam, render


# (translation in metres, rotation vector in degrees, gain): 5.4 cm / 2.7 deg and
# 4.1 cm / 2.3 deg; g = 1 ends on corrections of a millimetre or less, where a
# general homography decomposition's plane normal is arbitrary.
CASES = [((0.04, -0.03, 0.02), (1.5, -1.0, 2.0), 0.5), ((-0.03, 0.025, -0.012), (-1.2, 1.8, 0.6), 1.0)]


@pytest.mark.parametrize("shift, turn, gain", CASES)
def test_full_pose_loop_converges_on_the_rendered_scene(setup, shift, turn, gain):
    _, nominal = setup
    result, real_cam, render = run(setup, shift, turn, full_pose=True, gain=gain)
    start = result.steps[0]
    assert np.linalg.norm(start.camera.position - real_cam.position) > 0.04
    assert angle_deg(start.camera.rotation, real_cam.rotation) > 2.0
    assert start.pixel_error > 20.0
    assert result.converged, result.reason
    assert len(result.steps) <= (10 if gain < 1 else 6)
    assert render.calls == len(result.steps)
    assert result.steps[-1].pixel_error < 0.5
    cam = result.camera
    assert np.linalg.norm(cam.position - real_cam.position) < 0.005  # 5 mm
    assert angle_deg(cam.rotation, real_cam.rotation) < 0.2
    assert reprojection_px(cam, real_cam) < 0.5
    assert reprojection_px(nominal, real_cam) > 20.0
    # the position moved towards the truth at every correction
    gaps = [np.linalg.norm(s.camera.position - real_cam.position) for s in result.steps]
    assert all(b < a for a, b in zip(gaps, gaps[1:]))


def test_rotation_only_cannot_explain_the_translation(setup):
    shift, turn, gain = CASES[0]
    full, real_cam, _ = run(setup, shift, turn, full_pose=True, gain=gain)
    rot, _, _ = run(setup, shift, turn, full_pose=False, gain=gain)
    assert full.converged and not rot.converged
    # rotation only never moves the camera, so the floor stays misregistered
    assert np.linalg.norm(rot.camera.position - real_cam.position) == pytest.approx(np.linalg.norm(shift))
    best_rot = min(s.pixel_error for s in rot.steps)
    assert best_rot > 5.0 > 10 * full.steps[-1].pixel_error
    assert reprojection_px(rot.camera, real_cam) > 10 * reprojection_px(full.camera, real_cam)


def _plane_h(real: Camera, syn: Camera) -> np.ndarray:
    return real.projection[:, [0, 1, 3]] @ np.linalg.inv(syn.projection[:, [0, 1, 3]])


@pytest.mark.parametrize("shift", [0.0005, 0.002, 0.05])
def test_estimate_pose_is_well_conditioned_for_small_translations(setup, shift):
    _, nominal = setup
    rng = np.random.default_rng(7)
    d = rng.normal(size=3)
    real_cam = nominal.with_pose(rotation_exp(np.radians([0.3, -0.2, 0.1])) @ nominal.rotation,
                                 nominal.position + d / np.linalg.norm(d) * shift)
    pts = nominal.project(nominal.pixel_to_plane(rng.uniform((0, 200), (640, 480), (50, 2)), 0.0))
    h = _plane_h(real_cam, nominal)
    for sign in (1.0, -1.0):  # a homography is defined up to sign: cheirality picks it
        est = estimate_pose(nominal, sign * h, pts)
        assert np.linalg.norm(est.real.position - real_cam.position) < 1e-6
        assert angle_deg(est.real.rotation, real_cam.rotation) < 1e-6
        assert est.in_front == len(pts) and est.distortion < 1e-9
