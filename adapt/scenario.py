"""Scenario files: the only YAML reader of adapt.

A scenario is a YAML mapping.  This module reads its ``seed``, ``camera`` and
``world`` sections (documented key by key in ``docs/scenario.md``) into frozen
records; any other top-level section is kept, unread, in
:attr:`Scenario.extra` for the layers that own it (the scenario runner).

Every error is a :class:`~adapt.errors.ScenarioError` that names
``file:line:col`` of the offending key or value, its key path
(``world.walls[2].height``) and what was expected.

Textures resolve relative to the YAML file; a bare name of a bundled texture
(``brick``) or ``builtin:brick`` means the texture shipped with adapt.

Examples
--------
>>> text = '''
... camera: {fx: 500, fy: 500, cx: 320, cy: 240, width: 640, height: 480,
...          position: [0, -3, 1], look_at: [0, 0, 0.5]}
... world:
...   walls: [{from: [-2, 1], to: [2, 1], height: 1.0, texture: brick}]
...   objects: [{name: ball, radius: 0.1, velocity: [1, 0]}]
... '''
>>> sc = loads_scenario(text)
>>> sc.scene.walls[0].texture, sc.scene.balls[0].velocity, sc.camera.width
('builtin:brick', (1.0, 0.0), 640)
>>> loads_scenario(text.replace("height: 1.0", "height: -1"))
Traceback (most recent call last):
...
adapt.errors.ScenarioError: <string>:5:47: world.walls[0].height: expected a positive number, got -1
...
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import yaml

from adapt.errors import ImaginationError, ScenarioError
from adapt.geometry import Camera
from adapt.imagination.scene import (
    BUILTIN_TEXTURES,
    DEFAULT_DT,
    Ball,
    Floor,
    Obstacle,
    RobotSpec,
    SceneSpec,
    Wall,
    check_convex_polygon,
)

__all__ = ["Scenario", "load_scenario", "loads_scenario"]


@dataclass(frozen=True, slots=True, eq=False)
class Scenario:
    """A loaded scenario.

    Attributes
    ----------
    path : Path or None
        The YAML file (``None`` for text not read from a file).
    camera : Camera
        The camera of the ``camera`` section.
    scene : SceneSpec
        The ``world`` section.
    seed : int or None
        The top-level ``seed``.
    extra : dict
        Top-level sections other than ``seed``, ``camera`` and ``world``, as
        plain Python data, for the layers that read them.
    """

    path: Path | None
    camera: Camera
    scene: SceneSpec
    seed: int | None = None
    extra: dict[str, Any] = field(default_factory=dict)


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario YAML file.

    Raises
    ------
    ScenarioError
        If the file is missing, is not YAML, or a key or value is wrong.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ScenarioError("no such scenario file", file=str(path), line=1, col=1) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"cannot read the scenario: {exc}", file=str(path)) from None
    return loads_scenario(text, file=str(path), base=p.resolve().parent, path=p)


def loads_scenario(
    text: str, *, file: str = "<string>", base: Path | None = None, path: Path | None = None
) -> Scenario:
    """Read a scenario from YAML text; textures resolve relative to ``base``
    (default: the current directory)."""
    return _Reader(text, file, base or Path.cwd()).read(path)


# -- reading ----------------------------------------------------------------------

_Node = yaml.Node


class _Reader:
    def __init__(self, text: str, file: str, base: Path) -> None:
        self.text = text
        self.lines = text.splitlines()
        self.file = file
        self.base = base
        self.loader = yaml.SafeLoader(text)

    # errors

    def error(self, node: _Node | None, path: str, message: str) -> ScenarioError:
        line, col = 1, 1
        if node is not None:
            line, col = node.start_mark.line + 1, node.start_mark.column + 1
        src = self.lines[line - 1] if 0 < line <= len(self.lines) else None
        prefix = f"{path}: " if path else ""
        return ScenarioError(prefix + message, file=self.file, line=line, col=col, source_line=src)

    def scalar(self, node: _Node) -> Any:
        return self.loader.construct_object(node, deep=True)

    def mapping(self, node: _Node, path: str) -> dict[str, tuple[_Node, _Node]]:
        """Keys of a mapping node -> (key node, value node); rejects duplicates."""
        if not isinstance(node, yaml.MappingNode):
            raise self.error(node, path, f"expected a mapping, got {self.describe(node)}")
        out: dict[str, tuple[_Node, _Node]] = {}
        for k, v in node.value:
            key = self.scalar(k) if isinstance(k, yaml.ScalarNode) else None
            if not isinstance(key, str):
                raise self.error(k, path, "expected a string key")
            if key in out:
                raise self.error(k, _join(path, key), "duplicate key")
            out[key] = (k, v)
        return out

    def describe(self, node: _Node) -> str:
        if isinstance(node, yaml.MappingNode):
            return "a mapping"
        if isinstance(node, yaml.SequenceNode):
            return "a list"
        return repr(self.scalar(node))

    def check_keys(
        self, items: dict[str, tuple[_Node, _Node]], allowed: tuple[str, ...], path: str
    ) -> None:
        for key, (knode, _) in items.items():
            if key not in allowed:
                raise self.error(
                    knode, _join(path, key),
                    "unknown key; expected one of " + ", ".join(allowed),
                )

    # typed values

    def number(self, node: _Node, path: str, check: str = "") -> float:
        value = self.scalar(node) if isinstance(node, yaml.ScalarNode) else None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(node, path, f"expected a number, got {self.describe(node)}")
        v = float(value)
        if check == "positive" and v <= 0:
            raise self.error(node, path, f"expected a positive number, got {value!r}")
        if check == "nonnegative" and v < 0:
            raise self.error(node, path, f"expected a non-negative number, got {value!r}")
        if check == "unit" and not 0 <= v <= 1:
            raise self.error(node, path, f"expected a number from 0 to 1, got {value!r}")
        return v

    def integer(self, node: _Node, path: str, check: str = "") -> int:
        value = self.scalar(node) if isinstance(node, yaml.ScalarNode) else None
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(node, path, f"expected an integer, got {self.describe(node)}")
        if check == "positive" and value <= 0:
            raise self.error(node, path, f"expected a positive integer, got {value!r}")
        return value

    def vector(self, node: _Node, path: str, n: int) -> tuple[float, ...]:
        names = "[x, y]" if n == 2 else "[x, y, z]" if n == 3 else f"{n} numbers"
        if not isinstance(node, yaml.SequenceNode) or len(node.value) != n:
            raise self.error(node, path, f"expected {names}, got {self.describe(node)}")
        return tuple(self.number(v, f"{path}[{i}]") for i, v in enumerate(node.value))

    def string(self, node: _Node, path: str) -> str:
        value = self.scalar(node) if isinstance(node, yaml.ScalarNode) else None
        if not isinstance(value, str) or not value:
            raise self.error(node, path, f"expected a string, got {self.describe(node)}")
        return value

    def color(self, node: _Node, path: str) -> tuple[int, int, int]:
        if isinstance(node, yaml.ScalarNode):
            value = self.scalar(node)
            if isinstance(value, str) and len(value) == 7 and value.startswith("#"):
                try:
                    return (int(value[1:3], 16), int(value[3:5], 16), int(value[5:7], 16))
                except ValueError:
                    pass
            raise self.error(node, path, f"expected [r, g, b] or '#rrggbb', got {value!r}")
        rgb = self.vector(node, path, 3)
        for i, c in enumerate(rgb):
            if not 0 <= c <= 255:
                raise self.error(node.value[i], f"{path}[{i}]", f"expected 0..255, got {c:g}")
        return (int(rgb[0]), int(rgb[1]), int(rgb[2]))

    def texture(self, node: _Node, path: str) -> str:
        value = self.string(node, path)
        if value.startswith("builtin:"):
            name = value[len("builtin:"):]
            if name not in BUILTIN_TEXTURES:
                raise self.error(
                    node, path,
                    f"unknown builtin texture {name!r}; expected one of {', '.join(BUILTIN_TEXTURES)}",
                )
            return value
        if value in BUILTIN_TEXTURES:
            return f"builtin:{value}"
        p = Path(value).expanduser()
        if not p.is_absolute():
            p = self.base / p
        if not p.is_file():
            raise self.error(
                node, path,
                f"texture file {str(p)!r} not found; expected an image file (relative to the "
                f"scenario) or a bundled texture ({', '.join(BUILTIN_TEXTURES)})",
            )
        return str(p)

    def polygon(self, node: _Node, path: str) -> tuple[tuple[float, float], ...]:
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(node, path, f"expected a list of [x, y] points, got {self.describe(node)}")
        pts = [self.vector(v, f"{path}[{i}]", 2) for i, v in enumerate(node.value)]
        try:
            return check_convex_polygon("polygon", pts)  # type: ignore[arg-type]
        except ImaginationError as exc:
            raise self.error(node, path, str(exc).removeprefix("polygon: ")) from None

    # records

    def fields(
        self,
        node: _Node,
        path: str,
        spec: dict[str, Callable[[_Node, str], Any]],
        required: tuple[str, ...] = (),
    ) -> dict[str, Any]:
        items = self.mapping(node, path)
        self.check_keys(items, tuple(spec), path)
        for key in required:
            if key not in items:
                raise self.error(node, path, f"missing key {key!r}")
        return {key: spec[key](v, _join(path, key)) for key, (_, v) in items.items()}

    def build(self, cls: Callable[..., Any], node: _Node, path: str, kwargs: dict[str, Any],
              keymap: dict[str, str] | None = None) -> Any:
        try:
            return cls(**kwargs)
        except ImaginationError as exc:
            # Records name the field first: "radius: expected ...".
            msg = str(exc)
            field_name, _, rest = msg.partition(": ")
            items = self.mapping(node, path) if isinstance(node, yaml.MappingNode) else {}
            yaml_key = {v: k for k, v in (keymap or {}).items()}.get(field_name, field_name)
            if yaml_key in items:
                raise self.error(items[yaml_key][1], _join(path, yaml_key), rest) from None
            raise self.error(node, path, msg) from None

    def read(self, path: Path | None) -> Scenario:
        try:
            root = self.loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
            src = self.lines[line - 1] if 0 < line <= len(self.lines) else None
            raise ScenarioError(
                f"not valid YAML: {exc.problem or exc}", file=self.file, line=line, col=col,
                source_line=src,
            ) from None
        except yaml.YAMLError as exc:
            raise ScenarioError(f"not valid YAML: {exc}", file=self.file) from None
        if root is None:
            raise ScenarioError("the scenario is empty; expected a mapping with 'camera' and 'world'",
                                file=self.file)
        top = self.mapping(root, "")
        for key in ("camera", "world"):
            if key not in top:
                raise self.error(root, "", f"missing section {key!r}")
        seed = None
        if "seed" in top:
            seed = self.integer(top["seed"][1], "seed")
        camera = self.camera(top["camera"][1], "camera")
        scene = self.world(top["world"][1], "world")
        extra = {
            key: self.scalar(v) for key, (_, v) in top.items()
            if key not in ("seed", "camera", "world")
        }
        return Scenario(path=path, camera=camera, scene=scene, seed=seed, extra=extra)

    def camera(self, node: _Node, path: str) -> Camera:
        num = self.number
        spec: dict[str, Callable[[_Node, str], Any]] = {
            "fx": lambda n, p: num(n, p, "positive"),
            "fy": lambda n, p: num(n, p, "positive"),
            "cx": num,
            "cy": num,
            "width": lambda n, p: self.integer(n, p, "positive"),
            "height": lambda n, p: self.integer(n, p, "positive"),
            "position": lambda n, p: self.vector(n, p, 3),
            "look_at": lambda n, p: self.vector(n, p, 3),
            "roll_deg": num,
        }
        kw = self.fields(node, path, spec,
                         required=("fx", "fy", "cx", "cy", "width", "height", "position", "look_at"))
        try:
            return Camera.look_at(**kw)
        except ImaginationError as exc:
            items = self.mapping(node, path)
            raise self.error(items["look_at"][1], f"{path}.look_at", str(exc)) from None

    def world(self, node: _Node, path: str) -> SceneSpec:
        items = self.mapping(node, path)
        self.check_keys(items, ("floor", "walls", "obstacles", "objects", "robot", "gravity", "dt"), path)
        kw: dict[str, Any] = {}
        if "gravity" in items:
            kw["gravity"] = self.number(items["gravity"][1], f"{path}.gravity", "positive")
        kw["dt"] = DEFAULT_DT
        if "dt" in items:
            kw["dt"] = self.number(items["dt"][1], f"{path}.dt", "positive")
        if "floor" in items:
            kw["floor"] = self.floor(items["floor"][1], f"{path}.floor")
        kw["walls"] = tuple(self.listed(items, "walls", path, self.wall))
        kw["obstacles"] = tuple(self.listed(items, "obstacles", path, self.obstacle))
        kw["balls"] = tuple(self.listed(items, "objects", path, self.ball))
        if "robot" in items:
            kw["robot"] = self.robot(items["robot"][1], f"{path}.robot")
        try:
            return SceneSpec(**kw)
        except ImaginationError as exc:
            raise self.error(node, path, str(exc)) from None

    def listed(self, items: dict[str, tuple[_Node, _Node]], key: str, path: str,
               read: Callable[[_Node, str, int], Any]) -> list[Any]:
        if key not in items:
            return []
        node = items[key][1]
        if isinstance(node, yaml.ScalarNode) and self.scalar(node) is None:
            return []
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(node, f"{path}.{key}", f"expected a list, got {self.describe(node)}")
        return [read(v, f"{path}.{key}[{i}]", i) for i, v in enumerate(node.value)]

    def _surface_spec(self) -> dict[str, Callable[[_Node, str], Any]]:
        return {
            "name": self.string,
            "height": lambda n, p: self.number(n, p, "positive"),
            "texture": self.texture,
            "tile": lambda n, p: self.number(n, p, "positive"),
            "color": self.color,
            "restitution": lambda n, p: self.number(n, p, "unit"),
            "friction": lambda n, p: self.number(n, p, "nonnegative"),
        }

    def floor(self, node: _Node, path: str) -> Floor:
        spec = {
            "texture": self.texture,
            "tile": lambda n, p: self.number(n, p, "positive"),
            "color": self.color,
            "extent": lambda n, p: self.vector(n, p, 4),
        }
        kw = self.fields(node, path, spec)
        if "color" in kw and "texture" not in kw:
            kw["texture"] = None
        return self.build(Floor, node, path, kw)  # type: ignore[no-any-return]

    def wall(self, node: _Node, path: str, index: int) -> Wall:
        spec = self._surface_spec()
        spec["from"] = lambda n, p: self.vector(n, p, 2)
        spec["to"] = lambda n, p: self.vector(n, p, 2)
        kw = self.fields(node, path, spec, required=("from", "to", "height"))
        kw.setdefault("name", f"wall{index}")
        kw["start"] = kw.pop("from")
        kw["end"] = kw.pop("to")
        return self.build(Wall, node, path, kw, {"from": "from", "to": "to"})  # type: ignore[no-any-return]

    def obstacle(self, node: _Node, path: str, index: int) -> Obstacle:
        spec = self._surface_spec()
        spec["polygon"] = self.polygon
        kw = self.fields(node, path, spec, required=("polygon", "height"))
        kw.setdefault("name", f"obstacle{index}")
        return self.build(Obstacle, node, path, kw)  # type: ignore[no-any-return]

    def ball(self, node: _Node, path: str, index: int) -> Ball:
        spec: dict[str, Callable[[_Node, str], Any]] = {
            "name": self.string,
            "radius": lambda n, p: self.number(n, p, "positive"),
            "mass": lambda n, p: self.number(n, p, "positive"),
            "restitution": lambda n, p: self.number(n, p, "unit"),
            "friction": lambda n, p: self.number(n, p, "nonnegative"),
            "rolling_resistance": lambda n, p: self.number(n, p, "nonnegative"),
            "position": lambda n, p: self.vector(n, p, 2),
            "velocity": lambda n, p: self.vector(n, p, 2),
            "color": self.color,
            "texture": self.texture,
        }
        kw = self.fields(node, path, spec, required=("name",))
        return self.build(Ball, node, path, kw)  # type: ignore[no-any-return]

    def robot(self, node: _Node, path: str) -> RobotSpec:
        def shape(n: _Node, p: str) -> str:
            v = self.string(n, p)
            if v not in ("disc", "box"):
                raise self.error(n, p, f"expected 'disc' or 'box', got {v!r}")
            return v

        spec: dict[str, Callable[[_Node, str], Any]] = {
            "name": self.string,
            "shape": shape,
            "radius": lambda n, p: self.number(n, p, "positive"),
            "size": lambda n, p: self.vector(n, p, 2),
            "position": lambda n, p: self.vector(n, p, 2),
            "heading_deg": self.number,
            "max_speed": lambda n, p: self.number(n, p, "positive"),
            "max_accel": lambda n, p: self.number(n, p, "positive"),
            "mass": lambda n, p: self.number(n, p, "positive"),
            "height": lambda n, p: self.number(n, p, "positive"),
            "color": self.color,
        }
        kw = self.fields(node, path, spec, required=("max_speed", "max_accel"))
        return self.build(RobotSpec, node, path, kw)  # type: ignore[no-any-return]


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key
