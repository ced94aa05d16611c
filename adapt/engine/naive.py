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
  backtracking order (positive conditions in the Rete's join order,
  :func:`adapt.engine.reorder.join_order`, candidate WMEs in the order they
  were added);
* ``removed``: in the order of the previously reported match set.

The matching semantics are :mod:`adapt.engine.conditions`, called directly:
this matcher is that module plus the bookkeeping of a
:class:`~adapt.engine.matcher.Matcher`.

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

from collections.abc import Iterable, Mapping, Sequence

from adapt.engine.conditions import JoinOrder, WmeIndex, check_scope, conjunction_matches
from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import ConditionElement, Production, Variable
from adapt.engine.reorder import ConstantOrder, join_order
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = ["NaiveMatcher", "check_production"]


def check_production(production: Production) -> None:
    """Raise :class:`~adapt.errors.EngineError` if a relational test uses a
    variable that no equality test in its scope binds
    (:func:`adapt.engine.conditions.check_scope`)."""
    check_scope(production.name, production.conditions)


class _JoinOrder:
    """Soar's join order with the hints in force when a production was added."""

    __slots__ = ("multi_attributes", "constants")

    def __init__(self, multi_attributes: Mapping[str, int], constants: ConstantOrder) -> None:
        self.multi_attributes = multi_attributes
        self.constants = constants

    def __call__(self, elements: Sequence[ConditionElement],
                 outer: Iterable[Variable]) -> list[int]:
        return join_order(elements, outer, self.multi_attributes, self.constants)


class NaiveMatcher:
    """Brute-force implementation of :class:`adapt.engine.matcher.Matcher`.

    Every :meth:`take_changes` or :meth:`matches` after a change recomputes
    all matches of all productions: use it as a reference, not in production.
    """

    __slots__ = ("_productions", "_orders", "_joins", "_wmes", "_current", "_reported", "_dirty",
                 "multi_attributes", "constants")

    def __init__(self) -> None:
        self._productions: dict[str, Production] = {}
        #: each production's positive conditions in join order (the Rete's)
        self._orders: dict[str, list[int]] = {}
        #: each production's join order of a conjunctive negation's conditions (the Rete's)
        self._joins: dict[str, JoinOrder] = {}
        #: ``multi-attributes`` hints for the join order of productions added from now on
        self.multi_attributes: dict[str, int] = {}
        #: the order of constants that breaks the join order's last ties
        self.constants = ConstantOrder()
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
        self.constants.add_production(production)
        self._orders[production.name] = join_order(production.conditions, (),
                                                   self.multi_attributes, self.constants)
        self._joins[production.name] = _JoinOrder(dict(self.multi_attributes), self.constants)
        self._dirty = True

    def remove_production(self, name: str) -> None:
        """Remove a production; its matches become pending removals."""
        if name not in self._productions:
            raise EngineError(f"no production named {name} in the matcher")
        del self._productions[name]
        del self._orders[name]
        del self._joins[name]
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
        wmes = WmeIndex(self._wmes.values())
        current: dict[MatchKey, Match] = {}
        for production in self._productions.values():
            order = self._orders[production.name]
            for _, chosen in conjunction_matches(production.conditions, wmes, positives=order,
                                                 order=self._joins[production.name]):
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

