from __future__ import annotations

import json

from adapt.traceview.reader import Trace
from adapt.traceview.stats import compute_stats, format_stats


def test_counts_of_a_run_with_ties(counter_trace) -> None:
    stats = compute_stats(Trace(counter_trace(21, tie_every=7, schema_every=5)))
    assert stats.decisions == 21
    # ties at 7, 14, 21 propose two operators; the cycles after 7 and 14 propose none.
    assert stats.firings == {"apply*count": 18, "propose*count": 19, "propose*skip": 3,
                             "tie*prefer-count": 3}
    assert stats.impasses == {"operator tie": 3}
    assert stats.max_goal_depth == 2
    assert stats.schema_events == 4
    assert stats.stop_reason == "max-decisions"
    # 5 top-state WMEs + count + operator + its name = 8; a tie (the last cycle is one)
    # keeps two proposals (4 WMEs) and a substate of 6 WMEs instead of the operator's 2.
    assert (stats.wm_final, stats.wm_min, stats.wm_max) == (16, 8, 16)


def test_json_is_serialisable_and_complete(counter_trace) -> None:
    data = json.loads(json.dumps(compute_stats(Trace(counter_trace(5))).to_json()))
    assert data["production_firings"] == 10
    assert data["wm_size"]["series"][0] == [1, 8]
    assert data["phases"]["apply"]["count"] == 5


def test_low_level_trace_has_no_wm_size(counter_trace) -> None:
    stats = compute_stats(Trace(counter_trace(5, level=1)))
    assert stats.decisions == 5 and stats.wm_final is None and stats.firings == {}
    assert "working memory" not in format_stats(stats)


def test_time_per_phase_when_recorded(tmp_path) -> None:
    path = tmp_path / "t.jsonl"
    rows = [{"kind": "header", "format": "adapt-trace", "version": 1, "level": 2, "files": []},
            {"kind": "phase", "d": 0, "phase": "input", "time_s": 0.25},
            {"kind": "phase", "d": 1, "phase": "decision", "time_s": 0.5},
            {"kind": "decision", "d": 1, "level": 0, "selected": None, "impasse": None},
            {"kind": "phase", "d": 1, "phase": "input", "time_s": 0.125}]
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    stats = compute_stats(Trace(path))
    assert stats.phase_time_s == {"input": 0.375, "decision": 0.5}
    assert "no footer" in format_stats(stats)
