"""The runner's sections of a scenario: mount, object models, reality, goals, rules,
schemas, run, predict, outputs, overrides, and the positions kept for later errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from adapt.errors import ScenarioError
from adapt.scenario import (
    Creation,
    Mount,
    Range,
    RealityKind,
    Scenario,
    SyntheticReality,
    VideoReality,
    load_scenario,
    loads_scenario,
)

CAMERA = """camera:
  fx: 500
  fy: 500
  cx: 320
  cy: 240
  width: 640
  height: 480
  position: [0, -3, 1]
  look_at: [0, 0, 0.5]
"""
WORLD = """world:
  walls: [{name: north, from: [-2, 2], to: [2, 2], height: 1}]
  objects:
    - {name: ball, radius: 0.1, position: [0, 0], velocity: [1, 0]}
  robot: {position: [0, -1], heading_deg: 90, max_speed: 1, max_accel: 2}
"""


def load(text: str, tmp_path: Path | None = None, **kw: object) -> Scenario:
    if tmp_path is None:
        return loads_scenario(text, **kw)  # type: ignore[arg-type]
    p = tmp_path / "s.yaml"
    p.write_text(text, encoding="utf-8")
    return load_scenario(p, **kw)  # type: ignore[arg-type]


def err(text: str, tmp_path: Path | None = None, **kw: object) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        load(text, tmp_path, **kw)
    return info.value


# -- camera mount -----------------------------------------------------------------------

def test_a_camera_on_the_robot_is_placed_in_the_robots_frame() -> None:
    text = CAMERA.replace("position: [0, -3, 1]", "position: [0.1, 0, 0.6]").replace(
        "look_at: [0, 0, 0.5]", "look_at: [2, 0, 0.3]") + "  mount: robot\n" + WORLD
    sc = load(text)
    assert sc.mount.kind is Mount.ROBOT and sc.mount.position == (0.1, 0.0, 0.6)
    # robot at (0, -1) heading +y: the camera sits 0.1 m ahead of it, looking along +y
    assert np.allclose(sc.camera.position, [0.0, -0.9, 0.6])
    forward = sc.camera.rotation[2]
    assert forward[1] > 0.98 and abs(forward[0]) < 1e-9 and forward[2] < 0


def test_a_camera_on_the_robot_needs_a_robot() -> None:
    e = err(CAMERA + "  mount: robot\nworld: {}\n")
    assert e.message.startswith("camera.mount: a camera on the robot needs a world.robot")
    assert e.line == 10


def test_a_camera_below_the_floor_is_an_error() -> None:
    e = err(CAMERA.replace("position: [0, -3, 1]", "position: [0, -3, -0.2]") + "world: {}\n")
    assert e.message.startswith("camera.position: the camera is below the floor")
    assert e.line == 8


# -- object models ------------------------------------------------------------------------

def test_an_object_created_when_seen_is_not_in_the_starting_scene() -> None:
    text = CAMERA + """world:
  objects:
    - name: ball
      radius: 0.11
      create: when_seen
      ranges: {restitution: [0.6, 0.9], rolling_resistance: [0.01, 0.05]}
reality:
  objects:
    - {name: ball, throw: {t: 0.5, x: -2, y: 1, speed: 2, heading_deg: 30}}
"""
    sc = load(text)
    assert sc.scene.balls == ()
    model = sc.model("ball")
    assert model.create is Creation.WHEN_SEEN
    assert model.range("restitution") == Range(0.6, 0.9)
    assert model.ball.restitution == pytest.approx(0.75)  # the middle of the range
    assert model.range("friction") == Range.fixed(model.ball.friction)


@pytest.mark.parametrize("body, path, expected", [
    ("{name: b, create: when_seen, position: [0, 0]}", "world.objects[0].position",
     "gets its position from perception"),
    ("{name: b, create: later}", "world.objects[0].create", "expected one of 'at_start', 'when_seen'"),
    ("{name: b, restitution: 0.95, ranges: {restitution: [0.6, 0.9]}}", "world.objects[0].restitution",
     "outside its range"),
    ("{name: b, ranges: {restitution: [0.9, 0.6]}}", "world.objects[0].ranges.restitution",
     "low <= high"),
    ("{name: b, ranges: {spin: [0, 1]}}", "world.objects[0].ranges.spin", "unknown key"),
])
def test_bad_object_models(body: str, path: str, expected: str) -> None:
    e = err(CAMERA + f"world:\n  objects:\n    - {body}\n")
    assert e.message.startswith(path + ":") and expected in e.message


def test_two_objects_with_one_name_are_an_error() -> None:
    e = err(CAMERA + "world:\n  objects:\n    - {name: b}\n    - {name: b}\n")
    assert e.message.startswith("world.objects[1]: a second object called 'b'")


# -- YAML details --------------------------------------------------------------------------

def test_yaml_1_2_floats_are_numbers() -> None:
    sc = load(CAMERA + "world:\n  dt: 1e-3\n  gravity: 9.81E0\n")
    assert sc.scene.dt == 0.001 and sc.scene.gravity == 9.81


def test_a_recursive_anchor_is_a_positioned_error_not_a_crash() -> None:
    e = err(CAMERA + "world:\n  objects: &a\n    - {name: b, color: *a}\n")
    assert e.message.startswith("world.objects[0].color")


def test_a_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    p = tmp_path / "bom.yaml"
    p.write_bytes(b"\xef\xbb\xbf" + (CAMERA + "world: {}\n").encode())
    assert load_scenario(p).camera.width == 640


# -- reality ----------------------------------------------------------------------------------

def test_the_default_reality_is_synthetic_and_copies_the_world() -> None:
    sc = load(CAMERA + WORLD)
    r = sc.reality
    assert isinstance(r, SyntheticReality) and r.kind is RealityKind.SYNTHETIC
    assert r.dt < sc.scene.dt
    (ball,) = r.objects
    assert ball.declared and ball.restitution == Range.fixed(sc.scene.balls[0].restitution)
    assert ball.drag.low > 0 and ball.spin.low > 0  # real balls are not the model


def test_a_synthetic_reality_with_its_own_parameters() -> None:
    sc = load(CAMERA + WORLD + """reality:
  dt: 0.0005
  camera_offset: [0.02, -0.01, 0.0]
  camera_offset_deg: 1.5
  appearance: {brightness: 10, gradient: 0.3, blur: 1.0, noise: 3, texture_scale: 1.1,
               tint: [1.0, 0.9, 1.1], spin_marker: true}
  robot: {slip: 0.05, max_speed: 0.9}
  objects:
    - {name: ball, restitution: [0.6, 0.7], drag: 0.05, spin: 0.4}
    - {name: box, radius: 0.2, color: [20, 200, 20], position: [1, 1]}
""")
    r = sc.reality
    assert isinstance(r, SyntheticReality)
    assert r.dt == 0.0005 and r.camera.position == (0.02, -0.01, 0.0)
    assert r.camera.random_rotation == 1.5 and r.camera.rotation_deg == (0.0, 0.0, 0.0)
    assert r.appearance.spin_marker and r.appearance.tint == (1.0, 0.9, 1.1)
    assert r.robot.slip == 0.05 and r.robot.max_speed == 0.9 and r.robot.max_accel is None
    ball, box = r.objects
    assert ball.restitution == Range(0.6, 0.7) and ball.spin == Range.fixed(0.4)
    assert not box.declared and box.ball.radius == 0.2 and box.ball.position == (1.0, 1.0)


@pytest.mark.parametrize("reality, path, expected", [
    ("  objects: [{name: box}]\n", "reality.objects[0]", "give its radius"),
    ("  objects: [{name: ball, radius: 0.3}]\n", "reality.objects[0].radius", "is a world object"),
    ("  objects: [{name: ball, spin: 2}]\n", "reality.objects[0].spin", "from 0 to 1"),
    ("  objects: [{name: ball, throw: {x: 1}}]\n", "reality.objects[0].throw", "missing key 'y'"),
    ("  appearance: {blur: 50}\n", "reality.appearance.blur", "from 0 to 20"),
    ("  appearance: {glare: 1}\n", "reality.appearance.glare", "unknown key"),
    ("  kind: lidar\n", "reality.kind", "expected one of 'synthetic', 'video'"),
    ("  camera_offset: [1, 2]\n", "reality.camera_offset", "expected [x, y, z]"),
])
def test_bad_synthetic_realities(reality: str, path: str, expected: str) -> None:
    e = err(CAMERA + WORLD + "reality:\n" + reality)
    assert e.message.startswith(path + ":") and expected in e.message, e.message


def test_an_object_created_when_seen_needs_a_throw_in_reality() -> None:
    base = CAMERA + "world:\n  objects:\n    - {name: ball, create: when_seen}\n"
    e = err(base)
    assert e.message.startswith("world.objects[0]:") and "no reality section" in e.message
    e = err(base + "reality:\n  objects: [{name: ball}]\n")
    assert e.message.startswith("reality.objects[0]:") and "give a throw" in e.message


def test_reality_robot_without_a_world_robot() -> None:
    e = err(CAMERA + "world: {}\nreality:\n  robot: {slip: 0.1}\n")
    assert e.message.startswith("reality.robot: the world has no robot")


def test_a_video_reality(tmp_path: Path) -> None:
    (tmp_path / "frames").mkdir()
    for i in range(3):
        (tmp_path / "frames" / f"f{i}.png").write_bytes(b"")
    (tmp_path / "truth.csv").write_text("t,object,x,y\n")
    sc = load(CAMERA + WORLD + "reality:\n  kind: video\n  path: frames/*.png\n  fps: 25\n"
              "  ground_truth: truth.csv\n", tmp_path)
    r = sc.reality
    assert isinstance(r, VideoReality) and r.fps == 25.0
    assert r.pattern == str(tmp_path / "frames" / "*.png")
    assert r.ground_truth == tmp_path / "truth.csv"


@pytest.mark.parametrize("reality, expected", [
    ("  kind: video\n", "missing key 'path'"),
    ("  kind: video\n  path: none.mp4\n", "video file"),
    ("  kind: video\n  path: nothing/*.png\n  fps: 10\n", "no image matches"),
    ("  kind: video\n  path: frames/*.png\n", "needs 'fps'"),
    ("  kind: video\n  path: frames\n", "is a folder"),
    ("  kind: video\n  path: frames/*.png\n  fps: 10\n  ground_truth: gt.csv\n", "ground-truth file"),
    ("  kind: video\n  path: frames/*.png\n  fps: 10\n  dt: 0.1\n", "unknown key"),
])
def test_bad_video_realities(tmp_path: Path, reality: str, expected: str) -> None:
    (tmp_path / "frames").mkdir()
    (tmp_path / "frames" / "a.png").write_bytes(b"")
    e = err(CAMERA + WORLD + "reality:\n" + reality, tmp_path)
    assert e.message.startswith("reality") and expected in e.message, e.message


# -- goals, rules, schemas -----------------------------------------------------------------

def test_goals_keep_their_attributes_and_positions() -> None:
    sc = load(CAMERA + WORLD + "goals:\n  - {name: intercept, object: ball, within: 2.5}\n")
    (g,) = sc.goals
    assert g.name == "intercept" and g.attributes == (("object", "ball"), ("within", 2.5))
    assert g.attribute_sources["within"].line == 16
    assert g.source.path == "goals[0]"


@pytest.mark.parametrize("goals, path, expected", [
    ("  - {name: intercept, object: bal}\n", "goals[0].object", "no object called 'bal'"),
    ("  - {object: ball}\n", "goals[0]", "missing key 'name'"),
    ("  - {name: go, to: [1, 2]}\n", "goals[0].to", "a string or a number"),
    ("  - {name: go, 'bad key': 1}\n", "goals[0].bad key", "attribute name"),
])
def test_bad_goals(goals: str, path: str, expected: str) -> None:
    e = err(CAMERA + WORLD + "goals:\n" + goals)
    assert e.message.startswith(path + ":") and expected in e.message, e.message


def test_rules_resolve_relative_to_the_scenario(tmp_path: Path) -> None:
    (tmp_path / "r.soar").write_text("")
    sc = load(CAMERA + WORLD + "rules: [r.soar]\n", tmp_path)
    assert [r.path for r in sc.rules] == [tmp_path / "r.soar"]
    assert load(CAMERA + WORLD + "rules: r.soar\n", tmp_path).rules[0].path == tmp_path / "r.soar"
    e = err(CAMERA + WORLD + "rules: [r.soar, missing.soar]\n", tmp_path)
    assert e.message.startswith("rules[1]: rule file") and "missing.soar" in e.message


def test_schema_parameters_keep_their_positions() -> None:
    sc = load(CAMERA + WORLD + "schemas:\n  scene-background: {gain: 0.5, every: 2}\n"
              "  foreground-object: ~\n")
    bg = sc.schema_settings("scene-background")
    assert bg is not None and dict(bg.parameters) == {"gain": 0.5, "every": 2}
    assert bg.parameter_sources["every"].line == 16 and bg.source.path == "schemas.scene-background"
    fo = sc.schema_settings("foreground-object")
    assert fo is not None and dict(fo.parameters) == {}
    assert sc.schema_settings("none") is None


# -- run, predict, outputs --------------------------------------------------------------------

def test_run_settings_and_the_seed() -> None:
    sc = load(CAMERA + WORLD + "run: {fps: 20, duration: 2.5, seed: 11, decisions_per_frame: 2}\n")
    assert sc.run.frames == 50 and sc.seed == 11 and sc.run.decisions_per_frame == 2
    assert load(CAMERA + WORLD + "run: {max_frames: 7}\n").run.frames == 7
    assert load(CAMERA + WORLD).run.frames == 300  # 10 s at 30 frames/s


@pytest.mark.parametrize("extra, path, expected", [
    ("run: {duration: 1, max_frames: 3}\n", "run.max_frames", "not both"),
    ("run: {seed: 3}\nseed: 4\n", "seed", "given twice"),
    ("run: {fps: 0}\n", "run.fps", "positive"),
    ("run: {max_frames: 2000000}\n", "run.max_frames", "to 1000000"),
    ("run: {duration: 1.0e9}\n", "run.duration", "at most"),
    ("predict: {horizons: []}\n", "predict.horizons", "at least one"),
    ("predict: {horizons: [0.5, 100]}\n", "predict.horizons[1]", "at most 60"),
    ("predict: {ensemble: 5000}\n", "predict.ensemble", "to 1000"),
    ("outputs: {trace_level: 9}\n", "outputs.trace_level", "1 to 5"),
    ("outputs: {video: yes please}\n", "outputs.video", "true or false"),
])
def test_bad_run_predict_outputs(extra: str, path: str, expected: str) -> None:
    e = err(CAMERA + WORLD + extra)
    assert e.message.startswith(path + ":") and expected in e.message, e.message


def test_predict_horizons_are_sorted_and_unique() -> None:
    sc = load(CAMERA + WORLD + "predict: {horizons: [1.0, 0.5, 1.0], every: 3}\n")
    assert sc.predict.horizons == (0.5, 1.0) and sc.predict.every == 3


# -- overrides -----------------------------------------------------------------------------------

def test_overrides_replace_values_by_name_or_index_and_add_keys() -> None:
    sc = load(CAMERA + WORLD, overrides=["world.objects.ball.restitution=0.55",
                                         "world.walls[0].height=2",
                                         "reality.camera_offset_deg=2.0",
                                         "run.fps=15"])
    assert sc.scene.balls[0].restitution == 0.55 and sc.scene.walls[0].height == 2.0
    assert isinstance(sc.reality, SyntheticReality) and sc.reality.camera.random_rotation == 2.0
    assert sc.run.fps == 15.0


def test_an_override_of_the_run_length_replaces_the_files_other_one() -> None:
    assert load(CAMERA + WORLD + "run: {duration: 1}\n", overrides=["run.max_frames=7"]).run.frames == 7
    assert load(CAMERA + WORLD + "run: {max_frames: 7, fps: 10}\n",
                overrides=["run.duration=2"]).run.frames == 20
    e = err(CAMERA + WORLD, overrides=["run.max_frames=7", "run.duration=1"])
    assert "not both" in e.message


def test_a_bad_override_is_reported_in_the_override() -> None:
    e = err(CAMERA + WORLD, overrides=["world.objects.ball.restitution=7"])
    assert e.file == "--set" and e.message.startswith("world.objects[0].restitution: expected a "
                                                      "number from 0 to 1, got 7")
    assert "world.objects.ball.restitution=7" in str(e)
    e = err(CAMERA + WORLD, overrides=["world.objects.nope.restitution=0.5"])
    assert "no item named 'nope'" in e.message
    e = err(CAMERA + WORLD, overrides=["world.wals[0].height=1"])
    assert "no list called 'wals' to index (did you mean 'walls'?)" in e.message
    e = err(CAMERA + WORLD, overrides=["world.wals=[]"])
    assert e.message.startswith("world.wals: unknown key (did you mean 'walls'?)")
    e = err(CAMERA + WORLD, overrides=["no-equals-sign"])
    assert "expected KEY=VALUE" in e.message


# -- positions for later errors ---------------------------------------------------------------

def test_where_finds_the_nearest_read_key_path() -> None:
    sc = load(CAMERA + WORLD)
    assert sc.where("world.objects[0].radius").line == 13
    assert sc.where("world.objects[0].nothing").path == "world.objects[0]"
    assert sc.where("camera.fx").col == 7


def test_the_bundled_scenarios_load() -> None:
    root = Path(__file__).resolve().parents[2] / "scenarios"
    for path in sorted(root.glob("*.yaml")):
        sc = load_scenario(path)
        assert sc.camera.width > 0 and math.isfinite(sc.run.fps)
