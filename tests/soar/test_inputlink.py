"""The Soar engine's input-link writer: the operations it sends to the kernel (no kernel needed)."""

from __future__ import annotations

import pytest

from adapt.engine.interface import InputLink
from adapt.engine.symbols import Float, Identifier
from adapt.errors import EngineError
from adapt.soar.inputlink import SoarInputWriter


def writer() -> SoarInputWriter:
    w = SoarInputWriter(Identifier("I", 2))
    w.begin(0)
    return w


def test_it_is_an_input_link() -> None:
    assert isinstance(writer(), InputLink)


def test_values_become_typed_sml_wmes_in_order() -> None:
    w = writer()
    w.add(w.input_link, "n", 3)
    w.add(w.input_link, "x", 1.5)
    w.add(w.input_link, "name", "ball")
    assert w.end() == [("add", "I2", "n", 3, "int"), ("add", "I2", "x", 1.5, "float"),
                       ("add", "I2", "name", "ball", "string")]


def test_a_new_identifier_is_made_where_it_is_linked_and_shared_after() -> None:
    w = writer()
    thing = w.new_id("T")
    w.add(w.input_link, "thing", thing)
    w.add(thing, "size", 2)
    w.add(w.input_link, "same", thing)
    assert w.end() == [("add", "I2", "thing", 1, "new"), ("add", 1, "size", 2, "int"),
                       ("add", "I2", "same", 1, "id")]


def test_set_keeps_an_unchanged_value_and_replaces_another() -> None:
    w = writer()
    w.set(w.input_link, "v", 1)
    assert w.end() == [("add", "I2", "v", 1, "int")]
    w.begin(1)
    w.set(w.input_link, "v", 1)                    # the same value: nothing to do
    w.set(w.input_link, "w", Float(2.0))
    assert w.end() == [("add", "I2", "w", 2.0, "float")]
    w.begin(2)
    w.set(w.input_link, "v", 2)
    assert w.end() == [("remove", "I2", "v", 1, "int"), ("add", "I2", "v", 2, "int")]
    assert w.values(w.input_link, "v") == [2]


def test_values_are_those_of_the_last_phase_until_it_ends() -> None:
    w = writer()
    w.add(w.input_link, "v", 1)
    assert w.values(w.input_link, "v") == []
    w.end()
    assert w.values(w.input_link, "v") == [1]


def test_removing_a_structure_forgets_what_is_under_it() -> None:
    w = writer()
    thing = w.new_id("T")
    w.add(w.input_link, "thing", thing)
    w.add(thing, "size", 2)
    w.end()
    w.begin(1)
    w.remove(w.input_link, "thing", thing)
    assert w.end() == [("remove", "I2", "thing", 1, "new")]
    assert w.values(thing, "size") == []


def test_named_gives_the_identifier_its_kernel_name() -> None:
    w = writer()
    thing = w.new_id("T")
    w.add(w.input_link, "thing", thing)
    w.end()
    assert w.named(1) is thing and w.named(1) is None


def test_writing_outside_the_input_phase_and_bad_symbols_are_engine_errors() -> None:
    w = writer()
    w.end()
    with pytest.raises(EngineError, match="only during the input phase"):
        w.add(w.input_link, "v", 1)
    w.begin(1)
    with pytest.raises(EngineError, match="not a Soar symbol"):
        w.add(w.input_link, "v", None)
    with pytest.raises(EngineError, match="identifier"):
        w.add("I2", "v", 1)
