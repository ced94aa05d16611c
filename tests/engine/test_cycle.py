"""The decision cycle on small agents; expected values measured in real Soar 9.6.5.

The tests run on both engines (``make``): the figures are Soar's, so the Soar
engine must give them too.
"""

from __future__ import annotations

from typing import Any, Callable

from adapt.engine import Agent

from .both_engines import values_of

Make = Callable[..., Any]

COUNTER = """
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose (state <s> ^count {<c> < 12}) --> (<s> ^operator <o> +) (<o> ^name count)}
sp {apply (state <s> ^operator.name count ^count <c>)
   --> (<s> ^count <c> -) (<s> ^count (+ <c> 1))}
sp {done (state <s> ^count 12) --> (write |done|) (halt)}
"""


def run(make: Make, text: str, n: int | None = None, **kw: object) -> tuple[Any, Any]:
    agent = make(**kw)
    agent.load_text(text)
    return agent, agent.run(n)


def test_counter_counts_like_soar(make: Make) -> None:
    agent, r = run(make, COUNTER)
    assert (r.halted, r.stop_reason, r.decisions, r.output) == (True, "halt", 13, "done")
    assert [o[2] for o in r.operators] == ["init"] + ["count"] * 12
    assert r.elaboration_cycles == 28 and r.production_firings == 27


def test_counter_counts_like_soar_with_the_naive_matcher() -> None:
    agent = Agent(matcher="naive")
    agent.load_text(COUNTER)
    r = agent.run()
    assert (r.halted, r.decisions, r.elaboration_cycles, r.production_firings) == (True, 13, 28, 27)


def test_halt_in_first_proposal_gives_zero_decisions(make: Make) -> None:
    _, r = run(make, "sp {h (state <s> ^superstate nil) --> (write |a|) (halt)}\n"
                     "sp {w (state <s> ^superstate nil) --> (write |b|)}")
    assert (r.halted, r.decisions, sorted(r.output)) == (True, 0, ["a", "b"])
    assert r.elaboration_cycles == 1


RUNN = """
sp {propose (state <s> ^superstate nil -^n 5) --> (<s> ^operator <o> +) (<o> ^name step)}
sp {apply0 (state <s> ^operator.name step -^n) --> (<s> ^n 1)}
sp {apply (state <s> ^operator <o> ^n <n>) (<o> ^name step) --> (<s> ^n <n> -) (<s> ^n (+ <n> 1))}
sp {w (state <s> ^n <n>) --> (write <n> | |)}
"""


def test_operator_stays_selected_and_write_rules_refire(make: Make) -> None:
    _, r = run(make, RUNN, 3)
    assert r.to_dict()["operators"] == [[1, 0, "step"]]
    assert r.impasses == [[2, 1, "no-change", "state"], [3, 2, "no-change", "state"]]
    assert r.output == "1 2 3 4 5 " and r.elaboration_cycles == 11


def test_run_n_stops_before_the_apply_phase_and_continues(make: Make) -> None:
    agent = make()
    agent.load_text(COUNTER)
    r = agent.run(2)
    assert (r.stop_reason, r.decisions, len(r.operators)) == ("max-decisions", 2, 2)
    assert values_of(agent, agent.top_state, "count") == ["0"]  # 2nd not applied yet
    r = agent.run(1)
    assert r.decisions == 3 and values_of(agent, agent.top_state, "count") == ["1"]
    r = agent.run()
    assert (r.halted, r.decisions) == (True, 13)
    assert agent.run().decisions == 13                                # halted: no more


def test_run_0_runs_one_decision_as_soar_does(make: Make) -> None:
    agent = make()
    agent.load_text(COUNTER)
    r = agent.run(0)
    assert (r.stop_reason, r.decisions) == ("max-decisions", 1)


def test_max_elaborations_warning_and_limit(make: Make) -> None:
    _, r = run(make, "sp {grow (state <s> ^superstate nil ^x <x>) --> (<s> ^x (+ <x> 1))}\n"
                     "sp {init (state <s> ^superstate nil) --> (<s> ^x 0)}", 3)
    assert r.elaboration_cycles == 500 and r.production_firings == 500
    assert r.messages[:2] == ["Warning: reached max-elaborations; proceeding to decide phase.",
                              "Warning: reached max-elaborations; proceeding to output phase."]


def test_i_support_retracts_and_o_support_persists(make: Make) -> None:
    text = """
    sp {p (state <s> ^superstate nil -^done) --> (<s> ^operator <o> +) (<o> ^name go)}
    sp {a (state <s> ^operator.name go) --> (<s> ^done yes) (<s> ^persist 1)}
    sp {e (state <s> ^superstate nil -^done) --> (<s> ^elab yes)}
    sp {h (state <s> ^done yes) --> (halt)}
    """
    agent, r = run(make, text)
    assert values_of(agent, agent.top_state, "done") == ["yes"]
    assert values_of(agent, agent.top_state, "persist") == ["1"]
    assert values_of(agent, agent.top_state, "elab") == []


def test_o_reject_removes_an_i_supported_wme(make: Make) -> None:
    text = """
    sp {init (state <s> ^superstate nil) --> (<s> ^count 0)}
    sp {propose (state <s> ^count {<c> < 3}) --> (<s> ^operator <o> +) (<o> ^name c ^v <c>)}
    sp {apply (state <s> ^operator <o> ^count <c>) (<o> ^name c ^v <c>)
       --> (<s> ^count <c> -) (<s> ^count (+ <c> 1))}
    sp {done (state <s> ^count 3) --> (write |three|) (halt)}
    """
    _, r = run(make, text)
    assert (r.decisions, r.output, r.elaboration_cycles) == (3, "three", 8)


def test_i_reject_oscillates_like_soar(make: Make) -> None:
    text = """
    sp {mk (state <s> ^superstate nil) --> (<s> ^a 1)}
    sp {rej (state <s> ^a 1) --> (<s> ^a 1 -)}
    """
    _, r = run(make, text, 1)
    assert r.elaboration_cycles == 100 and r.impasses == [[1, 1, "no-change", "state"]]


def test_retention_case_a_and_case_b(make: Make) -> None:
    # (a) the acceptable preference retracts: the operator goes at once;
    # (b) a better newcomer: the operator goes at the next consistency check.
    text = """
    sp {prop-one (state <s> ^superstate nil -^a) --> (<s> ^operator <o> +) (<o> ^name one)}
    sp {app-one (state <s> ^operator.name one) --> (<s> ^a 1) (<s> ^trigger t)}
    sp {prop-two (state <s> ^trigger t -^b) --> (<s> ^operator <o> + >) (<o> ^name two)}
    sp {app-two (state <s> ^operator.name two) --> (<s> ^b 1)}
    sp {h (state <s> ^b 1) --> (halt)}
    """
    _, r = run(make, text)
    assert r.operators == [[1, 0, "one"], [2, 0, "two"]] and r.decisions == 2
