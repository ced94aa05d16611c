"""The small arena of the PyBullet reality's tests (160x120, a few frames)."""

from __future__ import annotations

from adapt.scenario import Scenario, loads_scenario

CAMERA = """camera: {fx: 130, fy: 130, cx: 79.5, cy: 59.5, width: 160, height: 120,
         position: [0, -2.3, 2.3], look_at: [0, 0.3, 0]}
"""
WORLD = """world:
  floor: {texture: gravel, tile: 0.8, extent: [-1.5, -1.5, 1.5, 1.5]}
  walls:
    - {name: north, from: [-1.5, 1.5], to: [1.5, 1.5], height: 0.5, restitution: 0.9}
    - {name: east, from: [1.5, 1.5], to: [1.5, -1.5], height: 0.5, restitution: 0.9}
    - {name: south, from: [1.5, -1.5], to: [-1.5, -1.5], height: 0.12, restitution: 0.9}
    - {name: west, from: [-1.5, -1.5], to: [-1.5, 1.5], height: 0.5, restitution: 0.9}
  obstacles:
    - {name: crate, polygon: [[0.5, 0.5], [0.9, 0.5], [0.9, 0.9], [0.5, 0.9]], height: 0.3}
  objects:
    - {name: ball, radius: 0.1, mass: 0.45, color: [230, 40, 30], create: when_seen}
"""
REALITY = """reality:
  kind: bullet
  objects:
    - {name: ball, throw: {t: 0, x: -0.5, y: -0.5, speed: 1.5, heading_deg: 60}}
"""
RUN = "run: {fps: 15, max_frames: 6}\n"


def scenario(reality: str = REALITY, camera: str = CAMERA, world: str = WORLD,
             run: str = RUN) -> Scenario:
    return loads_scenario(camera + world + reality + run)
