"""Production nodes: the bottom of a production's chain; each token that
reaches one is a match.

A production node keeps no memory of its own: its matches are its parent's
emitted tokens, and a match change is recorded in the network state as
``(name, timetags) -> (production, wmes)`` (see :mod:`.state`).
"""

from __future__ import annotations

from operator import itemgetter
from typing import TYPE_CHECKING, Callable

from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import Production
from adapt.engine.rete.state import make_match
from adapt.engine.rete.token import BetaNode, Token
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = ["ProductionNode"]

_timetag = itemgetter(4)


class ProductionNode:
    """Turns tokens into match changes.

    ``order`` maps each positive condition (in the production's order) to
    its level in the token, or is ``None`` when the network kept the
    production's order.
    """

    __slots__ = ("state", "parent", "production", "order", "name", "_reorder")

    def __init__(
        self,
        state: NetworkState,
        parent: BetaNode,
        production: Production,
        order: tuple[int, ...] | None,
    ) -> None:
        self.state = state
        self.parent = parent
        self.production = production
        self.order = order
        self.name = production.name
        #: token WMEs -> production-ordered WMEs (None: already in order)
        self._reorder: Callable[[tuple[WME, ...]], tuple[WME, ...]] | None = (
            None if order is None else _reorderer(order)
        )

    def left_add(self, token: Token) -> None:
        wmes = token.wmes
        reorder = self._reorder
        if reorder is not None:
            wmes = reorder(wmes)
        key = (self.name, tuple(map(_timetag, wmes)))
        state = self.state
        removed = state.removed
        if key in removed:
            del removed[key]
        else:
            state.added[key] = (self.production, wmes)

    def left_remove(self, token: Token) -> None:
        wmes = token.wmes
        reorder = self._reorder
        if reorder is not None:
            wmes = reorder(wmes)
        key = (self.name, tuple(map(_timetag, wmes)))
        state = self.state
        added = state.added
        if key in added:
            del added[key]
        else:
            state.removed[key] = (self.production, wmes)

    def key(self, token: Token) -> tuple[MatchKey, tuple[WME, ...]]:
        """The match key of ``token`` and its WMEs in production order."""
        wmes = token.wmes
        if self._reorder is not None:
            wmes = self._reorder(wmes)
        return (self.name, tuple(map(_timetag, wmes))), wmes

    def matches(self) -> list[Match]:
        """The current matches (the parent's emitted tokens)."""
        out = []
        for token in self.parent.emitted():
            key, wmes = self.key(token)
            out.append(make_match(self.production, wmes, key))
        return out


def _reorderer(order: tuple[int, ...]) -> Callable[[tuple[WME, ...]], tuple[WME, ...]]:
    if len(order) == 1:
        return lambda wmes: (wmes[order[0]],)
    return itemgetter(*order)  # type: ignore[return-value]
