"""Instantiations: what a production's match does when it fires.

A :class:`RuleInfo` is computed once per production (the facts about its
actions the decision cycle needs on every match); an :class:`Instantiation`
is one fired match: its goal, its support and the preferences it made, so
that it can be retracted.

Support (Soar 9.6, ``calculate_support_for_instantiation_preferences``):

* ``:o-support`` / ``:i-support`` flags decide;
* otherwise a match is **o-supported** iff it tests the *selected* operator
  (``(<s> ^operator <o>)``, not ``+``) of its *match goal* -- the lowest
  state among the identifiers of the WMEs it matched -- and the production
  makes no preference on ``^operator`` and does not augment the operator it
  tests (an operator elaboration gives all of its preferences i-support);
* a production whose actions are only function calls makes no preference:
  support ``"none"``, scheduled like i-support (it re-fires whenever its match
  changes).

Examples
--------
>>> from adapt.engine.production import (Production, Condition, EqualityTest,
...     MakeAction, CallAction, FunctionCall, Variable)
>>> s, o = Variable("<s>"), Variable("<o>")
>>> apply = Production("apply", (Condition(s, EqualityTest("operator"), EqualityTest(o)),),
...                    (MakeAction(s, "done", "yes"),))
>>> info = RuleInfo(apply)
>>> info.has_make, info.makes_operator_prefs, info.declared, info.new_variables
(True, False, None, ())
>>> RuleInfo(Production("w", apply.conditions,
...                     (CallAction(FunctionCall("write", ("hi",))),))).has_make
False
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Container, Final

from adapt.engine.matcher import FlatKey, Match
from adapt.engine.production import (
    CallAction,
    Condition,
    DisjunctionTest,
    EqualityTest,
    FunctionCall,
    MakeAction,
    PreferenceKind,
    Production,
    RhsValue,
    Test,
    Variable,
)
from adapt.engine.symbols import Identifier, Symbol
from adapt.engine.vocabulary import Support
from adapt.engine.wme import WME

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.goals import Goal, SlotPreference
    from adapt.engine.memory import WmeKey

__all__ = ["RuleInfo", "Instantiation", "CompiledValue", "PlanStep",
           "SRC_CONST", "SRC_WME", "SRC_NEW", "SRC_CALL"]

#: Tags of the compiled RHS values of :attr:`RuleInfo.plan`:
#: ``(SRC_CONST, symbol)``, ``(SRC_WME, index, field)`` (a field of the match's
#: ``index``-th WME), ``(SRC_NEW, k)`` (the firing's ``k``-th new identifier),
#: ``(SRC_CALL, name, (arg, ...))``.
SRC_CONST: Final = 0
SRC_WME: Final = 1
SRC_NEW: Final = 2
SRC_CALL: Final = 3

#: A compiled RHS value: a tuple starting with one of the ``SRC_*`` tags.
CompiledValue = tuple[Any, ...]
#: One compiled action: ``(True, id, attr, value, preference, referent)`` or
#: ``(False, call)``.
PlanStep = tuple[Any, ...]


def _may_test_operator(cond: Condition) -> bool:
    """Could a WME matched by ``cond`` be a selected-operator WME (``^operator`` without +)?"""
    if cond.acceptable:
        return False
    attr: Test | None = cond.attr
    if isinstance(attr, EqualityTest) and not isinstance(attr.term, Variable):
        return attr.term == "operator"
    if isinstance(attr, DisjunctionTest):
        return "operator" in attr.values
    return True


def _rhs_variables(value: RhsValue | None, out: dict[Variable, None]) -> None:
    """Add the variables of an RHS value to ``out`` (an insertion-ordered set)."""
    if isinstance(value, Variable):
        out[value] = None
    elif isinstance(value, FunctionCall):
        for arg in value.args:
            _rhs_variables(arg, out)


class RuleInfo:
    """Facts about one production's actions, computed once.

    Attributes
    ----------
    production : Production
    has_make : bool
        The production makes at least one preference (WME or operator).
    makes_operator_prefs : bool
        Some action has the constant attribute ``operator``.
    declared : Support or None
        ``"o"`` or ``"i"`` for ``:o-support`` / ``:i-support``.
    new_variables : tuple of Variable
        RHS variables not bound on the LHS: a new identifier each per firing.
    """

    __slots__ = ("production", "name", "has_make", "makes_operator_prefs", "declared",
                 "new_variables", "elaborates_operator", "op_elab_only", "static_support",
                 "operator_slots",
                 "new_hints", "plan", "id_sites", "proposes", "proposal_sites")

    def __init__(self, production: Production) -> None:
        self.production = production
        self.name = production.name
        makes = [a for a in production.actions if isinstance(a, MakeAction)]
        self.has_make = bool(makes)
        self.makes_operator_prefs = any(a.attr == "operator" for a in makes)
        # an operator proposal (an acceptable preference on a state's
        # ^operator) is i-supported, whatever else the rule tests (Soar's
        # calculate_support_for_instantiation_preferences); other operator
        # preferences do not decide the support
        states = {c.id for c in production.positive_conditions if c.goal}
        proposals = [a for a in makes if a.attr == "operator"
                     and a.preference is PreferenceKind.ACCEPTABLE]
        self.proposes = bool(proposals) and all(a.id in states for a in proposals)
        operator_vars = {
            c.value.term for c in production.positive_conditions
            if isinstance(c.attr, EqualityTest) and c.attr.term == "operator"
            and not c.acceptable and isinstance(c.value, EqualityTest)
            and isinstance(c.value.term, Variable)}
        #: some action augments an operator the rule tests as selected
        self.elaborates_operator = any(a.id in operator_vars for a in makes)
        #: every make action augments a tested operator (a pure operator
        #: elaboration: its support depends on the production's other matches)
        self.op_elab_only = bool(makes) and all(a.id in operator_vars for a in makes)
        flags = production.flags
        self.declared: Support | None = (
            Support.O if "o-support" in flags else Support.I if "i-support" in flags else None
        )
        seen: dict[Variable, None] = {}
        for action in production.actions:
            if isinstance(action, MakeAction):
                for v in (action.id, action.attr, action.value, action.referent):
                    _rhs_variables(v, seen)
            elif isinstance(action, CallAction):
                _rhs_variables(action.call, seen)
        bound = production.binding_sites
        self.new_variables = tuple(v for v in seen if v not in bound)
        #: the identifier letters of the new identifiers (``<o>`` -> ``o``; a
        #: dot path's hidden variable, as in Soar, the attribute's:
        #: ``^arithmetic.facts <f>`` makes ``A1``)
        path_hints: dict[Variable, str] = {}
        for a in makes:
            if isinstance(a.value, Variable) and a.value.name.startswith("<#") \
                    and isinstance(a.attr, str):
                path_hints.setdefault(a.value, a.attr)
        self.new_hints = tuple(path_hints.get(v, v.name[1:]) for v in self.new_variables)
        #: the support every match gets, or None when it depends on the match
        self.static_support: Support | None
        if not self.has_make:
            self.static_support = Support.NONE
        elif self.declared is not None:
            self.static_support = self.declared
        elif self.proposes or self.elaborates_operator:
            self.static_support = Support.I
        else:
            self.static_support = None
        #: positions in a match of the WMEs that may be a selected-operator WME
        self.operator_slots = tuple(i for i, c in enumerate(production.positive_conditions)
                                    if _may_test_operator(c))
        self.plan = self._compile(production)
        #: where the identifiers of acceptable ^operator preferences not known
        #: to be states come from (a state there makes the match a proposal)
        self.proposal_sites: tuple[tuple[int, int], ...] = ()
        if proposals and not self.proposes:
            self.proposal_sites = tuple(sorted(
                {(step[1][1], step[1][2]) for step in self.plan
                 if step[0] and step[2] == (SRC_CONST, "operator")
                 and step[4] is PreferenceKind.ACCEPTABLE and step[1][0] == SRC_WME}))
        #: where each make action's identifier comes from in a match, when it
        #: is bound on the left-hand side: (WME index, field)
        self.id_sites: tuple[tuple[int, int], ...] = tuple(sorted(
            {(step[1][1], step[1][2]) for step in self.plan if step[0] and step[1][0] == SRC_WME}))

    def _compile(self, production: Production) -> tuple[PlanStep, ...]:
        """The actions as tuples the kernel evaluates from a match's WMEs directly.

        ``(True, id, attr, value, preference, referent)`` for a make action
        (``referent`` None or a compiled value), ``(False, call)`` for a
        stand-alone call; values compiled as the ``SRC_*`` tags describe.
        """
        sites = production.binding_sites
        new_index = {v: k for k, v in enumerate(self.new_variables)}

        def src(value: RhsValue) -> CompiledValue:
            if isinstance(value, Variable):
                site = sites.get(value)
                if site is not None:
                    return (SRC_WME, site[0], site[1])
                return (SRC_NEW, new_index[value])
            if isinstance(value, FunctionCall):
                return (SRC_CALL, value.name, tuple(src(a) for a in value.args))
            return (SRC_CONST, value)

        plan: list[PlanStep] = []
        for action in production.actions:
            if isinstance(action, MakeAction):
                ref = None if action.referent is None else src(action.referent)
                plan.append((True, src(action.id), src(action.attr), src(action.value),
                             action.preference, ref))
            else:
                plan.append((False, src(action.call)))
        return tuple(plan)

    def changes_below(self, wmes: tuple[WME, ...], level: int) -> bool:
        """Whether every make action of the match over ``wmes`` changes an
        identifier below goal level ``level`` (deeper: a greater level) or a new
        one (Soar's ``shouldCreateInstantiation``, which lets a lower goal's
        match fire in the waterfall of an elaboration cycle)."""
        for i, field in self.id_sites:
            ident = wmes[i][field]
            if type(ident) is Identifier and ident.level <= level:
                return False
        return True

    def support(self, match: Match, goal_id: Symbol) -> Support:
        """The support a match of this production gets when its match goal is ``goal_id``."""
        return self.support_of(match.wmes, goal_id)

    def support_of(self, wmes: tuple[WME, ...], goal_id: Symbol,
                   states: Container[object] = ()) -> Support:
        """:meth:`support` of the match over ``wmes`` (condition order);
        ``states``: the state identifiers (for an operator proposal whose
        identifier the rule does not test as a state)."""
        static = self.static_support
        if static is not None:
            return static
        for i, field in self.proposal_sites:
            if wmes[i][field] in states:
                return Support.I
        for i in self.operator_slots:
            w = wmes[i]
            if w[0] is goal_id and w[1] == "operator":
                return Support.O
        return Support.I


class Instantiation:
    """One firing of a production (or a justification for a result).

    Attributes
    ----------
    key : tuple or None
        The match's flat key ``(name, timetag, ...)``; ``None`` for a
        justification.
    rule : RuleInfo or None
        ``None`` for a justification.
    goal : Goal
        The match goal (its level is the instantiation's level).
    support : Support
        ``"o"``, ``"i"`` or ``"none"``.
    wmes : tuple of WME
        The WMEs matched (for a justification: the superstate WMEs it tests).
    i_wmes : list of WmeKey
        WMEs this instantiation supports with i-support (retracted with it).
    slot_prefs : list
        ``(goal, SlotPreference)`` operator-slot preferences it made.
    """

    __slots__ = ("key", "rule", "goal", "support", "wmes", "i_wmes", "slot_prefs",
                 "bindings", "retracted", "unmatched", "traces")

    def __init__(self, key: FlatKey | None, rule: RuleInfo | None, goal: Goal,
                 support: Support, wmes: tuple[WME, ...]) -> None:
        self.key = key
        self.rule = rule
        self.goal = goal
        self.support = support
        self.wmes = wmes
        self.i_wmes: list[WmeKey] = []
        self.slot_prefs: list[tuple[Goal, SlotPreference]] = []
        self.bindings: dict[Variable, Symbol] | None = None
        self.retracted = False
        #: an o-supported justification whose match is gone: its retraction
        #: keeps everything (o-support) but is work of its goal, as in Soar
        self.unmatched = False
        #: for a substate's firing, what supported each matched WME when it
        #: fired (Soar's ``bt.trace``): backtracing follows these, not what
        #: supports the WMEs now (they may have gone or changed since)
        self.traces: tuple[Instantiation | None, ...] | None = None

    @property
    def name(self) -> str:
        """The production's name (``"justification"`` for a justification)."""
        return self.rule.name if self.rule is not None else "justification"

    def __repr__(self) -> str:
        tags = [w.timetag for w in self.wmes]
        return f"Instantiation({self.name}, {self.support.value}, level {self.goal.level}, {tags})"
