from __future__ import annotations

from adapt.cli import main
from adapt.traceview.diff import diff_traces, format_divergence
from adapt.traceview.reader import Trace


def test_identical_runs_agree(counter_trace) -> None:
    result = diff_traces(Trace(counter_trace(15, tie_every=4)), Trace(counter_trace(15, tie_every=4)))
    assert result.cycle is None and result.cycles_compared == 15


def test_a_different_increment_is_found_in_the_apply_phase(counter_trace) -> None:
    a, b = counter_trace(30, tie_every=7), counter_trace(30, tie_every=7, diverge_at=12)
    result = diff_traces(Trace(a), Trace(b))
    assert (result.cycle, result.aspect) == (12, "apply phase, WMEs added")
    assert format_divergence(result).splitlines() == [
        "the traces diverge at decision cycle 12: apply phase, WMEs added",
        "  A:", "    (S1 ^count 11)", "  B:", "    (S1 ^count 12)"]


def test_a_different_decision(counter_trace) -> None:
    result = diff_traces(Trace(counter_trace(12, tie_every=5)), Trace(counter_trace(12, tie_every=6)))
    assert result.cycle == 5 and result.aspect == "proposal phase, firings"


def test_length_and_header(counter_trace) -> None:
    result = diff_traces(Trace(counter_trace(10)), Trace(counter_trace(8, seed=4)))
    assert (result.cycle, result.aspect) == (9, "length")
    assert result.headers == ("seed: 1 vs 4",)


def test_cli_exit_code(capsys, counter_trace) -> None:
    a, b = counter_trace(6), counter_trace(6, diverge_at=2)
    assert main(["trace", "diff", str(a), str(a), "--exit-code"]) == 0
    assert main(["trace", "diff", str(a), str(b), "--exit-code"]) == 1
    assert "diverge at decision cycle 2" in capsys.readouterr().out
