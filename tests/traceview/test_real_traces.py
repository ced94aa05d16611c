"""The trace commands on traces the engine itself wrote."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from adapt.errors import TraceError
from adapt.traceview.memory import memory_at
from adapt.traceview.reader import Trace
from adapt.traceview.rules import load_productions
from adapt.traceview.show import ShowFilter, show_lines
from adapt.traceview.stats import compute_stats
from adapt.traceview.why import explain, find_timetag, why_not

engine = pytest.importorskip("adapt.engine")

RULES = """
sp {propose*init
   (state <s> ^superstate nil -^count)
-->
   (<s> ^operator <o> +)
   (<o> ^name init)}

sp {apply*init
   (state <s> ^operator.name init)
-->
   (<s> ^count 0)}

sp {propose*count
   (state <s> ^count <c> < 5)
-->
   (<s> ^operator <o> + =)
   (<o> ^name count)}

sp {propose*bump
   (state <s> ^count 2)
-->
   (<s> ^operator <o> + =)
   (<o> ^name bump)}

sp {apply*count
   (state <s> ^operator.name count ^count <c>)
-->
   (<s> ^count (+ <c> 1) ^count <c> -)}

sp {apply*bump
   (state <s> ^operator.name bump ^count <c>)
-->
   (<s> ^count (+ <c> 1) ^count <c> -)}

sp {done
   (state <s> ^count 5)
-->
   (write |done|)
   (halt)}
"""


@pytest.fixture
def real_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.chdir(tmp_path)
    Path("counter.soar").write_text(RULES)
    agent = engine.Agent(trace="run.jsonl", trace_level=5, seed=1)
    agent.load_file("counter.soar")
    report = agent.run(max_decisions=20)
    agent.close()
    return Trace(tmp_path / "run.jsonl"), report


def test_show_lists_the_operators_the_run_selected(real_run) -> None:
    trace, report = real_run
    lines = list(show_lines(trace, ShowFilter()))
    decisions = [line for line in lines if ": O: " in line]
    assert [line.split("(")[1].rstrip(")") for line in decisions] == [op[2] for op in report.operators]
    assert "done" in lines


def test_stats_agree_with_the_run_report(real_run) -> None:
    trace, report = real_run
    stats = compute_stats(trace)
    assert stats.decisions == report.decisions
    assert sum(stats.firings.values()) == report.production_firings
    assert stats.stop_reason == report.stop_reason


def test_wm_and_why_on_a_real_trace(real_run) -> None:
    trace, report = real_run
    counts = [w[3] for w in memory_at(trace, 4).find("S1", "count")]
    assert counts == [3]  # init, then three operators that each add one
    origin = explain(trace, find_timetag(trace, "S1", "count", "3"), 1, load_productions(trace))
    # count and bump are indifferent: the maker is the apply rule of the operator selected at 4
    assert origin.maker == "apply*" + report.operators[3][2]
    assert origin.firing["bindings"]["<c>"] == 2 and origin.cycle == 4
    result = why_not(trace, "propose*bump", 4, load_productions(trace))
    assert result.last_fired == 3 and result.failure is not None


def test_initial_wmes_from_the_header(tmp_path: Path) -> None:
    rows = [{"kind": "header", "format": "adapt-trace", "version": 1, "level": 4, "files": [],
             "wmes": [[1, {"id": "S1"}, "type", "state", False],
                      [2, {"id": "S1"}, "superstate", "nil", False]]},
            {"kind": "phase", "d": 0, "phase": "input", "adds": [[3, {"id": "S1"}, "x", 1, False]],
             "removes": [2]},
            {"kind": "decision", "d": 1, "level": 0, "selected": None, "impasse": None}]
    path = tmp_path / "t.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    trace = Trace(path)
    assert sorted(w[0] for w in memory_at(trace, 1)) == [1, 3]
    assert explain(trace, 1, 0).maker == "the architecture (before the first phase)"
    assert compute_stats(trace).wm_final == 2


@pytest.fixture
def water_jug_run(tmp_path: Path):
    """Water jug: i-supported WMEs are added and retracted within one apply phase."""
    root = Path(__file__).resolve().parents[2]
    agent = engine.Agent(trace=str(tmp_path / "wj.jsonl"), trace_level=5, seed=1)
    agent.load_file(str(root / "rules" / "examples" / "water-jug.soar"))
    report = agent.run(max_decisions=100)
    agent.close()
    return Trace(tmp_path / "wj.jsonl"), report


def test_same_phase_add_and_remove_is_not_kept_alive(water_jug_run) -> None:
    trace, report = water_jug_run
    same_phase = [t for r in trace.records() if r["kind"] == "phase"
                  for t in r.get("removes") or () if t in {a[0] for a in r.get("adds") or ()}]
    assert same_phase, "the fixture must exercise a WME added and removed in one phase"
    wm = memory_at(trace, report.decisions)
    assert len(wm) == report.wm_size_final
    assert not any(wm.get(t) for t in same_phase)
    assert compute_stats(trace).wm_final == report.wm_size_final
    origin = explain(trace, same_phase[0], 0)
    assert origin.removed is not None and origin.removed[0] == origin.cycle


def test_wm_past_the_last_decision_is_an_error(water_jug_run) -> None:
    trace, report = water_jug_run
    assert len(memory_at(trace, report.decisions)) == report.wm_size_final
    with pytest.raises(TraceError, match=f"ends at decision {report.decisions}"):
        memory_at(trace, report.decisions + 5)
