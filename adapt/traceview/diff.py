"""The first decision cycle where two traces part, and how.

Both traces are read in step, one decision cycle at a time.  A cycle is
compared aspect by aspect, in the order a reader would look: the decision
(selected operator or impasse), then for each phase the firings (rule and
bindings), the retractions, the WMEs added and removed (by content, not
timetag -- timetags shift as soon as one run makes one more WME), and the
``(write)`` output.  The first difference is reported with both sides.

Two traces of different engines (the header's ``engine``: adapt's own, or
``soar``, the Soar kernel) are compared on what both report (:class:`Comparison`):
what one trace's header names ``absent`` (the kernel reports no bindings,
and no retraction of an instantiation whose preferences were all
o-supported) is left out on both sides.

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

__all__ = ["Divergence", "Comparison", "cycle_aspects", "first_difference", "diff_traces",
           "format_divergence"]

Aspects = list[tuple[str, list[str]]]


@dataclass(frozen=True)
class Comparison:
    """What is compared of two traces (see the module docstring).

    Attributes
    ----------
    bindings : bool
        Firings are compared with their bindings (both traces have them).
    retractions : bool
        Retractions are compared (both traces report all of them).
    notes : tuple of str
        What is left out, and why (printed with the result).

    Examples
    --------
    >>> Comparison.of({}, {"engine": "soar", "absent": ["firings.bindings"]}).bindings
    False
    """

    bindings: bool = True
    retractions: bool = True
    notes: tuple[str, ...] = ()

    @staticmethod
    def of(a: dict[str, Any], b: dict[str, Any]) -> Comparison:
        """The comparison of two traces, from their headers."""
        absent = set(_strings(a.get("absent"))) | set(_strings(b.get("absent")))
        bindings = "firings.bindings" not in absent
        retractions = "retractions.o-support" not in absent
        notes = []
        if not bindings:
            notes.append("firings compared by rule only: a trace has no bindings "
                         "(the Soar kernel does not report them)")
        if not retractions:
            notes.append("retractions not compared: the Soar kernel reports only those of "
                         "instantiations with i-supported preferences")
        return Comparison(bindings, retractions, tuple(notes))


def _strings(value: Any) -> list[str]:
    return [v for v in value if isinstance(v, str)] if isinstance(value, list) else []


def _engine(header: dict[str, Any]) -> str:
    engine = header.get("engine")
    return engine if isinstance(engine, str) else "adapt"


def _firing(f: dict[str, Any], bindings: bool = True) -> str:
    if not bindings:
        return str(f.get("rule"))
    text = ", ".join(f"{k}={text_of(v)}" for k, v in (f.get("bindings") or {}).items())
    return f"{f.get('rule')} [{text}]" if text else str(f.get("rule"))


def cycle_aspects(records: list[dict[str, Any]], wm: LiveMemory | None,
                  compare: Comparison | None = None) -> Aspects:
    """What is compared of one cycle, as ``(aspect, sorted texts)`` pairs, in reading order."""
    out: Aspects = []
    how = compare if compare is not None else Comparison()
    for record in records:
        kind = record["kind"]
        if kind == "decision":
            line = decision_line(record)
            out.append(("decision", [line.split(": ", 1)[1].strip() if line else "(no change)"]))
        elif kind == "phase":
            phase = str(record.get("phase"))
            out.append((f"{phase} phase, firings",
                        sorted(_firing(f, how.bindings) for f in record.get("firings") or ())))
            if how.retractions:
                out.append((f"{phase} phase, retractions",
                            sorted(_firing(f, how.bindings) for f in record.get("retractions") or ())))
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
    notes: tuple[str, ...] = ()


def _cycles(trace: Trace) -> Iterator[tuple[int, list[dict[str, Any]]]]:
    yield from trace.cycles()


def diff_traces(a: Trace, b: Trace) -> Divergence:
    """Compare two traces cycle by cycle, streaming both."""
    ha, hb = a.header.raw, b.header.raw
    headers = tuple(
        f"{key}: {ha.get(key)!r} vs {hb.get(key)!r}"
        for key in ("files", "seed", "level")
        if ha.get(key) != hb.get(key)
    )
    engines = (_engine(ha), _engine(hb))
    if engines[0] != engines[1]:
        headers += (f"engine: {engines[0]!r} vs {engines[1]!r}",)
    compare = Comparison.of(ha, hb)
    track = a.header.level >= 4 and b.header.level >= 4
    wm_a, wm_b = (LiveMemory(a.initial_wmes()), LiveMemory(b.initial_wmes())) if track else (None, None)  # type: ignore[arg-type]
    compared = 0
    notes = compare.notes
    for (ca, ra), (cb, rb) in zip_longest(_cycles(a), _cycles(b), fillvalue=(None, None)):
        if ca is None or cb is None:
            ended, later = ("A", cb) if ca is None else ("B", ca)
            return Divergence(compared, later, "length",
                              (f"trace {ended} ends after decision cycle {compared}",), (), headers,
                              notes)
        if ca != cb:
            return Divergence(compared, min(ca, cb), "numbering",
                              (f"A has decision cycle {ca}",), (f"B has decision cycle {cb}",),
                              headers, notes)
        compared += 1
        diff = first_difference(cycle_aspects(ra or [], wm_a, compare),
                                cycle_aspects(rb or [], wm_b, compare))
        if diff is not None:
            aspect, ta, tb = diff
            return Divergence(compared, ca, aspect, tuple(ta), tuple(tb), headers, notes)
    return Divergence(compared, None, headers=headers, notes=notes)


def format_divergence(result: Divergence, name_a: str = "A", name_b: str = "B") -> str:
    """The text of ``adapt trace diff``."""
    lines = [f"headers differ: {h}" for h in result.headers]
    lines.extend(f"note: {n}" for n in result.notes)
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
