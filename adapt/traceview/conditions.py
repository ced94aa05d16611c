"""Why a rule does not match: its conditions checked one step at a time.

The matchers answer "which instantiations exist"; a user asking why a rule
did *not* fire wants the condition where its partial matches ran out.
:func:`first_failure` follows the engine's own evaluation
(:func:`adapt.engine.conditions.evaluation_order` and
:func:`~adapt.engine.conditions.extend`): positive conditions in source
order, each negation once the variables it shares with them are bound, a
relational test on a variable bound later checked by the condition that
binds it.  It is the semantics the matchers use, not a copy of it, so a rule
this module says matches is one the agent would fire.

Examples
--------
>>> from adapt.engine.parse import parse_rules
>>> from adapt.engine.symbols import Identifier
>>> from adapt.engine.wme import WME
>>> p, = parse_rules("sp {add (state <s> ^superstate nil ^count {<c> < 3}) --> (<s> ^done yes)}"
...                  ).productions
>>> s1 = Identifier("S", 1, goal=True)  # a state
>>> wmes = [WME(s1, "superstate", "nil", False, 1), WME(s1, "count", 5, False, 2)]
>>> failure = first_failure(p, wmes)
>>> print(condition_text(failure.condition))
(state <s> ^count { <c> < 3 })
>>> failure.alone, failure.partials
([], [{<s>: S1}])
>>> first_failure(p, [WME(s1, "superstate", "nil", False, 1), WME(s1, "count", 2, False, 3)]) is None
True

A relational test on a variable that a later condition binds fails there:

>>> p, = parse_rules("sp {r (state <s> ^a {<x> > <y>}) (<s> ^b <y>) --> (write hi)}").productions
>>> wmes = [WME(s1, "type", "state", False, 1), WME(s1, "a", 1, False, 2),
...         WME(s1, "b", 5, False, 3)]
>>> failure = first_failure(p, wmes)
>>> print(condition_text(failure.condition), failure.waiting)
(<s> ^b <y>) ['1 > <y>']
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from adapt.engine.conditions import (
    Bindings,
    Partial,
    Turned,
    WmeIndex,
    conjunction_matches,
    evaluation_order,
    extend,
    match_condition,
    turned_round,
)
from adapt.engine.joins import join_orders
from adapt.engine.parse import RuleFile
from adapt.engine.production import (
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    DisjunctionTest,
    EqualityTest,
    Production,
    RelationalTest,
    Test,
    Variable,
    simple_tests,
)
from adapt.engine.reorder import join_order
from adapt.engine.symbols import format_symbol
from adapt.engine.wme import WME

__all__ = ["Bindings", "Failure", "condition_text", "matches", "first_failure"]


def _term_text(term: object) -> str:
    return term.name if isinstance(term, Variable) else format_symbol(term)  # type: ignore[arg-type]


def _test_text(test: Test | None) -> str:
    if test is None:
        return ""
    if isinstance(test, EqualityTest):
        return _term_text(test.term)
    if isinstance(test, RelationalTest):
        return f"{test.relation} {_term_text(test.term)}"
    if isinstance(test, DisjunctionTest):
        return "<< " + " ".join(format_symbol(v) for v in test.values) + " >>"
    return "{ " + " ".join(_test_text(t) for t in test.tests) + " }"


def condition_text(element: ConditionElement) -> str:
    """A condition written back as rule text (after normalisation); one with
    the goal test of ``(state <s> ...)`` is written ``(state <s> ...)``.

    >>> from adapt.engine.production import Condition, EqualityTest, Variable
    >>> condition_text(Condition(Variable("<o>"), EqualityTest("name"), None, negated=True))
    '-(<o> ^name)'
    >>> condition_text(Condition(Variable("<s>"), EqualityTest("name"), EqualityTest("a"), goal=True))
    '(state <s> ^name a)'
    """
    if isinstance(element, ConjunctiveNegation):
        return "-{ " + " ".join(condition_text(c) for c in element.conditions) + " }"
    value = _test_text(element.value)
    state = "state " if element.goal else ""
    text = f"({state}{element.id.name} ^{_test_text(element.attr)}{' ' + value if value else ''}"
    text += " +)" if element.acceptable else ")"
    return ("-" if element.negated else "") + text


def matches(elements: Sequence[ConditionElement], wmes: Sequence[WME],
            bindings: Bindings | None = None,
            order: Sequence[int] | None = None) -> Iterator[Bindings]:
    """The bindings of every consistent match of a conjunction of condition
    elements (:func:`adapt.engine.conditions.conjunction_matches`), joined in the
    matchers' order (a relational test between values of different types reads
    differently turned round): ``order``, the elements' evaluation order as the
    matchers loaded them (:func:`adapt.engine.joins.join_orders`), or
    :func:`adapt.engine.reorder.join_order` with Soar's own symbols only."""
    if order is None:
        positives = join_order(elements, tuple(bindings or ()))
    else:
        positives = [i for i in order if isinstance(elements[i], Condition)
                     and not elements[i].negated]  # type: ignore[union-attr]
    for b, _ in conjunction_matches(elements, WmeIndex(wmes), bindings, positives=positives,
                                    order=join_order):
        yield b


@dataclass(frozen=True)
class Failure:
    """The condition where a production's partial matches ran out.

    Attributes
    ----------
    index : int
        Position of the condition in :attr:`Production.conditions` (0-based).
    condition : ConditionElement
        The condition.
    partials : list of dict
        Some partial matches that reached it (at most a few): the bindings
        it had to agree with.
    alone : list of WME
        For a positive condition: WMEs that match it with no bindings at all
        (it failed on consistency with the earlier ones).  For a negated
        condition: WMEs that matched it (so it blocked).
    waiting : list of str
        Relational tests of earlier conditions that waited for a variable
        this condition binds (``"1 > <y>"``), from the first partial.
    """

    index: int
    condition: ConditionElement
    partials: list[Bindings]
    alone: list[WME]
    waiting: list[str]


def _deepest(elements: Sequence[ConditionElement], order: Sequence[int], index: WmeIndex,
             examples: int, turned: Turned) -> tuple[int, list[Partial]]:
    """The number of evaluation steps some partial passes, and a few partials
    that got that far (``len(order)`` when the production matches); ``turned``:
    the relational tests read turned round in the matchers' join order."""
    best = -1
    found: list[Partial] = []

    def walk(step: int, partial: Partial) -> bool:
        nonlocal best, found
        if step > best:
            best, found = step, []
        if step == best and len(found) < examples:
            found.append(partial)
        if step == len(order):
            return True
        i = order[step]
        return any(walk(step + 1, p)
                   for p in extend(elements[i], partial, index, turned.get(i, frozenset()),
                                   join_order))

    walk(0, Partial({}))
    return best, found


def first_failure(production: Production, wmes: Sequence[WME], examples: int = 3,
                  order: Sequence[int] | None = None) -> Failure | None:
    """The first condition (in evaluation order) at which no partial match of
    ``production`` survives, or ``None`` if the production matches.  ``order`` is its
    conditions' evaluation order as the matchers loaded it (with the rule files before it:
    :func:`adapt.engine.joins.join_orders`, whose last ties the symbol table breaks); by
    default as a matcher holding only ``production``."""
    index = WmeIndex(wmes)
    elements = production.conditions
    if order is None:
        (_, order), = join_orders(RuleFile((production,)))
    # whether it matches, in the matchers' join order: a relational test waiting for a
    # variable bound later is checked there turned round, which between values of
    # different types reads differently; where, in source order (as the rule reads) unless
    # that order matches where the matchers' does not
    joined = list(order)
    turned = turned_round(elements, [i for i in joined if isinstance(elements[i], Condition)
                                     and not elements[i].negated], ())  # type: ignore[union-attr]
    depth, partials = _deepest(elements, joined, index, examples, turned)
    if depth == len(joined):
        return None
    order = evaluation_order(elements)
    written_depth, written = _deepest(elements, order, index, examples, turned)
    if written_depth < len(order):
        depth, partials = written_depth, written
    else:
        order = joined
    element = elements[order[depth]]
    alone: list[WME] = []
    if isinstance(element, Condition) and not element.negated:
        own = turned.get(order[depth], frozenset())
        alone = [w for w in wmes if match_condition(element, w, Partial({}), own) is not None]
    elif isinstance(element, Condition):
        for p in partials:
            ident = p.bindings.get(element.id)
            candidates = list(index) if ident is None else index.of(ident)
            alone += [w for w in candidates
                      if match_condition(element, w, Partial(p.bindings)) is not None][:1]
    waiting = [f"{format_symbol(r.value)} {r.relation} {r.variable.name}"
               for r in (partials[0].pending if partials else ())]
    if isinstance(element, Condition) and not element.negated:
        binds = {element.id} | {t.term for t in _equalities(element)}
        waiting = [w for w, r in zip(waiting, partials[0].pending) if r.variable in binds]
    else:
        waiting = []
    return Failure(order[depth], element, [p.bindings for p in partials], alone[:examples],
                   waiting)


def _equalities(cond: Condition) -> list[EqualityTest]:
    return [t for test in (cond.attr, cond.value) for t in simple_tests(test)
            if isinstance(t, EqualityTest) and isinstance(t.term, Variable)]
