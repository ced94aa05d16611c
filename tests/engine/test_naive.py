"""The brute-force matcher on hand-written examples of every test kind."""

from __future__ import annotations

import pytest

from adapt.engine.conditions import relation_holds
from adapt.engine.naive import NaiveMatcher
from adapt.engine.symbols import Float, Identifier
from adapt.engine.wme import WME
from adapt.errors import EngineError

from .strategies import EXAMPLES, S1, cond, make_wmes, prod, rel


@pytest.mark.parametrize("name,productions,rows,expected", EXAMPLES, ids=[e[0] for e in EXAMPLES])
def test_examples(name, productions, rows, expected) -> None:
    m = NaiveMatcher()
    for p in productions:
        m.add_production(p)
    for w in make_wmes(rows):
        m.add_wme(w)
    added, removed = m.take_changes()
    assert {x.key for x in added} == expected
    assert removed == []
    assert {x.key for x in m.matches()} == expected


def test_changes_are_diffs_and_transients_cancel() -> None:
    m = NaiveMatcher()
    m.add_production(prod("p", cond("<s>", "a", "<x>")))
    w1, w2 = WME(S1, "a", 1, False, 1), WME(S1, "a", 2, False, 2)
    m.add_wme(w1)
    m.add_wme(w2)
    m.remove_wme(w2)
    assert [x.key for x in m.take_changes()[0]] == [("p", (1,))]
    m.remove_wme(w1)
    m.add_wme(w1)
    assert m.take_changes() == ([], [])
    m.remove_wme(w1)
    assert [x.key for x in m.take_changes()[1]] == [("p", (1,))]


def test_removed_in_previous_order() -> None:
    m = NaiveMatcher()
    m.add_production(prod("p", cond("<s>", "a", "<x>")))
    ws = [WME(S1, "a", i, False, i) for i in (3, 1, 2)]
    for w in ws:
        m.add_wme(w)
    assert [x.key for x in m.take_changes()[0]] == [("p", (3,)), ("p", (1,)), ("p", (2,))]
    for w in ws:
        m.remove_wme(w)
    assert [x.key for x in m.take_changes()[1]] == [("p", (3,)), ("p", (1,)), ("p", (2,))]


def test_production_added_late_and_removed() -> None:
    m = NaiveMatcher()
    m.add_wme(WME(S1, "a", 1, False, 1))
    m.add_production(prod("p", cond("<s>", "a", "<x>")))
    assert [x.key for x in m.take_changes()[0]] == [("p", (1,))]
    m.remove_production("p")
    assert [x.key for x in m.take_changes()[1]] == [("p", (1,))]
    with pytest.raises(EngineError):
        m.remove_production("p")


def test_duplicate_production_and_unbound_relation_are_errors() -> None:
    m = NaiveMatcher()
    m.add_production(prod("p", cond("<s>", "a", "<x>")))
    with pytest.raises(EngineError, match="already"):
        m.add_production(prod("p", cond("<s>", "a", "<x>")))
    with pytest.raises(EngineError, match="<y>"):
        m.add_production(prod("q", cond("<s>", "a", rel("<", "<y>"))))
    # a variable local to one negation is not bound in another
    with pytest.raises(EngineError, match="<y>"):
        m.add_production(prod("r", cond("<s>", "a", "<x>"), cond("<s>", "b", "<y>", neg=True),
                              cond("<s>", "c", rel("<", "<y>"), neg=True)))


# Soar's compare_symbols: between types the tested value is "less"; identifiers
# by letter, then number (checked with soar-sml 9.6.5: agents/relations_soar_order.soar)
@pytest.mark.parametrize("relation,a,b,holds", [
    ("<", 1, 2, True), ("<", 2, Float(1.5), False), (">=", Float(2.0), 2, True),
    ("<=", "a", "b", True), ("<", "a", 1, True), (">", "a", 1, False), (">=", 1, "a", False),
    ("<", Identifier("A", 1), 5, True), (">", Identifier("O", 10), Identifier("O", 9), True),
    ("<", Identifier("O", 10), Identifier("S", 1), True),
    ("<>", 2, Float(2.0), True), ("=", 2, 2, True), ("<=>", Float(1.0), 2, False),
    ("<=>", "x", "y", True), ("<=>", Identifier("A", 1), Identifier("B", 2), True),
])
def test_relations(relation, a, b, holds) -> None:
    assert relation_holds(relation, a, b) is holds
