"""The matcher interface shared by the Rete and the brute-force matcher.

A matcher holds productions and the current working memory and reports, on
request, how the *match set* changed: which matches appeared and which
disappeared since the last call.  The decision cycle feeds it the WME changes
of one phase (after working memory has applied its buffered changes) and then
asks for :meth:`Matcher.take_changes`.

Semantics every implementation keeps:

* A :class:`Match` is one consistent assignment of WMEs to a production's
  positive conditions (in :attr:`Production.positive_conditions` order) such
  that every negated condition and conjunctive negation has no match.
* ``take_changes`` returns ``(added, removed)``, each in the order the changes
  happened.  A match that appeared and disappeared again between two calls is
  in neither list; so is one that disappeared and reappeared with the same WMEs.
* ``add_production`` makes the production's matches against the current WMEs
  pending additions; ``remove_production`` makes its current matches pending
  removals.
* ``matches()`` is the current match set (every production), in no particular
  order.

Examples
--------
Every matcher passes the same conformance checks (see ``tests/engine``); the
brute-force :class:`adapt.engine.naive.NaiveMatcher` is the reference.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable, Protocol, runtime_checkable

from adapt.engine.production import Production, Variable
from adapt.engine.symbols import Symbol
from adapt.engine.wme import WME

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.reorder import ConstantOrder

__all__ = ["Match", "Matcher", "RawMatcher", "MatchKey", "FlatKey", "MatchChanges"]

#: ``(production name, timetags of the matched WMEs)``: a match's identity.
MatchKey = tuple[str, tuple[int, ...]]
#: A match's identity as one flat tuple: ``(production name, timetag, ...)``.
FlatKey = tuple[Any, ...]
#: Match-set changes as the kernel files them: ``(added, removed)``, each a dict
#: ``flat key -> matched WMEs`` (condition order), in the order they happened.
MatchChanges = tuple[dict[FlatKey, tuple[WME, ...]], dict[FlatKey, tuple[WME, ...]]]


class Match:
    """One match (token) of a production.

    Two matches are equal when they are of the same production over the same
    WMEs.
    """

    __slots__ = ("production", "wmes", "key", "_hash")

    def __init__(self, production: Production, wmes: tuple[WME, ...],
                 key: MatchKey | None = None) -> None:
        self.production = production
        self.wmes = wmes
        #: ``(name, timetags)``; a caller that has it passes it (it must be exactly that)
        self.key: MatchKey = key if key is not None else (
            production.name, tuple(w.timetag for w in wmes))
        self._hash = hash(self.key)

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Match) and self.key == other.key

    def bindings(self) -> dict[Variable, Symbol]:
        """The values bound to the production's variables by this match."""
        return self.production.bindings(self.wmes)

    def __repr__(self) -> str:
        return f"Match({self.production.name}, {list(self.key[1])})"


class Matcher(Protocol):
    """What the decision cycle needs from a matcher.

    ``multi_attributes`` holds the agent's ``multi-attributes`` hints
    (attribute -> expected number of values): the join order of the
    productions added after a hint (:mod:`adapt.engine.reorder`).
    """

    multi_attributes: dict[str, int]
    #: the order of constants in Soar's symbol table (:class:`adapt.engine.reorder.ConstantOrder`)
    constants: ConstantOrder

    def add_production(self, production: Production) -> None:
        """Add a production; its current matches become pending additions.

        A production with the name of one already present must first be
        removed with :meth:`remove_production`.
        """

    def remove_production(self, name: str) -> None:
        """Remove a production; its current matches become pending removals."""

    def add_wme(self, wme: WME) -> None:
        """Tell the matcher that ``wme`` is now in working memory."""

    def remove_wme(self, wme: WME) -> None:
        """Tell the matcher that ``wme`` (previously added) has left working memory."""

    def take_changes(self) -> tuple[list[Match], list[Match]]:
        """``(added, removed)`` matches since the previous call, in order."""

    def matches(self) -> Iterable[Match]:
        """The current match set."""


@runtime_checkable
class RawMatcher(Matcher, Protocol):
    """A matcher that also gives its changes without building :class:`Match`
    records (the Rete): the kernel's fast path."""

    def take_raw(self) -> MatchChanges:
        """:meth:`Matcher.take_changes` as :data:`MatchChanges`; the caller
        reads them at once and must not keep them."""
