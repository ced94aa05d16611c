"""Soar-style text of a trace, filtered by decisions, rule, identifier and level.

The levels are Soar's watch levels:

1. decisions -- ``   12: O: O7 (count)`` or ``    3: ==>S: S2 (operator tie)``,
   indented three spaces per goal level;
2. + phases (``--- apply phase ---``), ``(write)`` output and kernel messages;
3. + ``Firing apply*count`` and ``Retracting propose*count``;
4. + working-memory changes ``=>WM: (231: S1 ^count 3)`` / ``<=WM: ...``;
5. + the candidates' preferences at each decision and the firings' bindings.

Examples
--------
>>> decision = {"kind": "decision", "d": 12, "level": 0, "impasse": None,
...             "selected": {"id": {"id": "O7"}, "name": "count"}}
>>> decision_line(decision)
'   12: O: O7 (count)'
>>> decision_line({"kind": "decision", "d": 3, "level": 0, "selected": None,
...                "impasse": {"type": "tie", "attribute": "operator",
...                            "items": [], "state": {"id": "S2"}}})
'    3: ==>S: S2 (operator tie)'
>>> firing_line({"rule": "apply*count", "bindings": {"<s>": {"id": "S1"}, "<c>": 2}}, 5)
'Firing apply*count [<s>=S1, <c>=2]'
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from adapt.traceview.memory import LiveMemory
from adapt.traceview.reader import Trace
from adapt.traceview.symbols import id_name, text_of, wme_text

__all__ = ["ShowFilter", "show_lines", "nothing_shown", "decision_line", "firing_line", "impasse_text",
           "PHASE_TITLES"]

#: How Soar titles each phase at watch level 2.
PHASE_TITLES = {
    "input": "--- input phase ---",
    "proposal": "--- propose phase ---",
    "decision": "--- decision phase ---",
    "apply": "--- apply phase ---",
    "output": "--- output phase ---",
}


@dataclass(frozen=True)
class ShowFilter:
    """What :func:`show_lines` prints.

    Attributes
    ----------
    first, last : int or None
        The decision cycles to show (inclusive); ``None`` for no bound.
    rule : str or None
        Only cycles where this rule fired or retracted, and only its firings.
    ident : str or None
        Only what mentions this identifier (WME changes, bindings, decisions).
    level : int
        The watch level 1..5 (capped at the trace's own level).
    """

    first: int | None = None
    last: int | None = None
    rule: str | None = None
    ident: str | None = None
    level: int = 1


def impasse_text(impasse: dict[str, Any]) -> str:
    """``operator tie``, ``state no-change``, ... as Soar names an impasse."""
    kind = str(impasse.get("type", "impasse"))
    if kind.endswith("no-change"):
        return kind
    return f"{impasse.get('attribute', 'operator')} {kind}"


def decision_line(record: dict[str, Any]) -> str | None:
    """The Soar decision line of a ``decision`` record (``None`` if nothing changed)."""
    prefix = f"{record['d']:>5}: " + "   " * int(record.get("level") or 0)
    impasse = record.get("impasse")
    if impasse:
        state = text_of(impasse.get("state")) if impasse.get("state") else "?"
        return f"{prefix}==>S: {state} ({impasse_text(impasse)})"
    selected = record.get("selected")
    if selected:
        return f"{prefix}O: {text_of(selected.get('id'))} ({text_of(selected.get('name'))})"
    return None


def _bindings_text(bindings: dict[str, Any]) -> str:
    return ", ".join(f"{var}={text_of(val)}" for var, val in bindings.items()
                     if not var.startswith("<#"))  # hidden dot-path variables


def firing_line(firing: dict[str, Any], level: int, verb: str = "Firing") -> str:
    """``Firing apply*count`` (with the bindings at level 5)."""
    line = f"{verb} {firing.get('rule')}"
    if level >= 5 and firing.get("bindings"):
        line += f" [{_bindings_text(firing['bindings'])}]"
    return line


def _candidates_line(record: dict[str, Any]) -> str | None:
    parts = []
    for cand in record.get("candidates") or ():
        prefs = " ".join(
            kind if ref is None else f"{kind} {text_of(ref)}"
            for kind, ref in cand.get("preferences", ())
        )
        parts.append(f"{text_of(cand.get('id'))} ({text_of(cand.get('name'))}) {prefs}".rstrip())
    if not parts:
        return None
    return " " * 7 + "   " * int(record.get("level") or 0) + "preferences: " + "; ".join(parts)


def _mentions(value: Any, ident: str) -> bool:
    if isinstance(value, dict):
        return id_name(value) == ident or any(_mentions(v, ident) for v in value.values())
    if isinstance(value, list):
        return any(_mentions(v, ident) for v in value)
    return False


class _CycleText:
    """Lines of one cycle, and whether the filter found what it looks for there."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.relevant = False


def _phase_text(record: dict[str, Any], wm: LiveMemory | None, flt: ShowFilter, level: int,
                out: _CycleText) -> None:
    if level >= 2:
        out.lines.append(PHASE_TITLES.get(record.get("phase", ""), f"--- {record.get('phase')} phase ---"))
    if level >= 3:
        for verb, key in (("Retracting", "retractions"), ("Firing", "firings")):
            for firing in record.get(key) or ():
                if flt.rule is not None and firing.get("rule") != flt.rule:
                    continue
                if flt.ident is not None and not _mentions(firing.get("bindings"), flt.ident):
                    continue
                out.lines.append(firing_line(firing, level, verb))
                out.relevant = True
    removed = wm.removed(record) if wm is not None else []
    if wm is not None:
        wm.apply(record)
    if level >= 4:
        for sign, wmes in (("<=WM: ", removed), ("=>WM: ", record.get("adds") or ())):
            for wme in wmes:
                if flt.ident is not None:
                    if text_of(wme[1]) != flt.ident and id_name(wme[3]) != flt.ident:
                        continue
                    out.relevant = True
                out.lines.append(sign + wme_text(*wme))
    if level >= 2:
        for message in record.get("messages") or ():
            out.lines.append(str(message))
    if record.get("writes"):
        out.lines.append(str(record["writes"]).rstrip("\n"))


def _cycle_text(records: list[dict[str, Any]], wm: LiveMemory | None, flt: ShowFilter,
                level: int, show: bool) -> _CycleText:
    out = _CycleText()
    held: dict[str, Any] | None = None
    for record in records:
        kind = record["kind"]
        if kind == "phase":
            if record.get("phase") == "decision" and any(r["kind"] == "decision" for r in records):
                held = record
                continue
            if show:
                _phase_text(record, wm, flt, level, out)
            elif wm is not None:
                wm.apply(record)
        elif kind == "decision":
            if show:
                line = decision_line(record)
                if line is not None:
                    out.lines.append(line)
                if flt.ident is not None and _mentions(
                    [record.get("selected"), record.get("impasse"), record.get("candidates")],
                    flt.ident,
                ):
                    out.relevant = True
                if level >= 5:
                    cands = _candidates_line(record)
                    if cands is not None:
                        out.lines.append(cands)
            if held is not None:
                if show:
                    _phase_text(held, wm, flt, level, out)
                elif wm is not None:
                    wm.apply(held)
                held = None
        elif kind == "schema" and show and level >= 2:
            out.lines.append(f"Schema {record.get('event', '')}: {record.get('schema', '')}")
    if held is not None:
        if show:
            _phase_text(held, wm, flt, level, out)
        elif wm is not None:
            wm.apply(held)
    if flt.rule is None and flt.ident is None:
        out.relevant = True
    return out


def show_lines(trace: Trace, flt: ShowFilter) -> Iterator[str]:
    """The Soar-style lines of the decision cycles ``flt`` selects, streaming."""
    level = min(flt.level, trace.header.level)
    wm = LiveMemory() if level >= 4 else None
    if wm is not None:
        wm.apply({"adds": trace.initial_wmes()})
    start = None if wm is not None else flt.first
    for cycle, records in trace.cycles(first=start, last=flt.last):
        show = flt.first is None or cycle >= flt.first
        text = _cycle_text(records, wm, flt, level, show)
        if show and text.relevant:
            yield from text.lines


def _selection(flt: ShowFilter) -> str:
    parts = []
    if flt.first is not None or flt.last is not None:
        if flt.first == flt.last:
            parts.append(f"--decisions {flt.first}")
        else:
            parts.append(f"--decisions {'' if flt.first is None else flt.first}.."
                         f"{'' if flt.last is None else flt.last}")
    if flt.rule is not None:
        parts.append(f"--rule {flt.rule}")
    if flt.ident is not None:
        parts.append(f"--id {flt.ident}")
    return " ".join(parts)


def nothing_shown(trace: Trace, flt: ShowFilter) -> str | None:
    """Why :func:`show_lines` gave no line, when the filter explains it; ``None`` when the
    selected cycles are merely quiet at that level.

    Reads the trace once more (only called when nothing was shown).
    """
    first_cycle: int | None = None
    last_cycle = 0
    rules: set[str] = set()
    for cycle, records in trace.cycles():
        first_cycle = cycle if first_cycle is None else min(first_cycle, cycle)
        last_cycle = max(last_cycle, cycle)
        if flt.rule is not None and len(rules) < 10_000:
            for record in records:
                for key in ("firings", "retractions"):
                    rules.update(f["rule"] for f in record.get(key) or ())
    what = _selection(flt)
    if first_cycle is None:
        return f"{trace.path} holds no decision cycles"
    if (flt.first is not None and flt.first > last_cycle) or (
            flt.last is not None and flt.last < first_cycle):
        return (f"{trace.path} has decision cycles {first_cycle}..{last_cycle}; "
                f"{what} selects none of them")
    if flt.rule is not None:
        if trace.header.level < 3:
            return (f"{trace.path} was written at level {trace.header.level}, without firings; "
                    "--rule needs a trace of level 3 or more (run with --trace-level 3)")
        if flt.rule not in rules:
            stem = flt.rule.split("*")[0]
            near = sorted(r for r in rules if stem and stem in r)[:5]
            hint = f" (rules that did: {', '.join(near)})" if near else ""
            return f"rule {flt.rule} never fired or retracted in {trace.path}{hint}"
    if flt.rule is not None or flt.ident is not None:
        level = min(flt.level, trace.header.level)
        return f"nothing in {trace.path} matches {what} at level {level}"
    return None
