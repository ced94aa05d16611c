"""What a condition means: the one definition every matcher and tool calls.

This module is the semantics of a production's left-hand side.  The
brute-force matcher (:mod:`adapt.engine.naive`), the justifications of
substate results (:mod:`adapt.engine.results`) and the trace tools
(:mod:`adapt.traceview.conditions`) all match conditions through it; the Rete
(:mod:`adapt.engine.rete`) compiles the same tests into its network, uses
:data:`RELATIONS` for every relational test, and is tested against this
module on random productions and working memories.

Tests on one field of a WME
---------------------------
* ``=`` (an equality test): the same symbol -- ``2`` and ``2.0`` differ;
  identifiers are compared by identity.  A variable not yet bound is bound
  to the field.
* ``<> x``: not the same symbol.
* ``< > <= >=``: Soar's order (:func:`soar_compare`): numbers numerically
  (int or float), strings as strings, identifiers by letter, then number;
  between two types the tested value is *less* than the other, so ``<`` and
  ``<=`` hold and ``>`` and ``>=`` do not.
* ``<=> x``: the same *type* of symbol (identifier, string, int, float).
* ``<< a b >>``: equal to one of the constants.
* a condition written in ``(state <s> ...)`` (:attr:`Condition.goal`): the
  WME's identifier is a state of the goal stack (:func:`is_goal`), not just
  something with ``^type state``.

Scope of variables
------------------
* A variable is bound by the first equality test on it among the positive
  conditions of its conjunction, *wherever* that condition is written: a
  relational test or a negated condition written before the condition that
  binds its variable is evaluated once the variable is bound.
* A relational test's variable must be bound by an equality test in its
  scope (:func:`check_scope` raises otherwise).
* Variables bound only inside a negated condition or a conjunctive negation
  are local to it; a negated condition's relational tests compare only with
  variables bound outside it (Soar refuses ``-(<s> ^{a < <y>} <y>)``).

Evaluation order
----------------
:func:`evaluation_order` puts a conjunction's positive conditions in source
order and each negation right after the positive condition that binds the
last variable it shares with them (first, when it shares none).  A relational
test whose variable is bound later waits in the partial match
(:class:`Partial`) and is checked by the condition that binds the variable.
Each relational test on a variable is read as written or turned round as
Soar's reorderer puts it back in the join order (:func:`turned_round`).
A match is a partial that passed every step; which step a production's
partials run out at is what ``adapt trace why --rule`` reports.

Examples
--------
>>> from adapt.engine.parse import parse_rules
>>> from adapt.engine.symbols import Identifier
>>> p, = parse_rules("sp {r (state <s> ^a {<x> > <y>}) (<s> ^b <y>) --> (write hi)}").productions
>>> s1 = Identifier("S", 1, goal=True)  # a state
>>> wm = WmeIndex([WME(s1, "type", "state", False, 1), WME(s1, "a", 1, False, 2),
...                WME(s1, "b", 5, False, 3)])
>>> list(conjunction_matches(p.conditions, wm))
[]
>>> wm = WmeIndex([WME(s1, "type", "state", False, 1), WME(s1, "a", 9, False, 2),
...                WME(s1, "b", 5, False, 3)])
>>> [sorted(v.name for v in b) for b, _ in conjunction_matches(p.conditions, wm)]
[['<s>', '<x>', '<y>']]
"""

from __future__ import annotations

from collections.abc import Callable, Container, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Final, Literal, Protocol

from adapt.engine.production import (
    FIELD_ATTR,
    FIELD_ID,
    FIELD_VALUE,
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    DisjunctionTest,
    EqualityTest,
    RelationalTest,
    Test,
    Variable,
    condition_equality_variables,
    relational_variables,
    simple_tests,
    variables_in_test,
)
from adapt.engine.symbols import (  # noqa: F401 (Float: the examples)
    Float,
    Identifier,
    Symbol,
    is_goal,
)
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = [
    "Relation",
    "RELATIONS",
    "REVERSED",
    "relation_holds",
    "soar_compare",
    "Bindings",
    "PendingRelation",
    "Partial",
    "WmeSource",
    "WmeIndex",
    "match_condition",
    "evaluation_order",
    "turned_round",
    "Turned",
    "JoinOrder",
    "extend",
    "conjunction_matches",
    "exists",
    "all_variables",
    "check_scope",
]

#: A relational test's operator.
Relation = Literal["=", "<>", "<", ">", "<=", ">=", "<=>"]

#: Variable bindings of a (partial) match.
Bindings = dict[Variable, Symbol]


# -- relations -------------------------------------------------------------------


def _kind(value: object) -> int:
    """The symbol type for ``<=>``: identifier, string, int or float."""
    t = type(value)
    if t is Identifier:
        return 0
    if t is str:
        return 1
    if t is int:
        return 2
    return 3


def _same(a: object, b: object) -> bool:
    return a == b


def _differ(a: object, b: object) -> bool:
    return not a == b


def _same_type(a: object, b: object) -> bool:
    return _kind(a) == _kind(b)


def soar_compare(a: object, b: object) -> int:
    """Soar's ``compare_symbols`` (``rete.cpp``): -1, 0 or 1.

    Numbers compare numerically (an int with a float too), strings as strings,
    identifiers by letter, then number (``O2 < O10 < S1``); a value compared
    with one of another type is always *less* -- so between types ``<`` and
    ``<=`` hold and ``>`` and ``>=`` do not, whatever the values.

    Examples
    --------
    >>> soar_compare(2, Float(2.5)), soar_compare("b", "a"), soar_compare("a", 3)
    (-1, 1, -1)
    >>> soar_compare(Identifier("O", 10), Identifier("O", 2)), soar_compare(3, "a")
    (1, -1)
    """
    if isinstance(a, (int, float)):  # a Float is a float
        if isinstance(b, (int, float)):
            return (a > b) - (a < b)
        return -1
    if isinstance(a, str):
        if isinstance(b, str):
            return (a > b) - (a < b)
        return -1
    if isinstance(a, Identifier) and isinstance(b, Identifier):
        x, y = a.sort_key(), b.sort_key()
        return (x > y) - (x < y)
    return -1


def _less(a: object, b: object) -> bool:
    if type(a) is int and type(b) is int:
        return a < b
    return soar_compare(a, b) < 0


def _greater(a: object, b: object) -> bool:
    if type(a) is int and type(b) is int:
        return a > b
    return soar_compare(a, b) > 0


def _less_equal(a: object, b: object) -> bool:
    if type(a) is int and type(b) is int:
        return a <= b
    return soar_compare(a, b) <= 0


def _greater_equal(a: object, b: object) -> bool:
    if type(a) is int and type(b) is int:
        return a >= b
    return soar_compare(a, b) >= 0


#: Each relation as a predicate ``(tested value, other) -> bool``: the one
#: definition of the relations (the Rete's join and alpha tests call these).
RELATIONS: Mapping[str, Callable[[object, object], bool]] = {
    "=": _same,
    "<>": _differ,
    "<=>": _same_type,
    "<": _less,
    ">": _greater,
    "<=": _less_equal,
    ">=": _greater_equal,
}


#: Each relation turned round (``a < b`` is ``b > a``).  A relational test
#: whose variable is bound later is checked at the condition that binds it,
#: turned round, as Soar's reorderer moves it there: with Soar's comparison of
#: values of different types (:func:`soar_compare`) the two readings differ
#: (``apple < 2`` holds, ``2 > apple`` does not).
REVERSED: Mapping[str, str] = {
    "=": "=", "<>": "<>", "<=>": "<=>", "<": ">", ">": "<", "<=": ">=", ">=": "<=",
}


def relation_holds(relation: str, value: object, other: object) -> bool:
    """Whether ``value relation other`` holds, with Soar's semantics.

    Examples
    --------
    >>> relation_holds("<", 2, Float(2.5)), relation_holds(">", "a", 3)
    (True, False)
    >>> relation_holds("<>", 2, Float(2.0)), relation_holds("<=>", 2, 7)
    (True, True)

    Raises
    ------
    EngineError
        For a relation that is not one of :data:`RELATIONS`.
    """
    test = RELATIONS.get(relation)
    if test is None:
        raise EngineError(f"unknown relation {relation!r}")
    return test(value, other)


# -- working memory as the semantics reads it ---------------------------------------


class WmeSource(Protocol):
    """WMEs to match against: all of them, and those of one identifier.

    :class:`WmeIndex` and :class:`adapt.engine.memory.WorkingMemory` are
    sources.
    """

    def __iter__(self) -> Iterator[WME]:
        """Every WME."""
        ...

    def of(self, ident: Symbol) -> Sequence[WME]:
        """The WMEs whose identifier is ``ident``."""
        ...


class WmeIndex:
    """A list of WMEs grouped by identifier (a :class:`WmeSource`).

    Examples
    --------
    >>> s1 = Identifier("S", 1, goal=True)  # a state
    >>> index = WmeIndex([WME(s1, "a", 1, False, 1), WME("x", "b", 2, False, 2)])
    >>> len(index.of(s1)), len(list(index))
    (1, 2)
    """

    __slots__ = ("wmes", "by_id")

    def __init__(self, wmes: Iterable[WME]) -> None:
        self.wmes: list[WME] = list(wmes)
        self.by_id: dict[Symbol, list[WME]] = {}
        for w in self.wmes:
            self.by_id.setdefault(w.id, []).append(w)

    def __iter__(self) -> Iterator[WME]:
        return iter(self.wmes)

    def of(self, ident: Symbol) -> Sequence[WME]:
        return self.by_id.get(ident, ())


# -- one condition against one WME -----------------------------------------------------


@dataclass(frozen=True, slots=True)
class PendingRelation:
    """A relational test met before its variable was bound: ``value relation <var>``,
    checked once ``<var>`` is bound -- as written, or turned round (``<var>`` with the
    relation reversed against ``value``) when Soar's reorderer reads it so
    (:func:`turned_round`)."""

    relation: str
    value: Symbol
    variable: Variable
    turned: bool = True

    def holds(self, bound: Symbol) -> bool:
        """Whether the test holds with its variable bound to ``bound``."""
        return _reads(self.relation, self.value, bound, self.turned)


def _reads(relation: str, value: object, other: object, turned: bool) -> bool:
    """``value relation other`` as Soar reads it: as written, or turned round
    (``other`` with the relation reversed against ``value``)."""
    if turned:
        return relation_holds(REVERSED[relation], other, value)
    return relation_holds(relation, value, other)


@dataclass(frozen=True, slots=True)
class Partial:
    """A partial match: bindings, the WMEs matched by the positive conditions
    so far (in evaluation order) and the relational tests waiting for a
    variable."""

    bindings: Bindings
    wmes: tuple[WME, ...] = ()
    pending: tuple[PendingRelation, ...] = ()


def _bind_field(test: Test | None, value: Symbol, b: Bindings) -> bool:
    """The equality and disjunction parts of ``test`` against ``value``;
    binds unbound equality variables in ``b`` (mutated)."""
    for t in simple_tests(test):
        if isinstance(t, EqualityTest):
            term = t.term
            if isinstance(term, Variable):
                bound = b.get(term, _UNBOUND)
                if bound is _UNBOUND:
                    b[term] = value
                elif not bound == value:
                    return False
            elif not term == value:
                return False
        elif isinstance(t, DisjunctionTest):
            if not any(c == value for c in t.values):
                return False
    return True


_UNBOUND: Final = object()


def _relations(test: Test | None, field: int, value: Symbol, b: Bindings,
               pending: list[PendingRelation], turned: Container[tuple[int, int]]) -> bool:
    """The relational parts of ``test`` (on ``field``): checked when their variable is
    bound -- turned round if ``(field, position)`` is in ``turned`` -- else appended to
    ``pending``."""
    for k, t in enumerate(simple_tests(test)):
        if isinstance(t, RelationalTest):
            term = t.term
            if isinstance(term, Variable):
                turn = (field, k) in turned
                if term in b:
                    if not _reads(t.relation, value, b[term], turn):
                        return False
                else:
                    pending.append(PendingRelation(t.relation, value, term, turn))
            elif not relation_holds(t.relation, value, term):
                return False
    return True


def match_condition(cond: Condition, wme: WME, partial: Partial,
                    turned: Container[tuple[int, int]] = ()) -> Partial | None:
    """``partial`` extended by matching ``cond`` (its negation ignored) to ``wme``.

    Equality tests bind first, so a relational test may use a variable bound
    anywhere in the same condition; relational tests whose variable is still
    unbound wait in the result's ``pending``, and pending tests whose
    variable this condition binds are checked.  ``turned`` holds the
    ``(field, position)`` of the relational tests Soar reads turned round
    (:func:`turned_round`; position in :func:`simple_tests` of the field's test).
    ``None`` when it does not match.
    """
    if wme.acceptable != cond.acceptable:
        return None
    if cond.goal and not is_goal(wme.id):
        return None
    b = dict(partial.bindings)
    ident = b.get(cond.id, _UNBOUND)
    if ident is _UNBOUND:
        b[cond.id] = wme.id
    elif ident is not wme.id and not ident == wme.id:
        return None
    if not (_bind_field(cond.attr, wme.attr, b) and _bind_field(cond.value, wme.value, b)):
        return None
    waiting: list[PendingRelation] = []
    for p in partial.pending:
        if p.variable in b:
            if not p.holds(b[p.variable]):
                return None
        else:
            waiting.append(p)
    if not (_relations(cond.attr, FIELD_ATTR, wme.attr, b, waiting, turned)
            and _relations(cond.value, FIELD_VALUE, wme.value, b, waiting, turned)):
        return None
    return Partial(b, partial.wmes + (wme,), tuple(waiting))


# -- conjunctions --------------------------------------------------------------------------


def all_variables(element: ConditionElement) -> set[Variable]:
    """Every variable an element mentions, nested ones included."""
    if isinstance(element, ConjunctiveNegation):
        out: set[Variable] = set()
        for e in element.conditions:
            out |= all_variables(e)
        return out
    return {element.id, *variables_in_test(element.attr), *variables_in_test(element.value)}


def _is_positive(element: ConditionElement) -> bool:
    return isinstance(element, Condition) and not element.negated


def evaluation_order(elements: Sequence[ConditionElement],
                     outer: Iterable[Variable] = (),
                     positives: Sequence[int] | None = None) -> list[int]:
    """Indexes of ``elements`` in the order they are evaluated.

    Positive conditions in source order (or in the order ``positives``
    gives their indexes: the Rete orders them by connectivity); each
    negation right after the positive condition that binds the last of the
    variables it shares with the conjunction's positive conditions
    (``outer`` are bound already), several there the last written first
    (as Soar's reorderer takes them).

    Examples
    --------
    >>> from adapt.engine.parse import parse_rules
    >>> p, = parse_rules("sp {r (state <s> -^a <v>) (<s> ^b <v>) --> (write x)}").productions
    >>> [type(p.conditions[i]).__name__ + ("-" if p.conditions[i].negated else "")
    ...  for i in evaluation_order(p.conditions)]
    ['Condition', 'Condition', 'Condition-']
    """
    outer_set = set(outer)
    if positives is None:
        positives = [i for i, e in enumerate(elements) if _is_positive(e)]
    # the step after which each variable is bound (0: before the first)
    step_of: dict[Variable, int] = {v: 0 for v in outer_set}
    for step, i in enumerate(positives, start=1):
        for v in condition_equality_variables(elements[i]):  # type: ignore[arg-type]
            if v not in step_of:
                step_of[v] = step
    slots: list[list[int]] = [[] for _ in range(len(positives) + 1)]
    for i, e in enumerate(elements):
        if _is_positive(e):
            continue
        k = max((step_of[v] for v in all_variables(e) if v in step_of and v not in outer_set),
                default=0)
        slots[k].append(i)
    # negations ready at the same step: the last written first, as Soar's
    # reorderer takes them
    order = slots[0][::-1]
    for k, i in enumerate(positives):
        order.append(i)
        order.extend(slots[k + 1][::-1])
    return order


#: The relational tests of a conjunction that Soar reads turned round: for an
#: element's index, the ``(field, position)`` of each (:func:`turned_round`).
Turned = Mapping[int, frozenset[tuple[int, int]]]

#: A join order: the indexes of a conjunction's positive conditions in the
#: order they are joined, given the variables bound outside it
#: (:func:`adapt.engine.reorder.join_order` with a matcher's hints).
JoinOrder = Callable[[Sequence[ConditionElement], Iterable[Variable]], Sequence[int]]


@dataclass(frozen=True, slots=True)
class _Slot:
    """The dummy variable Soar's reorderer gives a field without an equality test."""

    element: int
    field: int


def _is_constant(term: object) -> bool:
    return not isinstance(term, (Variable, _Slot))


def _same_term(a: object, b: object) -> bool:
    """The same variable or symbol (``2`` and ``2.0`` differ, as in Soar)."""
    return type(a) is type(b) and a == b


def _anchor(test: Test | None, element: int, field: int) -> object:
    """What Soar indexes a field's other tests by: its (first) equality test's
    variable or constant, else a dummy variable of the field's own."""
    for t in simple_tests(test):
        if isinstance(t, EqualityTest):
            return t.term
    return _Slot(element, field)


def turned_round(elements: Sequence[ConditionElement], positives: Sequence[int],
                 outer: Iterable[Variable] = ()) -> dict[int, frozenset[tuple[int, int]]]:
    """The relational tests on a variable that Soar reads turned round, given the
    order ``positives`` joins the positive conditions in (``outer`` are bound already).

    Soar's reorderer lifts every relational test of a positive condition out of
    it, orders the conditions, and puts each test back (``production_reorder.cpp``,
    ``restore_saved_tests_to_test``) at the first field, in join order, whose
    equality test is either the test's own field's (its *anchor*: the variable
    or constant of ``{<y> < <x>}`` or ``{a < <x>}``) while ``<x>`` is bound
    already -- read as written, ``<y> < <x>`` -- or ``<x>`` itself while the
    anchor is bound or a constant -- read turned round, ``<x> > <y>``.  With
    Soar's comparison of values of different types (:func:`soar_compare`) the
    two readings differ.  So a test anchored on a constant is read turned round
    whenever the condition binding its variable is joined in this conjunction,
    wherever that is; one anchored on a variable, when its variable is bound
    after the anchor -- in a later condition, or a later field of its own.
    A negated condition's tests stay where they are, read as written.

    Returns, for each element with such tests, the ``(field, position)`` of
    each (position in :func:`simple_tests` of the field's test).

    Examples
    --------
    >>> from adapt.engine.parse import parse_rules
    >>> p, = parse_rules("sp {r (state <s> ^b <x>) (<s> ^{a > <x>}) --> (write hi)}").productions
    >>> turned_round(p.conditions, [0, 1])  # 'a' is a constant: turned round at ^b
    {1: frozenset({(1, 1)})}
    >>> p, = parse_rules("sp {r (state <s> ^b <x>) (<s> ^a {<y> > <x>}) --> (write hi)}"
    ...                  ).productions
    >>> turned_round(p.conditions, [0, 1]), turned_round(p.conditions, [1, 0])
    ({}, {1: frozenset({(2, 1)})})
    """
    marked: set[object] = set(outer)
    waiting: list[tuple[int, int, int, object, Variable]] = []
    for i in positives:
        cond = elements[i]
        assert isinstance(cond, Condition)
        for field, test in ((FIELD_ATTR, cond.attr), (FIELD_VALUE, cond.value)):
            anchor = _anchor(test, i, field)
            for k, t in enumerate(simple_tests(test)):
                if isinstance(t, RelationalTest) and isinstance(t.term, Variable):
                    waiting.append((i, field, k, anchor, t.term))
    turned: dict[int, set[tuple[int, int]]] = {}
    for i in positives:
        if not waiting:
            break
        cond = elements[i]
        assert isinstance(cond, Condition)
        for field, test in ((FIELD_ID, EqualityTest(cond.id)), (FIELD_ATTR, cond.attr),
                            (FIELD_VALUE, cond.value)):
            here = _anchor(test, i, field)
            left: list[tuple[int, int, int, object, Variable]] = []
            for entry in waiting:
                j, f, k, anchor, variable = entry
                if _same_term(here, anchor) and (variable in marked
                                                 or _same_term(variable, anchor)):
                    continue  # as written
                if _same_term(here, variable) and (_is_constant(anchor) or anchor in marked):
                    turned.setdefault(j, set()).add((f, k))
                    continue
                left.append(entry)
            waiting = left
            if isinstance(here, _Slot):
                marked.add(here)
            for t in simple_tests(test):
                if isinstance(t, EqualityTest) and isinstance(t.term, Variable):
                    marked.add(t.term)
    return {i: frozenset(tests) for i, tests in turned.items()}


def _candidates(cond: Condition, source: WmeSource, b: Bindings) -> Iterable[WME]:
    ident = b.get(cond.id, _UNBOUND)
    if ident is _UNBOUND:
        return source
    return source.of(ident)  # type: ignore[arg-type]


_NONE_TURNED: Final[frozenset[tuple[int, int]]] = frozenset()


def extend(element: ConditionElement, partial: Partial, source: WmeSource,
           turned: Container[tuple[int, int]] = _NONE_TURNED,
           order: JoinOrder | None = None) -> Iterator[Partial]:
    """The partials that ``partial`` becomes after one evaluation step.

    A positive condition yields one partial per WME it matches consistently
    (``turned``: its relational tests read turned round, :func:`turned_round`);
    a negated condition or conjunctive negation yields ``partial`` itself when
    it has no match under its bindings (a conjunctive negation's conditions
    joined in ``order``), nothing otherwise.
    """
    if _is_positive(element):
        assert isinstance(element, Condition)
        for w in _candidates(element, source, partial.bindings):
            extended = match_condition(element, w, partial, turned)
            if extended is not None:
                yield extended
    elif not exists(element, source, partial.bindings, order):
        yield partial


def _search(elements: Sequence[ConditionElement], order: Sequence[int], step: int,
            partial: Partial, source: WmeSource, turned: Turned,
            join: JoinOrder | None) -> Iterator[Partial]:
    if step == len(order):
        yield partial
        return
    i = order[step]
    for p in extend(elements[i], partial, source, turned.get(i, _NONE_TURNED), join):
        yield from _search(elements, order, step + 1, p, source, turned, join)


def conjunction_matches(elements: Sequence[ConditionElement], source: WmeSource,
                        bindings: Bindings | None = None,
                        positives: Sequence[int] | None = None,
                        order: JoinOrder | None = None,
                        ) -> Iterator[tuple[Bindings, tuple[WME, ...]]]:
    """Every consistent match of a conjunction, given the enclosing bindings.

    Yields ``(bindings, wmes)``, ``wmes`` holding one WME per positive
    condition in source order.  Matches come in backtracking order:
    positive conditions in the order ``positives`` gives their indexes (a
    join order), else the one ``order`` gives (it also orders every
    conjunctive negation's conditions), else left to right; each one's
    candidate WMEs in the source's order.  The set of matches does not
    depend on the order, but the reading of a relational test between values
    of different types does (:func:`turned_round`): give the matcher's.
    """
    outer = dict(bindings or {})
    if positives is None and order is not None:
        positives = order(elements, outer)
    steps = evaluation_order(elements, outer, positives)
    joined = positives if positives is not None else [i for i in steps
                                                      if _is_positive(elements[i])]
    turned = turned_round(elements, joined, outer)
    if positives is None:
        for p in _search(elements, steps, 0, Partial(outer), source, turned, order):
            yield p.bindings, p.wmes
        return
    rank = {i: k for k, i in enumerate(positives)}
    written = sorted(positives)
    for p in _search(elements, steps, 0, Partial(outer), source, turned, order):
        yield p.bindings, tuple(p.wmes[rank[i]] for i in written)


def exists(element: ConditionElement, source: WmeSource, bindings: Bindings,
           order: JoinOrder | None = None) -> bool:
    """Whether a negated condition (read positively) or a conjunctive
    negation's conjunction (its conditions joined in ``order``) has a match
    under ``bindings``."""
    if isinstance(element, ConjunctiveNegation):
        return any(True for _ in conjunction_matches(element.conditions, source, bindings,
                                                     order=order))
    start = Partial(bindings)
    for w in _candidates(element, source, bindings):
        p = match_condition(element, w, start)
        if p is not None and not p.pending:
            return True
    return False


# -- scope -----------------------------------------------------------------------------------


def check_scope(name: str, elements: Sequence[ConditionElement],
                outer: Iterable[Variable] = ()) -> None:
    """Raise :class:`~adapt.errors.EngineError` if a relational test uses a
    variable that no equality test in its scope binds.

    Examples
    --------
    >>> from adapt.engine.production import Condition, RelationalTest
    >>> check_scope("bad", (Condition(Variable("<s>"), None,
    ...                                RelationalTest("<", Variable("<y>"))),))
    Traceback (most recent call last):
    ...
    adapt.errors.EngineError: production bad: variable <y> is tested with a relation but never bound
    """
    bound = set(outer)
    for e in elements:
        if _is_positive(e):
            bound |= condition_equality_variables(e)  # type: ignore[arg-type]
    for e in elements:
        if isinstance(e, ConjunctiveNegation):
            check_scope(name, e.conditions, bound)
            continue
        unbound = set(relational_variables(e.attr) + relational_variables(e.value)) - bound
        if unbound:
            var = sorted(v.name for v in unbound)[0]
            raise EngineError(
                f"production {name}: variable {var} is tested with a relation but never bound"
            )
