"""Impasses and substates; expected values measured in real Soar 9.6.5 (both engines)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Callable

import pytest

AGENTS = Path(__file__).parent / "agents"
Make = Callable[..., Any]


def run(make: Make, text: str, n: int | None = None) -> tuple[Any, Any]:
    agent = make()
    agent.load_text(text)
    return agent, agent.run(n)


def substate_attrs(agent: Any, level: int = 1) -> dict[str, list[str]]:
    """The substate's WMEs as the engine prints them."""
    text = " ".join(agent.print_state(agent.goals[level], depth=1).split())
    out: dict[str, list[str]] = {}
    for attr, value in re.findall(r"\^(\S+) ([^\s)^]+)", text):
        out.setdefault(attr, []).append(value)
    return out


TIE = """
sp {p (state <s> ^superstate nil) --> (<s> ^operator <a> + <b> +) (<a> ^name a) (<b> ^name b)}
"""


def test_tie_substate_structure(make: Make) -> None:
    agent, r = run(make, TIE, 1)
    assert r.impasses == [[1, 1, "tie", "operator"]]
    attrs = substate_attrs(agent)
    assert attrs["impasse"] == ["tie"] and attrs["choices"] == ["multiple"]
    assert attrs["attribute"] == ["operator"] and attrs["quiescence"] == ["t"]
    assert len(attrs["item"]) == 2 and attrs["item-count"] == ["2"]
    assert attrs["non-numeric-count"] == ["2"] and attrs["superstate"] == ["S1"]


def test_constraint_failure_has_choices_none(make: Make) -> None:
    agent, r = run(make, "sp {p (state <s> ^superstate nil) --> (<s> ^operator <a> ! <b> !)"
                   " (<a> ^name a) (<b> ^name b)}", 1)
    assert r.impasses == [[1, 1, "constraint-failure", "operator"]]
    assert substate_attrs(agent)["choices"] == ["none"]


def test_state_and_operator_no_change_nest_until_max_goal_depth(make: Make) -> None:
    agent, r = run(make, "sp {p (state <s> ^superstate nil -^x) --> (<s> ^operator <o> +)"
                   " (<o> ^name first)}")
    assert r.operators == [[1, 0, "first"]]
    assert r.impasses[0] == [2, 1, "no-change", "operator"]
    assert r.impasses[-1] == [101, 100, "no-change", "state"]
    assert (r.halted, r.stop_reason, r.decisions) == (False, "max-goal-depth", 101)
    assert "Goal stack depth exceeded" in r.messages[0]
    assert substate_attrs(agent)["choices"] == ["none"]


def test_halt_from_a_substate_stops_the_agent(make: Make) -> None:
    text = """
    sp {p (state <s> ^superstate nil -^done) --> (<s> ^operator <o> +) (<o> ^name first)}
    sp {a (state <s> ^operator.name first) --> (<s> ^done yes)}
    sp {h (state <s> ^superstate.superstate.superstate nil) --> (write |deep|) (halt)}
    """
    _, r = run(make, text)
    assert (r.halted, r.decisions, r.output) == (True, 3, "deep")
    assert r.impasses == [[2, 1, "no-change", "state"], [3, 2, "no-change", "state"]]


def test_tie_resolved_in_substate_by_result_and_substate_removed(make: Make) -> None:
    text = """
    sp {p (state <s> ^superstate nil -^done)
       --> (<s> ^operator <a> + <b> +) (<a> ^name a) (<b> ^name b)}
    sp {prefer (state <s> ^impasse tie ^superstate <ss> ^item <i>) (<i> ^name a)
       --> (<ss> ^operator <i> >)}
    sp {apply (state <s> ^operator.name a) --> (<s> ^done yes)}
    sp {h (state <s> ^done yes) --> (halt)}
    """
    agent, r = run(make, text)
    assert r.impasses == [[1, 1, "tie", "operator"]]
    assert r.operators == [[2, 0, "a"]] and r.decisions == 2
    assert agent.goals == [agent.top_state]


def test_result_support_i_retracts_and_o_persists(make: Make) -> None:
    text = """
    sp {p (state <s> ^superstate nil -^phase) --> (<s> ^operator <o> +) (<o> ^name work)}
    sp {sub-i (state <s> ^superstate <ss>) (<ss> ^flag on) --> (<ss> ^seen-flag yes)}
    sp {sub-o (state <s> ^superstate <ss>) (<ss> ^operator.name work) --> (<ss> ^phase 1)}
    sp {flag (state <s> ^superstate nil -^stop) --> (<s> ^flag on)}
    sp {stop (state <s> ^phase 1 ^seen-flag yes) --> (<s> ^stop yes)}
    sp {report (state <s> ^phase 1 ^stop yes -^seen-flag) --> (write |retracted|) (halt)}
    """
    _, r = run(make, text, 20)
    assert r.output == "retracted" and r.halted and r.decisions == 2
    assert r.impasses == [[2, 1, "no-change", "operator"]]


@pytest.mark.parametrize("name", sorted(p.name for p in AGENTS.glob("sub_*.soar")))
def test_substate_agents_run_to_their_end(make: Make, name: str) -> None:
    agent = make()
    agent.load_file(AGENTS / name)
    r = agent.run(200)
    assert r.stop_reason in ("halt", "max-decisions", "max-goal-depth")
    assert r.impasses, "every sub_* agent creates a substate"
