"""The Scene Background's ``tolerance`` counts pixels of the image the MMD works on: a
640x480 frame reduced to 320x240 (``mmd_pixels: 76800``) is corrected only above 1 px of its
own, twice the tolerance, because the reduced image measures no finer (a finer tolerance
corrected the camera by the matches' noise and rendered the whole background anew for it)."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.runner import FrameRecord, Runner
from adapt.scenario import OutputSettings, load_scenario

ROOT = Path(__file__).resolve().parents[2]
QUIET = OutputSettings(report=False, trace=False, video=False, figures=False)
SMALL = ("camera.width=320", "camera.height=240", "camera.fx=262.5", "camera.fy=262.5",
         "camera.cx=159.5", "camera.cy=119.5")


class Frames:
    def __init__(self) -> None:
        self.records: list[FrameRecord] = []

    def frame(self, record: FrameRecord) -> None:
        self.records.append(record)


@pytest.mark.parametrize(("size", "tolerance_px"), [((), 1.0), (SMALL, 0.5)])
def test_the_camera_is_corrected_only_above_the_tolerance_of_the_working_image(
        size: tuple[str, ...], tolerance_px: float) -> None:
    sc = load_scenario(ROOT / "scenarios" / "background-sync.yaml",
                       overrides=[*size, "schemas.scene-background.mmd_pixels=76800",
                                  "schemas.scene-background.tolerance=0.5", "run.duration=1.5"])
    frames = Frames()
    Runner(sc, out=None, outputs=QUIET, listeners=(frames,)).run()
    steps = [(bg.pixel_error, bg.camera_before.angle_to(bg.camera_after) > 0)
             for bg in (r.background for r in frames.records)
             if bg is not None and bg.mmd is not None and bg.mmd.aligned and bg.trusted]
    # what the frame records say (and camera.png draws)
    assert {r.background.tolerance for r in frames.records if r.background is not None} \
        == {tolerance_px}
    assert len(steps) > 30
    assert any(moved for _, moved in steps)  # the scenario's camera starts 2 degrees off
    for error, moved in steps:
        assert moved == (error > tolerance_px), (error, moved)
    # settled within the tolerance, not chasing below it
    assert steps[-1][0] <= tolerance_px
