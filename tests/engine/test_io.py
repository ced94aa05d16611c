"""Input-link writing during the input phase; output-link commands after output.

Every test runs on both engines (``make``): the Soar engine maps the same
calls to SML input WMEs and output-link changes.
"""

from __future__ import annotations

from typing import Any, Callable

import pytest

from adapt.engine import OutputView
from adapt.engine.interface import InputLink
from adapt.errors import EngineError

from .both_engines import values_of

Make = Callable[..., Any]

RULES = """
sp {propose (state <s> ^io.input-link.target <t> -^io.output-link.move)
   --> (<s> ^operator <o> +) (<o> ^name move ^to <t>)}
sp {apply (state <s> ^operator <o> ^io.output-link <ol>) (<o> ^name move ^to <t>)
   --> (<ol> ^move <m>) (<m> ^to <t>)}
sp {done (state <s> ^io.input-link.ack yes) --> (write |acked|) (halt)}
"""


def test_input_and_output_links(make: Make) -> None:
    agent = make()
    agent.load_text(RULES)
    seen: list[OutputView] = []
    state: dict[str, Any] = {"ack": False}

    def sense(w: InputLink) -> None:
        if w.decision == 0:
            obj = w.new_id("T")
            w.add(w.input_link, "target", obj)
            w.add(obj, "x", 3.5)
            state["target"] = obj
        if seen and not state["ack"]:
            w.add(w.input_link, "ack", "yes")
            state["ack"] = True

    agent.on_input(sense)
    agent.on_output(seen.append)
    r = agent.run(10)
    assert r.output == "acked" and r.halted
    assert len(seen) == 1
    view = seen[0]
    (attr, move), = view.commands()
    assert attr == "move"
    assert view.values(move, "to") == [state["target"]]   # the same identifier object
    assert str(state["target"]) == "T1"                     # named as the kernel names it
    assert view.added and not view.removed
    assert values_of(agent, agent.input_link, "target") == ["T1"]


def test_writing_outside_the_input_phase_raises(make: Make) -> None:
    agent = make()
    kept: list[InputLink] = []
    agent.on_input(kept.append)
    agent.run(1)
    with pytest.raises(EngineError):
        kept[0].add(agent.input_link, "late", 1)


def test_input_is_committed_at_the_end_of_the_input_phase(make: Make) -> None:
    agent = make()
    agent.load_text("sp {see (state <s> ^io.input-link.v <v>) --> (write <v> | |)}")
    values = iter([1, 2, 3])

    def sense(w: InputLink) -> None:
        for old in w.values(w.input_link, "v"):
            w.remove(w.input_link, "v", old)
        w.add(w.input_link, "v", next(values, 3))

    agent.on_input(sense)
    assert agent.run(3).output == "1 2 3 "


def test_set_replaces_and_keeps_an_unchanged_value(make: Make) -> None:
    agent = make()
    agent.load_text("sp {see (state <s> ^io.input-link.v <v>) --> (write <v> | |)}")
    seq = iter([1, 1, 2, 2.0, "a"])

    def sense(w: InputLink) -> None:
        w.set(w.input_link, "v", next(seq, "a"))

    agent.on_input(sense)
    # 1 is kept (no re-fire), 2 and 2.0 are different symbols, "a" last
    assert agent.run(5).output == "1 2 2.000000 a "
    assert values_of(agent, agent.input_link, "v") == ["a"]


def test_set_twice_in_one_phase_keeps_the_last_value(make: Make) -> None:
    agent = make()

    def sense(w: InputLink) -> None:
        w.set(w.input_link, "v", 1)
        w.set(w.input_link, "v", 2)

    agent.on_input(sense)
    agent.run(1)
    assert values_of(agent, agent.input_link, "v") == ["2"]


def test_clear_removes_every_value(make: Make) -> None:
    agent = make()

    def sense(w: InputLink) -> None:
        if w.decision == 0:
            w.add(w.input_link, "v", 1)
            w.add(w.input_link, "v", 2)
        else:
            w.clear(w.input_link, "v")

    agent.on_input(sense)
    agent.run(1)
    assert sorted(values_of(agent, agent.input_link, "v")) == ["1", "2"]
    agent.run(1)
    assert values_of(agent, agent.input_link, "v") == []


def test_removing_a_structure_removes_what_is_under_it(make: Make) -> None:
    agent = make()
    agent.load_text("sp {see (state <s> ^io.input-link.thing.part.size <n>) --> (write <n> | |)}")
    made: dict[str, Any] = {}

    def sense(w: InputLink) -> None:
        if w.decision == 0:
            thing = w.new_id("T")
            w.add(w.input_link, "thing", thing)
            part = w.new_id("P")
            w.add(thing, "part", part)
            w.add(part, "size", 2)
            made["thing"] = thing
        elif w.decision == 2:
            w.remove(w.input_link, "thing", made["thing"])

    agent.on_input(sense)
    assert agent.run(2).output == "2 "
    assert values_of(agent, agent.input_link, "thing") == ["T1"]
    agent.run(2)
    assert values_of(agent, agent.input_link, "thing") == []
    assert "^" not in agent.print_state(agent.input_link, depth=3)


def test_output_commands_get_a_status_written_back(make: Make) -> None:
    """The schema network's pattern: a command on the output-link, ^status on it next input."""
    agent = make()
    agent.load_text("""
sp {propose (state <s> ^superstate nil -^asked) --> (<s> ^operator <o> +) (<o> ^name ask)}
sp {apply (state <s> ^operator.name ask ^io.output-link <ol>) --> (<s> ^asked yes) (<ol> ^go <c>) (<c> ^n 1)}
sp {done (state <s> ^io.output-link.go.status complete) --> (write |complete|) (halt)}
""")
    pending: list[Any] = []

    def act(view: OutputView) -> None:
        pending.extend(value for attr, value in view.commands() if attr == "go")

    def sense(w: InputLink) -> None:
        while pending:
            w.set(pending.pop(), "status", "complete")

    agent.on_output(act)
    agent.on_input(sense)
    r = agent.run(10)
    assert (r.output, r.halted) == ("complete", True)


@pytest.mark.parametrize("value", [None, True, [1], object()])
def test_a_value_that_is_not_a_symbol_is_an_engine_error(make: Make, value: object) -> None:
    agent = make()

    def sense(w: InputLink) -> None:
        w.add(w.input_link, "v", value)

    agent.on_input(sense)
    with pytest.raises(EngineError, match="not a Soar symbol"):
        agent.run(1)


def test_an_id_that_is_not_an_identifier_is_an_engine_error(make: Make) -> None:
    agent = make()

    def sense(w: InputLink) -> None:
        w.set("I2", "v", 1)

    agent.on_input(sense)
    with pytest.raises(EngineError, match="identifier"):
        agent.run(1)


def test_values_of_a_non_identifier_is_an_engine_error(make: Make) -> None:
    agent = make()
    seen: list[str] = []

    def sense(w: InputLink) -> None:
        try:
            w.values("I2", "v")
        except EngineError as exc:
            seen.append(str(exc))

    agent.on_input(sense)
    agent.run(1)
    assert seen and "identifier" in seen[0]


def test_print_state_needs_an_identifier(make: Make) -> None:
    agent = make()
    assert agent.print_state().startswith("(S1 ")
    with pytest.raises(EngineError, match="identifier"):
        agent.print_state("S1")
