"""Bounded history for long runs, write listeners and sliced runs with one footer (both engines)."""

from __future__ import annotations

import io
import json
from typing import Any, Callable

import pytest

from adapt.errors import EngineError

Make = Callable[..., Any]

COUNTER = """
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose (state <s> ^count <c>) --> (<s> ^operator <o> +) (<o> ^name count)}
sp {apply (state <s> ^operator.name count ^count <c>)
   --> (<s> ^count <c> -) (<s> ^count (+ <c> 1)) (write <c> | |)}
"""


def test_history_keeps_the_most_recent_entries_and_counts_all(make: Make) -> None:
    agent = make(history=5)
    agent.load_text(COUNTER)
    report = agent.run(50)
    assert agent.operator_count == 50
    assert [o[0] for o in report.operators] == [46, 47, 48, 49, 50]
    # decision 1 is init; the 50th operator is not applied yet
    assert report.output == "43 44 45 46 47 "


def test_unbounded_history_is_the_default(make: Make) -> None:
    agent = make()
    agent.load_text(COUNTER)
    assert len(agent.run(30).operators) == 30


def test_history_must_be_positive(make: Make) -> None:
    with pytest.raises(EngineError):
        make(history=0)


def test_write_listeners_see_text_as_it_is_written(make: Make) -> None:
    agent = make()
    agent.load_text(COUNTER)
    seen: list[tuple[int, str]] = []
    agent.on_write(lambda text: seen.append((agent.decisions, text)))
    agent.run(4)
    assert seen == [(2, "0 "), (3, "1 ")]


def test_sliced_runs_write_one_footer(make: Make) -> None:
    buf = io.StringIO()
    agent = make(trace=buf, trace_level=2)
    agent.load_text(COUNTER)
    for _ in range(4):
        agent.run(2, footer=False)
    agent.write_footer(0.5)
    kinds = [json.loads(line)["kind"] for line in buf.getvalue().splitlines()]
    assert kinds.count("footer") == 1 and kinds[-1] == "footer"
    assert json.loads(buf.getvalue().splitlines()[-1])["decisions"] == 8
