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

from typing import TYPE_CHECKING

from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import (
    CallAction,
    EqualityTest,
    FunctionCall,
    MakeAction,
    Production,
    RhsValue,
    Variable,
)
from adapt.engine.symbols import Identifier, Symbol

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.goals import Goal

__all__ = ["RuleInfo", "Instantiation", "SUPPORT_O", "SUPPORT_I", "SUPPORT_NONE"]

SUPPORT_O, SUPPORT_I, SUPPORT_NONE = "o", "i", "none"


def _rhs_variables(value: RhsValue | None, out: list[Variable]) -> None:
    if isinstance(value, Variable):
        if value not in out:
            out.append(value)
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
    declared : str or None
        ``"o"`` or ``"i"`` for ``:o-support`` / ``:i-support``.
    new_variables : tuple of Variable
        RHS variables not bound on the LHS: a new identifier each per firing.
    """

    __slots__ = ("production", "name", "has_make", "makes_operator_prefs", "declared",
                 "new_variables", "elaborates_operator")

    def __init__(self, production: Production) -> None:
        self.production = production
        self.name = production.name
        makes = [a for a in production.actions if isinstance(a, MakeAction)]
        self.has_make = bool(makes)
        self.makes_operator_prefs = any(a.attr == "operator" for a in makes)
        operator_vars = {
            c.value.term for c in production.positive_conditions
            if isinstance(c.attr, EqualityTest) and c.attr.term == "operator"
            and not c.acceptable and isinstance(c.value, EqualityTest)
            and isinstance(c.value.term, Variable)}
        #: some action augments an operator the rule tests as selected
        self.elaborates_operator = any(a.id in operator_vars for a in makes)
        flags = production.flags
        self.declared: str | None = (
            SUPPORT_O if "o-support" in flags else SUPPORT_I if "i-support" in flags else None
        )
        seen: list[Variable] = []
        for action in production.actions:
            if isinstance(action, MakeAction):
                for v in (action.id, action.attr, action.value, action.referent):
                    _rhs_variables(v, seen)
            elif isinstance(action, CallAction):
                _rhs_variables(action.call, seen)
        bound = production.binding_sites
        self.new_variables = tuple(v for v in seen if v not in bound)

    def support(self, match: Match, goal_id: Symbol) -> str:
        """The support a match of this production gets when its match goal is ``goal_id``."""
        if not self.has_make:
            return SUPPORT_NONE
        if self.declared is not None:
            return self.declared
        if self.makes_operator_prefs or self.elaborates_operator:
            return SUPPORT_I
        for w in match.wmes:
            if w.id is goal_id and w.attr == "operator" and not w.acceptable:
                return SUPPORT_O
        return SUPPORT_I


class Instantiation:
    """One firing of a production (or a justification for a result).

    Attributes
    ----------
    key : MatchKey or None
        The match's key; ``None`` for a justification.
    rule : RuleInfo or None
        ``None`` for a justification.
    goal : Goal
        The match goal (its level is the instantiation's level).
    support : str
        ``"o"``, ``"i"`` or ``"none"``.
    wmes : tuple of WME
        The WMEs matched (for a justification: the superstate WMEs it tests).
    i_wmes : list of WmeKey
        WMEs this instantiation supports with i-support (retracted with it).
    slot_prefs : list
        ``(goal, SlotPreference)`` operator-slot preferences it made.
    """

    __slots__ = ("key", "rule", "goal", "support", "wmes", "i_wmes", "slot_prefs",
                 "bindings", "retracted")

    def __init__(self, key: MatchKey | None, rule: RuleInfo | None, goal: Goal,
                 support: str, wmes: tuple) -> None:
        self.key = key
        self.rule = rule
        self.goal = goal
        self.support = support
        self.wmes = wmes
        self.i_wmes: list[tuple] = []
        self.slot_prefs: list[tuple] = []
        self.bindings: dict[Variable, Symbol] | None = None
        self.retracted = False

    @property
    def name(self) -> str:
        """The production's name (``"justification"`` for a justification)."""
        return self.rule.name if self.rule is not None else "justification"

    def __repr__(self) -> str:
        tags = [w.timetag for w in self.wmes]
        return f"Instantiation({self.name}, {self.support}, level {self.goal.level}, {tags})"
