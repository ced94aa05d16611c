from __future__ import annotations

import pytest

from adapt.errors import TraceError
from adapt.traceview.memory import format_tree, memory_at
from adapt.traceview.reader import Trace


def test_counter_value_at_each_decision(counter_trace) -> None:
    trace = Trace(counter_trace(12))
    for d in (1, 5, 12):
        wm = memory_at(trace, d)
        assert [w[3] for w in wm.find("S1", "count")] == [d]
        assert [w[3] for w in wm.find("S1", "operator") if not w[4]] == [{"id": f"O{d}"}]


def test_tree_from_the_top_state(counter_trace) -> None:
    wm = memory_at(Trace(counter_trace(3)), 3)
    assert format_tree(wm, "S1", depth=2) == (
        "(S1 ^count 3 ^io I1 ^operator O3 ^superstate nil ^type state)\n"
        "  (I1 ^input-link I2 ^output-link I3)\n"
        "  (O3 ^name count)"
    )
    assert format_tree(wm, "S1", depth=1) == (
        "(S1 ^count 3 ^io I1 ^operator O3 ^superstate nil ^type state)")


def test_substate_exists_only_during_the_impasse(counter_trace) -> None:
    trace = Trace(counter_trace(9, tie_every=7))
    at7 = memory_at(trace, 7)
    assert format_tree(at7, "S2", depth=1) == (
        "(S2 ^attribute operator ^impasse tie ^item O7 ^item O8 ^superstate S1 ^type state)")
    with pytest.raises(TraceError, match="S2 has no working-memory elements"):
        format_tree(memory_at(trace, 8), "S2")


def test_internal_lists_timetags(counter_trace) -> None:
    wm = memory_at(Trace(counter_trace(1)), 1)
    assert format_tree(wm, "I1", internal=True).splitlines() == [
        "(4: I1 ^input-link I2)", "(5: I1 ^output-link I3)"]


def test_level_below_4_cannot_rebuild(counter_trace) -> None:
    with pytest.raises(TraceError, match="needs a trace written at level 4"):
        memory_at(Trace(counter_trace(3, level=3)), 2)
