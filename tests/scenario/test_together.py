"""Values that must fit together (adapt/scenario/sanity.py): places, speeds against the physics
step, a prediction's work, the real tiles, the true camera -- each refused at the value it names."""

from __future__ import annotations

import pytest

from adapt.errors import ScenarioError
from adapt.scenario import loads_scenario

CAMERA = ("camera: {fx: 60, fy: 60, cx: 39.5, cy: 29.5, width: 80, height: 60, "
          "position: [0, -0.9, 0.6], look_at: [0, 2, 0.3]}\n")
ROOM = """\
world:
  floor: {extent: [-2, -1, 2, 3]}
  walls:
    - {name: north, from: [-2, 3], to: [2, 3], height: 1}
    - {name: west, from: [-2, -1], to: [-2, 3], height: 1}
  obstacles:
    - {name: box, polygon: [[0.5, 1.5], [1.0, 1.5], [1.0, 2.0], [0.5, 2.0]], height: 0.4}
  objects:
    - {name: ball, radius: 0.1, position: [-1, 1], velocity: [1, 0]}
  robot: {shape: disc, radius: 0.25, position: [0, -0.5], max_speed: 0.8, max_accel: 1.5}
"""


def load(extra: str = "", sets: tuple[str, ...] = ()) -> object:
    return loads_scenario(CAMERA + ROOM + extra, overrides=list(sets))


def refused(extra: str = "", sets: tuple[str, ...] = ()) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        load(extra, sets)
    return info.value


def test_the_room_is_accepted() -> None:
    load()


@pytest.mark.parametrize("sets, path, words", [
    (("world.robot.position=[5, 1]",), "world.robot.position", "off the floor"),
    (("world.robot.position=[0.75, 1.75]",), "world.robot.position", "obstacle 'box'"),
    (("world.robot.position=[-1.9, 1]",), "world.robot.position", "wall 'west'"),
    (("world.robot.shape=box", "world.robot.size=[0.6, 0.4]", "world.robot.heading_deg=0",
      "world.robot.position=[-1.75, 1]"), "world.robot.position", "wall 'west'"),
    (("world.objects.ball.position=[0.9, 1.6]",), "world.objects[0].position", "obstacle 'box'"),
    (("world.objects.ball.position=[-1.95, 1]",), "world.objects[0].position", "wall 'west'"),
])
def test_a_body_starts_on_the_floor_clear_of_walls_and_obstacles(sets: tuple[str, ...],
                                                                  path: str, words: str) -> None:
    err = refused(sets=sets)
    assert err.file == "--set" and err.message.startswith(path + ": "), err.message
    assert words in err.message, err.message


def test_touching_is_allowed() -> None:
    load(sets=("world.robot.position=[-1.75, 1]",))  # the disc's edge on the west wall
    load(sets=("world.robot.shape=box", "world.robot.size=[0.5, 0.4]",
               "world.robot.heading_deg=0", "world.robot.position=[-1.7, 1]"))


def test_a_throw_fits_over_its_whole_range() -> None:
    throw = ("reality:\n  objects:\n    - {name: rock, radius: 0.1, throw: {x: [-1.5, -0.5], "
             "y: 1.7}}\n")
    load(throw)
    err = refused(throw.replace("[-1.5, -0.5]", "[-1.5, 0.6]"))
    assert err.message.startswith("reality.objects[0].throw.x: ") and "'box'" in err.message


def test_a_reality_only_object_starts_in_place() -> None:
    err = refused("reality:\n  objects:\n    - {name: rock, radius: 0.1, position: [0.7, 1.7]}\n")
    assert err.message.startswith("reality.objects[0].position: "), err.message


def test_a_ball_may_not_cross_a_wall_in_one_step() -> None:
    err = refused(sets=("world.dt=0.1", "world.objects.ball.velocity=[40, 0]"))
    assert err.message.startswith("world.objects[0].velocity: ") and "world.dt" in err.message
    err = refused("reality: {dt: 0.1, objects: [{name: ball, drag: 10}]}\n",
                  ("world.objects.ball.velocity=[30, 0]", "world.dt=0.001"))
    assert err.message.startswith("reality.objects[0].drag: ") and "reality.dt" in err.message


def test_a_prediction_does_bounded_work() -> None:
    err = refused("predict: {horizons: [60], ensemble: 1000}\n")
    assert err.message.startswith("predict.ensemble: ") and "5,000,000" in err.message
    load("predict: {horizons: [60], ensemble: 100}\n")


def test_the_real_tiles_and_the_true_camera() -> None:
    err = refused("reality: {appearance: {texture_scale: 0.01}}\n",
                  ("world.floor.tile=0.05",))
    assert err.message.startswith("reality.appearance.texture_scale: "), err.message
    err = refused("reality: {camera_offset: [100, 0, 0]}\n",
                  ("camera.position=[9950, -0.9, 0.6]", "camera.look_at=[9950, 2, 0.3]",
                   "world.floor.extent=[-2, -1, 10000, 3]"))
    assert err.message.startswith("reality.camera_offset: "), err.message
