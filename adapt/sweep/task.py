"""One task of a sweep: one run of the scenario, in a worker.

:func:`run_task` is what a Dask worker runs.  It reads the scenario with the
run's overrides, runs it with :class:`adapt.runner.Runner` (no outputs, or
every output the scenario asks for into the run's own folder with
``--keep-outputs``) and returns the run's record: its summary, its metrics
(:mod:`adapt.sweep.metrics`) and where it ran.  A run that raises is a
record with ``status: "failed"`` and the error, never an exception: the
sweep goes on.  This module imports neither Dask nor anything the worker
does not need.

A record (one line of ``runs.jsonl``)::

    {"key": "seed7-3f9a0c21b4e8", "seed": 7, "set": {"world.objects.ball.restitution": 0.7},
     "status": "ok", "error": null, "metrics": {"caught": true, ...},
     "summary": {...}, "fingerprint": "...",
     "worker": {"host": "...", "pid": 4242, "adapt": "0.1.0"},
     "started": "2026-11-22T10:00:00+00:00", "task_s": 2.31, "cpu_s": 2.2, "outputs": null}

``task_s`` is the run's wall time in the worker, ``cpu_s`` the CPU time of the thread that ran
it (less than ``task_s`` when other jobs share the machine's cores).
"""

from __future__ import annotations

import os
import socket
import time
import traceback
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from adapt.sweep.metrics import metrics_of

__all__ = ["RunSpec", "run_task", "probe", "STATUSES"]

#: ``ok``: the run finished; ``failed``: it raised (its error is kept); ``lost``: its
#: worker died more often than the scheduler allows (see ``docs/sweeps.md``).
STATUSES = ("ok", "failed", "lost")


@dataclass(frozen=True, slots=True)
class RunSpec:
    """Everything a worker needs for one run.

    Attributes
    ----------
    key : str
        The run's name: its seed and a hash of its overrides (stable when the
        grid changes, so a resumed sweep recognises it).
    scenario : str
        Absolute path of the scenario YAML (every worker must see it there).
    overrides : tuple of str
        ``KEY=VALUE`` overrides of the run's grid cell.
    set : tuple of (str, object) pairs
        The same overrides as values, for the record.
    seed : int
    max_frames : int or None
        At most this many frames (``--max-frames``).
    out : str or None
        The run's output folder with ``--keep-outputs``; None writes nothing.
    fingerprint : str
        The scenario's fingerprint (:func:`adapt.sweep.plan.fingerprint`).
    """

    key: str
    scenario: str
    overrides: tuple[str, ...]
    set: tuple[tuple[str, Any], ...]
    seed: int
    max_frames: int | None
    out: str | None
    fingerprint: str

    def record(self, **fields: Any) -> dict[str, Any]:
        """A record of this run with ``fields`` (see the module docstring)."""
        base: dict[str, Any] = {"key": self.key, "seed": self.seed, "set": dict(self.set),
                                "status": "ok", "error": None, "metrics": {}, "summary": None,
                                "fingerprint": self.fingerprint}
        base.update(fields)
        return base


def run_task(spec: RunSpec) -> dict[str, Any] | None:
    """Run ``spec`` and return its record (None when the run was interrupted: it is not
    finished, and the sweep does not count it).

    Examples
    --------
    >>> spec = RunSpec("seed0-x", "/nonexistent.yaml", (), (), 0, 2, None, "f")
    >>> r = run_task(spec)
    >>> r["status"], r["error"]
    ('failed', 'ScenarioError: /nonexistent.yaml:1:1: no such scenario file')
    """
    import adapt
    from adapt.runner import Runner
    from adapt.scenario import load_scenario

    started = datetime.now(timezone.utc).isoformat(timespec="seconds")
    t0 = time.perf_counter()
    c0 = time.thread_time()
    where = {"host": socket.gethostname(), "pid": os.getpid(), "adapt": adapt.__version__}
    try:
        sc = load_scenario(spec.scenario, overrides=list(spec.overrides))
        out = None if spec.out is None else Path(spec.out)
        result = Runner(sc, out=out, seed=spec.seed, max_frames=spec.max_frames).run()
    except Exception as exc:
        return spec.record(status="failed", error=f"{type(exc).__name__}: {exc}",
                           traceback=_tail(traceback.format_exc()), worker=where,
                           started=started, task_s=round(time.perf_counter() - t0, 3),
                           cpu_s=round(time.thread_time() - c0, 3), outputs=spec.out)
    if result.interrupted:
        return None
    summary = result.summary
    return spec.record(status="ok" if result.error is None else "failed", error=result.error,
                       metrics=metrics_of(summary), summary=summary, worker=where,
                       started=started, task_s=round(time.perf_counter() - t0, 3),
                       cpu_s=round(time.thread_time() - c0, 3), outputs=spec.out)


def _tail(text: str, lines: int = 25) -> str:
    parts = text.rstrip("\n").split("\n")
    return "\n".join(parts[-lines:])


def probe(scenario: str) -> dict[str, Any]:
    """What a worker has: adapt's version, whether it sees the scenario file, and its
    ``MALLOC_TRIM_THRESHOLD_`` (set, it slows runs down: :data:`adapt.sweep.cluster.NO_TRIM`).

    Examples
    --------
    >>> probe("/nonexistent.yaml")["scenario"]
    False
    """
    import adapt

    return {"adapt": adapt.__version__, "scenario": os.path.isfile(scenario),
            "host": socket.gethostname(), "pid": os.getpid(),
            "malloc_trim": os.environ.get("MALLOC_TRIM_THRESHOLD_")}
