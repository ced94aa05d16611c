"""MMD at any resolution: parameters relative to the image, a bounded working
resolution, and results in the input's pixels.

The scene is the bundled scenario rendered by the imagination renderer at
several resolutions (the camera's intrinsics and size scaled together): the
real view has the ball (1.5 s into the run), a camera turned by about 1.5
degrees and moved 1 cm, and sensor noise; the synthetic view is the nominal
camera without the ball.  With pixel parameters fixed at their 640x480 values
this gave 1, 1, 45, 232 and 540 regions at 320x240, 640x480, 1280x960,
1920x1440 and 2560x1920 (and a ball half its size at 320x240).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.errors import VisionError
from adapt.geometry import Camera, rotation_exp
from adapt.vision.homography import corner_error
from adapt.vision.mmd import mmd
from adapt.vision.regions import find_regions
from adapt.vision.scale import MAX_WORK_PIXELS_LIMIT, WorkingFrame, image_scale, working_frame

from . import scenes

SCENARIO = Path(__file__).resolve().parents[2] / "scenarios" / "room.yaml"


def scaled_camera(cam: Camera, k: float) -> Camera:
    """The same camera with an image ``k`` times larger (pixel centres kept)."""
    return replace(cam, fx=cam.fx * k, fy=cam.fy * k, cx=(cam.cx + 0.5) * k - 0.5,
                   cy=(cam.cy + 0.5) * k - 0.5, width=round(cam.width * k), height=round(cam.height * k))


@pytest.fixture(scope="module")
def renders():
    from adapt.imagination import Renderer, World
    from adapt.scenario import load_scenario

    sc = load_scenario(SCENARIO)
    world = World(sc.scene, seed=sc.seed)
    world.run(1.5)
    state = world.snapshot()
    empty = replace(sc.scene, balls=())
    out = {}
    for k in (0.5, 1.0, 2.0):
        cam = scaled_camera(sc.camera, k)
        real_cam = cam.with_pose(rotation_exp([0.01, -0.015, 0.02]) @ cam.rotation, cam.position + [0.01, 0, 0])
        real = Renderer(sc.scene, real_cam).render(state).image
        real = scenes.sensor_noise(real, np.random.default_rng(0), 3.0)
        out[k] = (real, Renderer(empty, cam).render().image)
    return out


def test_the_same_scene_gives_the_same_regions_at_every_resolution(renders):
    found = {}
    for k, (real, synthetic) in renders.items():
        r = mmd(real, synthetic)
        assert r.aligned
        regions = r.regions()
        assert len(regions) == 1, (k, [x.bbox for x in regions])
        found[k] = regions[0]
    ref = found[1.0]
    for k, region in found.items():
        # bounding box and area, scaled back to 640x480: within 3 pixels of the coarser
        # image (at 320x240 the ball's soft contact shadow may add a pixel or two)
        box = np.array(region.bbox) / k
        assert np.abs(box - ref.bbox).max() <= 3.0 * max(1.0, 1.0 / k), (k, region.bbox, ref.bbox)
        assert region.area / k**2 == pytest.approx(ref.area, rel=0.08)
        assert np.allclose(np.array(region.centroid) + 0.5, (np.array(ref.centroid) + 0.5) * k, atol=3 * k)


def test_scaled_parameters_at_full_resolution_find_the_same_region(renders):
    # 1280x960 analysed as it is (no reduction): the parameters themselves scale
    real, synthetic = renders[2.0]
    full = mmd(real, synthetic, max_pixels=1280 * 960)
    assert not full.frame.reduces and full.difference.shape == (960, 1280)
    (region,) = full.regions()
    (ref,) = mmd(*renders[1.0]).regions()
    assert np.abs(np.array(region.bbox) / 2 - ref.bbox).max() <= 3.0
    assert region.area / 4 == pytest.approx(ref.area, rel=0.08)
    # the defaults are the 640x480 values scaled: an explicit value is taken as given
    default = find_regions(full.difference)
    explicit = find_regions(full.difference, min_area=4 * 40, open_size=6)
    assert [r.bbox for r in default] == [r.bbox for r in explicit] == [region.bbox]
    assert find_regions(full.difference, min_area=region.area + 1) == ()


def test_a_large_pair_is_analysed_at_the_working_resolution_and_mapped_back():
    # 8000x6000: reduced to 640x480 at once (the old code took 124 s and 11.4 GB)
    world = cv2.resize(scenes.world("gravel"), (8400, 6300), interpolation=cv2.INTER_LINEAR)
    synthetic = world[150:6150, 200:8200]
    real = world[100:6100, 275:8275].copy()  # synthetic -> real: (-75, +50) px
    yy, xx = np.ogrid[:6000, :8000]
    ball = (xx - 5000) ** 2 + (yy - 2000) ** 2 <= 600**2
    real[ball] = 255
    r = mmd(real, synthetic)
    assert r.frame.shape == (480, 640) and r.difference.shape == (480, 640)
    shift = np.array([[1, 0, -75.0], [0, 1, 50.0], [0, 0, 1]])
    assert corner_error(r.homography, shift, real.shape) < 0.3 * 12.5
    # matches are in input pixels too
    inl = r.alignment.inliers
    p = np.c_[r.matches.synthetic_points[inl], np.ones(inl.sum())] @ shift.T
    assert np.median(np.linalg.norm(p[:, :2] - r.matches.real_points[inl], axis=1)) < 12.5
    (region,) = r.regions()
    x, y, w, h = region.bbox
    assert abs(x - 4400) < 30 and abs(y - 1400) < 30 and abs(w - 1200) < 60 and abs(h - 1200) < 60
    assert region.area == pytest.approx(ball.sum(), rel=0.05)
    assert region.to_mask(real.shape)[2000, 5000]


def test_working_frame_limits():
    assert working_frame((480, 640)) == WorkingFrame((480, 640), (480, 640))
    assert working_frame((6000, 8000)).shape == (480, 640)
    with pytest.raises(VisionError, match="at least 32 pixels on each side"):
        working_frame((40, 20000))
    with pytest.raises(VisionError, match="working resolution must have"):
        working_frame((480, 640), MAX_WORK_PIXELS_LIMIT + 1)
    with pytest.raises(VisionError, match="working resolution must have"):
        mmd(np.zeros((64, 64), np.uint8), np.zeros((64, 64), np.uint8), max_pixels=10)


@settings(max_examples=40, deadline=None)
@given(
    h=st.integers(32, 9000),
    w=st.integers(32, 9000),
    x=st.floats(-10, 10),
    y=st.floats(-10, 10),
)
def test_working_frame_maps_are_inverse_and_consistent(h, w, x, y):
    if w > 200 * h or h > 200 * w:
        return
    try:
        f = working_frame((h, w))
    except VisionError:
        return
    assert f.shape[0] * f.shape[1] <= max(h * w if not f.reduces else 0, 640 * 480)
    assert image_scale(f.shape) <= 1.0 + 1e-9 or not f.reduces
    p = np.array([[x * f.shape[1], y * f.shape[0]]])
    assert np.allclose(f.to_work(f.to_input(p)), p)
    # a homography between working images maps input points like the point maps do
    hw = np.array([[1.01, 0.02, 3.0], [-0.01, 0.99, -2.0], [1e-5, -2e-5, 1.0]])
    hi = f.homography_to_input(hw)
    q = np.c_[p, 1.0] @ hw.T
    q = q[:, :2] / q[:, 2:]
    pi = np.c_[f.to_input(p), 1.0] @ hi.T
    assert np.allclose(pi[:, :2] / pi[:, 2:], f.to_input(q), atol=1e-6 * max(h, w))
    # and back: the working images' homography again
    assert np.allclose(f.homography_to_work(hi), hw, rtol=1e-6, atol=1e-9)
