"""Shared scenario text and builders of the reality tests."""

from __future__ import annotations

from pathlib import Path

from adapt.reality import SyntheticSource
from adapt.scenario import Scenario, load_scenario, loads_scenario
from adapt.seeds import Streams

ROOT = Path(__file__).resolve().parents[2]

#: A small camera looking at a room from its south side.
CAMERA = """camera:
  fx: 160
  fy: 160
  cx: 79.5
  cy: 59.5
  width: 160
  height: 120
  position: [0.0, -1.0, 1.0]
  look_at: [0.0, 2.0, 0.2]
"""

#: A room with a north wall, one obstacle and a ball rolling towards the wall.
WORLD = """world:
  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.5, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
  obstacles:
    - {name: crate, polygon: [[1.0, 2.0], [1.5, 2.0], [1.5, 2.5], [1.0, 2.5]], height: 0.4,
       color: [150, 110, 60]}
  objects:
    - {name: ball, radius: 0.1, mass: 0.4, restitution: 0.8, rolling_resistance: 0.02,
       position: [0.0, 0.5], velocity: [0.0, 1.5]}
"""


def scenario(reality: str = "", run: str = "run: {fps: 10, max_frames: 10}\n",
             camera: str = CAMERA, world: str = WORLD, extra: str = "") -> Scenario:
    """A scenario from the parts above; ``reality`` is the body of the section."""
    text = camera + world + (("reality:\n" + reality) if reality else "") + run + extra
    return loads_scenario(text)


def source(sc: Scenario, seed: int = 1) -> SyntheticSource:
    return SyntheticSource(sc, streams=Streams(seed))


def bundled(name: str) -> Scenario:
    return load_scenario(ROOT / "scenarios" / name)
