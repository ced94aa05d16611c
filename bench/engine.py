"""Engine benchmarks: adapt against real Soar on the same rule files (figures, not tests).

Run ``python bench/engine.py`` (``--quick`` for a smoke run).  Two workloads,
each written as a ``.soar`` file that both systems load unchanged:

* counter: one operator per decision (propose ``count``, apply ``^count n+1``)
  until ^count reaches 100,000 -- decisions per second.  Target: adapt
  >= 0.25 x real Soar.
* value join: one operator builds N objects of kind ``a`` (``^v 1..N``) and N
  of kind ``b`` (``^w 1..N``) on the top state, and one rule joins every
  ``a`` with the ``b`` of equal value -- seconds.  The rule is written so that
  a matcher which hashes joins on values can follow it in linear time
  (``(<x> ^v <v>) (<y> ^w <v>)`` before the link ``(<s> ^b <y>)``).  Targets: adapt >= 10 x faster than real
  Soar at N = 5,000, and adapt's time(20,000) / time(5,000) <= 5.

Each child may use at most 8 GB of address space (real Soar's value join
needs N^2 partial matches and runs out of memory at N = 20,000).  Every
measurement is the wall time of the run alone (the rule file is already
loaded) in a fresh child process: adapt via ``Agent(seed=1, matcher="rete")``
(no trace), real Soar via SML with a kernel created in the child's own thread,
``chunk never``, ``trace 0`` (watch 0), ``timers`` left at the default (on), no
event callbacks, timed around ``run``.  Medians of several runs.  Nothing is
asserted: a slow engine or a run past its time limit is reported.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

COUNTER = """\
sp {counter*propose*init
   (state <s> ^superstate nil -^count)
-->
   (<s> ^operator <o> + !)
   (<o> ^name init)}

sp {counter*apply*init
   (state <s> ^operator.name init)
-->
   (<s> ^count 0)}

sp {counter*propose*count
   (state <s> ^count { <c> < LIMIT })
-->
   (<s> ^operator <o> +)
   (<o> ^name count)}

sp {counter*apply*count
   (state <s> ^operator.name count ^count <c>)
-->
   (<s> ^count <c> - (+ <c> 1))}

sp {counter*halt
   (state <s> ^count LIMIT)
-->
   (halt)}
"""

JOIN_RULES = """
sp {join*propose*finish
   (state <s> ^built yes)
-->
   (<s> ^operator <o> +)
   (<o> ^name finish)}

sp {join*apply*finish
   (state <s> ^operator.name finish)
-->
   (halt)}

sp {join*equal-values
   (state <s> ^a <x>)
   (<x> ^v <v>)
   (<y> ^w <v>)
   (<s> ^b <y>)
-->
   (<x> ^partner <y>)}
"""


def counter_file(limit: int) -> str:
    return COUNTER.replace("LIMIT", str(limit))


def join_file(n: int) -> str:
    """One operator whose application builds the 2N objects; one join rule."""
    lines = ["sp {join*propose*build", "   (state <s> ^superstate nil -^built)", "-->",
             "   (<s> ^operator <o> + !)", "   (<o> ^name build)}", "",
             "sp {join*apply*build", "   (state <s> ^operator.name build)", "-->",
             "   (<s> ^built yes)"]
    for i in range(1, n + 1):
        lines.append(f"   (<s> ^a <a{i}> ^b <b{i}>) (<a{i}> ^v {i}) (<b{i}> ^w {i})")
    lines[-1] += "}"
    return "\n".join(lines) + "\n" + JOIN_RULES


# ---- children ---------------------------------------------------------------


def child_adapt(path: str, max_decisions: int) -> dict[str, object]:
    sys.path.insert(0, str(ROOT))
    from adapt.engine import Agent
    from adapt.engine.agent import DEFAULT_GC_THRESHOLD

    gc_env = os.environ.get("ADAPT_BENCH_GC", "")  # set by --gc-threshold
    gc_threshold = DEFAULT_GC_THRESHOLD if not gc_env else int(gc_env) or None
    agent = Agent(seed=1, matcher="rete", gc_threshold=gc_threshold)
    agent.load_file(path)
    start, cpu = time.perf_counter(), time.process_time()
    report = agent.run(max_decisions=max_decisions).to_dict()
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    return {"seconds": seconds, "cpu": cpu, "decisions": report["decisions"],
            "halted": report["halted"], "firings": report["production_firings"]}


def child_soar(path: str, max_decisions: int) -> dict[str, object]:
    import soar_sml

    kernel = soar_sml.Kernel.CreateKernelInCurrentThread(True, soar_sml.Kernel.kSuppressListener)
    agent = kernel.CreateAgent("bench")
    for command in ("chunk never", "trace 0", "decide set-random-seed 1"):
        agent.ExecuteCommandLine(command)
    agent.ExecuteCommandLine(f'source "{path}"')
    if not agent.GetLastCommandLineResult():
        return {"error": "load failed"}
    start = time.perf_counter()
    agent.ExecuteCommandLine(f"run {max_decisions}")
    seconds = time.perf_counter() - start
    stats = agent.ExecuteCommandLine("stats")
    firings = next((int(line.split()[0]) for line in stats.splitlines()
                    if " production firings" in line and line.split()[0].isdigit()), None)
    halted = agent.GetRunState() == soar_sml.sml_RUNSTATE_HALTED
    return {"seconds": seconds, "decisions": agent.GetDecisionCycleCounter(), "halted": halted,
            "firings": firings}


MEMORY_LIMIT_GB = 8.0  # per child: a quadratic run fails alone instead of starving the machine


def _limit_memory() -> None:
    import resource

    limit = int(MEMORY_LIMIT_GB * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def measure(system: str, path: Path, max_decisions: int, timeout: float) -> dict[str, object]:
    argv = [sys.executable, str(Path(__file__).resolve()), "--child", system, str(path),
            str(max_decisions)]
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=timeout,
                              preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired:
        return {"error": f"over the {timeout:.0f} s limit"}
    try:
        return dict(json.loads(proc.stdout.decode().strip().splitlines()[-1]))
    except (ValueError, IndexError):
        how = (f"killed by signal {-proc.returncode}" if proc.returncode < 0
               else f"exit status {proc.returncode}")
        hint = (f" (out of memory? each child may use {MEMORY_LIMIT_GB:g} GB)"
                if proc.returncode in (-9, -6, 134, 137) else "")
        return {"error": f"child failed: {how}{hint} {proc.stderr.decode()[-300:]}".rstrip()}


def median_of(system: str, path: Path, max_decisions: int, runs: int,
              timeout: float) -> tuple[float | None, dict[str, object]]:
    good: list[dict[str, object]] = []
    for _ in range(runs):
        result = measure(system, path, max_decisions, timeout)
        if "seconds" not in result:
            return None, result  # no point repeating a failure or a timeout
        good.append(result)
    first = dict(good[0])
    if all("cpu" in r for r in good):  # adapt's children also report CPU seconds
        first["cpu"] = statistics.median(float(r["cpu"]) for r in good)
    return statistics.median(float(r["seconds"]) for r in good), first


def fmt(seconds: float | None) -> str:
    return "   n/a" if seconds is None else f"{seconds:8.3f} s"


# ---- the two workloads -----------------------------------------------------------


def bench_counter(tmp: Path, limit: int, runs: int, timeout: float,
                  systems: tuple[str, ...] = ("soar", "adapt")) -> None:
    path = tmp / "counter.soar"
    path.write_text(counter_file(limit))
    print(f"counter: one operator per decision, counting to {limit:,} (median of {runs})")
    rates: dict[str, float] = {}
    for system in systems:
        seconds, info = median_of(system, path, limit + 10, runs, timeout)
        if seconds is None:
            print(f"  {system:<6} {info.get('error')}")
            continue
        decisions = int(info["decisions"])
        rates[system] = decisions / seconds
        print(f"  {system:<6} {decisions:,} decisions in {fmt(seconds)}  ->  "
              f"{rates[system]:,.0f} decisions/s  (halted: {info['halted']})")
    if len(rates) == 2:
        ratio = rates["adapt"] / rates["soar"]
        verdict = "meets" if ratio >= 0.25 else "MISSES"
        print(f"  ratio adapt/Soar = {ratio:.3f}  (target >= 0.25: {verdict})")


def bench_join(tmp: Path, sizes: list[int], runs: int, timeout: float,
               systems: tuple[str, ...] = ("soar", "adapt")) -> None:
    print(f"value join: N objects of each of two kinds, one rule joining equal values "
          f"(median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"join-{n}.soar"
        path.write_text(join_file(n))
        row = []
        for system in systems:
            seconds, info = median_of(system, path, 10, runs, timeout)
            if seconds is not None:
                times[(system, n)] = seconds
                cpu = f", CPU {float(info['cpu']):.3f} s" if "cpu" in info else ""
                if "cpu" in info:
                    times[("adapt-cpu", n)] = float(info["cpu"])
                row.append(f"{system} {fmt(seconds)} ({info['firings']} firings{cpu})")
            else:
                row.append(f"{system} {info.get('error')}")
        speedup = ""
        if ("soar", n) in times and ("adapt", n) in times:
            speedup = f"  speed-up Soar/adapt {times[('soar', n)] / times[('adapt', n)]:.2f}x"
        print(f"  N = {n:>6,}:  " + ",  ".join(row) + speedup)
    if ("soar", 5000) in times and ("adapt", 5000) in times:
        speedup = times[("soar", 5000)] / times[("adapt", 5000)]
        verdict = "meets" if speedup >= 10 else "MISSES"
        print(f"  N = 5,000: adapt {speedup:.1f}x faster than Soar (target >= 10: {verdict})")
    if ("adapt", 5000) in times and ("adapt", 20000) in times:
        growth = times[("adapt", 20000)] / times[("adapt", 5000)]
        verdict = "meets" if growth <= 5 else "MISSES"
        print(f"  adapt time(20,000) / time(5,000) = {growth:.2f} (target <= 5: {verdict})")
        if ("adapt-cpu", 5000) in times and ("adapt-cpu", 20000) in times:
            print(f"  adapt CPU time(20,000) / CPU time(5,000) = "
                  f"{times[('adapt-cpu', 20000)] / times[('adapt-cpu', 5000)]:.2f}")
    if ("soar", 5000) in times and ("soar", 20000) in times:
        print(f"  Soar  time(20,000) / time(5,000) = "
              f"{times[('soar', 20000)] / times[('soar', 5000)]:.2f}")


def main() -> int:
    if len(sys.argv) == 5 and sys.argv[1] == "--child":
        runner = child_soar if sys.argv[2] == "soar" else child_adapt
        print(json.dumps(runner(sys.argv[3], int(sys.argv[4]))), flush=True)
        os._exit(0)  # the native kernel sometimes misbehaves at interpreter exit
    parser = argparse.ArgumentParser(description="adapt vs real Soar: counter and value join")
    parser.add_argument("--quick", action="store_true", help="small sizes, one run each")
    parser.add_argument("--runs", type=int, default=None, help="runs per figure (default 3)")
    parser.add_argument("--timeout", type=float, default=300.0,
                        help="limit per single run, seconds (default 300)")
    parser.add_argument("--only", choices=("counter", "join"), default=None,
                        help="run one workload only")
    parser.add_argument("--sizes", default=None,
                        help="value-join sizes, comma-separated (default 1000,5000,20000)")
    parser.add_argument("--systems", default="soar,adapt",
                        help="comma-separated subset of soar,adapt (default both)")
    parser.add_argument("--gc-threshold", type=int, default=None,
                        help="adapt's Agent(gc_threshold=...); 0 leaves Python's collector "
                             "alone (default: the agent's default policy)")
    opts = parser.parse_args()
    runs = opts.runs or (1 if opts.quick else 3)
    limit = 5_000 if opts.quick else 100_000
    sizes = [500, 1_000] if opts.quick else [1_000, 5_000, 20_000]
    if opts.sizes:
        sizes = [int(n) for n in opts.sizes.split(",")]
    systems = tuple(s for s in ("soar", "adapt") if s in opts.systems.split(","))
    if opts.gc_threshold is not None:
        os.environ["ADAPT_BENCH_GC"] = str(opts.gc_threshold)
    gc_note = ("default" if opts.gc_threshold is None
               else "off" if opts.gc_threshold == 0 else str(opts.gc_threshold))
    print(f"bench/engine.py  {time.strftime('%Y-%m-%d %H:%M')}  python {sys.version.split()[0]}"
          f"  cpus {os.cpu_count()}  adapt gc_threshold: {gc_note}")
    with tempfile.TemporaryDirectory() as tmp:
        if opts.only in (None, "counter"):
            bench_counter(Path(tmp), limit, runs, opts.timeout, systems)
        if opts.only in (None, "join"):
            bench_join(Path(tmp), sizes, runs, opts.timeout, systems)
    return 0


if __name__ == "__main__":
    sys.exit(main())
