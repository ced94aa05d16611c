from __future__ import annotations

import json

import pytest

from adapt.cli import main


def run(capsys, *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_show(capsys, counter_trace) -> None:
    status, out, _ = run(capsys, "trace", "show", str(counter_trace(5)), "--decisions", "2..3")
    assert status == 0
    assert out == "    2: O: O2 (count)\ncount 2\n    3: O: O3 (count)\ncount 3\n"


def test_wm(capsys, counter_trace) -> None:
    status, out, _ = run(capsys, "trace", "wm", str(counter_trace(4)), "--at", "2",
                         "--depth", "1")
    assert status == 0
    assert out.splitlines()[1] == "(S1 ^count 2 ^io I1 ^operator O2 ^superstate nil ^type state)"


def test_stats_json(capsys, counter_trace) -> None:
    status, out, _ = run(capsys, "trace", "stats", str(counter_trace(6)), "--json")
    assert status == 0 and json.loads(out)["decisions"] == 6


def test_truncated_trace_warns_on_stderr(capsys, counter_trace) -> None:
    status, out, err = run(capsys, "trace", "stats", str(counter_trace(6, truncate=True)))
    assert status == 0 and "decisions: 6" in out
    assert err.startswith("adapt: warning: ") and "truncated" in err


def test_not_a_trace_is_an_error_line(capsys, tmp_path) -> None:
    path = tmp_path / "notes.txt"
    path.write_text("hello\n")
    status, out, err = run(capsys, "trace", "show", str(path))
    assert status == 1 and out == ""
    assert err.startswith("adapt: error: ") and "not an adapt trace" in err


def test_bad_range_is_a_usage_error(capsys, counter_trace) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["trace", "show", str(counter_trace(2)), "--decisions", "9..3"])
    assert exc.value.code == 2
    assert "range is empty" in capsys.readouterr().err


def test_why_wme_and_rule(capsys, counter_trace, counter_rules) -> None:
    path = str(counter_trace(9, tie_every=7))
    status, out, _ = run(capsys, "trace", "why", path, "--wme", "(S1 ^count 3)", "--depth", "0")
    assert status == 0
    assert out.startswith("(18: S1 ^count 3)  added in decision cycle 3 (apply phase) by apply*count")
    status, out, _ = run(capsys, "trace", "why", path, "--rule", "check*done", "--at", "5")
    assert status == 0 and "condition 1 has no match" in out


def test_why_needs_a_question(capsys, counter_trace) -> None:
    status, _, err = run(capsys, "trace", "why", str(counter_trace(3)))
    assert status == 1 and "--wme" in err
