"""More Rete checks for the internals its fast paths rely on: matches made
lazily at ``take_changes``, pending changes of removed productions, the
single-entry buckets of the memories, and the counter workload of
``bench/rete.py`` against the brute-force matcher."""

from __future__ import annotations

import importlib.util
import random
from pathlib import Path
from types import ModuleType

import pytest

from adapt.engine.matcher import Match
from adapt.engine.naive import NaiveMatcher
from adapt.engine.rete import Rete
from adapt.engine.wme import WME

from .strategies import A1, A2, S1, cond, keys, make_wmes, ncc, prod


def _bench() -> ModuleType:
    """``bench/rete.py``, loaded under a private name."""
    path = Path(__file__).resolve().parents[2] / "bench" / "rete.py"
    spec = importlib.util.spec_from_file_location("_bench_rete", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_match_made_with_its_key_is_the_match() -> None:
    p = prod("p", cond("<s>", "a", "<x>"), cond("<x>", "b", "<y>"))
    wmes = tuple(make_wmes([(S1, "a", A1, False), (A1, "b", 3, False)]))
    made = Match(p, wmes, ("p", (1, 2)))
    real = Match(p, wmes)
    for slot in Match.__slots__:
        assert getattr(made, slot) == getattr(real, slot), slot
    assert made == real and hash(made) == hash(real)


def test_matches_carry_their_production_and_bindings() -> None:
    m = Rete()
    # Reordered by the network: <y> is joined before <x>'s condition.
    p = prod("p", cond("<x>", "b", "<v>"), cond("<s>", "a", "<x>"), cond("<s>", "c", "<v>"))
    m.add_production(p)
    for w in make_wmes([(S1, "a", A1, False), (A1, "b", 2, False), (S1, "c", 2, False)]):
        m.add_wme(w)
    (match,), removed = m.take_changes()
    assert removed == [] and match.production is p and match.key == ("p", (2, 1, 3))
    assert [w.timetag for w in match.wmes] == [2, 1, 3]
    (current,) = m.matches()
    assert current == match and current.bindings() == match.bindings()


def test_pending_changes_survive_removing_and_readding_a_production() -> None:
    m = Rete()
    old = prod("p", cond("<s>", "a", "<x>"))
    m.add_production(old)
    w = WME(S1, "a", 1, False, 1)
    m.add_wme(w)
    assert keys(m.take_changes()[0]) == [("p", (1,))]
    m.add_wme(WME(S1, "a", 2, False, 2))
    m.remove_wme(w)           # pending: +(p, 2), -(p, 1)
    m.remove_production("p")  # cancels +(p, 2); -(p, 1) stays, with the old production
    new = prod("p", cond("<s>", "a", "<x>"), cond("<s>", "a", "<x>"))
    m.add_production(new)     # +(p, (2, 2)): a different match
    added, removed = m.take_changes()
    assert keys(added) == [("p", (2, 2))] and added[0].production is new
    assert keys(removed) == [("p", (1,))] and removed[0].production is old


def test_same_key_many_tokens_and_wmes_removed_in_any_order() -> None:
    # Every token and WME shares one join key: buckets go single -> dict ->
    # empty and back, in every order.
    rng = random.Random(7)
    productions = [
        prod("p", cond("<s>", "a", "<x>"), cond("<s>", "b", "<y>")),
        prod("q", cond("<s>", "a", "<x>"), cond("<s>", "b", "<x>", neg=True)),
        prod("r", cond("<s>", "a", "<x>"), ncc(cond("<s>", "b", "<x>"), cond("<x>", "c", None))),
    ]
    rows = [(S1, "a", v, False) for v in (1, 2, A1)] + [(S1, "b", v, False) for v in (1, A1, A2)]
    rows += [(A1, "c", 0, False)]
    wmes = make_wmes(rows)
    for _ in range(30):
        naive, rete = NaiveMatcher(), Rete()
        for p in productions:
            naive.add_production(p)
            rete.add_production(p)
        present: list[WME] = []
        for _ in range(40):
            if present and rng.random() < 0.45:
                w = present.pop(rng.randrange(len(present)))
                naive.remove_wme(w)
                rete.remove_wme(w)
            else:
                w = rng.choice(wmes)
                if w in present:
                    continue
                present.append(w)
                naive.add_wme(w)
                rete.add_wme(w)
            (na, nr), (ra, rr) = naive.take_changes(), rete.take_changes()
            assert sorted(keys(ra)) == sorted(keys(na)) and sorted(keys(rr)) == sorted(keys(nr))
            assert sorted(m.key for m in rete.matches()) == sorted(m.key for m in naive.matches())
        for w in present:
            rete.remove_wme(w)
        assert rete.state.tokens_by_wme == {}
        assert all(not j.right for j in _joins(rete))


def _joins(rete: Rete) -> list:
    out, stack = [], list(rete.root.children)
    while stack:
        node = stack.pop()
        if hasattr(node, "right"):
            out.append(node)
        stack.extend(getattr(node, "children", ()))
    return out


@pytest.mark.parametrize("cls", [NaiveMatcher, Rete])
def test_counter_workload_changes(cls) -> None:
    """The counter decisions of ``bench/rete.py``: the same changes from both
    matchers, in the same order."""
    bench = _bench()
    m = cls()
    for p in bench.counter_productions(5):
        m.add_production(p)
    base = [WME(S1, "type", "state", False, 1), WME(S1, "superstate", "nil", False, 2)]
    for w in base:
        m.add_wme(w)
    assert keys(m.take_changes()[0]) == [("counter*propose*init", (1, 2))]
    count = WME(S1, "count", 0, False, 3)
    m.add_wme(count)
    assert keys(m.take_changes()[1]) == [("counter*propose*init", (1, 2))]
    tt = 3
    for i in range(6):
        op = A2 if i % 2 else A1
        plus = WME(S1, "operator", op, True, tt + 1)
        name = WME(op, "name", "count", False, tt + 2)
        chosen = WME(S1, "operator", op, False, tt + 3)
        new = WME(S1, "count", i + 1, False, tt + 4)
        tt += 4
        m.add_wme(plus)
        m.add_wme(name)
        assert m.take_changes() == ([], [])
        m.add_wme(chosen)
        apply = ("counter*apply*count", (1, chosen.timetag, name.timetag, count.timetag))
        assert keys(m.take_changes()[0]) == [apply]
        m.remove_wme(count)
        m.add_wme(new)
        for w in (plus, name, chosen):
            m.remove_wme(w)
        added, removed = m.take_changes()
        expect_added = [("counter*propose*count", (1, new.timetag, new.timetag))] if i + 1 < 5 else []
        if i + 1 == 5:
            expect_added.append(("counter*halt", (1, new.timetag)))
        assert sorted(keys(added)) == sorted(expect_added)
        expect_removed = [apply]
        if i < 5:
            expect_removed.append(("counter*propose*count", (1, count.timetag, count.timetag)))
        if i == 5:
            expect_removed.append(("counter*halt", (1, count.timetag)))
        assert sorted(keys(removed)) == sorted(expect_removed)
        count = new
