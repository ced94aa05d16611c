"""The real robot: it obeys motor commands within its own limits, its wheels slip,
and a camera on it follows its true pose."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adapt.errors import RealityError
from adapt.frames import Actuator
from adapt.imagination import Renderer
from adapt.reality.camera import nominal_camera, offset_camera

from .conftest import WORLD, scenario, source

ROBOT_CAMERA = """camera:
  fx: 160
  fy: 160
  cx: 79.5
  cy: 59.5
  width: 160
  height: 120
  position: [0.1, 0.0, 0.6]
  look_at: [2.0, 0.0, 0.3]
  mount: robot
"""
ROBOT = "  robot: {position: [0.0, -0.5], heading_deg: 90, max_speed: 1.0, max_accel: 2.0}\n"


def robot_scenario(reality: str, run: str = "run: {fps: 10, max_frames: 20}\n"):  # type: ignore[no-untyped-def]
    return scenario(reality, run=run, camera=ROBOT_CAMERA, world=WORLD + ROBOT)


def speeds_and_accels(slip: float, seconds: float = 1.5, seed: int = 1):  # type: ignore[no-untyped-def]
    src = source(robot_scenario(f"  robot: {{max_speed: 0.5, max_accel: 1.0, slip: {slip}}}\n"),
                 seed)
    assert isinstance(src.robot, Actuator)
    src.robot.command_robot((0.0, 3.0))
    world = src.world
    vs = []
    while world.time < seconds:
        world.step()
        vs.append(world.velocity("robot"))
    v = np.array(vs)
    accel = np.linalg.norm(np.diff(v, axis=0), axis=1) / world.dt
    return src, np.linalg.norm(v, axis=1), accel


@pytest.mark.parametrize("slip", [0.0, 0.2])
def test_the_robot_never_exceeds_its_true_limits(slip: float) -> None:
    _, speed, accel = speeds_and_accels(slip)
    assert speed.max() <= 0.5 * (1 + 1e-6)
    assert accel.max() <= 1.0 * (1 + 1e-6)
    assert speed[-1] > 0.4   # and it does drive


def test_without_slip_the_robot_drives_as_commanded() -> None:
    src, speed, _ = speeds_and_accels(0.0, seconds=2.0)
    # 0.5 s at 1 m/s^2 up to 0.5 m/s, then 1.5 s at 0.5 m/s: 0.125 + 0.75 m along +y.
    x, y = src.world.position("robot")
    assert x == pytest.approx(0.0, abs=1e-9) and y == pytest.approx(-0.5 + 0.875, abs=2e-3)
    assert speed[-1] == pytest.approx(0.5, rel=1e-6)


def test_wheel_slip_is_seeded_noise_that_pushes_the_robot_off_its_path() -> None:
    paths = []
    for seed in (1, 1, 2):
        src, _, _ = speeds_and_accels(0.2, seconds=2.0, seed=seed)
        paths.append(src.world.position("robot"))
    assert paths[0] == paths[1] != paths[2]
    assert abs(paths[0][0]) > 0.01   # drifted sideways
    assert abs(paths[0][1] - 0.375) > 1e-3


def test_a_camera_on_the_robot_follows_its_true_pose() -> None:
    sc = robot_scenario("  camera_offset: [0.02, 0.0, 0.0]\n  camera_offset_deg: [1.0, 0.0, 0.0]\n"
                        "  robot: {slip: 0.3}\n  appearance: {noise: 0, blur: 0}\n")
    src = source(sc)
    assert src.robot is not None
    frames = iter(src)
    first = next(frames)
    src.robot.command_robot((0.5, 0.5), 0.8)
    for _ in range(10):
        frame = next(frames)
    truth = src.truth.at(frame.index)
    robot = truth.robot
    assert robot is not None and math.dist(robot.position, (0.0, -0.5)) > 0.1
    assert robot.heading != pytest.approx(math.pi / 2)
    nominal = nominal_camera(sc.camera, sc.mount, robot.position, robot.heading)
    expected = offset_camera(nominal, (0.02, 0.0, 0.0), (1.0, 0.0, 0.0), robot.heading)
    assert np.allclose(truth.camera.rotation, expected.rotation)
    assert np.allclose(truth.camera.position, expected.position)
    # The offset turns with the robot: it sits 0.12 m ahead of the robot's centre.
    ahead = np.array([math.cos(robot.heading), math.sin(robot.heading)])
    assert (truth.camera.position[:2] - robot.position) @ ahead == pytest.approx(0.12)
    # The frame was rendered from there.
    state = src.world.state()
    assert np.array_equal(frame.image, Renderer(src.scene, truth.camera).render(state).image)
    assert not np.array_equal(frame.image, first.image)


@pytest.mark.parametrize("command, message", [
    (((float("nan"), 0.0), 0.0), "must be finite"),
    (((1.0, 0.0), float("inf")), "must be finite"),
    ((("fast", 0.0), 0.0), "a velocity"),
    (((1.0,), 0.0), "a velocity"),
])
def test_bad_commands_are_refused(command: tuple, message: str) -> None:  # type: ignore[type-arg]
    src = source(robot_scenario(""))
    assert src.robot is not None
    with pytest.raises(RealityError, match=message):
        src.robot.command_robot(*command)


def test_a_reality_without_a_robot_has_no_actuator() -> None:
    src = source(scenario())
    assert src.robot is None and src.truth.parameters.robot_max_speed is None
    with pytest.raises(RealityError, match="no robot"):
        src.world.command_robot((1.0, 0.0))
