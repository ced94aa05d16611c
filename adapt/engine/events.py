"""Kernel events and their listeners: how tracing and other layers watch a run.

The decision cycle and the kernel announce what happens through one
:class:`EventBus` per agent; any number of listeners may subscribe to each
:class:`Event`.  The trace writer is one listener
(:class:`adapt.engine.tracing.TraceRecorder`); ``Agent.on_write`` is another.
An event nobody listens to costs an empty-list test: the kernel checks
:meth:`EventBus.listeners` before it builds a payload.

Payloads, by event:

==================  ========================================================
``PHASE_BEGIN``     ``(decision, phase)``: decisions started so far, a Phase
``PHASE_END``       the :class:`~adapt.engine.vocabulary.Phase` that ended
``WM_CHANGES``      ``(added, removed)``: lists of WMEs of one commit
``FIRE``            the :class:`~adapt.engine.instantiation.Instantiation`
                    (its ``bindings`` set)
``RETRACT``         the retracting Instantiation
``DECISION``        ``(goal, SlotDecision)``: preferences were decided
``SELECT``          ``(goal, operator)``: an operator was selected
``IMPASSE``         ``(goal, substate goal)``: a substate was created
``DESELECT``        the goal whose selection the consistency check removed
``GDS``             the goal removed because its dependency set changed
``REMOVE_GOAL``     a goal being removed
``RESULT``          ``(instantiation, justification or None, preferences)``
``WRITE``           the text of a ``(write ...)``
``MESSAGE``         a kernel message (warnings, "This Agent halted.")
==================  ========================================================

Examples
--------
>>> bus = EventBus()
>>> seen = []
>>> stop = bus.subscribe(Event.WRITE, seen.append)
>>> _ = bus.subscribe(Event.WRITE, lambda text: seen.append(text.upper()))
>>> bus.emit(Event.WRITE, "hi")
>>> stop(); bus.emit(Event.WRITE, "again")
>>> seen
['hi', 'HI', 'AGAIN']
"""

from __future__ import annotations

from enum import Enum
from typing import Any, Callable

__all__ = ["Event", "EventBus", "Callback"]

#: A listener: called with the event's payload.
Callback = Callable[[Any], None]


class Event(Enum):
    """What the cycle and the kernel announce (see the module docstring)."""

    PHASE_BEGIN = "phase-begin"
    PHASE_END = "phase-end"
    WM_CHANGES = "wm-changes"
    FIRE = "fire"
    RETRACT = "retract"
    DECISION = "decision"
    SELECT = "select"
    IMPASSE = "impasse"
    DESELECT = "deselect"
    GDS = "gds"
    REMOVE_GOAL = "remove-goal"
    RESULT = "result"
    WRITE = "write"
    MESSAGE = "message"


class EventBus:
    """The listeners of one agent's events, in subscription order."""

    __slots__ = ("_listeners",)

    def __init__(self) -> None:
        self._listeners: dict[Event, list[Callback]] = {e: [] for e in Event}

    def subscribe(self, event: Event, callback: Callback) -> Callable[[], None]:
        """Call ``callback(payload)`` on every ``event``; returns a function
        that unsubscribes it."""
        listeners = self._listeners[event]
        listeners.append(callback)

        def unsubscribe() -> None:
            if callback in listeners:
                listeners.remove(callback)

        return unsubscribe

    def listeners(self, event: Event) -> list[Callback]:
        """The live list of ``event``'s listeners (empty: nobody listens).

        Hot paths keep this list and test it before building a payload;
        do not modify it (use :meth:`subscribe`).
        """
        return self._listeners[event]

    def emit(self, event: Event, payload: object) -> None:
        """Call every listener of ``event`` with ``payload``."""
        for callback in self._listeners[event]:
            callback(payload)
