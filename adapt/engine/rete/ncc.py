"""Conjunctive negations ``-{...}``, after Doorenbos's NCC node and partner.

The conditions inside the braces form a subnetwork hanging below the same
parent as the :class:`NccNode`; its bottom feeds the :class:`NccPartner`.
For every parent token the NCC node makes an *owner* token whose ``count`` is
the number of subnetwork results that extend that parent token; the owner is
emitted while the count is 0.  The partner finds a result's parent token by
walking ``depth`` parent links up from the result, and the owner through the
NCC node's ``owners`` index -- no scanning.

The subnetwork is built (and so activated) before the NCC node, so a new
parent token's results usually exist before its owner does; the owner then
starts blocked and nothing downstream sees a transient match.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from adapt.engine.rete.token import BetaNode, Token, emit, retract

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = ["NccNode", "NccPartner"]


class NccPartner:
    """Collects the results of a conjunctive negation's subnetwork."""

    __slots__ = ("parent", "depth", "ncc", "results")

    def __init__(self, parent: BetaNode, depth: int) -> None:
        self.parent = parent
        self.depth = depth
        self.ncc: NccNode | None = None
        self.results: dict[Token, dict[Token, None]] = {}

    def _owner_parent(self, result: Token) -> Token:
        token = result
        for _ in range(self.depth):
            token = token.parent  # type: ignore[assignment]
        return token

    def left_add(self, token: Token) -> None:
        above = self._owner_parent(token)
        bucket = self.results.get(above)
        if bucket is None:
            self.results[above] = {token: None}
        else:
            bucket[token] = None
        ncc = self.ncc
        owner = ncc.owners.get(above) if ncc is not None else None
        if owner is not None:
            owner.count += 1
            if owner.count == 1:
                retract(owner)

    def left_remove(self, token: Token) -> None:
        above = self._owner_parent(token)
        bucket = self.results[above]
        del bucket[token]
        if not bucket:
            del self.results[above]
        ncc = self.ncc
        owner = ncc.owners.get(above) if ncc is not None else None
        # When the parent token itself is going (deleted, or blocked and
        # being retracted), its owner goes with it: leave the owner alone.
        if owner is not None and not above.dead and above.count == 0:
            owner.count -= 1
            if owner.count == 0:
                emit(owner)


class NccNode(BetaNode):
    """Passes a parent token on while its subnetwork has no result for it."""

    __slots__ = ("partner", "owners")

    def __init__(self, state: NetworkState, parent: BetaNode, partner: NccPartner) -> None:
        super().__init__(state, parent)
        self.partner = partner
        self.owners: dict[Token, Token] = {}
        partner.ncc = self

    def signature(self) -> tuple[object, ...]:
        """What two nodes must share to be the same node."""
        return (type(self), self.partner.parent, self.partner.depth)

    def left_add(self, token: Token) -> None:
        owner = Token(token, token.wmes, self, self.state.epoch)
        results = self.partner.results.get(token)
        owner.count = len(results) if results else 0
        self.owners[token] = owner
        if owner.count == 0:
            for child in self.children:
                child.left_add(owner)

    def left_remove(self, token: Token) -> None:
        self.owners.pop(token, None)

    def up(self) -> BetaNode | None:
        """The bottom of the subnetwork (Soar goes up through it)."""
        return self.partner.parent

    def tokens(self) -> list[Token]:
        """This node's owner tokens."""
        return list(self.owners.values())
