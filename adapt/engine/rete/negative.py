"""Negative nodes: a negated condition ``-(...)``.

The node keeps one token per parent token, hashed like a join's left memory,
and counts in ``token.count`` the WMEs of its right memory that match it.  A
token is emitted while its count is 0; the first matching WME retracts it,
the removal of the last one emits it again.
"""

from __future__ import annotations

from adapt.engine.rete.join import TwoInputNode, left_bucket, right_bucket
from adapt.engine.rete.token import Token, emit, retract
from adapt.engine.wme import WME

__all__ = ["NegativeNode"]


class NegativeNode(TwoInputNode):
    """Passes a parent token on while no WME matches the negated condition."""

    blocks = True
    kind = 2
    __slots__ = ()

    def left_add(self, token: Token) -> None:
        if not self.r_linked:
            self.relink_right()
        mine = Token(token, token.wmes, self, self.state.epoch)
        key = self.left_key(token.wmes)
        self.index_left(mine, key)
        partners = self.right.get(key)
        if partners is not None:
            if self.tests:
                wmes = token.wmes
                mine.count = sum(1 for w in right_bucket(partners) if self.check(wmes, w))
            else:
                mine.count = len(partners) if isinstance(partners, dict) else 1
        if mine.count == 0:
            for child in self.children:
                child.left_add(mine)

    def left_remove(self, token: Token) -> None:
        """Nothing to do: this node's token is a child of ``token`` and is
        deleted with it."""

    def tokens(self) -> list[Token]:
        """This node's tokens: its left memory."""
        out: list[Token] = []
        for bucket in self.left.values():
            out.extend(left_bucket(bucket))
        return out

    def drop(self, token: Token) -> None:
        self.unindex_left(token)

    def right_join(self, wme: WME) -> None:
        """``wme`` (filed already) entered the alpha memory: it blocks the
        tokens it matches, the newest first."""
        tokens = self.left.get(self.right_key(wme))
        if tokens is not None:
            tests = self.tests
            for token in reversed(list(left_bucket(tokens))):
                if tests and not self.check(token.wmes, wme):
                    continue
                token.count += 1
                if token.count == 1:
                    retract(token)

    def unblock(self, wme: WME) -> None:
        """After ``wme`` left the network: un-count it from the tokens that
        counted it (those made before this removal began)."""
        tokens = self.left.get(self.right_key(wme))
        if tokens is not None:
            epoch = self.state.epoch
            tests = self.tests
            for token in reversed(list(left_bucket(tokens))):
                if token.epoch == epoch or token.dead:
                    continue
                if tests and not self.check(token.wmes, wme):
                    continue
                token.count -= 1
                if token.count == 0:
                    emit(token)
