from __future__ import annotations

from adapt.traceview.reader import Trace
from adapt.traceview.show import ShowFilter, show_lines


def text(path, **kw) -> str:
    return "\n".join(show_lines(Trace(path), ShowFilter(**kw)))


def test_level_1_is_decisions_and_writes(counter_trace) -> None:
    assert text(counter_trace(8, tie_every=7), first=6, last=8) == (
        "    6: O: O6 (count)\n"
        "count 6\n"
        "    7: ==>S: S2 (operator tie)\n"
        "    8: O: O7 (count)\n"
        "count 7"
    )


def test_level_4_shows_wme_changes_in_soar_order(counter_trace) -> None:
    assert text(counter_trace(3), first=3, last=3, level=4) == (
        "--- input phase ---\n"
        "--- propose phase ---\n"
        "Firing propose*count\n"
        "=>WM: (15: O3 ^name count)\n"
        "=>WM: (16: S1 ^operator O3 +)\n"
        "    3: O: O3 (count)\n"
        "--- decision phase ---\n"
        "<=WM: (13: S1 ^operator O2)\n"
        "<=WM: (11: O2 ^name count)\n"
        "=>WM: (17: S1 ^operator O3)\n"
        "--- apply phase ---\n"
        "Retracting propose*count\n"
        "Firing apply*count\n"
        "<=WM: (14: S1 ^count 2)\n"
        "<=WM: (16: S1 ^operator O3 +)\n"
        "=>WM: (18: S1 ^count 3)\n"
        "--- output phase ---\n"
        "count 3"
    )


def test_level_5_adds_preferences_and_bindings(counter_trace) -> None:
    out = text(counter_trace(7, tie_every=7), first=7, last=7, level=5).splitlines()
    assert "       preferences: O7 (count) +; O8 (skip) +" in out
    assert "Firing tie*prefer-count [<ss>=S2, <s>=S1]" in out


def test_rule_filter_keeps_only_cycles_where_it_fired(counter_trace) -> None:
    out = text(counter_trace(20, tie_every=7), rule="tie*prefer-count", level=3)
    assert [line for line in out.splitlines() if line.startswith(("Firing", "    ", "   "))] == [
        "    7: ==>S: S2 (operator tie)", "Firing tie*prefer-count",
        "   14: ==>S: S3 (operator tie)", "Firing tie*prefer-count"]


def test_id_filter(counter_trace) -> None:
    out = text(counter_trace(10, tie_every=7), ident="S2", level=4).splitlines()
    changes = [line for line in out if "WM:" in line]
    assert changes and all("S2" in line for line in changes)
    assert len([c for c in changes if c.startswith("=>")]) == 6
    assert len([c for c in changes if c.startswith("<=")]) == 6
    assert "    7: ==>S: S2 (operator tie)" in out
    assert not any(line.startswith("    3:") for line in out)


def test_level_is_capped_by_the_trace(counter_trace) -> None:
    out = text(counter_trace(3, level=2), level=5)
    assert "--- apply phase ---" in out and "Firing" not in out and "WM:" not in out
