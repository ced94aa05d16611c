"""Shared fixtures of the imagination tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.scenario import Scenario, load_scenario

BUNDLED = Path(__file__).resolve().parents[2] / "scenarios" / "room.yaml"


@pytest.fixture(scope="session")
def bundled() -> Scenario:
    return load_scenario(BUNDLED)
