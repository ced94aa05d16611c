"""From conditions to node specifications: ordering and test placement.

:func:`order_elements` chooses the order in which a conjunction's condition
elements become nodes: positive conditions as Soar's reorderer orders them
(:mod:`adapt.engine.reorder`: cheapest join first, by Soar's cost estimates
and the agent's ``multi-attributes`` hints), and each negated condition or
conjunctive negation right after the positive condition that binds the last
of the variables it shares with the conjunction's positive conditions.

:func:`compile_condition` sorts one condition's tests into

* the alpha key (constant equality tests on the attribute and the value,
  and ``acceptable``),
* alpha tests (the goal test of ``(state <s> ...)``, relations and
  disjunctions against constants, a variable met twice in the condition),
* join equality tests (variables bound at an earlier level) -- the hash key,
* join tests (relations against variables bound at an earlier level),
* new bindings, and *deferred* relations: a relation against a variable that
  a later positive condition binds, checked at that condition's join.

A relational test is read as written (``<y> < <x>``) or turned round
(``<x> > <y>``) as Soar's reorderer puts it back
(:func:`adapt.engine.conditions.turned_round`); between values of different
types the two readings differ.

Examples
--------
>>> from adapt.engine.production import Condition, EqualityTest, RelationalTest, Variable
>>> s, x = Variable("<s>"), Variable("<x>")
>>> c = Condition(s, EqualityTest("count"), RelationalTest(">", x))
>>> spec = compile_condition(c, {s: (0, 0), x: (0, 2)})
>>> spec.alpha_key, spec.token_fields, spec.wme_fields, spec.tests
(('count', ANY, False), ((0, 0),), (0,), (('>', -1, 2, 0, 2),))
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Sequence

from adapt.engine.conditions import REVERSED, evaluation_order
from adapt.engine.production import (
    FIELD_ATTR,
    FIELD_ID,
    FIELD_VALUE,
    Condition,
    ConditionElement,
    DisjunctionTest,
    EqualityTest,
    Term,
    Variable,
    simple_tests,
)
from adapt.engine.reorder import ConstantOrder, join_order
from adapt.engine.rete.alpha import ANY, GOAL_TEST, AlphaKey, AlphaTest
from adapt.engine.rete.join import JoinTest

__all__ = ["ConditionSpec", "compile_condition", "order_elements", "is_positive",
           "relation_test"]

#: Where a variable is bound: (token level, WME field).
Site = tuple[int, int]


@dataclass(frozen=True, slots=True)
class ConditionSpec:
    """One condition's tests, sorted by where the network checks them."""

    alpha_key: AlphaKey
    alpha_tests: tuple[AlphaTest, ...]
    token_fields: tuple[Site, ...]
    wme_fields: tuple[int, ...]
    tests: tuple[JoinTest, ...]
    binds: dict[Variable, int]
    #: ``(relation, field, variable, turned)`` of each relation waiting for a later binding
    deferred: tuple[tuple[str, int, Variable, bool], ...]


def relation_test(relation: str, own: Site, other: Site, turned: bool) -> JoinTest:
    """The join test of ``own relation other`` -- ``own`` the tested field's site, ``other``
    the variable's (level ``-1``: the new WME) -- as written, or turned round as Soar reads
    it (:func:`adapt.engine.conditions.turned_round`): ``other`` with the relation reversed.

    >>> relation_test("<", (-1, 2), (0, 2), False), relation_test("<", (-1, 2), (0, 2), True)
    (('<', -1, 2, 0, 2), ('>', 0, 2, -1, 2))
    """
    if turned:
        return (REVERSED[relation], other[0], other[1], own[0], own[1])
    return (relation, own[0], own[1], other[0], other[1])


def is_positive(element: ConditionElement) -> bool:
    """True for a non-negated :class:`Condition`."""
    return isinstance(element, Condition) and not element.negated


def compile_condition(cond: Condition, bound: dict[Variable, Site],
                      turned: frozenset[tuple[int, int]] = frozenset()) -> ConditionSpec:
    """Sort the tests of ``cond`` given the variables bound above it; ``turned``
    holds the ``(field, position)`` of its relational tests read turned round."""
    local: dict[Variable, int] = {}
    keys: list[object] = [ANY, ANY, ANY]
    alpha: list[AlphaTest] = []
    token_fields: list[Site] = []
    wme_fields: list[int] = []
    tests: list[JoinTest] = []
    relations: list[tuple[str, int, Term, bool]] = []
    if cond.goal:
        alpha.append(GOAL_TEST)
    for field, test in ((FIELD_ID, EqualityTest(cond.id)), (FIELD_ATTR, cond.attr),
                        (FIELD_VALUE, cond.value)):
        for k, t in enumerate(simple_tests(test)):
            if isinstance(t, EqualityTest):
                term = t.term
                if isinstance(term, Variable):
                    if term in bound:
                        token_fields.append(bound[term])
                        wme_fields.append(field)
                    elif term in local:
                        alpha.append(("=", field, False, local[term]))
                    else:
                        local[term] = field
                elif keys[field] is ANY and field != FIELD_ID:
                    keys[field] = term
                else:
                    alpha.append(("=", field, True, term))
            elif isinstance(t, DisjunctionTest):
                alpha.append(("in", field, True, t.values))
            else:
                relations.append((t.relation, field, t.term, (field, k) in turned))
    deferred: list[tuple[str, int, Variable, bool]] = []
    for relation, field, term, turn in relations:
        if not isinstance(term, Variable):
            alpha.append((relation, field, True, term))
        elif term in bound:
            tests.append(relation_test(relation, (-1, field), bound[term], turn))
        elif term in local:
            alpha.append((REVERSED[relation], local[term], False, field) if turn
                         else (relation, field, False, local[term]))
        else:
            deferred.append((relation, field, term, turn))
    return ConditionSpec(
        (keys[FIELD_ATTR], keys[FIELD_VALUE], cond.acceptable),
        tuple(alpha),
        tuple(token_fields),
        tuple(wme_fields),
        tuple(tests),
        local,
        tuple(deferred),
    )


def order_elements(elements: Sequence[ConditionElement], outer: set[Variable],
                   multi_attributes: Mapping[str, int] | None = None,
                   constants: ConstantOrder | None = None) -> list[int]:
    """Indexes of ``elements`` in the order their nodes are built: the positive
    conditions as Soar's reorderer orders them (:func:`adapt.engine.reorder.join_order`,
    with the ``multi-attributes`` hints), each negation after the positive
    condition that binds the last of its variables; ``outer`` are the
    variables bound above."""
    return evaluation_order(elements, outer,
                            join_order(elements, outer, multi_attributes, constants))
