"""Working memory: set semantics, timetags, buffering, garbage collection."""

from __future__ import annotations

from adapt.engine.memory import WorkingMemory
from adapt.engine.symbols import Float, IdentifierFactory, format_symbol
from adapt.engine.wme import WME


class Recorder:
    def __init__(self) -> None:
        self.log: list[tuple[str, int]] = []

    def add_wme(self, wme: WME) -> None:
        self.log.append(("+", wme.timetag))

    def remove_wme(self, wme: WME) -> None:
        self.log.append(("-", wme.timetag))


def setup():
    ids = IdentifierFactory()
    s1 = ids.state()
    rec = Recorder()
    wm = WorkingMemory(rec)
    wm.add_root(s1)
    return ids, s1, wm, rec


def test_timetags_in_request_order_and_buffering() -> None:
    ids, s1, wm, rec = setup()
    wm.add(s1, "a", 1)
    wm.add(s1, "b", 2)
    assert len(wm) == 0 and wm.pending
    added, removed = wm.commit()
    assert [w.timetag for w in added] == [1, 2] and removed == []
    # the matcher meets them as Soar's Rete does: the newest first
    assert rec.log == [("+", 2), ("+", 1)]


def test_set_semantics_and_multi_valued() -> None:
    ids, s1, wm, rec = setup()
    wm.add(s1, "a", 1)
    wm.add(s1, "a", 1)
    wm.add(s1, "a", 2)
    wm.add(s1, "a", Float(1.0))
    assert len(wm.commit()[0]) == 3
    wm.add(s1, "a", 1)
    assert wm.commit() == ([], [])           # existing WME: no-op
    wm.remove(s1, "a", 99)
    assert wm.commit() == ([], [])           # missing WME: no-op
    assert sorted(map(format_symbol, wm.values(s1, "a"))) == ["1", "1.000000", "2"]


def test_remove_and_add_in_one_batch_keeps_the_wme_unchanged() -> None:
    ids, s1, wm, rec = setup()
    wm.add(s1, "a", 1)
    wm.commit()
    rec.log.clear()
    wm.remove(s1, "a", 1)
    wm.add(s1, "a", 1)
    assert wm.commit() == ([], [])
    assert rec.log == []
    assert wm.get(s1, "a", 1).timetag == 1


def test_acceptable_flag_is_part_of_identity() -> None:
    ids, s1, wm, rec = setup()
    o1 = ids.new("O")
    wm.add(s1, "operator", o1, True)
    wm.add(s1, "operator", o1)
    assert len(wm.commit()[0]) == 2


def test_garbage_collection_of_unreachable_structure_including_cycles() -> None:
    ids, s1, wm, rec = setup()
    a, b, c = ids.new("A"), ids.new("B"), ids.new("C")
    wm.add(s1, "link", a)
    wm.add(a, "next", b)
    wm.add(b, "back", a)          # a cycle
    wm.add(b, "leaf", c)
    wm.add(c, "v", 1)
    wm.add(s1, "other", c)        # c stays reachable another way
    wm.commit()
    wm.remove(s1, "link", a)
    added, removed = wm.commit()
    assert {(w.id.name, w.attr) for w in removed} == {
        ("S1", "link"), ("A1", "next"), ("B1", "back"), ("B1", "leaf")}
    assert wm.get(c, "v", 1) is not None
    assert ("-", 2) in rec.log


def test_tree_prints_like_soar() -> None:
    ids, s1, wm, rec = setup()
    i1 = ids.new("I")
    wm.add(s1, "io", i1)
    wm.add(s1, "b", "x")
    wm.add(i1, "z", 3)
    wm.commit()
    assert wm.tree(s1, 1) == "(S1 ^b x ^io I1)"
    assert wm.tree(s1, 2) == "(S1 ^b x ^io I1)\n  (I1 ^z 3)"
