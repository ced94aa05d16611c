"""Justifications of substate results: grounds, negated conditions, support.

Every scenario's observable behaviour (writes, halting, operators) was first
measured in real Soar 9.6.5 with ``/work/shared/tools/soar_oracle.py``; the
differential agents ``tests/engine/agents/sub_just_*.soar`` cover the same
ground against Soar on every run.
"""

from __future__ import annotations

import pytest

from adapt.engine import Agent
from adapt.engine.events import Event
from adapt.engine.production import Condition, ConjunctiveNegation
from adapt.engine.results import Justification

# A state no-change substate below S1 makes (S1 ^go yes); operator block then
# runs APPLY (which may make the tested-for-absent structure) and ^done yes.
HEAD = """
sp {init*ready
   (state <s> ^superstate nil -^ready)
-->
   (<s> ^operator <o> + !)
   (<o> ^name init)}
sp {apply*init
   (state <s> ^operator.name init)
-->
   (<s> ^ready yes)}
sp {propose*block
   (state <s> ^superstate nil ^go yes -^done)
-->
   (<s> ^operator <o> +)
   (<o> ^name block)}
sp {report*kept
   (state <s> ^superstate nil ^done yes ^go yes)
-->
   (write |kept|)}
sp {report*retracted
   (state <s> ^superstate nil ^done yes -^go)
-->
   (write |retracted|)
   (halt)}
sp {propose*stop
   (state <s> ^superstate nil ^done yes ^go yes)
-->
   (<s> ^operator <o> + !)
   (<o> ^name stop)}
sp {apply*stop
   (state <s> ^operator.name stop)
-->
   (halt)}
"""


def run(text: str, n: int = 20) -> tuple[Agent, object, list[Justification]]:
    """Run ``text``; also return every justification made, in order."""
    agent = Agent()
    agent.load_text(text)
    made: list[Justification] = []
    agent.events.subscribe(Event.RESULT, lambda payload: made.append(payload[1]))
    return agent, agent.run(n), made


def output(agent: Agent) -> str:
    return "".join(agent.output) if isinstance(agent.output, list) else str(agent.output)


def scenario(substate_rules: str, apply: str) -> tuple[object, list[Justification]]:
    agent, report, made = run(HEAD + substate_rules + apply)
    return report, made


APPLY_BLOCKED = """
sp {apply*block
   (state <s> ^operator.name block)
-->
   (<s> ^blocked yes ^done yes)}
"""


def test_negated_superstate_test_is_in_the_justification_and_retracts_the_result() -> None:
    report, made = scenario("""
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
  -(<ss> ^blocked yes)
-->
   (<ss> ^go yes)}
""", APPLY_BLOCKED)
    (just,) = made
    assert just.support == "i" and len(just.negations) == 1
    element, _ = just.negations[0]
    assert isinstance(element, Condition) and element.negated
    # Soar: "kept" (same elaboration as the retraction), then "retracted"
    assert report.halted and report.decisions == 3  # type: ignore[attr-defined]
    assert [op[2] for op in report.operators] == ["init", "block"]  # type: ignore[attr-defined]


def test_negated_local_test_is_not_in_the_justification() -> None:
    report, made = scenario("""
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
  -(<s> ^blocked yes)
-->
   (<ss> ^go yes)}
""", APPLY_BLOCKED)
    (just,) = made
    assert just.negations == ()
    # the result stays: operator stop runs (Soar: decisions 4, "kept")
    assert [op[2] for op in report.operators] == ["init", "block", "stop"]  # type: ignore[attr-defined]


def test_negation_on_an_object_a_ground_links_to() -> None:
    report, made = scenario("""
sp {elab*thing
   (state <s> ^superstate nil)
-->
   (<s> ^thing <t>)}
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^thing <t>)
  -(<t> ^broken yes)
-->
   (<ss> ^go yes)}
""", """
sp {apply*block
   (state <s> ^operator.name block ^thing <t>)
-->
   (<t> ^broken yes) (<s> ^done yes)}
""")
    assert len(made[0].negations) == 1
    assert report.halted and report.decisions == 3  # type: ignore[attr-defined]


def test_negation_of_an_instantiation_behind_a_local_wme_is_included() -> None:
    report, made = scenario("""
sp {snc*local
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
  -(<ss> ^blocked yes)
-->
   (<s> ^can-go yes)}
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss> ^can-go yes)
-->
   (<ss> ^go yes)}
""", APPLY_BLOCKED)
    (just,) = made
    assert len(just.negations) == 1
    assert report.halted and report.decisions == 3  # type: ignore[attr-defined]


APPLY_RED_OBJECT = """
sp {apply*block
   (state <s> ^operator.name block)
-->
   (<s> ^obj <o> ^done yes) (<o> ^color red)}
"""


def test_connected_conjunctive_negation_is_included() -> None:
    report, made = scenario("""
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
  -{(<ss> ^obj <o>) (<o> ^color red)}
-->
   (<ss> ^go yes)}
""", APPLY_RED_OBJECT)
    (just,) = made
    assert [type(e) for e, _ in just.negations] == [ConjunctiveNegation]
    assert report.halted and report.decisions == 3  # type: ignore[attr-defined]


def test_conjunctive_negation_testing_the_substate_is_dropped() -> None:
    report, made = scenario("""
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
  -{(<ss> ^obj <o>) (<s> ^mark <o>)}
-->
   (<ss> ^go yes)}
""", APPLY_RED_OBJECT)
    assert made[0].negations == ()
    assert [op[2] for op in report.operators] == ["init", "block", "stop"]  # type: ignore[attr-defined]


TIE = """
sp {propose*init
   (state <s> ^superstate nil -^phase)
-->
   (<s> ^operator <o> + !)
   (<o> ^name init)}
sp {apply*init
   (state <s> ^operator.name init)
-->
   (<s> ^phase run)}
sp {propose*ab
   (state <s> ^superstate nil ^phase run)
-->
   (<s> ^operator <a> + <b> +)
   (<a> ^name a)
   (<b> ^name b)}
sp {tie*b-better
   (state <s> ^impasse tie ^superstate <ss> ^item <oa> ^item <ob>)
   (<oa> ^name a)
   (<ob> ^name b)
  -(<ss> ^veto b)
-->
   (<ss> ^operator <ob> > <oa>)}
sp {tie*a-best
   (state <s> ^impasse tie ^superstate <ss> ^item <oa>)
   (<oa> ^name a)
   (<ss> ^veto b)
-->
   (<ss> ^operator <oa> >)}
sp {apply*b
   (state <s> ^operator.name b -^veto b)
-->
   (<s> ^veto b)}
sp {apply*a
   (state <s> ^operator.name a)
-->
   (halt)}
"""


def test_operator_preference_result_retracts_and_the_tie_comes_back() -> None:
    agent, report, made = run(TIE)
    better, best = made
    assert isinstance(better, Justification) and better.support == "i"
    assert len(better.negations) == 1 and better.retracted
    # grounds: the acceptable preferences behind the two ^item WMEs, the names
    assert sum(1 for w in better.wmes if w.attr == "operator" and w.acceptable) == 2
    assert [sp.inst for _, sp in better.slot_prefs] == [better]
    assert best.negations == () and not best.retracted
    assert report.operators == [[1, 0, "init"], [3, 0, "b"], [5, 0, "a"]]  # type: ignore[attr-defined]
    assert report.impasses == [[2, 1, "tie", "operator"], [4, 1, "tie", "operator"]]  # type: ignore[attr-defined]


def test_o_supported_result_persists_although_a_negated_basis_appears() -> None:
    agent, report, made = run("""
sp {propose*work
   (state <s> ^superstate nil -^answer)
-->
   (<s> ^operator <o> +)
   (<o> ^name work)}
sp {onc*answer
   (state <s> ^impasse no-change ^attribute operator ^superstate <ss>)
   (<ss> ^operator <o>)
   (<o> ^name work)
  -(<ss> ^stop yes)
-->
   (<ss> ^answer 42)}
sp {propose*stop
   (state <s> ^superstate nil ^answer 42 -^stop)
-->
   (<s> ^operator <o> +)
   (<o> ^name stop)}
sp {apply*stop
   (state <s> ^operator.name stop)
-->
   (<s> ^stop yes)}
sp {done
   (state <s> ^superstate nil ^stop yes ^answer 42)
-->
   (halt)}
""")
    (just,) = made
    assert just.support == "o" and len(just.negations) == 1
    assert report.halted  # type: ignore[attr-defined]
    assert [op[2] for op in report.operators] == ["work", "stop"]  # type: ignore[attr-defined]


@pytest.mark.parametrize("negated", [True, False])
def test_justification_repr(negated: bool) -> None:
    _, _, made = run(HEAD + """
sp {snc*go
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
   (<ss> ^ready yes)
""" + ("  -(<ss> ^blocked yes)\n" if negated else "") + """-->
   (<ss> ^go yes)}
""" + APPLY_BLOCKED)
    text = repr(made[0])
    assert text.startswith("Justification(i, level 0") and f"{int(negated)} negated" in text


# -- results with no grounds (Soar builds no justification: "no conditions") --

NO_GROUNDS_VANISH = """
sp {snc*result
   (state <s> ^impasse no-change ^attribute state ^superstate <ss>)
-->
   (<ss> ^foo bar)}
sp {top*propose
   (state <s> ^superstate nil ^foo bar)
-->
   (<s> ^operator <o> +)
   (<o> ^name op)}
"""


def test_result_without_grounds_has_no_justification() -> None:
    agent, report, made = run(NO_GROUNDS_VANISH, 4)
    assert made and all(j is None for j in made)  # no justification is built
    # the result goes with the substate: OP is never selected, a new state
    # no-change impasse at level 1 comes every decision (as in Soar)
    assert report.operators == []  # type: ignore[attr-defined]
    assert [i[1:] for i in report.impasses] == [  # type: ignore[attr-defined]
        [1, "no-change", "state"]] * 4


def test_o_supported_result_without_grounds_goes_with_its_substate() -> None:
    agent, report, made = run("""
sp {snc*propose*make
   (state <s> ^impasse no-change ^attribute state -^made)
-->
   (<s> ^operator <o> +)
   (<o> ^name make)}
sp {snc*apply*make
   (state <s> ^operator.name make ^superstate <ss>)
-->
   (<ss> ^foo bar)
   (<s> ^made yes)}
""", 3)
    assert made == [None]
    k = agent.kernel
    key = (k.top.id, "foo", "bar", False)
    sub = k.top.lower
    assert sub is not None and key in k.preferences.osup and [e[0] for e in sub.ungrounded] == [key]
    k.remove_goal(sub)
    k.commit()
    assert key not in k.preferences.osup and k.wm.get(*key) is None


def test_i_supported_result_without_grounds_retracts_with_its_instantiation() -> None:
    _, report, made = run("""
sp {snc*elab*result
   (state <s> ^impasse no-change ^attribute state ^superstate <ss> -^flag)
-->
   (<ss> ^foo bar)}
sp {snc*propose*set
   (state <s> ^impasse no-change ^attribute state -^flag)
-->
   (<s> ^operator <o> +)
   (<o> ^name set)}
sp {snc*apply*set
   (state <s> ^operator.name set)
-->
   (<s> ^flag yes)}
sp {snc*gone
   (state <s> ^impasse no-change ^superstate <ss> ^flag yes)
   (<ss> -^foo)
-->
   (write |foo gone|)
   (halt)}
""")
    assert made == [None]
    assert report.halted and report.decisions == 2  # type: ignore[attr-defined]


def test_result_with_an_untraceable_local_basis_keeps_an_empty_justification() -> None:
    # The selected operator's proposal has retracted, so adapt cannot
    # backtrace it; the result keeps an (empty) justification as before.
    agent = Agent()
    agent.load_file("tests/engine/agents/sub_nested.soar")
    made: list[object] = []
    agent.events.subscribe(Event.RESULT, lambda payload: made.append(payload[1]))
    report = agent.run(10)
    assert report.halted and None not in made


def test_o_supported_operator_preference_result_stays_in_the_slot() -> None:
    text = open("tests/engine/agents/sub_just_osupport_operator_pref.soar").read()
    _, report, made = run(text, 6)
    (just,) = made
    assert just.support == "o" and just.slot_prefs
    assert not just.retracted  # its ground (S1 ^operator W) left; it stays
    assert [op[2] for op in report.operators] == ["w", "x"]  # type: ignore[attr-defined]
    assert report.halted  # type: ignore[attr-defined]
