"""Reading the ``camera`` and ``world`` sections (see ``docs/scenario.md``).

The world becomes the imagination's :class:`~adapt.imagination.scene.SceneSpec`
(with only the objects that are in the imagination from the start) plus one
:class:`~adapt.scenario.records.ObjectModel` per declared object; the camera
becomes an :class:`~adapt.geometry.Camera` at its starting pose and a
:class:`~adapt.scenario.records.CameraMount`.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Protocol, Sequence, TypeVar

import yaml

from adapt.errors import ImaginationError, ScenarioError
from adapt.geometry import MAX_PIXELS, Camera
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
from adapt.lens import DISTORTION_LENGTHS, Lens
from adapt.scenario.bounds import CHANNEL, bound_of
from adapt.scenario.calibration import read_calibration
from adapt.scenario.nodes import Node, NodeReader, join
from adapt.scenario.records import (
    MODEL_RANGE_PARAMETERS,
    CameraMount,
    Creation,
    Mount,
    ObjectModel,
    Range,
    Source,
)

__all__ = ["WorldReader", "CAMERA_KEYS", "CALIBRATED_KEYS", "WORLD_KEYS", "FLOOR_KEYS", "WALL_KEYS",
           "OBSTACLE_KEYS", "OBJECT_KEYS", "ROBOT_KEYS"]

CAMERA_KEYS = ("fx", "fy", "cx", "cy", "width", "height", "position", "look_at", "roll_deg",
               "mount", "distortion", "calibration")
#: The camera keys a calibration file gives (``camera.calibration``).
CALIBRATED_KEYS = ("fx", "fy", "cx", "cy", "width", "height")
WORLD_KEYS = ("floor", "walls", "obstacles", "objects", "robot", "gravity", "dt", "appearance")
FLOOR_KEYS = ("texture", "tile", "color", "extent")
WALL_KEYS = ("name", "from", "to", "height", "texture", "tile", "color", "restitution", "friction")
OBSTACLE_KEYS = ("name", "polygon", "height", "texture", "tile", "color", "restitution", "friction")
OBJECT_KEYS = ("name", "radius", "mass", "restitution", "friction", "rolling_resistance",
               "floor_friction", "drag", "position", "velocity", "color", "texture", "create",
               "ranges")
ROBOT_KEYS = ("name", "shape", "radius", "size", "position", "heading_deg", "max_speed",
              "max_accel", "mass", "height", "color")


class _Named(Protocol):
    """An object of reality, whichever the kind: its name and where it is written."""

    @property
    def name(self) -> str: ...

    @property
    def source(self) -> Source: ...


_Real = TypeVar("_Real", bound=_Named)


class WorldReader(NodeReader):
    """The ``camera`` and ``world`` sections."""

    # -- values of the world ------------------------------------------------------------

    def color(self, node: Node, path: str) -> tuple[int, int, int]:
        """``[r, g, b]`` (0..255) or ``'#rrggbb'``."""
        self.source(node, path)
        if isinstance(node, yaml.ScalarNode):
            value = self.scalar(node, path)
            if isinstance(value, str) and len(value) == 7 and value.startswith("#"):
                try:
                    return (int(value[1:3], 16), int(value[3:5], 16), int(value[5:7], 16))
                except ValueError:
                    pass
            raise self.error(node, path, f"expected [r, g, b] or '#rrggbb', got {value!r}")
        rgb = self.vector(node, path, 3, CHANNEL)
        return (int(rgb[0]), int(rgb[1]), int(rgb[2]))

    def texture(self, node: Node, path: str) -> str:
        """A bundled texture name (``brick`` or ``builtin:brick``) or an image file."""
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

    def polygon(self, node: Node, path: str) -> tuple[tuple[float, float], ...]:
        """A convex polygon of ``[x, y]`` points."""
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(node, path, f"expected a list of [x, y] points, got {self.describe(node)}")
        each = bound_of(path)
        pts = [self.vector(v, join(path, i), 2, each) for i, v in enumerate(node.value)]
        try:
            return check_convex_polygon("polygon", pts)  # type: ignore[arg-type]
        except ImaginationError as exc:
            raise self.error(node, path, str(exc).removeprefix("polygon: ")) from None

    def build(self, cls: Callable[..., Any], node: Node, path: str, kwargs: dict[str, Any],
              keymap: dict[str, str] | None = None) -> Any:
        """``cls(**kwargs)``; an :class:`ImaginationError` naming a field
        (``"radius: ..."``) is reported at that field's node."""
        try:
            return cls(**kwargs)
        except ImaginationError as exc:
            msg = str(exc)
            field_name, _, rest = msg.partition(": ")
            items = self.mapping(node, path) if isinstance(node, yaml.MappingNode) else {}
            yaml_key = {v: k for k, v in (keymap or {}).items()}.get(field_name, field_name)
            if yaml_key in items:
                raise self.error(items[yaml_key][1], join(path, yaml_key), rest) from None
            raise self.error(node, path, msg) from None

    # -- the camera ------------------------------------------------------------------------

    def camera(self, node: Node, path: str, robot: RobotSpec | None) -> tuple[Camera, CameraMount]:
        """The camera at its starting pose, and how it is mounted."""
        camera, mount, _ = self.camera_and_lens(node, path, robot)
        return camera, mount

    def camera_and_lens(self, node: Node, path: str, robot: RobotSpec | None
                        ) -> tuple[Camera, CameraMount, Lens | None]:
        """The camera at its starting pose, how it is mounted, and its lens (None without
        ``distortion`` or ``calibration``)."""
        num = self.number
        spec: dict[str, Callable[[Node, str], Any]] = {
            "fx": num,
            "fy": num,
            "cx": num,
            "cy": num,
            "width": self.integer,
            "height": self.integer,
            "position": lambda n, p: self.vector(n, p, 3),
            "look_at": lambda n, p: self.vector(n, p, 3),
            "roll_deg": num,
            "mount": lambda n, p: self.choice(n, p, [m.value for m in Mount]),
            "distortion": self.distortion,
            "calibration": lambda n, p: self.existing_file(n, p, "calibration file"),
        }
        items = self.mapping(node, path)
        calibrated = "calibration" in items
        kw = self.fields(node, path, spec, required=("position", "look_at") if calibrated else
                         ("fx", "fy", "cx", "cy", "width", "height", "position", "look_at"))
        lens: Lens | None = None
        if calibrated:
            for key in (*CALIBRATED_KEYS, "distortion"):
                if key in items:
                    raise self.error(items[key][0], join(path, key), "the calibration file "
                                     "gives the camera's intrinsics and distortion; remove this key")
            cpath = join(path, "calibration")
            file = kw.pop("calibration")
            try:
                lens = read_calibration(file)
            except ScenarioError as exc:  # at the file's line, and where the scenario names it
                named = self.source(items["calibration"][1], cpath)
                raise ScenarioError(f"{exc.message} (the {cpath} of {named.location})",
                                    file=exc.file, line=exc.line, col=exc.col,
                                    source_line=exc.source_line) from None
            kw["fx"], kw["fy"], kw["cx"], kw["cy"] = lens.intrinsics
            kw["width"], kw["height"] = lens.size
        elif "distortion" in kw:
            lens = Lens.pinhole(kw["fx"], kw["fy"], kw["cx"], kw["cy"],
                                (kw["width"], kw["height"]), kw.pop("distortion"))
        kind = Mount(kw.pop("mount", Mount.FIXED.value))
        mount = CameraMount(kind, kw["position"], kw["look_at"], kw.get("roll_deg", 0.0),
                            self.source(node, path))
        if kind is Mount.ROBOT:
            if robot is None:
                raise self.error(items["mount"][1], join(path, "mount"),
                                 "a camera on the robot needs a world.robot")
            pos, target = mount.world_pose(robot.position, math.radians(robot.heading_deg))
            kw["position"], kw["look_at"] = tuple(pos), tuple(target)
        if kw["position"][2] <= 0:
            key = "position"
            raise self.error(items[key][1], join(path, key),
                             f"the camera is {'on' if kw['position'][2] == 0 else 'below'} the "
                             f"floor (z = {kw['position'][2]:g}); expected a height above 0")
        if kw["width"] * kw["height"] > MAX_PIXELS:
            raise self.error(items["height"][1], join(path, "height"),
                             f"{kw['width']}x{kw['height']} is {kw['width'] * kw['height']:,} "
                             f"pixels; expected at most {MAX_PIXELS:,} (for example 4096x4096)")
        try:
            camera = Camera.look_at(**kw)
        except ImaginationError as exc:  # at the key the camera names (a robot's camera: the world's)
            name, sep, rest = str(exc).partition(": ")
            key = name if sep and name in items else "look_at"
            raise self.error(items[key][1], join(path, key),
                             rest if name == key else str(exc)) from None
        return camera, mount, lens

    def distortion(self, node: Node, path: str) -> tuple[float, ...]:
        """``[k1, k2, p1, p2]``, ``+ [k3]`` or ``+ [k3, k4, k5, k6]`` (OpenCV's order)."""
        if not isinstance(node, yaml.SequenceNode) or len(node.value) not in DISTORTION_LENGTHS:
            got = (f"{len(node.value)} values" if isinstance(node, yaml.SequenceNode)
                   else self.describe(node))
            raise self.error(node, path, "expected [k1, k2, p1, p2, k3] (4, 5 or 8 numbers in "
                             f"OpenCV's order), got {got}")
        each = bound_of(path)  # one bound for every coefficient
        return tuple(self.number(v, join(path, i), each) for i, v in enumerate(node.value))

    def reality_objects(self, node: Node | None, path: str, models: Sequence[ObjectModel],
                        read: Callable[[Node, str, dict[str, ObjectModel]], _Real],
                        from_model: Callable[[ObjectModel], _Real]) -> tuple[_Real, ...]:
        """The objects of a ``reality`` section (``node``: its ``objects`` list, or None): those
        it gives (``read``), in the world's order, then every other world object as its model
        says (``from_model``), then the objects of reality only, in the file's order.

        Raises
        ------
        ScenarioError
            An object given twice, or one created when seen that the section does not give.
        """
        given: dict[str, _Real] = {}
        if node is not None:
            by_name = {m.name: m for m in models}
            for obj in self.listed(node, path, lambda n, p, i: read(n, p, by_name)):
                if obj.name in given:
                    raise obj.source.error(f"a second reality object called {obj.name!r}")
                given[obj.name] = obj
        objects: list[_Real] = []
        for m in models:
            if m.name in given:
                objects.append(given.pop(m.name))
                continue
            if m.create is Creation.WHEN_SEEN:
                raise m.source.error(
                    f"object {m.name!r} is created when seen; reality.objects must say when and "
                    "how it appears (a throw)")
            objects.append(from_model(m))
        objects.extend(given.values())
        return tuple(objects)

    def reality_object(self, node: Node, path: str, keys: Sequence[str],
                       models: dict[str, ObjectModel], number: Callable[[Node, str], float]
                       ) -> tuple[dict[str, tuple[Node, Node]], str, ObjectModel | None,
                                  dict[str, Any]]:
        """What every kind's ``reality.objects[i]`` starts with: its keys (checked against
        ``keys``), its name, the world object of that name (None: an object of reality only)
        and the look it gives (``radius``, read with ``number``, only for an object of reality
        only; ``color``; ``texture``)."""
        items = self.mapping(node, path)
        self.check_keys(items, keys, path)
        if "name" not in items:
            raise self.error(node, path, "missing key 'name' (a world object's name, or a new name "
                             "for an object that exists in reality only)")
        name = self.string(items["name"][1], join(path, "name"))
        model = models.get(name)
        look: dict[str, Any] = {}
        if "radius" in items:
            if model is not None:
                raise self.error(items["radius"][0], join(path, "radius"),
                                 f"{name!r} is a world object: its radius is the world's; remove "
                                 "this key")
            look["radius"] = number(items["radius"][1], join(path, "radius"))
        if "color" in items:
            look["color"] = self.color(items["color"][1], join(path, "color"))
        if "texture" in items:
            look["texture"] = self.texture(items["texture"][1], join(path, "texture"))
        return items, name, model, look

    # -- the world ----------------------------------------------------------------------------

    def world(self, node: Node, path: str) -> tuple[SceneSpec, tuple[ObjectModel, ...]]:
        """The imagination's starting scene and the models of every declared object."""
        items = self.mapping(node, path)
        self.check_keys(items, WORLD_KEYS, path)
        kw: dict[str, Any] = {}
        if "gravity" in items:
            kw["gravity"] = self.number(items["gravity"][1], join(path, "gravity"))
        kw["dt"] = DEFAULT_DT
        if "dt" in items:
            kw["dt"] = self.number(items["dt"][1], join(path, "dt"))
        if "floor" in items:
            kw["floor"] = self.floor(items["floor"][1], join(path, "floor"))

        def listed(key: str, read: Callable[[Node, str, int], Any]) -> list[Any]:
            return self.listed(items[key][1], join(path, key), read) if key in items else []

        kw["walls"] = tuple(listed("walls", self.wall))
        kw["obstacles"] = tuple(listed("obstacles", self.obstacle))
        models = tuple(listed("objects", self.object_model))
        seen: dict[str, str] = {}
        for i, m in enumerate(models):
            where = join(join(path, "objects"), i)
            if m.name in seen:
                raise self.error(items["objects"][1].value[i], where,
                                 f"a second object called {m.name!r} (the first is {seen[m.name]})")
            seen[m.name] = where
        kw["balls"] = tuple(m.ball for m in models if m.create is Creation.AT_START)
        if "robot" in items:
            kw["robot"] = self.robot(items["robot"][1], join(path, "robot"))
        try:
            scene = SceneSpec(**kw)
        except ImaginationError as exc:
            raise self.error(node, path, str(exc)) from None
        return scene, models

    def world_appearance(self, node: Node, path: str) -> Path | None:
        """``world.appearance``: a folder of learned surface looks (``index.json``
        and images, as ``adapt run`` writes into ``appearance/``), or None."""
        items = self.mapping(node, path)
        if "appearance" not in items or self.is_null(items["appearance"][1]):
            return None
        key = join(path, "appearance")
        value = items["appearance"][1]
        folder = self.path_value(value, key)
        if not folder.is_dir():
            raise self.error(value, key, f"appearance folder {str(folder)!r} not found; expected "
                             "a folder written by `adapt run` (its appearance/ folder), relative "
                             "to the scenario")
        if not (folder / "index.json").is_file():
            raise self.error(value, key, f"{str(folder)!r} has no index.json; expected a folder "
                             "written by `adapt run` (its appearance/ folder)")
        return folder

    def floor(self, node: Node, path: str) -> Floor:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "texture": self.texture,
            "tile": self.number,
            "color": self.color,
            "extent": lambda n, p: self.vector(n, p, 4),
        }
        kw = self.fields(node, path, spec)
        if "color" in kw and "texture" not in kw:
            kw["texture"] = None
        return self.build(Floor, node, path, kw)  # type: ignore[no-any-return]

    def _surface_spec(self) -> dict[str, Callable[[Node, str], Any]]:
        return {
            "name": self.string,
            "height": self.number,
            "texture": self.texture,
            "tile": self.number,
            "color": self.color,
            "restitution": self.number,
            "friction": self.number,
        }

    def wall(self, node: Node, path: str, index: int) -> Wall:
        spec = self._surface_spec()
        spec["from"] = lambda n, p: self.vector(n, p, 2)
        spec["to"] = lambda n, p: self.vector(n, p, 2)
        spec = {k: spec[k] for k in WALL_KEYS}
        kw = self.fields(node, path, spec, required=("from", "to", "height"))
        kw.setdefault("name", f"wall{index}")
        kw["start"] = kw.pop("from")
        kw["end"] = kw.pop("to")
        return self.build(Wall, node, path, kw, {"from": "from", "to": "to"})  # type: ignore[no-any-return]

    def obstacle(self, node: Node, path: str, index: int) -> Obstacle:
        spec = self._surface_spec()
        spec["polygon"] = self.polygon
        spec = {k: spec[k] for k in OBSTACLE_KEYS}
        kw = self.fields(node, path, spec, required=("polygon", "height"))
        kw.setdefault("name", f"obstacle{index}")
        return self.build(Obstacle, node, path, kw)  # type: ignore[no-any-return]

    def object_model(self, node: Node, path: str, index: int) -> ObjectModel:
        """One ``world.objects[i]``: a ball model and what is known of it."""
        spec: dict[str, Callable[[Node, str], Any]] = {
            "name": self.string,
            "radius": self.number,
            "mass": self.number,
            "restitution": self.number,
            "friction": self.number,
            "rolling_resistance": self.number,
            "floor_friction": self.number,
            "drag": self.number,
            "position": lambda n, p: self.vector(n, p, 2),
            "velocity": lambda n, p: self.vector(n, p, 2),
            "color": self.color,
            "texture": self.texture,
            "create": lambda n, p: self.choice(n, p, [c.value for c in Creation]),
            "ranges": self.model_ranges,
        }
        kw = self.fields(node, path, spec, required=("name",))
        items = self.mapping(node, path)
        create = Creation(kw.pop("create", Creation.AT_START.value))
        ranges: dict[str, Range] = kw.pop("ranges", {})
        if create is Creation.WHEN_SEEN:
            for key in ("position", "velocity"):
                if key in items:
                    raise self.error(items[key][0], join(path, key),
                                     "an object created when seen gets its "
                                     f"{key} from perception; remove this key (or use "
                                     "create: at_start)")
        for name, r in ranges.items():
            if name in kw:
                if not r.low <= kw[name] <= r.high:
                    raise self.error(items[name][1], join(path, name),
                                     f"the nominal {name} {kw[name]:g} lies outside its range "
                                     f"[{r.low:g}, {r.high:g}] (ranges.{name})")
            else:
                kw[name] = r.mid
        ball = self.build(Ball, node, path, kw)
        return ObjectModel(ball, create, MappingProxyType(ranges), self.source(node, path))

    def model_ranges(self, node: Node, path: str) -> dict[str, Range]:
        """``ranges: {restitution: [lo, hi], ...}`` (a ``floor_friction`` range gives the ball
        spin)."""
        items = self.mapping(node, path)
        self.check_keys(items, MODEL_RANGE_PARAMETERS, path)
        out = {}
        for key, (_, v) in items.items():
            out[key] = self.range(v, join(path, key))
        return out

    def robot(self, node: Node, path: str) -> RobotSpec:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "name": self.string,
            "shape": lambda n, p: self.choice(n, p, ("disc", "box")),
            "radius": self.number,
            "size": lambda n, p: self.vector(n, p, 2),
            "position": lambda n, p: self.vector(n, p, 2),
            "heading_deg": self.number,
            "max_speed": self.number,
            "max_accel": self.number,
            "mass": self.number,
            "height": self.number,
            "color": self.color,
        }
        kw = self.fields(node, path, spec, required=("max_speed", "max_accel"))
        return self.build(RobotSpec, node, path, kw)  # type: ignore[no-any-return]
