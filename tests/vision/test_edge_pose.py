"""The camera's pose from the seams of the known structure: round trips with known offsets.

The real image is the imagination's render through a camera turned and moved by a known
offset, then given another look (colour gain and shift, grain, blur, sensor noise); the
fit starts from the nominal camera's seams.  (The imagination renders here only to make
test images: the library package ``adapt.vision`` must not import it; tests may.)
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.geometry import Camera, rotation_exp
from adapt.imagination import Renderer
from adapt.imagination.scene import Obstacle, SceneSpec
from adapt.scenario import load_scenario
from adapt.vision.edge_pose import SEARCH_M, SeamPoints, apply_pose, edge_score, fit_edges, seam_points

SCENARIO = Path(__file__).resolve().parents[2] / "scenarios" / "foreign-fixed.yaml"


@pytest.fixture(scope="module")
def nominal() -> Renderer:
    scenario = load_scenario(SCENARIO)
    return Renderer(scenario.scene, scenario.camera)


def floor_error_m(cam: Camera, true_cam: Camera, z: float = 0.1) -> float:
    """Median distance on the plane ``z`` between where ``cam`` and ``true_cam`` put the
    pixels of the lower two thirds of ``true_cam``'s image."""
    us, vs = np.meshgrid(np.linspace(10, true_cam.width - 10, 10),
                         np.linspace(true_cam.height / 3, true_cam.height - 10, 8))
    px = np.c_[us.ravel(), vs.ravel()]
    return float(np.median(np.linalg.norm(cam.pixel_to_plane(px, z) - true_cam.pixel_to_plane(px, z),
                                          axis=1)))


def other_look(image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Another renderer's look: per-channel gain and shift, grain, blur, noise."""
    out = image.astype(np.float32) * rng.uniform(0.7, 1.3, 3) + rng.uniform(-25, 25, 3)
    out += rng.normal(0.0, 10.0, image.shape[:2])[..., None]
    out = cv2.GaussianBlur(out, (0, 0), 0.8) + rng.normal(0.0, 3.0, out.shape)
    return np.clip(out, 0, 255).astype(np.uint8)


def offset_camera(cam: Camera, rng: np.random.Generator) -> Camera:
    """``cam`` turned by 1 degree about a random axis and moved 2 cm in a random direction
    (a camera set up by hand)."""
    axis = rng.normal(size=3)
    turn = rotation_exp(np.radians(1.0) * axis / np.linalg.norm(axis))
    shift = rng.normal(size=3)
    return cam.with_pose(turn @ cam.rotation, cam.position + 0.02 * shift / np.linalg.norm(shift))


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_the_fit_puts_the_floor_back_where_the_true_camera_sees_it(nominal: Renderer,
                                                                    seed: int) -> None:
    rng = np.random.default_rng(seed)
    cam = nominal.camera
    true_cam = offset_camera(cam, rng)
    image = other_look(nominal.with_camera(true_cam).background.image, rng)
    seams = seam_points(nominal.background.labels, nominal.background_depth, cam.K)
    fit = fit_edges(image, seams, cam.K)
    assert fit is not None
    fitted = apply_pose(cam, fit)
    before, after = floor_error_m(cam, true_cam), floor_error_m(fitted, true_cam)
    assert before > 0.02
    assert after < 0.4 * before and after < 0.015
    assert fit.score > fit.start_score
    assert np.all(np.abs(fit.translation) <= SEARCH_M + 1e-12)
    assert edge_score(image, seam_points(nominal.with_camera(fitted).background.labels,
                                         nominal.with_camera(fitted).background_depth, cam.K),
                      cam.K) > fit.start_score


def test_a_camera_already_right_stays_right(nominal: Renderer) -> None:
    rng = np.random.default_rng(7)
    cam = nominal.camera
    image = other_look(nominal.background.image, rng)
    fit = fit_edges(image, seam_points(nominal.background.labels, nominal.background_depth,
                                       cam.K), cam.K)
    assert fit is not None
    assert floor_error_m(apply_pose(cam, fit), cam) < 0.01
    assert fit.angle_deg < 0.3


def test_seams_lie_at_the_nearer_side_and_nothing_to_fit_is_none() -> None:
    K = np.diag([100.0, 100.0, 1.0])
    labels = np.zeros((6, 6), np.int32)
    labels[:, 3:] = 1
    depth = np.full((6, 6), 4.0)
    depth[:, 3:] = 2.0  # the right side is in front: its edge is the seam
    s = seam_points(labels, depth, K)
    assert len(s) == 6 and np.allclose(s.points[:, 2], 2.0)
    assert np.allclose(s.axes, [[1.0, 0.0]] * 6)
    depth[:] = np.inf  # nothing on either side
    assert len(seam_points(labels, depth, K)) == 0
    empty = SeamPoints(np.zeros((0, 3)), np.zeros((0, 2)))
    assert fit_edges(np.zeros((6, 6, 3), np.uint8), empty, K) is None
    with pytest.raises(ValueError, match="differ in size"):
        seam_points(labels, np.zeros((5, 6)), K)


def test_a_camera_far_off_the_scenario_is_found_by_fitting_clearly_better(
        nominal: Renderer) -> None:
    """6 degrees off: beyond the grid's 3, and far out on the prior on the turn, whose
    weight there is floored (PRIOR_FLOOR) -- a turn that fits clearly better wins, whether
    the compass walks there from the grid's edge or another alignment gives it as a start."""
    rng = np.random.default_rng(11)
    cam = nominal.camera
    w = np.radians(6.0) * np.array([0.6, -0.64, 0.48])
    true_cam = cam.with_pose(rotation_exp(w) @ cam.rotation, cam.position)
    image = other_look(nominal.with_camera(true_cam).background.image, rng)
    seams = seam_points(nominal.background.labels, nominal.background_depth, cam.K)
    found = np.r_[w + np.radians(0.3) * np.array([1.0, 0.0, 0.0]), 0.0, 0.0, 0.0]
    for starts in ((), (found,)):
        fit = fit_edges(image, seams, cam.K, starts=starts)
        assert fit is not None
        assert floor_error_m(apply_pose(cam, fit), true_cam) < 0.015


def _thick(scene: SceneSpec, thickness: float) -> SceneSpec:
    """``scene`` with each wall ``thickness`` thick behind its plane, a light top on it (the
    real walls; the model's are planes)."""
    cx, cy = np.mean([w.start for w in scene.walls] + [w.end for w in scene.walls], axis=0)
    boxes = []
    for w in scene.walls:
        (ax, ay), (bx, by) = w.start, w.end
        nx, ny = by - ay, -(bx - ax)
        norm = math.hypot(nx, ny)
        nx, ny = nx / norm, ny / norm
        if nx * (ax - cx) + ny * (ay - cy) < 0:
            nx, ny = -nx, -ny  # away from the room
        near, far = 0.002, thickness
        corners = [(ax + near * nx, ay + near * ny), (bx + near * nx, by + near * ny),
                   (bx + far * nx, by + far * ny), (ax + far * nx, ay + far * ny)]
        boxes.append(Obstacle(f"{w.name}-body", tuple(corners), height=w.height,
                              color=(225, 225, 220)))
    return dataclasses.replace(scene, obstacles=scene.obstacles + tuple(boxes))


@pytest.mark.parametrize("seed", [21, 22, 23])
def test_walls_thicker_than_the_models_planes_do_not_pull_the_camera_off(seed: int) -> None:
    """The model's walls are planes; the real ones are boxes 12 cm thick with a light top:
    each wall's real top edge against what lies beyond is behind the model's.  Such
    occluding contours weigh less (OCCLUDING_WEIGHT) than the seams where two surfaces
    meet, so the fit follows the walls' feet, the corners and the obstacles, and puts the
    floor back within 1.5 cm."""
    scenario = load_scenario(SCENARIO)
    model = Renderer(scenario.scene, scenario.camera)
    real = Renderer(_thick(scenario.scene, 0.12), scenario.camera)
    rng = np.random.default_rng(seed)
    cam = model.camera
    true_cam = offset_camera(cam, rng)
    image = other_look(real.with_camera(true_cam).background.image, rng)
    seams = seam_points(model.background.labels, model.background_depth, cam.K)
    assert 0.2 < float(np.mean(seams.weights < 1.0)) < 0.8  # both kinds of seam are there
    fit = fit_edges(image, seams, cam.K)
    assert fit is not None
    assert floor_error_m(apply_pose(cam, fit), true_cam) < 0.015
