"""Running a plan: the runs it still needs, on Dask, recorded as they finish.

:func:`run_sweep` is the whole sweep, in this order:

0. refuse an output that would replace anything the runs read (the plan's
   inputs, :func:`adapt.files.check_outputs`);
1. open ``DIR/runs.jsonl`` (:class:`~adapt.sweep.store.RunLog`: the folder
   locked, the temporary files a killed sweep left removed, a cut-short last
   line dropped) and refuse it if it holds runs of another
   version of the scenario (another fingerprint: the YAML, its rule files, its
   plugins' files or ``--max-frames`` changed), since their results would be mixed;
2. skip every run of the plan that is already there (``ok``, or ``failed``
   unless ``retry_failed``; a ``lost`` run is run again);
3. connect (:mod:`adapt.sweep.cluster`), check that the workers see the
   scenario, submit the remaining runs, and append each record to
   ``runs.jsonl`` the moment its run is back.  A worker that dies takes its
   runs with it; the scheduler runs them again elsewhere, and each is
   recorded once, when it comes back.  A run whose worker died more often
   than the scheduler allows (``distributed.scheduler.allowed-failures``,
   3) is recorded as ``lost``;
4. on Ctrl-C: cancel what is left, and go on to 5 with the runs done;
5. write ``sweep.json``, ``runs.csv`` and ``figures/`` for the runs of the
   plan (runs of an earlier, different grid stay in ``runs.jsonl`` but are
   left out), each file atomically.

Runs never share state: a run's record depends only on its seed and its
overrides (timings aside), whatever worker ran it and however many there are.
"""

from __future__ import annotations

import json
import signal
import threading
import time
import uuid
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

from adapt.errors import SweepError
from adapt.files import Input, Inputs, Output, check_outputs, write_atomic
from adapt.sweep.aggregate import INTERVALS, cell_id, csv_text, metric_names, summarise
from adapt.sweep.plan import Plan
from adapt.sweep.store import RunLog, latest
from adapt.sweep.task import RunSpec, probe, run_task

__all__ = ["run_sweep", "Progress", "Outcome", "FORMAT"]

#: The version of ``sweep.json``'s layout.
FORMAT = 1


@dataclass(frozen=True, slots=True)
class Progress:
    """What a progress line shows, after every finished run and a few times a second."""

    total: int
    ok: int
    failed: int
    lost: int
    remaining: int
    elapsed: float
    ran: int
    workers: int
    workers_left: int

    @property
    def done(self) -> int:
        """Runs finished, whatever their status."""
        return self.ok + self.failed + self.lost


@dataclass
class Outcome:
    """How a sweep ended.

    Attributes
    ----------
    records : list of dict
        The latest record of every run of the plan that has one, in plan order.
    skipped : int
        Runs already in ``runs.jsonl`` when the sweep started.
    ran : int
        Runs recorded by this invocation.
    ok, failed, lost, remaining : int
        Over the plan.
    outside_grid : int
        Runs in ``runs.jsonl`` that are not in this plan (an earlier grid).
    interrupted : bool
    outputs : dict of str to Path
    where : str
        What the runs ran on ("" when nothing needed running).
    workers_left : int
        Workers that left the scheduler while the sweep ran (died, or were stopped).
    dropped : int
        A cut-short last line dropped from ``runs.jsonl`` (0 or 1).
    """

    records: list[dict[str, Any]]
    skipped: int
    ran: int
    ok: int
    failed: int
    lost: int
    remaining: int
    outside_grid: int
    interrupted: bool
    outputs: dict[str, Path] = field(default_factory=dict)
    where: str = ""
    workers_left: int = 0
    dropped: int = 0


def run_sweep(plan: Plan, out: str | Path, *, workers: int | None = None,
              scheduler: str | None = None, client: Any = None, retry_failed: bool = False,
              plots: bool = True, on_progress: Callable[[Progress], None] | None = None,
              on_status: Callable[[str], None] | None = None) -> Outcome:
    """Run what ``plan`` still needs into ``out`` (see the module docstring).

    Parameters
    ----------
    plan : Plan
    out : path
        The sweep's folder.
    workers, scheduler :
        Where to run (:func:`adapt.sweep.cluster.connect`); ignored with ``client``.
    client : distributed.Client, optional
        An existing client to use (and leave open).
    retry_failed : bool
        Run again the runs recorded as failed.
    plots : bool
        Draw ``figures/``.
    on_progress, on_status : callable, optional
        Called with a :class:`Progress`, and with a line of text about the sweep
        (where it runs, what it waits for).
    """
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise SweepError(f"--out {str(folder)!r} is a file; expected a folder")
    _check_outputs(plan, folder)
    if client is None and scheduler is None and workers is not None:
        from adapt.sweep.cluster import check_workers

        check_workers(workers)  # before anything is written
    status = on_status or (lambda text: None)
    with RunLog(folder / "runs.jsonl") as log:
        _check_fingerprints(log, plan, folder)
        keys = {r.key for r in plan.runs}
        have = latest(log.records)
        finished = {k for k, r in have.items() if k in keys and (
            r.get("status") == "ok" or (r.get("status") == "failed" and not retry_failed))}
        todo = [r for r in plan.runs if r.key not in finished]
        state = _State(plan, log, todo, on_progress)
        interrupted = False
        where = ""
        left = 0
        if todo:
            with _connected(client, workers, scheduler) as conn:
                where = conn.description
                status(f"running {len(todo)} of {len(plan.runs)} runs on {where}")
                try:
                    _probe(conn, plan, status)
                    interrupted, left = _run(conn, todo, state)
                except KeyboardInterrupt:  # while waiting for workers
                    interrupted = True
                with _no_interrupt():
                    outcome = _finish(plan, folder, log, state, interrupted, where, left, plots)
            return outcome
        return _finish(plan, folder, log, state, interrupted, where, left, plots)


class _State:
    """Counts over the plan while the sweep runs."""

    def __init__(self, plan: Plan, log: RunLog, todo: list[RunSpec],
                 on_progress: Callable[[Progress], None] | None) -> None:
        self.plan = plan
        self.log = log
        self.skipped = len(plan.runs) - len(todo)
        keys = {r.key for r in plan.runs} - {r.key for r in todo}  # a retried run is to go
        self.status = {k: str(r.get("status")) for k, r in latest(log.records).items()
                       if k in keys}
        self.ran = 0
        self.on_progress = on_progress
        self.started = time.perf_counter()
        self.workers = 0
        self.workers_left = 0

    def append(self, record: dict[str, Any]) -> None:
        """Record a run that came back."""
        with _no_interrupt():  # a record is written whole or not at all
            self.log.append(record)
        self.status[record["key"]] = str(record.get("status"))
        self.ran += 1

    def counts(self) -> dict[str, int]:
        """ok, failed, lost and remaining over the plan (a run to retry counts as to go)."""
        return _counts(self.status.values(), len(self.plan.runs))

    def report(self, counts: dict[str, int] | None = None) -> None:
        if self.on_progress is None:
            return
        c = counts or self.counts()
        self.on_progress(Progress(len(self.plan.runs), c["ok"], c["failed"], c["lost"],
                                  c["remaining"], time.perf_counter() - self.started, self.ran,
                                  self.workers, self.workers_left))


@contextmanager
def _connected(client: Any, workers: int | None, scheduler: str | None) -> Iterator[Any]:
    from adapt.sweep.cluster import Connection, connect

    if client is not None:
        yield Connection(client, f"the scheduler at {client.scheduler.address}", False)
        return
    with connect(workers=workers, scheduler=scheduler) as conn:
        yield conn


def _probe(conn: Any, plan: Plan, status: Callable[[str], None]) -> None:
    """Wait for a worker; refuse workers that cannot run adapt or cannot see the scenario."""
    import adapt

    client = conn.client
    if not conn.workers():
        status("waiting for a worker to join the scheduler")
        client.wait_for_workers(1)
    try:
        found = client.run(probe, str(plan.scenario))
    except Exception as exc:
        raise SweepError(f"the workers cannot run adapt ({type(exc).__name__}: {exc}); "
                         "install adapt in the workers' environment (docs/sweeps.md)") from None
    try:  # a task goes through the scheduler, which must read it too
        client.submit(probe, str(plan.scenario), pure=False).result()
    except Exception as exc:
        first = str(exc).split("\n")[0].split(". ")[0]
        raise SweepError(f"a task of adapt's cannot go through the scheduler "
                         f"({type(exc).__name__}: {first}); the scheduler's environment needs "
                         "adapt too: pip install 'adapt[sweep]' where it runs "
                         "(docs/sweeps.md)") from None
    blind = sorted(addr for addr, info in found.items() if not info["scenario"])
    if blind:
        raise SweepError(f"{len(blind)} worker(s) cannot see the scenario {plan.scenario} "
                         f"(first: {blind[0]}); the scenario and its files must be at the same "
                         "path on every worker (a shared file system)")
    trimmed = sorted(addr for addr, info in found.items() if info.get("malloc_trim"))
    if trimmed:
        status(f"warning: {len(trimmed)} worker(s) run with MALLOC_TRIM_THRESHOLD_ set (Dask's "
               "default for workers it starts), which makes runs up to 2x slower; see "
               "docs/sweeps.md, 'On a cluster'")
    versions = sorted({info["adapt"] for info in found.values()} - {adapt.__version__})
    if versions:
        status(f"warning: some workers run adapt {', '.join(versions)}, this is "
               f"{adapt.__version__}")


def _run(conn: Any, todo: list[RunSpec], state: _State) -> tuple[bool, int]:
    """Submit ``todo`` and record every run as it comes back; (interrupted, workers left)."""
    from distributed import as_completed

    client = conn.client
    token = uuid.uuid4().hex[:8]
    names = [f"adapt-run-{token}-{spec.key}" for spec in todo]
    spec_of = dict(zip(names, todo))
    futures = client.map(run_task, todo, key=names, pure=False)
    seen = conn.workers()
    state.workers = len(seen)
    pending = as_completed(futures)
    recorded: set[str] = set()
    del futures
    try:
        last = asked = time.perf_counter()
        while not pending.is_empty():
            batch = pending.next_batch(block=False)
            for fut in batch:
                spec = spec_of[fut.key]
                record = _record_of(fut, spec)
                fut.release()
                if record is None or spec.key in recorded:
                    continue
                recorded.add(spec.key)
                state.append(record)
            now = time.perf_counter()
            if now - asked > 2.0:  # a round trip to the scheduler: not at every run
                current = conn.workers()
                seen |= current
                state.workers = len(current)
                state.workers_left = len(seen - current)
                asked = now
            if batch or now - last > 0.5:
                state.report()
                last = now
            if not batch:
                time.sleep(0.1)
        current = conn.workers()  # the last word on who left
        state.workers_left = len((seen | current) - current)
    except KeyboardInterrupt:
        with _no_interrupt():
            left = list(pending.futures)
            try:
                client.cancel(left)
            except Exception:  # pragma: no cover - the cluster is going away anyway
                pass
        return True, state.workers_left
    return False, state.workers_left


def _record_of(fut: Any, spec: RunSpec) -> dict[str, Any] | None:
    if fut.status == "finished":
        rec: dict[str, Any] | None = fut.result()
        return rec
    if fut.status == "cancelled":
        return None
    exc = fut.exception()
    return spec.record(status="lost", error=f"{type(exc).__name__}: {exc}")


@contextmanager
def _no_interrupt() -> Iterator[None]:
    """Hold off Ctrl-C while the outputs are written (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _counts(statuses: Iterable[str], total: int) -> dict[str, int]:
    out = {"ok": 0, "failed": 0, "lost": 0}
    for status in statuses:
        if status in out:
            out[status] += 1
    out["remaining"] = total - out["ok"] - out["failed"] - out["lost"]
    return out


def _check_outputs(plan: Plan, folder: Path) -> None:
    """Refuse, before anything is written, an output -- a file, or any file of ``figures/``
    (and ``runs/`` with ``--keep-outputs``) -- that would replace anything a run reads."""
    remedy = "choose another --out folder"
    outputs = [Output(f"the sweep's {name}", folder / name, remedy=remedy)
               for name in ("runs.jsonl", "sweep.json", "runs.csv")]
    outputs.append(Output("the sweep's figures", folder / "figures", folder=True, remedy=remedy))
    if any(spec.out is not None for spec in plan.runs):
        outputs.append(Output("the runs' outputs (--keep-outputs)", folder / "runs", folder=True,
                              remedy=remedy))
    check_outputs(outputs, Inputs([Input("the scenario", plan.scenario), *plan.inputs]))


def _check_fingerprints(log: RunLog, plan: Plan, folder: Path) -> None:
    other = [r for r in log.records if r.get("fingerprint") != plan.fingerprint]
    if other:
        raise SweepError(
            f"{folder / 'runs.jsonl'} holds {len(other)} run(s) of another version of the "
            f"scenario (fingerprint {other[0].get('fingerprint')}, now {plan.fingerprint}: the "
            "scenario file, one of its rule files or plugins or --max-frames changed since); "
            "their results would be mixed with new ones. Choose another --out folder, or move "
            "runs.jsonl away to start this folder over")


def _finish(plan: Plan, folder: Path, log: RunLog, state: _State, interrupted: bool,
            where: str, left: int, plots: bool) -> Outcome:
    have = latest(log.records)
    keys = {r.key for r in plan.runs}
    records = [have[r.key] for r in plan.runs if r.key in have]
    state.report()
    c = _counts((str(r.get("status")) for r in records), len(plan.runs))
    outputs: dict[str, Path] = {}
    figures: dict[str, Path] = {}
    if plots:
        from adapt.sweep.plots import write_plots

        figures = write_plots(records, plan.axes, folder / "figures",
                              title=f"{plan.scenario.name}: {c['ok']} runs")
    planned: dict[str, int] = {}
    for spec in plan.runs:
        cid = cell_id(dict(spec.set))
        planned[cid] = planned.get(cid, 0) + 1
    stats = summarise(records, plan.axes, planned)
    import adapt

    status = "interrupted" if interrupted else "complete" if c["remaining"] == 0 else "incomplete"
    doc = {
        "format": FORMAT, "adapt": adapt.__version__, "status": status,
        "written": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "grid": plan.describe(), "intervals": INTERVALS,
        "runs": {"planned": len(plan.runs), **c,
                 "outside_grid": len(set(have) - keys),
                 "ran_now": state.ran, "skipped": state.skipped},
        "metrics": metric_names(records),
        "figures": {k: str(p.relative_to(folder)) for k, p in figures.items()},
        "overall": stats["overall"], "by_parameter": stats["by_parameter"],
        "errors": stats["errors"], "cells": stats["cells"],
    }
    outputs["sweep"] = write_atomic(folder / "sweep.json",
                                    (json.dumps(doc, indent=1) + "\n").encode("utf-8"))
    outputs["csv"] = write_atomic(folder / "runs.csv",
                                  csv_text(records, plan.axes).encode("utf-8"))
    outputs["runs"] = log.path
    outputs.update(figures)
    return Outcome(records, state.skipped, state.ran, c["ok"], c["failed"], c["lost"],
                   c["remaining"], len(set(have) - keys), interrupted, outputs, where, left,
                   log.dropped)
