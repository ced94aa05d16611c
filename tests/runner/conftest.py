"""Scenarios for the runner tests: the test room (``tests/rooms.py``) with the mirror's rules."""

from __future__ import annotations

import pytest
from rooms import ROOT, room_text

from adapt.scenario import Scenario, loads_scenario


def room(objects: str = "", extra: str = "") -> Scenario:
    """The test room; ``objects`` is the YAML of ``world.objects`` (indented by 2)."""
    return loads_scenario(room_text(objects=objects) + extra, file="room.yaml", base=ROOT)


@pytest.fixture()
def scenario() -> Scenario:
    return room()
