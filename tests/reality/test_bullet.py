"""The PyBullet reality: frames, truth, contacts, the robot and bad input.

Small (160x120, a few frames) so the suite stays fast; skipped when PyBullet is not
installed (``test_bullet_missing.py`` checks what happens then).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adapt.errors import RealityError
from adapt.frames import Actuator
from adapt.geometry import Camera
from adapt.scenario import Scenario
from adapt.seeds import Streams

from .bullet_scene import CAMERA, REALITY, WORLD, scenario

pytest.importorskip("pybullet")

from adapt.reality.bullet import BulletSource, Client  # noqa: E402
from adapt.reality.bullet.calibrate import measure  # noqa: E402
from adapt.reality.bullet.draw import BallDraw, SurfaceDraw  # noqa: E402
from adapt.reality.bullet.view import matrices, render  # noqa: E402


def open_source(sc: Scenario, seed: int = 1, calibrate: bool = False) -> BulletSource:
    return BulletSource(sc, streams=Streams(seed), calibrate=calibrate)


def test_a_point_renders_where_the_camera_model_projects_it() -> None:
    cam = Camera.look_at(fx=300, fy=290, cx=150.3, cy=130.7, width=320, height=240,
                         position=(0.3, -3, 2), look_at=(0.2, 0.5, 0.1), roll_deg=7)
    points = [(0.0, 0.0, 0.05), (1.0, 1.0, 0.3), (-1.2, 0.4, 0.0), (0.5, -1.0, 0.6)]
    with Client() as c:
        shape = c.createVisualShape(c.GEOM_SPHERE, radius=0.05, rgbaColor=[1, 0, 0, 1])
        bodies = [c.createMultiBody(baseMass=0, baseVisualShapeIndex=shape, basePosition=p)
                  for p in points]
        view, projection = matrices(cam)
        out = c.getCameraImage(320, 240, viewMatrix=view, projectionMatrix=projection,
                               renderer=c.ER_TINY_RENDERER)
    seg = np.asarray(out[4]).reshape(240, 320)
    for body, p in zip(bodies, points):
        ys, xs = np.nonzero(seg == body)
        u, v = cam.project(np.array([p]))[0]
        assert len(xs) > 20
        assert abs(xs.mean() - u) < 0.3 and abs(ys.mean() - v) < 0.3, (p, xs.mean(), ys.mean(), u, v)


def test_frames_are_bgr_images_of_the_camera_size_with_the_ball_in_view() -> None:
    src = open_source(scenario())
    frames = list(src)
    assert [f.index for f in frames] == list(range(6))
    assert frames[2].time == pytest.approx(2 / 15)
    image = frames[0].image
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    assert not image.flags.writeable
    truth = src.truth.at(0)
    ball = truth.objects["ball"]
    assert ball is not None and ball.pixels is not None and ball.pixels > 20
    u, v = truth.camera.project(np.array([[*ball.position, ball.height]]))[0]
    b, g, r = image[int(round(v)), int(round(u))].astype(int)
    assert r > b + 40 and r > g + 40   # the red ball is red in a BGR frame


def test_walls_show_their_textured_faces_steadily_as_the_camera_moves() -> None:
    # a wall's collision box has no visual shape of its own, and a body without one is
    # drawn as plain white boxes: lying on the textured faces, they fought them for every
    # pixel, in a noise that changed as a robot's camera moved a centimetre
    src = open_source(scenario())
    look = src.drawn.look
    seen = []
    for dy in (0.0, 0.01):
        cam = Camera.look_at(fx=130, fy=130, cx=79.5, cy=59.5, width=160, height=120,
                             position=(0.0, -0.4 + dy, 0.35), look_at=(1.5, 1.2 + dy, 0.3))
        rgb, seg = render(src.client, cam, look)
        walls = np.isin(seg, [b for b, n in src.bodies.names.items()
                              if n in ("north", "east", "south", "west")])
        assert walls.mean() > 0.2                            # a quarter of the view is walls
        assert not np.isin(seg, src.bodies.walls).any()      # never a collision box
        seen.append(rgb.astype(int))
    # 1 cm further on, the walls' pixels are much as they were (texture, not a fight)
    assert np.abs(seen[0] - seen[1]).mean() < 12


def test_the_same_seed_gives_the_same_frames_and_another_seed_another_reality() -> None:
    sc = scenario()
    a = [f.image for f in open_source(sc, 3)]
    b = [f.image for f in open_source(sc, 3)]
    c = [f.image for f in open_source(sc, 4)]
    assert all(np.array_equal(x, y) for x, y in zip(a, b))
    assert not np.array_equal(a[0], c[0])


def test_the_ball_moves_from_frame_0_and_a_thrown_ball_enters_at_its_time() -> None:
    src = open_source(scenario())
    list(src)
    p0 = src.truth.at(0).objects["ball"].position
    p5 = src.truth.at(5).objects["ball"].position
    assert math.dist(p0, p5) > 0.3
    thrown = scenario(REALITY.replace("t: 0,", "t: 0.2,"))
    src = open_source(thrown)
    list(src)
    assert src.truth.at(2).objects["ball"] is None      # 0.133 s
    assert src.truth.at(3).objects["ball"] is not None  # 0.2 s
    assert src.truth.at(2).parameters.object("ball").appears == pytest.approx(0.2)


def test_a_ball_dropped_from_a_height_bounces_on_the_floor() -> None:
    reality = REALITY.replace("heading_deg: 60}", "heading_deg: 60, height: 0.4}")
    sc = scenario(reality.replace("objects:", "floor: {restitution: 0.8}\n  objects:"),
                  run="run: {fps: 30, max_frames: 20}\n")
    src = open_source(sc)
    heights = [src.truth.at(f.index).objects["ball"].height for f in src]
    assert heights[0] == pytest.approx(0.5, abs=0.01)
    low = next(i for i, h in enumerate(heights) if h < 0.15)
    assert max(heights[low:]) > 0.2   # down, and up again


def test_the_ball_rebounds_off_a_wall_with_the_measured_restitution() -> None:
    ball = BallDraw("ball", True, 0.1, 0.45, 0.8, 0.5, 0.002, 0.001, 0.0, 1.0, 0.0, None,
                    (0, 0), (0, 0), 0.0)
    floor, walls = SurfaceDraw(0.5, 0.8, 0.0, 0.0), SurfaceDraw(0.9, 0.5, 0.0, 0.0)
    e = measure(ball, floor, walls, walls, 9.81, 1 / 960)
    # rolling friction: a torque of (0.002 x 0.8) N m per newton: a = 5/7 x 0.0016 g / r
    assert e.rolling_resistance == pytest.approx(5 / 7 * 0.0016 / 0.1, rel=0.05)
    assert e.drag < 0.01
    # PyBullet multiplies the restitutions (0.72) and its solver adds a little
    assert 0.65 < e.restitution_walls < 0.85
    # the forward spin kept through the bounce slows the ball afterwards
    assert e.settled_walls < e.restitution_walls - 0.1 and 0.2 < e.spin <= 1.0
    damped = measure(BallDraw(*[*ball.as_json().values()][:8], 0.05, 1.0, 0.0, None, (0, 0),
                              (0, 0), 0.0), floor, walls, walls, 9.81, 1 / 960)
    assert damped.drag > 0.02   # damping slows a fast ball more than a slow one


def test_the_truth_reports_the_measured_parameters_in_the_models_terms() -> None:
    src = open_source(scenario(), calibrate=True)
    p = src.parameters.object("ball")
    measured = src.effective["ball"]
    assert p.restitution == pytest.approx(min(1.0, measured.restitution_walls / 0.9))
    assert p.rolling_resistance == pytest.approx(measured.rolling_resistance)
    details = src.parameters.as_json()["details"]
    assert details["measured"]["ball"]["restitution_walls"] == pytest.approx(
        measured.restitution_walls, abs=1e-4)
    drawn = details["pybullet"]["balls"][0]
    assert 0.7 <= drawn["restitution"] <= 0.9   # the default range


ROBOT_CAMERA = """camera: {fx: 130, fy: 130, cx: 79.5, cy: 59.5, width: 160, height: 120,
         mount: robot, position: [0, 0, 0.6], look_at: [2, 0, 0.2]}
"""
ROBOT = "  robot: {position: [0, -0.8], heading_deg: 90, max_speed: 0.8, max_accel: 1.5}\n"


def test_the_robot_drives_as_commanded_and_carries_its_camera() -> None:
    sc = scenario(camera=ROBOT_CAMERA, world=WORLD + ROBOT, run="run: {fps: 10, max_frames: 16}\n")
    src = open_source(sc)
    assert isinstance(src.robot, Actuator)
    frames = iter(src)
    next(frames)
    src.robot.command_robot((0.0, 5.0))   # clipped to 0.8 m/s
    for _ in range(15):
        next(frames)
    truth = src.truth.at(15)
    assert truth.robot.velocity[1] == pytest.approx(0.8, abs=0.02)
    assert truth.robot.position[1] == pytest.approx(-0.8 + 0.8 * 1.5 - 0.8**2 / 3.0, abs=0.05)
    assert truth.camera.position[1] == pytest.approx(truth.robot.position[1], abs=1e-6)
    assert truth.camera.position[2] == pytest.approx(0.6)


@pytest.mark.parametrize(("shape", "geometry"), [("disc", "GEOM_CYLINDER"), ("box", "GEOM_BOX")])
def test_the_robot_body_has_the_scenario_shape(shape: str, geometry: str) -> None:
    extra = ", size: [0.5, 0.3]" if shape == "box" else ""
    robot = ROBOT.replace("heading_deg: 90", f"heading_deg: 90, shape: {shape}{extra}")
    src = open_source(scenario(camera=ROBOT_CAMERA, world=WORLD + robot))
    c = src.client
    visual = c.getVisualShapeData(src.bodies.robot)[0]
    collision = c.getCollisionShapeData(src.bodies.robot, -1)[0]
    assert visual[2] == collision[2] == getattr(c, geometry)
    if shape == "disc":   # a cylinder's dimensions: (length, radius, -)
        assert visual[3][:2] == pytest.approx((0.3, 0.25))
    else:                 # a box's: full extents
        assert visual[3] == pytest.approx((0.5, 0.3, 0.3))


def test_the_robot_stops_at_a_wall() -> None:
    sc = scenario(camera=ROBOT_CAMERA, world=WORLD + ROBOT,
                  run="run: {fps: 10, max_frames: 60}\n")
    src = open_source(sc)
    src.robot.command_robot((0.0, -0.8))
    list(src)
    y = src.truth.at(59).robot.position[1]
    assert -1.5 + 0.25 - 0.02 < y < -1.5 + 0.25 + 0.02


def test_wheel_slip_moves_the_robot_off_its_command() -> None:
    def final(slip: float) -> tuple[float, float]:
        sc = scenario(REALITY.replace("objects:", f"robot: {{slip: {slip}}}\n  objects:"),
                      camera=ROBOT_CAMERA, world=WORLD + ROBOT,
                      run="run: {fps: 10, max_frames: 15}\n")
        src = open_source(sc)
        src.robot.command_robot((0.5, 0.0))
        list(src)
        return src.truth.at(14).robot.position

    assert final(0.0)[1] == pytest.approx(-0.8, abs=1e-3)
    assert abs(final(0.3)[1] + 0.8) > 0.01


def test_a_drawn_camera_offset_inside_a_wall_is_refused() -> None:
    camera = CAMERA.replace("[0, -2.3, 2.3]", "[0, -1.45, 0.1]")
    sc = scenario(REALITY.replace("objects:", "camera_offset: [0, -0.1, 0]\n  objects:"),
                  camera=camera)
    with pytest.raises(RealityError) as info:
        open_source(sc)
    assert "the drawn camera offset puts the camera at [0, -1.55, 0.1], inside the wall " \
           "'south'" in str(info.value)
    assert str(info.value).startswith("<string>:")


def test_pybullet_errors_become_reality_errors() -> None:
    with Client("scene.yaml:3:1") as c, pytest.raises(RealityError) as info:
        c.loadTexture("/no/such/texture.png")
    assert str(info.value).startswith("scene.yaml:3:1: PyBullet failed in loadTexture")
