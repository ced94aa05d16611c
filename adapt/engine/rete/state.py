"""State shared by every node of one Rete network: the operation counter,
the tokens that hold each WME, and the pending match-set changes.

A pending change is filed under the *flat* key ``(name, timetag, ...)`` (one
tuple: :attr:`Match.key` is ``(name, (timetag, ...))``) and holds the
matched WMEs in the production's condition order.  The
:class:`~adapt.engine.matcher.Match` records are made only by
:meth:`NetworkState.take`, for the changes that survive until then (most
transient ones cancel out before); the kernel takes the raw dictionaries
(:meth:`NetworkState.take_raw`) and never builds them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Union

from adapt.engine.matcher import FlatKey, Match
from adapt.engine.production import Production
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.pnode import ProductionNode
    from adapt.engine.rete.token import Token

__all__ = ["NetworkState", "Pending", "FlatKey"]

#: A pending match change: the matched WMEs, in the production's order.
Pending = tuple[WME, ...]



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
        Pending match-set changes ``flat key -> wmes`` (production order) in
        the order they happened; an addition and a removal of the same key
        cancel out.
    pnodes : dict
        ``name -> production node`` of the productions in the network.
    orphans : dict
        ``flat key -> production`` for the pending changes of productions
        removed since the last take (their name may already be reused).
    """

    __slots__ = ("epoch", "tokens_by_wme", "added", "removed", "pnodes", "orphans")

    def __init__(self) -> None:
        self.epoch = 0
        self.tokens_by_wme: dict[int, Union[Token, dict[Token, None]]] = {}
        self.added: dict[FlatKey, Pending] = {}
        self.removed: dict[FlatKey, Pending] = {}
        self.pnodes: dict[str, ProductionNode] = {}
        self.orphans: dict[FlatKey, Production] = {}

    def match_removed(self, key: FlatKey, pending: Pending) -> None:
        """Record that a match disappeared (cancelling a pending addition)."""
        if key in self.added:
            del self.added[key]
        else:
            self.removed[key] = pending

    def detach(self, pnode: ProductionNode) -> None:
        """``pnode`` leaves the network: remember the production of its
        pending changes."""
        del self.pnodes[pnode.name]
        name = pnode.name
        for pending in (self.added, self.removed):
            for key in pending:
                if key[0] == name:
                    self.orphans[key] = pnode.production

    def _matches(self, pending: dict[FlatKey, Pending]) -> list[Match]:
        pnodes = self.pnodes
        orphans = self.orphans
        out: list[Match] = []
        append = out.append
        for key, wmes in pending.items():
            name = key[0]
            production = orphans.get(key) if orphans else None
            if production is None:
                production = pnodes[name].production
            append(Match(production, wmes, (name, key[1:])))
        return out

    def take_raw(self) -> tuple[dict[FlatKey, Pending], dict[FlatKey, Pending]]:
        """The pending ``(added, removed)`` changes as they are kept
        (``flat key -> wmes``, in order), emptying both: what
        :meth:`take` returns without building a :class:`Match` per change."""
        added, removed = self.added, self.removed
        if added:
            self.added = {}
        if removed:
            self.removed = {}
        if self.orphans:
            self.orphans = {}
        return added, removed

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
        if self.orphans:
            self.orphans = {}
        return added, removed
