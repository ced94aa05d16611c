"""The video sink (atomic, checked frames) and independent seed streams."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.errors import AdaptError, ImageError
from adapt.frames import Frame, FrameSource, VideoSink
from adapt.seeds import STREAMS, Streams


def test_a_video_sink_writes_a_readable_video(tmp_path: Path) -> None:
    out = tmp_path / "sub" / "v.avi"
    with VideoSink(out, fps=12, size=(80, 60)) as sink:
        for i in range(5):
            sink.write(np.full((60, 80, 3), 50 * i, np.uint8))
    cap = cv2.VideoCapture(str(out))
    n = 0
    while cap.read()[0]:
        n += 1
    assert n == 5 and sorted(p.name for p in out.parent.iterdir()) == ["v.avi"]


def test_an_interrupted_sink_leaves_the_previous_file(tmp_path: Path) -> None:
    out = tmp_path / "v.mp4"
    out.write_bytes(b"previous")
    with pytest.raises(KeyboardInterrupt):
        with VideoSink(out, fps=10, size=(32, 32)) as sink:
            sink.write(np.zeros((32, 32, 3), np.uint8))
            raise KeyboardInterrupt
    assert out.read_bytes() == b"previous" and [p.name for p in tmp_path.iterdir()] == ["v.mp4"]


def test_bad_frames_and_names(tmp_path: Path) -> None:
    with pytest.raises(AdaptError, match="video file name"):
        VideoSink(tmp_path / "v.gif", fps=10, size=(32, 32))
    with pytest.raises(ImageError, match="32x16"):
        with VideoSink(tmp_path / "v.mp4", fps=10, size=(32, 32)) as sink:
            sink.write(np.zeros((16, 32, 3), np.uint8))
    assert not (tmp_path / "v.mp4").exists()


def test_a_list_of_frames_is_not_a_frame_source_but_a_class_with_the_protocol_is() -> None:
    class Source:
        size = (4, 4)
        fps = 1.0

        def __iter__(self):  # type: ignore[no-untyped-def]
            yield Frame(0, 0.0, np.zeros((4, 4, 3), np.uint8))

        def close(self) -> None:
            pass

    assert isinstance(Source(), FrameSource) and not isinstance([], FrameSource)


def test_streams_are_independent_and_reproducible() -> None:
    s = Streams(3)
    draws = {name: s.generator(name).random(4).tolist() for name in STREAMS}
    assert len({tuple(v) for v in draws.values()}) == len(STREAMS)
    assert draws == {name: Streams(3).generator(name).random(4).tolist() for name in STREAMS}
    assert Streams(4).generator("agent").random() != s.generator("agent").random()
    assert Streams(None).seed == 0
    with pytest.raises(ValueError):
        Streams(-1)
