"""The rasterizer: projection, ball centroid, labels, occlusion, caching."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.errors import ImageError
from adapt.geometry import Camera
from adapt.imagination import (
    LABEL_BALL,
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_ROBOT,
    LABEL_SKY,
    LABEL_WALL,
    Ball,
    BodyState,
    Floor,
    Obstacle,
    Renderer,
    RobotShape,
    RobotSpec,
    SceneSpec,
    Wall,
    World,
    WorldState,
    label_names,
)
from adapt.scenario import Scenario


def camera(**kw: object) -> Camera:
    args: dict[str, object] = dict(fx=400, fy=400, cx=159.5, cy=119.5, width=320, height=240,
                                   position=(0.0, -2.0, 1.0), look_at=(0.0, 1.0, 0.2))
    args.update(kw)
    return Camera.look_at(**args)  # type: ignore[arg-type]


def state_with(name: str, x: float, y: float) -> WorldState:
    return WorldState(0.0, 0, (BodyState(name, (x, y), (0.0, 0.0)),))


@pytest.mark.parametrize("xy", [(0.0, 0.5), (0.6, 1.2), (-0.5, 0.1), (0.3, 2.0)])
@pytest.mark.parametrize("roll", [0.0, 7.0])
def test_ball_label_centroid_is_within_one_pixel_of_projected_centre(
    xy: tuple[float, float], roll: float
) -> None:
    r = 0.08
    scene = SceneSpec(floor=Floor(texture=None), balls=(Ball("b", radius=r),))
    cam = camera(roll_deg=roll)
    out = Renderer(scene, cam).render(state_with("b", *xy))
    ys, xs = np.nonzero(out.labels == LABEL_BALL)
    assert len(xs) > 20
    centre = cam.project(np.array([[xy[0], xy[1], r]]))[0]
    assert np.hypot(xs.mean() - centre[0], ys.mean() - centre[1]) < 1.0


def test_wall_corner_lands_on_its_projected_pixel() -> None:
    scene = SceneSpec(floor=Floor(texture=None, color=(0, 0, 0)),
                      walls=(Wall("w", (-0.5, 1.0), (0.5, 1.0), height=0.5, texture=None,
                                  color=(255, 255, 255)),))
    cam = camera()
    out = Renderer(scene, cam).render()
    corners = cam.project(np.array([[-0.5, 1.0, 0.5], [0.5, 1.0, 0.0]]))
    # Just inside each projected corner is wall; just outside is not.
    (x0, y0), (x1, y1) = corners
    assert out.labels[int(np.ceil(y0)) + 1, int(np.ceil(x0)) + 1] == LABEL_WALL
    assert out.labels[int(np.floor(y1)) - 1, int(np.floor(x1)) - 1] == LABEL_WALL
    assert out.labels[int(np.floor(y0)) - 2, int(np.ceil(x0)) + 1] != LABEL_WALL
    assert out.labels[int(np.floor(y1)) - 1, int(np.ceil(x1)) + 2] != LABEL_WALL


def test_obstacle_hides_the_ball_behind_it() -> None:
    box = Obstacle("box", ((-0.3, 0.4), (0.3, 0.4), (0.3, 0.6), (-0.3, 0.6)), height=0.5)
    scene = SceneSpec(obstacles=(box,), balls=(Ball("b", radius=0.08),))
    r = Renderer(scene, camera(position=(0.0, -2.0, 0.3), look_at=(0.0, 1.0, 0.2)))
    hidden = r.render(state_with("b", 0.0, 1.2)).labels
    seen = r.render(state_with("b", 0.0, 0.0)).labels
    assert not (hidden == LABEL_BALL).any() and (hidden == LABEL_OBSTACLE).any()
    assert (seen == LABEL_BALL).sum() > 50


def test_labels_follow_the_documented_scheme(bundled: Scenario) -> None:
    out = Renderer(bundled.scene, bundled.camera).render()
    found = set(np.unique(out.labels).tolist())
    names = label_names(bundled.scene)
    assert found <= set(names)
    assert {LABEL_SKY, LABEL_FLOOR, LABEL_WALL + 0, LABEL_OBSTACLE + 0,
            LABEL_OBSTACLE + 1, LABEL_OBSTACLE + 2} <= found
    assert names[LABEL_WALL] == "north" and names[LABEL_BALL] == "ball"


def test_background_is_cached_and_frames_do_not_modify_it(bundled: Scenario) -> None:
    r = Renderer(bundled.scene, bundled.camera)
    world = World(bundled.scene)
    world.run(1.6)  # the ball is in view by the north wall
    bg = r.background.image.copy()
    out = r.render(world.snapshot())
    assert (out.labels == LABEL_BALL).any()
    assert np.array_equal(r.background.image, bg)
    assert r.background.image is r.background.image and not r.background.image.flags.writeable
    changed = np.any(out.image != bg, axis=2)
    ys, xs = np.nonzero(changed)
    # Only the ball and its shadow differ from the background.
    assert changed.sum() < 3 * (out.labels == LABEL_BALL).sum() + 200


def test_shadow_darkens_the_floor_by_the_ball() -> None:
    from adapt.imagination.render import LIGHT

    r = 0.1
    scene = SceneSpec(floor=Floor(texture=None, color=(200, 200, 200)), balls=(Ball("b", radius=r),))
    cam = camera(position=(0.0, -1.0, 1.5), look_at=(0.0, 0.5, 0.0))
    rend = Renderer(scene, cam)
    out = rend.render(state_with("b", 0.0, 0.5))
    centre = np.array([0.0, 0.5]) - LIGHT[:2] / LIGHT[2] * r
    ring = np.array([[*(centre + 0.8 * r * np.array([np.cos(a), np.sin(a)])), 0.0]
                     for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)])
    px = np.round(cam.project(ring)).astype(int)
    floor = out.labels[px[:, 1], px[:, 0]] == LABEL_FLOOR
    assert floor.sum() >= 6
    ratio = out.image[px[floor, 1], px[floor, 0]].mean() / rend.background.image[
        px[floor, 1], px[floor, 0]].mean()
    assert ratio < 0.85
    far = cam.project(np.array([[0.6, 0.5, 0.0]]))[0].round().astype(int)
    assert np.array_equal(out.image[far[1], far[0]], rend.background.image[far[1], far[0]])


def test_with_camera_renders_a_new_background(bundled: Scenario) -> None:
    r = Renderer(bundled.scene, bundled.camera)
    cam2 = bundled.camera.with_pose(bundled.camera.rotation, bundled.camera.position + [0.3, 0, 0])
    r2 = r.with_camera(cam2)
    assert r2.camera is cam2 and r2.scene is r.scene
    assert not np.array_equal(r.background.image, r2.background.image)


def test_robot_is_drawn_when_in_view() -> None:
    scene = SceneSpec(robot=RobotSpec(position=(0.0, 1.0), shape=RobotShape.BOX, size=(0.5, 0.3)))
    r = Renderer(scene, camera())
    assert (r.render().labels == LABEL_ROBOT).sum() > 500
    moved = WorldState(0.0, 0, (BodyState("robot", (5.0, -5.0), (0.0, 0.0)),))
    assert not (r.render(moved).labels == LABEL_ROBOT).any()


def test_textured_ball_and_missing_texture(tmp_path: object) -> None:
    scene = SceneSpec(balls=(Ball("b", radius=0.1, texture="builtin:coffee"),))
    out = Renderer(scene, camera()).render(state_with("b", 0.0, 0.5))
    assert (out.labels == LABEL_BALL).sum() > 100
    bad = SceneSpec(walls=(Wall("w", (-1, 1), (1, 1), texture="/no/such/texture.png"),))
    with pytest.raises(ImageError, match="/no/such/texture.png"):
        Renderer(bad, camera()).render()


def test_camera_inside_the_room_sees_no_gaps(bundled: Scenario) -> None:
    out = Renderer(bundled.scene, bundled.camera).render()
    lower = out.labels[bundled.camera.height // 2:]
    assert not (lower == LABEL_SKY).any()  # floor and walls cover the lower half


def test_brick_walls_show_horizontal_courses(bundled: Scenario) -> None:
    # the bundled brick photograph has vertical courses; walls must show them
    # horizontal: mortar lines across rows, so intensity changes more from row
    # to row than from column to column
    import cv2

    out = Renderer(bundled.scene, bundled.camera).render(World(bundled.scene, seed=1).snapshot())
    north = [i for i, w in enumerate(bundled.scene.walls) if w.name == "north"][0]
    wall = out.labels == LABEL_WALL + north
    grey = cv2.cvtColor(out.image, cv2.COLOR_BGR2GRAY).astype(np.float64)
    both_rows = wall[1:, :] & wall[:-1, :]
    both_cols = wall[:, 1:] & wall[:, :-1]
    assert bundled.scene.walls[north].texture == "builtin:brick" and both_rows.sum() > 10_000
    across_rows = np.abs(np.diff(grey, axis=0))[both_rows].mean()
    across_cols = np.abs(np.diff(grey, axis=1))[both_cols].mean()
    assert across_rows > 1.5 * across_cols


def box_of(labels: np.ndarray, label: int) -> tuple[int, int, int, int]:
    ys, xs = np.nonzero(labels == label)
    return (int(xs.min()), int(ys.min()), int(xs.max() - xs.min() + 1), int(ys.max() - ys.min() + 1))


def test_boxes_give_the_visible_part_of_each_moving_object(bundled: Scenario) -> None:
    world = World(bundled.scene)
    world.run(1.6)  # the ball is in view by the north wall
    out = Renderer(bundled.scene, bundled.camera).render(world.snapshot())
    assert set(out.boxes) == {"ball"}  # the robot carries the camera: out of view
    assert out.boxes["ball"] == box_of(out.labels, LABEL_BALL)
    assert out.names[LABEL_BALL] == "ball" and out.names[LABEL_WALL] == "north"


def test_a_partly_hidden_ball_has_the_box_of_its_visible_part() -> None:
    box = Obstacle("box", ((-0.3, 0.4), (0.3, 0.4), (0.3, 0.6), (-0.3, 0.6)), height=0.2)
    scene = SceneSpec(obstacles=(box,), balls=(Ball("b", radius=0.15),),
                      robot=RobotSpec(position=(0.8, 0.2), shape=RobotShape.BOX, size=(0.4, 0.3)))
    r = Renderer(scene, camera(position=(0.0, -2.0, 0.4), look_at=(0.0, 1.0, 0.2)))
    whole = r.render(WorldState(0.0, 0, (BodyState("b", (0.0, -0.2), (0.0, 0.0)),
                                          BodyState("robot", (0.8, 0.2), (0.0, 0.0)))))
    hidden = r.render(WorldState(0.0, 0, (BodyState("b", (0.0, 0.9), (0.0, 0.0)),)))
    assert whole.boxes["b"] == box_of(whole.labels, LABEL_BALL)
    assert whole.boxes["robot"] == box_of(whole.labels, LABEL_ROBOT)
    _, _, w, h = hidden.boxes["b"]
    assert h < w  # only the top of the ball shows over the box
    assert hidden.boxes["b"] == box_of(hidden.labels, LABEL_BALL)
    gone = r.render(WorldState(0.0, 0, (BodyState("b", (3.0, -1.9), (0.0, 0.0)),)))  # out of view
    assert "b" not in gone.boxes and "robot" not in gone.boxes


def test_balls_added_at_run_time_are_drawn_with_their_records(bundled: Scenario) -> None:
    world = World(bundled.scene)
    world.add_ball(Ball("late", radius=0.1, color=(0, 255, 0)), position=(0.0, 1.5))
    r = Renderer(bundled.scene, bundled.camera)
    without = r.render(world.snapshot())
    assert "late" not in without.boxes  # the renderer's scene does not know it
    out = r.render(world.snapshot(), balls=world.balls)
    assert set(out.boxes) >= {"late"} and out.names[LABEL_BALL + 1] == "late"
    assert out.boxes["late"] == box_of(out.labels, LABEL_BALL + 1)
    x, y, w, h = out.boxes["late"]
    assert out.image[y + h // 2, x + w // 2, 1] > 150  # green
    assert label_names(bundled.scene, world.balls)[LABEL_BALL + 1] == "late"


def test_exact_and_fast_renderers_draw_the_same_frame(bundled: Scenario) -> None:
    world = World(bundled.scene)
    world.run(1.6)
    fast = Renderer(bundled.scene, bundled.camera).render(world.snapshot())
    exact = Renderer(bundled.scene, bundled.camera, exact=True).render(world.snapshot())
    assert fast.boxes == exact.boxes
    assert (fast.labels == exact.labels).mean() > 0.995
