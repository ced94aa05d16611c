"""Scenario files: the only YAML reader of adapt.

A scenario is a YAML mapping with the sections ``plugins``, ``seed``, ``camera``,
``world``, ``reality``, ``goals``, ``rules``, ``engine``, ``schemas``,
``run``, ``predict`` and ``outputs`` (every key and its default is in
``docs/scenario.md``; a test keeps that page and this reader in step).  Each
section is read into frozen records that keep their source position
(:class:`~adapt.scenario.source.Source`), so an error found later -- an
unknown schema type, a rule file with an error -- still points at
``file:line:col`` with the key path.

Every error is a :class:`~adapt.errors.ScenarioError` that names
``file:line:col`` of the offending key or value, its key path
(``world.walls[2].height``) and what was expected.  An unknown key is an
error at every level, with a suggestion when it looks like a typo.

Textures, rule files, videos and ground-truth files resolve relative to the
YAML file; a bare name of a bundled texture (``brick``) or ``builtin:brick``
means the texture shipped with adapt.

Examples
--------
>>> text = '''
... camera: {fx: 500, fy: 500, cx: 320, cy: 240, width: 640, height: 480,
...          position: [0, -3, 1], look_at: [0, 0, 0.5]}
... world:
...   walls: [{from: [-2, 1], to: [2, 1], height: 1.0, texture: brick}]
...   objects: [{name: ball, radius: 0.1, velocity: [1, 0]}]
... goals: [{name: track, object: ball}]
... '''
>>> sc = loads_scenario(text)
>>> sc.scene.walls[0].texture, sc.scene.balls[0].velocity, sc.camera.width
('builtin:brick', (1.0, 0.0), 640)
>>> sc.goals[0].get("object"), sc.reality.kind.value, sc.run.frames
('ball', 'synthetic', 300)
>>> loads_scenario(text.replace("height: 1.0", "height: -1"))
Traceback (most recent call last):
...
adapt.errors.ScenarioError: <string>:5:47: world.walls[0].height: expected a positive number, at least 0.001 metres, got -1
...
>>> loads_scenario(text + "sede: 3\\n")
Traceback (most recent call last):
...
adapt.errors.ScenarioError: <string>:8:1: sede: unknown key (did you mean 'seed'?); expected one of plugins, seed, camera, world, reality, goals, rules, engine, schemas, run, predict, outputs
...
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Mapping, Sequence

from adapt.engine.interface import ENGINE_NAMES, EngineName
from adapt.errors import PluginError, ScenarioError
from adapt.files import Inputs
from adapt.geometry import Camera
from adapt.imagination.scene import SceneSpec
from adapt.lens import Lens
from adapt.plugins import PluginFrom, load_installed, load_plugin
from adapt.scenario.inputs import scenario_inputs
from adapt.scenario.kinds import REALITIES, RealityRegistry, RealityType
from adapt.scenario.nodes import Node, Override, join  # noqa: F401  (join re-exported)
from adapt.scenario.records import (
    BulletLook,
    BulletObject,
    BulletReality,
    BulletRobot,
    BulletSurfaces,
    CameraMount,
    CameraOffset,
    CameraReality,
    Creation,
    Goal,
    GoalKind,
    Mount,
    ObjectModel,
    OutputSettings,
    PluginReality,
    PluginRef,
    PredictSettings,
    Range,
    RealAppearance,
    Reality,
    RealityKind,
    RobotTruth,
    RuleFile,
    RunSettings,
    SchemaSettings,
    SyntheticReality,
    TextureSource,
    Throw,
    TrueObject,
    VideoCodec,
    VideoReality,
)
from adapt.scenario.run import RunReader
from adapt.scenario.sanity import check_together
from adapt.scenario.source import Source

__all__ = [
    "Scenario",
    "load_scenario",
    "loads_scenario",
    "Override",
    "Source",
    "TOP_KEYS",
    "Range",
    "Mount",
    "CameraMount",
    "Creation",
    "ObjectModel",
    "RealityKind",
    "Throw",
    "TrueObject",
    "CameraOffset",
    "RealAppearance",
    "RobotTruth",
    "SyntheticReality",
    "VideoReality",
    "CameraReality",
    "VideoCodec",
    "BulletReality",
    "BulletObject",
    "BulletSurfaces",
    "BulletLook",
    "BulletRobot",
    "TextureSource",
    "CameraReality",
    "VideoCodec",
    "PluginReality",
    "PluginRef",
    "RealityType",
    "RealityRegistry",
    "REALITIES",
    "Reality",
    "Goal",
    "GoalKind",
    "RuleFile",
    "EngineName",
    "SchemaSettings",
    "RunSettings",
    "PredictSettings",
    "OutputSettings",
]

#: The largest scenario file read, in bytes; no more is read.
MAX_BYTES = 16 * 1024 * 1024

#: The top-level sections, in the order the documentation lists them.
TOP_KEYS = ("plugins", "seed", "camera", "world", "reality", "goals", "rules", "engine", "schemas",
            "run", "predict", "outputs")


@dataclass(frozen=True, slots=True, eq=False)
class Scenario:
    """A loaded scenario.

    Attributes
    ----------
    path : Path or None
        The YAML file (``None`` for text not read from a file).
    camera : Camera
        The camera at its starting pose (``camera`` section).
    scene : SceneSpec
        The imagination's starting scene (``world``): the objects created at
        the start only.
    seed : int or None
        ``run.seed`` or the top-level ``seed`` (one of them).
    mount : CameraMount
        Whether the camera is fixed or on the robot.
    objects : tuple of ObjectModel
        Every declared object with what is known of it before it is seen.
    reality : SyntheticReality, VideoReality or PluginReality
        Where the real frames come from.
    plugins : tuple of PluginRef
        The ``plugins`` section: modules imported before the rest was read.
    goals, rules, schemas : tuples of Goal, RuleFile, SchemaSettings
    engine : EngineName
        The rule engine that runs the rules (``engine``): adapt's own (the
        default) or ``soar``, the Soar kernel.
    run, predict, outputs : RunSettings, PredictSettings, OutputSettings
    sources : mapping of str to Source
        The position of every key path read.
    appearance : Path or None
        ``world.appearance``: a folder of learned surface looks to start from.
    lens : Lens or None
        The camera's lens distortion (``camera.distortion`` or ``camera.calibration``);
        frames are undistorted before perception sees them.
    """

    path: Path | None
    camera: Camera
    scene: SceneSpec
    seed: int | None = None
    mount: CameraMount = field(default_factory=lambda: CameraMount(Mount.FIXED, (0, 0, 1), (0, 1, 1)))
    objects: tuple[ObjectModel, ...] = ()
    reality: Reality = field(default=None)  # type: ignore[assignment]
    goals: tuple[Goal, ...] = ()
    rules: tuple[RuleFile, ...] = ()
    engine: EngineName = EngineName.ADAPT
    schemas: tuple[SchemaSettings, ...] = ()
    run: RunSettings = field(default_factory=RunSettings)
    predict: PredictSettings = field(default_factory=PredictSettings)
    outputs: OutputSettings = field(default_factory=OutputSettings)
    sources: Mapping[str, Source] = field(default_factory=lambda: MappingProxyType({}))
    appearance: Path | None = None
    lens: Lens | None = None
    plugins: tuple[PluginRef, ...] = ()

    def where(self, path: str) -> Source:
        """The position of a key path (the nearest enclosing one that was read).

        Examples
        --------
        >>> sc = loads_scenario("camera: {fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, "
        ...                     "position: [0, 0, 1], look_at: [0, 1, 1]}\\nworld: {}\\n")
        >>> sc.where("camera.width").location, sc.where("camera.nothing.here").path
        ('<string>:1:45', 'camera')
        """
        p = path
        while True:
            if p in self.sources:
                return self.sources[p]
            if not p:
                return Source(str(self.path) if self.path else "<string>", 1, 1, path)
            cut = max(p.rfind("."), p.rfind("["))
            p = p[:cut] if cut > 0 else ""

    def model(self, name: str) -> ObjectModel:
        """The declared object called ``name``."""
        for m in self.objects:
            if m.name == name:
                return m
        raise KeyError(name)

    def inputs(self) -> Inputs:
        """Every file the scenario names: itself, its rule files, textures, the learned
        appearance, the video or its frames, the ground truth
        (:func:`adapt.scenario.inputs.scenario_inputs`); no output may replace one."""
        return scenario_inputs(self)

    def schema_settings(self, type_name: str) -> SchemaSettings | None:
        """The ``schemas.<type_name>`` parameters, or None."""
        for s in self.schemas:
            if s.type == type_name:
                return s
        return None

    @property
    def target(self) -> str | None:
        """The object of the first ``intercept`` goal (:attr:`GoalKind.INTERCEPT`), or None."""
        return next((str(g.get("object")) for g in self.goals
                     if g.kind is GoalKind.INTERCEPT and g.get("object") is not None), None)


def load_scenario(path: str | Path, overrides: Sequence[Override | str] = ()) -> Scenario:
    """Read a scenario YAML file, after applying ``overrides`` (``KEY=VALUE``).

    Raises
    ------
    ScenarioError
        If the file is missing, is not YAML, or a key or value is wrong.
    """
    p = Path(path)
    try:
        with open(p, "rb") as f:  # a bounded read: a device such as /dev/zero never ends
            data = f.read(MAX_BYTES + 1)
        text = data.decode("utf-8-sig")
    except FileNotFoundError:
        raise ScenarioError("no such scenario file", file=str(path), line=1, col=1) from None
    except IsADirectoryError:
        raise ScenarioError("is a folder; expected a scenario YAML file", file=str(path)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"cannot read the scenario: {exc}", file=str(path)) from None
    if len(data) > MAX_BYTES:
        raise ScenarioError(f"larger than {MAX_BYTES // (1024 * 1024)} MiB; expected a scenario "
                            "YAML file (a few kilobytes)", file=str(path))
    return loads_scenario(text, file=str(path), base=p.resolve().parent, path=p,
                          overrides=overrides)


def loads_scenario(
    text: str, *, file: str = "<string>", base: Path | None = None, path: Path | None = None,
    overrides: Sequence[Override | str] = (),
) -> Scenario:
    """Read a scenario from YAML text; relative paths resolve against ``base``
    (default: the current directory).

    The installed plugins are loaded first (:func:`adapt.plugins.load_installed`), then the
    ``plugins`` section's, so that their schema types and reality kinds are known to the rest.
    """
    ovs = [o if isinstance(o, Override) else Override.parse(o) for o in overrides]
    return _Reader(text, file, base or Path.cwd()).read(path, ovs)


class _Reader(RunReader):
    def read(self, path: Path | None, overrides: list[Override]) -> Scenario:
        root = self.compose()
        if root is None:
            raise ScenarioError("the scenario is empty; expected a mapping with 'camera' and 'world'",
                                file=self.file)
        root = self.apply_overrides(root, overrides)
        top = self.mapping(root, "")
        self.check_keys(top, TOP_KEYS, "")
        load_installed()
        plugins = self.plugins(top["plugins"][1], "plugins") if "plugins" in top else ()
        for key in ("camera", "world"):
            if key not in top:
                raise self.error(root, "", f"missing section {key!r}")

        def section(key: str) -> object:
            return top[key][1] if key in top and not self.is_null(top[key][1]) else None

        scene, models = self.world(top["world"][1], "world")
        appearance = self.world_appearance(top["world"][1], "world")
        camera, mount, lens = self.camera_and_lens(top["camera"][1], "camera", scene.robot)
        reality = self.reality(section("reality"), "reality", models, scene.robot,  # type: ignore[arg-type]
                               scene=scene, camera=(camera, mount))
        goals = self.goals(top["goals"][1], "goals", models) if section("goals") else ()
        rules = self.rules(top["rules"][1], "rules") if section("rules") else ()
        engine = (EngineName(self.choice(top["engine"][1], "engine", ENGINE_NAMES))
                  if "engine" in top else EngineName.ADAPT)
        schemas = self.schemas(top["schemas"][1], "schemas") if section("schemas") else ()
        run, run_seed = (self.run_settings(top["run"][1], "run") if section("run")
                         else (RunSettings(), None))
        predict = (self.predict_settings(top["predict"][1], "predict") if section("predict")
                   else PredictSettings())
        outputs = (self.output_settings(top["outputs"][1], "outputs") if section("outputs")
                   else OutputSettings())
        seed = None
        if "seed" in top:
            seed = self.integer(top["seed"][1], "seed")
        if run_seed is not None:
            if seed is not None:
                raise self.error(top["seed"][0], "seed", "the seed is given twice (seed and "
                                 "run.seed); keep one")
            seed = run_seed
        scenario = Scenario(
            path=path, camera=camera, scene=scene, seed=seed, mount=mount, objects=models,
            reality=reality, goals=goals, rules=rules, engine=engine, schemas=schemas, run=run,
            predict=predict,
            outputs=outputs, sources=MappingProxyType(dict(self.sources)), appearance=appearance,
            lens=lens,
            plugins=plugins,
        )
        check_together(scenario)
        return scenario

    def plugins(self, node: Node, path: str) -> tuple[PluginRef, ...]:
        """``plugins``: module names or ``.py`` files (relative to the scenario), imported now."""
        if self.is_null(node):
            return ()

        def one(item: Node, where: str, i: int) -> PluginRef:
            name = self.string(item, where)
            try:
                plugin = load_plugin(name, base=self.base, found=PluginFrom.SCENARIO)
            except PluginError as exc:
                raise self.error(item, where, str(exc)) from None
            return PluginRef(name, plugin.module, None if plugin.file is None else Path(plugin.file),
                             plugin.origin, self.source(item, where))

        return tuple(self.listed(node, path, one))
