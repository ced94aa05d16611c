"""``adapt sweep``: run a scenario over seeds and a grid of parameters, on Dask.

``adapt sweep SCENARIO.yaml [--seeds 1-200] [--set KEY=V1,V2,...]... [--workers N | --scheduler ADDRESS] [--out DIR]``
    runs the product of the seeds and the ``--set`` values (each a list, or
    a range ``lo:hi:step``), one run per task, and writes ``runs.jsonl``,
    ``sweep.json``, ``runs.csv`` and ``figures/`` into DIR (default
    ``sweeps/<scenario name>``).  Running it again with the same DIR resumes.
    See ``docs/sweeps.md``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from adapt.cli.exits import Exit
from adapt.cli.progress import ProgressLine
from adapt.cli.values import folder_name

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add ``sweep``."""
    p = sub.add_parser(
        "sweep", help="run a scenario over many seeds and a parameter grid, on Dask",
        description="Run SCENARIO once per seed and per combination of the --set values, on an "
        "embedded local Dask cluster or on a Dask scheduler; write runs.jsonl (as runs finish), "
        "sweep.json (rates with 95% Wilson intervals, medians, percentiles per grid cell), "
        "runs.csv and figures/. Running it again with the same --out resumes.",
        epilog="Example: adapt sweep scenarios/room.yaml --seeds 1-200 "
        "--set world.objects.ball.restitution=0.6:0.9:0.1 --set "
        "reality.camera_offset_deg=0,1,2 --out sweeps/room")
    p.add_argument("scenario", metavar="SCENARIO.yaml")
    p.add_argument("--seeds", metavar="SEEDS",
                   help="seeds and inclusive ranges, comma-separated: 1-200, 1,5,9, 1-10,50-60 "
                   "(default: the scenario's seed)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUES",
                   help="a scenario key path and its values, comma-separated YAML values or "
                   "ranges lo:hi:step (inclusive): world.objects.ball.restitution=0.6,0.8 or "
                   "=0.5:0.9:0.1; repeat for more axes of the grid")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help="worker processes of the embedded local cluster (default: one per "
                       "core)")
    where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="a running Dask scheduler (tcp://host:8786) or its scheduler file "
                       "(.json) instead of the embedded cluster")
    p.add_argument("--out", metavar="DIR", type=folder_name,
                   help="output folder (default sweeps/<scenario name>)")
    p.add_argument("--max-frames", type=int, default=None, metavar="N",
                   help="stop each run after N frames (default: the scenario's run section)")
    p.add_argument("--keep-outputs", action="store_true",
                   help="let every run write the outputs its scenario asks for (report, trace, "
                   "video, figures) into DIR/runs/<key>/")
    p.add_argument("--retry-failed", action="store_true",
                   help="when resuming, run again the runs recorded as failed")
    p.add_argument("--no-plots", action="store_true", help="do not draw figures/")
    p.add_argument("--json", action="store_true",
                   help="print the counts, the overall statistics and the outputs as JSON")
    p.add_argument("--quiet", action="store_true", help="print no progress line")
    p.set_defaults(func=_sweep)


class _ProgressLine(ProgressLine):
    """``  37/200 runs  35 ok  2 failed  163 to go  1.9 runs/s  ~1m25s  2 workers``."""

    def __call__(self, p: Any) -> None:
        rate = p.ran / p.elapsed if p.elapsed > 0 else 0.0
        eta = f"  ~{_duration(p.remaining / rate)} left" if rate > 0 and p.remaining else ""
        lost = f"  {p.lost} lost" if p.lost else ""
        gone = f", {p.workers_left} left" if p.workers_left else ""
        text = (f"{p.done}/{p.total} runs  {p.ok} ok  {p.failed} failed{lost}  "
                f"{p.remaining} to go  {rate:.2f} runs/s{eta}  {p.workers} worker"
                f"{'s' * (p.workers != 1)}{gone}")
        self.show(text)


def _duration(seconds: float) -> str:
    s = int(round(seconds))
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{s % 3600 // 60:02d}m"


def _sweep(args: argparse.Namespace) -> int:
    from adapt.sweep.cluster import require_dask
    from adapt.sweep.plan import make_plan
    from adapt.sweep.session import run_sweep

    require_dask()
    out = Path(args.out) if args.out else Path("sweeps") / Path(args.scenario).stem
    plan = make_plan(args.scenario, seeds=args.seeds, sets=args.sets,
                     max_frames=args.max_frames, out=out, keep_outputs=args.keep_outputs)
    cells = len(plan.cells)
    if not args.json:
        print(f"sweep: {len(plan.runs)} runs = {len(plan.seeds)} seed"
              f"{'s' * (len(plan.seeds) != 1)} x {cells} grid cell{'s' * (cells != 1)}; "
              f"output {out}", file=sys.stderr)
    bar = _ProgressLine(sys.stderr) if sys.stderr.isatty() and not args.quiet else None

    def status(text: str) -> None:
        if bar is not None:
            bar.clear()
        if not args.json:
            print(f"sweep: {text}", file=sys.stderr)

    try:
        outcome = run_sweep(plan, out, workers=args.workers, scheduler=args.scheduler,
                            retry_failed=args.retry_failed, plots=not args.no_plots,
                            on_progress=bar, on_status=status)
    finally:
        if bar is not None:
            bar.clear()
    if args.json:
        doc = json.loads(outcome.outputs["sweep"].read_text(encoding="utf-8"))
        print(json.dumps({"status": doc["status"], "runs": doc["runs"],
                          "overall": doc["overall"],
                          "outputs": {k: str(v) for k, v in outcome.outputs.items()}}))
    else:
        _print_outcome(outcome, out)
    if outcome.interrupted:
        return int(Exit.INTERRUPTED)
    if outcome.failed or outcome.lost or outcome.remaining:
        return int(Exit.RUNS_FAILED)
    return int(Exit.OK)


def _print_outcome(o: Any, out: Path) -> None:
    if o.dropped:
        print(f"note: the last line of {out / 'runs.jsonl'} was cut short (the sweep was killed "
              "while writing it); that run was run again")
    state = "interrupted" if o.interrupted else "done"
    print(f"{state}: {o.ok} ok, {o.failed} failed, {o.lost} lost, {o.remaining} to go "
          f"({o.ran} ran now{f' on {o.where}' if o.where else ''}, {o.skipped} already in "
          f"{out / 'runs.jsonl'})")
    if o.workers_left:
        print(f"{o.workers_left} worker(s) left the cluster while it ran (died or were "
              "stopped); their unfinished runs were run again elsewhere")
    if o.outside_grid:
        print(f"{o.outside_grid} run(s) in runs.jsonl are not in this grid: kept there, left "
              "out of sweep.json")
    doc = json.loads(o.outputs["sweep"].read_text(encoding="utf-8"))
    overall = doc["overall"]
    rates, values = overall["rates"], overall["values"]

    def pct(r: dict[str, Any]) -> str:
        return f"{100 * r['rate']:.0f}% ({100 * r['low']:.0f}-{100 * r['high']:.0f}%)"

    def spread(v: dict[str, Any]) -> str:
        return f"{v['median']:.4g} (p10 {v['p10']:.4g}, p90 {v['p90']:.4g})"

    for name, r in rates.items():
        peer = rates.get(f"baseline_{name}")
        if r["n"] and not name.startswith("baseline_"):
            print(f"{name}: {pct(r)} of {r['n']} runs (95% Wilson interval)"
                  + (f"; baseline {pct(peer)}" if peer and peer["n"] else ""))
    for name, v in values.items():
        peer = values.get(f"baseline_{name}")
        if v.get("n") and not name.startswith("baseline_") and name not in ("frames", "wall_s"):
            print(f"{name}: median {spread(v)} over {v['n']} runs"
                  + (f"; baseline {spread(peer)}" if peer and peer.get("n") else ""))
    for e in doc["errors"][:3]:
        print(f"{e['runs']} run{'s' * (e['runs'] != 1)} not finished: {e['error']}")
    for path in o.outputs.values():
        print(f"wrote {path}")
