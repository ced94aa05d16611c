"""The bundled video scenario: its image sequence loads, its ground truth parses, and
the script that made it still makes it."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from adapt.reality import open_reality
from adapt.reality.record import record_sequence
from adapt.scenario import VideoReality, load_scenario
from adapt.seeds import Streams

from .conftest import ROOT

PLAYBACK = ROOT / "scenarios" / "video-sequence.yaml"
MAKER = ROOT / "scenarios" / "video" / "synthetic.yaml"


def test_the_video_scenario_plays_its_sequence_with_its_truth() -> None:
    sc = load_scenario(PLAYBACK)
    assert isinstance(sc.reality, VideoReality) and sc.reality.fps == 15
    src = open_reality(sc, streams=Streams(sc.seed))
    frames = list(src)
    assert len(frames) == 36 and src.size == (320, 240)
    assert all(f.image.shape == (240, 320, 3) for f in frames)
    truth = src.truth
    assert truth is not None
    seen = [truth.at(f.index).position("ball") for f in frames]
    assert seen[0] is None and all(p is not None for p in seen[8:])
    # The ball rolls to the right across the room.
    assert seen[-1][0] - seen[8][0] > 2.0
    assert truth.at(20).objects["ball"].velocity is not None


def test_the_sequence_is_small() -> None:
    folder = ROOT / "scenarios" / "video"
    total = sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())
    assert total < 1_000_000


def test_the_playback_and_the_maker_describe_one_room() -> None:
    play, make = load_scenario(PLAYBACK), load_scenario(MAKER)
    assert play.camera.size == make.camera.size and play.camera.K.tolist() == make.camera.K.tolist()
    assert np.array_equal(play.camera.rotation, make.camera.rotation)
    assert np.array_equal(play.camera.position, make.camera.position)
    assert play.scene == make.scene and play.objects[0].ball == make.objects[0].ball
    assert play.reality.fps == make.run.fps  # type: ignore[union-attr]


def test_the_maker_still_makes_the_shipped_sequence(tmp_path: Path) -> None:
    rec = record_sequence(load_scenario(MAKER), tmp_path, quality=85)
    shipped = ROOT / "scenarios" / "video"
    assert rec.frames == 36
    assert (tmp_path / "truth.csv").read_text() == (shipped / "truth.csv").read_text()
    for i in (0, 20, 35):
        name = f"frame_{i:04d}.jpg"
        a = cv2.imread(str(tmp_path / "frames" / name)).astype(int)
        b = cv2.imread(str(shipped / "frames" / name)).astype(int)
        assert np.abs(a - b).mean() < 1.0
