"""Impasses and substates; expected values measured in real Soar 9.6.5."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.engine import Agent

AGENTS = Path(__file__).parent / "agents"


def run(text: str, n: int | None = None) -> tuple[Agent, object]:
    agent = Agent()
    agent.load_text(text)
    return agent, agent.run(n)


def substate_attrs(agent: Agent, level: int = 1) -> dict[str, list[str]]:
    sub = agent.goals[level]
    out: dict[str, list[str]] = {}
    for w in agent.kernel.wm.of(sub):
        out.setdefault(str(w.attr), []).append(str(w.value))
    return out


TIE = """
sp {p (state <s> ^superstate nil) --> (<s> ^operator <a> + <b> +) (<a> ^name a) (<b> ^name b)}
"""


def test_tie_substate_structure() -> None:
    agent, r = run(TIE, 1)
    assert r.impasses == [[1, 1, "tie", "operator"]]
    attrs = substate_attrs(agent)
    assert attrs["impasse"] == ["tie"] and attrs["choices"] == ["multiple"]
    assert attrs["attribute"] == ["operator"] and attrs["quiescence"] == ["t"]
    assert len(attrs["item"]) == 2 and attrs["item-count"] == ["2"]
    assert attrs["non-numeric-count"] == ["2"] and attrs["superstate"] == ["S1"]


def test_constraint_failure_has_choices_none() -> None:
    agent, r = run("sp {p (state <s> ^superstate nil) --> (<s> ^operator <a> ! <b> !)"
                   " (<a> ^name a) (<b> ^name b)}", 1)
    assert r.impasses == [[1, 1, "constraint-failure", "operator"]]
    assert substate_attrs(agent)["choices"] == ["none"]


def test_state_and_operator_no_change_nest_until_max_goal_depth() -> None:
    agent, r = run("sp {p (state <s> ^superstate nil -^x) --> (<s> ^operator <o> +)"
                   " (<o> ^name first)}")
    assert r.operators == [[1, 0, "first"]]
    assert r.impasses[0] == [2, 1, "no-change", "operator"]
    assert r.impasses[-1] == [101, 100, "no-change", "state"]
    assert (r.halted, r.stop_reason, r.decisions) == (False, "max-goal-depth", 101)
    assert "Goal stack depth exceeded" in r.messages[0]
    assert substate_attrs(agent)["choices"] == ["none"]


def test_halt_from_a_substate_stops_the_agent() -> None:
    text = """
    sp {p (state <s> ^superstate nil -^done) --> (<s> ^operator <o> +) (<o> ^name first)}
    sp {a (state <s> ^operator.name first) --> (<s> ^done yes)}
    sp {h (state <s> ^superstate.superstate.superstate nil) --> (write |deep|) (halt)}
    """
    _, r = run(text)
    assert (r.halted, r.decisions, r.output) == (True, 3, "deep")
    assert r.impasses == [[2, 1, "no-change", "state"], [3, 2, "no-change", "state"]]


def test_tie_resolved_in_substate_by_result_and_substate_removed() -> None:
    text = """
    sp {p (state <s> ^superstate nil -^done)
       --> (<s> ^operator <a> + <b> +) (<a> ^name a) (<b> ^name b)}
    sp {prefer (state <s> ^impasse tie ^superstate <ss> ^item <i>) (<i> ^name a)
       --> (<ss> ^operator <i> >)}
    sp {apply (state <s> ^operator.name a) --> (<s> ^done yes)}
    sp {h (state <s> ^done yes) --> (halt)}
    """
    agent, r = run(text)
    assert r.impasses == [[1, 1, "tie", "operator"]]
    assert r.operators == [[2, 0, "a"]] and r.decisions == 2
    assert agent.goals == [agent.top_state]


def test_result_support_i_retracts_and_o_persists() -> None:
    text = """
    sp {p (state <s> ^superstate nil -^phase) --> (<s> ^operator <o> +) (<o> ^name work)}
    sp {sub-i (state <s> ^superstate <ss>) (<ss> ^flag on) --> (<ss> ^seen-flag yes)}
    sp {sub-o (state <s> ^superstate <ss>) (<ss> ^operator.name work) --> (<ss> ^phase 1)}
    sp {flag (state <s> ^superstate nil -^stop) --> (<s> ^flag on)}
    sp {stop (state <s> ^phase 1 ^seen-flag yes) --> (<s> ^stop yes)}
    sp {report (state <s> ^phase 1 ^stop yes -^seen-flag) --> (write |retracted|) (halt)}
    """
    _, r = run(text, 20)
    assert r.output == "retracted" and r.halted and r.decisions == 2
    assert r.impasses == [[2, 1, "no-change", "operator"]]


@pytest.mark.parametrize("name", sorted(p.name for p in AGENTS.glob("sub_*.soar")))
def test_substate_agents_run_to_their_end(name: str) -> None:
    agent = Agent()
    agent.load_file(AGENTS / name)
    r = agent.run(200)
    assert r.stop_reason in ("halt", "max-decisions", "max-goal-depth")
    assert r.impasses, "every sub_* agent creates a substate"
