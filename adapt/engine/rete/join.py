"""Join nodes: extend a token with a WME from an alpha memory.

Both memories of a join are hashed on *every* equality test between the new
WME and the token (values included, not just identifiers): the left memory
files each parent token under the tuple of its values at the tested
positions, the right memory files each WME under the tuple of its tested
fields, so an activation from either side meets only its partners.  A join
with one equality test uses the bare value as its key, one with none uses
``None``.  Relational tests whose variables are bound by then are checked on
the pairs the hash lookup returns.

A bucket holding one entry is the entry itself (a :class:`Token` on the
left, a :class:`~adapt.engine.wme.WME` on the right); a second entry turns it
into a dict (``{token: None}`` / ``{timetag: wme}``, in arrival order).  Most
buckets hold one entry, so this saves a dict per token and per WME.

A join test is ``(relation, a_level, a_field, b_level, b_field)``: an operand
with level ``-1`` is a field of the new WME, otherwise ``token.wmes[level][field]``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Hashable, Iterable, Union

from adapt.engine.conditions import RELATIONS
from adapt.engine.rete.alpha import AlphaMemory
from adapt.engine.rete.token import BetaNode, Token
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.state import NetworkState

__all__ = ["JoinTest", "TwoInputNode", "JoinNode", "left_bucket", "right_bucket"]

JoinTest = tuple[str, int, int, int, int]
LeftBucket = Union[Token, dict[Token, None]]
RightBucket = Union[WME, dict[int, WME]]


def left_bucket(bucket: LeftBucket | None) -> Iterable[Token]:
    """The tokens of a left bucket, as a snapshot safe to iterate while
    activating other nodes."""
    if bucket is None:
        return ()
    if isinstance(bucket, dict):
        return list(bucket)
    return (bucket,)


def right_bucket(bucket: RightBucket | None) -> Iterable[WME]:
    """The WMEs of a right bucket."""
    if bucket is None:
        return ()
    if isinstance(bucket, dict):
        return bucket.values()
    return (bucket,)


class TwoInputNode(BetaNode):
    """What joins and negative nodes share: an alpha memory, hashed left and
    right memories, join tests."""

    #: whether the node's WMEs block tokens (negative nodes) rather than
    #: extend them
    blocks = False

    __slots__ = (
        "alpha", "token_fields", "wme_fields", "tests", "left", "right",
        "_n", "_level", "_field", "_wfield",
    )

    def __init__(
        self,
        state: NetworkState,
        parent: BetaNode,
        alpha: AlphaMemory,
        token_fields: tuple[tuple[int, int], ...],
        wme_fields: tuple[int, ...],
        tests: tuple[JoinTest, ...],
    ) -> None:
        super().__init__(state, parent)
        self.alpha = alpha
        self.token_fields = token_fields
        self.wme_fields = wme_fields
        self.tests = tests
        self.left: dict[Hashable, LeftBucket] = {}
        self.right: dict[Hashable, RightBucket] = {}
        self._n = len(wme_fields)
        self._level, self._field = token_fields[0] if token_fields else (0, 0)
        self._wfield = wme_fields[0] if wme_fields else 0

    def signature(self) -> tuple[object, ...]:
        """What two nodes must share to be the same node."""
        return (type(self), self.alpha, self.token_fields, self.wme_fields, self.tests)

    def left_key(self, wmes: tuple[WME, ...]) -> Hashable:
        """The hash key of a token (given its WMEs)."""
        n = self._n
        if n == 1:
            return wmes[self._level][self._field]
        if n == 0:
            return None
        return tuple([wmes[level][field] for level, field in self.token_fields])

    def right_key(self, wme: WME) -> Hashable:
        """The hash key of a WME."""
        n = self._n
        if n == 1:
            return wme[self._wfield]
        if n == 0:
            return None
        return tuple([wme[field] for field in self.wme_fields])

    def check(self, wmes: tuple[WME, ...], wme: WME) -> bool:
        """Whether the join tests hold between a token and a WME."""
        for relation, al, af, bl, bf in self.tests:
            a = wme[af] if al < 0 else wmes[al][af]
            b = wme[bf] if bl < 0 else wmes[bl][bf]
            if not RELATIONS[relation](a, b):
                return False
        return True

    def index_left(self, token: Token, key: Hashable) -> None:
        """File ``token`` in the left memory under ``key``."""
        left = self.left
        bucket = left.get(key)
        if bucket is None:
            left[key] = token
        elif isinstance(bucket, dict):
            bucket[token] = None
        else:
            left[key] = {bucket: None, token: None}

    def unindex_left(self, token: Token) -> None:
        """Take ``token`` out of the left memory."""
        n = self._n
        wmes = token.wmes
        if n == 1:
            key: Hashable = wmes[self._level][self._field]
        elif n == 0:
            key = None
        else:
            key = tuple([wmes[level][field] for level, field in self.token_fields])
        left = self.left
        bucket = left[key]
        if bucket is token:
            del left[key]
        else:
            del bucket[token]  # type: ignore[union-attr]
            if not bucket:
                del left[key]

    def index_right(self, wme: WME) -> Hashable:
        """File ``wme`` in the right memory; returns its key."""
        n = self._n
        if n == 1:
            key: Hashable = wme[self._wfield]
        elif n == 0:
            key = None
        else:
            key = tuple([wme[field] for field in self.wme_fields])
        right = self.right
        bucket = right.get(key)
        if bucket is None:
            right[key] = wme
        elif isinstance(bucket, dict):
            bucket[wme[4]] = wme
        else:
            right[key] = {bucket[4]: bucket, wme[4]: wme}
        return key

    def right_remove(self, wme: WME) -> None:
        """``wme`` left the alpha memory: take it out of the right memory."""
        n = self._n
        if n == 1:
            key: Hashable = wme[self._wfield]
        elif n == 0:
            key = None
        else:
            key = tuple([wme[field] for field in self.wme_fields])
        right = self.right
        bucket = right[key]
        if isinstance(bucket, dict):
            del bucket[wme[4]]
            if not bucket:
                del right[key]
        else:
            del right[key]

    def left_add(self, token: Token) -> None:
        """The parent node emitted ``token``."""
        raise NotImplementedError

    def left_remove(self, token: Token) -> None:
        """The parent node withdrew ``token``."""
        raise NotImplementedError

    def right_add(self, wme: WME) -> None:
        """``wme`` entered the alpha memory."""
        raise NotImplementedError

    def unblock(self, wme: WME) -> None:
        """``wme`` left the network (negative nodes count the WMEs that block a token)."""
        raise NotImplementedError

    def fill_right(self) -> None:
        """Load the alpha memory's current WMEs (a new node)."""
        for wme in self.alpha.items.values():
            self.index_right(wme)


class JoinNode(TwoInputNode):
    """A positive condition: one token per consistent (token, WME) pair.

    Deliberately inlined copies, kept because both activations are the hot path
    of the whole matcher: :meth:`left_add` copies :meth:`left_key` and
    :meth:`index_left`, :meth:`right_add` copies :meth:`right_key` and
    :meth:`index_right`, and both copy the registration of a new token under
    its last WME's timetag (the inverse of :meth:`drop`).  Calling the functions
    the Rete used to inline cost the pure engine 17% of its decisions per
    second (``docs/performance.md``, "The price of one loop"); these are not
    measured apart.  ``tests/engine/test_rete_inlined.py`` checks that the
    copies agree with the functions.
    """

    kind = 1
    __slots__ = ()

    def left_add(self, token: Token) -> None:
        wmes = token.wmes
        # inlined: left_key(wmes), then index_left(token, key) (see the class docstring)
        n = self._n
        if n == 1:
            key: Hashable = wmes[self._level][self._field]
        elif n == 0:
            key = None
        else:
            key = tuple([wmes[level][field] for level, field in self.token_fields])
        left = self.left
        bucket = left.get(key)
        if bucket is None:
            left[key] = token
        elif isinstance(bucket, dict):
            bucket[token] = None
        else:
            left[key] = {bucket: None, token: None}
        found = self.right.get(key)
        if found is None:
            return
        tests = self.tests
        partners: Iterable[WME]
        if isinstance(found, dict):
            # Emission never changes a right memory: no copy needed.
            partners = found.values()
        else:
            if tests and not self.check(wmes, found):
                return
            partners = (found,)
            tests = ()
        registries = self.state.tokens_by_wme
        children = self.children
        for wme in partners:
            if tests and not self.check(wmes, wme):
                continue
            new = Token(token, wmes + (wme,), self, 0)
            timetag = wme[4]  # inlined: the registration drop() undoes
            registry = registries.get(timetag)
            if registry is None:
                registries[timetag] = new
            elif isinstance(registry, dict):
                registry[new] = None
            else:
                registries[timetag] = {registry: None, new: None}
            for child in children:
                child.left_add(new)

    def left_remove(self, token: Token) -> None:
        """The parent withdrew ``token``: forget it (its children go through
        the token tree)."""
        self.unindex_left(token)

    def right_add(self, wme: WME) -> None:
        """``wme`` entered the alpha memory."""
        # inlined: index_right(wme), right_key included (see the class docstring)
        n = self._n
        if n == 1:
            key: Hashable = wme[self._wfield]
        elif n == 0:
            key = None
        else:
            key = tuple([wme[field] for field in self.wme_fields])
        right = self.right
        timetag = wme[4]
        bucket = right.get(key)
        if bucket is None:
            right[key] = wme
        elif isinstance(bucket, dict):
            bucket[timetag] = wme
        else:
            right[key] = {bucket[4]: bucket, timetag: wme}
        found = self.left.get(key)
        if found is None:
            return
        tests = self.tests
        parents: Iterable[Token]
        if isinstance(found, dict):
            parents = list(found)
        else:
            if tests and not self.check(found.wmes, wme):
                return
            parents = (found,)
            tests = ()
        registries = self.state.tokens_by_wme
        children = self.children
        for parent in parents:
            if tests and not self.check(parent.wmes, wme):
                continue
            new = Token(parent, parent.wmes + (wme,), self, 0)
            registry = registries.get(timetag)  # inlined: the registration drop() undoes
            if registry is None:
                registries[timetag] = new
            elif isinstance(registry, dict):
                registry[new] = None
            else:
                registries[timetag] = {registry: None, new: None}
            for child in children:
                child.left_add(new)

    def drop(self, token: Token) -> None:
        registries = self.state.tokens_by_wme
        timetag = token.wmes[-1][4]
        registry = registries.get(timetag)
        if registry is token:
            del registries[timetag]
        elif isinstance(registry, dict):
            registry.pop(token, None)
            if not registry:
                del registries[timetag]
