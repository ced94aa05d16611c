"""Preference semantics, table-driven (lis.py style).

Each row is (preferences, current, expected outcome) in a tiny notation:

* ``"a+"`` acceptable, ``"a!"`` require, ``"a~"`` prohibit, ``"a-"`` reject,
  ``"a>"`` best, ``"a<"`` worst, ``"a="`` unary indifferent,
  ``"a>b"`` a better than b, ``"a<b"`` a worse than b, ``"a=b"`` binary
  indifferent, ``"a=0.5"`` numeric indifferent;
* the expected outcome is ``"select a"``, ``"select a|b"`` (a random choice
  among a and b), ``"tie a b"``, ``"conflict a b"``, ``"constraint-failure a b"``
  or ``"none"``; for impasses the items are listed in order.

Every row marked ``# soar`` is also exercised by an agent in
``tests/engine/agents/pref_*.soar`` that was run in the real Soar kernel.
"""

from __future__ import annotations

import random
import re

import pytest

from adapt.engine.preferences import (
    Preference,
    SlotDecision,
    choose,
    decide,
    numeric_values,
    should_keep,
)
from adapt.engine.production import PreferenceKind as K
from adapt.engine.symbols import Float, Identifier, IdentifierFactory

_UNARY = {"+": K.ACCEPTABLE, "!": K.REQUIRE, "~": K.PROHIBIT, "-": K.REJECT,
          ">": K.BEST, "<": K.WORST, "=": K.UNARY_INDIFFERENT}
_BINARY = {">": K.BETTER, "<": K.WORSE, "=": K.BINARY_INDIFFERENT}
_TOKEN = re.compile(r"^([a-z]\w*)([+!~\-<>=])(.*)$")


def parse(spec: str) -> list[Preference]:
    """``"a+ b+ a>b c=0.5"`` -> preferences, oldest first."""
    prefs = []
    for token in spec.split():
        m = _TOKEN.match(token)
        assert m, token
        value, op, rest = m.groups()
        if not rest:
            prefs.append(Preference(_UNARY[op], value))
        elif re.fullmatch(r"-?\d+", rest):
            prefs.append(Preference(K.NUMERIC_INDIFFERENT, value, int(rest)))
        elif re.fullmatch(r"-?\d*\.\d+", rest):
            prefs.append(Preference(K.NUMERIC_INDIFFERENT, value, Float(float(rest))))
        else:
            prefs.append(Preference(_BINARY[op], value, rest))
    return prefs


def show(d: SlotDecision) -> str:
    if d.outcome == "none":
        return "none"
    if d.outcome == "select":
        return "select " + "|".join(map(str, d.candidates))
    return d.outcome + " " + " ".join(map(str, d.items))


TABLE: list[tuple[str, str | None, str]] = [
    # --- nothing / one candidate ---
    ("", None, "none"),
    ("a+", None, "select a"),
    ("a+ a+", None, "select a"),
    ("a> b= a>b", None, "none"),                      # no acceptable: no candidate
    # --- require ---
    ("a!", None, "select a"),                         # soar: `!` alone selects
    ("a! a-", None, "select a"),                      # soar: reject does not touch requires
    ("a! b+ b>a b>", None, "select a"),               # requires win over everything
    ("a! b!", None, "constraint-failure a b"),        # soar
    ("a! b! a!", None, "constraint-failure b a"),     # order: each value's last require
    ("a! a~ b+", None, "constraint-failure a"),       # soar: require + prohibit
    ("a! b~", None, "select a"),
    # --- acceptable, prohibit, reject ---
    ("a+ b+ b-", None, "select a"),
    ("a+ b+ b~", None, "select a"),
    ("a+ a-", None, "none"),
    ("a+ b+ a- b~", None, "none"),
    ("a+ b+ c+ c-", None, "tie a b"),                 # a rejected value is no item
    ("a+ b+ a+", None, "tie b a"),                    # order: each value's last acceptable
    # --- better / worse ---
    ("a+ b+ a>b", None, "select a"),
    ("a+ b+ a<b", None, "select b"),
    ("a+ b+ c+ a>b b>c", None, "select a"),           # soar: b and c both dominated
    ("a+ b+ c+ a>c", None, "tie a b"),                # not transitive: a does not beat b
    ("x+ y+ z+ y<x", None, "tie x z"),                # soar: y is no item
    ("a+ b+ a>b b>a", None, "conflict a b"),          # soar
    ("a+ b+ a>b a<b", None, "conflict a b"),          # worse gives the mirror relation
    ("a+ b+ c+ c- a>b b>a c>a", None, "conflict a b"),  # soar: c rejected first
    ("a+ b+ c+ a>b a<b", None, "select c"),           # soar: c escapes the cycle
    ("w+ x+ y+ z+ x>y y>z z>x", None, "select w"),    # soar: a 3-cycle, w escapes
    ("x+ y+ z+ x>y y>z z>x", None, "conflict x y z"),
    ("a+ b+ c+ a>b b>a c>a", None, "select c"),
    ("a+ b+ a>a", None, "tie a b"),                   # a value better than itself: ignored
    ("a+ b+ a>c", None, "tie a b"),                   # c is no candidate: ignored
    ("a+ b+ c+ c- c>a c>b", None, "tie a b"),         # a rejected value dominates nothing
    # --- best ---
    ("a+ b+ c+ b>", None, "select b"),                # soar
    ("a+ b+ c+ a> b>", None, "tie a b"),
    ("p+ q+ p> q>p", None, "select q"),               # soar: better/worse before best
    ("a+ b+ c>", None, "tie a b"),                    # best of a non-candidate: nothing
    # --- worst ---
    ("g+ h+ i+ g< h<", None, "select i"),             # soar
    ("j+ k+ j< k<", None, "tie j k"),                 # soar: all worst changes nothing
    ("d+ e+ f+ d> e> d<", None, "select e"),          # soar: best, then worst
    ("a+ b+ a< a=", None, "select b"),
    # --- indifferent ---
    ("a+ b+ a= b=", None, "select a|b"),
    ("a+ b+ a=", None, "tie a b"),                    # b is not indifferent
    ("a+ b+ a=b", None, "select a|b"),
    ("a+ b+ b=a", None, "select a|b"),                # binary indifference is symmetric
    ("p+ q+ r+ p= q=p q=r r=p", None, "select p|q|r"),  # soar
    ("u+ v+ w+ u=v v=w", None, "tie u v w"),          # soar: partial binary indifference
    ("a+ b+ c+ a= b= c=a", None, "tie a b c"),        # c is not indifferent to b
    ("a+ b+ a=0.7 b=", None, "select a|b"),           # soar (softmax picks a: below)
    ("a+ b+ a=0.5 b=0.5", None, "select a|b"),
    ("a+ b+ a=1 b=", None, "select a|b"),             # an int is a number too
    ("g+ h+ g=0.5", None, "tie g h"),                 # soar: numeric implies unary only for g
    ("a+ b+ c+ a=b a=c", None, "tie a b c"),
    # --- retention: `current` ---
    ("a+ b+ a= b=", "a", "select a|b"),               # kept, no random draw
    ("a+ b+ a= b=", "b", "select a|b"),
    ("a+ b+ b<a", "a", "select a"),                   # soar: worse newcomer
    ("a+ b+ b>a", "a", "select b"),                   # soar: better newcomer
    ("a+ b+ b>", "a", "select b"),                    # soar: best newcomer
    ("a+ b!", "a", "select b"),                       # soar: required newcomer
    ("a+ a- b+", "a", "select b"),                    # soar: rejected
    ("a+ b+", "a", "tie a b"),                        # soar: a newcomer that ties
    ("b+", "a", "select b"),                          # a's acceptable is gone
]


@pytest.mark.parametrize("spec,current,expected", TABLE)
def test_table(spec: str, current: str | None, expected: str) -> None:
    d = decide(parse(spec), current=current, rng=random.Random(5))
    assert show(d) == expected
    if d.outcome == "select":
        assert d.selected in d.candidates and d.items == ()
        if current is not None and current in d.candidates:
            assert d.selected == current
    elif d.outcome == "none":
        assert d.selected is None and d.candidates == ()
    else:
        assert d.selected is None and d.candidates == d.items
        assert d.is_impasse


KEEP: list[tuple[str, str, bool]] = [
    ("a+", "a", True),
    ("a! b+", "a", True),
    ("a+ b+ b<a", "a", True),            # soar: pref_keep_worse
    ("a+ b+ a= b=", "a", True),          # soar: pref_keep_indifferent
    ("a+ b+ a=b", "a", True),
    ("a+ b+ b>a", "a", False),           # soar: pref_deselect_better
    ("a+ b+ b>", "a", False),            # soar: pref_deselect_best
    ("a+ b!", "a", False),               # soar: pref_deselect_require
    ("a+ a- b+", "a", False),            # soar: pref_deselect_reject
    ("a+ b+", "a", False),               # soar: pref_deselect_tie
    ("b+", "a", False),                  # its acceptable preference is gone
    ("a+ a~", "a", False),
    ("a+ b+ a>b b>a", "a", False),       # a conflict
    ("a+ a! a~", "a", False),            # a constraint failure
    ("a+ b+ a= b=0.2", "a", True),
    ("a+ b+ c+ a>b b>c", "a", True),
    ("a+ b+ c+ a>b b>c", "c", False),
]


@pytest.mark.parametrize("spec,current,expected", KEEP)
def test_should_keep(spec: str, current: str, expected: bool) -> None:
    assert should_keep(parse(spec), current) is expected
    # decide(current=...) agrees: it keeps current exactly when should_keep holds
    d = decide(parse(spec), current=current, rng=random.Random(0))
    assert (d.outcome == "select" and d.selected == current) is expected


NON_NUMERIC: list[tuple[str, str, str]] = [
    ("g+ h+ g=0.5", "tie g h", "h"),
    ("a+ b+ c+ a=0.5 c=", "tie a b c", "b c"),
    ("a! b! a=0.5", "constraint-failure a b", "b"),   # soar: CF items get ^non-numeric too
    ("a+ b+ a>b b>a a=0.5", "conflict a b", "b"),     # soar: so do conflict items
    ("a+ b+", "tie a b", "a b"),
    ("a+ b+ c+ c=0.5 c-", "tie a b", "a b"),
]


@pytest.mark.parametrize("spec,expected,non_numeric", NON_NUMERIC)
def test_non_numeric(spec: str, expected: str, non_numeric: str) -> None:
    d = decide(parse(spec))
    assert show(d) == expected
    assert " ".join(map(str, d.non_numeric)) == non_numeric


def test_identifiers_and_typed_numbers() -> None:
    ids = IdentifierFactory()
    o1, o2 = ids.new("O"), ids.new("O")
    prefs = [Preference(K.ACCEPTABLE, o1), Preference(K.ACCEPTABLE, o2),
             Preference(K.BETTER, o2, o1)]
    assert decide(prefs).selected is o2
    # 2 and 2.0 are different values in Soar
    d = decide([Preference(K.ACCEPTABLE, 2), Preference(K.ACCEPTABLE, Float(2.0))])
    assert d.outcome == "tie" and len(d.items) == 2
    assert not should_keep([Preference(K.ACCEPTABLE, 2)], Float(2.0))
    assert should_keep([Preference(K.ACCEPTABLE, 2)], 2)
    # a better preference between two different identifiers with equal names
    o3 = Identifier("O", 1)
    d = decide([Preference(K.ACCEPTABLE, o1), Preference(K.ACCEPTABLE, o3),
                Preference(K.BETTER, o1, o3)])
    assert d.selected is o1


# --- random choice ---------------------------------------------------------

def picks(spec: str, n: int = 400, **kw: object) -> dict[str, int]:
    rng = random.Random(1234)
    counts: dict[str, int] = {}
    prefs = parse(spec)
    for _ in range(n):
        v = decide(prefs, rng=rng, **kw).selected  # type: ignore[arg-type]
        counts[str(v)] = counts.get(str(v), 0) + 1
    return counts


def test_softmax_never_picks_nonpositive_when_some_value_is_positive() -> None:
    # soar: pref_numeric.soar (a = 0.7 vs b =, and c = 0.5 + c = -0.9 vs d = 0.1)
    assert picks("a+ b+ a=0.7 b=") == {"a": 400}
    assert picks("c+ d+ c=0.5 c=-0.9 d=0.1") == {"d": 400}


def test_softmax_is_proportional_to_value() -> None:
    counts = picks("a+ b+ a=1 b=3", n=4000)
    assert 850 < counts["a"] < 1150 and counts["a"] + counts["b"] == 4000


def test_uniform_without_positive_values() -> None:
    counts = picks("a+ b+ c+ a= b= c=", n=3000)
    assert set(counts) == {"a", "b", "c"} and min(counts.values()) > 850


def test_avg_mode() -> None:
    # sum: a = 0.5 + 0.5 = 1.0 > b = 0.9; avg: a = 0.5 < b = 0.9; greedy picks the top
    spec = "a+ b+ a=0.5 a=0.5 b=0.9"
    assert picks(spec, n=50, policy="epsilon-greedy", epsilon=0.0) == {"a": 50}
    assert picks(spec, n=50, policy="epsilon-greedy", epsilon=0.0, numeric_mode="avg") == {"b": 50}


def test_other_policies() -> None:
    assert picks("a+ b+ a= b=", n=20, policy="first") == {"a": 20}
    assert picks("a+ b+ a= b=", n=20, policy="last") == {"b": 20}
    assert set(picks("a+ b+ a= b=", n=200, policy="random")) == {"a", "b"}
    counts = picks("a+ b+ a=0 b=5", n=500, policy="boltzmann", temperature=1.0)
    assert counts["b"] > 480  # e^5 : 1
    counts = picks("a+ b+ a=0 b=5", n=2000, policy="boltzmann", temperature=1000.0)
    assert 850 < counts.get("a", 0) < 1150


def test_seeded_choice_is_reproducible() -> None:
    prefs = parse("a+ b+ c+ d+ a= b= c= d=")
    run1 = [decide(prefs, rng=random.Random(s)).selected for s in range(30)]
    run2 = [decide(prefs, rng=random.Random(s)).selected for s in range(30)]
    assert run1 == run2 and len(set(run1)) > 1
    # without an rng: a fixed, reproducible draw
    assert decide(prefs).selected == decide(prefs).selected


def test_retention_draws_no_random_number() -> None:
    rng = random.Random(9)
    state = rng.getstate()
    assert decide(parse("a+ b+ a= b="), current="b", rng=rng).selected == "b"
    assert rng.getstate() == state


def test_numeric_values_and_choose() -> None:
    prefs = parse("a+ b+ a=0.5 a=b b=2")
    assert numeric_values(prefs, ["a", "b", "c"]) == [0.5, 2.0, 0.0]
    assert numeric_values(prefs, ["a"], "avg") == [0.25]   # the binary one counts as 0
    assert choose(["x"], [0.0], random.Random(0)) == "x"


def test_bad_options() -> None:
    with pytest.raises(ValueError):
        decide(parse("a+"), policy="greedy")
    with pytest.raises(ValueError):
        decide(parse("a+"), numeric_mode="max")


def test_common_case_is_cheap() -> None:
    """One candidate, or a few unary-indifferent ones: well under 50 us a call."""
    import time

    one = parse("a+")
    few = parse("a+ b+ c+ a= b= c=")
    rng = random.Random(0)
    t0 = time.perf_counter()
    for _ in range(2000):
        decide(one, rng=rng)
        decide(few, rng=rng)
    per_call = (time.perf_counter() - t0) / 4000
    assert per_call < 50e-6, per_call
