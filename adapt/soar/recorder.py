"""What the Soar kernel reports, turned into adapt's report and trace records.

The kernel tells what it does in its XML trace (:mod:`adapt.soar.xmltrace`):
phase markers, operator selections, new substates, rule firings and
retractions with the timetags of the WMEs they matched, the preferences
each firing made, WMEs added and removed, ``(write)`` text and messages.
:class:`KernelRecorder` reads those tags in order and keeps what the run
report needs (the operator selections, the impasses, the output, the
messages) and, when a :class:`~adapt.engine.trace.TraceWriter` is attached,
writes the records of ``docs/trace-format.md`` from them:

* a ``phase`` record per phase (the kernel's ``propose`` phase is the
  ``proposal`` phase), with its writes and messages; at trace level 3 and
  above its firings and retractions -- rule, goal level and matched
  timetags -- and at level 4 and above the WMEs added and removed;
* a ``decision`` record per decision phase: the selected operator (its
  ``^name`` as the kernel reports it), or the impasse with its new state
  and, from the ``^item`` WMEs the kernel added, its items.

Some fields are computed, by Soar's own definitions, from what the kernel
reports: a firing's goal ``level`` is the level of the deepest state whose
WMEs it matched (Soar's match goal), its ``support`` is ``o`` when the
preferences it made are o-supported and ``i`` otherwise.  What the kernel
does not report is left out and named in the trace header's ``absent``
(:data:`ABSENT`): the bindings of firings and retractions, the retraction of
an instantiation whose preferences were all o-supported (the kernel traces
only retractions that remove i-supported preferences), the candidates of a
decision and their preferences, the goals a decision removed, and the
support of a firing that made no preference.  Nothing is invented.

Examples
--------
>>> import io, json
>>> from adapt.engine.trace import TraceWriter
>>> rec = KernelRecorder(Symbols())
>>> buf = io.StringIO()
>>> rec.attach(TraceWriter(buf, level=3, header=trace_header("Soar 9.6.5")))
>>> rec.feed('<trace><phase name="decision"></phase><operator current_operator_id="O1" '
...          'decision_cycle_count="1" name="go" stack_level="0"></operator>'
...          '<phase name="decision" status="end"></phase><rhs_write string="hi"></rhs_write>'
...          '</trace>')
>>> [json.loads(line)["kind"] for line in buf.getvalue().splitlines()]
['header', 'phase', 'decision']
>>> json.loads(buf.getvalue().splitlines()[2])["selected"]
{'id': {'id': 'O1'}, 'name': 'go'}
>>> rec.operators, rec.output()
([[1, 0, 'go']], 'hi')
"""

from __future__ import annotations

import re
from collections import deque
from typing import Any, Callable, MutableSequence

from adapt.engine.symbols import Float, Identifier, Symbol
from adapt.engine.trace import TraceWriter, symbol_json
from adapt.engine.wme import WME
from adapt.soar.xmltrace import tags

__all__ = ["KernelRecorder", "Symbols", "ABSENT", "trace_header", "GOAL_DEPTH"]

#: Fields of the trace format the Soar kernel does not report (the header's ``absent``).
ABSENT = ("firings.bindings", "retractions.bindings", "retractions.o-support",
          "decision.candidates", "decision.removed_goals", "firings.support.none")
#: The start of the kernel's warning when the goal stack grows too deep.
GOAL_DEPTH = "Goal stack depth exceeded"

_PHASES = {"input": "input", "propose": "proposal", "decision": "decision", "apply": "apply",
           "output": "output"}
_NAME = re.compile(r"([A-Za-z])(\d+)$")


def trace_header(kernel: str) -> dict[str, Any]:
    """The header fields of a trace the Soar engine writes.

    >>> trace_header("Soar 9.6.5")["engine"]
    'soar'
    """
    return {"engine": "soar", "kernel": kernel, "absent": list(ABSENT)}


class Symbols:
    """One :class:`~adapt.engine.symbols.Identifier` object per kernel identifier name
    (adapt compares identifiers by identity), and typed values.

    >>> s = Symbols()
    >>> s.identifier("O12") is s.identifier("O12"), s.value("2.5", "double"), s.value("3", "int")
    (True, Float(2.5), 3)
    """

    def __init__(self) -> None:
        self.by_name: dict[str, Identifier] = {}

    def identifier(self, name: str) -> Identifier:
        """The identifier called ``name`` (made on first use)."""
        found = self.by_name.get(name)
        if found is None:
            m = _NAME.match(name)
            found = Identifier(m.group(1).upper(), int(m.group(2))) if m else Identifier(name, 0)
            if not m:
                found.name = name
            self.by_name[name] = found
        return found

    def bind(self, ident: Identifier, name: str) -> None:
        """Give a new input-link identifier the name the kernel gave it."""
        m = _NAME.match(name)
        if m is not None:
            ident.letter, ident.number = m.group(1), int(m.group(2))
        ident.name = name
        self.by_name[name] = ident

    def value(self, text: str, valtype: str | None) -> Symbol:
        """A WME value as the kernel typed it (``id``, ``int``, ``double``, ``string``)."""
        if valtype == "id":
            return self.identifier(text)
        if valtype == "int":
            try:
                return int(text)
            except ValueError:
                return text
        if valtype in ("double", "float"):
            try:
                return Float(float(text))
            except ValueError:
                return text
        return text


class _Instantiation:
    """A firing or retraction being read: its rule and matched timetags."""

    __slots__ = ("retract", "rule", "tags", "support", "collecting")

    def __init__(self, retract: bool) -> None:
        self.retract = retract
        self.rule = ""
        self.tags: list[int] = []
        self.support: str | None = None
        self.collecting = False


class KernelRecorder:
    """Reads the kernel's XML trace (see the module docstring).

    Parameters
    ----------
    symbols : Symbols
        The agent's identifiers.
    history : int or None
        Keep only the most recent operator selections, impasses, writes and
        messages (``None``: all), as :class:`adapt.engine.Agent` does.
    track_wmes : bool
        The kernel reports WME changes (its trace has ``--wmes``): keep
        working memory by timetag, for firings' goal levels and impasse items.
    """

    def __init__(self, symbols: Symbols, *, history: int | None = None,
                 track_wmes: bool = False) -> None:
        self.symbols = symbols
        self.history = history
        self.track_wmes = track_wmes
        self.writer: TraceWriter | None = None
        self.d = 0
        self.phase: str | None = None
        self.operators: MutableSequence[list[Any]] = self._log()
        self.impasses: MutableSequence[list[Any]] = self._log()
        self.messages: MutableSequence[str] = self._log()
        self._output: MutableSequence[str] = self._log()
        self.operator_count = 0
        self.impasse_count = 0
        self.goal_depth_exceeded = False
        self.on_write: list[Callable[[str], None]] = []
        self.on_message: list[Callable[[str], None]] = []
        #: working memory by timetag (when the kernel reports WME changes)
        self.wm: dict[int, WME] = {}
        #: goal level of each state
        self.levels: dict[Identifier, int] = {}
        self._decision: dict[str, Any] | None = None
        self._items: list[WME] = []
        self._inst: _Instantiation | None = None
        self._ended = False  # a phase ended, its record not yet written
        self._wme_for: str | None = None  # "add"/"remove": the next <wme> is that change
        self._prefs_seen: set[tuple[tuple[str, str], ...]] = set()

    def _log(self) -> MutableSequence[Any]:
        return [] if self.history is None else deque(maxlen=self.history)

    def output(self) -> str:
        """Everything ``(write)`` printed (the most recent ``history`` writes)."""
        return "".join(self._output)

    def existing(self, xml: str) -> None:
        """The WMEs that exist before the first phase, as ``<wme>`` elements (the kernel's
        ``print --internal``); the state with ``^superstate nil`` is the top state."""
        s = self.symbols
        for name, a in tags(xml):
            if name != "wme" or "id" not in a:
                continue
            w = WME(s.identifier(a["id"]), a.get("attr", ""), s.value(a.get("value", ""), a.get("valtype")),
                    a.get("preference") == "+", _int(a.get("tag"), 0))
            self.wm[w.timetag] = w
            if w.attr == "superstate" and w.value == "nil" and type(w.id) is Identifier:
                self.levels[w.id] = 0

    def attach(self, writer: TraceWriter) -> None:
        """Write the trace to ``writer`` from now on; the WMEs that exist are the
        first phase's adds."""
        self.writer = writer
        writer.existing_wmes(self.wm.values())

    # -- reading ------------------------------------------------------------------------

    def feed(self, xml: str) -> None:
        """Read one XML trace string of the kernel."""
        for name, a in tags(xml):
            handler = _HANDLERS.get(name)
            if handler is None:
                continue
            if name != "wme" and name != "preference" and name != "production" \
                    and name != "actionsidemarker" and name != "rhs_write" and self._inst is not None:
                self._finish_instantiation()
            handler(self, a)
        if self._inst is not None:
            self._finish_instantiation()

    # phases
    def _phase(self, a: dict[str, str]) -> None:
        phase = _PHASES.get(a.get("name", ""))
        if phase is None:
            return
        self._prefs_seen.clear()
        if a.get("status") == "end":
            self._end_phase(phase)
            return
        if phase == "decision":
            self.d += 1
            self._decision = None
            self._items = []
        self.phase = phase
        if self.writer is not None:
            if self._ended:
                self.writer.end_phase()
            self._ended = False
            self.writer.begin_phase(self.d, phase)

    def _end_phase(self, phase: str) -> None:
        """A phase ended.  Its record is written when the next phase begins (or the
        trace ends): what the kernel reports between the two -- the messages and
        printed errors of a halt -- belongs to it."""
        self.phase = None
        writer = self.writer
        if writer is None:
            return
        self._ended = True
        if phase == "decision":
            self._ended = False
            record = self._decision or {"d": self.d, "level": None, "selected": None,
                                        "impasse": None}
            impasse = record.get("impasse")
            if impasse is not None and self.track_wmes:
                state = self.symbols.identifier(impasse["state"]["id"])
                impasse["items"] = [symbol_json(w.value) for w in sorted(self._items, key=lambda w: w.timetag)
                                    if w.id is state]
            self._decision = None
            writer.decision(record)

    def _subphase(self, a: dict[str, str]) -> None:
        self._prefs_seen.clear()

    # decisions
    def _operator(self, a: dict[str, str]) -> None:
        d = _int(a.get("decision_cycle_count"), self.d)
        self.d = d
        level = _int(a.get("stack_level"), 0)
        name = a.get("name")
        ident = a.get("current_operator_id", "")
        self.operators.append([d, level, name])
        self.operator_count += 1
        self._decision = {"d": d, "level": level, "selected": {"id": {"id": ident}, "name": name},
                          "impasse": None}

    def _state(self, a: dict[str, str]) -> None:
        ident = self.symbols.identifier(a.get("current_state_id", ""))
        level = _int(a.get("stack_level"), 0)
        self.levels[ident] = level
        kind = a.get("impasse_type")
        if not kind:
            return  # the top state, made by init-soar
        d = _int(a.get("decision_cycle_count"), self.d)
        self.d = d
        attribute = a.get("impasse_object", "state")
        self.impasses.append([d, level, kind, attribute])
        self.impasse_count += 1
        self._decision = {"d": d, "level": level - 1, "selected": None,
                          "impasse": {"type": kind, "attribute": attribute,
                                      "state": {"id": ident.name}}}

    # output and messages
    def _write(self, a: dict[str, str]) -> None:
        text = a.get("string", "")
        self._output.append(text)
        if self.writer is not None:
            self.writer.write_text(text)
        for callback in self.on_write:
            callback(text)

    def _message(self, a: dict[str, str]) -> None:
        text = a.get("string", "")
        if GOAL_DEPTH in text:
            self.goal_depth_exceeded = True
        self.messages.append(text)
        if self.writer is not None:
            self.writer.message(text)
        for callback in self.on_message:
            callback(text)

    # working memory
    def _adding(self, a: dict[str, str]) -> None:
        self._wme_for = "add"

    def _removing(self, a: dict[str, str]) -> None:
        self._wme_for = "remove"

    def _wme(self, a: dict[str, str]) -> None:
        inst = self._inst
        if inst is not None and not inst.collecting and "attr" not in a:
            inst.tags.append(_int(a.get("tag"), 0))
            return
        change, self._wme_for = self._wme_for, None
        if change is None or "id" not in a:
            return
        s = self.symbols
        w = WME(s.identifier(a["id"]), s.value(a.get("attr", ""), a.get("attr_type")),
                s.value(a.get("value", ""), a.get("valtype")), a.get("preference") == "+",
                _int(a.get("tag"), 0))
        if change == "add":
            self.wm[w.timetag] = w
            if self.phase == "decision" and w.attr == "item":
                self._items.append(w)
            if self.writer is not None:
                self.writer.wm_changes([w], [])
        else:
            self.wm.pop(w.timetag, None)
            if self.writer is not None:
                self.writer.wm_changes([], [w])

    # firings and retractions
    def _firing(self, a: dict[str, str]) -> None:
        self._inst = _Instantiation(retract=False)

    def _retracting(self, a: dict[str, str]) -> None:
        self._inst = _Instantiation(retract=True)

    def _production(self, a: dict[str, str]) -> None:
        if self._inst is not None:
            self._inst.rule = a.get("prodname", "")

    def _marker(self, a: dict[str, str]) -> None:
        if self._inst is not None:
            self._inst.collecting = True

    def _preference(self, a: dict[str, str]) -> None:
        key = tuple(sorted(a.items()))
        inst = self._inst
        if inst is not None and inst.collecting and not inst.retract and inst.support is None \
                and key not in self._prefs_seen:
            inst.support = "o" if a.get("o_supported") else "i"
        self._prefs_seen.add(key)

    def _finish_instantiation(self) -> None:
        inst, self._inst = self._inst, None
        writer = self.writer
        if inst is None or writer is None or not inst.rule:
            return
        wm = self.wm
        matched = [wm.get(t) or WME("", "", "", False, t) for t in inst.tags]
        level = 0
        levels = self.levels
        for w in matched:
            found = levels.get(w.id) if type(w.id) is Identifier else None  # type: ignore[call-overload]
            if found is not None and found > level:
                level = found
        if inst.retract:
            writer.retraction(inst.rule, level, matched)
        else:
            writer.firing(inst.rule, level, inst.support, None, matched)


def _int(text: str | None, default: int) -> int:
    try:
        return int(text) if text is not None else default
    except ValueError:
        return default


_HANDLERS: dict[str, Callable[[KernelRecorder, dict[str, str]], None]] = {
    "phase": KernelRecorder._phase,
    "subphase": KernelRecorder._subphase,
    "operator": KernelRecorder._operator,
    "state": KernelRecorder._state,
    "rhs_write": KernelRecorder._write,
    "message": KernelRecorder._message,
    "warning": KernelRecorder._message,
    "error": KernelRecorder._message,
    "adding_wme": KernelRecorder._adding,
    "removing_wme": KernelRecorder._removing,
    "wme": KernelRecorder._wme,
    "firing_production": KernelRecorder._firing,
    "retracting_production": KernelRecorder._retracting,
    "production": KernelRecorder._production,
    "actionsidemarker": KernelRecorder._marker,
    "preference": KernelRecorder._preference,
}
