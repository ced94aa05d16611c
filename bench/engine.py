"""Engine benchmarks: adapt against real Soar on the same rule files (figures, not tests).

Run ``python bench/engine.py`` (``--quick`` for a smoke run).  Two workloads,
each written as a ``.soar`` file that both systems load unchanged:

* counter: one operator per decision (propose ``count``, apply ``^count n+1``)
  until ^count reaches 100,000 -- decisions per second.  Target: adapt
  >= 0.25 x real Soar.
* value join: one operator builds N objects of kind ``a`` (``^v 1..N``) and N
  of kind ``b`` (``^w 1..N``) on the top state, and one rule joins every
  ``a`` with the ``b`` of equal value -- seconds.  With ``multi-attributes``
  hints for ``^a`` and ``^b`` (N values each), a matcher which hashes joins on
  values orders the join on ``<v>`` first and follows it in linear time.  Targets: adapt >= 10 x faster than real
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


def rules_file(n: int) -> str:
    """``n`` generated rules of a realistic shape: a proposal each, testing the top
    state, a linked object with a relational test and a negated condition
    (50 task values and 7 kinds shared among them, so the Rete shares nodes)."""
    out = []
    for i in range(n):
        out.append(f"""sp {{gen*rule*{i}
   (state <s> ^superstate nil ^task t{i % 50} ^item <x>)
   (<x> ^kind k{i % 7} ^value {{ <v> > {i % 13} }})
   -(<x> ^blocked v{i})
-->
   (<s> ^operator <o> + =)
   (<o> ^name op{i} ^arg <v>)}}
""")
    return "\n".join(out)


def counter_file(limit: int) -> str:
    return COUNTER.replace("LIMIT", str(limit))


def join_file(n: int) -> str:
    """One operator whose application builds the 2N objects; one join rule.

    The ``multi-attributes`` hints say that ``^a`` and ``^b`` have N values:
    the conditions are reordered as Soar reorders them, and with the hints the
    join on ``<v>`` comes before the link ``(<s> ^b <y>)`` (see
    ``adapt/engine/reorder.py``); Soar, which joins on identifiers only,
    gets no help from them."""
    lines = [f"multi-attributes a {n}", f"multi-attributes b {n}", "",
             "sp {join*propose*build", "   (state <s> ^superstate nil -^built)", "-->",
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
    from adapt.engine import Agent, engine_build
    from adapt.engine.agent import DEFAULT_GC_THRESHOLD

    gc_env = os.environ.get("ADAPT_BENCH_GC", "")  # set by --gc-threshold
    gc_threshold = DEFAULT_GC_THRESHOLD if not gc_env else int(gc_env) or None
    agent = Agent(seed=1, matcher="rete", gc_threshold=gc_threshold)
    if max_decisions < 0:  # loading alone: parse, build the Rete
        start = time.perf_counter()
        rules = agent.load_file(path)
        return {"seconds": time.perf_counter() - start, "rules": len(rules.productions),
                "engine": engine_build()}
    agent.load_file(path)
    start, cpu = time.perf_counter(), time.process_time()
    report = agent.run(max_decisions=max_decisions).to_dict()
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    return {"seconds": seconds, "cpu": cpu, "decisions": report["decisions"],
            "halted": report["halted"], "firings": report["production_firings"],
            "engine": engine_build()}


def child_soar(path: str, max_decisions: int) -> dict[str, object]:
    import soar_sml

    kernel = soar_sml.Kernel.CreateKernelInCurrentThread(True, soar_sml.Kernel.kSuppressListener)
    agent = kernel.CreateAgent("bench")
    for command in ("chunk never", "trace 0", "decide set-random-seed 1"):
        agent.ExecuteCommandLine(command)
    start = time.perf_counter()
    agent.ExecuteCommandLine(f'source "{path}"')
    loaded = time.perf_counter() - start
    if not agent.GetLastCommandLineResult():
        return {"error": "load failed"}
    if max_decisions < 0:
        return {"seconds": loaded}
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


#: The systems a run compares: real Soar, adapt as installed (compiled where it
#: could be built) and adapt forced to its pure-Python source.
SYSTEMS = ("soar", "adapt", "adapt-py")


def measure(system: str, path: Path, max_decisions: int, timeout: float) -> dict[str, object]:
    argv = [sys.executable, str(Path(__file__).resolve()), "--child", system, str(path),
            str(max_decisions)]
    env = dict(os.environ)
    env.pop("ADAPT_PURE_PYTHON", None)
    if system == "adapt-py":
        env["ADAPT_PURE_PYTHON"] = "1"
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=timeout,
                              preexec_fn=_limit_memory, env=env)
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


def interleaved(systems: tuple[str, ...], path: Path, max_decisions: int, runs: int,
                timeout: float) -> dict[str, tuple[float | None, dict[str, object]]]:
    """Median seconds and the first run's details of each system, the systems'
    runs interleaved round by round (so that a noisy neighbour hits all of them)."""
    good: dict[str, list[dict[str, object]]] = {s: [] for s in systems}
    failed: dict[str, dict[str, object]] = {}
    for _ in range(runs):
        for system in systems:
            if system in failed:
                continue
            result = measure(system, path, max_decisions, timeout)
            if "seconds" not in result:
                failed[system] = result  # no point repeating a failure or a timeout
            else:
                good[system].append(result)
    out: dict[str, tuple[float | None, dict[str, object]]] = {}
    for system in systems:
        if system in failed:
            out[system] = (None, failed[system])
            continue
        first = dict(good[system][0])
        if all("cpu" in r for r in good[system]):
            first["cpu"] = statistics.median(float(r["cpu"]) for r in good[system])
        out[system] = (statistics.median(float(r["seconds"]) for r in good[system]), first)
    return out


def fmt(seconds: float | None) -> str:
    return "   n/a" if seconds is None else f"{seconds:8.3f} s"


# ---- the two workloads -----------------------------------------------------------


def bench_counter(tmp: Path, limit: int, runs: int, timeout: float,
                  systems: tuple[str, ...] = SYSTEMS) -> None:
    path = tmp / "counter.soar"
    path.write_text(counter_file(limit))
    print(f"counter: one operator per decision, counting to {limit:,} (median of {runs})")
    rates: dict[str, float] = {}
    for system, (seconds, info) in interleaved(systems, path, limit + 10, runs, timeout).items():
        if seconds is None:
            print(f"  {system:<8} {info.get('error')}")
            continue
        decisions = int(info["decisions"])  # type: ignore[call-overload]
        rates[system] = decisions / seconds
        engine = f", {info['engine']}" if "engine" in info else ""
        print(f"  {system:<8} {decisions:,} decisions in {fmt(seconds)}  ->  "
              f"{rates[system]:,.0f} decisions/s  (halted: {info['halted']}{engine})")
    for system in ("adapt", "adapt-py"):
        if system in rates and "soar" in rates:
            ratio = rates[system] / rates["soar"]
            verdict = "meets" if ratio >= 0.25 else "MISSES"
            print(f"  ratio {system}/Soar = {ratio:.3f}  (target >= 0.25: {verdict})")
    if "adapt" in rates and "adapt-py" in rates:
        print(f"  adapt (as installed) / adapt pure Python = {rates['adapt'] / rates['adapt-py']:.2f}x")


def bench_load(tmp: Path, sizes: list[int], runs: int, timeout: float,
               systems: tuple[str, ...] = SYSTEMS) -> None:
    print(f"loading N generated rules: parse and build the matcher (median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"rules-{n}.soar"
        path.write_text(rules_file(n))
        row = []
        for system, (seconds, info) in interleaved(systems, path, -1, runs, timeout).items():
            if seconds is None:
                row.append(f"{system} {info.get('error')}")
                continue
            times[(system, n)] = seconds
            row.append(f"{system} {fmt(seconds)}")
        print(f"  N = {n:>6,}:  " + ",  ".join(row))
    for system in ("adapt", "adapt-py"):
        if (system, 10_000) in times and ("soar", 10_000) in times:
            ratio = times[(system, 10_000)] / times[("soar", 10_000)]
            verdict = "meets" if ratio <= 2 else "MISSES"
            print(f"  N = 10,000: {system} / Soar = {ratio:.1f}x the time (target <= 2: {verdict})")
        if (system, 10_000) in times and (system, 20_000) in times:
            growth = times[(system, 20_000)] / times[(system, 10_000)]
            verdict = "meets" if growth <= 2.5 else "MISSES"
            print(f"  {system} time(20,000) / time(10,000) = {growth:.2f} (target <= 2.5: {verdict})")
    if ("soar", 10_000) in times and ("soar", 20_000) in times:
        print(f"  soar time(20,000) / time(10,000) = "
              f"{times[('soar', 20_000)] / times[('soar', 10_000)]:.2f}")


def bench_join(tmp: Path, sizes: list[int], runs: int, timeout: float,
               systems: tuple[str, ...] = ("soar", "adapt")) -> None:
    print(f"value join: N objects of each of two kinds, one rule joining equal values "
          f"(median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"join-{n}.soar"
        path.write_text(join_file(n))
        row = []
        for system, (seconds, info) in interleaved(systems, path, 10, runs, timeout).items():
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
        runner = child_soar if sys.argv[2] == "soar" else child_adapt  # adapt, adapt-py
        print(json.dumps(runner(sys.argv[3], int(sys.argv[4]))), flush=True)
        os._exit(0)  # the native kernel sometimes misbehaves at interpreter exit
    parser = argparse.ArgumentParser(description="adapt vs real Soar: counter, value join, loading")
    parser.add_argument("--quick", action="store_true", help="small sizes, one run each")
    parser.add_argument("--runs", type=int, default=None, help="runs per figure (default 3)")
    parser.add_argument("--timeout", type=float, default=300.0,
                        help="limit per single run, seconds (default 300)")
    parser.add_argument("--only", choices=("counter", "join", "load"), default=None,
                        help="run one workload only")
    parser.add_argument("--sizes", default=None,
                        help="value-join sizes, comma-separated (default 1000,5000,20000)")
    parser.add_argument("--load-sizes", default=None,
                        help="rule-base sizes, comma-separated (default 2500,5000,10000,20000)")
    parser.add_argument("--systems", default=",".join(SYSTEMS),
                        help="comma-separated subset of soar,adapt,adapt-py (default all; "
                             "adapt-py is adapt forced to its pure-Python source; the value "
                             "join runs soar and adapt)")
    parser.add_argument("--gc-threshold", type=int, default=None,
                        help="adapt's Agent(gc_threshold=...); 0 leaves Python's collector "
                             "alone (default: the agent's default policy)")
    opts = parser.parse_args()
    runs = opts.runs or (1 if opts.quick else 3)
    limit = 5_000 if opts.quick else 100_000
    sizes = [500, 1_000] if opts.quick else [1_000, 5_000, 20_000]
    if opts.sizes:
        sizes = [int(n) for n in opts.sizes.split(",")]
    systems = tuple(s for s in SYSTEMS if s in opts.systems.split(","))
    load_sizes = [500, 1_000] if opts.quick else [2_500, 5_000, 10_000, 20_000]
    if opts.load_sizes:
        load_sizes = [int(n) for n in opts.load_sizes.split(",")]
    if opts.gc_threshold is not None:
        os.environ["ADAPT_BENCH_GC"] = str(opts.gc_threshold)
    gc_note = ("default" if opts.gc_threshold is None
               else "off" if opts.gc_threshold == 0 else str(opts.gc_threshold))
    sys.path.insert(0, str(ROOT))
    from adapt.engine import engine_build

    print(f"bench/engine.py  {time.strftime('%Y-%m-%d %H:%M')}  python {sys.version.split()[0]}"
          f"  cpus {os.cpu_count()}  adapt gc_threshold: {gc_note}  adapt engine: {engine_build()}")
    with tempfile.TemporaryDirectory() as tmp:
        if opts.only in (None, "counter"):
            bench_counter(Path(tmp), limit, runs, opts.timeout, systems)
        if opts.only in (None, "join"):
            bench_join(Path(tmp), sizes, runs, opts.timeout,
                       tuple(s for s in systems if s != "adapt-py"))
        if opts.only in (None, "load"):
            bench_load(Path(tmp), load_sizes, runs, opts.timeout, systems)
    return 0


if __name__ == "__main__":
    sys.exit(main())
