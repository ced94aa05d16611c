"""The alpha network: memories of the WMEs that pass one condition's
intra-WME tests.

Every alpha memory is filed under a hash key ``(attribute, value,
acceptable)`` built from the condition's constant equality tests, with
:data:`ANY` for a field without one (a condition's identifier is always a
variable).  A WME therefore finds its memories with at most four dictionary
lookups, whatever the number of memories.  Tests that a hash cannot express
(relations and disjunctions against constants, the same variable twice in one
condition) are the memory's ``tests``, checked after the lookup.

An alpha test is ``(relation, field, is_constant, operand)``: ``operand`` is a
constant, or (``is_constant`` false) the index of another field of the same
WME.  ``relation`` is one of ``= <> < > <= >= <=>``, ``in`` (a disjunction,
whose operand is a tuple of constants) or ``goal`` (:data:`GOAL_TEST`: the
identifier is a state of the goal stack, Soar's goal test, checked when the
WME enters the network as Soar checks it when the WME is joined).

Examples
--------
>>> from adapt.engine.symbols import Float
>>> holds("<", 2, Float(2.5)), holds("<>", 2, Float(2.0)), holds(">", "b", 1)
(True, True, False)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Final

from adapt.engine.conditions import RELATIONS, relation_holds
from adapt.engine.symbols import Identifier, is_goal
from adapt.engine.wme import WME

if TYPE_CHECKING:
    from adapt.engine.rete.join import TwoInputNode

__all__ = ["ANY", "GOAL_TEST", "AlphaTest", "AlphaKey", "AlphaGroup", "AlphaMemory", "holds",
           "passes", "compile_tests"]


class _Any:
    __slots__ = ()

    def __repr__(self) -> str:
        return "ANY"


#: The wildcard of an alpha key: the field has no constant equality test.
ANY: Final[object] = _Any()

AlphaTest = tuple[str, int, bool, object]
AlphaKey = tuple[object, object, bool]

#: The goal test of a condition written in ``(state <s> ...)``.
GOAL_TEST: Final[AlphaTest] = ("goal", 0, True, None)


def holds(relation: str, a: object, b: object) -> bool:
    """``a relation b``: the relations of :data:`adapt.engine.conditions.RELATIONS`,
    plus ``in`` (membership in a disjunction's tuple of constants)."""
    if relation == "in":
        return a in b  # type: ignore[operator]
    if relation == "goal":
        return is_goal(a)
    return relation_holds(relation, a, b)


def passes(tests: tuple[AlphaTest, ...], wme: WME) -> bool:
    """Whether ``wme`` passes every alpha test."""
    for relation, field, is_constant, operand in tests:
        other = operand if is_constant else wme[operand]  # type: ignore[call-overload]
        if not holds(relation, wme[field], other):
            return False
    return True


def compile_tests(tests: tuple[AlphaTest, ...]) -> Callable[[WME], bool] | None:
    """A predicate equivalent to :func:`passes` with ``tests`` (None for no test).

    A single test of a field against a constant (``^count { <c> < 10 }``)
    calls the relation's predicate directly.

    Examples
    --------
    >>> from adapt.engine.symbols import Float, Identifier
    >>> check = compile_tests((("<", 2, True, 10),))
    >>> s1 = Identifier("S", 1)
    >>> [check(WME(s1, "count", v, False, 1)) for v in (3, 12, "x", Float(2.5))]
    [True, False, True, True]

    (A string is *less* than a number, as in Soar: see
    :func:`adapt.engine.conditions.soar_compare`.)
    """
    if not tests:
        return None
    if tests[0] == GOAL_TEST:
        rest = compile_tests(tests[1:])
        if rest is None:
            def goal_test(wme: WME) -> bool:
                ident = wme[0]
                return type(ident) is Identifier and ident.goal

            return goal_test
        return lambda wme: is_goal(wme[0]) and rest(wme)
    if len(tests) == 1:
        relation, field, is_constant, operand = tests[0]
        predicate = RELATIONS.get(relation)
        if predicate is not None and is_constant:
            def constant_test(wme: WME) -> bool:
                return predicate(wme[field], operand)

            return constant_test
    return lambda wme: passes(tests, wme)


class AlphaGroup:
    """The alpha memories of one key ``(attribute, value, acceptable)``:
    what Soar keeps as *one* alpha memory (its other tests are in the join
    nodes), and so the order in which a new WME activates their nodes.

    Attributes
    ----------
    key : tuple
    memories : tuple of AlphaMemory
        adapt's memories of this key (differing in their tests).
    count : int
        The WMEs with this key (Soar's alpha memory's size, whatever the tests).
    linked : list
        The successors of the memories that a new WME activates, in the order
        Soar's Rete keeps them (its ``beta_nodes`` list with *right
        unlinking*): a node whose left memory is empty is taken out (it has
        nothing to join), and one that comes back goes just before its
        nearest ancestor of the same key that is in the list, or at the end.
        Only the order of the matches depends on it.
    """

    __slots__ = ("key", "memories", "count", "linked")

    def __init__(self, key: AlphaKey) -> None:
        self.key = key
        self.memories: tuple[AlphaMemory, ...] = ()
        self.count = 0
        self.linked: list[TwoInputNode] = []


class AlphaMemory:
    """The WMEs that pass one set of intra-WME tests.

    Attributes
    ----------
    key : tuple
        ``(attribute, value, acceptable)`` with :data:`ANY` wildcards.
    tests : tuple
        Further alpha tests.
    check : callable or None
        ``tests`` as one predicate on a WME.
    items : dict
        ``timetag -> WME`` in arrival order.
    successors : tuple
        Join and negative nodes fed by this memory (every one files each WME
        in its right memory).
    negatives : tuple
        The negative nodes among them (to un-block after a removal).
    group : AlphaGroup
        The memories of the same key (Soar's one alpha memory).
    """

    __slots__ = ("key", "tests", "check", "items", "successors", "negatives", "group")

    def __init__(self, key: AlphaKey, tests: tuple[AlphaTest, ...]) -> None:
        self.key = key
        self.tests = tests
        #: ``tests`` compiled (:func:`compile_tests`); None when there is none
        self.check = compile_tests(tests)
        self.items: dict[int, WME] = {}
        self.successors: tuple[TwoInputNode, ...] = ()
        self.negatives: tuple[TwoInputNode, ...] = ()
        self.group = AlphaGroup(key)

    def add_successor(self, node: TwoInputNode) -> None:
        """Feed ``node`` (after the current successors)."""
        self.successors += (node,)
        if node.blocks:
            self.negatives += (node,)

    def remove_successor(self, node: TwoInputNode) -> None:
        """Stop feeding ``node``."""
        self.successors = tuple([n for n in self.successors if n is not node])
        self.negatives = tuple([n for n in self.negatives if n is not node])
        if node in self.group.linked:
            self.group.linked.remove(node)

    def accepts(self, wme: WME) -> bool:
        """Whether ``wme`` belongs in this memory."""
        attr, value, acceptable = self.key
        if wme.acceptable != acceptable:
            return False
        if attr is not ANY and not attr == wme.attr:
            return False
        if value is not ANY and not value == wme.value:
            return False
        return self.check is None or self.check(wme)

    def __repr__(self) -> str:
        return f"AlphaMemory({self.key}, {self.tests}, {len(self.items)} WMEs)"

