"""Loading scenario YAML: the camera and world sections, resolved textures and located errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.errors import ScenarioError
from adapt.geometry import Camera
from adapt.scenario import Scenario, load_scenario, loads_scenario

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


def write(tmp_path: Path, world: str, extra: str = "") -> Path:
    p = tmp_path / "s.yaml"
    p.write_text(CAMERA + "world:\n" + world + extra, encoding="utf-8")
    return p


def error_of(path: Path) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    return info.value


def test_bundled_scenario(bundled: Scenario) -> None:
    scene = bundled.scene
    assert isinstance(bundled.camera, Camera) and bundled.seed == 7
    assert (len(scene.balls), len(scene.walls), len(scene.obstacles)) == (1, 4, 3)
    assert scene.robot is not None and scene.walls[0].texture == "builtin:brick"
    assert bundled.path is not None and bundled.path.name == "room.yaml"


def test_wall_height_error_names_file_line_col_and_key_path(tmp_path: Path) -> None:
    p = write(tmp_path, """  walls:
    - {from: [0, 0], to: [1, 0], height: 1}
    - {from: [1, 0], to: [1, 1], height: 1}
    - from: [1, 1]
      to: [0, 1]
      height: tall
""")
    err = error_of(p)
    assert (err.file, err.line, err.col) == (str(p), 16, 15)
    assert "world.walls[2].height: expected a number, got 'tall'" in str(err)
    assert str(err).startswith(f"{p}:16:15:")


@pytest.mark.parametrize(
    "world, path, expected",
    [
        ("  objects:\n    - {name: b, radius: -0.1}\n", "world.objects[0].radius", "positive"),
        ("  objects:\n    - {name: b, mass: -2}\n", "world.objects[0].mass", "positive"),
        ("  objects:\n    - {name: b, spin: 3}\n", "world.objects[0].spin", "unknown key"),
        ("  obstacles:\n    - {polygon: [[0, 0], [1, 0]], height: 1}\n",
         "world.obstacles[0].polygon", "at least 3 points"),
        ("  obstacles:\n    - {polygon: [[0, 0], [2, 0], [1, 0.5], [2, 2], [0, 2]], height: 1}\n",
         "world.obstacles[0].polygon", "convex"),
        ("  obstacles:\n    - {polygon: [[0, 0], [1, 0], [0, 1]]}\n", "world.obstacles[0]",
         "missing key 'height'"),
        ("  walls:\n    - {from: [0, 0], to: [1, 0], height: 1, texture: no_such.png}\n",
         "world.walls[0].texture", "no_such.png"),
        ("  floor: {texture: builtin:marble}\n", "world.floor.texture", "unknown builtin"),
        ("  gravity: -1\n", "world.gravity", "positive"),
        ("  wind: 3\n", "world.wind", "unknown key"),
        ("  objects: {name: b}\n", "world.objects", "expected a list"),
        ("  objects:\n    - {name: b, color: '#zz0000'}\n", "world.objects[0].color", "#rrggbb"),
    ],
)
def test_bad_world_values(tmp_path: Path, world: str, path: str, expected: str) -> None:
    err = error_of(write(tmp_path, world))
    assert err.message.startswith(path + ":"), err.message
    assert expected in err.message
    assert err.line >= 10


def test_camera_errors(tmp_path: Path) -> None:
    p = tmp_path / "c.yaml"
    p.write_text(CAMERA.replace("look_at: [0, 0, 0.5]", "look_at: [0, -3, 5]") + "world: {}\n")
    err = error_of(p)
    assert err.line == 9 and "camera.look_at" in err.message and "straight up" in err.message
    p.write_text(CAMERA.replace("look_at: [0, 0, 0.5]", "look_at: [0, -3, 1]") + "world: {}\n")
    assert "equals its position" in error_of(p).message
    p.write_text(CAMERA.replace("  fx: 500\n", "  fx: 500\n  zoom: 2\n") + "world: {}\n")
    assert error_of(p).message.startswith("camera.zoom: unknown key")
    p.write_text(CAMERA.replace("  width: 640\n", "") + "world: {}\n")
    assert "missing key 'width'" in error_of(p).message


def test_textures_resolve_relative_to_the_file_and_builtin_names(tmp_path: Path) -> None:
    import shutil

    from adapt.imagination.texture import texture_path

    (tmp_path / "tex").mkdir()
    shutil.copy(texture_path("builtin:grass"), tmp_path / "tex" / "g.png")
    p = write(tmp_path, """  floor: {texture: tex/g.png, tile: 2}
  walls:
    - {from: [0, 0], to: [1, 0], height: 1, texture: builtin:coffee}
    - {from: [1, 0], to: [1, 1], height: 1, texture: gravel}
""")
    scene = load_scenario(p).scene
    assert scene.floor.texture == str(tmp_path / "tex" / "g.png")
    assert [w.texture for w in scene.walls] == ["builtin:coffee", "builtin:gravel"]


def test_unknown_top_level_sections_are_errors_with_a_suggestion(tmp_path: Path) -> None:
    p = write(tmp_path, "  objects: [{name: b}]\n", "sede: 4\n")
    err = error_of(p)
    assert err.message.startswith("sede: unknown key (did you mean 'seed'?)")
    assert (err.line, err.col) == (12, 1)
    p = write(tmp_path, "  objects: [{name: b}]\n", "agent: {}\n")
    assert error_of(p).message.startswith("agent: unknown key; expected one of plugins, seed, camera")


def test_file_level_errors(tmp_path: Path) -> None:
    assert "no such scenario file" in str(error_of(tmp_path / "missing.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text("camera: [1, 2\nworld: {}\n")
    err = error_of(bad)
    assert "not valid YAML" in err.message and err.line == 2
    bad.write_text(CAMERA)
    assert "missing section 'world'" in error_of(bad).message
    bad.write_text("")
    assert "empty" in error_of(bad).message
    with pytest.raises(ScenarioError, match="duplicate key"):
        loads_scenario(CAMERA + "world: {}\nworld: {}\n")
    with pytest.raises(ScenarioError, match="seed: expected an integer"):
        loads_scenario(CAMERA + "world: {}\nseed: 1.5\n")


def test_the_example_in_docs_scenario_md_loads() -> None:
    import re

    doc = Path(__file__).resolve().parents[2] / "docs" / "scenario.md"
    example = re.search(r"```yaml\n(.*?)```", doc.read_text(encoding="utf-8"), re.S)
    assert example is not None
    sc = loads_scenario(example.group(1))
    assert sc.scene.walls[0].name == "north" and sc.scene.robot is not None


@pytest.mark.parametrize("block", [False, True], ids=["flow", "block"])
def test_yaml_nested_too_deeply_is_refused_at_its_place(tmp_path: Path, block: bool) -> None:
    """Issue 21: 500 levels used to end in a RecursionError (status 70)."""
    n = 500
    if block:
        deep = "".join(" " * i + f"k{i}:\n" for i in range(n)) + " " * n + "v: 1\n"
    else:
        deep = "x: " + "[" * n + "]" * n + "\n"
    path = write(tmp_path, "  walls: []\n", deep)
    err = error_of(path)
    assert "nests deeper than 64 levels" in str(err), err
    assert err.file == str(path) and err.line == (CAMERA + "world:\n").count("\n") + 2 + (
        63 if block else 0), err  # the 65th node down: a key in block style


def test_a_set_value_nested_too_deeply_is_refused_at_its_column(bundled: Scenario) -> None:
    value = "[" * 500 + "]" * 500
    with pytest.raises(ScenarioError) as info:
        load_scenario(bundled.path, overrides=[f"seed={value}"])
    err = info.value
    assert err.file == "--set" and err.col == len("seed=") + 65, err
    assert "nests deeper than 64 levels" in str(err)


@pytest.mark.parametrize("key, col", [("run..fps", 5), (".run.fps", 1), ("run.fps.", 8),
                                      ("world..objects[0].mass", 7)])
def test_an_empty_step_of_a_set_key_is_refused_at_its_column(bundled: Scenario, key: str,
                                                             col: int) -> None:
    """Issue 21: ``run..fps=3`` was taken as ``run.fps=3``."""
    with pytest.raises(ScenarioError, match="an empty key between dots") as info:
        load_scenario(bundled.path, overrides=[f"{key}=3"])
    assert (info.value.file, info.value.col) == ("--set", col), info.value


def test_the_engine_key_names_one_of_the_engines(tmp_path: Path) -> None:
    from adapt.scenario import EngineName

    assert load_scenario(write(tmp_path, "  objects: [{name: b}]\n")).engine is EngineName.ADAPT
    p = write(tmp_path, "  objects: [{name: b}]\n", "engine: soar\n")
    assert load_scenario(p).engine is EngineName.SOAR
    assert load_scenario(p, overrides=["engine=adapt"]).engine is EngineName.ADAPT
    err = error_of(write(tmp_path, "  objects: [{name: b}]\n", "engine: kernel\n"))
    assert err.message == "engine: expected one of 'adapt', 'soar', got 'kernel'"
    assert (err.line, err.col) == (12, 9)
