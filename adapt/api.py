"""The Python API: load a scenario, run it, or step it frame by frame.

These are the functions ``import adapt`` gives (:data:`adapt.__all__`); the
rest of the package is reachable but private by convention.

* :func:`load_scenario` -- a scenario file (or YAML text), with ``--set``-style
  overrides and plugins loaded first;
* :func:`run` -- the whole run, like ``adapt run``, returning its
  :class:`~adapt.runner.RunResult`;
* :func:`start` -- a :class:`Run`: an iterator of the run's
  :class:`~adapt.runner.record.FrameRecord`\\ s, one a frame, for notebooks and
  for closing the loop with a simulator or a robot outside adapt (give it
  ``source=``: any :class:`~adapt.frames.FrameSource`; one with a ``robot``
  is the robot the motor schemas drive).

Examples
--------
>>> import adapt
>>> sc = adapt.load_scenario(EXAMPLE, overrides=["run.duration=0.2"])
>>> with adapt.start(sc, max_frames=3) as loop:
...     times = [round(record.time, 3) for record in loop]
>>> times, loop.result.summary["frames"]
([0.0, 0.033, 0.067], 3)
"""

from __future__ import annotations

import os
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Iterator, Mapping, Sequence

from adapt.plugins import Plugin, PluginFrom, load_plugin

if TYPE_CHECKING:  # pragma: no cover
    from adapt.frames import FrameSource
    from adapt.runner import Runner, RunResult
    from adapt.runner.baseline import BaselineFactory
    from adapt.runner.record import FrameListener, FrameRecord
    from adapt.scenario import Override, Scenario

__all__ = ["load_scenario", "run", "start", "Run", "load_plugins", "EXAMPLE"]

#: A small bundled scenario (a ball rolling past a wall, no rules), for examples.
EXAMPLE = Path(__file__).resolve().parent / "data" / "example.yaml"

PathLike = str | os.PathLike[str]


def load_plugins(plugins: Sequence[str], base: PathLike | None = None) -> tuple[Plugin, ...]:
    """Import ``plugins`` (module names, or ``.py`` files relative to ``base``, by default
    the current folder), each once per process (:func:`adapt.plugins.load_plugin`).

    Raises
    ------
    PluginError
        A plugin that is missing, raises on import or registers a taken name.
    """
    if isinstance(plugins, str):
        plugins = [plugins]
    return tuple(load_plugin(str(p), base=None if base is None else Path(base),
                             found=PluginFrom.PYTHON) for p in plugins)


def load_scenario(scenario: "PathLike | Scenario", *, overrides: Sequence["Override | str"] = (),
                  plugins: Sequence[str] = ()) -> "Scenario":
    """A scenario: read from a YAML file (``overrides`` applied, as ``KEY=VALUE`` strings),
    or returned as it is when it is one already (then ``overrides`` must be empty).

    ``plugins`` are loaded first, so the scenario may use what they register; so are the
    installed plugins and the scenario's own ``plugins:``.

    Parameters
    ----------
    scenario : path or Scenario
    overrides : sequence of str
        ``"reality.objects.ball.restitution=0.7"``, like ``adapt run --set``.
    plugins : sequence of str
        Module names or ``.py`` files (relative to the current folder).

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        A missing file, bad YAML, a wrong key or value (``file:line:col``), a scenario plugin
        that fails.
    PluginError
        One of ``plugins`` fails.

    Examples
    --------
    >>> sc = load_scenario(EXAMPLE, overrides=["run.fps=10"])
    >>> sc.run.fps, sc.reality.name
    (10.0, 'synthetic')
    """
    from adapt.errors import RunError
    from adapt.scenario import Scenario
    from adapt.scenario import load_scenario as read

    load_plugins(plugins)
    if isinstance(scenario, Scenario):
        if overrides:
            raise RunError("overrides apply to a scenario file; this scenario is loaded already")
        return scenario
    return read(Path(scenario), overrides=overrides)


def _runner(scenario: "PathLike | Scenario", *, source: "FrameSource | None",
            out: PathLike | None, overrides: Sequence["Override | str"], plugins: Sequence[str],
            seed: int | None, max_frames: int | None, listeners: Sequence["FrameListener"],
            baselines: "Mapping[str, BaselineFactory] | None") -> "Runner":
    from adapt.runner import Runner

    sc = load_scenario(scenario, overrides=overrides, plugins=plugins)
    return Runner(sc, source=source, out=out, seed=seed, max_frames=max_frames,
                  listeners=tuple(listeners), baselines=baselines)


def run(scenario: "PathLike | Scenario", *, source: "FrameSource | None" = None,
        out: PathLike | None = None, overrides: Sequence["Override | str"] = (),
        plugins: Sequence[str] = (), seed: int | None = None, max_frames: int | None = None,
        listeners: Sequence["FrameListener"] = (),
        baselines: "Mapping[str, BaselineFactory] | None" = None) -> "RunResult":
    """Run a scenario to its end, like ``adapt run``.

    Parameters
    ----------
    scenario : path or Scenario
    source : FrameSource, optional
        The real frames instead of the scenario's reality (a simulator, a robot's camera);
        one with a ``robot`` (:class:`~adapt.frames.Actuator`) is driven by the motor
        schemas, one with a ``truth`` is scored against it.
    out : path, optional
        The output folder (``report.json``, ``trace.jsonl``, ``mmd.mp4``, ``figures/``);
        None writes nothing.
    overrides, plugins
        As for :func:`load_scenario`.
    seed, max_frames : int, optional
        As ``adapt run --seed``, ``--max-frames``.
    listeners : sequence of FrameListener
        Objects with ``frame(record)``, called with every frame's record after the run's own.
    baselines : mapping of str to BaselineFactory
        More baselines beside the Kalman one, scored in the same run.

    Returns
    -------
    RunResult
        ``summary`` (the report's summary), ``outputs`` (what was written), ``interrupted``
        and ``error``.

    Raises
    ------
    AdaptError
        Bad input, before anything is written: a scenario, plugin, rule file, output folder
        or frame source that is wrong.

    Examples
    --------
    >>> result = run(EXAMPLE, max_frames=4)
    >>> result.summary["frames"], result.summary["stopped"], result.outputs
    (4, 'end-of-frames', {})
    """
    return _runner(scenario, source=source, out=out, overrides=overrides, plugins=plugins,
                   seed=seed, max_frames=max_frames, listeners=listeners,
                   baselines=baselines).run()


def start(scenario: "PathLike | Scenario", *, source: "FrameSource | None" = None,
           out: PathLike | None = None, overrides: Sequence["Override | str"] = (),
           plugins: Sequence[str] = (), seed: int | None = None, max_frames: int | None = None,
           listeners: Sequence["FrameListener"] = (),
           baselines: "Mapping[str, BaselineFactory] | None" = None) -> "Run":
    """The run of a scenario, one frame at a time: a :class:`Run`, an iterator of
    :class:`~adapt.runner.record.FrameRecord` (parameters as for :func:`run`).

    Examples
    --------
    >>> loop = start(EXAMPLE, max_frames=2)
    >>> first = next(loop)
    >>> first.index, [o.name for o in first.tracked]
    (0, ['ball'])
    >>> loop.close()
    >>> loop.result.summary["frames"], loop.result.summary["stopped"]
    (1, 'interrupted')
    """
    return Run(_runner(scenario, source=source, out=out, overrides=overrides, plugins=plugins,
                       seed=seed, max_frames=max_frames, listeners=listeners,
                       baselines=baselines))


class Run:
    """A run stepped by its caller: iterate it for the frame records; :attr:`result` when it
    has ended; :meth:`close` (or leaving a ``with`` block) ends it early, writing the outputs
    of the frames done (the summary says ``interrupted``).

    Attributes
    ----------
    runner : Runner
        The runner (its ``scenario``, ``network`` and ``agent`` are there to inspect).
    """

    def __init__(self, runner: "Runner") -> None:
        self.runner = runner
        self._frames = runner.frames()

    def __iter__(self) -> Iterator["FrameRecord"]:
        return self

    def __next__(self) -> "FrameRecord":
        return next(self._frames)

    @property
    def result(self) -> "RunResult | None":
        """How the run ended (None while it goes on)."""
        return self.runner.result

    def close(self) -> None:
        """End the run now; its outputs are written."""
        self._frames.close()
        self.runner.close()

    def __enter__(self) -> "Run":
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()
