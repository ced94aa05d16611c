"""A small room scenario on disk (workers read scenarios by path) and Dask clusters."""

from __future__ import annotations

from pathlib import Path
from typing import Iterator

import pytest
from rooms import room_text

#: The test room with two walls and the crate, a camera a little off, and a ball of reality
#: only that rolls in at a time drawn from the seed: runs differ from seed to seed.
ROOM = room_text(walls=("north", "east"), obstacles=("crate",), reality="""reality:
  camera_offset_deg: 0.8
  appearance: {brightness: 5, blur: 0.6, noise: 2.5}
  objects:
    - name: stranger
      radius: 0.13
      color: [40, 190, 60]
      throw: {t: [0.0, 0.1], x: [0.3, 0.8], y: 1.2, speed: 0.3, heading_deg: 100}""",
                 run="run: {fps: 30, max_frames: 4}")


@pytest.fixture(scope="session")
def room(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The scenario file."""
    path = tmp_path_factory.mktemp("scenario") / "room.yaml"
    path.write_text(ROOM, encoding="utf-8")
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
