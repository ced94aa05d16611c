"""Input-link writing during the input phase; output-link commands after output."""

from __future__ import annotations

import pytest

from adapt.engine import Agent, InputWriter, OutputView
from adapt.errors import EngineError

RULES = """
sp {propose (state <s> ^io.input-link.target <t> -^io.output-link.move)
   --> (<s> ^operator <o> +) (<o> ^name move ^to <t>)}
sp {apply (state <s> ^operator <o> ^io.output-link <ol>) (<o> ^name move ^to <t>)
   --> (<ol> ^move <m>) (<m> ^to <t>)}
sp {done (state <s> ^io.input-link.ack yes) --> (write |acked|) (halt)}
"""


def test_input_and_output_links() -> None:
    agent = Agent()
    agent.load_text(RULES)
    seen: list[OutputView] = []
    state = {"ack": False}

    def sense(w: InputWriter) -> None:
        if w.decision == 0:
            obj = w.new_id("T")
            w.add(w.input_link, "target", obj)
            w.add(obj, "x", 3.5)
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
    assert view.values(move, "to")[0] in {w.value for w in agent.wm if w.attr == "target"}
    assert view.added and not view.removed


def test_writing_outside_the_input_phase_raises() -> None:
    agent = Agent()
    kept: list[InputWriter] = []
    agent.on_input(kept.append)
    agent.run(1)
    with pytest.raises(EngineError):
        kept[0].add(agent.input_link, "late", 1)


def test_input_is_committed_at_the_end_of_the_input_phase() -> None:
    agent = Agent()
    agent.load_text("sp {see (state <s> ^io.input-link.v <v>) --> (write <v> | |)}")
    values = iter([1, 2, 3])

    def sense(w: InputWriter) -> None:
        for old in w.values(w.input_link, "v"):
            w.remove(w.input_link, "v", old)
        w.add(w.input_link, "v", next(values, 3))

    agent.on_input(sense)
    assert agent.run(3).output == "1 2 3 "


def test_set_replaces_and_keeps_an_unchanged_value() -> None:
    agent = Agent()
    agent.load_text("sp {see (state <s> ^io.input-link.v <v>) --> (write <v> | |)}")
    seq = iter([1, 1, 2, 2.0, "a"])

    def sense(w: InputWriter) -> None:
        w.set(w.input_link, "v", next(seq, "a"))

    agent.on_input(sense)
    # 1 is kept (no re-fire), 2 and 2.0 are different symbols, "a" last
    assert agent.run(5).output == "1 2 2.000000 a "
    assert [w.value for w in agent.wm if w.attr == "v"] == ["a"]


def test_set_twice_in_one_phase_keeps_the_last_value() -> None:
    agent = Agent()

    def sense(w: InputWriter) -> None:
        w.set(w.input_link, "v", 1)
        w.set(w.input_link, "v", 2)

    agent.on_input(sense)
    agent.run(1)
    assert [w.value for w in agent.wm if w.attr == "v"] == [2]


def test_clear_removes_every_value() -> None:
    agent = Agent()

    def sense(w: InputWriter) -> None:
        if w.decision == 0:
            w.add(w.input_link, "v", 1)
            w.add(w.input_link, "v", 2)
        else:
            w.clear(w.input_link, "v")

    agent.on_input(sense)
    agent.run(1)
    assert sorted(w.value for w in agent.wm if w.attr == "v") == [1, 2]
    agent.run(1)
    assert [w.value for w in agent.wm if w.attr == "v"] == []


@pytest.mark.parametrize("value", [None, True, [1], object()])
def test_a_value_that_is_not_a_symbol_is_an_engine_error(value: object) -> None:
    agent = Agent()

    def sense(w: InputWriter) -> None:
        w.add(w.input_link, "v", value)

    agent.on_input(sense)
    with pytest.raises(EngineError, match="not a Soar symbol"):
        agent.run(1)


def test_an_id_that_is_not_an_identifier_is_an_engine_error() -> None:
    agent = Agent()

    def sense(w: InputWriter) -> None:
        w.set("I2", "v", 1)

    agent.on_input(sense)
    with pytest.raises(EngineError, match="identifier"):
        agent.run(1)


def test_values_of_a_non_identifier_is_an_engine_error() -> None:
    agent = Agent()
    seen: list[str] = []

    def sense(w: InputWriter) -> None:
        try:
            w.values("I2", "v")
        except EngineError as exc:
            seen.append(str(exc))

    agent.on_input(sense)
    agent.run(1)
    assert seen and "identifier" in seen[0]


def test_print_state_needs_an_identifier() -> None:
    agent = Agent()
    assert agent.print_state().startswith("(S1 ")
    with pytest.raises(EngineError, match="identifier"):
        agent.print_state("S1")
