"""The trace as a listener: a :class:`TraceRecorder` turns an agent's events
into the records of a :class:`~adapt.engine.trace.TraceWriter`.

The decision cycle knows nothing of traces: it announces phases, decisions
and impasses, and the kernel firings, retractions and working-memory
changes, on the agent's :class:`~adapt.engine.events.EventBus`.  A recorder
subscribes to those events and writes what ``docs/trace-format.md``
describes; a run with a trace is the same run as one without.

Examples
--------
>>> import io, json
>>> from adapt.engine import Agent
>>> buf = io.StringIO()
>>> agent = Agent(trace=buf, trace_level=3)
>>> _ = agent.load_text("sp {hi (state <s> ^superstate nil) --> (write |hi|) (halt)}")
>>> _ = agent.run()
>>> [json.loads(line)["kind"] for line in buf.getvalue().splitlines()]
['header', 'phase', 'phase', 'footer']
"""

from __future__ import annotations

from typing import Any

from adapt.engine.events import Event, EventBus
from adapt.engine.goals import Goal
from adapt.engine.instantiation import Instantiation
from adapt.engine.kernel import Kernel
from adapt.engine.preferences import SlotDecision
from adapt.engine.symbols import Symbol
from adapt.engine.trace import TraceWriter, symbol_json
from adapt.engine.vocabulary import Phase
from adapt.engine.wme import WME

__all__ = ["TraceRecorder"]


class TraceRecorder:
    """Writes one agent's events to a trace writer.

    Parameters
    ----------
    writer : TraceWriter
    kernel : Kernel
        The agent's kernel (for operator names and the WMEs that exist when
        the trace starts).
    events : EventBus
        The agent's events; the recorder subscribes at once.
    """

    __slots__ = ("writer", "kernel", "_d", "_decision", "_unsubscribe")

    def __init__(self, writer: TraceWriter, kernel: Kernel, events: EventBus) -> None:
        self.writer = writer
        self.kernel = kernel
        self._d = 0
        self._decision: dict[str, Any] | None = None
        writer.existing_wmes(kernel.wm)
        # subscribe only to what the level writes: a firing's bindings, the
        # WMEs of a commit and a decision's candidates are built only when
        # someone listens, so level 1 costs what it shows
        level = writer.level
        subscriptions: list[tuple[Event, Any]] = [
            (Event.PHASE_BEGIN, self.phase_begun),
            (Event.PHASE_END, self.phase_ended),
            (Event.DECISION, self.decided),
            (Event.IMPASSE, self.impasse)]
        if level >= 2:
            subscriptions += [(Event.WRITE, writer.write_text), (Event.MESSAGE, writer.message)]
        if level >= 3:
            subscriptions += [(Event.FIRE, self.fired), (Event.RETRACT, self.retracted)]
        if level >= 4:
            subscriptions.append((Event.WM_CHANGES, self.wm_changed))
        self._unsubscribe = [events.subscribe(event, callback)
                             for event, callback in subscriptions]

    def detach(self) -> None:
        """Stop listening."""
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        self._unsubscribe = []

    def phase_begun(self, payload: tuple[int, Phase]) -> None:
        """``PHASE_BEGIN``: open the phase's record."""
        d, phase = payload
        self._d = d
        self.writer.begin_phase(d, phase.value)

    def phase_ended(self, phase: Phase) -> None:
        """``PHASE_END``: write the phase's record (and, after a decision
        phase, its decision record)."""
        self.writer.end_phase()
        if phase is Phase.DECISION:
            record = self._decision or {"d": self._d, "level": None,
                                        "candidates": [], "selected": None, "impasse": None}
            self._decision = None
            self.writer.decision(record)

    def wm_changed(self, payload: tuple[list[WME], list[WME]]) -> None:
        """``WM_CHANGES``."""
        added, removed = payload
        self.writer.wm_changes(added, removed)

    def fired(self, inst: Instantiation) -> None:
        """``FIRE``."""
        self.writer.firing(inst.name, inst.goal.level, inst.support.value, inst.bindings or {},
                           inst.wmes)

    def retracted(self, inst: Instantiation) -> None:
        """``RETRACT``."""
        self.writer.retraction(inst.name, inst.goal.level, inst.wmes)

    def decided(self, payload: tuple[Goal, SlotDecision]) -> None:
        """``DECISION``: the candidates and the selection of the decision record."""
        goal, d = payload
        k = self.kernel
        record: dict[str, Any] = {"d": self._d, "level": goal.level}
        if self.writer.level >= 5:  # the candidates: only the level that writes them
            candidates: dict[Symbol, list[Any]] = {}
            for sp in goal.prefs:
                p = sp.preference
                candidates.setdefault(p.value, []).append([p.kind.value, symbol_json(p.referent)])
            record["candidates"] = [
                {"id": symbol_json(v), "name": k.operator_name(v), "preferences": ps}
                for v, ps in candidates.items()]
        record["selected"] = (None if d.selected is None else
                              {"id": symbol_json(d.selected), "name": k.operator_name(d.selected)})
        record["impasse"] = None
        self._decision = record

    def impasse(self, payload: tuple[Goal, Goal]) -> None:
        """``IMPASSE``: the impasse of the decision record."""
        goal, sub = payload
        record = self._decision or {"d": self._d, "level": goal.level,
                                    "candidates": [], "selected": None}
        record["impasse"] = {"type": sub.impasse, "attribute": sub.attribute,
                             "items": [symbol_json(v) for v in sub.items],
                             "state": symbol_json(sub.id)}
        self._decision = record
