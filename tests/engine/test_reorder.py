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
    relational = _conditions("sp {r (state <s> ^a <x>) (<x> ^v > 2) (<x> ^w 3) --> (halt)}")
    constant = _conditions("sp {r (state <s> ^a <x>) (<x> ^v 2) (<x> ^w 3) --> (halt)}")
    assert join_order(relational) == [0, 2, 1]
    assert join_order(constant) == [0, 1, 2]
    assert join_order(relational) == [0, 2, 1]


def test_outer_variables_are_part_of_the_key() -> None:
    # the conditions as a conjunctive negation's would be, with <y> bound outside
    conds = _conditions("sp {o (state <s> ^a <x> ^b <y>) (<y> ^w <x>) (<y> ^z <q>) --> (halt)}")
    inner = conds[2:] + conds[:2]
    assert join_order(inner, [Variable("<y>")]) == _fresh(inner, [Variable("<y>")])
    assert join_order(inner) == _fresh(inner)
