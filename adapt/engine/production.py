"""Productions as plain frozen data: tests, conditions, actions.

The parser (:mod:`adapt.engine.parse`) turns ``sp {...}`` text into these
records; the matchers (:mod:`adapt.engine.rete`, :mod:`adapt.engine.naive`)
and the decision cycle consume them.  Everything here is already *normalised*:

* dot paths are expanded into chains of conditions/actions linked by hidden
  variables (named ``<#1>``, ``<#2>``, ... -- a name no user variable can have);
* a condition with several attribute-value pairs is split into one
  :class:`Condition` per pair, all sharing the identifier variable;
* ``(state <s> ...)`` marks the conditions on ``<s>`` written in it as
  :attr:`Condition.goal` (``<s>`` must be a state of the goal stack, Soar's
  goal test); when it has no positive attribute test (``(state <s>)``,
  ``(state <s> -^done)``), the condition ``(<s> ^type state)`` with that mark
  is added first;
* ``-^attr value`` inside a condition becomes a negated :class:`Condition`;
* a value without a preference on the RHS becomes ``acceptable``; ``+`` is
  implicit only when no other preference is given for that value.

Tests
-----
A field test is ``None`` (matches anything), an :class:`EqualityTest` (a
variable, which binds or must equal its binding, or a constant), a
:class:`RelationalTest` (``<> < > <= >= <=>`` against a variable or constant),
a :class:`DisjunctionTest` (``<< a b >>``) or a :class:`ConjunctiveTest`
(``{ ... }``, holding at most one equality test).

Matching semantics (both matchers implement exactly these):

* ``=``: the same symbol (``2`` and ``2.0`` differ; identifiers by identity);
* ``<> x``: not the same symbol;
* ``< > <= >=``: both numbers (int or float, compared numerically) or both
  symbolic constants (compared as strings); otherwise the test fails;
  identifiers never satisfy them;
* ``<=> x``: the same *type* of symbol (identifier, string, int, float);
* a variable in a relational test must be bound by an equality test somewhere
  in the positive conditions (or, inside a negation, earlier in it); the
  matcher evaluates the test once it is bound.

Variables bound only inside a negated condition or conjunctive negation are
local to it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Union

from adapt.engine.symbols import Constant, Symbol

__all__ = [
    "Variable",
    "Term",
    "EqualityTest",
    "RelationalTest",
    "DisjunctionTest",
    "ConjunctiveTest",
    "Test",
    "SimpleTest",
    "Condition",
    "ConjunctiveNegation",
    "ConditionElement",
    "FunctionCall",
    "RhsValue",
    "PreferenceKind",
    "MakeAction",
    "CallAction",
    "Action",
    "SourceLocation",
    "Production",
    "FIELD_ID",
    "FIELD_ATTR",
    "FIELD_VALUE",
    "variables_in_test",
    "equality_variable",
    "simple_tests",
    "condition_equality_variables",
    "relational_variables",
]

#: Indexes of a WME's fields, as used in :attr:`Production.binding_sites`.
FIELD_ID, FIELD_ATTR, FIELD_VALUE = 0, 1, 2


@dataclass(frozen=True, slots=True)
class Variable:
    """A variable such as ``<x>``; ``name`` includes the angle brackets."""

    name: str

    def __repr__(self) -> str:
        return self.name


#: What a test compares against: a variable or a constant.
Term = Union[Variable, Constant]


@dataclass(frozen=True, slots=True)
class EqualityTest:
    """``<x>`` (bind or compare) or a constant."""

    term: Term


@dataclass(frozen=True, slots=True)
class RelationalTest:
    """``<> < > <= >= <=>`` followed by a variable or a constant."""

    relation: str
    term: Term


@dataclass(frozen=True, slots=True)
class DisjunctionTest:
    """``<< a b c >>``: equal to one of the constants."""

    values: tuple[Constant, ...]


@dataclass(frozen=True, slots=True)
class ConjunctiveTest:
    """``{ t1 t2 ... }``: every test holds; at most one is an equality test."""

    tests: tuple["Test", ...]


Test = Union[EqualityTest, RelationalTest, DisjunctionTest, ConjunctiveTest]
#: A test that is not a conjunction.
SimpleTest = Union[EqualityTest, RelationalTest, DisjunctionTest]


@dataclass(frozen=True, slots=True)
class SourceLocation:
    """Where something was written: file, 1-based line and column."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass(frozen=True, slots=True)
class Condition:
    """One WME test ``(<id> ^attr value [+])``, possibly negated.

    ``id`` is always a variable.  ``attr`` and ``value`` are tests, ``None``
    meaning "anything" (``(<s> ^foo)`` has ``value=None``).  ``goal``: the
    identifier must be a state of the goal stack (written ``(state <s> ...)``:
    Soar's goal test, :func:`adapt.engine.symbols.is_goal`); a WME that merely
    looks like a state, ``^type state`` and all, does not pass it.
    """

    id: Variable
    attr: Test | None
    value: Test | None
    acceptable: bool = False
    negated: bool = False
    location: SourceLocation | None = field(default=None, compare=False)
    goal: bool = False


@dataclass(frozen=True, slots=True)
class ConjunctiveNegation:
    """``-{ c1 c2 ... }``: no consistent match of all the conditions exists.

    The inner conditions may themselves be negated :class:`Condition`\\ s or
    nested :class:`ConjunctiveNegation`\\ s.
    """

    conditions: tuple["ConditionElement", ...]
    location: SourceLocation | None = field(default=None, compare=False)


ConditionElement = Union[Condition, ConjunctiveNegation]


@dataclass(frozen=True, slots=True)
class FunctionCall:
    """``(name arg ...)`` on the right-hand side."""

    name: str
    args: tuple["RhsValue", ...]
    location: SourceLocation | None = field(default=None, compare=False)


RhsValue = Union[Variable, Constant, FunctionCall]


class PreferenceKind(str, Enum):
    """The preference a :class:`MakeAction` makes.

    For a non-operator attribute only ``ACCEPTABLE`` (add the WME) and
    ``REJECT`` (remove the WME, ``-``) are meaningful.
    """

    ACCEPTABLE = "+"
    REJECT = "-"
    REQUIRE = "!"
    PROHIBIT = "~"
    BEST = ">"
    WORST = "<"
    BETTER = ">x"
    WORSE = "<x"
    UNARY_INDIFFERENT = "="
    BINARY_INDIFFERENT = "=x"
    NUMERIC_INDIFFERENT = "=n"


@dataclass(frozen=True, slots=True)
class MakeAction:
    """``(<id> ^attr value pref [referent])``: one preference for one value.

    ``referent`` is the other operator of a binary preference (better, worse,
    binary indifferent) or the number of a numeric-indifferent one; ``None``
    otherwise.
    """

    id: Variable
    attr: RhsValue
    value: RhsValue
    preference: PreferenceKind = PreferenceKind.ACCEPTABLE
    referent: RhsValue | None = None
    location: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class CallAction:
    """A stand-alone function call on the RHS: ``(write ...)``, ``(halt)``."""

    call: FunctionCall
    location: SourceLocation | None = field(default=None, compare=False)


Action = Union[MakeAction, CallAction]


def variables_in_test(test: Test | None) -> list[Variable]:
    """Every variable a test mentions, equality or relational, in order."""
    if test is None or isinstance(test, DisjunctionTest):
        return []
    if isinstance(test, (EqualityTest, RelationalTest)):
        return [test.term] if isinstance(test.term, Variable) else []
    out: list[Variable] = []
    for t in test.tests:
        out.extend(variables_in_test(t))
    return out


def simple_tests(test: Test | None) -> list[SimpleTest]:
    """The test's parts with conjunctive tests flattened (``None`` gives ``[]``).

    Examples
    --------
    >>> t = ConjunctiveTest((EqualityTest(Variable("<x>")), RelationalTest(">", 3)))
    >>> [type(p).__name__ for p in simple_tests(t)]
    ['EqualityTest', 'RelationalTest']
    """
    if test is None:
        return []
    if isinstance(test, ConjunctiveTest):
        return [s for t in test.tests for s in simple_tests(t)]
    return [test]


def condition_equality_variables(cond: Condition) -> set[Variable]:
    """The variables a condition's equality tests bind, its identifier included."""
    out = {cond.id}
    for test in (cond.attr, cond.value):
        for t in simple_tests(test):
            if isinstance(t, EqualityTest) and isinstance(t.term, Variable):
                out.add(t.term)
    return out


def relational_variables(test: Test | None) -> list[Variable]:
    """The variables the test's relational tests compare against, in order."""
    return [t.term for t in simple_tests(test)
            if isinstance(t, RelationalTest) and isinstance(t.term, Variable)]


def equality_variable(test: Test | None) -> Variable | None:
    """The variable of the test's equality test, if it has one."""
    if isinstance(test, EqualityTest):
        return test.term if isinstance(test.term, Variable) else None
    if isinstance(test, ConjunctiveTest):
        for t in test.tests:
            if isinstance(t, EqualityTest) and isinstance(t.term, Variable):
                return t.term
    return None


@dataclass(frozen=True)
class Production:
    """A parsed, normalised ``sp`` production.

    Attributes
    ----------
    name : str
        The production's name.
    conditions : tuple of ConditionElement
        All conditions in source order (after normalisation).
    actions : tuple of Action
        All actions in source order.
    documentation : str or None
        The optional ``"..."`` string.
    flags : frozenset of str
        Flags such as ``"o-support"``, ``"i-support"``, ``"default"``.
    location : SourceLocation or None
        Where ``sp`` was written.
    positive_conditions : tuple of Condition
        Derived: the non-negated top-level conditions, in order.  A match
        holds one WME per positive condition, in this order.
    binding_sites : dict
        Derived: for every variable bound by a positive condition's equality
        test, ``(index into positive_conditions, FIELD_ID/ATTR/VALUE)`` of the
        first place it is bound.
    """

    name: str
    conditions: tuple[ConditionElement, ...]
    actions: tuple[Action, ...]
    documentation: str | None = None
    flags: frozenset[str] = frozenset()
    location: SourceLocation | None = field(default=None, compare=False)
    positive_conditions: tuple[Condition, ...] = field(init=False, compare=False, repr=False)
    binding_sites: dict[Variable, tuple[int, int]] = field(
        init=False, compare=False, repr=False
    )

    def __post_init__(self) -> None:
        positives = tuple(
            c for c in self.conditions if isinstance(c, Condition) and not c.negated
        )
        sites: dict[Variable, tuple[int, int]] = {}
        for i, cond in enumerate(positives):
            for fld, test in ((FIELD_ID, EqualityTest(cond.id)), (FIELD_ATTR, cond.attr),
                              (FIELD_VALUE, cond.value)):
                var = equality_variable(test)
                if var is not None and var not in sites:
                    sites[var] = (i, fld)
        object.__setattr__(self, "positive_conditions", positives)
        object.__setattr__(self, "binding_sites", sites)

    def bindings(self, wmes: tuple[object, ...]) -> dict[Variable, Symbol]:
        """Variable bindings of a match, given its WMEs (one per positive condition)."""
        return {var: wmes[i][f] for var, (i, f) in self.binding_sites.items()}  # type: ignore[index]
