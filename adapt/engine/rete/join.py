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

Order.  Activations meet their partners the newest first, and a node's
linking follows Soar's right and left unlinking (``rete.cpp``): a node whose
left memory is empty leaves its alpha memory's ``linked`` list and comes back
where Soar's ``relink_to_right_mem`` puts it; a join whose alpha memory is
empty is *left-unlinked* (it files the tokens it gets but joins nothing)
until a WME arrives, when it goes first among its parent's joins that hash
on the same variable (Soar's shared memory node).  None of this changes
what matches, only the order in which matches are found, which is the order
Soar fires them in (reversed).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Hashable, Iterable, Union

from adapt.engine.conditions import RELATIONS
from adapt.engine.rete.alpha import AlphaMemory
from adapt.engine.rete.token import BetaNode, Token, children_of
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
        "_n", "_level", "_field", "_wfield", "_level2", "_field2", "_wfield2",
        "r_linked", "l_linked", "group", "same_am",
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
        # the second field of a two-field key (the commonest longer key)
        self._level2, self._field2 = token_fields[1] if len(token_fields) > 1 else (0, 0)
        self._wfield2 = wme_fields[1] if len(wme_fields) > 1 else 0
        #: in the alpha memory's ``linked`` list (Soar: not right-unlinked)
        self.r_linked = False
        #: joins what it gets from the left (Soar: not left-unlinked)
        self.l_linked = True
        #: where the identifier's binding comes from (the joins of one parent
        #: that share it share Soar's memory node); None: not hashed
        self.group: tuple[int, int] | None = None
        #: the ancestors with the same alpha group, nearest first (found
        #: when first needed)
        self.same_am: tuple[TwoInputNode, ...] | None = None

    def relink_right(self) -> None:
        """Back into the alpha memory's ``linked`` list (Soar's
        ``relink_to_right_mem``): before the nearest ancestor with the same
        alpha memory that is in it, or at the end."""
        linked = self.alpha.group.linked
        same_am = self.same_am
        if same_am is None:
            same_am = self.same_am = self._same_am_ancestors()
        for ancestor in same_am:
            if ancestor.r_linked:
                linked.insert(linked.index(ancestor), self)
                break
        else:
            linked.append(self)
        self.r_linked = True

    def _same_am_ancestors(self) -> tuple[TwoInputNode, ...]:
        """The ancestors with this node's alpha group, nearest first (Soar's
        ``nearest_ancestor_with_same_am``, which goes up a conjunctive
        negation's subnetwork from its CN node)."""
        group = self.alpha.group
        out: list[TwoInputNode] = []
        up = self.parent
        while up is not None:
            if isinstance(up, TwoInputNode) and up.alpha.group is group:
                out.append(up)
            up = up.up()
        return tuple(out)

    def unlink_right(self) -> None:
        """Out of the alpha memory's ``linked`` list (Soar's ``unlink_from_right_mem``)."""
        self.alpha.group.linked.remove(self)
        self.r_linked = False

    def relink_left(self) -> None:
        """Joins again (Soar's ``relink_to_left_mem``): first among the
        parent's joins that share its memory node."""
        self.l_linked = True
        parent = self.parent
        if parent is None or parent.parent is None:  # the root emits no more tokens
            return
        children = parent.children
        first = -1
        for i, child in enumerate(children):
            if isinstance(child, JoinNode) and child.group == self.group:
                if child is self:
                    if first < 0:
                        return
                    del children[i]
                    children.insert(first, self)
                    return
                if first < 0:
                    first = i

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
        if n == 2:
            return (wmes[self._level][self._field], wmes[self._level2][self._field2])
        return tuple([wmes[level][field] for level, field in self.token_fields])

    def right_key(self, wme: WME) -> Hashable:
        """The hash key of a WME."""
        n = self._n
        if n == 1:
            return wme[self._wfield]
        if n == 0:
            return None
        if n == 2:
            return (wme[self._wfield], wme[self._wfield2])
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
        """Take ``token`` out of the left memory (an empty left memory takes
        a linked node out of the alpha memory's ``linked`` list)."""
        n = self._n
        wmes = token.wmes
        if n == 1:
            key: Hashable = wmes[self._level][self._field]
        elif n == 0:
            key = None
        else:
            key = ((wmes[self._level][self._field], wmes[self._level2][self._field2])
                if n == 2 else tuple([wmes[level][field] for level, field in self.token_fields]))
        left = self.left
        bucket = left[key]
        if bucket is token:
            del left[key]
            if not left and self.l_linked and self.r_linked:
                self.unlink_right()
        else:
            del bucket[token]  # type: ignore[union-attr]
            if not bucket:
                del left[key]
                if not left and self.l_linked and self.r_linked:
                    self.unlink_right()

    def index_right(self, wme: WME) -> Hashable:
        """File ``wme`` in the right memory; returns its key."""
        n = self._n
        if n == 1:
            key: Hashable = wme[self._wfield]
        elif n == 0:
            key = None
        else:
            key = ((wme[self._wfield], wme[self._wfield2]) if n == 2
                else tuple([wme[field] for field in self.wme_fields]))
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
            key = ((wme[self._wfield], wme[self._wfield2]) if n == 2
                else tuple([wme[field] for field in self.wme_fields]))
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
        """``wme`` entered the alpha memory: file it and join it."""
        self.index_right(wme)
        self.right_join(wme)

    def right_join(self, wme: WME) -> None:
        """``wme`` (filed already) entered the alpha memory: join it."""
        raise NotImplementedError

    def unblock(self, wme: WME) -> None:
        """``wme`` left the network (negative nodes count the WMEs that block a token)."""
        raise NotImplementedError

    def tokens(self) -> list[Token]:
        """The tokens this node made: children of the tokens in its left
        memory (none while either memory is empty)."""
        if not self.left or not self.right:
            return []
        out: list[Token] = []
        for bucket in self.left.values():
            for t in left_bucket(bucket):
                out.extend(c for c in children_of(t) if c.node is self)
        return out

    def fill_right(self) -> None:
        """Load the alpha memory's current WMEs (a new node)."""
        for wme in self.alpha.items.values():
            self.index_right(wme)


class JoinNode(TwoInputNode):
    """A positive condition: one token per consistent (token, WME) pair.

    Deliberately inlined copies, kept because both activations are the hot path
    of the whole matcher: :meth:`left_add` copies :meth:`left_key` and
    :meth:`index_left`, :meth:`right_join` copies :meth:`right_key`, and both
    copy the registration of a new token under its last WME's timetag (the
    inverse of :meth:`drop`).  Calling the functions the Rete used to inline
    cost the pure engine 17% of its decisions per second
    (``docs/performance.md``, "The price of one loop").
    ``tests/engine/test_rete_inlined.py`` checks that the copies agree with the
    functions.
    """

    kind = 1
    __slots__ = ()

    def left_add(self, token: Token) -> None:
        wmes = token.wmes
        n = self._n
        if n == 1:
            key: Hashable = wmes[self._level][self._field]
        elif n == 0:
            key = None
        else:
            key = ((wmes[self._level][self._field], wmes[self._level2][self._field2])
                if n == 2 else tuple([wmes[level][field] for level, field in self.token_fields]))
        left = self.left
        bucket = left.get(key)
        if bucket is None:
            left[key] = token
        elif isinstance(bucket, dict):
            bucket[token] = None
        else:
            left[key] = {bucket: None, token: None}
        if not self.l_linked:
            return
        if not self.r_linked:
            self.relink_right()
            if not self.alpha.group.count:
                self.l_linked = False
                return
        found = self.right.get(key)
        if found is None:
            return
        tests = self.tests
        partners: Iterable[WME]
        if isinstance(found, dict):
            # Emission never changes a right memory: no copy needed.  The
            # newest WME first, as Soar's right memories are kept.
            partners = reversed(found.values())
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
            timetag = wme[4]
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

    def right_join(self, wme: WME) -> None:
        """``wme`` (filed already) entered the alpha memory: join it with the
        left memory's tokens, the newest first."""
        if not self.l_linked:
            self.relink_left()
            if not self.left:
                self.unlink_right()
                return
        n = self._n
        if n == 1:
            key: Hashable = wme[self._wfield]
        elif n == 0:
            key = None
        else:
            key = ((wme[self._wfield], wme[self._wfield2]) if n == 2
                else tuple([wme[field] for field in self.wme_fields]))
        timetag = wme[4]
        found = self.left.get(key)
        if found is None:
            return
        tests = self.tests
        parents: Iterable[Token]
        if isinstance(found, dict):
            parents = list(found)
            parents.reverse()
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
            registry = registries.get(timetag)
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
