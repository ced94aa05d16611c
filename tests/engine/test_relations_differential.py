"""Relational tests between values of different types, on random rules, against the kernel.

Soar compares a value with one of another type as *less*, whichever side it is on, so
``a < <x>`` and ``<x> > a`` differ, and which one Soar evaluates depends on where its
reorderer puts the test back (``docs/rule-language.md``).  Hand-written agents cover the
cases we thought of (``agents/relations_*.soar``); this file writes rule files of random
conditions -- relations on attributes and values, anchored on constants and on variables,
inside conjunctive negations -- over a working memory of identifiers, strings, ints and
floats, and runs each in the real Soar kernel and in adapt with both matchers.  It found
the readings ``conditions.turned_round`` implements, the join order's tie on a condition
with its tests lifted out, and the roots of a production whose identifiers are all values.
"""

from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

from .soar_harness import first_difference, run_adapt, run_soar
from .test_differential import requires_soar

ATTRIBUTES = ("a", "b", "n", "m", "w", "v", "c")
RELATIONS = ("<", ">", "<=", ">=")
VARIABLES = ("<x>", "<y>", "<z>")
#: ^a and ^b are the state itself: identifier, string, int and float values
WORKING_MEMORY = "^a <s> ^b <s> ^n 2 ^m 3.5 ^w apple ^v 7 ^c a"


def _condition(rng: random.Random) -> tuple[str, set[str]]:
    """A random condition on the state and the variables its equality tests bind."""
    attr, rel = rng.choice(ATTRIBUTES), rng.choice(RELATIONS)
    v, u = rng.choice(VARIABLES), rng.choice(VARIABLES)
    shapes = [
        (f"(<s> ^{attr} {v})", {v}),
        (f"(<s> ^{attr} {{ {u} {rel} {v} }})", {u}),
        (f"(<s> ^{{ {attr} {rel} {v} }})", set()),
        (f"(<s> ^{{ {attr} {rel} {v} }} {u})", {u}),
        (f"(<s> ^{{ {u} {rel} {v} }} <s>)", {u}),
        (f"(<s> ^{attr} {{ {rel} {v} }})", set()),
    ]
    return rng.choice(shapes)


def _used(conditions: list[tuple[str, set[str]]]) -> set[str]:
    return set(re.findall(r"<[xyz]>", " ".join(text for text, _ in conditions)))


def _bound(conditions: list[tuple[str, set[str]]]) -> set[str]:
    return set().union(*(binds for _, binds in conditions)) if conditions else set()


def random_rules(seed: int, count: int) -> str:
    """A rule file: ``init`` makes the working memory, each rule writes its number, ``stop``
    halts after the first elaboration.  Every relational variable is bound by a positive
    condition in its scope; a conjunctive negation of one condition compares only with
    variables bound outside it (Soar refuses the rest)."""
    rng = random.Random(seed)
    rules = [f"sp {{init (state <s> ^superstate nil -^go) --> (<s> {WORKING_MEMORY} ^go yes)}}"]
    for r in range(count):
        while True:
            conditions = [_condition(rng) for _ in range(rng.randint(2, 3))]
            if _used(conditions) <= _bound(conditions):
                break
        body = " ".join(text for text, _ in conditions)
        if rng.random() < 0.3:
            k = rng.randint(1, 2)
            inner, outer = conditions[-k:], conditions[:-k]
            if (_used(inner) <= _bound(inner) | _bound(outer) and _used(outer) <= _bound(outer)
                    and (k > 1 or _used(inner) <= _bound(outer))):
                body = " ".join(text for text, _ in outer) + " -{ " + " ".join(
                    text for text, _ in inner) + " }"
        rules.append(f"sp {{rule{r} (state <s> ^superstate nil ^go) {body} --> "
                     f"(write |R{r} |)}}")
    rules.append("sp {stop (state <s> ^superstate nil ^go) --> (halt)}")
    return "\n".join(rules) + "\n"


def test_random_rules_are_well_formed_and_vary() -> None:
    text = random_rules(1, 40)
    assert text == random_rules(1, 40) and text != random_rules(2, 40)
    assert text.count("sp {") == 42 and "-{" in text and "^{ a" in text


@requires_soar
@pytest.mark.soar
@pytest.mark.parametrize("seed", range(1, 13))
def test_random_relations_match_as_in_real_soar(seed: int, tmp_path: Path) -> None:
    """The same rules fire, as often, in Soar and in adapt with either matcher (every one of
    these seeds failed with the readings adapt had before 2026-11-29)."""
    path = tmp_path / f"relations-{seed}.soar"
    path.write_text(random_rules(seed, 80))
    soar = run_soar(path)
    assert soar.get("error") is None and soar["halted"], soar
    assert soar["output"].count("R") >= 10  # enough rules fire to say something
    for matcher in ("rete", "naive"):
        difference = first_difference(soar, run_adapt(path, matcher=matcher))
        assert difference is None, f"seed {seed} ({matcher}): {difference}"
