"""The camera reality: a file played as a camera (the stand-in for a device), dropped frames,
a camera that stalls, and every way one fails to open -- no hardware needed."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from adapt.errors import RealityError, ScenarioError
from adapt.frames import VideoSink
from adapt.reality import open_reality
from adapt.reality.live import CameraSource
from adapt.runner import Runner
from adapt.scenario import CameraReality, OutputSettings, load_scenario
from adapt.seeds import Streams

SIZE = (64, 48)


def video(path: Path, frames: int, fps: float, size: tuple[int, int] = SIZE) -> Path:
    """A video whose frame i is grey level 8 * i (so a frame says which it was)."""
    with VideoSink(path, fps=fps, size=size) as sink:
        for i in range(frames):
            sink.write(np.full((size[1], size[0], 3), 8 * i, np.uint8))
    return path


class FakeCapture:
    """A device: ``frames`` frames at ``fps`` with increasing timestamps, then it either
    blocks (``then="block"``) or fails every read (``then="fail"``)."""

    def __init__(self, frames: int, fps: float = 50.0, then: str = "block",
                 size: tuple[int, int] = SIZE, stamps: bool = True) -> None:
        self.frames, self.fps, self.then, self.size, self.stamps = frames, fps, then, size, stamps
        self.i = 0
        self.released = threading.Event()

    def isOpened(self) -> bool:  # noqa: N802
        return True

    def read(self) -> tuple[bool, Any]:
        if self.i >= self.frames:
            if self.then == "block":
                self.released.wait(5.0)
            return False, None
        if self.i:
            time.sleep(1.0 / self.fps)
        self.i += 1
        return True, np.full((self.size[1], self.size[0], 3), self.i, np.uint8)

    def get(self, prop: int) -> float:
        import cv2

        if prop == cv2.CAP_PROP_FPS:
            return self.fps
        if prop == cv2.CAP_PROP_POS_MSEC:
            return 1000.0 * (self.i - 1) / self.fps + 5000.0 if self.stamps else 0.0
        return 0.0

    def set(self, prop: int, value: float) -> bool:
        return False

    def release(self) -> None:
        self.released.set()


def test_a_file_plays_as_a_camera_at_its_own_rate_with_its_timestamps(tmp_path: Path) -> None:
    path = video(tmp_path / "v.avi", 10, fps=25)
    source = CameraSource.open(str(path), size=SIZE)
    assert source.fps == 25.0 and source.size == SIZE and source.robot is None
    started = time.monotonic()
    frames = list(source)
    took = time.monotonic() - started
    assert [f.index for f in frames] == list(range(10))
    assert [round(f.time, 3) for f in frames] == [round(i / 25, 3) for i in range(10)]
    assert took >= 0.3  # paced: 9 intervals of 40 ms, not as fast as it decodes
    status = source.status()
    assert status["clock"] == "source" and status["stopped"] == "end-of-stream"
    assert status["frames_read"] == 10 and status["frames_dropped"] == 0
    assert status["fps_measured"] == pytest.approx(25.0, rel=0.01) and not source.stalled


def test_a_slow_loop_drops_frames_and_they_are_counted(tmp_path: Path) -> None:
    path = video(tmp_path / "v.avi", 30, fps=50)
    source = CameraSource.open(str(path), size=SIZE)
    frames = []
    for f in source:
        frames.append(f)
        time.sleep(0.07)  # the loop takes 3.5 frame intervals
    status = source.status()
    assert status["frames_read"] == 30
    assert status["frames_delivered"] == len(frames) < 20
    assert status["frames_dropped"] == 30 - len(frames)
    assert status["fps_measured"] == pytest.approx(50.0, rel=0.01)  # the camera's rate, not the loop's
    # each frame's time is its own timestamp, and the grey level says which frame it was
    for f in frames:
        assert f.time == pytest.approx(round(int(f.image[0, 0, 0]) / 8) / 50, abs=1e-6)
    assert max(np.diff([f.time for f in frames])) > 0.05  # the gaps are where frames dropped


def test_a_stream_served_over_http_is_read_as_a_url_and_stalls_when_it_ends(tmp_path: Path) -> None:
    import functools
    import http.server

    video(tmp_path / "v.avi", 12, fps=25)

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args: Any) -> None:
            pass

    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Quiet, directory=str(tmp_path)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        url = f"http://127.0.0.1:{server.server_address[1]}/v.avi"
        source = CameraSource.open(url, size=SIZE, stall_s=0.4)
        frames = list(source)
    finally:
        server.shutdown()
    status = source.status()
    assert status["frames_read"] == 12 == len(frames) + status["frames_dropped"]
    assert status["fps_stated"] == 25.0 and status["clock"] == "source"
    # a URL is live: when it gives no more frames, it has stalled (it cannot tell an end)
    assert source.stalled and status["stopped"] == "stalled"


def test_a_camera_that_stops_delivering_has_stalled() -> None:
    cap = FakeCapture(4, then="block")
    source = CameraSource(cap, where="camera 0", size=SIZE, stall_s=0.3)
    started = time.monotonic()
    frames = list(source)
    assert len(frames) == 4 and time.monotonic() - started < 3.0
    assert source.stalled and source.status()["stopped"] == "stalled"
    assert [round(f.time, 3) for f in frames] == [0.0, 0.02, 0.04, 0.06]
    source.close()


def test_a_device_whose_reads_fail_stalls_and_one_without_timestamps_is_timed_by_the_clock() -> None:
    source = CameraSource(FakeCapture(3, then="fail", stamps=False), where="camera 0", size=SIZE,
                          stall_s=0.3)
    frames = list(source)
    assert len(frames) == 3 and source.stalled
    assert source.status()["clock"] == "wall"
    times = [f.time for f in frames]
    assert times == sorted(times) and times[-1] > 0.0


def test_a_camera_stops_at_the_runs_length() -> None:
    source = CameraSource(FakeCapture(50), where="camera 0", size=SIZE, limit=5)
    assert len(list(source)) == 5 and source.status()["stopped"] == "frames-done"
    assert not source.stalled


@pytest.mark.parametrize("cap, message", [
    (FakeCapture(3, size=(32, 24)), "gives 32x24 images; expected 64x48"),
    (FakeCapture(0, then="fail"), "delivered no frame"),
    (FakeCapture(3, fps=0.0), "states no frame rate; give reality.fps"),
])
def test_a_wrong_camera_fails_when_opened(cap: FakeCapture, message: str) -> None:
    with pytest.raises(RealityError, match=message):
        CameraSource(cap, where="camera 0", size=SIZE, stall_s=0.2)
    assert cap.released.is_set()


def test_a_device_that_does_not_exist_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(RealityError, match=r"camera 97: OpenCV cannot open this device"):
        CameraSource.open(97, size=SIZE)
    (tmp_path / "bad.mp4").write_bytes(b"not a video" * 50)
    with pytest.raises(RealityError, match="OpenCV cannot open this video"):
        CameraSource.open(str(tmp_path / "bad.mp4"), size=SIZE)
    with pytest.raises(RealityError, match="no such file"):
        CameraSource.open(str(tmp_path / "none.mp4"), size=SIZE)


HEAD = """camera: {fx: 60, fy: 60, cx: 31.5, cy: 23.5, width: 64, height: 48,
         position: [0, -2, 1], look_at: [0, 1, 0]}
world: {}
"""


def write(tmp_path: Path, reality: str, run: str = "run: {max_frames: 6}\n") -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(HEAD + "reality: " + reality + "\n" + run)
    return path


def test_the_scenario_reads_a_camera_reality(tmp_path: Path) -> None:
    video(tmp_path / "v.avi", 3, fps=10)
    sc = load_scenario(write(tmp_path, "{kind: camera, device: v.avi, stall_s: 0.5}"))
    assert isinstance(sc.reality, CameraReality)
    assert sc.reality.device == str(tmp_path / "v.avi") and sc.reality.stall_s == 0.5
    assert sc.reality.fps is None
    sc = load_scenario(write(tmp_path, "{kind: camera, device: 'rtsp://cam.local/live', fps: 25}"))
    assert sc.reality.device == "rtsp://cam.local/live" and sc.reality.fps == 25  # type: ignore[union-attr]
    inputs = load_scenario(write(tmp_path, "{kind: camera, device: v.avi}")).inputs()
    assert inputs.find(tmp_path / "v.avi") is not None  # no output may replace it


@pytest.mark.parametrize("reality, where, message", [
    ("{kind: camera}", "4:10", "missing key 'device'"),
    ("{kind: camera, device: nothing.mp4}", "4:33", "camera file '.*nothing.mp4' not found"),
    ("{kind: camera, device: [0]}", "4:33", "expected a device index"),
    ("{kind: camera, device: true}", "4:33", "expected a device index"),
    ("{kind: camera, device: 0, fps: 0}", "4:41", "expected a positive number"),
    ("{kind: camera, device: 0, stall: 1}", "4:36", r"unknown key \(did you mean 'stall_s'\?\)"),
])
def test_a_bad_camera_section_is_a_positioned_error(tmp_path: Path, reality: str, where: str,
                                                     message: str) -> None:
    with pytest.raises(ScenarioError, match=f"s.yaml:{where}: reality.*{message}"):
        load_scenario(write(tmp_path, reality))


def test_a_camera_that_cannot_be_opened_names_its_scenario_line(tmp_path: Path) -> None:
    sc = load_scenario(write(tmp_path, "{kind: camera, device: 97}"))
    with pytest.raises(ScenarioError) as info:
        open_reality(sc, streams=Streams(0))
    text = str(info.value)
    assert "s.yaml:4:33: reality.device: camera 97: OpenCV cannot open this device" in text
    assert "device: 97}" in text  # the line, with a caret under the value


QUIET = OutputSettings(video=False, figures=False, trace=False)


def test_a_run_on_a_camera_reports_what_the_camera_did(tmp_path: Path) -> None:
    video(tmp_path / "v.avi", 8, fps=20)
    sc = load_scenario(write(tmp_path, "{kind: camera, device: v.avi}", "run: {max_frames: 20}\n"))
    result = Runner(sc, out=tmp_path / "run", outputs=QUIET).run()
    summary = result.summary
    source = summary["source"]
    assert summary["stopped"] == "end-of-frames" and summary["frames"] == source["frames_delivered"]
    assert source["frames_read"] == 8 == source["frames_delivered"] + source["frames_dropped"]
    assert source["stopped"] == "end-of-stream" and source["fps"] == 20.0
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert report["summary"]["source"] == source and report["reality"] == "camera"


def test_a_stalled_camera_ends_the_run_as_stalled_with_a_complete_report(tmp_path: Path) -> None:
    sc = load_scenario(write(tmp_path, "{kind: camera, device: 0}", "run: {max_frames: 50}\n"))
    source = CameraSource(FakeCapture(5, fps=20.0), where="camera 0", size=SIZE, stall_s=0.4)
    result = Runner(sc, source=source, out=tmp_path / "run",
                    outputs=OutputSettings(video=False, figures=False)).run()
    assert result.error is None and not result.interrupted
    assert result.summary["stopped"] == "stalled" and result.summary["frames"] == 5
    assert result.summary["source"]["stalled"] is True
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert report["summary"]["stopped"] == "stalled" and len(report["frames"]) == 5
    footer = json.loads((tmp_path / "run" / "trace.jsonl").read_text().splitlines()[-1])
    assert footer["stop_reason"] == "stalled"
