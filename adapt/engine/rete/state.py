"""State shared by every node of one Rete network: the operation counter,
the tokens that hold each WME, and the pending match-set changes.

A pending change is filed under the *flat* key ``(name, timetag, ...)`` (one
tuple: :attr:`Match.key` is ``(name, (timetag, ...))``) and holds the token
that matched, or ``(production, wmes)`` once the production is gone.  The
:class:`~adapt.engine.matcher.Match` records are made only for the changes
that survive until :meth:`NetworkState.take` -- most transient ones cancel
out before that.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Union

from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import Production
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.pnode import ProductionNode
    from adapt.engine.rete.token import Token

__all__ = ["NetworkState", "Pending", "FlatKey", "make_match"]

#: ``(production name, timetag, timetag, ...)``
FlatKey = tuple[Union[str, int], ...]
#: A pending match change: the token, or the production and its WMEs
#: (production order) once the production has been removed.
Pending = Union["Token", tuple[Production, tuple[WME, ...]]]

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
        Pending match-set changes ``flat key -> token or (production, wmes)``
        in the order they happened; an addition and a removal of the same key
        cancel out.
    pnodes : dict
        ``name -> production node`` of the productions in the network.
    """

    __slots__ = ("epoch", "tokens_by_wme", "added", "removed", "pnodes")

    def __init__(self) -> None:
        self.epoch = 0
        self.tokens_by_wme: dict[int, Union[Token, dict[Token, None]]] = {}
        self.added: dict[FlatKey, Pending] = {}
        self.removed: dict[FlatKey, Pending] = {}
        self.pnodes: dict[str, ProductionNode] = {}

    def match_removed(self, key: FlatKey, pending: Pending) -> None:
        """Record that a match disappeared (cancelling a pending addition)."""
        if key in self.added:
            del self.added[key]
        else:
            self.removed[key] = pending

    def detach(self, pnode: ProductionNode) -> None:
        """``pnode`` leaves the network: resolve its pending changes now."""
        del self.pnodes[pnode.name]
        name = pnode.name
        for pending in (self.added, self.removed):
            for key, value in pending.items():
                if key[0] == name and type(value) is not tuple:
                    wmes = pnode.wmes_of(value)  # type: ignore[arg-type]
                    pending[key] = (pnode.production, wmes)

    def _matches(self, pending: dict[FlatKey, Pending]) -> list[Match]:
        pnodes = self.pnodes
        out = []
        append = out.append
        for key, value in pending.items():
            name = key[0]
            if type(value) is tuple:
                production, wmes = value
            else:
                pnode = pnodes[name]  # type: ignore[index]
                production = pnode.production
                wmes = value.wmes  # type: ignore[union-attr]
                reorder = pnode._reorder
                if reorder is not None:
                    wmes = reorder(wmes)
            # make_match, inlined.
            match: Match = _new(Match)
            match.production = production
            match.wmes = wmes
            match.key = match_key = (name, key[1:])  # type: ignore[assignment]
            match._hash = hash(match_key)
            append(match)
        return out

    def take(self) -> tuple[list[Match], list[Match]]:
        """The pending ``(added, removed)`` matches, emptying both."""
        if self.added:
            added = self._matches(self.added)
            self.added = {}
        else:
            added = []
        if self.removed:
            removed = self._matches(self.removed)
            self.removed = {}
        else:
            removed = []
        return added, removed
