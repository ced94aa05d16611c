"""Hypothesis strategies and helpers for the matcher tests.

* :func:`productions` -- random small productions over a small vocabulary:
  constant and variable attributes, ``+`` tests, negated conditions,
  conjunctive negations (nested), disjunctions, relational tests against
  constants and bound variables, conjunctive tests, ints and floats that are
  numerically equal (``2`` and ``2.0``), identifiers as values, the goal
  test of ``(state <s> ...)`` (S1 is a state, A1 and A2 are not).
* :func:`scenarios` -- productions plus batches of operations (WME adds and
  removes, production adds and removes), replayed by :class:`Replay`.
* :func:`cond`, :func:`prod` -- terse constructors for hand-written examples.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterator, Sequence

from hypothesis import strategies as st

from adapt.engine.matcher import Match, MatchKey
from adapt.engine.production import (
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    ConjunctiveTest,
    DisjunctionTest,
    EqualityTest,
    Production,
    RelationalTest,
    Test,
    Variable,
)
from adapt.engine.symbols import Float, Identifier, Symbol
from adapt.engine.wme import WME

IDS = [Identifier("S", 1, goal=True), Identifier("A", 1), Identifier("A", 2), Identifier("B", 1)]
#: Identifiers that random WMEs use (B1 only appears in the examples).
WME_IDS = IDS[:3]
ATTRS = ["a", "b", "c"]
CONSTANTS: list[Symbol] = ["x", "y", 1, 2, Float(2.0), 3]
VALUES: list[Symbol] = CONSTANTS + IDS
VARS = [Variable(f"<{n}>") for n in ("s", "x", "y", "z", "v", "w")]
RELATIONS = ["<>", "<", ">", "<=", ">=", "<=>"]


# -- terse constructors ------------------------------------------------------

def term(x: Any) -> Any:
    """``"<x>"`` -> Variable, anything else unchanged."""
    if isinstance(x, str) and x.startswith("<") and x.endswith(">") and len(x) > 2:
        return Variable(x)
    return x


def field_test(x: Any) -> Test | None:
    """A field test from a shorthand: None, a Test, a variable name or a constant."""
    if x is None or isinstance(x, (EqualityTest, RelationalTest, DisjunctionTest, ConjunctiveTest)):
        return x
    return EqualityTest(term(x))


def rel(relation: str, x: Any) -> RelationalTest:
    return RelationalTest(relation, term(x))


def conj(*tests: Any) -> ConjunctiveTest:
    return ConjunctiveTest(tuple(field_test(t) for t in tests))  # type: ignore[misc]


def disj(*values: Any) -> DisjunctionTest:
    return DisjunctionTest(tuple(values))


def cond(id: str, attr: Any, value: Any = None, *, plus: bool = False, neg: bool = False) -> Condition:
    return Condition(Variable(id), field_test(attr), field_test(value), plus, neg)


def ncc(*elements: ConditionElement) -> ConjunctiveNegation:
    return ConjunctiveNegation(tuple(elements))


def prod(name: str, *elements: ConditionElement) -> Production:
    return Production(name, tuple(elements), ())


# -- random productions ------------------------------------------------------

_plus = st.sampled_from([False, False, False, False, True])
_goal = st.sampled_from([False, False, False, True])


def _eq_vars(c: Condition) -> set[Variable]:
    out = {c.id}
    for t in (c.attr, c.value):
        tests = t.tests if isinstance(t, ConjunctiveTest) else (t,)
        for s in tests:
            if isinstance(s, EqualityTest) and isinstance(s.term, Variable):
                out.add(s.term)
    return out


@st.composite
def _skeleton(draw: st.DrawFn, bound: Sequence[Variable], first_id: Variable | None) -> Condition:
    """A condition with equality, constant and disjunction tests only."""
    if first_id is not None:
        ident = first_id
    elif bound and draw(st.integers(0, 4)) > 0:
        ident = draw(st.sampled_from(sorted(bound, key=lambda v: v.name)))
    else:
        ident = draw(st.sampled_from(VARS))
    attr = draw(st.one_of(
        st.sampled_from(ATTRS).map(EqualityTest),
        st.sampled_from(ATTRS).map(EqualityTest),
        st.sampled_from(ATTRS).map(EqualityTest),
        st.sampled_from(VARS).map(EqualityTest),
        st.lists(st.sampled_from(ATTRS), min_size=1, max_size=2, unique=True)
        .map(lambda v: DisjunctionTest(tuple(v))),
        st.none(),
    ))
    value = draw(st.one_of(
        st.none(),
        st.none(),
        st.sampled_from(CONSTANTS).map(EqualityTest),
        st.sampled_from(VARS).map(EqualityTest),
        st.sampled_from(VARS).map(EqualityTest),
        st.sampled_from(VARS).map(EqualityTest),
        st.lists(st.sampled_from(CONSTANTS), min_size=1, max_size=3, unique=True)
        .map(lambda v: DisjunctionTest(tuple(v))),
    ))
    return Condition(ident, attr, value, draw(_plus), goal=draw(_goal))


@st.composite
def _with_relations(draw: st.DrawFn, c: Condition, bound: set[Variable]) -> Condition:
    """Maybe add a relational test (against a constant or a bound variable)
    to the value (or, rarely, the attribute) of ``c``."""
    choice = draw(st.integers(0, 5))
    if choice >= 3:
        return c
    relation = draw(st.sampled_from(RELATIONS))
    pool: list[Any] = list(CONSTANTS) + sorted(bound, key=lambda v: v.name) * 2
    rt = RelationalTest(relation, draw(st.sampled_from(pool)))
    field = "attr" if choice == 0 else "value"
    old = getattr(c, field)
    if old is None:
        new: Test = rt
    elif isinstance(old, ConjunctiveTest):
        new = ConjunctiveTest(old.tests + (rt,))
    else:
        new = ConjunctiveTest((old, rt))
    if field == "attr":
        return Condition(c.id, new, c.value, c.acceptable, c.negated, goal=c.goal)
    return Condition(c.id, c.attr, new, c.acceptable, c.negated, goal=c.goal)


@st.composite
def _conjunction(
    draw: st.DrawFn, outer: frozenset[Variable], depth: int, top: bool
) -> tuple[ConditionElement, ...]:
    n_pos = draw(st.integers(1, 3 if top else 2))
    positives: list[Condition] = []
    bound = set(outer)
    for i in range(n_pos):
        first = VARS[0] if top and i == 0 else None
        c = draw(_skeleton(sorted(bound, key=lambda v: v.name), first))
        positives.append(c)
        bound |= _eq_vars(c)
    positives = [draw(_with_relations(c, bound)) for c in positives]
    negations: list[ConditionElement] = []
    for _ in range(draw(st.integers(0, 3))):
        if depth < 2 and draw(st.booleans()):
            negations.append(ConjunctiveNegation(draw(_conjunction(frozenset(bound), depth + 1, False))))
        else:
            c = draw(_skeleton(sorted(bound, key=lambda v: v.name), None))
            c = draw(_with_relations(c, bound))
            negations.append(Condition(c.id, c.attr, c.value, c.acceptable, True, goal=c.goal))
    elements: list[ConditionElement] = list(positives)
    for n in negations:
        elements.insert(draw(st.integers(0, len(elements))), n)
    return tuple(elements)


@st.composite
def productions(draw: st.DrawFn, name: str = "p") -> Production:
    """A random production (no actions) named ``name``."""
    return Production(name, draw(_conjunction(frozenset(), 0, True)), ())


# -- operation sequences ------------------------------------------------------

wme_fields = st.tuples(
    st.sampled_from(WME_IDS),
    st.sampled_from(ATTRS),
    st.one_of(st.sampled_from(WME_IDS), st.sampled_from(CONSTANTS)),
    st.sampled_from([False] * 7 + [True]),
)

operation = st.one_of(
    st.tuples(st.just("add"), wme_fields),
    st.tuples(st.just("add"), wme_fields),
    st.tuples(st.just("add"), wme_fields),
    st.tuples(st.just("remove"), st.integers(0, 1000)),
    st.tuples(st.just("remove"), st.integers(0, 1000)),
    st.tuples(st.just("toggle"), st.integers(0, 1000)),
)


@dataclass(frozen=True)
class Scenario:
    productions: tuple[Production, ...]
    initially: tuple[bool, ...]
    batches: tuple[tuple[tuple[str, Any], ...], ...]


@st.composite
def scenarios(draw: st.DrawFn, max_batches: int = 8) -> Scenario:
    """Productions (some added at the start, some toggled later) and batches
    of operations."""
    n = draw(st.integers(1, 3))
    prods = tuple(draw(productions(f"p{i}")) for i in range(n))
    initially = tuple(draw(st.lists(st.sampled_from([True, True, True, False]), min_size=n, max_size=n)))
    batches = draw(st.lists(
        st.lists(operation, min_size=3, max_size=12).map(tuple), min_size=2, max_size=max_batches
    ))
    return Scenario(prods, initially, tuple(batches))


class Replay:
    """Turns a scenario's operations into matcher calls, with set semantics
    for WMEs (an add of an existing (id, attr, value, +) is skipped) and fresh
    timetags."""

    def __init__(self, scenario: Scenario, matchers: Sequence[Any]) -> None:
        self.scenario = scenario
        self.matchers = matchers
        self.wm: dict[tuple[Any, ...], WME] = {}
        self.active = list(scenario.initially)
        self.timetag = 0
        for p, on in zip(scenario.productions, scenario.initially):
            if on:
                for m in matchers:
                    m.add_production(p)

    def apply(self, op: tuple[str, Any]) -> None:
        kind, arg = op
        if kind == "add":
            ident, attr, value, plus = arg
            key = (ident, attr, value, plus)
            if key in self.wm:
                return
            self.timetag += 1
            w = WME(ident, attr, value, plus, self.timetag)
            self.wm[key] = w
            for m in self.matchers:
                m.add_wme(w)
        elif kind == "remove":
            if not self.wm:
                return
            key = list(self.wm)[arg % len(self.wm)]
            w = self.wm.pop(key)
            for m in self.matchers:
                m.remove_wme(w)
        else:
            i = arg % len(self.scenario.productions)
            p = self.scenario.productions[i]
            for m in self.matchers:
                if self.active[i]:
                    m.remove_production(p.name)
                else:
                    m.add_production(p)
            self.active[i] = not self.active[i]

    def batches(self) -> Iterator[None]:
        """Apply one batch per iteration."""
        for batch in self.scenario.batches:
            for op in batch:
                self.apply(op)
            yield None


def keys(matches: Sequence[Match]) -> list[MatchKey]:
    return [m.key for m in matches]


# -- hand-written examples: (name, productions, WMEs, expected match keys) ----
# WMEs are (id, attr, value, plus); the i-th gets timetag i + 1.

S1, A1, A2, B1 = IDS[0], IDS[1], IDS[2], IDS[3]

EXAMPLES: list[tuple[str, list[Production], list[tuple[Any, ...]], set[MatchKey]]] = [
    ("constants",
     [prod("p", cond("<s>", "a", "x"))],
     [(S1, "a", "x", False), (S1, "a", "y", False), (S1, "b", "x", False)],
     {("p", (1,))}),
    ("variable join",
     [prod("p", cond("<s>", "a", "<x>"), cond("<x>", "b", "<v>"))],
     [(S1, "a", A1, False), (A1, "b", 1, False), (A2, "b", 2, False)],
     {("p", (1, 2))}),
    ("one WME matches two conditions",
     [prod("p", cond("<s>", "a", "<x>"), cond("<s>", "a", "<y>"))],
     [(S1, "a", "x", False), (S1, "a", "y", False)],
     {("p", (1, 1)), ("p", (1, 2)), ("p", (2, 1)), ("p", (2, 2))}),
    ("same variable twice in one condition",
     [prod("p", cond("<s>", "<a>", "<a>"))],
     [(S1, "a", "a", False), (S1, "a", "b", False), (S1, "b", "b", False)],
     {("p", (1,)), ("p", (3,))}),
    ("negation bound later in the text",
     [prod("p", cond("<s>", "b", "<x>", neg=True), cond("<s>", "a", "<x>"))],
     [(S1, "a", "x", False), (S1, "a", "y", False), (S1, "b", "x", False)],
     {("p", (2,))}),
    ("negation with a local variable",
     [prod("p", cond("<s>", "a", "<x>"), cond("<x>", "b", "<y>", neg=True))],
     [(S1, "a", A1, False), (S1, "a", A2, False), (A2, "b", 7, False)],
     {("p", (1,))}),
    ("conjunctive negation with an inner negation",
     [prod("p", cond("<s>", "a", "<x>"),
           ncc(cond("<x>", "b", "<y>"), cond("<y>", "c", "x", neg=True)))],
     [(S1, "a", A1, False), (S1, "a", A2, False), (A1, "b", B1, False),
      (A2, "b", S1, False), (B1, "c", "x", False)],
     {("p", (1,))}),
    ("nested conjunctive negations",
     [prod("p", cond("<s>", "a", "<x>"),
           ncc(cond("<x>", "b", "<y>"),
               ncc(cond("<y>", "c", "<z>"), cond("<z>", "a", 1))))],
     [(S1, "a", A1, False), (A1, "b", A2, False), (A2, "c", B1, False),
      (B1, "a", 1, False), (S1, "a", B1, False), (B1, "b", A1, False)],
     {("p", (1,)), ("p", (4,))}),
    ("attribute variable",
     [prod("p", cond("<s>", "<a>", "<v>"), cond("<v>", "<a>", 1))],
     [(S1, "b", A1, False), (A1, "b", 1, False), (A1, "c", 1, False)],
     {("p", (1, 2))}),
    ("acceptable versus plain",
     [prod("p", cond("<s>", "a", "<o>", plus=True)), prod("q", cond("<s>", "a", "<o>"))],
     [(S1, "a", A1, True), (S1, "a", A2, False)],
     {("p", (1,)), ("q", (2,))}),
    # Soar joins ^b first (of two tied conditions the last written) and checks
    # the relation at ^a turned round: 2 < z holds (another type is less)
    ("relation against a variable written earlier, joined later",
     [prod("p", cond("<s>", "a", "<x>"), cond("<s>", "b", rel(">", "<x>")))],
     [(S1, "a", 2, False), (S1, "b", 3, False), (S1, "b", 2, False),
      (S1, "b", Float(2.5), False), (S1, "b", "z", False)],
     {("p", (1, 2)), ("p", (1, 4)), ("p", (1, 5))}),
    ("relation against a variable bound later",
     [prod("p", cond("<s>", "b", rel(">", "<x>")), cond("<s>", "a", "<x>"))],
     [(S1, "a", 2, False), (S1, "b", 3, False), (S1, "b", 2, False),
      (S1, "b", Float(2.5), False), (S1, "b", "z", False)],
     {("p", (2, 1)), ("p", (4, 1))}),
    ("int 2 is not float 2.0",
     [prod("p", cond("<s>", "a", 2)),
      prod("q", cond("<s>", "a", "<x>"), cond("<s>", "b", "<x>")),
      prod("r", cond("<s>", "a", "<x>"), cond("<s>", "b", rel("<>", "<x>")))],
     [(S1, "a", 2, False), (S1, "b", Float(2.0), False)],
     {("p", (1,)), ("r", (1, 2))}),
    ("disjunction",
     [prod("p", cond("<s>", "a", disj("x", 1)))],
     [(S1, "a", "x", False), (S1, "a", 1, False), (S1, "a", Float(1.0), False),
      (S1, "a", "y", False)],
     {("p", (1,)), ("p", (2,))}),
    ("conjunctive test",
     [prod("p", cond("<s>", "a", conj("<x>", rel(">", 1), rel("<", 3))))],
     [(S1, "a", 1, False), (S1, "a", 2, False), (S1, "a", Float(2.5), False),
      (S1, "a", 3, False), (S1, "a", "x", False)],
     {("p", (2,)), ("p", (3,))}),
    ("same type",
     [prod("p", cond("<s>", "a", "<x>"), cond("<s>", "b", rel("<=>", "<x>")))],
     [(S1, "a", 1, False), (S1, "b", 2, False), (S1, "b", Float(2.0), False),
      (S1, "b", "x", False)],
     {("p", (1, 2))}),
    ("strings compare as strings; a value of another type is less (Soar's compare_symbols)",
     [prod("p", cond("<s>", "a", rel(">", "x"))), prod("q", cond("<s>", "b", rel("<", 5))),
      prod("r", cond("<s>", "b", rel("<>", 5)))],
     [(S1, "a", "y", False), (S1, "a", "x", False), (S1, "a", 1, False),
      (S1, "b", A1, False), (S1, "b", 4, False)],
     {("p", (1,)), ("q", (4,)), ("q", (5,)), ("r", (4,)), ("r", (5,))}),
    ("any attribute, any value",
     [prod("p", cond("<s>", None, None)), prod("q", cond("<s>", "a", None, plus=True))],
     [(S1, "a", 1, False), (A1, "a", 2, True)],
     {("p", (1,)), ("q", (2,))}),
    ("negation alone with no positive before it",
     [prod("p", cond("<s>", "a", "x", neg=True), cond("<s>", "b", "<v>"))],
     [(S1, "b", 1, False), (A1, "b", 2, False), (A1, "a", "x", False)],
     {("p", (1,))}),
]


def make_wmes(rows: Sequence[tuple[Any, ...]]) -> list[WME]:
    return [WME(i, a, v, p, n + 1) for n, (i, a, v, p) in enumerate(rows)]
