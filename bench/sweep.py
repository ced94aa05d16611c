"""Speed-up of a sweep from 1 to 2 Dask workers, and its cost per task (figures, not tests).

Run ``python bench/sweep.py`` (about four minutes on a quiet machine; ``--quick``: one round).  The
machine's load average is printed before and after: on a shared machine other jobs take cores
from the workers, and the per-round ratios show how much.  The
runs are ``scenarios/unexpected-object.yaml`` (640x480, the Fig. 5 scene: a ball of reality
only rolls in and a schema is spawned for it) for ``--frames`` frames each, seeds 1..N.
Three ways of running the same N runs are timed, interleaved over ``--rounds`` rounds, and
their medians compared:

``loop``
    a plain loop in a process of its own (no Dask in it): ``run_task(spec)`` for every run,
    nothing else (the same function a worker runs, with OpenCV on one thread as in a worker);
``1 worker``, ``2 workers``
    ``run_sweep`` on an embedded local cluster of 1 or 2 worker processes (one cluster alive at
    a time): submitting, running, sending every record back, appending it to ``runs.jsonl``
    and writing ``sweep.json`` and ``runs.csv`` (no figures).

Besides wall time, the CPU time every process spends is counted (the loop's process; for a
sweep this process, which holds the client and the embedded scheduler, plus the worker
processes, through psutil): on a shared
machine CPU time is far less disturbed by other jobs than wall time, so the overhead per task is
also given as CPU, ``(CPU_1worker - CPU_loop) / N``.

The speed-up needs the machine's 2 cores: the ``cores obtained`` (CPU seconds over wall
seconds) of each configuration show how much of them other jobs left, and the CPU time of 2
workers over 1 worker for the same runs bounds the speed-up on 2 whole cores (2 divided by it).

Every process is warmed up first (one run each, untimed), so the figures are of the steady
state; starting a cluster and the first run in a fresh worker (imports, textures) are printed
apart.  Printed: the speed-up 2 workers / 1 worker (target >= 1.7x on 2 cores) and the
overhead per task of 1 worker against the loop, ``(T_1worker - T_loop) / N``, in
milliseconds and as a share of a run (target <= 5 %).
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import statistics
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import cv2  # noqa: E402
import psutil  # noqa: E402  (installed with dask[distributed])

from adapt.sweep.cluster import connect  # noqa: E402
from adapt.sweep.plan import make_plan  # noqa: E402
from adapt.sweep.session import run_sweep  # noqa: E402
from adapt.sweep.task import RunSpec, run_task  # noqa: E402

SCENARIO = ROOT / "scenarios" / "unexpected-object.yaml"


def _loop(specs: list[RunSpec]) -> tuple[float, float]:
    """In the loop's own process: run ``specs`` one after the other; (wall s, CPU s)."""
    cv2.setNumThreads(1)  # as in a worker: one core per run
    c0, t0 = time.process_time(), time.perf_counter()
    for spec in specs:
        run_task(spec)
    return time.perf_counter() - t0, time.process_time() - c0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=8, help="runs per measurement (default 8)")
    ap.add_argument("--frames", type=int, default=30, help="frames per run (default 30)")
    ap.add_argument("--rounds", type=int, default=8, help="interleaved rounds (default 8)")
    ap.add_argument("--quick", action="store_true", help="8 runs, 1 round")
    args = ap.parse_args()
    if args.quick:
        args.runs, args.rounds = 8, 1
    plan = make_plan(SCENARIO, seeds=f"1-{args.runs}", max_frames=args.frames)
    warm = list(make_plan(SCENARIO, seeds="1000-1001", max_frames=args.frames).runs)
    print(f"{args.runs} runs of {SCENARIO.name}, {args.frames} frames each; "
          f"{args.rounds} round(s), medians; load average {_load()}")

    times: dict[str, list[float]] = {"loop": [], "1 worker": [], "2 workers": []}
    cpu: dict[str, list[float]] = {k: [] for k in times}
    me = psutil.Process()
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        wall, _ = pool.submit(_loop, warm[:1]).result()
        print(f"loop process: first run (imports, textures) {wall:.2f} s")
        for r in range(args.rounds):
            wall, used = pool.submit(_loop, list(plan.runs)).result()
            times["loop"].append(wall)
            cpu["loop"].append(used)
            for n, name in ((1, "1 worker"), (2, "2 workers")):
                # one cluster at a time, started and warmed up (one run per worker) untimed
                t0 = time.perf_counter()
                with connect(workers=n) as conn:
                    client = conn.client
                    started = time.perf_counter() - t0
                    t0 = time.perf_counter()
                    client.gather(client.map(run_task, warm[:n], pure=False))
                    if r == 0:
                        print(f"{name}: cluster started in {started:.2f} s, first run per "
                              f"worker {time.perf_counter() - t0:.2f} s")
                    procs = [me] + [psutil.Process(p) for p in client.run(os.getpid).values()]
                    with tempfile.TemporaryDirectory() as d:
                        c0 = _cpu(procs)
                        t0 = time.perf_counter()
                        out = run_sweep(plan, d, client=client, plots=False)
                        times[name].append(time.perf_counter() - t0)
                        cpu[name].append(_cpu(procs) - c0)
                    assert out.ok == args.runs, (out.ok, out.failed, out.lost)
            print(f"round {r + 1}: " + ", ".join(f"{k} {v[-1]:.2f} s" for k, v in times.items())
                  + f"; speed-up {times['1 worker'][-1] / times['2 workers'][-1]:.2f}x, "
                  f"1 worker / loop {times['1 worker'][-1] / times['loop'][-1]:.3f}; cores "
                  "obtained " + "/".join(f"{cpu[k][-1] / times[k][-1]:.2f}" for k in times)
                  + f"; load {_load()}")
    med = {k: statistics.median(v) for k, v in times.items()}
    per_run = med["loop"] / args.runs
    overhead = (med["1 worker"] - med["loop"]) / args.runs
    print()
    print(f"{'':12s} {'median s':>9s} {'s per run':>10s}")
    for k, v in med.items():
        print(f"{k:12s} {v:9.2f} {v / args.runs:10.3f}")
    print()
    speedups = [a / b for a, b in zip(times["1 worker"], times["2 workers"])]
    ratios = [a / b for a, b in zip(times["1 worker"], times["loop"])]
    print(f"speed-up 1 -> 2 workers: {med['1 worker'] / med['2 workers']:.2f}x of the medians, "
          f"{statistics.median(speedups):.2f}x median of the rounds (best {max(speedups):.2f}x)"
          " (target >= 1.7x)")
    whole = [sp for sp, c, t in zip(speedups, cpu["2 workers"], times["2 workers"])
             if c / t >= 1.8]
    if whole:
        print(f"speed-up in the {len(whole)} round(s) where 2 workers obtained >= 1.8 cores: "
              f"median {statistics.median(whole):.2f}x (" + ", ".join(f"{v:.2f}" for v in whole)
              + ")")
    else:
        print("no round gave 2 workers >= 1.8 cores: other jobs held the machine")
    print(f"1 worker / loop: median of the rounds {statistics.median(ratios):.3f} "
          f"(best {min(ratios):.3f})")
    print(f"overhead per task, 1 worker vs loop: {1000 * overhead:+.1f} ms = "
          f"{100 * overhead / per_run:+.1f} % of a run (wall time; target <= 5 %)")
    cmed = {k: statistics.median(v) for k, v in cpu.items()}
    cpu_over = (cmed["1 worker"] - cmed["loop"]) / args.runs
    print("CPU s per run (all processes): " + ", ".join(
        f"{k} {v / args.runs:.3f}" for k, v in cmed.items()))
    print(f"overhead per task, 1 worker vs loop, CPU: {1000 * cpu_over:+.1f} ms = "
          f"{100 * cpu_over / (cmed['loop'] / args.runs):+.1f} % of a run's CPU")
    print(f"2 workers vs loop: {med['loop'] / med['2 workers']:.2f}x; load average {_load()}")
    extra = statistics.median(b / a for a, b in zip(cpu["1 worker"], cpu["2 workers"]))
    print(f"CPU time of 2 workers / 1 worker for the same runs (median of the rounds): {extra:.3f}"
          f"; so on 2 whole cores the speed-up is at most {2 / extra:.2f}x")
    print("cores obtained (CPU s / wall s, medians over rounds): " + ", ".join(
        f"{k} {statistics.median(c / t for c, t in zip(cpu[k], times[k])):.2f}" for k in times)
        + " (2 workers on an idle 2-core machine: about 2)")


def _cpu(procs: list[psutil.Process]) -> float:
    """User + system CPU seconds of ``procs`` so far."""
    total = 0.0
    for p in procs:
        t = p.cpu_times()
        total += t.user + t.system
    return total


def _load() -> str:
    return " ".join(f"{v:.1f}" for v in os.getloadavg())


if __name__ == "__main__":
    main()
