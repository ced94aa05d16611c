"""Scenarios on the Soar engine: ``engine: soar``, the check, the same decisions as the own
engine on the mirror's rules, and a kernel crash in the middle of ``adapt run``."""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path
from typing import Any

import pytest

from adapt.cli import main
from adapt.errors import EngineError, ScenarioError
from adapt.runner import Runner, check_scenario
from adapt.runner.record import FrameRecord
from adapt.scenario import EngineName, OutputSettings, load_scenario
from adapt.traceview.diff import diff_traces
from adapt.traceview.reader import Trace

ROOT = Path(__file__).resolve().parents[2]
BALL = ROOT / "scenarios" / "bouncing-ball.yaml"
#: Frames of the bouncing ball that hold its first decisions that matter: the background
#: schema (decision 1), the ball spawned bottom-up (decision 37, frame 12) and the intercept
#: schema instantiated for the goal (decision 39).
FRAMES = 16
TRACE_ONLY = OutputSettings(video=False, figures=False, report=True, trace=True, trace_level=4)


def test_check_refuses_the_soar_engine_without_the_kernel_at_its_position(
        tmp_path: Path, monkeypatch: Any, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "soar_sml", None)      # soar-sml is not installed
    text = BALL.read_text().replace("../", str(ROOT) + "/").replace("rules:", "engine: soar\nrules:")
    path = tmp_path / "ball.yaml"
    path.write_text(text)
    line = text.splitlines().index("engine: soar") + 1
    with pytest.raises(ScenarioError) as info:
        check_scenario(load_scenario(path))
    assert (info.value.file, info.value.line, info.value.col) == (str(path), line, 9)
    assert info.value.message == ("engine: the Soar engine needs the Soar kernel, which is not "
                                  "installed: pip install 'adapt[soar]' (soar-sml, Soar 9.6)")
    assert main(["check", str(BALL), "--set", "engine=soar"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("adapt: error: --set:1:8: engine: the Soar engine needs the Soar "
                          "kernel") and "adapt[soar]" in err


@pytest.mark.soar
def test_check_loads_the_rules_into_the_kernel(tmp_path: Path) -> None:
    sc = load_scenario(BALL, overrides=["engine=soar"])
    assert sc.engine is EngineName.SOAR
    assert [r.productions for r in check_scenario(sc).rules] == [22, 17]
    # what the own engine refuses, the kernel reads; what the kernel rejects is an error
    # with the file and line
    learning = tmp_path / "learning.soar"
    learning.write_text("chunk always\n" + (ROOT / "rules/mirror/perception.soar").read_text())
    over = [f"rules=[{learning}]"]
    assert [r.productions for r in check_scenario(load_scenario(BALL, over + ["engine=soar"])
                                                  ).rules] == [22]
    with pytest.raises(Exception, match="chunking"):
        check_scenario(load_scenario(BALL, over))
    learning.write_text("sp {broken (state <s>) --> (<s> ^a)}\n")
    with pytest.raises(Exception, match=r"the Soar kernel rejected it") as info:
        check_scenario(load_scenario(BALL, over + ["engine=soar"]))
    assert info.value.file.endswith("learning.soar") and info.value.line == 1  # type: ignore[attr-defined]


def _run(engine: str, out: Path, frames: int = FRAMES) -> dict[str, Any]:
    sc = load_scenario(BALL, overrides=[f"engine={engine}"])
    Runner(sc, out=out, max_frames=frames, outputs=TRACE_ONLY).run()
    return json.loads((out / "report.json").read_text())


def _decisions(trace: Path) -> list[tuple[int, Any, Any]]:
    return [(r["d"], (r.get("selected") or {}).get("name"), r.get("impasse"))
            for r in Trace(trace).records() if r["kind"] == "decision"]


def _schema_events(trace: Path) -> list[tuple[Any, ...]]:
    return [(r["d"], r["event"], r["schema"]) for r in Trace(trace).records()
            if r["kind"] == "schema"]


@pytest.mark.soar
def test_the_bouncing_ball_makes_the_same_decisions_on_both_engines(tmp_path: Path) -> None:
    own = _run("adapt", tmp_path / "own")
    soar = _run("soar", tmp_path / "soar")
    a, b = tmp_path / "own" / "trace.jsonl", tmp_path / "soar" / "trace.jsonl"
    assert Trace(b).header.raw["engine"] == "soar" and "engine" not in Trace(a).header.raw
    decisions = _decisions(a)
    assert len(decisions) == 3 * FRAMES and decisions == _decisions(b)
    selected = [name for _, name, _ in decisions if name != "wait"]
    assert selected[:2] == ["instantiate-background", "clean-command"]
    assert "spawn-object" in selected and "instantiate-intercept" in selected
    assert _schema_events(a) == _schema_events(b)
    assert ("spawned", "ball") in [(e, s) for _, e, s in _schema_events(a)]
    # every decision cycle the same: operators, firings by rule, WME changes, output-link
    result = diff_traces(Trace(a), Trace(b))
    assert result.cycle is None and result.cycles_compared >= 3 * FRAMES
    for key in ("decisions", "halted", "stopped", "events"):
        assert own["summary"][key] == soar["summary"][key], key


class _KillKernel:
    """A frame listener that kills the Soar kernel's process after frame ``at``."""

    def __init__(self, at: int) -> None:
        self.at = at
        self.runner: Runner | None = None

    def frame(self, record: FrameRecord) -> None:
        if record.index == self.at and self.runner is not None:
            os.kill(self.runner.agent.process.pid, signal.SIGKILL)  # type: ignore[attr-defined]


@pytest.mark.soar
def test_a_kernel_crash_ends_the_run_with_a_complete_report_and_trace(tmp_path: Path) -> None:
    killer = _KillKernel(at=5)
    sc = load_scenario(BALL, overrides=["engine=soar"])
    runner = Runner(sc, out=tmp_path, max_frames=FRAMES, outputs=TRACE_ONLY, listeners=(killer,))
    killer.runner = runner
    with pytest.raises(EngineError, match="the Soar kernel's process was killed by SIGKILL"):
        runner.run()
    report = json.loads((tmp_path / "report.json").read_text())
    summary = report["summary"]
    assert summary["stopped"] == "error" and "KernelCrash" in summary["error"]
    assert summary["frames"] == 6 and len(report["frames"]) == 6
    trace = Trace(tmp_path / "trace.jsonl")
    records = list(trace.records())                     # every record reads
    kinds = [r["kind"] for r in records]
    assert kinds.count("footer") == 1 and kinds[-1] == "footer" and kinds[-2] == "summary"
    footer = records[-1]
    assert "KernelCrash" in footer["error"] and footer["stop_reason"] == "error"
    decided = [r["d"] for r in records if r["kind"] == "decision"]
    assert decided == list(range(1, len(decided) + 1)) and len(decided) == 3 * 6
    assert footer["decisions"] == summary["decisions"] == len(decided)
    assert not list(tmp_path.glob("*.tmp*")) and not (tmp_path / ".lock").exists()


@pytest.mark.soar
def test_adapt_run_reports_a_kernel_crash(tmp_path: Path, monkeypatch: Any,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    from adapt.soar import SoarAgent

    real = SoarAgent.run
    calls = []

    def crashing(self: SoarAgent, *args: Any, **kw: Any) -> Any:
        calls.append(1)
        if len(calls) == 4:
            os.kill(self.process.pid, signal.SIGSEGV)
        return real(self, *args, **kw)

    monkeypatch.setattr(SoarAgent, "run", crashing)
    status = main(["run", str(BALL), "--set", "engine=soar", "--max-frames", "8", "--out",
                   str(tmp_path), "--no-video", "--no-figures", "--quiet"])
    out, err = capsys.readouterr()
    assert status == 1
    assert err.startswith("adapt: error: the Soar kernel's process was killed by SIGSEGV")
    assert "Traceback" not in err and err.rstrip().endswith(
        f"the run stopped in frame 3, and {tmp_path / 'trace.jsonl'} and "
        f"{tmp_path / 'report.json'} hold what ran")
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["summary"]["frames"] == 3 and report["summary"]["stopped"] == "error"
    assert list(Trace(tmp_path / "trace.jsonl").records())[-1]["kind"] == "footer"


def test_a_sweep_refuses_the_soar_engine_without_the_kernel_at_its_column(monkeypatch: Any) -> None:
    from adapt.sweep.plan import make_plan

    monkeypatch.setitem(sys.modules, "soar_sml", None)
    text = "engine=adapt,soar"
    with pytest.raises(ScenarioError) as info:
        make_plan(BALL, seeds="1-2", sets=[text])
    assert (info.value.file, info.value.col) == ("--set", text.index("soar") + 1)
    assert "adapt[soar]" in info.value.message


@pytest.mark.soar
def test_a_sweep_makes_the_engine_an_axis() -> None:
    from adapt.sweep.plan import make_plan

    plan = make_plan(BALL, seeds="1-2", sets=["engine=adapt,soar"])
    assert [r.overrides for r in plan.runs] == [("engine=adapt",), ("engine=soar",)] * 2
