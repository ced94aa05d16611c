"""The kernel's XML trace read into adapt's report and trace records (no kernel needed).

The XML strings are shaped as soar-sml 9.6.5 sends them (taken from its trace of
``rules/examples/water-jug.soar`` and of a tie impasse).
"""

from __future__ import annotations

import io
import json
from typing import Any

from adapt.engine.trace import TraceWriter
from adapt.soar.recorder import ABSENT, KernelRecorder, Symbols, trace_header
from adapt.soar.xmltrace import tags
from adapt.traceview.records import check_record

INIT = ('<trace><adding_wme><wme attr="type" id="S1" tag="1" valtype="string" value="state"></wme>'
        '</adding_wme><adding_wme><wme attr="superstate" id="S1" tag="2" valtype="string" '
        'value="nil"></wme></adding_wme><state current_state_id="S1" decision_cycle_count="0" '
        'stack_level="0"></state></trace>')

CYCLE = (
    '<trace><phase name="input"></phase><phase name="input" status="end"></phase>'
    '<phase name="propose"></phase>'
    '<firing_production><production prodname="propose*go"><wme tag="1"></wme></production>'
    '</firing_production><actionsidemarker></actionsidemarker>'
    '<preference attr="operator" id="S1" pref_type="+" value="O1"></preference>'
    '<preference attr="operator" id="S1" pref_type="+" value="O1"></preference>'
    '<adding_wme><wme attr="operator" id="S1" preference="+" tag="3" valtype="id" value="O1">'
    '</wme></adding_wme>'
    '<phase name="propose" status="end"></phase><phase name="decision"></phase>'
    '<adding_wme><wme attr="operator" id="S1" tag="4" valtype="id" value="O1"></wme></adding_wme>'
    '<operator current_operator_id="O1" decision_cycle_count="1" name="go" stack_level="0">'
    '</operator><phase name="decision" status="end"></phase><phase name="apply"></phase>'
    '<subphase firing_type="PE" level_num="1" name="firingprods"></subphase>'
    '<firing_production><production prodname="apply*go"><wme tag="4"></wme></production>'
    '</firing_production><actionsidemarker></actionsidemarker>'
    '<rhs_write string="went&#10;"></rhs_write>'
    '<preference attr="count" id="S1" o_supported=":O" pref_type="+" value="1"></preference>'
    '<firing_production><production prodname="monitor"><wme tag="4"></wme></production>'
    '</firing_production><actionsidemarker></actionsidemarker>'
    '<preference attr="count" id="S1" o_supported=":O" pref_type="+" value="1"></preference>'
    '<subphase firing_type="PE" name="changingwm"></subphase>'
    '<adding_wme><wme attr="count" id="S1" tag="5" valtype="int" value="1"></wme></adding_wme>'
    '<retracting_production><production prodname="propose*go"><wme tag="1"></wme></production>'
    '</retracting_production><actionsidemarker></actionsidemarker>'
    '<removing_wme><wme attr="operator" id="S1" preference="+" tag="3" valtype="id" value="O1">'
    '</wme></removing_wme>'
    '<phase name="apply" status="end"></phase><phase name="output"></phase></trace>')

TIE = (
    '<trace><phase name="output" status="end"></phase><phase name="input"></phase>'
    '<phase name="input" status="end"></phase><phase name="propose"></phase>'
    '<phase name="propose" status="end"></phase><phase name="decision"></phase>'
    '<adding_wme><wme attr="item" id="S2" tag="9" valtype="id" value="O3"></wme></adding_wme>'
    '<adding_wme><wme attr="item" id="S2" tag="8" valtype="id" value="O2"></wme></adding_wme>'
    '<adding_wme><wme attr="epmem" id="S2" tag="7" valtype="id" value="E2"></wme></adding_wme>'
    '<state current_state_id="S2" decision_cycle_count="2" impasse_object="operator" '
    'impasse_type="tie" stack_level="1"></state><phase name="decision" status="end"></phase>'
    '<phase name="apply"></phase><firing_production><production prodname="in-sub">'
    '<wme tag="7"></wme><wme tag="1"></wme></production></firing_production>'
    '<actionsidemarker></actionsidemarker>'
    '<preference attr="x" id="S2" pref_type="+" value="1"></preference>'
    '<phase name="apply" status="end"></phase></trace>')


def recorded(*xml: str, level: int = 5) -> tuple[KernelRecorder, list[dict[str, Any]]]:
    rec = KernelRecorder(Symbols(), track_wmes=True)
    rec.feed(INIT)
    buf = io.StringIO()
    writer = TraceWriter(buf, level=level, header=trace_header("Soar 9.6.5"))
    rec.attach(writer)
    for x in xml:
        rec.feed(x)
    writer.footer({"halted": False, "stop_reason": "max-decisions", "decisions": rec.d,
                   "production_firings": 0, "wm_size_final": len(rec.wm)}, 0.0)
    records = [json.loads(line) for line in buf.getvalue().splitlines()][:-1]
    for r in records[1:]:
        check_record(r)  # every record follows the trace schema
    return rec, records


def test_tags_keep_order_attributes_and_newlines() -> None:
    found = tags(CYCLE)
    assert [t for t, _ in found[:4]] == ["phase", "phase", "phase", "firing_production"]
    assert ("rhs_write", {"string": "went\n"}) in found


def test_a_cycle_gives_phase_and_decision_records() -> None:
    rec, records = recorded(CYCLE)
    assert [r["kind"] for r in records] == ["header", "phase", "phase", "phase", "decision",
                                            "phase", "phase"]
    assert [r.get("phase") for r in records if r["kind"] == "phase"] == [
        "input", "proposal", "decision", "apply", "output"]
    assert records[1]["adds"][:2] == [[1, {"id": "S1"}, "type", "state", False],
                                      [2, {"id": "S1"}, "superstate", "nil", False]]
    decision = records[4]
    assert decision == {"kind": "decision", "d": 1, "level": 0,
                        "selected": {"id": {"id": "O1"}, "name": "go"}, "impasse": None}
    assert rec.operators == [[1, 0, "go"]] and rec.output() == "went\n"


def test_firings_have_rule_level_support_and_timetags_but_no_bindings() -> None:
    _, records = recorded(CYCLE)
    proposal, apply = records[2], records[5]
    assert proposal["firings"] == [{"rule": "propose*go", "level": 0, "support": "i",
                                    "wmes": [1]}]
    assert apply["firings"][0] == {"rule": "apply*go", "level": 0, "support": "o", "wmes": [4]}
    assert apply["writes"] == "went\n"
    assert apply["retractions"] == [{"rule": "propose*go", "level": 0, "wmes": [1]}]
    assert apply["adds"] == [[5, {"id": "S1"}, "count", 1, False]] and apply["removes"] == [3]


def test_a_preference_made_by_two_firings_tells_only_the_first_its_support() -> None:
    # "monitor" made no preference of its own: the one after its marker is the same as
    # apply*go's, so its support is not known and is left out (never guessed)
    _, records = recorded(CYCLE)
    monitor = records[5]["firings"][1]
    assert monitor["rule"] == "monitor" and "support" not in monitor


def test_an_impasse_names_its_state_items_and_the_firing_level() -> None:
    rec, records = recorded(CYCLE, TIE)
    decision = [r for r in records if r["kind"] == "decision"][1]
    assert decision["level"] == 0
    assert decision["impasse"] == {"type": "tie", "attribute": "operator",
                                   "state": {"id": "S2"}, "items": [{"id": "O2"}, {"id": "O3"}]}
    assert rec.impasses == [[2, 1, "tie", "operator"]]
    in_sub = [r for r in records if r["kind"] == "phase"][-1]["firings"][0]
    assert in_sub["level"] == 1  # it matched a WME of S2, the deepest state it tested


def test_the_header_says_engine_kernel_and_what_is_absent() -> None:
    _, records = recorded(CYCLE)
    header = records[0]
    assert header["engine"] == "soar" and header["kernel"] == "Soar 9.6.5"
    assert header["absent"] == list(ABSENT) and "firings.bindings" in header["absent"]
    assert "architecture" not in header  # both engines build the memories' structures


def test_level_1_writes_decisions_only_and_the_report_is_the_same() -> None:
    rec, records = recorded(CYCLE, TIE, level=1)
    assert [r["kind"] for r in records] == ["header", "decision", "decision"]
    assert rec.operators == [[1, 0, "go"]] and rec.impasses == [[2, 1, "tie", "operator"]]


def test_messages_and_the_goal_depth_warning() -> None:
    rec = KernelRecorder(Symbols())
    rec.feed('<trace><warning string="&#10;Goal stack depth exceeded on a no-change impasse.&#10;">'
             '</warning><message string="This Agent halted."></message></trace>')
    assert rec.goal_depth_exceeded
    assert list(rec.messages) == ["\nGoal stack depth exceeded on a no-change impasse.\n",
                            "This Agent halted."]


def test_history_bounds_what_is_kept() -> None:
    rec = KernelRecorder(Symbols(), history=2)
    for d in range(1, 6):
        rec.feed(f'<trace><operator current_operator_id="O{d}" decision_cycle_count="{d}" '
                 f'name="n" stack_level="0"></operator><rhs_write string="{d}"></rhs_write>'
                 '</trace>')
    assert list(rec.operators) == [[4, 0, "n"], [5, 0, "n"]] and rec.operator_count == 5
    assert rec.output() == "45"


def test_symbols_are_one_object_per_name_and_typed_values() -> None:
    s = Symbols()
    assert s.identifier("O3") is s.identifier("O3")
    assert s.value("3", "int") == 3 and type(s.value("3.5", "double")).__name__ == "Float"
    assert s.value("abc", "string") == "abc" and s.value("x", "int") == "x"


def test_the_existing_wmes_come_from_the_kernels_print() -> None:
    rec = KernelRecorder(Symbols())
    rec.existing('<sml><result><wme attr="superstate" id="S1" tag="2" valtype="string" '
                 'value="nil"></wme><wme attr="io" id="S1" tag="11" valtype="id" value="I1">'
                 '</wme><arg param="message" type="string">(2: S1 ^superstate nil)</arg>'
                 '</result></sml>')
    assert sorted(rec.wm) == [2, 11] and rec.wm[11].value is rec.symbols.identifier("I1")
    assert rec.levels == {rec.symbols.identifier("S1"): 0}
