"""The plan of a sweep: every run it is made of, checked before any runs.

:func:`make_plan` reads ``--seeds`` and every ``--set`` (:mod:`adapt.sweep.grid`),
forms the grid's cells (the product of the axes, the first axis varying
slowest) and reads the scenario **once per cell** with that cell's overrides,
so a bad value is reported before anything runs, by the scenario reader
itself, at its column in the ``--set`` argument.  Each cell is checked as
``adapt check`` and the runner check a scenario
(:func:`adapt.runner.check_scenario`: its schema parameters, and each
distinct rule file parsed once).

Runs are ordered seed by seed, each seed over every cell, so a sweep stopped
early still has about as many runs in every cell.

A run's key is its seed and a hash of its cell's overrides
(``seed7-3f9a0c21b4e8``): it stays the same when the grid around it changes,
which is how a resumed sweep recognises the runs it already has.  The
scenario's **fingerprint** (a hash of the YAML text, its rule files, its plugins'
files and ``--max-frames``) goes into every record, so a sweep never mixes runs of two
versions of its scenario.

Examples
--------
>>> import pathlib
>>> root = pathlib.Path(__file__).resolve().parents[2]
>>> plan = make_plan(root / "scenarios" / "background-sync.yaml", seeds="1-2",
...                  sets=["reality.appearance.noise=1,3"], max_frames=2)
>>> len(plan.runs), [c for c in plan.cells]
(4, [(('reality.appearance.noise', 1),), (('reality.appearance.noise', 3),)])
>>> [r.key.split("-")[0] for r in plan.runs]
['seed1', 'seed1', 'seed2', 'seed2']
>>> make_plan(root / "scenarios" / "background-sync.yaml",
...           sets=["reality.appearance.noise=1,300"])
Traceback (most recent call last):
...
adapt.errors.ScenarioError: --set:1:28: reality.appearance.noise: expected a number from 0 to 100 grey levels, got 300
    reality.appearance.noise=1,300
                               ^
"""

from __future__ import annotations

import hashlib
import itertools
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from adapt.errors import LocatedError, ScenarioError, SweepSpecError
from adapt.files import Input, Inputs
from adapt.runner.check import RuleCheck, check_scenario
from adapt.scenario import EngineName, Scenario, load_scenario
from adapt.scenario.inputs import scenario_files
from adapt.sweep.grid import Axis, Item, parse_axis, parse_seeds
from adapt.sweep.task import RunSpec

__all__ = ["Plan", "make_plan", "fingerprint", "Cell", "cell_hash"]

#: A grid cell: ``((key path, value), ...)`` in the order of the axes.
Cell = tuple[tuple[str, Any], ...]

#: Key paths a sweep sets itself (``--seeds``), never through ``--set``.
_SEED_PATHS = ("seed", "run.seed")


@dataclass(frozen=True, slots=True)
class Plan:
    """A checked sweep: the scenario, the grid and its runs (see the module docstring).

    Attributes
    ----------
    scenario : Path
        The scenario file, absolute.
    seeds : tuple of int
    axes : tuple of Axis
    cells : tuple of Cell
    runs : tuple of RunSpec
        Seed by seed, each seed over every cell.
    max_frames : int or None
    fingerprint : str
    inputs : tuple of Input
        Everything the runs read, over every cell: the scenario's files
        (:meth:`adapt.scenario.Scenario.inputs`) and the files its rules
        ``source``; no output of the sweep may replace one.
    """

    scenario: Path
    seeds: tuple[int, ...]
    axes: tuple[Axis, ...]
    cells: tuple[Cell, ...]
    runs: tuple[RunSpec, ...]
    max_frames: int | None
    fingerprint: str
    inputs: tuple[Input, ...] = ()

    def describe(self) -> dict[str, Any]:
        """The grid as ``sweep.json`` records it."""
        return {"scenario": str(self.scenario), "fingerprint": self.fingerprint,
                "max_frames": self.max_frames, "seeds": list(self.seeds),
                "axes": [{"path": a.path, "values": a.values} for a in self.axes],
                "cells": len(self.cells), "runs": len(self.runs)}


def cell_hash(cell: Cell) -> str:
    """Twelve hex digits naming a cell by its overrides (not by its place in the grid).

    >>> cell_hash((("world.dt", 0.01),)) == cell_hash((("world.dt", 0.01),))
    True
    >>> cell_hash(()) != cell_hash((("world.dt", 0.01),))
    True
    """
    text = json.dumps(sorted([p, v] for p, v in cell), separators=(",", ":"), sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:12]


def fingerprint(scenario: Scenario, text: bytes, max_frames: int | None) -> str:
    """A hash of the scenario's YAML text, its rule files' and plugins' text (each plugin's
    own file: a package's other modules are not read) and ``max_frames``."""
    h = hashlib.sha256()
    h.update(text)
    files = [("rules", str(r.path)) for r in scenario.rules]
    files += [("plugin", str(p.file)) for p in scenario.plugins if p.file is not None]
    for kind, name in sorted(set(files)):
        h.update(b"\0" + kind.encode("utf-8") + b"\0" + name.encode("utf-8") + b"\0")
        try:
            h.update(Path(name).read_bytes())
        except OSError:
            h.update(b"<unreadable>")
    h.update(f"\0max_frames={max_frames}".encode())
    return h.hexdigest()[:16]


def make_plan(scenario: str | os.PathLike[str], *, seeds: str | None = None,
              sets: Sequence[str] = (), max_frames: int | None = None,
              out: str | os.PathLike[str] | None = None,
              keep_outputs: bool = False) -> Plan:
    """Read and check a sweep's grid (see the module docstring).

    Parameters
    ----------
    scenario : path
    seeds : str, optional
        ``--seeds``; by default the scenario's own seed (0 when it has none).
    sets : sequence of str
        Each ``--set KEY=VALUES``.
    max_frames : int, optional
        At most this many frames per run.
    out : path, optional
        The sweep's folder; with ``keep_outputs`` every run writes its outputs
        into ``out/runs/<key>/``.

    Raises
    ------
    SweepSpecError
        A ``--seeds`` or ``--set`` that cannot be read.
    ScenarioError, RuleError
        A value the scenario cannot take, at its column in ``--set``.
    """
    path = Path(scenario)
    if max_frames is not None and max_frames < 1:
        raise SweepSpecError(f"--max-frames must be at least 1, got {max_frames}",
                             file="--max-frames", source_line=str(max_frames))
    base = load_scenario(path)
    text = path.read_bytes()
    seed_list = parse_seeds(seeds) if seeds is not None else (base.seed or 0,)
    axes = _axes(sets)
    cells: list[Cell] = [tuple((a.path, i.value) for a, i in zip(axes, combo))
                         for combo in itertools.product(*(a.items for a in axes))]
    overrides: list[tuple[str, ...]] = [
        tuple(f"{a.path}={i.text}" for a, i in zip(axes, combo))
        for combo in itertools.product(*(a.items for a in axes))]
    inputs = _check_cells(path, axes, overrides, cells)
    fp = fingerprint(base, text, max_frames)
    absolute = str(path.resolve())
    runs: list[RunSpec] = []
    for seed in seed_list:
        for cell, ovs in zip(cells, overrides):
            key = f"seed{seed}-{cell_hash(cell)}"
            run_out = None
            if keep_outputs and out is not None:
                run_out = str(Path(out).resolve() / "runs" / key)
            runs.append(RunSpec(key, absolute, ovs, cell, seed, max_frames, run_out, fp))
    return Plan(path.resolve(), seed_list, axes, tuple(cells), tuple(runs), max_frames, fp,
                tuple(inputs))


def _axes(sets: Sequence[str]) -> tuple[Axis, ...]:
    axes: list[Axis] = []
    for text in sets:
        axis = parse_axis(text)
        if axis.path in _SEED_PATHS:
            raise SweepSpecError("the seed is swept with --seeds, not --set", file="--set",
                                 col=1, source_line=text)
        for other in axes:
            if other.path == axis.path:
                raise SweepSpecError(f"{axis.path} is set twice (also --set {other.text}); give "
                                     "all its values in one --set", file="--set", col=1,
                                     source_line=text)
        axes.append(axis)
    return tuple(axes)


def _check_cells(path: Path, axes: Sequence[Axis], overrides: Sequence[tuple[str, ...]],
                 cells: Sequence[Cell]) -> Inputs:
    """Check every cell's scenario (each distinct rule file parsed once); return what the
    runs read over every cell."""
    from adapt.runner.inputs import sourced_inputs

    origin: dict[str, tuple[Axis, Item]] = {}
    for axis in axes:
        for item in axis.items:
            origin[f"{axis.path}={item.text}"] = (axis, item)
    parsed: dict[tuple[EngineName, Path], RuleCheck] = {}
    inputs = Inputs()
    for ovs, cell in zip(overrides, cells):
        try:
            sc = load_scenario(path, overrides=list(ovs))
            checked = check_scenario(sc, parsed=parsed)
        except ScenarioError as exc:
            raise _relocate(exc, origin, cell) from None
        inputs.extend(scenario_files(sc))
        for rf, rc in zip(sc.rules, checked.rules):
            inputs.extend(sourced_inputs(rf, rc.files))
    return inputs


def _relocate(exc: LocatedError, origin: dict[str, tuple[Axis, Item]],
              cell: Cell) -> LocatedError:
    """An error the reader found in a generated override, moved to the user's ``--set``."""
    where = origin.get(exc.source_line or "") if exc.file == "--set" else None
    if where is None:
        if not cell:
            return exc
        combo = " ".join(f"--set {p}={json.dumps(v)}" for p, v in cell)
        return type(exc)(f"{exc.message} (in the grid cell {combo})", file=exc.file,
                         line=exc.line, col=exc.col, source_line=exc.source_line)
    axis, item = where
    value_col = len(axis.path) + 2
    message = exc.message
    if item.from_range:
        col = item.col
        message += f" (the value {item.text} of the range)"
    elif exc.col >= value_col:
        col = item.col + exc.col - value_col
    else:
        col = exc.col
    return type(exc)(message, file="--set", line=1, col=col, source_line=axis.text)
