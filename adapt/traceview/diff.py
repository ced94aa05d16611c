"""The first decision cycle where two traces part, and how.

Both traces are read in step, one decision cycle at a time.  A cycle is
compared aspect by aspect, in the order a reader would look: the decision
(selected operator or impasse), then for each phase the firings (rule and
bindings), the retractions, the WMEs added and removed (by content, not
timetag -- timetags shift as soon as one run makes one more WME), and the
``(write)`` output.  The first difference is reported with both sides.

Examples
--------
>>> a = [{"kind": "decision", "d": 3, "level": 0, "impasse": None,
...       "selected": {"id": {"id": "O3"}, "name": "count"}}]
>>> b = [{"kind": "decision", "d": 3, "level": 0, "impasse": None,
...       "selected": {"id": {"id": "O4"}, "name": "skip"}}]
>>> first_difference(cycle_aspects(a, None), cycle_aspects(b, None))
('decision', ['O: O3 (count)'], ['O: O4 (skip)'])
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from itertools import zip_longest
from typing import Any

from adapt.traceview.memory import LiveMemory
from adapt.traceview.reader import Trace
from adapt.traceview.show import decision_line
from adapt.traceview.symbols import text_of, wme_text

__all__ = ["Divergence", "cycle_aspects", "first_difference", "diff_traces", "format_divergence"]

Aspects = list[tuple[str, list[str]]]


def _firing(f: dict[str, Any]) -> str:
    bindings = ", ".join(f"{k}={text_of(v)}" for k, v in (f.get("bindings") or {}).items())
    return f"{f.get('rule')} [{bindings}]" if bindings else str(f.get("rule"))


def cycle_aspects(records: list[dict[str, Any]], wm: LiveMemory | None) -> Aspects:
    """What is compared of one cycle, as ``(aspect, sorted texts)`` pairs, in reading order."""
    out: Aspects = []
    for record in records:
        kind = record["kind"]
        if kind == "decision":
            line = decision_line(record)
            out.append(("decision", [line.split(": ", 1)[1].strip() if line else "(no change)"]))
        elif kind == "phase":
            phase = str(record.get("phase"))
            out.append((f"{phase} phase, firings", sorted(_firing(f) for f in record.get("firings") or ())))
            out.append((f"{phase} phase, retractions",
                        sorted(_firing(f) for f in record.get("retractions") or ())))
            if wm is not None:
                removed = sorted(wme_text(None, *w[1:]) for w in wm.removed(record))
                wm.apply(record)
                out.append((f"{phase} phase, WMEs removed", removed))
                out.append((f"{phase} phase, WMEs added",
                            sorted(wme_text(None, *a[1:]) for a in record.get("adds") or ())))
            out.append((f"{phase} phase, output", [str(record["writes"])] if record.get("writes") else []))
        elif kind == "schema":
            out.append(("schema event", [f"{record.get('event')} {record.get('schema')}"]))
    return out


def first_difference(a: Aspects, b: Aspects) -> tuple[str, list[str], list[str]] | None:
    """The first aspect in which two cycles differ: ``(aspect, a's texts, b's texts)``."""
    for (name_a, texts_a), (name_b, texts_b) in zip_longest(a, b, fillvalue=("", [])):
        if name_a != name_b:
            return ("phases", [name_a or "(nothing)"], [name_b or "(nothing)"])
        if texts_a != texts_b:
            return (name_a, texts_a, texts_b)
    return None


@dataclass(frozen=True)
class Divergence:
    """Where two traces part; ``cycle`` is ``None`` when they agree throughout."""

    cycles_compared: int
    cycle: int | None = None
    aspect: str = ""
    a: tuple[str, ...] = ()
    b: tuple[str, ...] = ()
    headers: tuple[str, ...] = ()


def _cycles(trace: Trace) -> Iterator[tuple[int, list[dict[str, Any]]]]:
    yield from trace.cycles()


def diff_traces(a: Trace, b: Trace) -> Divergence:
    """Compare two traces cycle by cycle, streaming both."""
    headers = tuple(
        f"{key}: {a.header.raw.get(key)!r} vs {b.header.raw.get(key)!r}"
        for key in ("files", "seed", "level")
        if a.header.raw.get(key) != b.header.raw.get(key)
    )
    track = a.header.level >= 4 and b.header.level >= 4
    wm_a, wm_b = (LiveMemory(a.initial_wmes()), LiveMemory(b.initial_wmes())) if track else (None, None)  # type: ignore[arg-type]
    compared = 0
    for (ca, ra), (cb, rb) in zip_longest(_cycles(a), _cycles(b), fillvalue=(None, None)):
        if ca is None or cb is None:
            ended, other = ("A", cb) if ca is None else ("B", ca)
            return Divergence(compared, other, "length",
                              (f"trace {ended} ends after decision cycle {compared}",), (), headers)
        if ca != cb:
            return Divergence(compared, min(ca, cb), "numbering",
                              (f"A has decision cycle {ca}",), (f"B has decision cycle {cb}",),
                              headers)
        compared += 1
        diff = first_difference(cycle_aspects(ra or [], wm_a), cycle_aspects(rb or [], wm_b))
        if diff is not None:
            aspect, ta, tb = diff
            return Divergence(compared, ca, aspect, tuple(ta), tuple(tb), headers)
    return Divergence(compared, None, headers=headers)


def format_divergence(result: Divergence, name_a: str = "A", name_b: str = "B") -> str:
    """The text of ``adapt trace diff``."""
    lines = [f"headers differ: {h}" for h in result.headers]
    if result.cycle is None:
        lines.append(f"the traces agree on all {result.cycles_compared} decision cycles")
        return "\n".join(lines)
    lines.append(f"the traces diverge at decision cycle {result.cycle}: {result.aspect}")
    if result.aspect == "length":
        lines.append("  " + result.a[0])
        return "\n".join(lines)
    set_a, set_b = set(result.a), set(result.b)
    only_a = [t for t in result.a if t not in set_b] or ["(nothing)"]
    only_b = [t for t in result.b if t not in set_a] or ["(nothing)"]
    lines.append(f"  {name_a}:")
    lines.extend(f"    {t.rstrip()}" for t in only_a)
    lines.append(f"  {name_b}:")
    lines.extend(f"    {t.rstrip()}" for t in only_b)
    return "\n".join(lines)
