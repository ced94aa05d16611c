"""Scenarios for the runner tests: the bundled room at 320x240 with the mirror's rules."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.scenario import Scenario, loads_scenario

ROOT = Path(__file__).resolve().parents[2]
RULES = ROOT / "rules" / "mirror" / "perception.soar"

ROOM = """
camera: {fx: 262.5, fy: 262.5, cx: 159.5, cy: 119.5, width: 320, height: 240,
         position: [0.0, -0.6, 0.6], look_at: [0.0, 3.0, 0.3]}
world:
  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
    - {name: east, from: [2.5, 3.0], to: [2.5, -1.0], height: 1.0, texture: brick, tile: 0.6}
    - {name: west, from: [-2.5, -1.0], to: [-2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
  obstacles:
    - {name: crate, polygon: [[-1.3, 2.35], [-0.75, 2.35], [-0.75, 2.85], [-1.3, 2.85]],
       height: 0.4, color: [150, 110, 60]}
    - {name: bin, polygon: [[1.45, 2.0], [1.85, 2.2], [1.7, 2.55], [1.3, 2.35]], height: 0.5,
       color: [90, 150, 80]}
{objects}
goals: [{name: watch}]
rules: [{rules}]
run: {fps: 30, max_frames: 60, seed: 3}
"""


def room(objects: str = "", extra: str = "") -> Scenario:
    """The test room; ``objects`` is the YAML of ``world.objects`` (indented by 2)."""
    text = ROOM.replace("{objects}", objects).replace("{rules}", str(RULES)) + extra
    return loads_scenario(text, file="room.yaml", base=ROOT)


@pytest.fixture()
def scenario() -> Scenario:
    return room()
