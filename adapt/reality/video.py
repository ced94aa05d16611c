"""Frames from a video file or an image sequence.

:class:`VideoSource` is a :class:`~adapt.frames.FrameSource` over

* a **video file** OpenCV can read (its own frame rate unless the scenario
  gives ``fps``), or
* an **image sequence** given as a glob (``frames/*.png``; ``fps`` required),
  in natural order (``f2.png`` before ``f10.png``).

Frame ``i`` has time ``i / fps``.  Every frame must have the scenario
camera's size and three 8-bit channels (BGR colour); the first frame is
checked when the source is opened, so a wrong video fails before a run
starts.  The source yields at most ``run.max_frames`` frames, or
``run.duration`` (10 s by default) times its frame rate, and fewer when the
video is shorter.

A video file whose stream ends before the frame count in its header (a
truncated file) ends cleanly at its last readable frame: iteration stops,
:attr:`VideoSource.note` says how many frames were missing, and a
:class:`RealityWarning` is issued.  An image of the sequence that cannot be
read is an error (:class:`~adapt.errors.RealityError`) naming the file.

A ground-truth CSV (``reality.ground_truth``) is read and checked when the
source is opened and is available as :attr:`VideoSource.truth`, for
evaluation only (see :mod:`adapt.reality.truth`).

Examples
--------
>>> import tempfile, pathlib, cv2, numpy as np
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> for i in (1, 2, 10):
...     _ = cv2.imwrite(str(d / f"f{i}.png"), np.full((24, 32, 3), 10 * i, np.uint8))
>>> source = VideoSource.images(str(d / "*.png"), fps=5.0, size=(32, 24))
>>> [(f.index, f.time, int(f.image[0, 0, 0])) for f in source]
[(0, 0.0, 10), (1, 0.2, 20), (2, 0.4, 100)]
"""

from __future__ import annotations

import glob as globbing
import math
import re
import warnings
from pathlib import Path
from typing import Iterator

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import RealityError
from adapt.frames import Frame
from adapt.native import NativeMessages, native_messages
from adapt.reality.truth import CsvTruth, load_truth_csv
from adapt.reality.warning import RealityWarning
from adapt.scenario import Scenario, VideoReality

__all__ = ["VideoSource", "RealityWarning", "natural_key", "frame_limit"]


def natural_key(path: str) -> list[object]:
    """Sort key that orders the numbers inside names by value.

    Examples
    --------
    >>> sorted(["f10.png", "f2.png", "f1.png"], key=natural_key)
    ['f1.png', 'f2.png', 'f10.png']
    """
    return [int(p) if p.isdigit() else p for p in re.split(r"(\d+)", path)]


def frame_limit(scenario: Scenario, fps: float) -> int:
    """Frames a video run takes at most: the run's length at the video's ``fps``
    (:meth:`RunSettings.frames_at <adapt.scenario.RunSettings.frames_at>`)."""
    return scenario.run.frames_at(fps)


def _check(image: NDArray[np.generic] | None, index: int, where: str,
           size: tuple[int, int], said: NativeMessages | None = None) -> NDArray[np.uint8]:
    """A frame as read, checked: 8-bit, three channels, the expected size (``said``: what
    the decoder printed, for the message)."""
    if image is None:
        raise RealityError(f"frame {index} ({where}) is not a readable image"
                           f"{said.detail() if said is not None else ''}")
    channels = 1 if image.ndim == 2 else image.shape[2]
    if image.dtype != np.uint8:
        raise RealityError(f"frame {index} ({where}) has {image.dtype} pixels; expected 8-bit "
                           "(uint8) colour images")
    if channels != 3:
        raise RealityError(f"frame {index} ({where}) has {channels} channel"
                           f"{'s' if channels != 1 else ''}; expected 3 (BGR colour)")
    h, w = image.shape[:2]
    if (w, h) != size:
        raise RealityError(f"frame {index} ({where}) is {w}x{h} pixels; expected {size[0]}x"
                           f"{size[1]} (the scenario camera's width and height)")
    out = np.ascontiguousarray(image)
    out.setflags(write=False)
    return out  # type: ignore[return-value]


class VideoSource:
    """A video file or an image sequence as a frame source.

    Use :meth:`images`, :meth:`video` or :meth:`from_scenario`.

    Attributes
    ----------
    robot : None
        A recording cannot be commanded.
    truth : CsvTruth or None
        The ground truth, when a file was given (evaluation only).
    note : str or None
        Set when a video ended before its stated length.
    """

    robot = None

    def __init__(self, *, files: list[str] | None, capture: cv2.VideoCapture | None,
                 where: str, fps: float, size: tuple[int, int], limit: int | None,
                 stated: int | None, truth: CsvTruth | None) -> None:
        self._files = files
        self._capture = capture
        self._where = where
        self._fps = float(fps)
        self._size = (int(size[0]), int(size[1]))
        self._stated = stated
        self._limit = limit
        self.truth = truth
        self.note: str | None = None
        self._started = False
        self._closed = False
        self._first: NDArray[np.uint8] | None = None
        try:
            self._first = self._read(0)
        except BaseException:
            self.close()
            raise
        if self._first is None:
            self.close()
            raise RealityError(f"{where}: the video has no frames")

    # -- constructors ----------------------------------------------------------------------

    @classmethod
    def images(cls, pattern: str, *, fps: float, size: tuple[int, int],
               limit: int | None = None, ground_truth: str | Path | None = None) -> "VideoSource":
        """An image sequence: the files matching ``pattern``, in natural order."""
        files = sorted(globbing.glob(pattern), key=natural_key)
        files = [f for f in files if Path(f).is_file()]
        if not files:
            raise RealityError(f"no image file matches {pattern!r}")
        cls._check_fps(fps, pattern)
        truth = None if ground_truth is None else CsvTruth(load_truth_csv(ground_truth), fps)
        return cls(files=files, capture=None, where=pattern, fps=fps, size=size, limit=limit,
                   stated=len(files), truth=truth)

    @classmethod
    def video(cls, path: str | Path, *, fps: float | None, size: tuple[int, int],
              limit: int | None = None, ground_truth: str | Path | None = None) -> "VideoSource":
        """A video file (``fps`` None: the file's own rate)."""
        p = Path(path)
        if not p.is_file():
            raise RealityError(f"video file {str(p)!r} not found")
        with native_messages() as said:  # FFmpeg's complaints go into the message
            capture = cv2.VideoCapture(str(p))
        if not capture.isOpened():
            capture.release()
            raise RealityError(f"{str(p)!r}: OpenCV cannot open it as a video{said.detail()}")
        if fps is None:
            fps = float(capture.get(cv2.CAP_PROP_FPS))
            if not (fps > 0 and math.isfinite(fps)):
                capture.release()
                raise RealityError(f"{str(p)!r}: the video states no frame rate; give "
                                   "reality.fps")
        cls._check_fps(fps, str(p))
        count = capture.get(cv2.CAP_PROP_FRAME_COUNT)
        stated = int(count) if count > 0 and math.isfinite(count) else None
        try:
            truth = None if ground_truth is None else CsvTruth(load_truth_csv(ground_truth), fps)
        except BaseException:
            capture.release()
            raise
        return cls(files=None, capture=capture, where=str(p), fps=fps, size=size, limit=limit,
                   stated=stated, truth=truth)

    @classmethod
    def from_scenario(cls, scenario: Scenario) -> "VideoSource":
        """The video reality of a scenario, at its camera's size, for its run's length."""
        reality = scenario.reality
        if not isinstance(reality, VideoReality):
            raise RealityError(f"{scenario.where('reality').location}: expected a video reality, "
                               f"got {reality.kind.value}")
        size = scenario.camera.size
        if reality.pattern is not None:
            assert reality.fps is not None
            return cls.images(reality.pattern, fps=reality.fps, size=size,
                              limit=frame_limit(scenario, reality.fps),
                              ground_truth=reality.ground_truth)
        source = cls.video(reality.path, fps=reality.fps, size=size, limit=None,
                           ground_truth=reality.ground_truth)
        source._limit = frame_limit(scenario, source.fps)
        return source

    @staticmethod
    def _check_fps(fps: float, where: str) -> None:
        if not (fps > 0 and math.isfinite(fps)):
            raise RealityError(f"{where}: expected a positive frame rate, got {fps}")

    # -- FrameSource ------------------------------------------------------------------------

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` of every frame."""
        return self._size

    @property
    def fps(self) -> float:
        """Frames per second."""
        return self._fps

    @property
    def length(self) -> int | None:
        """Frames the source will yield at most (None when the video states no length)."""
        if self._stated is None:
            return self._limit
        return self._stated if self._limit is None else min(self._stated, self._limit)

    def __iter__(self) -> Iterator[Frame]:
        if self._started:
            raise RealityError(f"{self._where}: a video source can be iterated once")
        self._started = True
        return self._frames()

    def close(self) -> None:
        """Release the video file."""
        self._closed = True
        if self._capture is not None:
            self._capture.release()
            self._capture = None

    def __enter__(self) -> "VideoSource":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- reading -----------------------------------------------------------------------------

    def _read(self, index: int) -> NDArray[np.uint8] | None:
        """Frame ``index`` (in order), or None at the end of the stream."""
        if self._files is not None:
            if index >= len(self._files):
                return None
            f = self._files[index]
            with native_messages() as said:  # libjpeg's complaints go into the message
                image = cv2.imread(f, cv2.IMREAD_UNCHANGED)
            return _check(image, index, f, self._size, said)
        assert self._capture is not None
        with native_messages() as said:
            ok, image = self._capture.read()
        if not ok:
            return None
        return _check(image, index, self._where, self._size, said)

    def _frames(self) -> Iterator[Frame]:
        index = 0
        while self._limit is None or index < self._limit:
            if self._closed:
                return
            if index == 0 and self._first is not None:
                image: NDArray[np.uint8] | None = self._first
                self._first = None
            else:
                image = self._read(index)
            if image is None:
                if self._stated is not None and index < self._stated:
                    self.note = (f"{self._where}: the video ended after {index} of the "
                                 f"{self._stated} frames its header states")
                    warnings.warn(self.note, RealityWarning, stacklevel=2)
                return
            yield Frame(index, index / self._fps, image)
            index += 1
        self.close()
