"""State shared by every node of one Rete network: the operation counter,
the tokens that hold each WME, and the pending match-set changes.

Pending changes are kept as ``key -> (production, wmes)``; the
:class:`~adapt.engine.matcher.Match` records are made only for the changes
that survive until :meth:`NetworkState.take` (most transient ones cancel
out before that).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Union

from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import Production
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.token import Token

__all__ = ["NetworkState", "Pending", "make_match"]

#: A pending match change: the production and its WMEs (production order).
Pending = tuple[Production, tuple[WME, ...]]

_new = object.__new__


def make_match(production: Production, wmes: tuple[WME, ...], key: MatchKey) -> Match:
    """``Match(production, wmes)`` without recomputing ``key`` (which must be
    ``(production.name, timetags of wmes)``)."""
    match: Match = _new(Match)
    match.production = production
    match.wmes = wmes
    match.key = key
    match._hash = hash(key)
    return match


class NetworkState:
    """Mutable bookkeeping of one network.

    Attributes
    ----------
    epoch : int
        Incremented by every WME add or remove; negative-node tokens remember
        the epoch they were made in, so that removing a WME never un-counts it
        from a negative-node token created after it had left the network
        (join tokens, which never need it, record 0).
    tokens_by_wme : dict
        ``timetag -> token or {token: None}`` for the tokens whose last WME is
        that WME (tokens made by join nodes): what to delete when the WME goes.
    added, removed : dict
        Pending match-set changes ``key -> (production, wmes)``, keyed by
        :attr:`Match.key`, in the order they happened; an addition and a
        removal of the same key cancel out.
    """

    __slots__ = ("epoch", "tokens_by_wme", "added", "removed")

    def __init__(self) -> None:
        self.epoch = 0
        self.tokens_by_wme: dict[int, Union[Token, dict[Token, None]]] = {}
        self.added: dict[MatchKey, Pending] = {}
        self.removed: dict[MatchKey, Pending] = {}

    def match_added(self, key: MatchKey, pending: Pending) -> None:
        """Record that a match appeared (cancelling a pending removal)."""
        if key in self.removed:
            del self.removed[key]
        else:
            self.added[key] = pending

    def match_removed(self, key: MatchKey, pending: Pending) -> None:
        """Record that a match disappeared (cancelling a pending addition)."""
        if key in self.added:
            del self.added[key]
        else:
            self.removed[key] = pending

    def take(self) -> tuple[list[Match], list[Match]]:
        """The pending ``(added, removed)`` matches, emptying both."""
        pending = self.added
        if pending:
            added = [make_match(p, w, k) for k, (p, w) in pending.items()]
            self.added = {}
        else:
            added = []
        pending = self.removed
        if pending:
            removed = [make_match(p, w, k) for k, (p, w) in pending.items()]
            self.removed = {}
        else:
            removed = []
        return added, removed
