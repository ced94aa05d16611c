"""``adapt rules run``: one exit status per way a run ends; output as it happens; Ctrl-C."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.cli.exits import Exit

ROOT = Path(__file__).resolve().parents[1]

FOREVER = """\
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose*tick (state <s> ^count <c>) --> (<s> ^operator <o> +) (<o> ^name tick)}
sp {apply*tick (state <s> ^operator.name tick ^count <c>)
--> (<s> ^count <c> - (+ <c> 1)) (write |tick | <c> (crlf))}
"""

CASES = {
    "halt": ("sp {a (state <s> ^superstate nil) --> (write |hi|) (halt)}", [], Exit.OK),
    "decision limit": (FOREVER, ["--max-decisions", "5"], Exit.DECISION_LIMIT),
    "goal depth": ("sp {a (state <s> ^superstate nil) --> (<s> ^x 1)}", [], Exit.GOAL_DEPTH),
    "interrupt": ("sp {a (state <s> ^superstate nil) --> (interrupt)}", [], Exit.RULE_INTERRUPT),
    "division by zero": ("sp {a (state <s> ^superstate nil) --> (<s> ^x (/ 1 0)) (halt)}", [],
                         Exit.RULE_ERROR),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_each_stop_reason_has_its_status(tmp_path: Path, capsys, case: str) -> None:
    text, args, status = CASES[case]
    rules = tmp_path / "r.soar"
    rules.write_text(text + "\n")
    assert main(["rules", "run", str(rules), *args]) == status
    assert main(["rules", "run", str(rules), *args, "--json"]) == status
    report = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert report["exit_status"] == status


def test_write_output_is_printed_as_it_is_produced(tmp_path: Path) -> None:
    """A run that never halts shows its output at once, not when it ends."""
    rules = tmp_path / "r.soar"
    rules.write_text(FOREVER)
    proc = subprocess.Popen([sys.executable, "-m", "adapt", "rules", "run", str(rules)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT)
    try:
        first = proc.stdout.readline()  # type: ignore[union-attr]
        assert first == b"tick 0\n"
    finally:
        proc.kill()
        proc.wait()


def _interrupted(tmp_path: Path, *args: str) -> tuple[int, str, str]:
    rules = tmp_path / "r.soar"
    rules.write_text(FOREVER)
    proc = subprocess.Popen(
        [sys.executable, "-m", "adapt", "rules", "run", str(rules), *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # noqa: PLW1509
    assert proc.stdout is not None
    if "--json" in args:
        time.sleep(1.5)
    else:
        for _ in range(200):  # wait until the run is well under way
            proc.stdout.readline()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    return proc.returncode, out.decode(), err.decode()


@pytest.mark.skipif(os.name != "posix", reason="SIGINT")
def test_ctrl_c_prints_the_summary_and_the_trace_agrees(tmp_path: Path, capsys) -> None:
    trace = tmp_path / "t.jsonl"
    status, out, err = _interrupted(tmp_path, "--trace", str(trace))
    assert status == Exit.INTERRUPTED
    summary = out.splitlines()[-1]
    assert summary.startswith("-- interrupted by Ctrl-C: ") and "adapt: interrupted" in err
    decisions = int(summary.split(": ")[1].split()[0])
    footer = json.loads(trace.read_text().splitlines()[-1])
    assert footer["kind"] == "footer" and footer["decisions"] == decisions
    assert main(["trace", "stats", str(trace), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["decisions"] == decisions


@pytest.mark.skipif(os.name != "posix", reason="SIGINT")
def test_ctrl_c_prints_the_json_report_of_what_ran(tmp_path: Path) -> None:
    status, out, _ = _interrupted(tmp_path, "--json")
    assert status == Exit.INTERRUPTED
    report = json.loads(out)
    assert report["exit_status"] == Exit.INTERRUPTED and report["output"].startswith("tick 0\n")
    assert report["decisions"] > 0


def test_stats_counts_the_decisions_the_footer_counts(tmp_path: Path, capsys) -> None:
    """A run interrupted inside a decision phase may miss that decision's record."""
    rules = tmp_path / "r.soar"
    rules.write_text(FOREVER)
    trace = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(rules), "--max-decisions", "6", "--trace", str(trace)]) == 3
    lines = trace.read_text().splitlines()
    last = max(i for i, line in enumerate(lines) if '"kind":"decision"' in line)
    footer = json.loads(lines[-1])
    footer["decisions"] += 1  # the footer counts a decision whose record was never written
    trimmed = tmp_path / "cut.jsonl"
    trimmed.write_text("\n".join(lines[:last + 1] + [json.dumps(footer)]) + "\n")
    capsys.readouterr()
    assert main(["trace", "stats", str(trimmed)]) == 0
    assert "decisions: 7 " in capsys.readouterr().out
