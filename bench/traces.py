"""What checking every trace record costs the trace reader.

Writes a level-5 trace of a counting agent (``--decisions``, default 30,000)
with the engine, then reads it back, in the same process, three ways:

* ``json``: the lines decoded with ``json.loads`` and nothing else (the floor);
* ``unchecked``: :meth:`adapt.traceview.reader.Trace.records` with the record
  checks switched off (``records.check_record`` replaced by a no-op);
* ``checked``: ``Trace.records`` as shipped (strict JSON, the schema's types).

Prints the median of ``--repeat`` runs of each and the ratios.  Usage::

    python bench/traces.py [--decisions N] [--repeat K]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import adapt.traceview.reader as reader  # noqa: E402
from adapt.engine import Agent  # noqa: E402

RULES = """\
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose*tick (state <s> ^count <c>) --> (<s> ^operator <o> + =) (<o> ^name tick)}
sp {propose*tock (state <s> ^count <c>) --> (<s> ^operator <o> + =) (<o> ^name tock)}
sp {apply*tick (state <s> ^operator.name << tick tock >> ^count <c>)
--> (<s> ^count <c> - (+ <c> 1)) (write |n | <c> (crlf))}
"""


def _time(read) -> float:  # type: ignore[no-untyped-def]
    start = time.perf_counter()
    read()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--decisions", type=int, default=30_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp())
    path = folder / "t.jsonl"
    agent = Agent(seed=1, trace=str(path), trace_level=5)
    agent.load_text(RULES)
    agent.run(args.decisions)
    agent.close()
    size = path.stat().st_size

    def plain() -> None:
        with open(path, "rb") as f:
            for line in f:
                json.loads(line)

    def shipped() -> None:
        for _ in reader.Trace(path).records():
            pass

    checked, unchecked, floor = [], [], []
    original = reader.check_record
    for _ in range(args.repeat):
        floor.append(_time(plain))
        checked.append(_time(shipped))
        reader.check_record = lambda record, **_: None  # type: ignore[assignment]
        try:
            unchecked.append(_time(shipped))
        finally:
            reader.check_record = original
    m_json, m_un, m_ch = (statistics.median(v) for v in (floor, unchecked, checked))
    records = sum(1 for _ in open(path, "rb"))
    print(f"trace: {args.decisions:,} decisions, level 5, {records:,} records, {size / 1e6:.1f} MB")
    print(f"medians of {args.repeat}: json {m_json:.3f} s, unchecked {m_un:.3f} s, checked {m_ch:.3f} s")
    print(f"checked / unchecked = {m_ch / m_un:.2f}; checked / json = {m_ch / m_json:.2f}; "
          f"checked reads {size / m_ch / 1e6:.0f} MB/s, {records / m_ch / 1e3:.0f}k records/s")


if __name__ == "__main__":
    main()
