"""A crash of the Soar kernel ends the run with a clear error and a complete, valid report
and trace of what ran.

The kernel runs in its own process; here it is killed by SIGSEGV in the middle of a run,
as a crash inside the native kernel would end it (a rule doing ``(cmd |init-soar|)`` while
it is rematched makes soar-sml 9.6.5 segfault this way, but only after tens of seconds).
"""

from __future__ import annotations

import json
import os
import signal
from pathlib import Path
from typing import Any

import pytest

from adapt.cli import main
from adapt.soar import KernelCrash, SoarAgent
from adapt.traceview.reader import Trace

pytestmark = pytest.mark.soar

COUNTER = """
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose*count (state <s> ^count { <c> < 1000 }) --> (<s> ^operator <o> +) (<o> ^name count ^value <c>)}
sp {apply*count (state <s> ^operator <o> ^count <c>) (<o> ^name count ^value <c>)
   --> (<s> ^count <c> - (+ <c> 1)) (write |count | (+ <c> 1) (crlf))}
"""


def crash_on(agent: SoarAgent, text: str) -> None:
    """Kill the kernel's process when ``text`` is written (a crash in the middle of a run)."""
    def listener(written: str) -> None:
        if written == text:
            os.kill(agent.process.pid, signal.SIGSEGV)

    agent.on_write(listener)


def test_a_crash_raises_and_leaves_a_complete_trace_and_report(tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = SoarAgent(trace=str(path), trace_level=5)
    agent.load_text(COUNTER)
    crash_on(agent, "count 5\n")
    with pytest.raises(KernelCrash, match="killed by SIGSEGV"):
        agent.run()
    report = agent.report()
    with pytest.raises(KernelCrash):                # the kernel is gone for good
        agent.run(1, footer=False)
    agent.close()
    assert report.stop_reason == "interrupted" and not report.halted
    assert report.output.startswith("count 1\ncount 2\ncount 3\ncount 4\ncount 5\n")
    assert report.decisions >= 6 and len(report.operators) == report.decisions
    trace = Trace(path)
    records = list(trace.records())               # every record is valid
    assert [r["kind"] for r in records].count("footer") == 1
    footer = records[-1]
    assert footer["kind"] == "footer" and "KernelCrash" in footer["error"]
    assert footer["decisions"] == report.decisions
    assert [r["d"] for r in records if r["kind"] == "decision"] == list(
        range(1, report.decisions + 1))


def test_the_command_line_reports_a_crash(tmp_path: Path, monkeypatch: Any,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    rules = tmp_path / "counter.soar"
    rules.write_text(COUNTER)
    trace = tmp_path / "t.jsonl"
    made: list[SoarAgent] = []
    real = SoarAgent.__init__

    def made_and_crashing(self: SoarAgent, **options: Any) -> None:
        real(self, **options)
        crash_on(self, "count 3\n")
        made.append(self)

    monkeypatch.setattr(SoarAgent, "__init__", made_and_crashing)
    status = main(["rules", "run", str(rules), "--engine", "soar", "--json",
                   "--trace", str(trace)])
    out, err = capsys.readouterr()
    assert status == 1
    report = json.loads(out)
    assert report["engine"] == "soar" and "killed by SIGSEGV" in report["error"]
    assert report["output"].startswith("count 1\ncount 2\ncount 3\n")
    assert err.startswith("adapt: error: the Soar kernel's process was killed by SIGSEGV")
    assert f"the {report['decisions']} decisions it reported" in err
    records = list(Trace(trace).records())
    assert records[-1]["kind"] == "footer" and records[-1]["decisions"] == report["decisions"]
    assert made and made[0].process.dead is not None
