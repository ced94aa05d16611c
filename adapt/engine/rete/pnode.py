"""Production nodes: the bottom of a production's chain; each token that
reaches one is a match."""

from __future__ import annotations

from typing import TYPE_CHECKING

from adapt.engine.matcher import Match
from adapt.engine.production import Production
from adapt.engine.rete.token import BetaNode, Token

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = ["ProductionNode"]


class ProductionNode:
    """Turns tokens into :class:`~adapt.engine.matcher.Match` records.

    ``order`` maps each positive condition (in the production's order) to
    its level in the token, or is ``None`` when the network kept the
    production's order.
    """

    __slots__ = ("state", "parent", "production", "order", "matches")

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
        self.matches: dict[Token, Match] = {}

    def left_add(self, token: Token) -> None:
        order = self.order
        wmes = token.wmes
        if order is not None:
            wmes = tuple([wmes[i] for i in order])
        match = Match(self.production, wmes)
        self.matches[token] = match
        self.state.match_added(match)

    def left_remove(self, token: Token) -> None:
        self.state.match_removed(self.matches.pop(token))
