"""The fast background (one warp per surface) against the exact ray-caster, and
appearance overrides.

Agreement bounds, with what they catch (measured on the bundled scene):

* labels: at least 99.5% of all pixels equal, and at least 99.95% of the pixels
  away from an edge (no 8-neighbour with another exact label).  The fast path
  rasterises each projected polygon, which may take or leave a pixel whose
  centre lies within a pixel of an edge; everywhere else both agree (measured:
  99.6-99.8% overall, 100% off the edges).
* colour: mean absolute difference at most 0.5 grey levels over the pixels
  whose labels agree (measured 0.0-0.22).  A texture misregistered by half a
  texel gives 1.4, by a quarter texel 0.58, one mip level too coarse or too fine
  about 5, so the bound catches each of these.  What remains comes from the mip
  level being chosen on an 8-pixel grid instead of per pixel.
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
import pytest

from adapt.errors import ImaginationError
from adapt.geometry import Camera, rotation_exp
from adapt.imagination import (
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_WALL,
    Appearance,
    Backdrop,
    Floor,
    Obstacle,
    Renderer,
    SceneSpec,
    Wall,
)
from adapt.scenario import Scenario


def edges(depth: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Pixels next to another label or another face: ``1/z`` is affine in pixel
    coordinates on a plane, so its second difference is zero inside a face."""
    inv = np.where(np.isfinite(depth), 1.0 / depth.astype(np.float64), 0.0)
    kink = np.zeros(labels.shape, bool)
    kink[1:-1, :] |= np.abs(inv[2:, :] - 2 * inv[1:-1, :] + inv[:-2, :]) > 1e-4
    kink[:, 1:-1] |= np.abs(inv[:, 2:] - 2 * inv[:, 1:-1] + inv[:, :-2]) > 1e-4
    edge = np.zeros(labels.shape, bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            edge |= np.roll(np.roll(labels, dy, 0), dx, 1) != labels
            edge |= np.roll(np.roll(kink, dy, 0), dx, 1)
    edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
    return edge


def agreement(fast: tuple, exact: tuple) -> tuple[float, float, float]:
    """(share of equal labels, share of equal labels off the edges, mean colour difference)."""
    same = fast[1] == exact[1]
    edge = edges(exact[2], exact[1])
    diff = np.abs(fast[0].astype(np.int16) - exact[0].astype(np.int16)).mean(axis=2)
    return float(same.mean()), float(same[~edge].mean()), float(diff[same].mean())


def cam(position: tuple[float, float, float], look_at: tuple[float, float, float],
        roll: float = 0.0, f: float = 525.0) -> Camera:
    return Camera.look_at(fx=f, fy=f, cx=319.5, cy=239.5, width=640, height=480,
                          position=position, look_at=look_at, roll_deg=roll)


POSES = {
    "bundled": None,
    "turned and rolled": ((0.0, -0.6, 0.6), (1.5, 3.0, 0.1), 9.0),
    "high, over the obstacle tops": ((0.5, 0.4, 1.6), (0.3, 2.6, 0.0), 0.0),
    "corner, grazing the floor": ((2.2, -0.8, 0.25), (-1.0, 2.5, 0.2), -4.0),
    "outside, the backs of the walls": ((0.0, -4.0, 1.5), (0.0, 1.0, 0.3), 0.0),
    "close to the crate (near clipping)": ((-1.0, 2.2, 0.3), (-1.0, 3.0, 0.1), 0.0),
}


@pytest.mark.parametrize("pose", list(POSES))
def test_fast_background_agrees_with_the_exact_ray_caster(bundled: Scenario, pose: str) -> None:
    spec = POSES[pose]
    camera = bundled.camera if spec is None else cam(*spec)
    backdrop = Backdrop(bundled.scene)
    fast = backdrop.render(camera)
    exact = backdrop.render(camera, exact=True)
    labels, off_edge, colour = agreement(fast, exact)
    assert labels >= 0.995 and off_edge >= 0.9995, (labels, off_edge)
    assert colour <= 0.5, colour
    # Depth (camera z) off the edges: float32 precision.
    both = ~edges(exact[2], exact[1]) & (fast[1] == exact[1]) & np.isfinite(exact[2])
    assert np.allclose(fast[2][both], exact[2][both], rtol=1e-4)
    assert np.isinf(fast[2][fast[1] == 0]).all()


def test_unbounded_floor_to_the_horizon() -> None:
    scene = SceneSpec(floor=Floor(texture="builtin:grass", tile=0.5),
                      walls=(Wall("w", (-3, 6), (3, 6), height=2.0, texture="builtin:brick"),))
    backdrop = Backdrop(scene)
    for camera in (cam((0, 0, 1.2), (0, 5, 1.0)), cam((0, 0, 1.2), (3, 5, 0.6), roll=12.0)):
        fast, exact = backdrop.render(camera), backdrop.render(camera, exact=True)
        labels, off_edge, colour = agreement(fast, exact)
        assert labels >= 0.995 and off_edge >= 0.9995 and colour <= 0.5
        assert (fast[1] == LABEL_FLOOR).mean() > 0.3 and (fast[1] == 0).any()


def test_a_camera_under_the_floor_sees_no_floor_and_a_wall_edge_on_is_skipped() -> None:
    scene = SceneSpec(walls=(Wall("w", (0, 2), (0, 4), height=1.0),))
    backdrop = Backdrop(scene)
    below = cam((0, -1, -0.5), (0, 3, 0.5))
    assert not (backdrop.render(below)[1] == LABEL_FLOOR).any()
    # Looking along the wall's own plane (x = 0): the wall is a line, not drawn.
    along = cam((0.0, -1.0, 0.5), (0.0, 3.0, 0.5))
    assert not (backdrop.render(along)[1] == LABEL_WALL).any()


def test_textures_are_prepared_once_per_scene_not_per_pose(
    bundled: Scenario, monkeypatch: pytest.MonkeyPatch
) -> None:
    import adapt.imagination.backdrop as backdrop_module

    renderer = Renderer(bundled.scene, bundled.camera)
    renderer.render()
    calls: list[object] = []
    original = backdrop_module._prepare
    monkeypatch.setattr(backdrop_module, "_prepare", lambda s: calls.append(s) or original(s))
    for k in range(5):
        turned = bundled.camera.with_rotation(rotation_exp([0.0, 0.01 * k, 0.0])
                                              @ bundled.camera.rotation)
        other = renderer.with_camera(turned)
        assert other.backdrop is renderer.backdrop
        other.render()
    assert calls == []


def test_the_background_is_cached_per_pose_and_appearance_version(bundled: Scenario) -> None:
    renderer = Renderer(bundled.scene, bundled.camera)
    first = renderer.background.image
    assert renderer.background.image is first
    renderer.set_appearance("north", np.zeros((60, 500, 3), np.uint8))
    second = renderer.background.image
    assert second is not first and not np.array_equal(second, first)
    renderer.clear_appearance("north")
    assert np.array_equal(renderer.background.image, first)


# -- appearance ------------------------------------------------------------------


def wall_scene() -> SceneSpec:
    return SceneSpec(floor=Floor(texture=None, color=(90, 90, 90), extent=(-3, -1, 3, 4)),
                     walls=(Wall("north", (-2, 3), (2, 3), height=1.0, texture="builtin:brick",
                                 tile=0.5),))


FRONT = cam((0.3, -0.5, 0.7), (0.0, 3.0, 0.45))


def test_an_appearance_pixel_lands_where_the_camera_projects_its_face_point() -> None:
    scene = wall_scene()
    renderer = Renderer(scene, FRONT)
    north = renderer.backdrop.surface("north")
    image = np.zeros((200, 800, 3), np.uint8)  # 200 px per metre over 4 m x 1 m
    for s, t in ((0.5, 0.25), (2.0, 0.5), (3.3, 0.8)):
        col, row = int(s * 200), int((1.0 - t) * 200)  # rows run down from the top
        image[row - 2:row + 3, col - 2:col + 3] = 255
        renderer.set_appearance("north", image)
        out = renderer.render()
        bright = (cv2.cvtColor(out.image, cv2.COLOR_BGR2GRAY) > 128) & (out.labels == LABEL_WALL)
        ys, xs = np.nonzero(bright)
        # The spot's centre (pixel centres at integer coordinates) is the projected point.
        centre_s = (col + 0.5) / 200
        centre_t = 1.0 - (row + 0.5) / 200
        expected = FRONT.project(np.array([north.point(centre_s, centre_t)]))[0]
        assert np.hypot(xs.mean() - expected[0], ys.mean() - expected[1]) < 0.5
        image[row - 2:row + 3, col - 2:col + 3] = 0


def test_back_projected_frame_round_trips_through_an_appearance(bundled: Scenario) -> None:
    """What issue 14 does: warp a camera frame onto each plane, set it as the
    surface's appearance, and the render reproduces the frame."""
    renderer = Renderer(bundled.scene, bundled.camera)
    frame = renderer.background
    for name, ppm in (("floor", 200), ("north", 250)):
        surface = renderer.backdrop.surface(name)
        e = surface.extent
        assert e is not None
        size = (int((e[2] - e[0]) * ppm), int((e[3] - e[1]) * ppm))
        h = surface.image_homography(bundled.camera, size)
        flags = cv2.WARP_INVERSE_MAP
        image = cv2.warpPerspective(frame.image, h, size, flags=flags | cv2.INTER_LINEAR)
        seen = cv2.warpPerspective(frame.labels.astype(np.float32), h, size,
                                   flags=flags | cv2.INTER_NEAREST, borderValue=-1) == surface.label
        renderer.set_appearance(name, image, cv2.erode(seen.view(np.uint8), np.ones((3, 3))))
    out = renderer.background
    assert np.array_equal(out.labels, frame.labels)
    diff = np.abs(out.image.astype(np.int16) - frame.image.astype(np.int16)).mean(axis=2)
    for label in (LABEL_FLOOR, LABEL_WALL):
        # Two bilinear resamplings blur the gravel a little; nothing is displaced.
        assert diff[frame.labels == label].mean() < 4.5
    # Another texture (the obstacles) is untouched.
    obstacle = frame.labels == LABEL_OBSTACLE
    assert diff[obstacle].max() == 0


def test_where_the_mask_is_invalid_the_scenario_texture_shows() -> None:
    scene = wall_scene()
    plain = Renderer(scene, FRONT).render()
    renderer = Renderer(scene, FRONT)
    image = np.full((400, 1600, 3), (0, 0, 255), np.uint8)  # 400 px per metre
    mask = np.zeros((400, 1600), bool)
    mask[:, 800:] = True  # the right half of the wall (s from 2 to 4 m)
    renderer.set_appearance("north", image, mask)
    out = renderer.render()
    north = renderer.backdrop.surface("north")
    wall = plain.labels == LABEL_WALL
    split = FRONT.project(np.array([north.point(2.0, 0.5)]))[0][0]
    cols = np.arange(640)[None, :]
    red = wall & (cols > split + 2)
    kept = wall & (cols < split - 2)
    assert (out.image[red] == (0, 0, 255)).all()
    # The scenario's brick, resampled at the appearance's resolution.
    diff = np.abs(out.image[kept].astype(np.int16) - plain.image[kept].astype(np.int16))
    assert diff.mean() < 3.0
    assert np.corrcoef(out.image[kept][:, 1], plain.image[kept][:, 1])[0, 1] > 0.95
    # Outside the wall nothing changed.
    assert np.array_equal(out.image[~wall], plain.image[~wall])


def test_fast_and_exact_agree_with_appearances(bundled: Scenario) -> None:
    backdrop = Backdrop(bundled.scene)
    rng = np.random.default_rng(4)
    pattern = cv2.resize(rng.integers(0, 256, (40, 50, 3), dtype=np.uint8), (500, 400),
                         interpolation=cv2.INTER_LINEAR)
    mask = np.zeros((400, 500), bool)
    mask[50:350, 100:450] = True
    backdrop.set_appearance("floor", pattern, mask)
    backdrop.set_appearance("crate/side0", np.full((40, 55, 3), 30, np.uint8))
    for spec in (None, POSES["turned and rolled"], POSES["corner, grazing the floor"]):
        camera = bundled.camera if spec is None else cam(*spec)
        labels, off_edge, colour = agreement(backdrop.render(camera),
                                             backdrop.render(camera, exact=True))
        assert labels >= 0.995 and off_edge >= 0.9995 and colour <= 0.5, (labels, colour)


def test_unbounded_floor_appearance_needs_an_extent_and_covers_only_it() -> None:
    scene = SceneSpec(floor=Floor(texture=None, color=(100, 100, 100)))
    backdrop = Backdrop(scene)
    with pytest.raises(ImaginationError, match="^extent: surface 'floor' is unbounded"):
        backdrop.set_appearance("floor", np.zeros((10, 10, 3), np.uint8))
    backdrop.set_appearance("floor", np.full((100, 100, 3), 250, np.uint8),
                            extent=(-0.5, 1.0, 0.5, 2.0))
    camera = cam((0, -1, 1.0), (0, 2, 0))
    image = backdrop.render(camera)[0]
    inside = camera.project(np.array([[0.0, 1.5, 0.0]]))[0].round().astype(int)
    outside = camera.project(np.array([[1.5, 1.5, 0.0]]))[0].round().astype(int)
    assert (image[inside[1], inside[0]] == 250).all()
    assert (image[outside[1], outside[0]] < 120).all()


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda b: b.set_appearance("nowhere", np.zeros((4, 4, 3), np.uint8)), "^surface: no surface"),
        (lambda b: b.set_appearance("north", np.zeros((4, 4), np.uint8)), "^image: expected a BGR"),
        (lambda b: b.set_appearance("north", np.zeros((4, 4, 3), np.float32)), "^image: expected"),
        (lambda b: b.set_appearance("north", np.zeros((4, 4, 3), np.uint8), np.ones((3, 4))),
         "^mask: expected shape"),
        (lambda b: b.set_appearance("north", np.zeros((4, 4, 3), np.uint8), extent=(1, 0, 0, 1)),
         "^extent: expected"),
        (lambda b: b.set_appearance("north", np.zeros((4, 4, 3), np.uint8),
                                    extent=(0, 0, 1e300, 1)), "^extent: expected values within"),
        (lambda b: b.set_appearance("north", np.zeros((1, 9000, 3), np.uint8)), "^image: expected 1 to"),
        (lambda b: b.clear_appearance("nowhere"), "^surface: no surface"),
    ],
)
def test_bad_appearances_are_errors_naming_the_field(call: object, message: str) -> None:
    backdrop = Backdrop(wall_scene())
    with pytest.raises(ImaginationError, match=message):
        call(backdrop)  # type: ignore[operator]
    assert backdrop.appearances == {}


def test_appearance_arrays_are_copies_and_read_only() -> None:
    image = np.zeros((10, 40, 3), np.uint8)
    mask = np.ones((10, 40), np.uint8)
    look = Appearance(image, mask, (0, 0, 4, 1))
    image[:] = 9
    mask[:] = 0
    assert look.image.max() == 0 and look.mask.all()
    assert not look.image.flags.writeable and not look.mask.flags.writeable
    backdrop = Backdrop(wall_scene())
    assert backdrop.set_appearance("north", look) is look
    with pytest.raises(ImaginationError, match="carries its own mask"):
        backdrop.set_appearance("north", look, mask)


def test_an_obstacle_face_appearance_and_an_all_invalid_mask() -> None:
    box = Obstacle("box", ((-0.3, 1.0), (0.3, 1.0), (0.3, 1.4), (-0.3, 1.4)), height=0.5,
                   color=(10, 200, 10))
    scene = replace(wall_scene(), obstacles=(box,))
    renderer = Renderer(scene, FRONT)
    plain = renderer.render()
    renderer.set_appearance("box/side0", np.zeros((50, 60, 3), np.uint8), np.zeros((50, 60)))
    assert np.array_equal(renderer.render().image, plain.image)  # nothing valid: no change
    renderer.set_appearance("box/side0", np.zeros((50, 60, 3), np.uint8))
    front = plain.labels == LABEL_OBSTACLE
    out = renderer.render()
    assert (out.image[front] == 0).mean() > 0.9  # side0 faces the camera (y = 1.0 side)


@pytest.mark.parametrize("shape", [(4, 1), (1, 4), (2, 2), (1, 1), (5, 3)])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int32])
def test_setting_a_masked_region_of_any_small_shape(shape: tuple[int, int], dtype: type) -> None:
    # OpenCV takes a 4x1 array for a scalar: a label region of that shape used to raise
    from adapt.imagination.backdrop import _set

    roi = np.zeros(shape, dtype)
    mask = np.zeros(shape, np.uint8)
    mask[0, 0] = 255
    _set(roi, 7, mask)
    assert roi[0, 0] == 7 and int(roi.sum()) == 7
