"""Statistics, metrics and the record file: closed forms, the summary contract, and crashes."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from adapt.errors import OutputError, SweepError
from adapt.sweep.aggregate import cell_stats, csv_text, deterministic
from adapt.sweep.grid import parse_axis
from adapt.sweep.metrics import metrics_of
from adapt.sweep.stats import describe, median_interval, rate, wilson
from adapt.sweep.store import RunLog

# -- statistics ------------------------------------------------------------------------------


@pytest.mark.parametrize("k, n, low, high", [
    # Newcombe (1998, Statistics in Medicine 17:857), Wilson 95 % intervals of 81/263 and
    # 15/148; for 0/n and n/n the closed form z^2 / (n + z^2)
    (81, 263, 0.2553, 0.3662),
    (15, 148, 0.0624, 0.1605),
    (0, 10, 0.0, 0.2775),
    (10, 10, 0.7225, 1.0),
])
def test_wilson_matches_published_intervals(k: int, n: int, low: float, high: float) -> None:
    a, b = wilson(k, n)
    assert a == pytest.approx(low, abs=1e-4) and b == pytest.approx(high, abs=1e-4)


@given(st.integers(1, 400).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))))
def test_wilson_holds_the_estimate_inside_zero_one(kn: tuple[int, int]) -> None:
    k, n = kn
    a, b = wilson(k, n)
    assert 0.0 <= a <= k / n + 1e-12 and k / n - 1e-12 <= b <= 1.0


def test_rate_without_runs_is_unknown_not_zero() -> None:
    assert rate(0, 0) == {"k": 0, "n": 0, "rate": None, "low": None, "high": None}


@given(st.lists(st.floats(-1e3, 1e3), min_size=1, max_size=80))
def test_median_interval_has_its_coverage_and_holds_the_median(xs: list[float]) -> None:
    ci = median_interval(xs)
    n = len(xs)
    if ci is None:
        # no pair of order statistics covers 95 %: P(1 <= B <= n-1) < 0.95
        assert 1 - 2 / 2 ** n < 0.95
        return
    lo, hi = ci
    med = sorted(xs)[n // 2] if n % 2 else (sorted(xs)[n // 2 - 1] + sorted(xs)[n // 2]) / 2
    assert lo <= med <= hi
    j = sorted(xs).index(lo) + 1
    cover = sum(math.comb(n, i) for i in range(j, n - j + 1)) / 2 ** n
    assert cover >= 0.95


def test_describe_percentiles() -> None:
    d = describe([float(v) for v in range(1, 101)])
    assert (d["n"], d["median"], d["p10"], d["p90"], d["min"], d["max"]) == (
        100, 50.5, 10.9, 90.1, 1.0, 100.0)
    # n = 100: P(40 <= B <= 60) = 0.965 for B ~ Bin(100, 1/2), P(41 <= B <= 59) = 0.943, so the
    # 95 % interval is (x_(40), x_(61))
    assert d["median_low"] == 40.0 and d["median_high"] == 61.0
    assert describe([]) == {"n": 0}


# -- metrics from the runner's summary ----------------------------------------------------------

CONTRACT = {
    "frames": 90, "frames_per_s": 22.0, "wall_s": 4.1,
    "intercept": {"object": "ball", "reach": 0.3, "caught": False, "t": None, "reachable": True},
    "baseline": {"caught": True, "t": 2.5},
    "tracking_error_m": {"ball": {"median": 0.012, "p90": 0.03}},
    "imagination_error_m": {"ball": {"median": 0.02}},
    "camera_position_error_m": {"median": 0.002}, "camera_rotation_error_deg": None,
    "prediction_error_m": {"0.5": {"mirror": {"median": 0.05, "bounce_median": 0.09},
                                   "baseline": {"median": 0.11, "bounce_median": None}},
                           "1": {"mirror": {"median": 0.1}}},
}


def test_metrics_follow_the_summary_contract() -> None:
    m = metrics_of(CONTRACT)
    assert m == {"caught": False, "reachable": True, "baseline_caught": True,
                 "baseline_catch_t": 2.5, "tracking_error_m": 0.012,
                 "imagination_error_m": 0.02, "camera_position_error_m": 0.002,
                 "prediction_error_m@0.5": 0.05, "bounce_prediction_error_m@0.5": 0.09,
                 "baseline_prediction_error_m@0.5": 0.11, "prediction_error_m@1": 0.1,
                 "frames": 90, "frames_per_s": 22.0, "wall_s": 4.1}


def test_missing_or_odd_summary_keys_are_missing_metrics() -> None:
    assert metrics_of({}) == {}
    assert metrics_of({"intercept": "yes", "prediction_error_m": {"0.5": None},
                       "tracking_error_m": {"a": None}, "frames_per_s": float("nan")}) == {}


def test_paired_comparison_with_the_baseline() -> None:
    recs = [{"key": str(i), "status": "ok",
             "metrics": {"caught": i < 6, "baseline_caught": i % 2 == 0,
                         "prediction_error_m@0.5": 0.05 + 0.01 * i,
                         "baseline_prediction_error_m@0.5": 0.1}} for i in range(10)]
    recs.append({"key": "x", "status": "failed", "metrics": {}})
    s = cell_stats(recs, planned=12)
    assert (s["planned"], s["ok"], s["failed"], s["remaining"]) == (12, 10, 1, 1)
    assert s["rates"]["caught"]["k"] == 6 and s["rates"]["caught"]["n"] == 10  # failed: not a miss
    assert s["paired"]["caught"] == {"n": 10, "both": 3, "mirror_only": 3, "baseline_only": 2,
                                     "neither": 2}
    p = s["paired"]["prediction_error_m@0.5"]
    assert p["mirror_lower"]["k"] == 5 and p["median_difference"] == pytest.approx(-0.005)


def test_csv_has_one_row_per_run_and_the_swept_keys() -> None:
    ax = parse_axis("reality.camera_offset_deg=[1,0,0],2")
    text = csv_text([{"key": "a", "seed": 1, "set": {ax.path: [1, 0, 0]}, "status": "ok",
                      "metrics": {"caught": True}},
                     {"key": "b", "seed": 1, "set": {ax.path: 2}, "status": "failed",
                      "error": "RunError: x, y", "metrics": {}}], [ax])
    lines = text.splitlines()
    assert lines[0] == "key,seed,reality.camera_offset_deg,status,error,task_s,cpu_s,caught"
    assert lines[1] == 'a,1,"[1, 0, 0]",ok,,,,true'
    assert lines[2] == 'b,1,2,failed,"RunError: x, y",,,'


def test_timings_are_not_part_of_a_runs_result() -> None:
    a = {"key": "k", "status": "ok", "metrics": {"frames": 3, "wall_s": 1.0},
         "summary": {"frames": 3, "stage_ms": {"x": 1}, "mmd_ms_median": 3.0}}
    b = json.loads(json.dumps(a))
    b["metrics"]["wall_s"] = 2.0
    b["summary"]["stage_ms"] = {"x": 5}
    assert deterministic(a) == deterministic(b)
    b["summary"]["frames"] = 4
    assert deterministic(a) != deterministic(b)


# -- runs.jsonl ---------------------------------------------------------------------------------


def test_a_line_cut_short_is_dropped_and_the_log_goes_on(tmp_path: Path) -> None:
    path = tmp_path / "runs.jsonl"
    with RunLog(path) as log:
        log.append({"key": "a", "status": "ok", "x": float("nan")})  # JSON has no NaN
    path.write_text(path.read_text() + '{"key": "b", "stat')
    with RunLog(path) as log:
        assert [r["key"] for r in log.records] == ["a"] and log.dropped == 1
        assert log.records[0]["x"] is None
        log.append({"key": "c", "status": "ok"})
    assert [json.loads(line)["key"] for line in path.read_text().splitlines()] == ["a", "c"]


def test_a_last_record_without_its_newline_is_kept(tmp_path: Path) -> None:
    path = tmp_path / "runs.jsonl"
    path.write_text('{"key": "a"}')
    with RunLog(path) as log:
        log.append({"key": "b"})
    assert [json.loads(line)["key"] for line in path.read_text().splitlines()] == ["a", "b"]


def test_a_bad_line_inside_is_an_error_naming_it(tmp_path: Path) -> None:
    path = tmp_path / "runs.jsonl"
    path.write_text('{"key": "a"}\nnonsense\n{"key": "b"}\n')
    with pytest.raises(SweepError, match=r"runs.jsonl:2: not a run record"):
        RunLog(path).open()


def test_two_sweeps_cannot_write_one_folder(tmp_path: Path) -> None:
    with RunLog(tmp_path / "runs.jsonl"):
        with pytest.raises(OutputError, match="another adapt command .* is writing"):
            RunLog(tmp_path / "runs.jsonl").open()
    with RunLog(tmp_path / "runs.jsonl"):  # released
        pass


def test_a_sweep_removes_the_temporary_files_a_killed_sweep_left(tmp_path: Path) -> None:
    (tmp_path / "figures").mkdir()
    stale = [tmp_path / ".adapt-tmp-sweep.json.k2j3.tmp",
             tmp_path / "figures" / ".adapt-tmp-rates.png.x8y9.png"]
    for path in stale:
        path.write_text("half")
    (tmp_path / ".hidden-of-the-user").write_text("mine")
    with RunLog(tmp_path / "runs.jsonl"):
        assert not any(p.exists() for p in stale)
    assert (tmp_path / ".hidden-of-the-user").read_text() == "mine"
