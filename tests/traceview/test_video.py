"""A run's ``mmd.mp4`` in the trace viewer: VP9 in MP4 when the scenario asks
(``outputs.video_codec: vp9``), linked from the page, played by a browser (headless Chromium)
and kept at the selected frame; MPEG-4 by default."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cv2
import pytest

from adapt.traceview.html import page_payload, video_beside
from adapt.traceview.reader import Trace

from .test_browser import CHROMIUM, browser, open_page, page  # noqa: F401 (fixtures)

ROOT = Path(__file__).resolve().parents[2]
SMALL = ["--set", "camera.width=160", "--set", "camera.height=120", "--set", "camera.fx=131.25",
         "--set", "camera.fy=131.25", "--set", "camera.cx=79.5", "--set", "camera.cy=59.5"]


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("run") / "run"
    proc = subprocess.run([sys.executable, "-m", "adapt", "run", "scenarios/bouncing-ball.yaml",
                           "--max-frames", "8", "--out", str(out), "--no-figures", "--quiet", *SMALL,
                           "--set", "outputs.video_codec=vp9"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return out


def test_the_runs_video_is_vp9_in_mp4_with_a_frame_per_record(run: Path) -> None:
    data = (run / "mmd.mp4").read_bytes()
    assert data[4:8] == b"ftyp" and b"vp09" in data and b"vpcC" in data  # what browsers play
    capture = cv2.VideoCapture(str(run / "mmd.mp4"))
    frames = 0
    while capture.read()[0]:
        frames += 1
    assert frames == 8 and capture.get(cv2.CAP_PROP_FPS) == pytest.approx(30.0)
    assert int(capture.get(cv2.CAP_PROP_FRAME_WIDTH)) == 3 * 160


def test_the_page_links_the_video_beside_the_trace(run: Path, tmp_path: Path) -> None:
    trace = Trace(str(run / "trace.jsonl"))
    assert page_payload(trace, str(run / "trace.html"))["video"] == {"src": "mmd.mp4", "fps": 30.0}
    assert page_payload(trace, str(run / "view" / "t.html"))["video"]["src"] == "../mmd.mp4"
    assert video_beside(str(tmp_path / "trace.jsonl"), str(tmp_path / "t.html")) is None
    proc = subprocess.run([sys.executable, "-m", "adapt", "trace", "html", str(run / "trace.jsonl")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert '"video":{"src":"mmd.mp4","fps":30.0}' in (run / "trace.html").read_text()


@pytest.mark.browser
@pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"{CHROMIUM} is missing")
def test_a_browser_plays_the_video_at_the_selected_frame(run: Path, page) -> None:  # noqa: F811
    subprocess.run([sys.executable, "-m", "adapt", "trace", "html", str(run / "trace.jsonl"),
                    "--out", str(run / "view" / "t.html")], check=True, capture_output=True,
                   timeout=600)
    open_page(page, run / "view" / "t.html")
    state = "(() => { const v = document.getElementById('mmd-video'); " \
            "return [v.readyState, v.videoWidth, v.duration, v.error && v.error.code]; })()"
    for _ in range(50):
        ready, width, duration, error = page.evaluate(state)
        if ready >= 1 or error:
            break
        page.wait_for_timeout(100)
    assert error is None and ready >= 1, "the browser could not play mmd.mp4"
    assert width == 480 and duration == pytest.approx(8 / 30, abs=0.02)
    assert page.locator("#video-panel").is_visible()
    # the selected decision's frame is shown: its record's frame index at 30 frames/s
    rows = page.locator("#timeline .row")
    rows.nth(rows.count() - 1).click()
    page.wait_for_timeout(300)
    when = page.locator("#mmd-when").inner_text()
    frame = int(when.split("frame ")[1].split(",")[0])
    shown = page.evaluate("document.getElementById('mmd-video').currentTime")
    assert shown == pytest.approx((frame + 0.5) / 30, abs=1e-3)
    assert not page.errors  # type: ignore[attr-defined]


def test_the_default_video_is_mpeg4_and_vp9_is_asked_for(tmp_path: Path) -> None:
    import numpy as np

    from adapt.frames import VideoSink
    from adapt.runner.panels import VideoOutput
    from adapt.scenario import OutputSettings, VideoCodec

    assert OutputSettings().video_codec is VideoCodec.MPEG4 and VideoOutput(tmp_path / "a.mp4", 10.0,
                                                                            (8, 8)).codec is VideoCodec.MPEG4
    for codec, tag in (("mp4v", b"mp4v"), ("vp09", b"vp09")):
        with VideoSink(tmp_path / f"{codec}.mp4", 10.0, (64, 48), codec=codec) as sink:
            sink.write(np.zeros((48, 64, 3), np.uint8))
        assert tag in (tmp_path / f"{codec}.mp4").read_bytes()
    with VideoSink(tmp_path / "d.mp4", 10.0, (64, 48)) as sink:
        sink.write(np.zeros((48, 64, 3), np.uint8))
    assert sink.codec == "mp4v"
