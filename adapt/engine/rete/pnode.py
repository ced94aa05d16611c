"""Production nodes: the bottom of a production's chain; each token that
reaches one is a match.

A production node keeps no memory of its own: its matches are its parent's
emitted tokens, and a match change is recorded in the network state as
``(name, timetag, ...) -> wmes`` (see :mod:`.state`).
"""

from __future__ import annotations

from operator import itemgetter
from typing import TYPE_CHECKING, Callable

from adapt.engine.matcher import Match
from adapt.engine.production import Production
from adapt.engine.rete.state import FlatKey
from adapt.engine.rete.token import BetaNode, Token
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = ["ProductionNode"]

_TIMETAG = itemgetter(4)



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

    def flat_key(self, token: Token) -> FlatKey:
        """``(name, timetag, ...)`` of the match ``token`` makes."""
        return self.key_and_wmes(token)[0]

    def key_and_wmes(self, token: Token) -> tuple[FlatKey, tuple[WME, ...]]:
        """The match's flat key and its WMEs in the production's condition order."""
        wmes = token.wmes
        reorder = self._reorder
        if reorder is not None:
            wmes = reorder(wmes)
        return (self.name, *map(_TIMETAG, wmes)), wmes

    def left_add(self, token: Token) -> None:
        key, wmes = self.key_and_wmes(token)
        state = self.state
        removed = state.removed
        if key in removed:
            del removed[key]
        else:
            state.added[key] = wmes

    def left_remove(self, token: Token) -> None:
        key, wmes = self.key_and_wmes(token)
        state = self.state
        added = state.added
        if key in added:
            del added[key]
        else:
            state.removed[key] = wmes

    def wmes_of(self, token: Token) -> tuple[WME, ...]:
        """The WMEs of ``token`` in the production's condition order."""
        reorder = self._reorder
        return token.wmes if reorder is None else reorder(token.wmes)

    def matches(self) -> list[Match]:
        """The current matches (the parent's emitted tokens)."""
        out: list[Match] = []
        for token in self.parent.emitted():
            wmes = self.wmes_of(token)
            out.append(Match(self.production, wmes))
        return out


def _reorderer(order: tuple[int, ...]) -> Callable[[tuple[WME, ...]], tuple[WME, ...]]:
    if len(order) == 1:
        return lambda wmes: (wmes[order[0]],)
    return itemgetter(*order)
