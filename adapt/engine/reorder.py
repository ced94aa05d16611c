"""The order in which a conjunction's conditions are joined: Soar's reorderer.

A Rete joins a production's conditions one after the other; a condition
joined while its identifier is still unbound, or one with many values per
bound identifier, multiplies the partial matches.  Soar reorders every
production's conditions when it is loaded (``production_reorder.cpp``,
``reorder_simplified_conditions``); adapt does the same, with the same cost
estimates:

* a positive condition whose identifier is not bound yet costs
  ``MAX_COST`` (it would be a cross product) -- unless its value (or
  attribute) is a bound variable: adapt's joins hash every bound field, not
  only the identifier as Soar's do, so such a condition is a join too,
  estimated at 8 times the cost it would have with a bound identifier and an
  unbound value (Soar gives it ``MAX_COST``).  So it comes after the joins
  through bound identifiers that Soar would choose, unless a
  ``multi-attributes`` hint says those have many values:
  ``multi-attributes b 1000`` lets ``(<x> ^v <v>) (<y> ^w <v>) (<s> ^b <y>)``
  join on ``<v>``, in linear time, where Soar builds every ``(<x>, <y>)`` pair;
* otherwise its cost is the expected number of WMEs per bound identifier:
  the attribute's ``multi-attributes`` hint (1 when there is none) when the
  attribute is a constant or a bound variable, 8 when it is an unbound
  variable, times 8 more when the value is not a constant or bound
  variable (a relational test or a disjunction alone does not bind);
* while a *root* variable (the identifier of the state tests, which no
  other condition reaches) is unbound, it counts as bound for the cost and
  hints are not used, as in Soar;
* a negated condition or conjunctive negation costs 1 once every variable it
  shares with the conjunction's positive conditions is bound, else
  ``MAX_COST``.

Each step takes the cheapest condition.  Ties between costs above 1 are
broken by a one-step lookahead (the cheapest condition that could come next
if this one were taken); remaining ties keep the written order -- so a
production written in a good order keeps it.  (Soar breaks those last ties
by the hash values of the constants, which adapt does not have; the match
set never depends on the order, only the work does.)

:func:`join_order` gives the positive conditions' order;
:func:`adapt.engine.conditions.evaluation_order` then places each negation
right after the positive condition that binds the last of its variables.
Both matchers use the result.  ``adapt rules check --verbose`` prints it.

Examples
--------
>>> from adapt.engine.parse import parse_rules
>>> p, = parse_rules('''sp {done
...   (state <s> ^holds <h1> <h2>)
...   (<h1> ^disk <d1> ^on <peg>)
...   (<h2> ^disk <d2> ^on <peg>)
...   (<d1> ^name 1) (<d2> ^name 2)
... --> (halt)}''').productions
>>> [str(p.conditions[i].attr.term) + " " + str(p.conditions[i].value.term)
...  for i in join_order(p.conditions, multi_attributes={"holds": 8})]
... # doctest: +NORMALIZE_WHITESPACE
['holds <h1>', 'disk <d1>', 'name 1', 'on <peg>', 'holds <h2>', 'on <peg>', 'disk <d2>',
 'name 2']

Joined as written, every ``^holds`` would be joined before any test on the
holdings (adapt before it reordered: 11 holdings made 11^11 partial
matches); reordered, each holding is narrowed to its disk before the next
one is joined.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Final, Union

from adapt.engine.conditions import all_variables
from adapt.engine.production import (
    Condition,
    ConditionElement,
    ConjunctiveTest,
    EqualityTest,
    Test,
    Variable,
    condition_equality_variables,
)

__all__ = ["join_order", "MAX_COST", "BRANCHING"]

#: The cost of a condition whose identifier is not bound (Soar's MAX_COST).
MAX_COST: Final = 10_000_005
#: Soar's estimated branching factor of an unbound attribute or value.
BRANCHING: Final = 8

#: A field as the costs see it: a constant, a variable, or None (no
#: equality test: nothing that binds).
_Field = Union[Variable, str, int, float, None]


def _referent(test: Test | None) -> _Field:
    """The equality test's term of a field's test, or None when it has none."""
    if isinstance(test, EqualityTest):
        return test.term
    if isinstance(test, ConjunctiveTest):
        for t in test.tests:
            if isinstance(t, EqualityTest):
                return t.term
    return None


class _Element:
    """What the cost of one element depends on, computed once."""

    __slots__ = ("index", "positive", "ident", "attr", "value", "binds", "needs")

    def __init__(self, index: int, element: ConditionElement) -> None:
        self.index = index
        self.positive = isinstance(element, Condition) and not element.negated
        self.ident: _Field = None
        self.attr: _Field = None
        self.value: _Field = None
        self.binds: frozenset[Variable] = frozenset()
        self.needs: frozenset[Variable] = frozenset()
        if self.positive:
            assert isinstance(element, Condition)
            self.ident = element.id
            self.attr = _referent(element.attr)
            self.value = _referent(element.value)
            # every equality test binds: {<a> <b>} binds both
            self.binds = frozenset(condition_equality_variables(element))

    def shape(self, hints: Mapping[str, int]) -> tuple[object, ...]:
        """Everything :func:`join_order` reads of this element: the variables
        as they are, a constant attribute as its ``multi-attributes`` hint (the
        cost it is given), any other constant as 0 (a field that is covered)."""
        if not self.positive:
            return (False, self.needs)
        attr, value = self.attr, self.value
        if isinstance(attr, str):
            attr_shape: object = hints.get(attr, 1)
        elif attr is None or isinstance(attr, Variable):
            attr_shape = attr
        else:
            attr_shape = 1  # a number as attribute: no hint
        value_shape = value if value is None or isinstance(value, Variable) else 0
        return (True, self.ident, attr_shape, value_shape, self.binds)


#: Join orders already chosen, by the shape of the conjunction: the outer
#: variables and each element's :meth:`_Element.shape`.  Rule bases repeat a
#: few shapes with different constants (10,000 generated rules: 12% of the
#: load time); at most ``_ORDERS_MAX`` shapes are kept.
_ORDERS: dict[tuple[object, ...], list[int]] = {}
_ORDERS_MAX = 10_000


def _covered(field: _Field, bound: set[Variable] | frozenset[Variable],
             extra: frozenset[Variable]) -> bool:
    if field is None:
        return False
    if not isinstance(field, Variable):
        return True
    return field in bound or field in extra


def _cost(e: _Element, bound: set[Variable], roots: frozenset[Variable],
          hints: Mapping[str, int]) -> int:
    """Soar's ``cost_of_adding_condition``."""
    if not e.positive:
        return 1 if e.needs <= bound else MAX_COST
    attr = e.attr
    if not roots:  # Soar's common case: every root is bound
        if attr is not None and (not isinstance(attr, Variable) or attr in bound):
            cost = hints.get(attr, 1) if isinstance(attr, str) else 1
        else:
            cost = BRANCHING
    else:
        cost = 1 if _covered(attr, bound, roots) else BRANCHING
    if not _covered(e.ident, bound, roots):
        # adapt's joins hash every bound field: a bound value (or attribute)
        # connects the condition as a bound identifier would, the identifier
        # counting as an unbound value
        value = e.value
        if isinstance(value, Variable) and value in bound:
            return cost * BRANCHING * BRANCHING
        if isinstance(attr, Variable) and attr in bound:
            return BRANCHING * BRANCHING * BRANCHING
        return MAX_COST
    if not _covered(e.value, bound, roots):
        cost *= BRANCHING
    return cost


def _roots(elements: Sequence[_Element], outer: set[Variable]) -> frozenset[Variable]:
    """Identifier variables no positive condition's value reaches (Soar's roots)."""
    values = {e.value for e in elements if e.positive and isinstance(e.value, Variable)}
    return frozenset(e.ident for e in elements
                     if e.positive and isinstance(e.ident, Variable)
                     and e.ident not in values and e.ident not in outer)


def join_order(elements: Sequence[ConditionElement], outer: Iterable[Variable] = (),
               multi_attributes: Mapping[str, int] | None = None) -> list[int]:
    """Indexes of the positive conditions of a conjunction in join order.

    ``outer``: the variables bound outside the conjunction (for the
    conditions of a conjunctive negation); ``multi_attributes``: the
    ``multi-attributes`` hints (attribute -> expected number of values).
    """
    hints: Mapping[str, int] = multi_attributes if multi_attributes is not None else {}
    bound = set(outer)
    remaining = [_Element(i, el) for i, el in enumerate(elements)]
    scope = set(bound)
    for e in remaining:
        scope |= e.binds
    for e, el in zip(remaining, elements):
        if not e.positive:
            e.needs = frozenset(all_variables(el) & scope)
    key = (frozenset(bound), *(e.shape(hints) for e in remaining))
    known = _ORDERS.get(key)
    if known is not None:
        return list(known)
    roots = _roots(remaining, bound)
    order: list[int] = []
    while remaining:
        if roots and roots <= bound:
            roots = frozenset()
        costs = [_cost(e, bound, roots, hints) for e in remaining]
        least = min(costs)
        tied = [e for e, c in zip(remaining, costs) if c == least]
        chosen = tied[0]
        if len(tied) > 1:
            if least > 1:
                best = MAX_COST + 2
                for e in tied:
                    ahead = _lookahead(e, remaining, bound, roots, hints)
                    if ahead < best:
                        best, chosen = ahead, e
            else:  # a negation first, else the first written
                chosen = next((e for e in tied if not e.positive), tied[0])
        remaining.remove(chosen)
        if chosen.positive:
            order.append(chosen.index)
            bound |= chosen.binds
    if len(_ORDERS) < _ORDERS_MAX:
        _ORDERS[key] = list(order)
    return order


def _lookahead(chosen: _Element, remaining: Sequence[_Element], bound: set[Variable],
               roots: frozenset[Variable], hints: Mapping[str, int]) -> int:
    """The cost of the cheapest element that could follow ``chosen``
    (Soar's ``find_lowest_cost_lookahead``)."""
    after = bound | chosen.binds
    best = MAX_COST + 1
    for e in remaining:
        if e is chosen:
            continue
        cost = _cost(e, after, roots, hints)
        if cost < best:
            best = cost
            if cost <= 1:
                break
    return best
