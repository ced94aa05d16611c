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

from adapt.engine.matcher import Match
from adapt.engine.production import ConditionElement, ConjunctiveNegation, Production, Variable
from adapt.engine.rete.alpha import ANY, AlphaKey, AlphaMemory, AlphaTest
from adapt.engine.rete.build import compile_condition, is_positive, order_elements
from adapt.engine.rete.join import JoinNode, JoinTest, TwoInputNode
from adapt.engine.rete.ncc import NccNode, NccPartner
from adapt.engine.rete.negative import NegativeNode
from adapt.engine.rete.pnode import ProductionNode
from adapt.engine.rete.state import FlatKey, NetworkState
from adapt.engine.rete.token import BetaNode, RootNode, delete_token, unlink
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = ["Rete"]

Site = tuple[int, int]


class Rete:
    """A Rete network implementing :class:`adapt.engine.matcher.Matcher`."""

    __slots__ = (
        "state", "root", "_wmes", "_alpha", "_alpha_by_sig", "_wme_alphas", "_pnodes",
        "_shapes", "multi_attributes",
    )

    def __init__(self) -> None:
        self.state = NetworkState()
        self.root = RootNode(self.state)
        self._wmes: dict[int, WME] = {}
        #: alpha key -> memories with that key (differing in their tests)
        self._alpha: dict[AlphaKey, tuple[AlphaMemory, ...]] = {}
        self._alpha_by_sig: dict[tuple[AlphaKey, tuple[AlphaTest, ...]], AlphaMemory] = {}
        #: timetag -> the WME's alpha memories (tuples, shared: never mutated)
        self._wme_alphas: dict[int, tuple[AlphaMemory, ...]] = {}
        self._pnodes: dict[str, ProductionNode] = {}
        #: how many alpha memories have a constant attribute/value: the
        #: key shapes (attr, value), (attr, ANY), (ANY, value), (ANY, ANY)
        self._shapes = [0, 0, 0, 0]
        #: ``multi-attributes`` hints for ordering the conditions of productions
        #: added from now on (attribute -> expected number of values)
        self.multi_attributes: dict[str, int] = {}

    # -- working memory -----------------------------------------------------

    def _alphas_of(self, wme: WME) -> tuple[AlphaMemory, ...]:
        """The alpha memories ``wme`` belongs in (the shapes' order)."""
        alpha = self._alpha
        both, attr_only, value_only, neither = self._shapes
        attr, value, acceptable = wme[1], wme[2], wme[3]
        found: tuple[AlphaMemory, ...] = ()
        if attr_only:
            found = alpha.get((attr, ANY, acceptable), ())
        if both:
            memories = alpha.get((attr, value, acceptable))
            if memories:
                found = found + memories if found else memories
        if value_only:
            memories = alpha.get((ANY, value, acceptable))
            if memories:
                found = found + memories if found else memories
        if neither:
            memories = alpha.get((ANY, ANY, acceptable))
            if memories:
                found = found + memories if found else memories
        for am in found:
            if am.check is not None:
                return tuple([m for m in found if m.check is None or m.check(wme)])
        return found

    def add_wme(self, wme: WME) -> None:
        """Add a WME (a timetag already present is ignored)."""
        timetag = wme[4]
        wmes = self._wmes
        if timetag in wmes:
            return
        wmes[timetag] = wme
        self.state.epoch += 1
        memories = self._alphas_of(wme)
        if not memories:
            return
        self._wme_alphas[timetag] = memories
        for am in memories:
            am.items[timetag] = wme
            for node in am.successors:
                node.right_add(wme)

    def remove_wme(self, wme: WME) -> None:
        """Remove a WME (a timetag not present is ignored)."""
        timetag = wme[4]
        known = self._wmes.pop(timetag, None)
        if known is None:
            return
        wme = known
        state = self.state
        state.epoch += 1
        memories = self._wme_alphas.pop(timetag, None)
        if memories is None:
            return
        for am in memories:
            del am.items[timetag]
            for node in am.successors:
                node.right_remove(wme)
        tokens = state.tokens_by_wme.pop(timetag, None)
        if tokens is not None:
            if isinstance(tokens, dict):
                for token in tokens:
                    if not token.dead:
                        unlink(token)
                        delete_token(token)
            else:
                unlink(tokens)
                delete_token(tokens)
        for am in memories:
            for negative in am.negatives:
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
        bottom.children.append(pnode)
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
        deferred: dict[Variable, list[tuple[str, int, int]]] = {}
        levels: dict[int, int] = {}
        hops = 0
        node = parent
        for i in order_elements(elements, set(bound), self.multi_attributes):
            element = elements[i]
            hops += 1
            if isinstance(element, ConjunctiveNegation):
                bottom, _, sub_hops, _ = self._build(node, element.conditions, bound, depth)
                node = self._ncc(node, bottom, sub_hops)
                continue
            spec = compile_condition(element, bound)
            if element.negated:
                if spec.deferred:
                    raise _Unbound(spec.deferred[0][2])
                node = self._two_input(NegativeNode, node, spec.alpha_key, spec.alpha_tests,
                                       spec.token_fields, spec.wme_fields, spec.tests)
                continue
            tests = list(spec.tests)
            for var, field in spec.binds.items():
                for relation, level, other in deferred.pop(var, ()):
                    tests.append((relation, level, other, -1, field))
            for relation, field, var in spec.deferred:
                deferred.setdefault(var, []).append((relation, depth, field))
            node = self._two_input(JoinNode, node, spec.alpha_key, spec.alpha_tests,
                                   spec.token_fields, spec.wme_fields, tuple(tests))
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
        self._alpha[key] = self._alpha.get(key, ()) + (am,)
        self._shapes[_shape(key)] += 1
        wme_alphas = self._wme_alphas
        for timetag, wme in self._wmes.items():
            if am.accepts(wme):
                am.items[timetag] = wme
                wme_alphas[timetag] = wme_alphas.get(timetag, ()) + (am,)
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
    ) -> TwoInputNode:
        am = self._alpha_memory(key, alpha_tests)
        sig = (cls, am, token_fields, wme_fields, tests)
        shared = parent.shared.get(sig)
        if shared is not None:
            assert isinstance(shared, TwoInputNode)
            return shared
        node = cls(self.state, parent, am, token_fields, wme_fields, tests)
        parent.children.append(node)
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
        bottom.children.append(partner)
        for token in bottom.emitted():
            partner.left_add(token)
        node = NccNode(self.state, parent, partner)
        parent.children.append(node)
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
        memories = tuple([m for m in self._alpha[am.key] if m is not am])
        if memories:
            self._alpha[am.key] = memories
        else:
            del self._alpha[am.key]
        self._shapes[_shape(am.key)] -= 1
        wme_alphas = self._wme_alphas
        for timetag in am.items:
            memories = tuple([m for m in wme_alphas[timetag] if m is not am])
            if memories:
                wme_alphas[timetag] = memories
            else:
                del wme_alphas[timetag]


class _Unbound(Exception):
    """A relational test's variable is bound nowhere in its scope."""


def _shape(key: AlphaKey) -> int:
    attr, value, _ = key
    return (2 if attr is ANY else 0) + (1 if value is ANY else 0)
