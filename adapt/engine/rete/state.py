"""State shared by every node of one Rete network: the operation counter,
the tokens that hold each WME, and the pending match-set changes."""

from __future__ import annotations

from typing import TYPE_CHECKING

from adapt.engine.matcher import Match, MatchKey

if TYPE_CHECKING:
    from adapt.engine.rete.token import Token

__all__ = ["NetworkState"]


class NetworkState:
    """Mutable bookkeeping of one network.

    Attributes
    ----------
    epoch : int
        Incremented by every WME add or remove; tokens remember the epoch they
        were made in, so that removing a WME never un-counts it from a
        negative-node token created after it had left the network.
    tokens_by_wme : dict
        ``timetag -> {token: None}`` for the tokens whose last WME is that WME
        (tokens made by join nodes): what to delete when the WME goes.
    added, removed : dict
        Pending match-set changes keyed by :attr:`Match.key`, in the order
        they happened; an addition and a removal of the same key cancel out.
    """

    __slots__ = ("epoch", "tokens_by_wme", "added", "removed")

    def __init__(self) -> None:
        self.epoch = 0
        self.tokens_by_wme: dict[int, dict[Token, None]] = {}
        self.added: dict[MatchKey, Match] = {}
        self.removed: dict[MatchKey, Match] = {}

    def match_added(self, match: Match) -> None:
        """Record that ``match`` appeared (cancelling a pending removal)."""
        key = match.key
        if key in self.removed:
            del self.removed[key]
        else:
            self.added[key] = match

    def match_removed(self, match: Match) -> None:
        """Record that ``match`` disappeared (cancelling a pending addition)."""
        key = match.key
        if key in self.added:
            del self.added[key]
        else:
            self.removed[key] = match
