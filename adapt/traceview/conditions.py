"""Conditions checked one at a time against a rebuilt working memory.

The matchers answer "which instantiations exist"; a user asking why a rule
did *not* fire wants the first condition that left no consistent match.
:func:`first_failure` walks a production's conditions in source order,
extending every partial match, and stops at the condition where none
survives.  The semantics are those of :mod:`adapt.engine.production`
(relational tests through :func:`adapt.engine.naive.relation_holds`).

Examples
--------
>>> from adapt.engine.parse import parse_rules
>>> from adapt.engine.symbols import Identifier
>>> from adapt.engine.wme import WME
>>> p, = parse_rules("sp {add (state <s> ^count {<c> < 3}) --> (<s> ^done yes)}").productions
>>> s1 = Identifier("S", 1)
>>> wmes = [WME(s1, "type", "state", False, 1), WME(s1, "count", 5, False, 2)]
>>> failure = first_failure(p, wmes)
>>> print(condition_text(failure.condition))
(<s> ^count { <c> < 3 })
>>> failure.alone, failure.partials
([], [{<s>: S1}])
>>> first_failure(p, [WME(s1, "type", "state", False, 1), WME(s1, "count", 2, False, 3)]) is None
True
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from adapt.engine.naive import relation_holds
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
from adapt.engine.symbols import Symbol, format_symbol
from adapt.engine.wme import WME

__all__ = ["Bindings", "Failure", "condition_text", "match_condition", "matches",
           "first_failure"]

Bindings = dict[Variable, Symbol]

#: Partial matches kept per condition; a diagnosis needs examples, not all of them.
MAX_PARTIALS = 5000


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
    """A condition written back as rule text (after normalisation).

    >>> from adapt.engine.production import Condition, EqualityTest, Variable
    >>> condition_text(Condition(Variable("<o>"), EqualityTest("name"), None, negated=True))
    '-(<o> ^name)'
    """
    if isinstance(element, ConjunctiveNegation):
        return "-{ " + " ".join(condition_text(c) for c in element.conditions) + " }"
    value = _test_text(element.value)
    text = f"({element.id.name} ^{_test_text(element.attr)}{' ' + value if value else ''}"
    text += " +)" if element.acceptable else ")"
    return ("-" if element.negated else "") + text


def _field(test: Test | None, value: Symbol, b: Bindings, later: list[tuple[str, Symbol, Variable]]) -> bool:
    for t in simple_tests(test):
        if isinstance(t, EqualityTest):
            if isinstance(t.term, Variable):
                if t.term in b:
                    if not b[t.term] == value:
                        return False
                else:
                    b[t.term] = value
            elif not t.term == value:
                return False
        elif isinstance(t, DisjunctionTest):
            if not any(v == value for v in t.values):
                return False
        elif isinstance(t, RelationalTest):
            term = t.term
            if isinstance(term, Variable):
                if term in b:
                    if not relation_holds(t.relation, value, b[term]):
                        return False
                else:
                    later.append((t.relation, value, term))
            elif not relation_holds(t.relation, value, term):
                return False
    return True


def match_condition(cond: Condition, wme: WME, bindings: Bindings) -> Bindings | None:
    """The bindings extended by matching ``cond`` (ignoring negation) to ``wme``, or ``None``."""
    if wme.acceptable != cond.acceptable:
        return None
    b = dict(bindings)
    later: list[tuple[str, Symbol, Variable]] = []
    if not (_field(EqualityTest(cond.id), wme.id, b, later) and _field(cond.attr, wme.attr, b, later)
            and _field(cond.value, wme.value, b, later)):
        return None
    for relation, value, term in later:  # a variable bound later in this same condition
        if term in b and not relation_holds(relation, value, b[term]):
            return None
    return b


def _candidates(cond: Condition, wmes: Sequence[WME], by_id: dict[Symbol, list[WME]],
                b: Bindings) -> Sequence[WME]:
    return by_id.get(b[cond.id], ()) if cond.id in b else wmes


def matches(elements: Sequence[ConditionElement], wmes: Sequence[WME],
            bindings: Bindings | None = None) -> Iterator[Bindings]:
    """Every consistent match of a conjunction of condition elements."""
    by_id: dict[Symbol, list[WME]] = {}
    for w in wmes:
        by_id.setdefault(w.id, []).append(w)
    partials = [dict(bindings or {})]
    for element in elements:
        partials = _step(element, partials, wmes, by_id)
        if not partials:
            return
    yield from partials


def _exists(element: ConditionElement, wmes: Sequence[WME], b: Bindings) -> bool:
    if isinstance(element, ConjunctiveNegation):
        return any(True for _ in matches(element.conditions, wmes, b))
    positive = Condition(element.id, element.attr, element.value, element.acceptable)
    return any(match_condition(positive, w, b) is not None for w in wmes)


def _step(element: ConditionElement, partials: list[Bindings], wmes: Sequence[WME],
          by_id: dict[Symbol, list[WME]]) -> list[Bindings]:
    if isinstance(element, Condition) and not element.negated:
        out: list[Bindings] = []
        for b in partials:
            for w in _candidates(element, wmes, by_id, b):
                extended = match_condition(element, w, b)
                if extended is not None:
                    out.append(extended)
                    if len(out) >= MAX_PARTIALS:
                        return out
        return out
    return [b for b in partials if not _exists(element, wmes, b)]


@dataclass(frozen=True)
class Failure:
    """The condition where a production's match ran out.

    Attributes
    ----------
    index : int
        Position of the condition in :attr:`Production.conditions` (0-based).
    condition : ConditionElement
        The condition.
    partials : list of dict
        Some matches of the conditions before it (at most a few), the
        bindings the condition had to agree with.
    alone : list of WME
        For a positive condition: WMEs that match it with no bindings at all
        (it failed on consistency with the earlier ones).  For a negation:
        WMEs that matched the negated condition (so it blocked).
    """

    index: int
    condition: ConditionElement
    partials: list[Bindings]
    alone: list[WME]


def first_failure(production: Production, wmes: Sequence[WME], examples: int = 3) -> Failure | None:
    """The first condition of ``production`` with no consistent match, or ``None`` if it matches."""
    by_id: dict[Symbol, list[WME]] = {}
    for w in wmes:
        by_id.setdefault(w.id, []).append(w)
    partials: list[Bindings] = [{}]
    for index, element in enumerate(production.conditions):
        survivors = _step(element, partials, wmes, by_id)
        if survivors:
            partials = survivors
            continue
        if isinstance(element, Condition) and not element.negated:
            alone = [w for w in wmes if match_condition(element, w, {}) is not None]
        else:
            alone = []
            for b in partials[:examples]:
                if isinstance(element, Condition):
                    positive = Condition(element.id, element.attr, element.value, element.acceptable)
                    alone += [w for w in _candidates(positive, wmes, by_id, b)
                              if match_condition(positive, w, b) is not None][:1]
        return Failure(index, element, partials[:examples], alone[:examples])
    return None
