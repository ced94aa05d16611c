"""The decision cycle, phase by phase, as Soar 9.6 runs it.

One decision cycle is::

    input -> proposal -> decision -> apply -> output

* **input** -- input callbacks write to the input-link; the changes are
  committed at the end of the phase.
* **proposal** -- elaboration cycles that fire only i-supported matches and
  retractions (o-supported matches wait for the apply phase), until quiescence
  or ``max-elaborations``.
* **decision** -- the decision counter increases; at most one slot changes:
  the highest goal whose operator slot changed (or the bottom goal) is
  decided: an operator is selected, or an impasse creates a substate (or an
  existing one only gets its ``^item`` set updated and the next goal down is
  decided).
* **apply** -- elaboration cycles: at the active level, while i-supported
  matches or retractions are pending only those fire (IE), otherwise the
  o-supported ones (PE).
* **output** -- output callbacks see the output-link.

The **waterfall**: each elaboration cycle fires at the highest (oldest) goal
with pending work, the *active* goal; in the same cycle each lower goal then
fires its pending matches whose actions stay below the change level (the
deepest goal above it that fired), as Soar's inner elaboration loop does
(:func:`waterfall`).  When the active level moves, or when a goal
that was firing i-supported matches runs out of them (*minor quiescence*),
the goal stack is checked for consistency: a selected operator that the
current preferences would no longer choose, or an impasse whose kind the
preferences no longer give, is removed on the spot -- and the phase ends
(apply goes to output, proposal to decision).

``halt`` finishes its elaboration cycle and stops the agent (no output
phase).  ``(interrupt)`` stops the run before the next decision phase: the
phase it fires in, and the output, input and proposal phases after it, run
to their end (as in Soar).  A match of a production flagged ``:interrupt``
stops the run at the end of the phase in which it appeared (unless it went
again before then, as in Soar).  ``run N`` stops before the apply phase of the run's ``N``-th
decision.
"""

from __future__ import annotations

import random
from typing import TYPE_CHECKING, Final

from adapt.engine.events import Event
from adapt.engine.goals import Goal
from adapt.engine.preferences import decide, should_keep
from adapt.engine.symbols import Symbol
from adapt.engine.vocabulary import NO_CHANGE, ImpasseAttribute, ImpasseType, Phase, Support

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.agent import Agent
    from adapt.engine.kernel import Kernel

__all__ = ["run", "run_phase", "decide_context_slots", "goal_stack_consistent", "waterfall"]

_MAX_ELAB: Final = "Warning: reached max-elaborations; proceeding to {} phase."

# The enum members the loop tests, as constants (compiled code reads them
# without an attribute lookup on the enum class).
_INPUT: Final = Phase.INPUT
_PROPOSAL: Final = Phase.PROPOSAL
_DECISION: Final = Phase.DECISION
_APPLY: Final = Phase.APPLY
_I: Final = Support.I
_O: Final = Support.O
_NEXT: Final = {p: p.next for p in Phase}
_ON_DECISION: Final = Event.DECISION
_ON_SELECT: Final = Event.SELECT
_ON_IMPASSE: Final = Event.IMPASSE


def run(agent: Agent, max_decisions: int | None) -> None:
    """Run phases until a stop: halt, interrupt, goal depth, or the decision bound.

    This is the one loop, traced or not: a trace is a listener of the
    ``PHASE_BEGIN`` / ``PHASE_END`` events (and of the kernel's), which
    are announced only when someone listens.  ``max_decisions`` stops the
    run before the apply phase of its ``max_decisions``-th decision; 0
    behaves as Soar's ``run 0``, like 1.
    """
    done = 0
    events = agent.events
    on_begin = events.listeners(Event.PHASE_BEGIN)
    on_end = events.listeners(Event.PHASE_END)
    while agent.stop_reason is None:
        phase = agent.next_phase
        if phase is _APPLY and max_decisions is not None and done >= max_decisions:
            agent.stop_reason = "max-decisions"
            break
        if phase is _DECISION and agent.interrupt_pending:
            # (interrupt) lets the phases before the next decision finish, as in Soar
            agent.interrupt_pending = False
            agent.stop_reason = "interrupted"
            break
        if on_begin:
            events.emit(Event.PHASE_BEGIN, (agent.decisions + (phase is _DECISION), phase))
        try:
            run_phase(agent, phase)
            if phase is _DECISION:
                done += 1
        finally:
            if agent.halted_message_pending:
                agent.message("This Agent halted.")
            if on_end:
                events.emit(Event.PHASE_END, phase)
        agent.next_phase = _NEXT[phase]
        if agent.halted:
            agent.stop_reason = "halt"
        elif agent.kernel.interrupt_matches:
            # a production flagged :interrupt matched in this phase (Soar's
            # match-time interrupt): the run stops after the phase
            names = agent.kernel.interrupt_matches
            agent.message("*** Production match-time interrupt (:interrupt), probably from "
                          f"{list(names.values())[-1]}")
            names.clear()
            agent.stop_reason = "interrupted"


def run_phase(agent: Agent, phase: Phase) -> None:
    """Run one phase of the cycle."""
    if phase is _PROPOSAL:
        elaborate(agent, apply=False)
    elif phase is _APPLY:
        elaborate(agent, apply=True)
    elif phase is _DECISION:
        agent.decisions += 1
        decide_context_slots(agent)
        agent.kernel.commit()
    elif phase is _INPUT:
        agent.io.run_input()
        agent.kernel.commit()
    else:
        agent.io.run_output()


# -- elaboration: the waterfall ------------------------------------------------

def elaborate(agent: Agent, *, apply: bool) -> None:
    """The proposal (``apply=False``) or apply phase's elaboration cycles."""
    k = agent.kernel
    top = k.top
    goal: Goal | None = top
    while goal is not None:
        goal.saved_firing = None
        goal = goal.lower
    cycles = 0
    max_elaborations = agent.max_elaborations
    active: Goal | None = None
    firing = _I
    fire = k.fire
    commit = k.commit
    while True:
        # the highest goal with pending work (the waterfall)
        nxt: Goal | None = top
        while nxt is not None:
            if nxt.pending_i or nxt.retractions or (apply and nxt.pending_o):
                break
            nxt = nxt.lower
        if nxt is None:
            if firing is _I and not k.bottom.i_activity():
                goal_stack_consistent(agent, k.bottom)
            return
        if cycles >= max_elaborations:
            agent.message(_MAX_ELAB.format("output" if apply else "decide"))
            return
        previous = active
        active = nxt
        if previous is None:
            pass
        elif active is previous or active.level == previous.level:
            if apply and firing is _I and not (active.pending_i or active.retractions):
                if not goal_stack_consistent(agent, active):
                    return
        elif active.level > previous.level:
            alive = k.goals.get(previous.id) is previous
            if (not apply or firing is _I) and alive and not previous.i_activity():
                if not goal_stack_consistent(agent, previous):
                    return
            if apply and active.saved_firing is _I and not active.i_activity():
                if not goal_stack_consistent(agent, active):
                    return
        else:
            previous.saved_firing = firing
            if not goal_stack_consistent(agent, active):
                return
        firing = _O if apply and not (active.pending_i or active.retractions) else _I
        fire(active, firing)
        if active.lower is not None:
            waterfall(k, active, firing, apply)
        if firing is _I:
            k.retract_pending(active)
        cycles += 1
        agent.elaboration_cycles += 1
        commit()
        if agent.halted or agent.stop_reason is not None:  # halt; the goal-depth limit
            return


def waterfall(k: Kernel, active: Goal, firing: Support, apply: bool) -> None:
    """The rest of an elaboration cycle below the active goal (Soar's inner
    elaboration loop): each lower goal with pending work in turn fires its
    pending matches of the cycle's kind whose actions stay below the *change
    level* -- the deepest goal above it that had such matches -- and leaves
    the others (and its retractions) for a later cycle."""
    change = active.level
    goal = active.lower
    while goal is not None:
        if goal.pending_i or goal.retractions or (apply and goal.pending_o):
            pending = goal.pending_i if firing is _I else goal.pending_o
            if pending:
                k.fire(goal, firing, change)
                change = goal.level
        goal = goal.lower


# -- consistency (operator retention) -------------------------------------------

def goal_stack_consistent(agent: Agent, through: Goal) -> bool:
    """Soar's consistency check down to ``through``; removes the first
    inconsistent decision (and returns False) if there is one."""
    k = agent.kernel
    goal: Goal | None = k.top
    while goal is not None and goal.level <= through.level:
        if goal.changed and (goal.lower is not None or goal.operator is not None):
            if not _consistent(goal):
                agent.events.emit(Event.DESELECT, goal)
                k.deselect(goal)
                k.commit()
                return False
        goal = goal.lower
    return True


_NO_RNG: Final = random.Random(0)


def _consistent(goal: Goal) -> bool:
    prefs = goal.preferences()
    if goal.operator is not None:
        return should_keep(prefs, goal.operator)
    assert goal.lower is not None
    current = goal.lower.impasse
    outcome = decide(prefs, rng=_NO_RNG).outcome
    new = None if outcome in ("select", "none") else outcome
    return new == current


# -- the decision ---------------------------------------------------------------

def decide_context_slots(agent: Agent) -> None:
    """Decide the highest changed slot (or the bottom goal's); at most one
    change to the goal stack."""
    k = agent.kernel
    goal: Goal | None = k.top
    while goal is not None and not goal.changed:
        goal = goal.lower
    if goal is None:
        goal = k.bottom
    while True:
        while not goal.changed and goal.lower is not None:
            goal = goal.lower
        if _decide_slot(agent, goal) or goal.lower is None:
            return
        goal = goal.lower


def _decide_slot(agent: Agent, goal: Goal) -> bool:
    k = agent.kernel
    items: tuple[Symbol, ...] = ()
    non_numeric: tuple[Symbol, ...] = ()
    impasse: ImpasseType
    attribute: ImpasseAttribute
    if goal.operator is not None or not goal.changed:
        impasse = NO_CHANGE
        attribute = "operator" if goal.operator is not None else "state"
    else:
        d = decide(goal.preferences(), rng=agent.rng)
        events = agent.events
        if events.listeners(_ON_DECISION):
            events.emit(_ON_DECISION, (goal, d))
        if d.outcome == "select":
            selected = d.selected
            assert selected is not None
            k.select(goal, selected)
            agent.operators.append([agent.decisions, goal.level, k.operator_name(selected)])
            agent.operator_count += 1
            if events.listeners(_ON_SELECT):
                events.emit(_ON_SELECT, (goal, selected))
            return True
        if d.outcome == "none":
            impasse, attribute = NO_CHANGE, "state"
        else:
            impasse, attribute = d.outcome, "operator"
            items, non_numeric = d.items, d.non_numeric
    lower = goal.lower
    if lower is not None and lower.impasse == impasse and lower.attribute == attribute:
        k.update_items(goal, items, non_numeric)
        return False
    level = goal.level + 1
    if level >= agent.max_goal_depth:
        agent.message(f"\nGoal stack depth exceeded on a {impasse} impasse.\n")
        agent.message("Soar appears to be in an infinite loop.  \nContinuing to subgoal may "
                      "cause Soar to \nexceed the program stack of your system.\n")
        agent.stop_reason = "max-goal-depth"
    sub = k.create_impasse(goal, impasse, attribute, items, non_numeric)
    agent.impasses.append([agent.decisions, sub.level, impasse, attribute])
    agent.impasse_count += 1
    if agent.events.listeners(_ON_IMPASSE):
        agent.events.emit(_ON_IMPASSE, (goal, sub))
    return True
