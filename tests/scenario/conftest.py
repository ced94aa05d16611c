"""Shared fixtures of the scenario tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.scenario import Scenario, load_scenario

ROOT = Path(__file__).resolve().parents[2]
BUNDLED = ROOT / "scenarios" / "room.yaml"


@pytest.fixture(scope="session")
def bundled() -> Scenario:
    return load_scenario(BUNDLED)
