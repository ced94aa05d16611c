"""The Soar engine as an agent: loading, seeds, commands, goals, and its errors."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import pytest

from adapt.engine import Agent
from adapt.errors import AdaptError, EngineError, RuleError
from adapt.soar import SoarAgent

pytestmark = pytest.mark.soar

EXAMPLES = Path(__file__).resolve().parents[2] / "rules" / "examples"

TIE = """
sp {init (state <s> ^superstate nil -^round) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^round 0)}
sp {propose (state <s> ^round < 8)
   --> (<s> ^operator <a> +) (<s> ^operator <a> =) (<s> ^operator <b> +) (<s> ^operator <b> =)
       (<s> ^operator <c> +) (<s> ^operator <c> =) (<a> ^name a) (<b> ^name b) (<c> ^name c)}
sp {apply (state <s> ^operator <o> ^round <r>) (<o> ^name { <n> <> init })
   --> (write <n>) (<s> ^round <r> - (+ <r> 1))}
sp {done (state <s> ^round 8) --> (write | | (rand-int 1000) | | (rand-int 1000)) (halt)}
"""


@pytest.mark.parametrize("seed", [1, 7, 42])
def test_seeds_are_soars_srand_the_same_choices_as_the_own_engine(seed: int) -> None:
    """Indifferent selection and rand-int draw from Soar's generator, seeded by srand: the
    own engine (which mirrors it) and the kernel choose alike for every seed."""
    runs = []
    for agent in (Agent(seed=seed), SoarAgent(seed=seed)):
        agent.load_text(TIE)
        runs.append(agent.run(20).output)
        agent.close()
    assert runs[0] == runs[1] and len(runs[0]) > 8


def test_reseed_is_srand(soar: SoarAgent) -> None:
    soar.load_text(TIE)
    soar.reseed(42)
    own = Agent(seed=42)
    own.load_text(TIE)
    assert soar.run(20).output == own.run(20).output


def test_a_file_loads_with_soars_source_and_runs_to_its_halt(soar: SoarAgent) -> None:
    rules = soar.load_file(EXAMPLES / "water-jug.soar")
    assert len(rules.productions) == 13 and "water-jug*apply*fill" in rules.productions
    report = soar.run()
    assert (report.halted, report.stop_reason, report.decisions) == (True, "halt", 8)
    assert report.output.endswith("Solved: the big jug holds 4 gallons after 6 steps.\n")
    assert report.messages == ["Interrupt received.", "This Agent halted."]
    assert soar.files == [str(EXAMPLES / "water-jug.soar")]


def test_a_rule_the_kernel_rejects_gives_its_message_file_and_line(tmp_path: Path,
                                                                   soar: SoarAgent) -> None:
    inner = tmp_path / "inner.soar"
    inner.write_text("sp {ok (state <s> ^superstate nil) --> (<s> ^a 1)}\n"
                     "sp {bad (state <s>) --> (<s> ^b 1)}\n")
    top = tmp_path / "top.soar"
    top.write_text("# the agent\nsource inner.soar\n")
    with pytest.raises(RuleError) as caught:
        soar.load_file(top)
    err = caught.value
    assert (Path(err.file).name, err.line) == ("inner.soar", 2)
    assert err.message.startswith("the Soar kernel rejected it: Expected attribute-value test")
    assert "sp {bad" in str(err)  # the line, with a caret


def test_load_text_names_its_file_in_errors(soar: SoarAgent) -> None:
    with pytest.raises(RuleError, match=r"^agent\.soar:2:1: the Soar kernel rejected it"):
        soar.load_text("sp {ok (state <s> ^superstate nil) --> (<s> ^a 1)}\n"
                       "sp {bad (state <s>) --> (<s> ^b 1)}\n", file="agent.soar")


def test_a_missing_file_is_a_rule_error_as_in_the_own_engine(soar: SoarAgent) -> None:
    with pytest.raises(RuleError, match="nope.soar:1:1: cannot read rule file: No such file"):
        soar.load_file("nope.soar")


def test_warnings_of_the_kernel_are_kept(soar: SoarAgent) -> None:
    rules = soar.load_text("sp {w (state <s> ^superstate nil) (<x> ^b <y>) --> (<s> ^c 1)}\n")
    assert any("not connected to any goal" in w for w in rules.warnings)
    assert rules.warnings == tuple(soar.warnings)


def test_commands_goals_and_printing(soar: SoarAgent) -> None:
    soar.load_text("sp {p (state <s> ^superstate nil) --> (<s> ^operator <a> + <b> +)"
                   " (<a> ^name a) (<b> ^name b)}")
    soar.run(1)
    assert [g.name for g in soar.goals] == ["S1", "S2"]
    assert "^impasse tie" in " ".join(soar.print_state(soar.goals[1]).split())
    assert "p" in soar.command("print --all").split()
    with pytest.raises(EngineError, match="the Soar kernel refused 'no-such-command'"):
        soar.command("no-such-command")


def test_without_soar_sml_the_error_says_which_extra_to_install(monkeypatch: Any) -> None:
    monkeypatch.setitem(sys.modules, "soar_sml", None)
    with pytest.raises(AdaptError, match=r"pip install 'adapt\[soar\]'"):
        SoarAgent()


def test_a_bad_history_or_trace_level_is_refused() -> None:
    with pytest.raises(EngineError, match="history"):
        SoarAgent(history=0)
    with pytest.raises(EngineError, match="trace level"):
        SoarAgent(trace="t.jsonl", trace_level=9)


def test_a_printed_kernel_error_is_a_message_a_written_one_is_not(soar: SoarAgent) -> None:
    # the kernel prints an RHS function's error only in its printed trace, right after the
    # decision line; a (write) is in the printed trace too
    soar.load_text("""
sp {propose (state <s> ^superstate nil -^done) --> (<s> ^operator <o> +) (<o> ^name go)}
sp {apply (state <s> ^operator.name go) --> (write |Error: only a write|) (<s> ^done yes)
   (<s> ^x (/ 1 0))}
sp {stop (state <s> ^done yes) --> (halt)}
""")
    report = soar.run(5)
    assert report.output == "Error: only a write"
    assert "Error: attempt to divide ('/') by zero." in report.messages
    assert not any("only a write" in m for m in report.messages)


def test_writing_under_a_removed_input_structure_stops_the_run_with_an_error(
        soar: SoarAgent) -> None:
    made: dict[str, Any] = {}

    def sense(w: Any) -> None:
        if w.decision == 0:
            made["thing"] = w.new_id("T")
            w.add(w.input_link, "thing", made["thing"])
        elif w.decision == 1:
            w.remove(w.input_link, "thing", made["thing"])
        elif w.decision == 2:
            w.add(made["thing"], "late", 1)  # SML has no such identifier any more

    soar.on_input(sense)
    with pytest.raises(EngineError, match="input-link: identifier T1 is not on the input-link"):
        soar.run(10)
    report = soar.report()
    assert report.stop_reason == "interrupted" and report.decisions >= 3
    assert soar.run(1).decisions == report.decisions + 1  # the kernel is still there
