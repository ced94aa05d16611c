"""Reading the ``reality`` section: where the "real" frames come from.

``kind: synthetic`` (the default, also when the section is absent) describes
a ground-truth world that differs from the imagination as reality does;
``kind: video`` names a video file or an image sequence; ``kind: bullet`` a
reality on PyBullet (read by :mod:`adapt.scenario.bullet`); ``kind: camera`` a
camera (read by :mod:`adapt.scenario.device`); any other kind is one a plugin
registered (:mod:`adapt.scenario.kinds`), its keys checked against the kind's
parameters.  See ``docs/scenario.md`` for every key and its default.
"""

from __future__ import annotations

import glob as globbing
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable

from adapt.geometry import Camera
from adapt.imagination.scene import Ball, RobotSpec, SceneSpec
from adapt.parameters import REQUIRED, ParameterError
from adapt.scenario.bullet import BulletReader
from adapt.scenario.device import read_camera_reality
from adapt.scenario.kinds import BUILTIN_KINDS, REALITIES, RealityType
from adapt.scenario.nodes import Node, join
from adapt.scenario.records import (
    BulletReality,
    CameraMount,
    CameraOffset,
    CameraReality,
    Creation,
    ObjectModel,
    PluginReality,
    Range,
    RealAppearance,
    RealityKind,
    RobotTruth,
    SyntheticReality,
    Throw,
    TrueObject,
    VideoReality,
)
from adapt.scenario.source import Source

__all__ = ["RealityReader", "SYNTHETIC_KEYS", "VIDEO_KEYS", "TRUE_OBJECT_KEYS", "THROW_KEYS",
           "APPEARANCE_KEYS", "REALITY_ROBOT_KEYS", "DEFAULT_REALITY_DT", "DEFAULT_DRAG",
           "DEFAULT_SPIN"]

SYNTHETIC_KEYS = ("kind", "dt", "camera_offset", "camera_offset_deg", "appearance", "robot",
                  "objects")
VIDEO_KEYS = ("kind", "path", "fps", "ground_truth")
TRUE_OBJECT_KEYS = ("name", "radius", "color", "texture", "position", "velocity", "restitution",
                    "friction", "rolling_resistance", "mass", "drag", "spin", "throw")
THROW_KEYS = ("t", "x", "y", "speed", "heading_deg")
APPEARANCE_KEYS = ("brightness", "contrast", "color_shift", "gradient", "gradient_deg", "blur",
                   "noise", "texture_scale", "texture_phase", "tint", "spin_marker")
REALITY_ROBOT_KEYS = ("max_speed", "max_accel", "slip", "slip_interval")

#: Reality's physics step when the scenario gives none (four times finer than the model's).
DEFAULT_REALITY_DT = 1.0 / 960.0
#: Speed-dependent rolling drag of a real ball when the scenario gives none, 1/m.
DEFAULT_DRAG = 0.03
#: Share of the tangential velocity a real ball stores as spin at a bounce, by default.
DEFAULT_SPIN = 0.25
#: The default appearance of a synthetic reality: a little sensor noise and blur.
DEFAULT_APPEARANCE = RealAppearance(noise=2.0, blur=0.6)


class RealityReader(BulletReader):
    """The ``reality`` section (on top of the world reader)."""

    def reality(self, node: Node | None, path: str, models: tuple[ObjectModel, ...],
                robot: RobotSpec | None, *, scene: SceneSpec | None = None,
                camera: tuple[Camera, CameraMount] | None = None
                ) -> SyntheticReality | VideoReality | BulletReality | CameraReality | PluginReality:
        """Read ``reality`` (``node`` None: the default synthetic reality); a PyBullet
        reality's geometry is checked against ``scene`` and ``camera``."""
        if node is None:
            return self.default_reality(models, Source(self.file, 1, 1, path, self.line_text(1)))
        items = self.mapping(node, path)
        kind = RealityKind.SYNTHETIC
        if "kind" in items:
            name = self.choice(items["kind"][1], join(path, "kind"),
                               [*BUILTIN_KINDS, *REALITIES.names()])
            if name not in BUILTIN_KINDS:
                return self.plugin_reality(node, path, REALITIES.get(name))
            kind = RealityKind(name)
        if kind is RealityKind.VIDEO:
            return self.video(node, path)
        if kind is RealityKind.CAMERA:
            return read_camera_reality(self, node, path)
        if kind is RealityKind.BULLET:
            return self.bullet(node, path, models, scene if scene is not None else
                               SceneSpec(robot=robot), camera)
        return self.synthetic(node, path, models, robot)

    def default_reality(self, models: tuple[ObjectModel, ...], source: Source) -> SyntheticReality:
        """The synthetic reality of a scenario without a ``reality`` section."""
        objects = []
        for m in models:
            if m.create is Creation.WHEN_SEEN:
                raise m.source.error(
                    f"object {m.name!r} is created when seen, but the scenario has no reality "
                    "section to say when it appears; add reality.objects with a throw for it")
            objects.append(self.true_from_model(m, None, {}, source))
        return SyntheticReality(DEFAULT_REALITY_DT, CameraOffset(source=source), DEFAULT_APPEARANCE,
                                tuple(objects), RobotTruth(source=source), source)

    # -- a plugin's kind --------------------------------------------------------------------

    def plugin_reality(self, node: Node, path: str, rt: RealityType) -> PluginReality:
        """A section of a plugin's kind: its keys checked against the kind's parameters."""
        items = self.mapping(node, path)
        self.check_keys(items, ("kind", *(p.name for p in rt.parameters)), path)
        values: dict[str, Any] = {}
        files: list[tuple[str, Path]] = []
        sources: dict[str, Source] = {}
        for p in rt.parameters:
            key = join(path, p.name)
            if p.name not in items:
                if p.default is REQUIRED:
                    raise self.error(node, path, f"missing key {p.name!r} of reality kind "
                                     f"{rt.name!r} ({p.doc})")
                values[p.name] = p.default
                continue
            vnode = items[p.name][1]
            sources[p.name] = self.source(items[p.name][0], key)
            if p.name in rt.files:
                found = self.existing_file(vnode, key, p.doc or p.name)
                values[p.name] = str(found)
                files.append((p.name, found))
                continue
            try:
                values[p.name] = p.check(self.scalar(vnode, key))
            except ParameterError as exc:
                raise self.error(vnode, key, str(exc)) from None
        return PluginReality(rt.name, MappingProxyType(values), tuple(files), rt.like,
                             self.source(node, path), MappingProxyType(sources))

    # -- video ---------------------------------------------------------------------------

    def video(self, node: Node, path: str) -> VideoReality:
        items = self.mapping(node, path)
        self.check_keys(items, VIDEO_KEYS, path)
        if "path" not in items:
            raise self.error(node, path, "missing key 'path' (a video file or an image glob)")
        pnode = items["path"][1]
        target = self.path_value(pnode, join(path, "path"))
        pattern: str | None = None
        if any(ch in str(target) for ch in "*?["):
            pattern = str(target)
            if not globbing.glob(pattern):
                raise self.error(pnode, join(path, "path"),
                                 f"no image matches {pattern!r}; expected a glob of image files "
                                 "(relative to the scenario)")
        elif target.is_dir():
            raise self.error(pnode, join(path, "path"),
                             f"{str(target)!r} is a folder; expected a video file or an image glob "
                             "such as frames/*.png")
        elif not target.is_file():
            raise self.error(pnode, join(path, "path"),
                             f"video file {str(target)!r} not found (paths are relative to the "
                             "scenario)")
        fps = self.number(items["fps"][1], join(path, "fps")) if "fps" in items else None
        if pattern is not None and fps is None:
            raise self.error(node, path, "an image sequence needs 'fps' (frames per second)")
        truth = None
        if "ground_truth" in items:
            truth = self.existing_file(items["ground_truth"][1], join(path, "ground_truth"),
                                       "ground-truth file")
        return VideoReality(Path(target), pattern, fps, truth, self.source(node, path))

    # -- synthetic --------------------------------------------------------------------------

    def synthetic(self, node: Node, path: str, models: tuple[ObjectModel, ...],
                  robot: RobotSpec | None) -> SyntheticReality:
        items = self.mapping(node, path)
        self.check_keys(items, SYNTHETIC_KEYS, path)
        src = self.source(node, path)
        dt = DEFAULT_REALITY_DT
        if "dt" in items:
            dt = self.number(items["dt"][1], join(path, "dt"))
        offset = self.camera_offset(items, path)
        appearance = DEFAULT_APPEARANCE
        if "appearance" in items:
            appearance = self.appearance(items["appearance"][1], join(path, "appearance"))
        truth = RobotTruth(source=src)
        if "robot" in items:
            if robot is None:
                raise self.error(items["robot"][0], join(path, "robot"),
                                 "the world has no robot for reality.robot to describe")
            truth = self.robot_truth(items["robot"][1], join(path, "robot"))
        objects = self.reality_objects(
            items["objects"][1] if "objects" in items else None, join(path, "objects"), models,
            self.true_object, lambda m: self.true_from_model(m, None, {}, src))
        return SyntheticReality(dt, offset, appearance, objects, truth, src)

    def appearance(self, node: Node, path: str) -> RealAppearance:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "brightness": self.number,
            "contrast": self.number,
            "color_shift": lambda n, p: self.vector(n, p, 3),
            "gradient": self.number,
            "gradient_deg": self.number,
            "blur": self.number,
            "noise": self.number,
            "texture_scale": self.number,
            "texture_phase": lambda n, p: self.vector(n, p, 2),
            "tint": lambda n, p: self.vector(n, p, 3),
            "spin_marker": self.boolean,
        }
        kw = self.fields(node, path, spec)
        return RealAppearance(**kw, source=self.source(node, path))

    def robot_truth(self, node: Node, path: str) -> RobotTruth:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "max_speed": self.number,
            "max_accel": self.number,
            "slip": self.number,
            "slip_interval": self.number,
        }
        return RobotTruth(**self.fields(node, path, spec), source=self.source(node, path))

    def throw(self, node: Node, path: str) -> Throw:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "t": self.range,
            "x": self.range,
            "y": self.range,
            "speed": self.range,
            "heading_deg": self.range,
        }
        kw = self.fields(node, path, spec, required=("x", "y"))
        return Throw(kw.get("t", Range.fixed(0.0)), kw["x"], kw["y"],
                     kw.get("speed", Range.fixed(0.0)), kw.get("heading_deg", Range.fixed(0.0)),
                     self.source(node, path))

    def true_object(self, node: Node, path: str, models: dict[str, ObjectModel]) -> TrueObject:
        """One ``reality.objects[i]``: the truth about a world object, or an object of reality only."""
        items, name, model, look = self.reality_object(node, path, TRUE_OBJECT_KEYS, models,
                                                       self.number)
        params: dict[str, Range] = {}
        for key in ("restitution", "friction", "rolling_resistance", "mass", "drag", "spin"):
            if key in items:
                params[key] = self.range(items[key][1], join(path, key))
        for key in ("position", "velocity"):
            if key in items:
                look[key] = self.vector(items[key][1], join(path, key), 2)
        throw = self.throw(items["throw"][1], join(path, "throw")) if "throw" in items else None
        src = self.source(node, path)
        if model is not None:
            if model.create is Creation.WHEN_SEEN and throw is None and "position" not in look:
                raise self.error(node, path, f"object {name!r} is created when seen: give a throw "
                                 "(when and how it appears) or a position")
            return self.true_from_model(model, throw, params, src, look)
        if "radius" not in look:
            raise self.error(node, path, f"{name!r} is not a world object, so it exists in reality "
                             "only: give its radius (and a colour)")
        ball = self.build(Ball, node, path, {"name": name, **look})
        return TrueObject(
            name, ball, False,
            params.get("restitution", Range.fixed(ball.restitution)),
            params.get("friction", Range.fixed(ball.friction)),
            params.get("rolling_resistance", Range.fixed(ball.rolling_resistance)),
            params.get("mass", Range.fixed(ball.mass)),
            params.get("drag", Range.fixed(DEFAULT_DRAG)),
            params.get("spin", Range.fixed(DEFAULT_SPIN)),
            throw, src)

    def true_from_model(self, model: ObjectModel, throw: Throw | None, params: dict[str, Range],
                        source: Source, look: dict[str, Any] | None = None) -> TrueObject:
        """A declared object's truth: the model's values unless ``params`` say otherwise."""
        ball = model.ball
        if look:
            ball = replace(ball, **look)
        return TrueObject(
            model.name, ball, True,
            params.get("restitution", Range.fixed(model.ball.restitution)),
            params.get("friction", Range.fixed(model.ball.friction)),
            params.get("rolling_resistance", Range.fixed(model.ball.rolling_resistance)),
            params.get("mass", Range.fixed(model.ball.mass)),
            params.get("drag", Range.fixed(DEFAULT_DRAG)),
            params.get("spin", Range.fixed(DEFAULT_SPIN)),
            throw, source)
