"""The Rete network: the fast :class:`~adapt.engine.matcher.Matcher`.

Built after Doorenbos (1995, *Production Matching for Large Learning
Systems*), with three departures: beta memories live inside the nodes that
fill them; both memories of every join and negative node are hashed on all
of its equality tests, values included, so a join on an equal value costs
time linear in the number of matches (Soar's Rete hashes only identifiers);
and a conjunctive negation's owner tokens count their results, so activation
order between the subnetwork and the NCC node never matters for
correctness.

Working-memory changes:

* ``add_wme`` finds the WME's alpha memories with at most four hash lookups
  and right-activates their successors (ancestors first);
* ``remove_wme`` takes the WME out of every right memory, deletes the tokens
  that hold it (and their subtrees) through the token tree, then un-blocks
  the negative-node tokens it was blocking.

``take_changes`` returns the match-set changes in the order they happened;
an appearance and a disappearance of the same match (by
:attr:`~adapt.engine.matcher.Match.key`) cancel out in O(1).

Examples
--------
>>> from adapt.engine.production import Production, Condition, EqualityTest, Variable
>>> from adapt.engine.symbols import Identifier
>>> from adapt.engine.wme import WME
>>> s, x = Variable("<s>"), Variable("<x>")
>>> rete = Rete()
>>> rete.add_production(Production("p", (
...     Condition(s, EqualityTest("a"), EqualityTest(x)),
...     Condition(s, EqualityTest("b"), EqualityTest(x)),), ()))
>>> s1 = Identifier("S", 1)
>>> for w in (WME(s1, "a", 1, False, 1), WME(s1, "b", 1, False, 2), WME(s1, "b", 2, False, 3)):
...     rete.add_wme(w)
>>> rete.take_changes()
([Match(p, [1, 2])], [])
>>> rete.remove_wme(WME(s1, "a", 1, False, 1))
>>> rete.take_changes()
([], [Match(p, [1, 2])])
"""

from __future__ import annotations

from typing import Sequence

from adapt.engine.conditions import turned_round
from adapt.engine.matcher import Match
from adapt.engine.production import ConditionElement, ConjunctiveNegation, Production, Variable
from adapt.engine.reorder import ConstantOrder
from adapt.engine.rete.alpha import ANY, AlphaGroup, AlphaKey, AlphaMemory, AlphaTest
from adapt.engine.rete.build import (
    compile_condition,
    is_positive,
    order_elements,
    relation_test,
)
from adapt.engine.rete.join import JoinNode, JoinTest, TwoInputNode
from adapt.engine.rete.ncc import NccNode, NccPartner
from adapt.engine.rete.negative import NegativeNode
from adapt.engine.rete.pnode import ProductionNode
from adapt.engine.rete.state import FlatKey, NetworkState
from adapt.engine.rete.token import BetaNode, RootNode, Successor, delete_token, unlink
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = ["Rete"]

Site = tuple[int, int]


class Rete:
    """A Rete network implementing :class:`adapt.engine.matcher.Matcher`."""

    __slots__ = (
        "state", "root", "_wmes", "_alpha", "_alpha_by_sig", "_wme_groups", "_pnodes",
        "_shapes", "multi_attributes", "constants",
    )

    def __init__(self) -> None:
        self.state = NetworkState()
        self.root = RootNode(self.state)
        self._wmes: dict[int, WME] = {}
        #: alpha key -> its group: the memories with that key (differing in
        #: their tests), Soar's one alpha memory
        self._alpha: dict[AlphaKey, AlphaGroup] = {}
        self._alpha_by_sig: dict[tuple[AlphaKey, tuple[AlphaTest, ...]], AlphaMemory] = {}
        #: timetag -> the groups of the WME's key (tuples, never mutated)
        self._wme_groups: dict[int, tuple[AlphaGroup, ...]] = {}
        self._pnodes: dict[str, ProductionNode] = {}
        #: how many alpha groups have a constant attribute/value: the
        #: key shapes (attr, value), (attr, ANY), (ANY, value), (ANY, ANY)
        self._shapes = [0, 0, 0, 0]
        #: ``multi-attributes`` hints for ordering the conditions of productions
        #: added from now on (attribute -> expected number of values)
        self.multi_attributes: dict[str, int] = {}
        #: the order of constants that breaks the join order's last ties
        self.constants = ConstantOrder()

    # -- working memory -----------------------------------------------------

    def _groups_of(self, wme: WME) -> tuple[AlphaGroup, ...]:
        """The alpha groups (Soar's alpha memories) of ``wme``'s key, in the
        order of Soar's alpha hash tables: no constant, attribute, value, both."""
        groups = self._alpha
        both, attr_only, value_only, neither = self._shapes
        attr, value, acceptable = wme[1], wme[2], wme[3]
        found: list[AlphaGroup] = []
        if neither:
            group = groups.get((ANY, ANY, acceptable))
            if group is not None:
                found.append(group)
        if attr_only:
            group = groups.get((attr, ANY, acceptable))
            if group is not None:
                found.append(group)
        if value_only:
            group = groups.get((ANY, value, acceptable))
            if group is not None:
                found.append(group)
        if both:
            group = groups.get((attr, value, acceptable))
            if group is not None:
                found.append(group)
        return tuple(found)

    def add_wme(self, wme: WME) -> None:
        """Add a WME (a timetag already present is ignored).

        As Soar's ``add_wme_to_rete``: alpha memory by alpha memory, the WME
        is filed, then the linked nodes are activated in their order (see
        :class:`~adapt.engine.rete.alpha.AlphaGroup`).
        """
        timetag = wme[4]
        wmes = self._wmes
        if timetag in wmes:
            return
        wmes[timetag] = wme
        self.state.epoch += 1
        groups = self._groups_of(wme)
        if not groups:
            return
        self._wme_groups[timetag] = groups
        for group in groups:
            group.count += 1
            for am in group.memories:
                check = am.check
                if check is None or check(wme):
                    am.items[timetag] = wme
                    for node in am.successors:
                        node.index_right(wme)
            linked = group.linked
            if not linked:
                continue
            # an activation may link or unlink nodes of this list: go on
            # from the node that came next before it (Soar's saved pointer)
            i = 0
            while i < len(linked):
                node = linked[i]
                after = linked[i + 1] if i + 1 < len(linked) else None
                if timetag in node.alpha.items:
                    node.right_join(wme)
                if after is None:
                    break
                if i + 1 < len(linked) and linked[i + 1] is after:
                    i += 1
                elif after in linked:
                    i = linked.index(after)
                elif node in linked:
                    i = linked.index(node) + 1

    def remove_wme(self, wme: WME) -> None:
        """Remove a WME (a timetag not present is ignored)."""
        timetag = wme[4]
        known = self._wmes.pop(timetag, None)
        if known is None:
            return
        wme = known
        state = self.state
        state.epoch += 1
        groups = self._wme_groups.pop(timetag, None)
        if groups is None:
            return
        memories: list[AlphaMemory] = []
        for group in groups:
            group.count -= 1
            for am in group.memories:
                if am.items.pop(timetag, None) is not None:
                    memories.append(am)
                    for node in am.successors:
                        node.right_remove(wme)
            if not group.count:
                # an empty alpha memory left-unlinks its linked joins (Soar)
                for node in group.linked:
                    if not node.blocks:
                        node.l_linked = False
        tokens = state.tokens_by_wme.pop(timetag, None)
        if tokens is not None:
            if isinstance(tokens, dict):
                # the newest token first, as Soar's tree-based removal goes
                for token in reversed(tokens):
                    if not token.dead:
                        unlink(token)
                        delete_token(token)
            else:
                unlink(tokens)
                delete_token(tokens)
        for am in memories:
            for negative in reversed(am.negatives):
                negative.unblock(wme)

    # -- match set ------------------------------------------------------------

    def take_changes(self) -> tuple[list[Match], list[Match]]:
        """``(added, removed)`` since the previous call, each in the order the
        changes happened; transient matches cancel out."""
        return self.state.take()

    def take_raw(self) -> tuple[dict[FlatKey, tuple[WME, ...]], dict[FlatKey, tuple[WME, ...]]]:
        """:meth:`take_changes` without :class:`Match` records: ``(added,
        removed)`` as dicts ``(name, timetag, ...) -> wmes`` (condition order),
        in order.  The caller reads them at once and must not keep them."""
        return self.state.take_raw()

    def matches(self) -> list[Match]:
        """The current match set."""
        return [m for p in self._pnodes.values() for m in p.matches()]

    # -- productions ------------------------------------------------------------

    def add_production(self, production: Production) -> None:
        """Add a production, sharing the nodes of equal prefixes; its matches
        against the current WMEs become pending additions.

        Raises
        ------
        EngineError
            If a production of that name is present, or a relational test
            uses a variable that nothing in its scope binds.
        """
        if production.name in self._pnodes:
            raise EngineError(f"production {production.name} is already in the matcher")
        elements = production.conditions
        self.constants.add_production(production)
        try:
            bottom, _, _, levels = self._build(self.root, elements, {}, 0)
        except _Unbound as err:
            raise EngineError(
                f"production {production.name}: variable {err.args[0]} is tested with a "
                "relation but never bound"
            ) from None
        order = tuple(levels[i] for i, e in enumerate(elements) if is_positive(e))
        pnode = ProductionNode(
            self.state, bottom, production, None if order == tuple(range(len(order))) else order
        )
        bottom.children.insert(0, pnode)
        self._pnodes[production.name] = pnode
        self.state.pnodes[production.name] = pnode
        for token in bottom.emitted():
            pnode.left_add(token)

    def remove_production(self, name: str) -> None:
        """Remove a production and the nodes no other production uses; its
        matches become pending removals."""
        pnode = self._pnodes.pop(name, None)
        if pnode is None:
            raise EngineError(f"no production named {name} in the matcher")
        state = self.state
        for token in pnode.parent.emitted():
            state.match_removed(pnode.flat_key(token), pnode.wmes_of(token))
        state.detach(pnode)
        pnode.parent.children.remove(pnode)
        self._prune(pnode.parent)

    def _build(
        self,
        parent: BetaNode,
        elements: Sequence[ConditionElement],
        outer: dict[Variable, Site],
        depth: int,
    ) -> tuple[BetaNode, int, int, dict[int, int]]:
        """Build (or share) the nodes of a conjunction below ``parent``.

        Returns the bottom node, the token depth there, the number of
        token-making nodes built (the NCC partner's walk), and the level of
        each positive element.
        """
        bound = dict(outer)
        deferred: dict[Variable, list[tuple[str, int, int, bool]]] = {}
        levels: dict[int, int] = {}
        hops = 0
        node = parent
        order = order_elements(elements, set(bound), self.multi_attributes, self.constants)
        turned = turned_round(elements, [i for i in order if is_positive(elements[i])], bound)
        for i in order:
            element = elements[i]
            hops += 1
            if isinstance(element, ConjunctiveNegation):
                bottom, _, sub_hops, _ = self._build(node, element.conditions, bound, depth)
                node = self._ncc(node, bottom, sub_hops)
                continue
            spec = compile_condition(element, bound, turned.get(i, frozenset()))
            if element.negated:
                if spec.deferred:
                    raise _Unbound(spec.deferred[0][2])
                node = self._two_input(NegativeNode, node, spec.alpha_key, spec.alpha_tests,
                                       spec.token_fields, spec.wme_fields, spec.tests,
                                       bound.get(element.id))
                continue
            tests = list(spec.tests)
            for var, field in spec.binds.items():
                for relation, level, other, turn in deferred.pop(var, ()):
                    # read as Soar's reorderer puts the test back (conditions.turned_round)
                    tests.append(relation_test(relation, (level, other), (-1, field), turn))
            for relation, field, var, turn in spec.deferred:
                deferred.setdefault(var, []).append((relation, depth, field, turn))
            node = self._two_input(JoinNode, node, spec.alpha_key, spec.alpha_tests,
                                   spec.token_fields, spec.wme_fields, tuple(tests),
                                   bound.get(element.id))
            for var, field in spec.binds.items():
                bound[var] = (depth, field)
            levels[i] = depth
            depth += 1
        if deferred:
            raise _Unbound(next(iter(deferred)))
        return node, depth, hops, levels

    def _alpha_memory(self, key: AlphaKey, tests: tuple[AlphaTest, ...]) -> AlphaMemory:
        sig = (key, tests)
        am = self._alpha_by_sig.get(sig)
        if am is not None:
            return am
        am = AlphaMemory(key, tests)
        self._alpha_by_sig[sig] = am
        group = self._alpha.get(key)
        if group is None:
            group = am.group
            self._alpha[key] = group
            self._shapes[_shape(key)] += 1
            wme_groups = self._wme_groups
            probe = AlphaMemory(key, ())
            for timetag, wme in self._wmes.items():
                if probe.accepts(wme):
                    group.count += 1
                    wme_groups[timetag] = wme_groups.get(timetag, ()) + (group,)
        else:
            am.group = group
        group.memories += (am,)
        for timetag, wme in self._wmes.items():
            if am.accepts(wme):
                am.items[timetag] = wme
        return am

    def _two_input(
        self,
        cls: type[TwoInputNode],
        parent: BetaNode,
        key: AlphaKey,
        alpha_tests: tuple[AlphaTest, ...],
        token_fields: tuple[Site, ...],
        wme_fields: tuple[int, ...],
        tests: tuple[JoinTest, ...],
        group: Site | None = None,
    ) -> TwoInputNode:
        am = self._alpha_memory(key, alpha_tests)
        sig = (cls, am, token_fields, wme_fields, tests)
        shared = parent.shared.get(sig)
        if shared is not None:
            assert isinstance(shared, TwoInputNode)
            return shared
        node = cls(self.state, parent, am, token_fields, wme_fields, tests)
        node.group = group
        # Soar lists a node's children newest first; the joins that hash on
        # the same variable share a memory node, whose place is the first one's
        children = parent.children
        at = 0
        if cls is JoinNode:
            for i, child in enumerate(children):
                if isinstance(child, JoinNode) and child.group == group:
                    at = i
                    break
        children.insert(at, node)
        parent.shared[sig] = node
        am.add_successor(node)
        node.fill_right()
        for token in parent.emitted():
            node.left_add(token)
        return node

    def _ncc(self, parent: BetaNode, bottom: BetaNode, depth: int) -> NccNode:
        sig = (NccNode, bottom, depth)
        shared = parent.shared.get(sig)
        if shared is not None:
            assert isinstance(shared, NccNode)
            return shared
        partner = NccPartner(bottom, depth)
        bottom.children.insert(0, partner)
        for token in bottom.emitted():
            partner.left_add(token)
        node = NccNode(self.state, parent, partner)
        # Soar moves the top of the subnetwork (with the joins that share its
        # memory node) to the head of the parent's children, the CN node
        # right after it
        top: object = bottom
        while isinstance(top, BetaNode) and top.parent is not parent and top.parent is not None:
            top = top.parent
        children = parent.children
        moved: list[Successor] = []
        if isinstance(top, JoinNode):
            group = top.group
            moved = [c for c in children if isinstance(c, JoinNode) and c.group == group]
        else:
            moved = [c for c in children if c is top]
        rest = [c for c in children if all(c is not m for m in moved)]
        children[:] = moved + [node] + rest
        parent.shared[sig] = node
        for token in parent.emitted():
            node.left_add(token)
        return node

    def _prune(self, node: BetaNode) -> None:
        """Remove ``node`` and its ancestors while they have no children."""
        while node is not self.root and not node.children:
            parent = node.parent
            assert parent is not None
            for token in node.tokens():
                unlink(token)
                delete_token(token)
            parent.children.remove(node)  # type: ignore[arg-type]
            if isinstance(node, (TwoInputNode, NccNode)):
                del parent.shared[node.signature()]
            if isinstance(node, TwoInputNode):
                am = node.alpha
                am.remove_successor(node)
                if not am.successors:
                    self._drop_alpha(am)
            elif isinstance(node, NccNode):
                partner = node.partner
                partner.parent.children.remove(partner)
                # Pruning the subnetwork walks up to ``parent`` and beyond if
                # they are left without children: nothing more to do here.
                self._prune(partner.parent)
                return
            node = parent

    def _drop_alpha(self, am: AlphaMemory) -> None:
        del self._alpha_by_sig[(am.key, am.tests)]
        group = am.group
        group.memories = tuple([m for m in group.memories if m is not am])
        if group.memories:
            return
        del self._alpha[am.key]
        self._shapes[_shape(am.key)] -= 1
        wme_groups = self._wme_groups
        for timetag, groups in list(wme_groups.items()):
            if group in groups:
                rest = tuple([g for g in groups if g is not group])
                if rest:
                    wme_groups[timetag] = rest
                else:
                    del wme_groups[timetag]


class _Unbound(Exception):
    """A relational test's variable is bound nowhere in its scope."""


def _shape(key: AlphaKey) -> int:
    attr, value, _ = key
    return (2 if attr is ANY else 0) + (1 if value is ANY else 0)
