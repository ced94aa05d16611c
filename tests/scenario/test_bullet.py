"""The reader of a ``bullet`` reality: its keys, defaults, and the bad input it refuses at the
YAML position (no PyBullet needed)."""

from __future__ import annotations

import pytest

from adapt.errors import ScenarioError
from adapt.scenario import BulletReality, Range, TextureSource, loads_scenario
from adapt.scenario.bullet import OBJECT_DEFAULTS, SURFACE_DEFAULTS, inside_wall, wall_body

CAMERA = """camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
         position: [0, -2.4, 2.3], look_at: [0, 0.3, 0]}
"""
WORLD = """world:
  floor: {extent: [-1.5, -1.5, 1.5, 1.5]}
  walls:
    - {name: north, from: [-1.5, 1.5], to: [1.5, 1.5], height: 0.5}
    - {name: south, from: [1.5, -1.5], to: [-1.5, -1.5], height: 0.12}
  obstacles:
    - {name: crate, polygon: [[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], height: 0.3}
  objects:
    - {name: ball, radius: 0.1, create: when_seen}
"""
THROW = "{x: [-1, 1], y: [-1, 0], speed: [1, 2]}"


def read(reality: str = "", camera: str = CAMERA, world: str = WORLD) -> BulletReality:
    body = reality or f"  objects: [{{name: ball, throw: {THROW}}}]\n"
    sc = loads_scenario(camera + world + "reality:\n  kind: bullet\n" + body)
    assert isinstance(sc.reality, BulletReality)
    return sc.reality


def test_defaults_are_wide_ranges_and_a_world_object_keeps_its_look() -> None:
    r = read()
    assert r.dt == pytest.approx(1 / 960) and r.wall_thickness == 0.1
    assert r.walls.restitution == SURFACE_DEFAULTS["walls"]["restitution"]
    assert r.floor.friction == SURFACE_DEFAULTS["floor"]["friction"]
    ball = r.object("ball")
    assert ball.declared and ball.ball.radius == 0.1
    assert ball.spin == OBJECT_DEFAULTS["spin"] and ball.mass == Range.fixed(0.4)
    assert ball.throw is not None and ball.throw.height == Range.fixed(0.0)
    assert r.look.textures is TextureSource.MIXED and not r.look.shadows


def test_every_key_given() -> None:
    r = read("""  dt: 0.002
  wall_thickness: 0.2
  camera_offset: 0.02
  camera_offset_deg: [1, 0, 0]
  floor: {restitution: 0.4, friction: [0.6, 0.7], rolling_friction: 0.001, spinning_friction: 0}
  walls: {restitution: [0.8, 0.9]}
  obstacles: {friction: 0.2}
  look: {textures: procedural, texture_scale: 2, light_elevation_deg: [40, 60],
         light_azimuth_deg: 10, light_warmth: 0.1, ambient: 0.5, diffuse: 0.4, specular: 0,
         shadows: true, ball_marks: false, gain: 1.1, vignette: 0.2, blur: 1, noise: [2, 3]}
  objects:
    - {name: ball, mass: 0.5, restitution: 0.8, friction: 0.4, rolling_friction: 0.002,
       spinning_friction: 0.001, damping: 0.01, spin: [0, 1], side_spin: 3,
       throw: {t: [0.5, 1], x: 0, y: -1, speed: 2, heading_deg: 90, height: 0.3}}
    - {name: extra, radius: 0.05, color: [10, 200, 10], throw: {x: -1, y: 1}}
""")
    assert r.dt == 0.002 and r.wall_thickness == 0.2 and r.camera.random_position == 0.02
    assert r.floor.restitution == Range.fixed(0.4) and r.floor.friction == Range(0.6, 0.7)
    assert r.obstacles.friction == Range.fixed(0.2)
    assert r.obstacles.restitution == SURFACE_DEFAULTS["obstacles"]["restitution"]
    assert r.look.textures is TextureSource.PROCEDURAL and r.look.shadows and not r.look.ball_marks
    assert r.look.noise == Range(2, 3)
    ball = r.object("ball")
    assert ball.throw is not None and ball.throw.height == Range.fixed(0.3)
    assert ball.spin == Range(0, 1) and ball.side_spin == Range.fixed(3)
    extra = r.object("extra")
    assert not extra.declared and extra.ball.radius == 0.05 and extra.ball.color == (10, 200, 10)


@pytest.mark.parametrize(("reality", "where", "expected"), [
    ("  walls: {restitution: [0.9, 0.8]}\n", "reality.walls.restitution",
     "expected [low, high] with low <= high, got [0.9, 0.8]"),
    ("  walls: {restitution: []}\n", "reality.walls.restitution",
     "expected a number or [low, high], got a list"),
    ("  floor: {friction: [0.5]}\n", "reality.floor.friction", "expected a number or [low, high]"),
    ("  floor: {restitution: 1.5}\n", "reality.floor.restitution", "expected a number from 0 to 1"),
    ("  look: {blur: [1, 30]}\n", "reality.look.blur[1]",
     "expected a number from 0 to 20 pixels, got 30"),
    ("  look: {textures: wood}\n", "reality.look.textures", "expected one of 'scenario'"),
    ("  look: {glare: 1}\n", "reality.look.glare", "unknown key"),
    ("  dt: 0.5\n", "reality.dt", "expected a number from 1e-05 to 0.01 seconds"),
    ("  wall_thickness: 0\n", "reality.wall_thickness", "expected a positive number"),
    ("  robot: {slip: 0.1}\n", "reality.robot", "the world has no robot"),
    ("  appearance: {noise: 1}\n", "reality.appearance", "unknown key"),
    ("  objects: [{name: ball, throw: {x: 0.4, y: 0.4}}]\n", "reality.objects[0].throw",
     "the throw puts the ball 'ball' (radius 0.1 m) inside the obstacle 'crate'"),
    ("  objects: [{name: ball, throw: {x: [0.3, 0.5], y: [0.3, 0.5]}}]\n",
     "reality.objects[0].throw", "every position of the throw puts the ball 'ball'"),
    ("  objects: [{name: ball, throw: {x: 0, y: 1.45}}]\n", "reality.objects[0].throw",
     "inside the wall 'north'"),
    ("  objects: [{name: ball}]\n", "reality.objects[0]", "give a throw"),
    ("  objects: []\n", "world.objects[0]", "reality.objects must say when and how it appears"),
    ("  objects: [{name: ball, radius: 0.2, throw: {x: 0, y: 0}}]\n",
     "reality.objects[0].radius", "its radius is the world's"),
    ("  objects: [{name: ball, throw: {x: 0, y: 0, height: -1}}]\n",
     "reality.objects[0].throw.height", "expected a non-negative number"),
    ("  objects: [{name: ball, throw: " + THROW + "}, {name: ball, throw: " + THROW + "}]\n",
     "reality.objects[1]", "a second reality object called 'ball'"),
])
def test_bad_input_is_refused_at_its_position(reality: str, where: str, expected: str) -> None:
    if "objects" not in reality:
        reality += f"  objects: [{{name: ball, throw: {THROW}}}]\n"
    with pytest.raises(ScenarioError) as info:
        read(reality)
    message = str(info.value)
    assert f": {where}: " in message and expected in message, message
    assert message.startswith("<string>:")


@pytest.mark.parametrize(("position", "expected"), [
    ("[0, 1.55, 0.3]", "inside the wall 'north' (world.walls[0]: 0.5 m high, its real body 0.1 m "
                       "thick behind its line)"),
    ("[0, -1.58, 0.05]", "inside the wall 'south'"),
    ("[0.4, 0.4, 0.2]", "inside the obstacle 'crate'"),
    ("[0, -1.0, -0.1]", "the camera is below the floor (z = -0.1); expected a height above 0"),
])
def test_a_camera_inside_a_wall_or_an_obstacle_is_refused(position: str, expected: str) -> None:
    camera = CAMERA.replace("[0, -2.4, 2.3]", position)
    with pytest.raises(ScenarioError) as info:
        read(camera=camera)
    assert ": camera.position: " in str(info.value) and expected in str(info.value)


def test_a_camera_outside_above_a_low_wall_or_over_a_wall_is_accepted() -> None:
    read(camera=CAMERA.replace("[0, -2.4, 2.3]", "[0, -1.55, 0.2]"))  # above the 12 cm wall
    read(camera=CAMERA.replace("[0, -2.4, 2.3]", "[0.4, 0.4, 0.35]"))  # above the crate


def test_a_camera_on_the_robot_inside_its_body_is_refused() -> None:
    camera = """camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60, mount: robot,
         position: [0.0, 0, 0.2], look_at: [2, 0, 0]}
"""
    world = WORLD + "  robot: {position: [0, -0.8], max_speed: 1, max_accel: 2, height: 0.3}\n"
    with pytest.raises(ScenarioError, match="inside the robot's body"):
        read(camera=camera, world=world)
    read(camera=camera.replace("[0.0, 0, 0.2]", "[0.0, 0, 0.45]"), world=world)


def test_the_walls_stand_behind_their_line_away_from_the_arena() -> None:
    sc = loads_scenario(CAMERA + WORLD + f"reality:\n  kind: bullet\n  objects: [{{name: ball, "
                        f"throw: {THROW}}}]\n")
    north, south = sc.scene.walls
    assert max(y for _, y in wall_body(north, 0.1, (0, 0))) == pytest.approx(1.6)
    assert min(y for _, y in wall_body(south, 0.1, (0, 0))) == pytest.approx(-1.6)
    assert inside_wall(sc.scene, 0.1, (0.0, 1.55)) == 0
    assert inside_wall(sc.scene, 0.1, (0.0, 1.45)) is None
    assert inside_wall(sc.scene, 0.1, (0.0, -1.55, 0.13)) is None  # above the 12 cm wall


def _documented(heading: str) -> dict[str, str]:
    """key -> default cell of the table under ``heading`` in docs/scenario.md."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "scenario.md").read_text(encoding="utf-8")
    lines = text.split(f"### {heading}\n", 1)[1].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("|"))
    end = next(i for i in range(start, len(lines)) if not lines[i].startswith("|"))
    out = {}
    for line in lines[start + 2:end]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        out[cells[0].strip("`")] = cells[2]
    return out


def _cell(r: Range) -> str:
    return f"{r.low:g}" if r.is_fixed else f"`[{r.low!r}, {r.high!r}]`"


def test_the_documented_defaults_are_the_readers() -> None:
    from adapt.scenario import BulletLook

    look = _documented("`reality.look` (bullet)")
    defaults = BulletLook()
    for key, cell in look.items():
        value = getattr(defaults, key)
        if isinstance(value, Range):
            assert cell == _cell(value).replace(".0,", ",").replace(".0]", "]") or \
                cell == _cell(value), (key, cell, value)
    assert look["textures"] == "`mixed`" and look["shadows"] == "false"
    objects = _documented("`reality.objects[i]` (bullet)")
    for key, r in OBJECT_DEFAULTS.items():
        assert objects[key] in (_cell(r), _cell(r).replace(".0,", ",").replace(".0]", "]")), key
    surfaces = _documented("`reality.floor`, `reality.walls` and `reality.obstacles` (bullet)")
    for key in ("restitution", "friction"):
        cells = [c.strip() for c in surfaces[key].split("/")]
        assert cells == [_cell(SURFACE_DEFAULTS[g][key]) for g in ("floor", "walls", "obstacles")]
    assert surfaces["rolling_friction"] == "0" and surfaces["spinning_friction"] == "0"
