"""Tokens (partial matches) and the tree operations on them.

A token is one row of a node's memory: the WMEs matched by the positive
conditions above it (``wmes``, one per join level), a link to the token it
extends (``parent``) and links to the tokens that extend it (``children``).
Removing a token removes its whole subtree through those links; nothing is
ever found by scanning a memory.

To keep allocations (and the cyclic garbage collector's work) low, a token's
``children`` is ``None`` (no child), the child token itself (one child) or a
dict ``{token: None}`` (several, in creation order); the hashed memories of
the nodes use the same single-entry convention (see :mod:`.join`).

A token is *emitted* (visible to the nodes below its node) while its
``count`` is 0.  Join tokens always have count 0; a negative node's token
counts the WMEs that block it, a conjunctive-negation owner token counts the
results of its subnetwork.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Iterable, Protocol, Union

from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = [
    "Token", "Successor", "BetaNode", "RootNode", "emit", "retract", "delete_token",
    "children_of", "unlink",
]


class Token:
    """A partial match held by one node; registers itself with its parent."""

    __slots__ = ("parent", "wmes", "node", "children", "count", "epoch", "dead")

    def __init__(
        self, parent: Token | None, wmes: tuple[WME, ...], node: BetaNode, epoch: int
    ) -> None:
        self.parent = parent
        self.wmes = wmes
        self.node = node
        self.children: Union[None, Token, dict[Token, None]] = None
        self.count = 0
        self.epoch = epoch
        self.dead = False
        if parent is not None:
            siblings = parent.children
            if siblings is None:
                parent.children = self
            elif isinstance(siblings, dict):
                siblings[self] = None
            else:
                parent.children = {siblings: None, self: None}

    def __repr__(self) -> str:
        return f"Token({[w.timetag for w in self.wmes]}, count={self.count})"


def children_of(token: Token) -> Iterable[Token]:
    """The tokens that extend ``token``, oldest first."""
    below = token.children
    if below is None:
        return ()
    if isinstance(below, dict):
        return below
    return (below,)


def unlink(token: Token) -> None:
    """Remove ``token`` from its parent's ``children`` (the parent stays)."""
    parent = token.parent
    if parent is not None:
        siblings = parent.children
        if siblings is token:
            parent.children = None
        elif isinstance(siblings, dict):
            siblings.pop(token, None)


class Successor(Protocol):
    """A node below a token-holding node."""

    def left_add(self, token: Token) -> None:
        """The parent node emitted ``token``."""

    def left_remove(self, token: Token) -> None:
        """The parent node withdrew ``token`` (its child tokens are deleted
        separately, through the token tree)."""


class BetaNode:
    """Base of the nodes that hold tokens (root, join, negative, NCC).

    ``children`` are the nodes that receive this node's emitted tokens
    (``left_add``) and hear of their retraction (``left_remove``).
    """

    #: non-zero when :func:`delete_token` must call :meth:`drop` to forget a
    #: token of this node (joins: the WME registry; negative nodes: the left memory)
    kind = 0

    __slots__ = ("state", "parent", "children", "shared")

    def __init__(self, state: NetworkState, parent: BetaNode | None) -> None:
        self.state = state
        self.parent = parent
        self.children: list[Successor] = []
        #: the children that productions may share, by their signature: a
        #: new production finds a node to share in one lookup (a scan of
        #: ``children`` made loading quadratic)
        self.shared: dict[tuple[object, ...], BetaNode] = {}

    def drop(self, token: Token) -> None:
        """Forget ``token``, one of this node's own tokens, which is being
        deleted (the base class keeps no index of its tokens)."""

    def up(self) -> BetaNode | None:
        """The node above in Soar's sense (a conjunctive negation's node:
        the bottom of its subnetwork)."""
        return self.parent

    def tokens(self) -> list[Token]:
        """All of this node's tokens, emitted or not (for building and pruning)."""
        parent = self.parent
        assert parent is not None
        out: list[Token] = []
        for t in parent.emitted():
            out.extend(c for c in children_of(t) if c.node is self)
        return out

    def emitted(self) -> list[Token]:
        """This node's emitted tokens."""
        return [t for t in self.tokens() if t.count == 0]


class RootNode(BetaNode):
    """The top of the beta network: one empty token, always emitted."""

    __slots__ = ("token",)

    def __init__(self, state: NetworkState) -> None:
        super().__init__(state, None)
        self.token = Token(None, (), self, 0)

    def tokens(self) -> list[Token]:
        return [self.token]


def emit(token: Token) -> None:
    """Pass ``token`` to the children of its node."""
    for child in token.node.children:
        child.left_add(token)


def retract(token: Token) -> None:
    """Withdraw ``token`` from the children of its node and delete the tokens
    below it; ``token`` itself stays (it became blocked)."""
    for child in token.node.children:
        child.left_remove(token)
    below = token.children
    if below is not None:
        token.children = None
        if isinstance(below, dict):
            for t in below:
                delete_token(t)
        else:
            delete_token(below)


def delete_token(token: Token) -> None:
    """Delete ``token`` and its subtree.  The caller unlinks it from its
    parent's ``children`` if the parent stays."""
    token.dead = True
    node = token.node
    if token.count == 0:
        for child in node.children:
            child.left_remove(token)
    below = token.children
    if below is not None:
        token.children = None
        if isinstance(below, dict):
            for t in below:
                delete_token(t)
        else:
            delete_token(below)
    if node.kind:
        node.drop(token)
