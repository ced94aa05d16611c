"""Profile adapt's decision cycle on the counter agent of ``bench/engine.py``.

``python bench/engine_profile.py [--limit N] [--matcher rete|naive] [--profile] [--top K]``

Without ``--profile`` it prints decisions/s (median of ``--repeat`` runs, each a
fresh agent, the run alone timed, no trace).  With ``--profile`` it runs once
under cProfile and prints the top functions by own time.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import pstats
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from engine import counter_file  # noqa: E402

from adapt.engine import Agent  # noqa: E402


def make_agent(limit: int, matcher: str) -> Agent:
    agent = Agent(seed=1, matcher=matcher)
    agent.load_text(counter_file(limit))
    return agent


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--limit", type=int, default=20000)
    ap.add_argument("--matcher", default="rete")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--sort", default="tottime")
    args = ap.parse_args(argv)
    if args.profile:
        agent = make_agent(args.limit, args.matcher)
        prof = cProfile.Profile()
        prof.enable()
        report = agent.run(max_decisions=args.limit + 10)
        prof.disable()
        out = io.StringIO()
        pstats.Stats(prof, stream=out).sort_stats(args.sort).print_stats(args.top)
        print(out.getvalue())
        print(f"decisions={report.decisions} firings={report.production_firings}")
        return 0
    rates, cpu_rates = [], []
    for _ in range(args.repeat):
        agent = make_agent(args.limit, args.matcher)
        start, cpu = time.perf_counter(), time.process_time()
        report = agent.run(max_decisions=args.limit + 10)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        rates.append(report.decisions / seconds)
        cpu_rates.append(report.decisions / cpu)
    print(f"{args.matcher}: decisions={report.decisions} firings={report.production_firings} "
          f"elab={report.elaboration_cycles} halted={report.halted} "
          f"decisions/s median={statistics.median(rates):,.0f} "
          f"(per CPU second {statistics.median(cpu_rates):,.0f}) "
          f"all={[round(r) for r in rates]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
