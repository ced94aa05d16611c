"""Fixtures of the engine tests: ``engine`` and ``make`` run a test on each engine
(``both_engines.py``)."""

from __future__ import annotations

from typing import Any, Callable, Iterator

import pytest

from adapt.engines import make_agent

from .both_engines import ENGINES


@pytest.fixture(params=ENGINES)
def engine(request: pytest.FixtureRequest) -> str:
    """The engine a semantics test runs on."""
    return str(request.param)


@pytest.fixture
def make(engine: str) -> Iterator[Callable[..., Any]]:
    """Make agents of the test's engine (closed at the end of the test)."""
    made: list[Any] = []

    def agent(**options: Any) -> Any:
        a = make_agent(engine, **options)
        made.append(a)
        return a

    yield agent
    for a in made:
        a.close()
