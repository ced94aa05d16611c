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

The **waterfall**: each elaboration cycle fires at one goal only, the highest
(oldest) goal with pending work.  When the active level moves, or when a goal
that was firing i-supported matches runs out of them (*minor quiescence*),
the goal stack is checked for consistency: a selected operator that the
current preferences would no longer choose, or an impasse whose kind the
preferences no longer give, is removed on the spot -- and the phase ends
(apply goes to output, proposal to decision).

``halt`` finishes its elaboration cycle and stops the agent (no output
phase).  ``run N`` stops before the apply phase of the run's ``N``-th
decision.
"""

from __future__ import annotations

import random
from typing import TYPE_CHECKING

from adapt.engine.goals import NO_CHANGE, Goal
from adapt.engine.preferences import decide, should_keep

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.agent import Agent

__all__ = ["run", "PHASES", "decide_context_slots", "goal_stack_consistent"]

PHASES = ("input", "proposal", "decision", "apply", "output")
_NEXT = {"input": "proposal", "proposal": "decision", "decision": "apply",
         "apply": "output", "output": "input"}

_MAX_ELAB = "Warning: reached max-elaborations; proceeding to {} phase."


def run(agent: Agent, max_decisions: int | None) -> None:
    """Run phases until a stop: halt, interrupt, goal depth, or the decision bound."""
    if agent.tracer is None:
        _run_untraced(agent, max_decisions)
        return
    done = 0
    while agent.stop_reason is None:
        phase = agent.next_phase
        if phase == "apply" and max_decisions is not None and done >= max_decisions:
            agent.stop_reason = "max-decisions"
            break
        agent.begin_phase(phase)
        try:
            if phase == "input":
                input_phase(agent)
            elif phase == "proposal":
                elaborate(agent, apply=False)
            elif phase == "decision":
                decision_phase(agent)
                done += 1
            elif phase == "apply":
                elaborate(agent, apply=True)
            else:
                output_phase(agent)
        finally:
            agent.end_phase(phase)
        agent.next_phase = _NEXT[phase]
        if agent.halted:
            agent.stop_reason = "halt"


def _run_untraced(agent: Agent, max_decisions: int | None) -> None:
    """:func:`run` without a trace: the same phases, without the per-phase hooks
    (``Agent.end_phase`` only adds the halt message, done here once)."""
    done = 0
    limit = -1 if max_decisions is None else max_decisions
    k = agent.kernel
    io = agent.io
    try:
        while agent.stop_reason is None:
            phase = agent.next_phase
            if phase == "input":
                if io.input_callbacks:
                    io.run_input()
                    k.commit()
                elif k.wm.pending or k._matcher_dirty:
                    k.commit()
                agent.next_phase = "proposal"
            elif phase == "proposal":
                elaborate(agent, apply=False)
                agent.next_phase = "decision"
            elif phase == "decision":
                decision_phase(agent)
                done += 1
                agent.next_phase = "apply"
            elif phase == "apply":
                if done == limit:
                    agent.stop_reason = "max-decisions"
                    break
                elaborate(agent, apply=True)
                agent.next_phase = "output"
            else:
                if io.output_callbacks:
                    io.run_output()
                agent.next_phase = "input"
            if agent.halted:
                agent.stop_reason = "halt"
    finally:
        if agent.halted_message_pending:
            agent.message("This Agent halted.")


def input_phase(agent: Agent) -> None:
    """Let the input callbacks write to the input-link; commit their changes."""
    agent.io.run_input()
    agent.kernel.commit()


def output_phase(agent: Agent) -> None:
    """Show the output-link to the output callbacks."""
    agent.io.run_output()


def decision_phase(agent: Agent) -> None:
    """Count the decision, decide one slot, commit the changes."""
    agent.decisions += 1
    decide_context_slots(agent)
    agent.kernel.commit()


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
    firing = "i"
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
            if firing == "i" and not k.bottom.i_activity():
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
            if apply and firing == "i" and not (active.pending_i or active.retractions):
                if not goal_stack_consistent(agent, active):
                    return
        elif active.level > previous.level:
            alive = k.goals.get(previous.id) is previous
            if (not apply or firing == "i") and alive and not previous.i_activity():
                if not goal_stack_consistent(agent, previous):
                    return
            if apply and active.saved_firing == "i" and not active.i_activity():
                if not goal_stack_consistent(agent, active):
                    return
        else:
            previous.saved_firing = firing
            if not goal_stack_consistent(agent, active):
                return
        firing = "o" if apply and not (active.pending_i or active.retractions) else "i"
        fire(active, firing)
        cycles += 1
        agent.elaboration_cycles += 1
        commit()
        if agent.halted or agent.stop_reason is not None:
            return


def _highest_active(top: Goal, apply: bool) -> Goal | None:
    goal: Goal | None = top
    while goal is not None:
        if goal.pending_i or goal.retractions or (apply and goal.pending_o):
            return goal
        goal = goal.lower
    return None


def _kind_at(goal: Goal, apply: bool) -> str:
    if not apply or goal.pending_i or goal.retractions:
        return "i"
    return "o"


# -- consistency (operator retention) -------------------------------------------

def goal_stack_consistent(agent: Agent, through: Goal) -> bool:
    """Soar's consistency check down to ``through``; removes the first
    inconsistent decision (and returns False) if there is one."""
    k = agent.kernel
    goal: Goal | None = k.top
    while goal is not None and goal.level <= through.level:
        if goal.changed and (goal.lower is not None or goal.operator is not None):
            if not _consistent(goal):
                agent.kernel.emit("deselect", goal)
                k.deselect(goal)
                k.commit()
                return False
        goal = goal.lower
    return True


_NO_RNG = random.Random(0)


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
    items: tuple = ()
    non_numeric: tuple = ()
    if goal.operator is not None or not goal.changed:
        impasse = NO_CHANGE
        attribute = "operator" if goal.operator is not None else "state"
    else:
        d = decide(goal.preferences(), rng=agent.rng)
        if agent.tracer is not None:
            agent.note_decision(goal, d)
        if d.outcome == "select":
            k.select(goal, d.selected)  # type: ignore[arg-type]
            agent.operators.append([agent.decisions, goal.level,
                                    k.operator_name(d.selected)])  # type: ignore[arg-type]
            agent.operator_count += 1
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
    agent.note_impasse(goal, sub)
    return True
