"""Working memory rebuilt from a trace, and printed as a tree from a root.

Replaying the ``adds`` and ``removes`` of every ``phase`` record up to the
end of decision cycle ``D`` gives working memory as it was when cycle ``D``
ended (after its output phase) -- what Soar's ``print`` shows after
``run D``.  Only the live WMEs are kept, so memory is bounded by the size of
working memory, never by the length of the run.

Examples
--------
>>> wm = LiveMemory()
>>> wm.apply({"adds": [[1, {"id": "S1"}, "type", "state", False],
...                    [2, {"id": "S1"}, "io", {"id": "I1"}, False],
...                    [3, {"id": "I1"}, "output-link", {"id": "I3"}, False],
...                    [4, {"id": "S1"}, "count", 2, False]]})
>>> wm.apply({"removes": [4], "adds": [[5, {"id": "S1"}, "count", 3, False]]})
>>> len(wm), wm.get(5)
(4, (5, {'id': 'S1'}, 'count', 3, False))
>>> print(format_tree(wm, "S1", depth=2))
(S1 ^count 3 ^io I1 ^type state)
  (I1 ^output-link I3)
>>> print(format_tree(wm, "S1", depth=1, internal=True))
(5: S1 ^count 3)
(2: S1 ^io I1)
(1: S1 ^type state)
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from adapt.engine.symbols import symbol_sort_key
from adapt.errors import TraceError
from adapt.traceview.reader import Trace
from adapt.traceview.symbols import IdentifierTable, id_name, text_of, wme_text

__all__ = ["TraceWME", "LiveMemory", "memory_at", "format_tree", "sort_key"]

#: A WME as the trace writes it: ``(timetag, id, attr, value, acceptable)``.
TraceWME = tuple[int, Any, Any, Any, bool]

_SORT_TABLE = IdentifierTable()


def sort_key(wme: TraceWME) -> tuple[Any, ...]:
    """Soar's print order: by attribute, then value, then timetag."""
    return (
        symbol_sort_key(_SORT_TABLE.decode(wme[2])),
        symbol_sort_key(_SORT_TABLE.decode(wme[3])),
        wme[4],
        wme[0],
    )


class LiveMemory:
    """The WMEs alive at one point of a trace, keyed by timetag."""

    __slots__ = ("_wmes", "cycle")

    def __init__(self, wmes: Iterable[TraceWME] = ()) -> None:
        #: The decision cycle this memory is the end of (set by :func:`memory_at`).
        self.cycle: int | None = None
        self._wmes: dict[int, TraceWME] = {w[0]: (w[0], w[1], w[2], w[3], bool(w[4])) for w in wmes}

    def apply(self, phase: dict[str, Any]) -> None:
        """Replay one ``phase`` record: its adds, then its removes.

        A phase runs several elaboration waves, so a WME can be added and
        removed within the same phase record (an i-supported WME whose
        instantiation retracts a wave later).  Timetags are never reused, so
        adding first and removing second always leaves what the engine held
        at the end of the phase.
        """
        wmes = self._wmes
        for add in phase.get("adds", ()):
            tt, ident, attr, value, acceptable = add
            wmes[tt] = (tt, ident, attr, value, bool(acceptable))
        for timetag in phase.get("removes", ()):
            wmes.pop(timetag, None)

    def removed(self, phase: dict[str, Any]) -> list[TraceWME]:
        """The WMEs a phase record removes (call before :meth:`apply`).

        Those live before the phase, and those the same phase adds and removes.
        """
        added = {a[0]: (a[0], a[1], a[2], a[3], bool(a[4])) for a in phase.get("adds", ())}
        wmes = self._wmes
        return [wmes[t] if t in wmes else added[t] for t in phase.get("removes", ())
                if t in wmes or t in added]

    def get(self, timetag: int) -> TraceWME | None:
        """The live WME with that timetag, or ``None``."""
        return self._wmes.get(timetag)

    def __len__(self) -> int:
        return len(self._wmes)

    def __iter__(self) -> Iterator[TraceWME]:
        return iter(self._wmes.values())

    def by_id(self) -> dict[str, list[TraceWME]]:
        """The live WMEs grouped by identifier name, each group in print order."""
        groups: dict[str, list[TraceWME]] = {}
        for wme in self._wmes.values():
            name = id_name(wme[1])
            if name is not None:
                groups.setdefault(name, []).append(wme)
        for group in groups.values():
            group.sort(key=sort_key)
        return groups

    def find(self, ident: str, attr: str | None = None, value: str | None = None) -> list[TraceWME]:
        """Live WMEs whose id (and attribute, value, as printed) are those given."""
        return sorted(
            (
                w
                for w in self._wmes.values()
                if text_of(w[1]) == ident
                and (attr is None or text_of(w[2]) == attr)
                and (value is None or text_of(w[3]) == value)
            ),
            key=sort_key,
        )


def memory_at(trace: Trace, decision: int | None = None) -> LiveMemory:
    """Working memory at the end of decision cycle ``decision`` (default: the trace's last).

    The cycle replayed last is :attr:`LiveMemory.cycle`.

    Raises
    ------
    adapt.errors.TraceError
        If the trace was written below level 4 (it has no adds/removes), or
        ``decision`` is negative or past the trace's last decision.
    """
    trace.require_level(4, "rebuilding working memory")
    if decision is not None and decision < 0:
        raise TraceError(f"decision {decision}: decisions are numbered from 0")
    wm = LiveMemory()
    wm.apply({"adds": trace.initial_wmes()})
    last = 0
    for cycle, records in trace.cycles(last=decision):
        last = max(last, cycle)
        for record in records:
            if record["kind"] == "phase":
                wm.apply(record)
    if decision is not None and decision > last:
        raise TraceError(f"decision {decision}: {trace.path} ends at decision {last}; "
                         f"expected a decision from 0 to {last}")
    wm.cycle = last if decision is None else decision
    return wm


def format_tree(
    wm: LiveMemory, root: str, depth: int = 1, *, internal: bool = False
) -> str:
    """Print working memory from ``root`` down ``depth`` levels, like Soar's ``print --depth``.

    Each identifier is printed once, as ``(S1 ^attr value ...)``, with the
    identifiers it links to indented below it.  With ``internal`` every WME
    is printed on its own line with its timetag (Soar's ``print --internal``).

    Raises
    ------
    adapt.errors.TraceError
        If ``root`` has no WMEs.
    """
    groups = wm.by_id()
    if root not in groups:
        known = ", ".join(sorted(n for n in groups if n[:1] == root[:1])[:8])
        hint = f" (identifiers like it: {known})" if known else ""
        raise TraceError(f"{root} has no working-memory elements at that decision{hint}")
    lines: list[str] = []
    seen: set[str] = set()
    stack: list[tuple[str, int]] = [(root, 1)]  # iterative: a long chain of identifiers is fine
    while stack:
        name, level = stack.pop()
        if name in seen:
            continue
        seen.add(name)
        indent = "  " * (level - 1)
        wmes = groups.get(name, [])
        if internal:
            lines.extend(indent + wme_text(*w) for w in wmes)
        else:
            parts = " ".join(
                f"^{text_of(w[2])} {text_of(w[3])}{' +' if w[4] else ''}" for w in wmes
            )
            lines.append(f"{indent}({name} {parts})" if parts else f"{indent}({name})")
        if level >= depth:
            continue
        children = [child for w in wmes
                    if (child := id_name(w[3])) is not None and child not in seen and child in groups]
        stack.extend((child, level + 1) for child in reversed(children))
    return "\n".join(lines)
