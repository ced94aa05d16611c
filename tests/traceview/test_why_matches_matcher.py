"""The trace tools' answer to "does this rule match?" is the matchers' answer.

``adapt trace why --rule`` (:func:`adapt.traceview.conditions.first_failure`
and :func:`~adapt.traceview.conditions.matches`) must say a rule matches
exactly when the brute-force matcher and the Rete have a match, and list the
same instantiations.  Checked on random productions (negations anywhere,
relational tests on variables bound later, conjunctive negations) and random
working memories, and on the case that used to disagree.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.cli import main
from adapt.engine.joins import join_orders
from adapt.engine.naive import NaiveMatcher
from adapt.engine.parse import RuleFile
from adapt.engine.production import Condition, EqualityTest, Production, RelationalTest, Variable
from adapt.engine.rete import Rete
from adapt.engine.symbols import Identifier
from adapt.engine.wme import WME
from adapt.traceview.conditions import first_failure, matches

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "engine"))
from strategies import productions, wme_fields  # noqa: E402


def _key(bindings: dict) -> tuple:
    return tuple(sorted((v.name, type(s).__name__, repr(s)) for v, s in bindings.items()))


@settings(max_examples=300, deadline=None)
@given(productions(), st.lists(wme_fields, max_size=12))
def test_trace_tools_agree_with_both_matchers(production, rows) -> None:
    wmes = [WME(*row, tt) for tt, row in enumerate(dict.fromkeys(rows), start=1)]
    answers = []
    for matcher in (NaiveMatcher(), Rete()):
        matcher.add_production(production)
        for w in wmes:
            matcher.add_wme(w)
        answers.append(Counter(_key(m.bindings()) for m in matcher.matches()))
    naive, rete = answers
    assert naive == rete
    failure = first_failure(production, wmes)
    assert (failure is None) == bool(naive)
    (_, order), = join_orders(RuleFile((production,)))
    assert Counter(_key(b) for b in matches(production.conditions, wmes, order=order)) == naive


def test_the_join_orders_last_tie_is_broken_by_the_matchers_constants() -> None:
    """``(<s> ^a) (<s>) (<x> ^{< <s>} x)``: the matchers, whose symbol table holds ``a`` and
    ``x``, join ``(<s> ^a)`` first and read ``a < S1`` as written; without those constants
    the tie fell the other way, ``(<x> ...)`` first, and the relation was checked turned
    round (``S1 > a``), which between a string and an identifier reads otherwise."""
    s, x = Variable("<s>"), Variable("<x>")
    production = Production("p", (Condition(s, EqualityTest("a"), None), Condition(s, None, None),
                                  Condition(x, RelationalTest("<", s), EqualityTest("x"))), ())
    s1 = Identifier("S", 1)
    wmes = [WME(s1, "a", s1, False, 1), WME(s1, "a", "x", False, 2)]
    found = []
    for matcher in (NaiveMatcher(), Rete()):
        matcher.add_production(production)
        for w in wmes:
            matcher.add_wme(w)
        found.append(len(list(matcher.matches())))
    assert found == [4, 4]
    assert first_failure(production, wmes) is None
    (_, order), = join_orders(RuleFile((production,)))
    assert len(list(matches(production.conditions, wmes, order=order))) == 4


def test_relation_on_a_later_variable(tmp_path, capsys) -> None:
    """``(state <s> ^a {<x> > <y>}) (<s> ^b <y>)`` with ``^a 1 ^b 5`` does not match."""
    rules = tmp_path / "r.soar"
    rules.write_text("""
sp {propose (state <s> ^superstate nil -^a) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply (state <s> ^operator.name init) --> (<s> ^a 1 ^b 5)}
sp {r (state <s> ^a {<x> > <y>}) (<s> ^b <y>) --> (write hi)}
""")
    trace = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(rules), "--max-decisions", "3", "--trace", str(trace)]) == 3  # the decision limit
    capsys.readouterr()
    assert main(["trace", "why", str(trace), "--rule", "r", "--at", "3"]) == 0
    out = capsys.readouterr().out
    assert "it never fired up to here" in out
    assert "condition 2 has no match" in out and "(<s> ^b <y>)" in out
    assert "1 > <y>" in out
    assert "all its conditions match" not in out


def test_negation_before_its_binding_condition(tmp_path) -> None:
    """A negated condition written before the condition that binds its variable."""
    from adapt.engine.parse import parse_rules

    p, = parse_rules("sp {r (state <s> -^x <v>) (<s> ^y <v>) --> (write hi)}").productions
    s1 = Identifier("S", 1, goal=True)
    base = [WME(s1, "type", "state", False, 1), WME(s1, "y", 2, False, 2)]
    assert first_failure(p, base + [WME(s1, "x", 3, False, 3)]) is None
    failure = first_failure(p, base + [WME(s1, "x", 2, False, 3)])
    assert failure is not None and failure.index == 1 and failure.condition.negated
    assert [w.timetag for w in failure.alone] == [3]


def test_a_relation_between_types_waiting_for_a_later_identifier() -> None:
    """``(<s> ^{a < <x>}) (<x> ^{a <> x})`` on ``(S1 ^a S1)``: the trace tools once joined in
    source order and read the test differently from the matchers (found by the property
    above).  ``a`` is a constant, so Soar puts the test back where ``<x>`` is bound, turned
    round: ``S1 > a``, which does not hold (a value of another type is less) -- checked in
    the Soar kernel, which fires the rule with ``{a > <x>}`` and not with ``{a < <x>}``.
    Both matchers and the trace tools agree."""
    from adapt.engine.production import (
        Condition,
        ConjunctiveTest,
        EqualityTest,
        Production,
        RelationalTest,
        Variable,
    )

    s, x = Variable("<s>"), Variable("<x>")
    production = Production("p", (
        Condition(s, ConjunctiveTest((EqualityTest("a"), RelationalTest("<", x))), None),
        Condition(x, ConjunctiveTest((EqualityTest("a"), RelationalTest("<>", "x"))), None)),
        ())
    s1 = Identifier("S", 1)
    wmes = [WME(s1, "a", s1, False, 1)]
    rete = Rete()
    rete.add_production(production)
    rete.add_wme(wmes[0])
    assert list(rete.matches()) == []
    failure = first_failure(production, wmes)
    assert failure is not None and failure.index == 1
    assert list(matches(production.conditions, wmes)) == []


def test_a_relation_on_a_variable_bound_later_in_a_conjunctive_negation() -> None:
    """``-{(<s> ^{a < <x>}) (<s> ^b <x>)} (<s> ^a)`` over ``(S1 ^a S1) (S1 ^b S1)`` (found by
    the property above): the Rete joined the negation's conditions in the reorderer's order,
    the brute-force matcher in the written one, and each read ``a < <x>`` by its own order.
    Soar reads it turned round (``S1 > a``: ``a`` is a constant, the test goes back where
    ``<x>`` is bound), so the negation has no match and the rule matches, in both."""
    from adapt.engine.production import ConjunctiveNegation, ConjunctiveTest
    from adapt.engine.symbols import IdentifierFactory

    s, x = Variable("<s>"), Variable("<x>")
    ncc = ConjunctiveNegation((
        Condition(s, ConjunctiveTest((EqualityTest("a"), RelationalTest("<", x))), None),
        Condition(s, EqualityTest("b"), EqualityTest(x))))
    production = Production("p", (ncc, Condition(s, EqualityTest("a"), None)), ())
    s1 = IdentifierFactory().new("S")
    counts = []
    for matcher in (NaiveMatcher(), Rete()):
        matcher.add_production(production)
        for tt, (attr, value) in enumerate((("a", s1), ("b", s1)), start=1):
            matcher.add_wme(WME(s1, attr, value, False, tt))
        counts.append(len(list(matcher.matches())))
    assert counts == [1, 1]
