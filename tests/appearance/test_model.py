"""The appearance model: back-projection round trips with known looks, masks, the
accumulation's closed form, the sky by direction, saving and loading, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.errors import AppearanceError
from adapt.geometry import Camera, rotation_exp
from adapt.imagination import (
    LABEL_BALL,
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_SKY,
    LABEL_WALL,
    Floor,
    Obstacle,
    Renderer,
    SceneSpec,
    Wall,
)
from adapt.mirror import Mirror
from adapt.mirror.appearance import SKY_FACES, AppearanceModel

SCENE = SceneSpec(
    floor=Floor(texture="builtin:gravel", tile=0.8, extent=(-2.5, -1.0, 2.5, 3.0)),
    walls=(Wall("north", (-2.5, 3.0), (2.5, 3.0), height=1.0, texture="builtin:brick", tile=0.6),),
    obstacles=(Obstacle("crate", ((-0.6, 1.6), (0.0, 1.6), (0.0, 2.1), (-0.6, 2.1)), height=0.5,
                        color=(150, 110, 60)),),
)
CAMERA = Camera.look_at(fx=262.5, fy=262.5, cx=159.5, cy=119.5, width=320, height=240,
                        position=(0.0, -0.6, 0.6), look_at=(0.0, 3.0, 0.4))


def pattern(shape: tuple[int, int], seed: int) -> np.ndarray:
    """A smooth random BGR image (detail a few pixels wide)."""
    rng = np.random.default_rng(seed)
    noise = rng.integers(0, 256, (*shape, 3), dtype=np.uint8)
    return np.asarray(cv2.GaussianBlur(noise, (0, 0), 3.0) * 3 - 200, np.uint8).clip(0, 255)


def reality(image: np.ndarray) -> Renderer:
    """The scene whose north wall shows ``image`` (over the whole wall)."""
    r = Renderer(SCENE, CAMERA)
    r.set_appearance("north", image, aligned=True)
    return r


def texel_frame_pixels(model_texture, surface, camera: Camera) -> np.ndarray:
    """Frame pixel (x, y) of every texel centre of a learned texture, (H, W, 2)."""
    h, w = model_texture.mask.shape
    hom = surface.image_homography(camera, (w, h), model_texture.extent)
    ys, xs = np.mgrid[0:h, 0:w]
    p = np.stack([xs.ravel(), ys.ravel(), np.ones(xs.size)]) .T @ hom.T
    return (p[:, :2] / p[:, 2:]).reshape(h, w, 2)


def test_a_surface_learns_the_look_the_camera_saw() -> None:
    truth = pattern((100, 500), 1)
    real = reality(truth).render()
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    labels = Renderer(SCENE, CAMERA).render().labels
    learned = model.learn(real.image, CAMERA, labels)
    assert {"floor", "north", "crate/side0", "crate/top"} <= set(learned.surfaces)
    t = model.texture("north")
    assert t is not None and t.extent == (0.0, 0.0, 5.0, 1.0)
    expected = cv2.resize(truth, t.mask.shape[::-1], interpolation=cv2.INTER_AREA)
    inner = cv2.erode(t.mask.view(np.uint8), np.ones((5, 5), np.uint8)) > 0
    err = np.abs(t.image.astype(int) - expected.astype(int))[inner]
    assert inner.sum() > 0.3 * inner.size and err.mean() < 4.0, err.mean()


def test_only_what_the_camera_sees_of_a_surface_is_learned() -> None:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    model = AppearanceModel(renderer.surfaces)
    model.learn(frame.image, CAMERA, frame.labels)
    t = model.texture("north")
    assert t is not None
    north = renderer.backdrop.surface("north")
    px = texel_frame_pixels(t, north, CAMERA)
    xi, yi = np.round(px[..., 0]).astype(int), np.round(px[..., 1]).astype(int)
    inside = (xi >= 2) & (xi < 318) & (yi >= 2) & (yi < 238)
    on = np.zeros_like(inside)
    on[inside] = frame.labels[yi[inside], xi[inside]] == LABEL_WALL
    behind = np.zeros_like(inside)
    behind[inside] = frame.labels[yi[inside], xi[inside]] == LABEL_OBSTACLE
    assert behind.sum() > 100  # the crate hides part of the wall
    assert not t.mask[behind].any()  # never learned from the crate's pixels
    far_out = (px[..., 0] < -3) | (px[..., 0] > 322) | (px[..., 1] < -3) | (px[..., 1] > 242)
    assert far_out.sum() > 100 and not t.mask[far_out].any()  # the frame's edge: 2 px beyond
    assert t.mask[on].mean() > 0.98


def test_an_excluded_part_of_the_frame_is_not_learned() -> None:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    exclude = np.zeros(frame.labels.shape, bool)
    exclude[80:110, 20:80] = True  # a part of the wall
    model = AppearanceModel(renderer.surfaces)
    model.learn(frame.image, CAMERA, frame.labels, exclude=exclude)
    t = model.texture("north")
    assert t is not None
    px = texel_frame_pixels(t, renderer.backdrop.surface("north"), CAMERA)
    hidden = (px[..., 0] > 21) & (px[..., 0] < 78) & (px[..., 1] > 81) & (px[..., 1] < 108)
    assert hidden.sum() > 500 and not t.mask[hidden].any()


def test_a_slow_drift_is_absorbed_at_the_rate_and_a_jump_is_not() -> None:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    model = AppearanceModel(renderer.surfaces)
    for _ in range(10):  # the first passes average; from the tenth on, the rate holds
        model.learn(frame.image, CAMERA, frame.labels, rate=0.1, gate=40)
    t0 = model.texture("north")
    assert t0 is not None
    inner = cv2.erode(t0.mask.view(np.uint8), np.ones((5, 5), np.uint8)) > 0
    inner &= (t0.image.astype(int) < 230).all(axis=2)  # room to brighten without clipping
    base = t0.image.astype(float)
    brighter = cv2.add(frame.image, 6)
    for n in range(1, 8):
        model.learn(brighter, CAMERA, frame.labels, rate=0.1, gate=40)
        moved = (model.texture("north").image.astype(float) - base)[inner].mean()  # type: ignore[union-attr]
        assert abs(moved - 6 * (1 - 0.9 ** n)) < 0.6, (n, moved)
    before = model.texture("north").image.copy()  # type: ignore[union-attr]
    jump = cv2.add(frame.image, 60)  # beyond the gate: not lighting, not learned
    model.learn(jump, CAMERA, frame.labels, rate=0.1, gate=40)
    after = model.texture("north").image  # type: ignore[union-attr]
    assert np.abs(after.astype(int) - before.astype(int))[inner].max() <= 1


def sky_colour(camera: Camera) -> np.ndarray:
    """A sky whose colour depends on the viewing direction only (azimuth and elevation)."""
    ys, xs = np.mgrid[0:camera.height, 0:camera.width]
    rays = camera.pixel_ray(np.c_[xs.ravel(), ys.ravel()])
    az = np.arctan2(rays[:, 1], rays[:, 0])
    el = np.arcsin(np.clip(rays[:, 2], -1, 1))
    b = 128 + 100 * np.sin(6 * az)
    g = 128 + 100 * np.cos(9 * az + 3 * el)
    r = 60 + 300 * el
    return np.clip(np.c_[b, g, r], 0, 255).astype(np.uint8).reshape(camera.height, camera.width, 3)


def test_the_sky_is_learned_by_direction() -> None:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    real = frame.image.copy()
    sky = frame.labels == LABEL_SKY
    real[sky] = sky_colour(CAMERA)[sky]
    model = AppearanceModel(renderer.surfaces)
    learned = model.learn(real, CAMERA, frame.labels)
    assert set(learned.surfaces) & set(SKY_FACES) == {"sky/+y"}
    # turned by 4 degrees: the directions seen before look as they did
    turned = CAMERA.with_rotation(rotation_exp([0.01, 0.0, math.radians(4)]) @ CAMERA.rotation)
    view = renderer.with_camera(turned).render()
    out = model.composite(view.image, view.labels, turned)
    new_sky = view.labels == LABEL_SKY
    seen_before = new_sky & (out != view.image).any(axis=2)
    assert seen_before.sum() > 0.9 * new_sky.sum()  # a few degrees turned: most was seen
    err = np.abs(out.astype(int) - sky_colour(turned).astype(int))[seen_before]
    assert np.median(err) <= 1 and np.percentile(err, 99) <= 4
    # never outside the sky
    assert np.array_equal(out[~new_sky], view.image[~new_sky])


def test_the_sky_round_a_room_seen_from_above_is_learned_on_every_face_it_shows() -> None:
    # a camera outside a room, high and looking down over it: the sky (what the scene
    # does not model: the ground beyond) surrounds the floor, on four faces of the sky's
    # cube.  The frame's bottom corners look behind the +y face; its top corners alone
    # on it once left it a sliver of a few rows, and the rest of it never learned.
    scene = SceneSpec(floor=Floor(texture="builtin:gravel", tile=0.8,
                                  extent=(-1.7, -1.4, 1.7, 1.4)),
                      walls=(Wall("north", (-1.7, 1.4), (1.7, 1.4), height=0.8,
                                  texture="builtin:brick", tile=0.6),))
    cam = Camera.look_at(fx=145.6, fy=145.6, cx=159.5, cy=119.5, width=320, height=240,
                         position=(-0.2, -2.0, 2.5), look_at=(-0.2, -0.4, 0.0))
    renderer = Renderer(scene, cam)
    frame = renderer.render()
    sky = frame.labels == LABEL_SKY
    real = frame.image.copy()
    real[sky] = sky_colour(cam)[sky]
    model = AppearanceModel(renderer.surfaces)
    learned = model.learn(real, cam, frame.labels)
    assert {"sky/+y", "sky/+x", "sky/-x", "sky/-z"} <= set(learned.surfaces)
    out = model.composite(frame.image, frame.labels, cam)
    err = np.abs(out.astype(int) - sky_colour(cam).astype(int)).max(axis=2)[sky]
    assert sky.mean() > 0.3
    assert (err <= 12).mean() > 0.98, (err <= 12).mean()


def test_an_unbounded_floor_grows_as_more_of_it_is_seen() -> None:
    scene = SceneSpec(floor=Floor(texture="builtin:gravel", tile=0.8))
    first = Camera.look_at(fx=200, fy=200, cx=79.5, cy=59.5, width=160, height=120,
                           position=(0, 0, 1.0), look_at=(0, 2, 0))
    second = Camera.look_at(fx=200, fy=200, cx=79.5, cy=59.5, width=160, height=120,
                            position=(6, 0, 1.0), look_at=(6, 2, 0))
    renderer = Renderer(scene, first)
    model = AppearanceModel(renderer.surfaces, sky=False)
    a = renderer.render()
    model.learn(a.image, first, a.labels)
    e1 = model.texture("floor").extent  # type: ignore[union-attr]
    ppm1 = model.texture("floor").pixels_per_metre[0]  # type: ignore[union-attr]
    probe = np.array([[0.2, 1.5, 0.0]])  # a floor point the first camera saw
    value = _texel(model, probe)
    b = renderer.with_camera(second).render()
    model.learn(b.image, second, b.labels)
    e2 = model.texture("floor").extent  # type: ignore[union-attr]
    assert e2[0] <= e1[0] and e2[2] > e1[2] + 5.0 and e2[2] >= 6.5
    # what was learned stayed where it was (at half the resolution: 2x2 texels averaged)
    assert model.texture("floor").pixels_per_metre[0] < 0.6 * ppm1  # type: ignore[union-attr]
    assert np.abs(_texel(model, probe).astype(int) - value.astype(int)).max() <= 12


def _texel(model: AppearanceModel, world: np.ndarray) -> np.ndarray:
    t = model.texture("floor")
    assert t is not None
    h, w = t.mask.shape
    e = t.extent
    col = int((world[0, 0] - e[0]) / (e[2] - e[0]) * w)
    row = int((e[3] - world[0, 1]) / (e[3] - e[1]) * h)
    assert t.mask[row, col]
    return t.image[row, col].copy()


def test_the_mirror_renders_what_it_learned(tmp_path: Path) -> None:
    truth = pattern((100, 500), 2)
    real = reality(truth).render()
    mirror = Mirror(SCENE, CAMERA)
    mirror.learn_appearance(real.image, mirror.render().labels)
    again = mirror.render()
    inner = cv2.erode((again.labels == LABEL_WALL).astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
    assert np.abs(again.image.astype(int) - real.image.astype(int))[inner].mean() < 3.0
    assert np.array_equal(mirror.background.image[inner], again.image[inner])
    # a new camera pose shows the same look (the backdrop is shared)
    mirror.set_camera(CAMERA.with_rotation(rotation_exp([0.0, 0.003, 0.0]) @ CAMERA.rotation))
    assert mirror.appearance.learned == mirror.appearance.learned
    moved = mirror.render()
    assert not np.array_equal(moved.image, again.image)


def test_saved_looks_load_into_another_model_and_render_alike(tmp_path: Path) -> None:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    real = frame.image.copy()
    real[frame.labels == LABEL_SKY] = (200, 120, 40)
    model = AppearanceModel(renderer.surfaces)
    model.learn(real, CAMERA, frame.labels)
    written = model.save(tmp_path / "look")
    index = json.loads((tmp_path / "look" / "index.json").read_text())
    assert index["format"] == "adapt-appearance" and written[-1].name == "index.json"
    names = [e["name"] for e in index["surfaces"]]
    assert names == list(model.learned) and "sky/+y" in names and "crate/side0" in names
    other = AppearanceModel(renderer.surfaces)
    assert other.load(tmp_path / "look") == model.learned
    for name in model.learned:
        a, b = model.texture(name), other.texture(name)
        assert a is not None and b is not None and a.extent == b.extent
        assert np.array_equal(a.mask, b.mask) and np.array_equal(a.image, b.image)
    r1, r2 = Renderer(SCENE, CAMERA), Renderer(SCENE, CAMERA)
    model.apply(r1)
    other.apply(r2)
    i1 = model.composite(r1.render().image, frame.labels, CAMERA)
    i2 = other.composite(r2.render().image, frame.labels, CAMERA)
    assert np.array_equal(i1, i2)


def _saved(tmp_path: Path) -> Path:
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    model = AppearanceModel(renderer.surfaces)
    model.learn(frame.image, CAMERA, frame.labels)
    model.save(tmp_path / "look")
    return tmp_path / "look"


def _edit_index(folder: Path, change) -> None:
    path = folder / "index.json"
    index = json.loads(path.read_text())
    change(index)
    path.write_text(json.dumps(index))


@pytest.mark.parametrize("break_it, message", [
    (lambda f: (f / "index.json").unlink(), "no such file"),
    (lambda f: (f / "index.json").write_text("{not json"), "cannot read it as JSON"),
    (lambda f: _edit_index(f, lambda i: i.update(format="other")), "not an appearance index"),
    (lambda f: _edit_index(f, lambda i: i.update(version=9)), "version 9"),
    (lambda f: _edit_index(f, lambda i: i.update(surfaces={})), '"surfaces" must be a list'),
    (lambda f: _edit_index(f, lambda i: i["surfaces"][0].update(name="south")),
     "the scene has no surface 'south'"),
    (lambda f: _edit_index(f, lambda i: i["surfaces"].append(i["surfaces"][0])), "listed twice"),
    (lambda f: _edit_index(f, lambda i: i["surfaces"][0].update(extent=[0, 0, -1, 1])),
     "extent must be"),
    (lambda f: _edit_index(f, lambda i: i["surfaces"][0].update(image="../x.png")),
     "expected a file name in the folder"),
    (lambda f: (f / "floor.png").unlink(), "cannot read"),
    (lambda f: (f / "floor.png").write_bytes(b"not a png"), "is not an 8-bit image"),
    (lambda f: cv2.imwrite(str(f / "floor.mask.png"), np.zeros((5, 7), np.uint8)),
     "the mask is 7x5"),
    (lambda f: _edit_index(f, lambda i: i["surfaces"][-1].update(extent=[0, 0, 1, 1])),
     "a sky face is"),
])
def test_a_bad_folder_is_refused_and_nothing_changes(tmp_path: Path, break_it, message) -> None:
    folder = _saved(tmp_path)
    break_it(folder)
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    with pytest.raises(AppearanceError, match=message.replace("(", r"\(").replace(")", r"\)")):
        model.load(folder)
    assert model.learned == ()


def test_a_save_that_cannot_be_written_says_where(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("x")
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    with pytest.raises(AppearanceError, match="cannot make the appearance folder"):
        model.save(tmp_path / "file" / "look")


@pytest.mark.parametrize("image, labels, kw, message", [
    (np.zeros((240, 320), np.uint8), None, {}, "expected a BGR uint8 image"),
    (np.zeros((240, 320, 3), np.float32), None, {}, "expected a BGR uint8 image"),
    (np.zeros((120, 160, 3), np.uint8), None, {}, "expected the camera's 320x240"),
    (None, np.zeros((10, 10), np.int32), {}, "labels: expected shape"),
    (None, None, {"exclude": np.zeros((10, 10), bool)}, "exclude: expected shape"),
    (None, None, {"rate": 0.0}, "rate: expected a fraction"),
])
def test_bad_arguments_to_learn(image, labels, kw, message) -> None:
    frame = Renderer(SCENE, CAMERA).render()
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    with pytest.raises(AppearanceError, match=message):
        model.learn(frame.image if image is None else image, CAMERA,
                    frame.labels if labels is None else labels, **kw)
    assert model.learned == ()


def test_relearn_replaces_a_wrong_texel_past_the_gate_and_nothing_else() -> None:
    # a ghost: the look learned with something in it (a red patch on the wall) that has left
    renderer = Renderer(SCENE, CAMERA)
    frame = renderer.render()
    inner = cv2.erode((frame.labels == LABEL_WALL).view(np.uint8), np.ones((41, 41), np.uint8),
                      borderType=cv2.BORDER_CONSTANT, borderValue=0)
    inside = np.argwhere(inner > 0)
    y, x = (int(v) for v in inside[len(inside) // 2])  # amid 40 px of wall each way
    patch = (slice(y - 8, y + 8), slice(x - 8, x + 8))
    wrong = frame.image.copy()
    wrong[y - 12:y + 12, x - 12:x + 12] = (30, 30, 230)
    model = AppearanceModel(renderer.surfaces)
    model.learn(wrong, CAMERA, frame.labels)
    model.learn(frame.image, CAMERA, frame.labels, rate=0.1, gate=40)  # gated: stays wrong
    mine = Renderer(SCENE, CAMERA)
    model.apply(mine)
    assert np.abs(mine.render().image[patch].astype(int) - (30, 30, 230)).max() < 30
    before = model.texture("north").image.copy()  # type: ignore[union-attr]
    spot = np.zeros(frame.labels.shape, bool)
    spot[y - 16:y + 16, x - 16:x + 16] = True
    model.learn(frame.image, CAMERA, frame.labels, rate=0.1, gate=40, relearn=spot)
    model.apply(mine)
    repaired = mine.render().image[patch].astype(int)
    assert np.abs(repaired - frame.image[patch].astype(int)).mean() < 6
    # elsewhere the gate and the rate hold as before: what was learned right barely moves
    after = model.texture("north").image  # type: ignore[union-attr]
    seen = model.texture("north").mask  # type: ignore[union-attr]
    far = seen.copy()
    far[:, far.shape[1] // 4:] = False
    assert far.any() and np.abs(after.astype(int) - before.astype(int))[far].max() <= 2


def test_unseen_is_where_the_look_was_never_learned_and_only_there() -> None:
    real = reality(pattern((100, 500), 4)).render()
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    frame = Renderer(SCENE, CAMERA).render()
    labels = frame.labels
    surfaces = (labels >= LABEL_FLOOR) & (labels < LABEL_BALL)  # floor, walls and obstacles
    assert surfaces.sum() > 0.5 * labels.size
    assert np.array_equal(model.unseen(CAMERA, labels), surfaces)  # nothing learned yet
    # something stood on the floor when the look was learned (its box a margin inside it)
    hidden = np.zeros(labels.shape, bool)
    hidden[180:215, 120:200] = True
    model.learn(real.image, CAMERA, labels, exclude=hidden)
    unseen = model.unseen(CAMERA, labels)
    inner = np.zeros_like(hidden)
    inner[183:212, 123:197] = True  # a texel's width inside the box
    assert unseen[inner].all()
    outer = cv2.dilate(hidden.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    lab = labels.astype(np.float32)
    seams = cv2.dilate(lab, np.ones((3, 3))) != cv2.erode(lab, np.ones((3, 3)))
    # everything else the camera saw is learned (but at the pixel where two surfaces meet)
    assert not unseen[~outer & ~seams & surfaces].any()
    assert not unseen[labels == LABEL_SKY].any()
    # a box gives the same pixels as the whole image, cut to it
    box = (100, 150, 130, 80)
    assert np.array_equal(model.unseen(CAMERA, labels, box), unseen[150:230, 100:230])
    # once seen uncovered, it is learned
    model.learn(real.image, CAMERA, labels)
    assert not model.unseen(CAMERA, labels)[~seams].any()


def test_hidden_is_what_a_pass_saw_covered_and_a_face_never_in_view_is_not() -> None:
    real = reality(pattern((100, 500), 5)).render()
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    labels = Renderer(SCENE, CAMERA).render().labels
    ball = np.zeros(labels.shape, bool)
    ball[180:215, 120:200] = True  # a ball rolled there while the look was learned
    lab = labels.astype(np.float32)
    seams = cv2.dilate(lab, np.ones((3, 3))) != cv2.erode(lab, np.ones((3, 3)))
    model.learn(real.image, CAMERA, labels, covered=ball)
    hidden = model.hidden(CAMERA, labels)
    inner = np.zeros_like(ball)
    inner[183:212, 123:197] = True
    assert hidden[inner].all() and not hidden[~ball & ~seams].any()
    assert np.array_equal(model.hidden(CAMERA, labels, (100, 150, 130, 80)), hidden[150:230, 100:230])
    # a camera turned away sees surfaces no pass saw: unseen there, but not hidden
    turned = CAMERA.with_pose(rotation_exp([0.0, math.radians(25), 0.0]) @ CAMERA.rotation,
                              CAMERA.position)
    other = Renderer(SCENE, turned).render().labels
    unseen, left = model.unseen(turned, other), model.hidden(turned, other)
    assert unseen.sum() > 1000 and not (left & ~unseen).any() and left.sum() < 0.5 * unseen.sum()
    # learned once uncovered
    model.learn(real.image, CAMERA, labels)
    assert not model.hidden(CAMERA, labels)[~seams].any()


def test_new_only_learns_what_was_never_learned_and_leaves_the_rest() -> None:
    first = reality(pattern((100, 500), 6)).render()
    then = reality(pattern((100, 500), 7)).render()  # the same wall, another look
    model = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    labels = Renderer(SCENE, CAMERA).render().labels
    half = np.zeros(labels.shape, bool)
    half[:, 160:] = True
    model.learn(first.image, CAMERA, labels, exclude=half)
    seen_before = int(model.texture("north").mask.sum())  # type: ignore[union-attr]
    learned = model.learn(then.image, CAMERA, labels, new_only=True, rate=0.5)
    after = model.texture("north")
    assert after is not None and learned.new > 1000 and after.mask.sum() > 1.5 * seen_before
    # what was learned is as it was (the first look); the other half is learned now, from
    # the new frame
    mine = Renderer(SCENE, CAMERA)
    model.apply(mine)
    render = mine.render().image.astype(int)
    wall = cv2.erode((labels == LABEL_WALL).view(np.uint8), np.ones((9, 9), np.uint8)) > 0
    left, right = wall.copy(), wall.copy()
    left[:, 150:] = False
    right[:, :170] = False
    assert left.sum() > 1000 and right.sum() > 1000
    assert np.abs(render - first.image.astype(int))[left].mean() < 4
    assert np.abs(render - then.image.astype(int))[right].mean() < 4
    assert np.abs(render - then.image.astype(int))[left].mean() > 10  # the looks differ
    # what a pass excludes is not hidden: only what it says an object covered
    model2 = AppearanceModel(Renderer(SCENE, CAMERA).surfaces)
    model2.learn(first.image, CAMERA, labels, exclude=half)
    assert not model2.hidden(CAMERA, labels).any()
