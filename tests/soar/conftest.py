"""The Soar engine's tests: those marked ``soar`` need soar-sml and are skipped without it."""

from __future__ import annotations

from typing import Any, Iterator

import pytest

from adapt.errors import AdaptError
from adapt.soar import require_soar


def _available() -> bool:
    try:
        require_soar()
    except AdaptError:
        return False
    return True


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if _available():
        return
    skip = pytest.mark.skip(reason="soar-sml (the Soar kernel) is not installed")
    for item in items:
        if "soar" in item.keywords and "tests/soar" in str(item.fspath).replace("\\", "/"):
            item.add_marker(skip)


@pytest.fixture
def soar() -> Iterator[Any]:
    """A Soar engine agent (seed 1), closed at the end of the test."""
    from adapt.soar import SoarAgent

    agent = SoarAgent(seed=1)
    yield agent
    agent.close()
