"""Profile adapt's decision cycle on the counter agent of ``bench/engine.py``.

``python bench/engine_profile.py [--limit N] [--matcher rete|naive] [--profile|--sample] [--top K]``

Without options it prints decisions/s (median of ``--repeat`` runs, each a
fresh agent, the run alone timed, no trace; also per CPU second, steadier on a
busy machine).  With ``--profile`` it runs once under cProfile and prints the
top functions by own time.  With ``--sample`` a thread samples the running
line every millisecond (little overhead, so the shares are closer to the
truth than cProfile's) and prints the hottest lines and functions.
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import io
import pstats
import statistics
import sys
import threading
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


def sample(agent: Agent, limit: int, top: int) -> None:
    """Run ``agent`` while a thread samples the main thread's current line."""
    main_id = threading.get_ident()
    lines: collections.Counter[tuple[str, int, str]] = collections.Counter()
    funcs: collections.Counter[tuple[str, str]] = collections.Counter()
    files: collections.Counter[str] = collections.Counter()
    done = threading.Event()

    def sampler() -> None:
        while not done.is_set():
            frame = sys._current_frames().get(main_id)
            if frame is not None:
                code = frame.f_code
                name = code.co_filename.replace(str(ROOT) + "/", "")
                lines[(name, frame.f_lineno, code.co_name)] += 1
                funcs[(name, code.co_name)] += 1
                files["rete" if "/rete/" in name else name] += 1
            time.sleep(0.0005)

    old_interval = sys.getswitchinterval()
    sys.setswitchinterval(0.0002)
    thread = threading.Thread(target=sampler, daemon=True)
    thread.start()
    agent.run(max_decisions=limit + 10)
    done.set()
    thread.join()
    sys.setswitchinterval(old_interval)
    total = sum(lines.values()) or 1
    for title, counter in (("files", files), ("functions", funcs), ("lines", lines)):
        print(f"-- {title} (share of {total} samples)")
        for key, n in counter.most_common(top):
            print(f"{n / total:6.1%}  {key}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--limit", type=int, default=20000)
    ap.add_argument("--matcher", default="rete")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--sort", default="tottime")
    ap.add_argument("--sample", action="store_true")
    args = ap.parse_args(argv)
    if args.sample:
        sample(make_agent(args.limit, args.matcher), args.limit, args.top)
        return 0
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
