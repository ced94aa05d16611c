"""The JSON Lines trace: records, levels, flushing, footer on errors (both engines where
the engine does not matter; what the Soar kernel does not report is checked as absent)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

import pytest

from adapt.engine import Agent
from adapt.errors import EngineError

Make = Callable[..., Any]

COUNTER = """
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose (state <s> ^count {<c> < 3}) --> (<s> ^operator <o> +) (<o> ^name count)}
sp {apply (state <s> ^operator.name count ^count <c>)
   --> (<s> ^count <c> -) (<s> ^count (+ <c> 1)) (write <c>)}
sp {done (state <s> ^count 3) --> (halt)}
"""


def records(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()]


def test_level_5_trace_rebuilds_working_memory(make: Make, engine: str, tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = make(trace=str(path))
    agent.load_text(COUNTER)
    report = agent.run()
    agent.close()
    recs = records(path)
    assert recs[0]["kind"] == "header" and recs[0]["level"] == 5
    assert recs[-1]["kind"] == "footer" and recs[-1]["decisions"] == report.decisions
    decisions = [r for r in recs if r["kind"] == "decision"]
    assert [r["d"] for r in decisions] == list(range(1, report.decisions + 1))
    assert decisions[0]["selected"]["name"] == "init"
    if engine == "adapt":
        assert decisions[0]["candidates"][0]["preferences"] == [["+", None]]
    else:  # the kernel does not report candidates: absent, and said so
        assert "candidates" not in decisions[0]
        assert "decision.candidates" in recs[0]["absent"] and recs[0]["engine"] == "soar"
    wm: dict[int, list] = {}
    for r in recs:
        if r["kind"] == "phase":
            for tt in r["removes"]:
                del wm[tt]
            for add in r["adds"]:
                wm[add[0]] = add
    assert len(wm) == report.wm_size_final
    writes = "".join(r.get("writes", "") for r in recs if r["kind"] == "phase")
    assert writes == report.output == "012"
    fired = [f for r in recs if r["kind"] == "phase" for f in r["firings"]]
    assert {f["support"] for f in fired if f["rule"] == "apply"} == {"o"}


def test_level_1_has_no_phase_records(make: Make, tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = make(trace=str(path), trace_level=1)
    agent.load_text(COUNTER)
    agent.run()
    agent.close()
    assert {r["kind"] for r in records(path)} == {"header", "decision", "footer"}


@pytest.mark.parametrize("level", [1, 2, 3, 4, 5])
def test_a_level_listens_only_to_what_it_writes(tmp_path: Path, level: int) -> None:
    # level 1 must cost what it shows: no firing bindings, WME lists or
    # candidate lists are built for records the level does not write
    from adapt.engine.events import Event

    path = tmp_path / "t.jsonl"
    agent = Agent(trace=str(path), trace_level=level)
    agent.load_text(COUNTER)
    report = agent.run()
    heard = {event for event in Event if agent.events.listeners(event)}
    agent.close()
    assert (Event.FIRE in heard) == (Event.RETRACT in heard) == (level >= 3)
    assert (Event.WM_CHANGES in heard) == (level >= 4)
    assert (Event.WRITE in heard) == (level >= 2)
    decisions = [r for r in records(path) if r["kind"] == "decision"]
    assert len(decisions) == report.decisions
    assert [r["selected"]["name"] for r in decisions] == ["init", "count", "count", "count"]
    assert all(("candidates" in r) == (level == 5) for r in decisions)
    assert list(decisions[0]) == (["kind", "d", "level"] + ["candidates"] * (level == 5)
                                  + ["selected", "impasse"])


def test_footer_written_when_a_user_function_raises(tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = Agent(trace=str(path), trace_level=2)

    def boom(*args: object) -> None:
        raise RuntimeError("sensor failed")

    agent.register_function("boom", boom)
    agent.load_text(COUNTER + "sp {b (state <s> ^count 2) --> (boom)}")
    with pytest.raises(EngineError, match="sensor failed"):
        agent.run()
    agent.close()
    recs = records(path)
    assert recs[-1]["kind"] == "footer" and "sensor failed" in recs[-1]["error"]


def test_footer_written_when_an_input_callback_raises(make: Make, engine: str,
                                                     tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = make(trace=str(path), trace_level=2)
    agent.load_text(COUNTER)

    def sense(w: Any) -> None:
        if w.decision == 2:
            raise RuntimeError("camera unplugged")

    agent.on_input(sense)
    with pytest.raises(RuntimeError, match="camera unplugged"):
        agent.run()
    agent.close()
    recs = records(path)
    assert recs[-1]["kind"] == "footer" and "camera unplugged" in recs[-1]["error"]
    assert recs[-1]["stop_reason"] == "interrupted"
    # the own engine stops at once; the kernel stops its run at the end of the decision
    # under way (Soar's stop-soar), and the trace says so
    assert recs[-1]["decisions"] == {"adapt": 2, "soar": 3}[engine]


def test_trace_is_valid_up_to_the_last_decision_when_interrupted(make: Make,
                                                                   tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    agent = make(trace=str(path), trace_level=2)
    agent.load_text(COUNTER)
    agent.run(2)                       # flushed per decision, file still open
    lines = path.read_text().splitlines()
    recs = [json.loads(line) for line in lines]
    assert recs[-1]["kind"] in ("decision", "footer")
    assert [r["d"] for r in recs if r["kind"] == "decision"] == [1, 2]
    agent.close()
