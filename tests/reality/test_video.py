"""The video source: round trips through VideoSink, image sequences, and every bad input."""

from __future__ import annotations

import warnings
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.errors import GroundTruthError, RealityError
from adapt.frames import VideoSink
from adapt.reality import RealitySource, RealityWarning, VideoSource, open_reality
from adapt.scenario import load_scenario
from adapt.seeds import Streams

from .conftest import CAMERA, WORLD

SIZE = (160, 120)


def pattern(i: int) -> np.ndarray:
    """A frame with a bright bar that moves with ``i``."""
    img = np.full((SIZE[1], SIZE[0], 3), 40, np.uint8)
    img[20:100, 10 + 8 * i:30 + 8 * i] = (220, 180, 60)
    return img


def write_video(path: Path, n: int, fps: float = 12.0) -> None:
    with VideoSink(path, fps=fps, size=SIZE) as sink:
        for i in range(n):
            sink.write(pattern(i))


def write_images(folder: Path, n: int, ext: str = ".png") -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        cv2.imwrite(str(folder / f"img{i}{ext}"), pattern(i))


def video_scenario(tmp_path: Path, reality: str, run: str = ""):  # type: ignore[no-untyped-def]
    (tmp_path / "s.yaml").write_text(CAMERA + WORLD + "reality:\n" + reality + run)
    return load_scenario(tmp_path / "s.yaml")


# -- round trips ---------------------------------------------------------------------------

@pytest.mark.parametrize("ext", [".avi", ".mp4"])
def test_a_video_written_by_the_sink_reads_back(tmp_path: Path, ext: str) -> None:
    write_video(tmp_path / f"v{ext}", 15)
    with VideoSource.video(tmp_path / f"v{ext}", fps=None, size=SIZE) as src:
        assert src.fps == pytest.approx(12.0) and src.size == SIZE and src.length == 15
        frames = list(src)
    assert [f.index for f in frames] == list(range(15))
    assert [f.time for f in frames] == pytest.approx([i / 12 for i in range(15)])
    for i, f in enumerate(frames):
        assert f.image.shape == (120, 160, 3) and not f.image.flags.writeable
        assert np.abs(f.image.astype(int) - pattern(i)).mean() < 4   # lossy codecs


def test_a_video_scenario_plays_its_file_for_the_run(tmp_path: Path) -> None:
    write_video(tmp_path / "clip.avi", 10)
    sc = video_scenario(tmp_path, "  kind: video\n  path: clip.avi\n", "run: {max_frames: 6}\n")
    src = open_reality(sc, streams=Streams(0))
    assert isinstance(src, RealitySource) and src.robot is None and src.truth is None
    assert len(list(src)) == 6
    # A duration counts in the video's own frames.
    sc = video_scenario(tmp_path, "  kind: video\n  path: clip.avi\n  fps: 4\n",
                        "run: {duration: 1.0}\n")
    assert [f.time for f in open_reality(sc, streams=Streams(0))] == [0, 0.25, 0.5, 0.75]


def test_an_image_sequence_plays_in_natural_order(tmp_path: Path) -> None:
    write_images(tmp_path / "seq", 12)
    sc = video_scenario(tmp_path, "  kind: video\n  path: seq/img*.png\n  fps: 8\n")
    src = open_reality(sc, streams=Streams(0))
    frames = list(src)
    assert len(frames) == 12 and src.fps == 8
    for i, f in enumerate(frames):     # img2 before img10
        assert np.array_equal(f.image, pattern(i))
    with pytest.raises(RealityError, match="iterated once"):
        iter(src)


# -- bad input ---------------------------------------------------------------------------------

def test_a_video_that_cannot_be_opened(tmp_path: Path) -> None:
    (tmp_path / "bad.mp4").write_bytes(b"this is not a video" * 20)
    with pytest.raises(RealityError, match="cannot open it as a video"):
        VideoSource.video(tmp_path / "bad.mp4", fps=None, size=SIZE)
    with pytest.raises(RealityError, match="not found"):
        VideoSource.video(tmp_path / "none.mp4", fps=None, size=SIZE)


def test_a_video_that_ends_before_its_stated_length_ends_cleanly_with_a_note(tmp_path: Path) -> None:
    write_video(tmp_path / "v.avi", 20)
    data = (tmp_path / "v.avi").read_bytes()
    (tmp_path / "cut.avi").write_bytes(data[: int(len(data) * 0.8)])
    src = VideoSource.video(tmp_path / "cut.avi", fps=None, size=SIZE)
    assert src.length == 20
    with pytest.warns(RealityWarning, match="ended after"):
        frames = list(src)
    assert 0 < len(frames) < 20
    assert src.note is not None and f"after {len(frames)} of the 20 frames" in src.note


def test_a_video_shorter_than_the_run_ends_without_a_note(tmp_path: Path) -> None:
    write_video(tmp_path / "v.avi", 5)
    src = VideoSource.video(tmp_path / "v.avi", fps=None, size=SIZE, limit=50)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(list(src)) == 5
    assert src.note is None


def test_frames_of_the_wrong_size_are_refused_when_opened(tmp_path: Path) -> None:
    write_video(tmp_path / "v.avi", 3)
    with pytest.raises(RealityError, match=r"frame 0 \(.*v.avi\) is 160x120 pixels; expected 320x240"):
        VideoSource.video(tmp_path / "v.avi", fps=None, size=(320, 240))


def test_a_frame_of_the_wrong_size_inside_a_sequence_names_its_file(tmp_path: Path) -> None:
    write_images(tmp_path, 4)
    cv2.imwrite(str(tmp_path / "img2.png"), np.zeros((100, 160, 3), np.uint8))
    src = VideoSource.images(str(tmp_path / "*.png"), fps=5, size=SIZE)
    with pytest.raises(RealityError, match=r"frame 2 \(.*img2.png\) is 160x100 pixels"):
        list(src)


@pytest.mark.parametrize("image, message", [
    (np.zeros((120, 160), np.uint8), "has 1 channel; expected 3"),
    (np.zeros((120, 160, 4), np.uint8), "has 4 channels; expected 3"),
    (np.zeros((120, 160, 3), np.uint16), "has uint16 pixels; expected 8-bit"),
])
def test_frames_of_the_wrong_channel_count_or_depth(tmp_path: Path, image: np.ndarray,
                                                    message: str) -> None:
    write_images(tmp_path, 3)
    cv2.imwrite(str(tmp_path / "img1.png"), image)
    src = VideoSource.images(str(tmp_path / "*.png"), fps=5, size=SIZE)
    with pytest.raises(RealityError, match=r"frame 1 \(.*img1.png\) " + message):
        list(src)


def test_an_unreadable_image_names_its_file(tmp_path: Path) -> None:
    write_images(tmp_path, 3)
    (tmp_path / "img1.png").write_bytes(b"\x89PNG but broken")
    src = VideoSource.images(str(tmp_path / "*.png"), fps=5, size=SIZE)
    frames = iter(src)
    next(frames)
    with pytest.raises(RealityError, match=r"frame 1 \(.*img1.png\) is not a readable image"):
        next(frames)


def test_an_unreadable_first_image_fails_when_opened(tmp_path: Path) -> None:
    (tmp_path / "a.png").write_bytes(b"")
    with pytest.raises(RealityError, match="a.png"):
        VideoSource.images(str(tmp_path / "*.png"), fps=5, size=SIZE)
    with pytest.raises(RealityError, match="no image file matches"):
        VideoSource.images(str(tmp_path / "*.jpg"), fps=5, size=SIZE)
    with pytest.raises(RealityError, match="positive frame rate"):
        VideoSource.images(str(tmp_path / "*.png"), fps=0.0, size=SIZE)


# -- ground truth -----------------------------------------------------------------------------

def test_ground_truth_is_interpolated_at_the_frame_times(tmp_path: Path) -> None:
    write_images(tmp_path / "seq", 8)
    (tmp_path / "gt.csv").write_text(
        "t,object,x,y,vx,vy\n"
        "0.0,ball,0.0,0.0,1.0,0.0\n"
        "0.5,ball,1.0,2.0,3.0,0.0\n"
        "0.5,box,5,5,,\n"
        "0.75,ball,,,,\n"         # the ball leaves
        "0.875,ball,9,9,0,0\n")   # and comes back
    sc = video_scenario(tmp_path, "  kind: video\n  path: seq/*.png\n  fps: 8\n"
                        "  ground_truth: gt.csv\n")
    src = open_reality(sc, streams=Streams(0))
    truth = src.truth
    assert truth is not None
    t1 = truth.at(1)   # t = 0.125
    assert t1.time == 0.125
    assert t1.objects["ball"].position == pytest.approx((0.25, 0.5))
    assert t1.objects["ball"].velocity == pytest.approx((1.5, 0.0))
    assert t1.objects["box"] is None                   # not there yet
    assert truth.at(4).objects["box"].position == (5.0, 5.0)
    assert truth.at(4).objects["box"].velocity is None  # no velocity given
    assert truth.at(5).objects["ball"] is None          # 0.625: after its last row with a position
    assert truth.at(6).objects["ball"] is None          # 0.75: gone
    assert truth.at(7).position("ball") == (9.0, 9.0)
    assert truth.at(8).position("ball") is None          # past the end
    assert truth.at(-1) is None


# Each bad file, the line and column of the error and what the message says.
BAD_TRUTH = [
    ("", 1, 1, "expected a header line"),
    ("time,object,x,y\n", 1, 1, "unknown column 'time'"),
    ("t,object,x\n", 1, 1, "missing column 'y'"),
    ("t,object,x,y,vx\n", 1, 1, "both 'vx' and 'vy'"),
    ("t,object,x,y,x\n", 1, 1, "named twice"),
    ("t,object,x,y\n0,ball,1\n", 2, 1, "expected 4 values (t,object,x,y), got 3"),
    ("t,object,x,y\n0,ball,1,2\nzero,ball,1,2\n", 3, 1, "column 't': expected a number of seconds"),
    ("t,object,x,y\n-1,ball,1,2\n", 2, 1, "expected a time >= 0"),
    ("t,object,x,y\n0,ball,1,nan\n", 2, 10, "column 'y': expected a finite number"),
    ("t,object,x,y\n0,,1,2\n", 2, 3, "expected an object name"),
    ("t,object,x,y\n0,ball,1,\n", 2, 10, "expected both or neither"),
    ("t,object,x,y\n1,ball,1,2\n0.5,ball,1,2\n", 3, 1, "times of 'ball' to increase"),
    ("t,object,x,y,vx,vy\n0,ball,1,2,fast,0\n", 2, 12, "column 'vx': expected a number of m/s"),
]


@pytest.mark.parametrize("text, line, col, message", BAD_TRUTH)
def test_a_ground_truth_file_with_bad_rows(tmp_path: Path, text: str, line: int, col: int,
                                           message: str) -> None:
    write_images(tmp_path, 2)
    (tmp_path / "gt.csv").write_text(text)
    with pytest.raises(GroundTruthError) as info:
        VideoSource.images(str(tmp_path / "*.png"), fps=5, size=SIZE,
                           ground_truth=tmp_path / "gt.csv")
    e = info.value
    assert e.file == str(tmp_path / "gt.csv") and (e.line, e.col) == (line, col), str(e)
    assert message in e.message, e.message
    assert isinstance(e, RealityError)


def test_a_ground_truth_file_that_is_not_text(tmp_path: Path) -> None:
    write_video(tmp_path / "v.avi", 2)
    (tmp_path / "gt.csv").write_bytes(b"t,object,x,y\n\xff\xfe\x00")
    with pytest.raises(GroundTruthError, match="expected UTF-8 text"):
        VideoSource.video(tmp_path / "v.avi", fps=None, size=SIZE, ground_truth=tmp_path / "gt.csv")
