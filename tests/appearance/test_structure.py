"""Aligning the camera to the scene's structure: the flat look, the obstacles' faces, and
the whole loop recovering a known turn of the camera from a real image whose surfaces
look otherwise than the scenario says."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from adapt.geometry import Camera, rotation_exp
from adapt.imagination import LABEL_OBSTACLE, Renderer
from adapt.mirror.structure import face_labels
from adapt.reality.surfaces import shift_textures
from adapt.vision.camera_correction import correct_rotation
from adapt.vision.homography import corner_error
from adapt.vision.registration import align_structure, flat_look, structure_homography

from .test_model import CAMERA, SCENE


def test_a_lighting_gradient_is_fitted_exactly_and_edges_are_kept_out() -> None:
    h, w = 120, 160
    labels = np.zeros((h, w), np.int32)
    labels[60:] = 1
    ys, xs = np.mgrid[0:h, 0:w]
    real = np.zeros((h, w, 3), np.uint8)
    real[..., 0] = 40 + 0.5 * xs  # blue rises to the right
    real[..., 1] = 100
    real[..., 2] = 200 - 0.4 * ys
    real[58:62] = 255  # a bright seam the margin leaves out
    flat = flat_look(real, labels, margin=4)
    body = (np.abs(ys - 60) > 3)
    assert np.abs(flat.astype(int) - real.astype(int))[body].max() <= 1


def test_a_small_region_takes_the_reference_colour_through_the_large_ones_map() -> None:
    h, w = 120, 160
    labels = np.zeros((h, w), np.int32)
    labels[60:] = 1
    labels[:30, 120:] = 2  # a large third region
    labels[70:80, 70:85] = 3  # small: 150 px, under 5% of the image
    reference = np.zeros((h, w, 3), np.uint8)
    for k, v in enumerate((50, 100, 150, 120)):
        reference[labels == k] = v
    real = cv2.convertScaleAbs(reference, alpha=1.2, beta=10)  # what the camera sees: brighter
    real[70:80, 70:85] = 0  # the small region's own pixels (say, another surface's)
    flat = flat_look(real, labels, margin=2, reference=reference)
    assert np.abs(flat[75, 77].astype(int) - (1.2 * 120 + 10)).max() <= 1
    own = flat_look(real, labels, margin=2)
    assert own[75, 77].max() == 0


def test_each_face_of_an_obstacle_gets_a_label_of_its_own() -> None:
    r = Renderer(SCENE, CAMERA)
    labels = r.background.labels
    split = face_labels(labels, r.surfaces, CAMERA)
    crate = labels == LABEL_OBSTACLE
    faces = {int(v) for v in np.unique(split[crate])}
    names = [r.surfaces[-(1 + v)].name for v in faces if v < 0]
    assert sorted(names) == ["crate/side0", "crate/top"]  # the front and the top are seen
    assert all(v < 0 for v in faces)
    assert np.array_equal(split[~crate], labels[~crate])


def test_a_blank_image_does_not_align() -> None:
    flat = np.full((120, 160, 3), 100, np.uint8)
    assert align_structure(flat, flat.copy(), (79.5, 59.5)) is None


def real_look(camera: Camera) -> np.ndarray:
    """The scene through ``camera`` with the surfaces' pattern moved and tinted: a look
    the scenario does not know."""
    r = Renderer(SCENE, camera)
    shift_textures(r, (0.23, 0.11), centre=(0.0, 0.0))
    image = r.render().image.astype(np.float32) * np.array([0.9, 1.0, 1.1], np.float32) + 8
    return np.clip(image, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("turn_deg", [(2.0, -1.5, 1.0), (-3.0, 2.0, -2.0)])
def test_the_structure_loop_finds_the_camera_the_texture_cannot(turn_deg) -> None:
    true = CAMERA.with_rotation(rotation_exp(np.radians(turn_deg)) @ CAMERA.rotation)
    real = real_look(true)

    def truth_error(cam: Camera) -> float:
        h = true.K @ true.rotation @ cam.rotation.T @ np.linalg.inv(cam.K)
        return corner_error(h, np.eye(3), real.shape)

    cam = CAMERA
    start = truth_error(cam)
    margin = 12.0
    for _ in range(10):
        bg = Renderer(SCENE, cam).background
        labels = face_labels(bg.labels, SCENE_SURFACES, cam)
        h = structure_homography(real, labels, (cam.cx, cam.cy), margin=margin,
                                 reference=bg.image if margin > 3 else None)
        assert h is not None
        err = corner_error(h, np.eye(3), real.shape)
        margin = float(np.clip(2 * err, 1.0, 12.0))
        if err < 0.2:
            break
        cam = correct_rotation(cam, h, gain=1.0)
    print(f"\nturn {turn_deg} deg: {start:.1f} px -> {truth_error(cam):.2f} px from the truth")
    assert start > 10 and truth_error(cam) < 0.5


SCENE_SURFACES = Renderer(SCENE, CAMERA).surfaces


def test_one_step_takes_most_of_a_turn() -> None:
    # a pure turn of the camera moves the image by K R K^-1; one step finds most of it
    true = CAMERA.with_rotation(rotation_exp([0.0, math.radians(0.8), 0.0]) @ CAMERA.rotation)
    real = real_look(true)
    bg = Renderer(SCENE, CAMERA).background
    h = structure_homography(real, face_labels(bg.labels, SCENE_SURFACES, CAMERA),
                             (CAMERA.cx, CAMERA.cy), margin=6, reference=bg.image)
    expected = true.K @ true.rotation @ CAMERA.rotation.T @ np.linalg.inv(CAMERA.K)
    assert h is not None
    assert corner_error(h, expected, real.shape) < 0.5 * corner_error(np.eye(3), expected, real.shape)
