"""``adapt rules run --engine soar``: the same command line, statuses and reports as the own
engine, and the Soar engine's own bad input."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from adapt.cli import main

pytestmark = pytest.mark.soar

ROOT = Path(__file__).resolve().parents[2]
WATER_JUG = ROOT / "rules" / "examples" / "water-jug.soar"

STOPS = {
    "halt": ("sp {a (state <s> ^superstate nil) --> (write |hi|) (halt)}", 0),
    "interrupt": ("sp {a (state <s> ^superstate nil) --> (interrupt)}", 5),
    "rule error": ("sp {a (state <s> ^superstate nil) --> (<s> ^x (/ 1 0)) (halt)}", 6),
    "goal depth": ("max-goal-depth 5\nsp {a (state <s> ^superstate nil) --> (<s> ^x 1)}", 4),
    "decision bound": ("sp {a (state <s> ^superstate nil) --> (<s> ^operator <o> +) "
                       "(<o> ^name x)}", 3),
}


@pytest.mark.parametrize("stop", sorted(STOPS))
def test_each_stop_has_the_same_status_and_report_on_both_engines(
        stop: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text, status = STOPS[stop]
    rules = tmp_path / "a.soar"
    rules.write_text(text + "\n")
    reports = {}
    for engine in ("adapt", "soar"):
        assert main(["rules", "run", str(rules), "--engine", engine, "--json",
                     "--max-decisions", "8"]) == status
        reports[engine] = json.loads(capsys.readouterr().out)
    own, kernel = reports["adapt"], reports["soar"]
    assert (own["engine"], kernel["engine"]) == ("adapt", "soar")
    for key in ("halted", "stop_reason", "decisions", "output", "operators", "impasses",
                "production_firings", "exit_status"):
        assert own[key] == kernel[key], key


def test_the_summary_line_and_writes_as_they_happen(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rules", "run", str(WATER_JUG), "--engine", "soar"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Measure 4 gallons")
    assert out.endswith("-- halt: 8 decisions, 32 firings, 8 operators, 0 impasses, 31 WMEs\n")


def test_without_soar_sml_it_says_which_extra_to_install(
        monkeypatch: Any, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "soar_sml", None)
    assert main(["rules", "run", str(WATER_JUG), "--engine", "soar"]) == 1
    err = capsys.readouterr().err
    assert err == ("adapt: error: the Soar engine needs the Soar kernel, which is not installed: "
                   "pip install 'adapt[soar]' (soar-sml, Soar 9.6)\n")


def test_a_rule_the_kernel_rejects_is_an_error_with_file_and_line(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rules = tmp_path / "bad.soar"
    rules.write_text("sp {ok (state <s> ^superstate nil) --> (<s> ^a 1)}\n\n"
                     "sp {later (state <s>) --> (<s> ^d 1)}\n")
    assert main(["rules", "run", str(rules), "--engine", "soar"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"adapt: error: {rules}:3:1: the Soar kernel rejected it: Expected "
                          "attribute-value test after state/impasse test.")
    assert "sp {later (state <s>) --> (<s> ^d 1)}" in err


@pytest.mark.parametrize("argv, message", [
    (["--engine", "kernel"], "unknown engine 'kernel'; expected adapt (adapt's own, the default) "
                             "or soar (the Soar kernel, soar-sml)"),
    (["--engine", "soar", "--matcher", "naive"],
     "--matcher chooses the matcher of adapt's own engine; the Soar kernel (--engine soar) "
     "matches with its own Rete"),
])
def test_bad_options(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rules", "run", str(WATER_JUG), *argv]) == 1
    assert capsys.readouterr().err == f"adapt: error: {message}\n"


def test_rules_info_says_whether_the_soar_engine_can_run(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rules", "info"]) == 0
    assert "Soar engine (--engine soar): soar-sml 9.6" in capsys.readouterr().out


def test_ctrl_c_stops_the_kernel_and_reports_what_ran(tmp_path: Path) -> None:
    rules = tmp_path / "count.soar"
    rules.write_text("""
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose (state <s> ^count <c>) --> (<s> ^operator <o> +) (<o> ^name count ^value <c>)}
sp {apply (state <s> ^operator <o> ^count <c>) (<o> ^name count ^value <c>)
   --> (<s> ^count <c> - (+ <c> 1))}
""")
    trace = tmp_path / "t.jsonl"
    proc = subprocess.Popen([sys.executable, "-m", "adapt", "rules", "run", str(rules),
                             "--engine", "soar", "--trace", str(trace)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=dict(os.environ))
    deadline = time.time() + 60
    while time.time() < deadline and (not trace.exists() or trace.stat().st_size < 20_000):
        time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert b"-- interrupted by Ctrl-C: " in out and err.endswith(b"adapt: interrupted\n")
    footer = json.loads(trace.read_text().splitlines()[-1])
    assert footer["kind"] == "footer" and footer["stop_reason"] == "interrupted"
    assert footer["decisions"] > 10
