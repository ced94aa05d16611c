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
  unbound value, plus one so that a tie goes to a condition Soar could
  choose (Soar gives it ``MAX_COST``).  So it comes after the joins
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

Each step takes the cheapest condition, breaking ties as Soar does.  Among
conditions of cost 1, a negation first (the last written); otherwise the
one whose constant attribute, then constant value, comes *latest* in Soar's
symbol table (:class:`ConstantOrder`: Soar's own symbols first, then every
constant in the order the rules were read; a variable, relational test or
disjunction counts as earliest), and of those the last written.  Among
conditions of a higher cost, the one after which the cheapest condition is
cheapest (a one-step lookahead), then the same rule.

The lookahead is bounded: a step whose tied conditions times remaining
conditions exceed :data:`LOOKAHEAD_BUDGET` skips it and takes the tie rule
alone (a greedy order).  Soar has no such bound, and no agent of Soar's
repositories comes near it (their largest conjunctions have a few dozen
conditions); it keeps a production with thousands of conditions on one
identifier loadable (it took minutes).  Costs are kept per condition and
recomputed only for the conditions that mention a variable just bound, so a
step costs about what its tied conditions cost, not the whole conjunction.

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
['holds <h2>', 'disk <d2>', 'name 2', 'on <peg>', 'holds <h1>', 'on <peg>', 'disk <d1>',
 'name 1']

Joined as written, every ``^holds`` would be joined before any test on the
holdings (adapt before it reordered: 11 holdings made 11^11 partial
matches); reordered, each holding is narrowed to its disk before the next
one is joined.  (``^holds <h2>`` comes first because, as in Soar, the last
written of two tied conditions wins.)
"""

from __future__ import annotations

import heapq
from collections.abc import Iterable, Mapping, Sequence
from typing import Final, Union

from adapt.engine.conditions import all_variables
from adapt.engine.production import (
    Action,
    CallAction,
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    ConjunctiveTest,
    DisjunctionTest,
    EqualityTest,
    FunctionCall,
    MakeAction,
    Production,
    RelationalTest,
    RhsValue,
    Test,
    Variable,
    condition_equality_variables,
    simple_tests,
)

__all__ = ["join_order", "ConstantOrder", "MAX_COST", "BRANCHING", "LOOKAHEAD_BUDGET",
           "SOAR_SYMBOLS"]

#: The cost of a condition whose identifier is not bound (Soar's MAX_COST).
MAX_COST: Final = 10_000_005
#: Soar's estimated branching factor of an unbound attribute or value.
BRANCHING: Final = 8
#: The most cost evaluations one step's lookahead may make (tied conditions
#: times remaining conditions); above it the step takes the tie rule alone.
LOOKAHEAD_BUDGET: Final = 4096

#: The constants Soar's symbol table holds before any rule is read, in the
#: order it makes them (its predefined symbols, ``symbol_manager.cpp``, then
#: the names of its RHS functions): they come before every constant of the
#: rules in :class:`ConstantOrder`.
SOAR_SYMBOLS: Final = tuple("""
@ problem-space state operator superstate io object attribute impasse choices none
constraint-failure no-change multiple item-count non-numeric-count constant conflict tie item
non-numeric quiescence t nil type goal name input-link output-link reward-link reward value
epmem command result retrieved status match-score cue-size normalized-match-score
match-cardinality memory-id present-id no-memory graph-match mapping node cue success failure
bad-cmd retrieve next previous query neg-query before after prohibit yes no smem
depth-retrieved activation depth store-new link-to-new-ltm link-to-ltm store math-query less
greater less-or-equal greater-or-equal max min count dont-learn force-learn halt
link-stm-to-ltm wait write trace log capitalize-symbol crlf dc make-constant-symbol strlen
timestamp trim string accept deep-copy ifeq from-st-xml + * - / div size sum product mod
set-count set-sum set-multiply set-min set-max set-range set-mean set-stdev sin cos atan2 sqrt
abs int float round-off-heading round-off compute-heading compute-range predict-x predict-y
compute-closest-intercept compute-dice-probability rand-int rand-float
""".split())

#: A field as the costs see it: a constant, a variable, or None (no
#: equality test: nothing that binds).
_Field = Union[Variable, str, int, float, None]


class ConstantOrder:
    """The order of constants in Soar's symbol table, which breaks its
    reorderer's last ties (Soar compares the symbols' hash ids, handed out in
    the order the symbols are made).

    Soar's own symbols come first (:data:`SOAR_SYMBOLS`); each production's
    constants are added, in the order they are written, when it is loaded.
    ``2`` and ``2.0`` are different constants.

    Examples
    --------
    >>> order = ConstantOrder()
    >>> order.rank("name") < order.rank("count"), order.rank("zebra")
    (True, 0)
    >>> order.add("zebra"); order.rank("zebra") > order.rank("count")
    True
    """

    __slots__ = ("_ranks",)

    def __init__(self) -> None:
        self._ranks: dict[tuple[type, object], int] = {}
        for name in SOAR_SYMBOLS:
            self.add(name)

    def add(self, constant: object) -> None:
        """Give ``constant`` the next rank, unless it has one."""
        key = (type(constant), constant)
        if key not in self._ranks:
            self._ranks[key] = len(self._ranks) + 1

    def rank(self, constant: object) -> int:
        """The constant's place (1, 2, ...); 0 for one never added."""
        return self._ranks.get((type(constant), constant), 0)

    def add_production(self, production: Production) -> None:
        """Add the constants of ``production`` in the order they are written
        (its name is a symbol too)."""
        self.add(production.name)
        for element in production.conditions:
            self._add_element(element)
        for action in production.actions:
            self._add_action(action)

    def _add_element(self, element: ConditionElement) -> None:
        if isinstance(element, ConjunctiveNegation):
            for e in element.conditions:
                self._add_element(e)
            return
        self._add_test(element.attr)
        self._add_test(element.value)

    def _add_test(self, test: Test | None) -> None:
        if test is None:
            return
        if isinstance(test, ConjunctiveTest):
            for t in test.tests:
                self._add_test(t)
        elif isinstance(test, DisjunctionTest):
            for v in test.values:
                self.add(v)
        elif isinstance(test, (EqualityTest, RelationalTest)):
            if not isinstance(test.term, Variable):
                self.add(test.term)

    def _add_action(self, action: Action) -> None:
        if isinstance(action, MakeAction):
            for value in (action.attr, action.value, action.referent):
                self._add_rhs(value)
        elif isinstance(action, CallAction):
            self._add_rhs(action.call)

    def _add_rhs(self, value: RhsValue | None) -> None:
        if value is None or isinstance(value, Variable):
            return
        if isinstance(value, FunctionCall):
            self.add(value.name)
            for arg in value.args:
                self._add_rhs(arg)
            return
        self.add(value)


def _referent(test: Test | None) -> _Field:
    """The equality test's term of a field's test, or None when it has none."""
    if isinstance(test, EqualityTest):
        return test.term
    if isinstance(test, ConjunctiveTest):
        for t in test.tests:
            if isinstance(t, EqualityTest):
                return t.term
    return None


def _constant(test: Test | None) -> object:
    """The constant of a constant equality test (Soar's canonical test), else
    None.  Soar orders the conditions with their other tests lifted out
    (``simplify_test``), so ``{a > <x>}`` counts as ``a``; a conjunction of two
    equality tests does not count."""
    equalities = [t for t in simple_tests(test) if isinstance(t, EqualityTest)]
    if len(equalities) == 1 and not isinstance(equalities[0].term, Variable):
        return equalities[0].term
    return None


class _Element:
    """What the cost of one element depends on, computed once."""

    __slots__ = ("index", "positive", "goal", "ident", "attr", "value", "binds", "needs",
                 "tie", "cost", "mentions")

    def __init__(self, index: int, element: ConditionElement) -> None:
        self.index = index
        self.positive = isinstance(element, Condition) and not element.negated
        #: a positive condition with the goal test of ``(state <s> ...)``
        self.goal = self.positive and element.goal  # type: ignore[union-attr]
        self.ident: _Field = None
        self.attr: _Field = None
        self.value: _Field = None
        self.binds: frozenset[Variable] = frozenset()
        self.needs: frozenset[Variable] = frozenset()
        #: the tie rule's key, smallest preferred (set by join_order)
        self.tie: tuple[int, int, int, int] = (0, 0, 0, 0)
        self.cost = MAX_COST
        #: the variables whose binding may change the cost
        self.mentions: frozenset[Variable] = frozenset()
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
        cost it is given), any other constant as 0 (a field that is covered),
        and the tie key's ranks (made dense by the caller)."""
        if not self.positive:
            return (False, self.needs, self.tie[0])
        attr, value = self.attr, self.value
        if isinstance(attr, str):
            attr_shape: object = hints.get(attr, 1)
        elif attr is None or isinstance(attr, Variable):
            attr_shape = attr
        else:
            attr_shape = 1  # a number as attribute: no hint
        value_shape = value if value is None or isinstance(value, Variable) else 0
        return (True, self.goal, self.ident, attr_shape, value_shape, self.binds, self.tie[1],
                self.tie[2])


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
        # counting as an unbound value -- one more, so that a tie goes to a
        # condition Soar could choose (Soar gives this one MAX_COST)
        value = e.value
        if isinstance(value, Variable) and value in bound:
            return cost * BRANCHING * BRANCHING + 1
        if isinstance(attr, Variable) and attr in bound:
            return BRANCHING * BRANCHING * BRANCHING + 1
        return MAX_COST
    if not _covered(e.value, bound, roots):
        cost *= BRANCHING
    return cost


def _roots(elements: Sequence[_Element], outer: set[Variable]) -> frozenset[Variable]:
    """Identifier variables no positive condition's value reaches (Soar's roots);
    when there is none in a production's conditions (``outer`` empty: not a
    conjunctive negation's), the first state test's identifier, as in Soar's
    ``reorder_lhs``."""
    values = {e.value for e in elements if e.positive and isinstance(e.value, Variable)}
    roots = frozenset(e.ident for e in elements
                      if e.positive and isinstance(e.ident, Variable)
                      and e.ident not in values and e.ident not in outer)
    if roots or outer:
        return roots
    first = next((e.ident for e in elements if e.goal and isinstance(e.ident, Variable)), None)
    return frozenset() if first is None else frozenset((first,))


def _dense(ranks: Iterable[int]) -> dict[int, int]:
    """Each rank's place among the distinct non-zero ranks (0 stays 0)."""
    return {r: k for k, r in enumerate(sorted({r for r in ranks if r}), start=1)} | {0: 0}


def join_order(elements: Sequence[ConditionElement], outer: Iterable[Variable] = (),
               multi_attributes: Mapping[str, int] | None = None,
               constants: ConstantOrder | None = None) -> list[int]:
    """Indexes of the positive conditions of a conjunction in join order.

    ``outer``: the variables bound outside the conjunction (for the
    conditions of a conjunctive negation); ``multi_attributes``: the
    ``multi-attributes`` hints (attribute -> expected number of values);
    ``constants``: the order of constants that breaks the last ties (Soar's
    symbol table; None: Soar's own symbols only).
    """
    hints: Mapping[str, int] = multi_attributes if multi_attributes is not None else {}
    order_of = constants if constants is not None else _SOAR_ONLY
    bound = set(outer)
    remaining = [_Element(i, el) for i, el in enumerate(elements)]
    scope = set(bound)
    for e in remaining:
        scope |= e.binds
    attr_ranks: list[int] = []
    value_ranks: list[int] = []
    for e, el in zip(remaining, elements):
        if not e.positive:
            e.needs = frozenset(all_variables(el) & scope)
            attr_ranks.append(0)
            value_ranks.append(0)
        else:
            assert isinstance(el, Condition)
            a, v = _constant(el.attr), _constant(el.value)
            attr_ranks.append(order_of.rank(a) if a is not None else 0)
            value_ranks.append(order_of.rank(v) if v is not None else 0)
    dense_a, dense_v = _dense(attr_ranks), _dense(value_ranks)
    for e, a, v in zip(remaining, attr_ranks, value_ranks):
        # smallest preferred: a negation, then the latest attribute, the
        # latest value, the last written (Soar's canonical order)
        e.tie = (1 if e.positive else 0, -dense_a[a], -dense_v[v], -e.index)
    key = (frozenset(bound), *(e.shape(hints) for e in remaining))
    known = _ORDERS.get(key)
    if known is not None:
        return list(known)
    order = _order(remaining, bound, hints)
    if len(_ORDERS) < _ORDERS_MAX:
        _ORDERS[key] = list(order)
    return order


def _order(remaining: list[_Element], bound: set[Variable],
           hints: Mapping[str, int]) -> list[int]:
    """The greedy order with Soar's ties (see the module docstring)."""
    roots = _roots(remaining, bound)
    by_var: dict[Variable, list[_Element]] = {}
    for e in remaining:
        if e.positive:
            mentions = {v for v in (e.ident, e.attr, e.value) if isinstance(v, Variable)}
        else:
            mentions = set(e.needs)
        e.mentions = frozenset(mentions)
        for v in mentions:
            by_var.setdefault(v, []).append(e)
    # the elements of each cost, in heaps by the tie key (stale entries skipped)
    buckets: dict[int, dict[_Element, None]] = {}
    heaps: dict[int, list[tuple[tuple[int, int, int, int], _Element]]] = {}

    def place(e: _Element, cost: int) -> None:
        e.cost = cost
        bucket = buckets.get(cost)
        if bucket is None:
            buckets[cost] = {e: None}
            heaps[cost] = [(e.tie, e)]
        else:
            bucket[e] = None
            heapq.heappush(heaps[cost], (e.tie, e))

    def unplace(e: _Element) -> None:
        bucket = buckets[e.cost]
        del bucket[e]
        if not bucket:
            del buckets[e.cost]
            del heaps[e.cost]

    for e in remaining:
        place(e, _cost(e, bound, roots, hints))
    left = len(remaining)
    order: list[int] = []
    while left:
        if roots and roots <= bound:
            roots = frozenset()
            for e in list(e for b in buckets.values() for e in b):
                unplace(e)
                place(e, _cost(e, bound, roots, hints))
        least = min(buckets)
        tied = buckets[least]
        heap = heaps[least]
        while heap[0][1] not in tied or heap[0][1].cost != least:
            heapq.heappop(heap)
        chosen = heap[0][1]
        if least > 1 and len(tied) > 1 and len(tied) * left <= LOOKAHEAD_BUDGET:
            best: tuple[int, tuple[int, int, int, int]] | None = None
            for e in tied:
                ahead = _lookahead(e, buckets, by_var, bound, roots, hints)
                # a negation never displaces a tie (Soar compares positives)
                rank = (ahead, e.tie if e.positive else (2, 0, 0, -e.index))
                if best is None or rank < best:
                    best, chosen = rank, e
        unplace(chosen)
        left -= 1
        if chosen.positive:
            order.append(chosen.index)
            new = chosen.binds - bound
            bound |= chosen.binds
            touched: dict[_Element, None] = {}
            for v in new:
                for e in by_var.get(v, ()):
                    if e is not chosen and e.cost and e in buckets.get(e.cost, {}):
                        touched[e] = None
            for e in touched:
                cost = _cost(e, bound, roots, hints)
                if cost != e.cost:
                    unplace(e)
                    place(e, cost)
    return order


def _lookahead(chosen: _Element, buckets: Mapping[int, Mapping[_Element, None]],
               by_var: Mapping[Variable, list[_Element]], bound: set[Variable],
               roots: frozenset[Variable], hints: Mapping[str, int]) -> int:
    """The cost of the cheapest element that could follow ``chosen``
    (Soar's ``find_lowest_cost_lookahead``): the elements that mention a
    variable ``chosen`` binds get a new cost, the others keep theirs."""
    after = bound | chosen.binds
    affected: dict[_Element, None] = {chosen: None}
    best = MAX_COST + 1
    for v in chosen.binds - bound:
        for e in by_var.get(v, ()):
            if e not in affected and e in buckets.get(e.cost, {}):
                affected[e] = None
                cost = _cost(e, after, roots, hints)
                if cost < best:
                    best = cost
    for cost in sorted(buckets):
        if cost >= best:
            break
        bucket = buckets[cost]
        if len(bucket) > sum(1 for e in affected if e in bucket):
            best = cost
            break
    return best


_SOAR_ONLY: Final = ConstantOrder()
