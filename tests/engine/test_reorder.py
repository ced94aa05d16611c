"""Join orders: Soar's reorderer, and the cache of orders by conjunction shape."""

from __future__ import annotations

import pytest

from adapt.engine import reorder
from adapt.engine.parse import parse_rules
from adapt.engine.production import Variable
from adapt.engine.reorder import join_order


def _conditions(text: str):  # type: ignore[no-untyped-def]
    p, = parse_rules(text).productions
    return p.conditions


def _fresh(elements, outer=(), hints=None):  # type: ignore[no-untyped-def]
    saved = dict(reorder._ORDERS)
    reorder._ORDERS.clear()
    try:
        return join_order(elements, outer, hints)
    finally:
        reorder._ORDERS.clear()
        reorder._ORDERS.update(saved)


JOIN = """sp {j (state <s> ^a <x> ^b <y>) (<x> ^v <v>) (<y> ^w <v>) --> (<x> ^p <y>)}"""


def test_written_order_kept_when_good() -> None:
    conds = _conditions("sp {t (state <s> ^item <x>) (<x> ^kind k) --> (<x> ^seen yes)}")
    assert _fresh(conds) == [0, 1]


def test_hints_change_the_order_and_the_cache_keeps_them_apart() -> None:
    conds = _conditions(JOIN)
    plain = join_order(conds)
    hinted = join_order(conds, multi_attributes={"a": 1000, "b": 1000})
    assert plain == _fresh(conds)
    assert hinted == _fresh(conds, hints={"a": 1000, "b": 1000})
    assert plain != hinted
    # asked again in either order, each gets its own
    assert join_order(conds) == plain
    assert join_order(conds, multi_attributes={"a": 1000, "b": 1000}) == hinted


def test_same_shape_other_constants_share_an_order() -> None:
    a = _conditions("sp {a (state <s> ^item <x>) (<x> ^kind k1 ^value 3) --> (<x> ^p 1)}")
    b = _conditions("sp {b (state <s> ^item <x>) (<x> ^kind k2 ^value 4) --> (<x> ^p 1)}")
    assert join_order(a) == join_order(b) == _fresh(b)


@pytest.mark.parametrize("text", [
    # an equality test inside a conjunctive test binds
    "sp {c (state <s> ^a <x>) (<x> ^v { <u> > 2 }) (<y> ^w <u>) (<s> ^b <y>) --> (halt)}",
    "sp {c (state <s> ^a <x>) (<x> ^v { <v> }) (<y> ^w <u>) (<s> ^b <y>) --> (halt)}",
    # negations: which variables they need
    "sp {n (state <s> ^a <x>) -(<x> ^v <z>) (<s> ^b <z>) --> (halt)}",
    "sp {n (state <s> ^a <x>) -(<x> ^v <q>) (<s> ^b <z>) --> (halt)}",
    "sp {m (state <s> ^a <x>) -{(<x> ^v <z>) (<z> ^w 1)} (<s> ^b <z>) --> (halt)}",
    # attribute variables, bound and unbound
    "sp {v (state <s> ^a <x> ^<at> <y>) (<x> ^<at> <z>) --> (halt)}",
    "sp {v (state <s> ^a <x> ^c <y>) (<x> ^<at> <z>) --> (halt)}",
])
def test_cached_order_equals_a_fresh_one_whatever_came_before(text: str) -> None:
    # every case is asked after all the others, so a key too coarse shows here
    cases = [_conditions(t) for t in (
        "sp {c (state <s> ^a <x>) (<x> ^v { <u> > 2 }) (<y> ^w <u>) (<s> ^b <y>) --> (halt)}",
        "sp {m (state <s> ^a <x>) -{(<x> ^v <z>) (<z> ^w 1)} (<s> ^b <z>) --> (halt)}",
        "sp {c (state <s> ^a <x>) (<x> ^v { <v> }) (<y> ^w <u>) (<s> ^b <y>) --> (halt)}",
        "sp {n (state <s> ^a <x>) -(<x> ^v <z>) (<s> ^b <z>) --> (halt)}",
        "sp {n (state <s> ^a <x>) -(<x> ^v <q>) (<s> ^b <z>) --> (halt)}",
        "sp {v (state <s> ^a <x> ^<at> <y>) (<x> ^<at> <z>) --> (halt)}",
        "sp {v (state <s> ^a <x> ^c <y>) (<x> ^<at> <z>) --> (halt)}",
    )]
    for conds in cases:
        join_order(conds)
        join_order(conds, [Variable("<y>")])
    conds = _conditions(text)
    assert join_order(conds) == _fresh(conds)
    assert join_order(conds, [Variable("<y>")]) == _fresh(conds, [Variable("<y>")])


def test_a_negations_variables_decide_a_tie() -> None:
    # ^a and ^b cost the same; the lookahead prefers the one after which the
    # negation can be tested
    on_z = _conditions("sp {g (state <s> ^a <x> ^b <z>) -(<z> ^v 1) --> (halt)}")
    on_x = _conditions("sp {g (state <s> ^a <x> ^b <z>) -(<x> ^v 1) --> (halt)}")
    assert join_order(on_z) == [1, 0]
    assert join_order(on_x) == [0, 1]
    assert join_order(on_z) == [1, 0]


def test_a_relational_test_alone_is_not_a_constant() -> None:
    relational = _conditions("sp {r (state <s> ^a <x>) (<x> ^w 3) (<x> ^v > 2) --> (halt)}")
    constant = _conditions("sp {r (state <s> ^a <x>) (<x> ^w 3) (<x> ^v 2) --> (halt)}")
    # ^v > 2 costs 8 (it binds nothing), ^w 3 costs 1; two constants tie at 1
    # and Soar takes the last written
    assert join_order(relational) == [0, 1, 2]
    assert join_order(constant) == [0, 2, 1]
    assert join_order(relational) == [0, 1, 2]


def test_outer_variables_are_part_of_the_key() -> None:
    # the conditions as a conjunctive negation's would be, with <y> bound outside
    conds = _conditions("sp {o (state <s> ^a <x> ^b <y>) (<y> ^w <x>) (<y> ^z <q>) --> (halt)}")
    inner = conds[2:] + conds[:2]
    assert join_order(inner, [Variable("<y>")]) == _fresh(inner, [Variable("<y>")])
    assert join_order(inner) == _fresh(inner)


def test_ties_go_to_the_latest_constant_then_the_last_written() -> None:
    """Soar's canonical order: among tied conditions the one whose constant
    attribute (then value) Soar's symbol table made last, then the last
    written; Soar's own symbols (``name``) come before the rules' constants."""
    first = _conditions("sp {t (state <s> ^x <o>) (<o> ^colour red ^shape box) --> (halt)}")
    second = _conditions("sp {t (state <s> ^x <o>) (<o> ^shape box ^colour red) --> (halt)}")
    # constants never seen: a tie, the last written first
    assert _fresh(first) == [0, 2, 1] and _fresh(second) == [0, 2, 1]
    constants = reorder.ConstantOrder()
    constants.add("colour")
    constants.add("shape")
    assert join_order(first, constants=constants) == [0, 2, 1]
    assert join_order(second, constants=constants) == [0, 1, 2]
    # Soar's own symbol ^name comes before any constant of the rules
    named = _conditions("sp {t (state <s> ^x <o>) (<o> ^colour red ^name go) --> (halt)}")
    assert join_order(named, constants=constants) == [0, 1, 2]
    # the same attribute: the value decides
    values = _conditions("sp {t (state <s> ^x <o>) (<o> ^colour blue ^colour red) --> (halt)}")
    constants.add("red")
    constants.add("blue")
    assert join_order(values, constants=constants) == [0, 1, 2]


def test_a_negation_wins_a_tie_of_cost_one() -> None:
    conds = _conditions("sp {t (state <s> ^x <o>) -(<o> ^done yes) (<o> ^size 3) --> (halt)}")
    # the order of positives only: the negation goes right after ^x anyway
    assert _fresh(conds) == [0, 2]


@pytest.mark.parametrize("shape", ["^a{i} <v{i}>", "^a{i} {i}", "^a <v{i}>"])
def test_two_thousand_conditions_on_one_identifier_are_ordered_without_lookahead(
        shape: str) -> None:
    """The lookahead is bounded (issue 21): 2,000 tied conditions on one
    identifier take the tie rule; the order is complete and deterministic."""
    text = " ".join(shape.format(i=i) for i in range(2000))
    conds = _conditions(f"sp {{big (state <s> {text}) --> (halt)}}")
    order = _fresh(conds)
    assert sorted(order) == list(range(2000))
    assert order == _fresh(conds)


@pytest.mark.parametrize("shape", ["^a{i} <v{i}>", "^a{i} {i}", "^a <v{i}>",
                                   "^a{i} <v{i}> ^b{i} <v{i}>"])
def test_the_reorderers_work_grows_linearly_with_the_conditions(
        shape: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 21: the lookahead grew as N^3 (a production of 800 conditions on
    one identifier took over 120 s to load).  Costs are computed a bounded
    number of times per condition, and lookahead steps stop at the budget."""
    counts = {"cost": 0, "lookahead": 0}
    cost, lookahead = reorder._cost, reorder._lookahead

    def counted_cost(*args, **kwargs):  # type: ignore[no-untyped-def]
        counts["cost"] += 1
        return cost(*args, **kwargs)

    def counted_lookahead(*args, **kwargs):  # type: ignore[no-untyped-def]
        counts["lookahead"] += 1
        return lookahead(*args, **kwargs)

    monkeypatch.setattr(reorder, "_cost", counted_cost)
    monkeypatch.setattr(reorder, "_lookahead", counted_lookahead)
    work = {}
    for n in (1000, 2000):
        text = " ".join(shape.format(i=i) for i in range(n))
        conds = _conditions(f"sp {{big (state <s> {text}) --> (halt)}}")
        counts.update(cost=0, lookahead=0)
        assert sorted(_fresh(conds)) == list(range(len(conds)))
        work[n] = dict(counts)
        assert counts["cost"] <= 5 * len(conds)
        assert counts["lookahead"] <= reorder.LOOKAHEAD_BUDGET
    assert work[2000]["cost"] <= 2.2 * work[1000]["cost"]
    assert work[2000]["lookahead"] <= work[1000]["lookahead"] + 1


def test_rule_files_loaded_one_after_another_share_the_symbol_table() -> None:
    """``join_orders`` of several rule files: the constants an earlier file made come
    first in the symbol table, and break the ties of a later file's productions as in one
    agent that loaded both (alone, the later file's own written order decides)."""
    from adapt.engine.joins import join_orders

    earlier = parse_rules("sp {a (state <s> ^colour red) --> (halt)}\n"
                          "sp {b (state <s> ^shape box) --> (halt)}")
    later = parse_rules("sp {t (state <s> ^x <o>) (<o> ^shape box ^colour red) --> (halt)}")
    assert join_orders(later) == [(later.productions[0], [0, 2, 1])]  # colour made last
    assert join_orders([earlier, later])[-1] == (later.productions[0], [0, 1, 2])  # shape
