"""A small room scenario on disk (workers read scenarios by path) and Dask clusters."""

from __future__ import annotations

from pathlib import Path
from typing import Iterator

import pytest

ROOT = Path(__file__).resolve().parents[2]
RULES = ROOT / "rules" / "mirror" / "perception.soar"

#: The bundled room at 320x240, a camera a little off, and a ball of reality only that rolls
#: in at a time drawn from the seed: runs differ from seed to seed.
ROOM = """
camera: {fx: 262.5, fy: 262.5, cx: 159.5, cy: 119.5, width: 320, height: 240,
         position: [0.0, -0.6, 0.6], look_at: [0.0, 3.0, 0.3]}
world:
  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
    - {name: east, from: [2.5, 3.0], to: [2.5, -1.0], height: 1.0, texture: brick, tile: 0.6}
  obstacles:
    - {name: crate, polygon: [[-1.3, 2.35], [-0.75, 2.35], [-0.75, 2.85], [-1.3, 2.85]],
       height: 0.4, color: [150, 110, 60]}
reality:
  camera_offset_deg: 0.8
  appearance: {brightness: 5, blur: 0.6, noise: 2.5}
  objects:
    - name: stranger
      radius: 0.13
      color: [40, 190, 60]
      throw: {t: [0.0, 0.1], x: [0.3, 0.8], y: 1.2, speed: 0.3, heading_deg: 100}
goals: [{name: watch}]
rules: [RULES]
run: {fps: 30, max_frames: 4}
"""


@pytest.fixture(scope="session")
def room(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The scenario file."""
    path = tmp_path_factory.mktemp("scenario") / "room.yaml"
    path.write_text(ROOM.replace("RULES", str(RULES)), encoding="utf-8")
    return path


def _cluster(n: int) -> Iterator[object]:
    pytest.importorskip("distributed")
    from adapt.sweep.cluster import connect

    with connect(workers=n) as conn:
        yield conn


@pytest.fixture(scope="module")
def two_workers() -> Iterator[object]:
    """A :class:`~adapt.sweep.cluster.Connection` to a local cluster of 2 worker processes."""
    yield from _cluster(2)
