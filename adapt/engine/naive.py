"""The brute-force matcher: obviously correct, slow, the Rete's reference.

:class:`NaiveMatcher` keeps the productions and the WMEs and, when asked,
recomputes the whole match set from scratch by backtracking over each
production's positive conditions, then checking the relational tests and the
negated conditions and conjunctive negations.  :meth:`NaiveMatcher.take_changes`
diffs that set against the one it reported last time, so transient matches
cancel out by construction.

Order of the changes (deterministic for a given sequence of calls):

* ``added``: in the order the recomputation finds the matches -- productions in
  the order they were added, and for one production the WME combinations in
  backtracking order (positive conditions left to right, candidate WMEs in the
  order they were added);
* ``removed``: in the order of the previously reported match set.

The matching semantics are those of :mod:`adapt.engine.production`.

Examples
--------
>>> from adapt.engine.production import Production, Condition, EqualityTest, Variable
>>> from adapt.engine.symbols import Identifier
>>> from adapt.engine.wme import WME
>>> s, x = Variable("<s>"), Variable("<x>")
>>> p = Production("p", (Condition(s, EqualityTest("count"), EqualityTest(x)),), ())
>>> m = NaiveMatcher()
>>> m.add_production(p)
>>> s1 = Identifier("S", 1)
>>> m.add_wme(WME(s1, "count", 1, False, 5))
>>> added, removed = m.take_changes()
>>> added, removed
([Match(p, [5])], [])
>>> added[0].bindings()
{<s>: S1, <x>: 1}
"""

from __future__ import annotations

from typing import Iterator, Sequence

from adapt.engine.matcher import Match, MatchKey
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
    condition_equality_variables,
    relational_variables,
    simple_tests,
)
from adapt.engine.symbols import Identifier, Symbol, is_number
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = ["NaiveMatcher", "relation_holds", "check_production"]

Bindings = dict[Variable, Symbol]
#: A relational test waiting for its variable: (relation, tested value, term).
Pending = tuple[str, Symbol, object]


def _kind(value: object) -> int:
    """The symbol type for ``<=>``: identifier, string, int or float."""
    if isinstance(value, Identifier):
        return 0
    if isinstance(value, str):
        return 1
    if isinstance(value, float):
        return 3
    return 2


def relation_holds(relation: str, value: Symbol, other: Symbol) -> bool:
    """Whether ``value relation other`` holds, with Soar's semantics.

    Examples
    --------
    >>> from adapt.engine.symbols import Float
    >>> relation_holds("<", 2, Float(2.5)), relation_holds("<", "a", 3)
    (True, False)
    >>> relation_holds("<>", 2, Float(2.0)), relation_holds("<=>", 2, 7)
    (True, True)
    """
    if relation == "=":
        return value == other
    if relation == "<>":
        return not value == other
    if relation == "<=>":
        return _kind(value) == _kind(other)
    if is_number(value) and is_number(other):
        pass
    elif isinstance(value, str) and isinstance(other, str):
        pass
    else:
        return False
    if relation == "<":
        return value < other  # type: ignore[operator]
    if relation == ">":
        return value > other  # type: ignore[operator]
    if relation == "<=":
        return value <= other  # type: ignore[operator]
    if relation == ">=":
        return value >= other  # type: ignore[operator]
    raise EngineError(f"unknown relation {relation!r}")


def _match_field(
    test: Test | None, value: Symbol, bindings: Bindings, pending: list[Pending]
) -> bool:
    """Check the equality, constant and disjunction parts of ``test`` against
    ``value``, binding unbound equality variables in ``bindings`` (mutated);
    relational tests are appended to ``pending``."""
    for t in simple_tests(test):
        if isinstance(t, EqualityTest):
            term = t.term
            if isinstance(term, Variable):
                if term in bindings:
                    if not bindings[term] == value:
                        return False
                else:
                    bindings[term] = value
            elif not term == value:
                return False
        elif isinstance(t, DisjunctionTest):
            if not any(c == value for c in t.values):
                return False
        else:
            assert isinstance(t, RelationalTest)
            pending.append((t.relation, value, t.term))
    return True


def _match_condition(
    cond: Condition, wme: WME, bindings: Bindings, pending: list[Pending]
) -> bool:
    if wme.acceptable != cond.acceptable:
        return False
    return (
        _match_field(EqualityTest(cond.id), wme.id, bindings, pending)
        and _match_field(cond.attr, wme.attr, bindings, pending)
        and _match_field(cond.value, wme.value, bindings, pending)
    )


def _pending_hold(pending: list[Pending], bindings: Bindings) -> bool:
    for relation, value, term in pending:
        other = bindings[term] if isinstance(term, Variable) else term
        if not relation_holds(relation, value, other):  # type: ignore[arg-type]
            return False
    return True


class _Memory:
    """The WMEs, in arrival order, and the same grouped by identifier."""

    __slots__ = ("wmes", "by_id")

    def __init__(self, wmes: Sequence[WME]) -> None:
        self.wmes = wmes
        self.by_id: dict[Symbol, list[WME]] = {}
        for w in wmes:
            self.by_id.setdefault(w.id, []).append(w)

    def candidates(self, cond: Condition, bindings: Bindings) -> Sequence[WME]:
        """The WMEs that might match ``cond``: those with its identifier if
        that is bound, else all."""
        if cond.id in bindings:
            return self.by_id.get(bindings[cond.id], ())
        return self.wmes


def _conjunction(
    elements: Sequence[ConditionElement], wmes: _Memory, bindings: Bindings
) -> Iterator[tuple[Bindings, tuple[WME, ...]]]:
    """Every consistent match of a conjunction of condition elements, given
    the bindings of the enclosing scope."""
    positives = [e for e in elements if isinstance(e, Condition) and not e.negated]
    negations = [e for e in elements if not (isinstance(e, Condition) and not e.negated)]

    def extend(
        i: int, b: Bindings, chosen: tuple[WME, ...], pending: list[Pending]
    ) -> Iterator[tuple[Bindings, tuple[WME, ...]]]:
        if i == len(positives):
            if _pending_hold(pending, b) and not any(_exists(n, wmes, b) for n in negations):
                yield b, chosen
            return
        for w in wmes.candidates(positives[i], b):
            b2 = dict(b)
            p2 = list(pending)
            if _match_condition(positives[i], w, b2, p2):
                yield from extend(i + 1, b2, chosen + (w,), p2)

    yield from extend(0, dict(bindings), (), [])


def _exists(element: ConditionElement, wmes: _Memory, bindings: Bindings) -> bool:
    """Whether a negated condition or conjunctive negation has a match."""
    if isinstance(element, ConjunctiveNegation):
        return any(True for _ in _conjunction(element.conditions, wmes, bindings))
    for w in wmes.candidates(element, bindings):
        b2 = dict(bindings)
        pending: list[Pending] = []
        if _match_condition(element, w, b2, pending) and _pending_hold(pending, b2):
            return True
    return False


def _check_scope(name: str, elements: Sequence[ConditionElement], outer: set[Variable]) -> None:
    bound = set(outer)
    for e in elements:
        if isinstance(e, Condition) and not e.negated:
            bound |= condition_equality_variables(e)
    for e in elements:
        if isinstance(e, ConjunctiveNegation):
            _check_scope(name, e.conditions, bound)
            continue
        local = bound | condition_equality_variables(e) if e.negated else bound
        unbound = set(relational_variables(e.attr) + relational_variables(e.value)) - local
        if unbound:
            var = sorted(v.name for v in unbound)[0]
            raise EngineError(
                f"production {name}: variable {var} is tested with a relation but never bound"
            )


def check_production(production: Production) -> None:
    """Raise :class:`~adapt.errors.EngineError` if a relational test uses a
    variable that no equality test in its scope binds.

    Examples
    --------
    >>> from adapt.engine.production import Condition, RelationalTest, Variable
    >>> bad = Production("bad", (Condition(Variable("<s>"), None,
    ...                          RelationalTest("<", Variable("<y>"))),), ())
    >>> check_production(bad)
    Traceback (most recent call last):
    ...
    adapt.errors.EngineError: production bad: variable <y> is tested with a relation but never bound
    """
    _check_scope(production.name, production.conditions, set())


class NaiveMatcher:
    """Brute-force implementation of :class:`adapt.engine.matcher.Matcher`.

    Every :meth:`take_changes` or :meth:`matches` after a change recomputes
    all matches of all productions: use it as a reference, not in production.
    """

    __slots__ = ("_productions", "_wmes", "_current", "_reported", "_dirty")

    def __init__(self) -> None:
        self._productions: dict[str, Production] = {}
        self._wmes: dict[int, WME] = {}
        self._current: dict[MatchKey, Match] = {}
        self._reported: dict[MatchKey, Match] = {}
        self._dirty = False

    def add_production(self, production: Production) -> None:
        """Add a production; its matches become pending additions."""
        if production.name in self._productions:
            raise EngineError(f"production {production.name} is already in the matcher")
        check_production(production)
        self._productions[production.name] = production
        self._dirty = True

    def remove_production(self, name: str) -> None:
        """Remove a production; its matches become pending removals."""
        if name not in self._productions:
            raise EngineError(f"no production named {name} in the matcher")
        del self._productions[name]
        self._dirty = True

    def add_wme(self, wme: WME) -> None:
        """Add a WME (a timetag already present is ignored)."""
        if wme.timetag not in self._wmes:
            self._wmes[wme.timetag] = wme
            self._dirty = True

    def remove_wme(self, wme: WME) -> None:
        """Remove a WME (a timetag not present is ignored)."""
        if self._wmes.pop(wme.timetag, None) is not None:
            self._dirty = True

    def _refresh(self) -> None:
        if not self._dirty:
            return
        wmes = _Memory(list(self._wmes.values()))
        current: dict[MatchKey, Match] = {}
        for production in self._productions.values():
            for _, chosen in _conjunction(production.conditions, wmes, {}):
                match = Match(production, chosen)
                current[match.key] = match
        self._current = current
        self._dirty = False

    def take_changes(self) -> tuple[list[Match], list[Match]]:
        """``(added, removed)`` since the previous call (see the module doc for the order)."""
        self._refresh()
        current, reported = self._current, self._reported
        added = [m for k, m in current.items() if k not in reported]
        removed = [m for k, m in reported.items() if k not in current]
        self._reported = current
        return added, removed

    def matches(self) -> list[Match]:
        """The current match set."""
        self._refresh()
        return list(self._current.values())

