"""Suite-wide pytest hooks and fixtures."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.scenario import Scenario, load_scenario

#: The repository's root.
ROOT = Path(__file__).resolve().parents[1]


def pytest_report_header() -> str:
    """Say which engine the run tests: the mypyc-compiled modules or the source."""
    from adapt.engine import engine_build

    return f"adapt engine: {engine_build()}"


@pytest.fixture(scope="session")
def bundled() -> Scenario:
    """The bundled room (``scenarios/room.yaml``), the scene the imagination is shown with."""
    return load_scenario(ROOT / "scenarios" / "room.yaml")
