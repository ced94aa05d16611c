"""The scenario check, and a run's length: used by ``adapt check``, the runner and sweeps.

:func:`check_scenario` checks everything about a scenario that can be
checked without running it: its schema parameters against the schema types
(:func:`adapt.schemas.check_settings`), the camera's image at the MMD's working
size, its engine (``engine: soar`` needs
the Soar kernel installed) and its rule files (parsed, with their warnings;
on the Soar engine, loaded into the kernel, which reads what adapt's parser
refuses).  Every error points at ``file:line:col``: a schema parameter or
the engine where the scenario gives it, a rule where the rule file has it
(and where the scenario names the file).

:func:`planned_frames` is the one computation of how many frames a run
takes: the scenario's ``run`` section at the source's own frame rate
(:meth:`RunSettings.frames_at <adapt.scenario.RunSettings.frames_at>`),
no more than the source has, and no more than asked for.
:func:`run_length` opens the scenario's reality to say it before a run.

Examples
--------
>>> import pathlib
>>> root = pathlib.Path(__file__).resolve().parents[2]
>>> from adapt.scenario import load_scenario
>>> sc = load_scenario(root / "scenarios" / "video-sequence.yaml")
>>> length = run_length(sc)
>>> length.fps, length.frames
(15.0, 36)
>>> [r.productions for r in check_scenario(load_scenario(root / "scenarios" / "bouncing-ball.yaml")).rules]
[22, 17]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping, MutableMapping, Protocol, runtime_checkable

from adapt.engine.functions import default_functions
from adapt.engine.interface import EngineName
from adapt.engine.parse import load_rule_file
from adapt.engines import make_agent, require_engine
from adapt.errors import AdaptError, RuleError, VisionError
from adapt.runner.agent import scenario_rule_error
from adapt.scenario import RunSettings, Scenario
from adapt.schemas import REGISTRY, Registry, check_settings
from adapt.seeds import Streams
from adapt.vision.scale import working_frame

__all__ = ["RuleCheck", "ScenarioCheck", "RunLength", "check_scenario", "planned_frames",
           "run_length"]


@dataclass(frozen=True, slots=True)
class RuleCheck:
    """A rule file of the scenario, parsed: how many productions, the parser's warnings, and
    every file it read (itself first, then the files it ``source`` s)."""

    path: Path
    productions: int
    warnings: tuple[str, ...] = ()
    files: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True, eq=False)
class ScenarioCheck:
    """What the check found: the checked schema parameters per type, and the rule files."""

    scenario: Scenario
    schemas: Mapping[str, Mapping[str, Any]] = field(default_factory=lambda: MappingProxyType({}))
    rules: tuple[RuleCheck, ...] = ()


@dataclass(frozen=True, slots=True)
class RunLength:
    """How a run goes: frames per second (the source's own) and frames at most."""

    fps: float
    frames: int


@runtime_checkable
class _Counted(Protocol):
    """A source that knows how many frames it has (None: it does not say)."""

    @property
    def length(self) -> int | None: ...


def check_scenario(scenario: Scenario, registry: Registry = REGISTRY, *,
                   parsed: MutableMapping[tuple[EngineName, Path], RuleCheck] | None = None
                   ) -> ScenarioCheck:
    """Check ``scenario``'s schema parameters and rule files (see the module docstring).

    ``parsed`` keeps the rule files already read, by engine (a sweep checks many
    cells of one scenario).

    Raises
    ------
    ScenarioError
        An unknown schema type or parameter, or a bad value, at its position.
    RuleError
        A rule file with an error, at its position and where the scenario names it.
    """
    schemas = check_settings(scenario.schemas, registry)
    _check_working_size(scenario, schemas, registry)
    try:
        require_engine(scenario.engine)
    except AdaptError as exc:
        raise scenario.where("engine").error(str(exc)) from None
    read = _kernel_rules if scenario.engine is EngineName.SOAR else _parsed_rules
    rules = []
    for rf in scenario.rules:
        key = (scenario.engine, rf.path)
        known = None if parsed is None else parsed.get(key)
        if known is None:
            try:
                known = read(rf.path)
            except RuleError as exc:
                raise scenario_rule_error(exc, rf) from None
            if parsed is not None:
                parsed[key] = known
        rules.append(known)
    return ScenarioCheck(scenario, MappingProxyType(schemas), tuple(rules))


def _check_working_size(scenario: Scenario, schemas: Mapping[str, Mapping[str, Any]],
                        registry: Registry) -> None:
    """The camera's image reduced to the background schema's ``mmd_pixels`` keeps at least
    32 pixels a side (a long thin image would not), at the parameter's position or the
    camera's height."""
    if "scene-background" not in registry:
        return
    given = schemas.get("scene-background", {})
    pixels = given.get("mmd_pixels",
                       registry.get("scene-background").parameter("mmd_pixels").default)
    try:
        working_frame((scenario.camera.height, scenario.camera.width), int(pixels))
    except VisionError as exc:
        key = "schemas.scene-background.mmd_pixels" if "mmd_pixels" in given else "camera.height"
        raise scenario.where(key).error(str(exc), path=key) from None


def _parsed_rules(path: Path) -> RuleCheck:
    """A rule file as adapt's own engine reads it."""
    loaded = load_rule_file(path, functions=default_functions())
    return RuleCheck(path, len(loaded.productions), tuple(loaded.warnings), tuple(loaded.files))


def _kernel_rules(path: Path) -> RuleCheck:
    """A rule file as the Soar kernel reads it (loaded into a kernel of its own)."""
    agent = make_agent(EngineName.SOAR)
    try:
        loaded = agent.load_file(path)
        return RuleCheck(path, len(loaded.productions), tuple(agent.warnings), tuple(agent.files))
    finally:
        agent.close()


def planned_frames(run: RunSettings, source: object, fps: float, limit: int | None = None) -> int:
    """Frames a run takes at most: ``run`` at ``fps`` (the source's rate), no more than the
    source has (when it says, by a ``length``) and no more than ``limit``.

    Examples
    --------
    >>> planned_frames(RunSettings(), object(), 15.0), planned_frames(RunSettings(), object(), 15.0, 40)
    (150, 40)
    """
    frames = run.frames_at(fps)
    if isinstance(source, _Counted) and source.length is not None:
        frames = min(frames, int(source.length))
    return frames if limit is None else min(frames, limit)


def run_length(scenario: Scenario, seed: int | None = None) -> RunLength:
    """The frame rate and the frames of a run of ``scenario``, from its reality (opened to
    read them, then closed: a bad video fails here, before a run)."""
    from adapt.reality import open_reality

    if seed is None:
        seed = scenario.seed or 0
    source = open_reality(scenario, streams=Streams(seed))
    try:
        fps = float(source.fps)
        return RunLength(fps, planned_frames(scenario.run, source, fps))
    finally:
        source.close()
