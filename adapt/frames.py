"""Frames in and frames out: the frame-source protocol and the video sink.

A :class:`FrameSource` is where the runner's "real" images come from -- a
synthetic reality, a video file, an image sequence, later a live camera.  It
yields :class:`Frame` records (index, time, BGR image) of a fixed size at a
fixed rate.  What a source knows beyond the image (ground truth, a robot it
can move) is reached through separate, optional interfaces
(:class:`Actuator` here, ground truth in :mod:`adapt.reality.truth`), so the
perceiving side, which receives only frames, cannot read ground truth.

A :class:`VideoSink` writes frames to a video file atomically: the file
appears, complete, when the sink is closed; an error or an interrupt leaves
the previous file (if any) untouched.  An ``.mp4`` is MPEG-4 Part 2 (``mp4v``,
fast) unless ``codec="vp09"`` asks for VP9, which browsers play;
:attr:`VideoSink.codec` says which codec was used.

Examples
--------
>>> import numpy as np, tempfile, pathlib
>>> out = pathlib.Path(tempfile.mkdtemp()) / "v.mp4"
>>> with VideoSink(out, fps=10, size=(64, 48)) as sink:
...     for i in range(3):
...         sink.write(np.full((48, 64, 3), 40 * i, np.uint8))
>>> out.exists(), sink.frames, sink.codec
(True, 3, 'mp4v')
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any, Iterator, Protocol, runtime_checkable

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import AdaptError, ImageError
from adapt.files import atomic_path
from adapt.native import native_messages

__all__ = ["Frame", "FrameSource", "SourceStatus", "Actuator", "VideoSink", "VIDEO_CODECS"]

#: Video containers a :class:`VideoSink` writes, with their codecs in order of preference:
#: MPEG-4 Part 2 in MP4 (fast; browsers do not play it), or VP9 in MP4 (``vp09``: browsers
#: play it, but OpenCV encodes it 4 to 45 times slower; its wheel has no H.264 encoder); Motion
#: JPEG in AVI.
VIDEO_CODECS = {".mp4": ("mp4v", "vp09"), ".avi": ("MJPG",)}


@dataclass(frozen=True, slots=True, eq=False)
class Frame:
    """One image from a frame source.

    Attributes
    ----------
    index : int
        0, 1, 2, ... in the order the source delivers them.
    time : float
        Seconds since the source started (``index / fps`` for a steady source).
    image : (H, W, 3) uint8 ndarray
        BGR, read-only.
    """

    index: int
    time: float
    image: NDArray[np.uint8]


@runtime_checkable
class FrameSource(Protocol):
    """Where frames come from.

    ``size`` is ``(width, height)``; ``fps`` the frame rate; iterating yields
    frames in order until the source ends; ``close`` releases files.
    """

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` of every frame."""
        ...

    @property
    def fps(self) -> float:
        """Frames per second."""
        ...

    def __iter__(self) -> Iterator[Frame]:
        """The frames, in order."""
        ...

    def close(self) -> None:
        """Release what the source holds open."""
        ...


@runtime_checkable
class SourceStatus(Protocol):
    """A frame source that reports on itself (a camera: frames dropped, the rate
    measured); ``stalled`` is True when it ended because no frame came."""

    @property
    def stalled(self) -> bool:
        """True when the source ended because it delivered nothing for too long."""
        ...

    def status(self) -> dict[str, Any]:
        """JSON values: what the source did (the run's summary keeps them as ``source``)."""
        ...


@runtime_checkable
class Actuator(Protocol):
    """A robot in reality that motor schemas can command (absent for a video)."""

    def command_robot(self, velocity: tuple[float, float], angular_velocity: float = 0.0) -> None:
        """Command the robot's velocity (m/s, world frame) and turn rate (rad/s)."""
        ...


class VideoSink:
    """Writes BGR frames of one size to ``path`` (``.mp4`` or ``.avi``), atomically.

    ``codec`` (a four-character code of :data:`VIDEO_CODECS` for the extension) chooses
    the codec; by default the first of the extension's that OpenCV can write here.

    Raises
    ------
    AdaptError
        For an extension no codec is known for, or when OpenCV cannot write
        video here.
    ImageError
        For a frame of the wrong size or type.
    """

    def __init__(self, path: str | os.PathLike[str], fps: float, size: tuple[int, int],
                 codec: str | None = None) -> None:
        self.path = Path(path)
        ext = self.path.suffix.lower()
        if ext not in VIDEO_CODECS:
            raise AdaptError(f"{str(self.path)!r}: expected a video file name ending in "
                             + " or ".join(VIDEO_CODECS))
        codecs = VIDEO_CODECS[ext]
        if codec is not None and codec not in codecs:
            raise AdaptError(f"{str(self.path)!r}: {ext} video is written as "
                             + " or ".join(codecs) + f", not {codec!r}")
        if not (fps > 0 and np.isfinite(fps)):
            raise AdaptError(f"video frame rate must be positive, got {fps}")
        self.size = (int(size[0]), int(size[1]))
        self.fps = float(fps)
        self.frames = 0
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._atomic = atomic_path(self.path, suffix=ext)
        self._tmp = self._atomic.__enter__()
        self._closed = False
        self.codec = ""
        for fourcc in (codecs if codec is None else (codec,)):
            with native_messages():  # a codec the build lacks says so on stderr: try the next
                self._writer = cv2.VideoWriter(self._tmp, cv2.VideoWriter_fourcc(*fourcc),  # type: ignore[attr-defined]
                                               self.fps, self.size)
            if self._writer.isOpened():
                self.codec = fourcc
                break
            self._writer.release()
        if not self.codec:
            self._abort()
            raise AdaptError(f"OpenCV cannot write {ext} video here")

    def write(self, image: NDArray[np.uint8]) -> None:
        """Append one frame."""
        img = np.asarray(image)
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3:
            raise ImageError(f"video frames must be BGR uint8 images, got {img.dtype} {img.shape}")
        if (img.shape[1], img.shape[0]) != self.size:
            raise ImageError(f"video frame is {img.shape[1]}x{img.shape[0]}, the video is "
                             f"{self.size[0]}x{self.size[1]}")
        self._writer.write(np.ascontiguousarray(img))
        self.frames += 1

    def close(self) -> None:
        """Finish the file and move it into place."""
        if self._closed:
            return
        self._closed = True
        self._writer.release()
        self._atomic.__exit__(None, None, None)

    def _abort(self) -> None:
        """Drop the partial file (the previous file at ``path``, if any, stays)."""
        self._closed = True
        self._writer.release()
        aborted = RuntimeError("video aborted")
        self._atomic.__exit__(RuntimeError, aborted, None)

    def __enter__(self) -> "VideoSink":
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if kind is None:
            self.close()
        else:
            self._abort()
