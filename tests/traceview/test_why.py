from __future__ import annotations

import pytest

from adapt.errors import TraceError
from adapt.traceview.reader import Trace
from adapt.traceview.rules import load_productions
from adapt.traceview.why import explain, find_timetag, format_origin, format_why_not, why_not


@pytest.fixture
def traced(counter_trace, counter_rules):
    trace = Trace(counter_trace(20, tie_every=7))
    return trace, load_productions(trace)


def test_rule_files_are_found_beside_the_trace(traced) -> None:
    _trace, productions = traced
    assert {"propose*count", "apply*count", "check*done"} <= set(productions)


def test_maker_bindings_and_matched_wmes(traced) -> None:
    trace, productions = traced
    tt = find_timetag(trace, "S1", "count", "7")
    origin = explain(trace, tt, depth=1, productions=productions)
    assert (origin.cycle, origin.phase, origin.maker) == (8, "apply", "apply*count")
    assert origin.firing["bindings"]["<c>"] == 6
    assert origin.removed == (9, "apply")
    makers = {m.wme[2]: m.maker for m in origin.matched}
    assert makers == {"type": "input (the architecture or the environment)",
                      "operator": "the decision procedure (operator selection)",
                      "count": "apply*count", "name": "propose*count"}
    # depth 1: the matched WMEs' own matches are listed by timetag only
    assert all(not m.matched for m in origin.matched)


def test_new_identifiers_tell_two_proposals_apart(traced) -> None:
    trace, productions = traced
    skip = explain(trace, find_timetag(trace, "S1", "operator", "O8", acceptable=True), 0,
                   productions)
    count = explain(trace, find_timetag(trace, "S1", "operator", "O7", acceptable=True), 0,
                    productions)
    assert (skip.maker, count.maker) == ("propose*skip", "propose*count")


def test_without_rules_the_candidates_are_listed(counter_trace) -> None:
    trace = Trace(counter_trace(8, tie_every=7))
    origin = explain(trace, find_timetag(trace, "O8", "name"), 0, None)
    assert origin.candidates == ("propose*count", "propose*skip")
    assert "fired in that phase: propose*count, propose*skip" in format_origin(origin)


def test_substate_wmes_come_from_the_decision(traced) -> None:
    trace, productions = traced
    origin = explain(trace, find_timetag(trace, "S2", "impasse"), 0, productions)
    assert origin.maker == "the decision procedure (substate of an impasse)"


def test_firing_with_its_own_adds_is_trusted(tmp_path) -> None:
    import json
    rows = [{"kind": "header", "format": "adapt-trace", "version": 1, "level": 4, "files": []},
            {"kind": "phase", "d": 0, "phase": "proposal",
             "adds": [[1, {"id": "S1"}, "x", 1, False]], "removes": [],
             "firings": [{"rule": "a", "level": 0, "bindings": {}, "wmes": [], "adds": []},
                         {"rule": "b", "level": 0, "bindings": {}, "wmes": [], "adds": [1]}]}]
    path = tmp_path / "t.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert explain(Trace(path), 1, 0, None).maker == "b"


def test_unknown_timetag(traced) -> None:
    trace, productions = traced
    with pytest.raises(TraceError, match="no WME with timetag 99999"):
        explain(trace, 99999, 1, productions)


def test_why_not_names_the_failing_condition(traced) -> None:
    trace, productions = traced
    text = format_why_not(why_not(trace, "check*done", 7, productions))
    assert "condition 1 has no match: " in text and "(state <s> ^count { <c> >= 10 })" in text
    assert "no WME matches it at all" in text
    assert "counter.soar:" in text  # the condition's position in the rule file


def test_why_not_consistency(traced) -> None:
    trace, productions = traced
    result = why_not(trace, "watch*substate", 7, productions)
    assert result.failure is not None and result.failure.index == 1
    assert [repr(w) for w in result.failure.alone] == ["(37: S2 ^impasse tie)"]
    assert "<s>=S2, <ss>=S1" in format_why_not(result)


def test_why_not_negation_blocks(traced) -> None:
    trace, productions = traced
    result = why_not(trace, "stop*idle", 6, productions)
    assert result.failure is not None and result.failure.condition.negated
    assert [repr(w) for w in result.failure.alone] == ["(29: S1 ^operator O6)"]
    # in the tie there is no selected operator, so the negation holds and the rule matches
    assert why_not(trace, "stop*idle", 7, productions).failure is None


def test_why_not_of_a_rule_that_fired(traced) -> None:
    trace, productions = traced
    result = why_not(trace, "apply*count", 6, productions)
    assert result.fired_in_cycle == 1


def test_unknown_rule(traced) -> None:
    trace, productions = traced
    with pytest.raises(TraceError, match="no rule named nope"):
        why_not(trace, "nope", 3, productions)


def test_missing_rule_files_is_a_clear_error(counter_trace) -> None:
    trace = Trace(counter_trace(3, files=("rules/absent.soar",)))
    with pytest.raises(TraceError, match="rule file rules/absent.soar .* not found"):
        load_productions(trace)
