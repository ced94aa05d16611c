"""Frames from a camera: a device, a stream URL, or a file played as a camera would.

:class:`CameraSource` is a :class:`~adapt.frames.FrameSource` over OpenCV's
``VideoCapture``.  Unlike a video reality, a camera does not wait for the
loop: a reading thread takes each frame as the camera delivers it and keeps
only the newest; a frame the loop had not taken when the next one arrived
is **dropped** and counted.  A video file given as the device is played at
its own frame rate, as a camera would deliver it (a *stream served from a
file*: how the tests stand in for a device).

Each frame's time is the **source's timestamp** (``CAP_PROP_POS_MSEC``)
from the first frame's, while the source gives increasing timestamps; a
device that gives none is timed by the wall clock from the first frame
(the status says which clock).  The frame rate is the device's stated one
unless the scenario gives ``reality.fps``; the rate the camera really
delivered frames at (every frame read, dropped or not) is **measured** from
their timestamps and reported.

A source that delivers no frame for ``reality.stall_s`` seconds has
**stalled**: iteration ends, :attr:`CameraSource.stalled` is set and the
status says so, so the run ends with its status ``stalled`` and a complete
report.  A file that ends, ends the run as a video does.

Examples
--------
>>> import tempfile, pathlib, numpy as np
>>> from adapt.frames import VideoSink
>>> path = pathlib.Path(tempfile.mkdtemp()) / "cam.avi"
>>> with VideoSink(path, fps=50, size=(32, 24)) as sink:
...     for i in range(5):
...         sink.write(np.full((24, 32, 3), 40 * i, np.uint8))
>>> source = CameraSource.open(str(path), size=(32, 24))
>>> frames = [(f.index, round(f.time, 3)) for f in source]
>>> frames, source.status()["clock"], source.status()["stopped"]
([(0, 0.0), (1, 0.02), (2, 0.04), (3, 0.06), (4, 0.08)], 'source', 'end-of-stream')
"""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path
from typing import Any, Callable, Iterator, Protocol

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import RealityError
from adapt.frames import Frame
from adapt.native import native_messages
from adapt.scenario import CameraReality, Scenario

__all__ = ["CameraSource", "Capture", "DEFAULT_STALL_S"]

#: Seconds without a frame after which a camera has stalled, when the scenario gives none.
DEFAULT_STALL_S = 2.0


class Capture(Protocol):
    """What :class:`CameraSource` uses of ``cv2.VideoCapture``."""

    def isOpened(self) -> bool: ...  # noqa: N802 (OpenCV's names)

    def read(self) -> tuple[bool, Any]: ...

    def get(self, prop: int) -> float: ...

    def set(self, prop: int, value: float) -> bool: ...

    def release(self) -> None: ...


def _describe(device: int | str) -> str:
    return f"camera {device}" if isinstance(device, int) else repr(device)


class CameraSource:
    """A camera as a frame source (see the module docstring).

    Use :meth:`open` or :meth:`from_scenario`; the constructor takes an opened
    :class:`Capture` (a test may give its own).

    Attributes
    ----------
    robot, truth : None
        A camera has neither a robot to command nor ground truth.
    stalled : bool
        True once the source delivered nothing for ``stall_s`` seconds.
    """

    robot = None
    truth = None

    def __init__(self, capture: Capture, *, where: str, size: tuple[int, int],
                 fps: float | None = None, live: bool = True, stall_s: float = DEFAULT_STALL_S,
                 limit: int | None = None, clock: Callable[[], float] = time.monotonic) -> None:
        self._capture: Capture | None = capture
        self._where = where
        self._size = (int(size[0]), int(size[1]))
        self._live = live
        self._stall_s = float(stall_s)
        self._limit = limit
        self._clock = clock
        self.stalled = False
        self._stopped: str | None = None
        self._error: BaseException | None = None
        self._started = False
        self._closing = threading.Event()
        self._cond = threading.Condition()
        self._pending: tuple[NDArray[np.uint8], float] | None = None
        self._ended = False
        self._read = 0
        self._dropped = 0
        self._delivered = 0
        self._source_clock = True
        self._first_ms: float | None = None
        self._last_ms: float | None = None
        self._wall0: float | None = None
        self._timed: tuple[int, float, float] | None = None  # frames the reader read, first, last time
        self._thread: threading.Thread | None = None
        try:
            stated = float(capture.get(cv2.CAP_PROP_FPS))
            self._stated = stated if stated > 0 and math.isfinite(stated) and stated < 1000 else None
            if fps is None:
                if self._stated is None:
                    raise RealityError(f"{where}: the camera states no frame rate; give reality.fps")
                fps = self._stated
            if not (fps > 0 and math.isfinite(fps)):
                raise RealityError(f"{where}: expected a positive frame rate, got {fps}")
            self._fps = float(fps)
            first = self._grab()  # a wrong camera fails before a run starts
            if first is None:
                raise RealityError(f"{where}: the camera delivered no frame")
            self._pending = first
            self._read = 1
            if math.isfinite(first[1]):
                self._first_ms = first[1]
        except BaseException:
            self.close()
            raise

    # -- constructors ----------------------------------------------------------------------

    @classmethod
    def open(cls, device: int | str, *, size: tuple[int, int], fps: float | None = None,
             stall_s: float = DEFAULT_STALL_S, limit: int | None = None) -> "CameraSource":
        """Open ``device``: a device index, a stream URL (``rtsp://``, ``http://``) or a
        video file (played at its own rate).

        Raises
        ------
        RealityError
            When OpenCV cannot open it (with what the decoder printed), it states no frame
            rate and none is given, or its first frame is not a BGR image of ``size``.
        """
        what = _describe(device)
        live = isinstance(device, int) or "://" in str(device)
        if not live and not Path(str(device)).is_file():
            raise RealityError(f"{what}: no such file")
        with native_messages() as said:  # V4L2's and FFmpeg's complaints go into the message
            capture = cv2.VideoCapture(device)
            if isinstance(device, int) and capture.isOpened():  # ask for the camera's size
                capture.set(cv2.CAP_PROP_FRAME_WIDTH, size[0])
                capture.set(cv2.CAP_PROP_FRAME_HEIGHT, size[1])
        if not capture.isOpened():
            capture.release()
            kind = "device" if isinstance(device, int) else "stream" if live else "video"
            raise RealityError(f"{what}: OpenCV cannot open this {kind}{said.detail()}")
        return cls(capture, where=what, size=size, fps=fps, live=live, stall_s=stall_s,
                   limit=limit)

    @classmethod
    def from_scenario(cls, scenario: Scenario) -> "CameraSource":
        """The camera reality of a scenario, at its camera's size, for its run's length; an
        error names the position of ``reality.device`` in the scenario."""
        reality = scenario.reality
        if not isinstance(reality, CameraReality):
            raise RealityError(f"{scenario.where('reality').location}: expected a camera "
                               f"reality, got {reality.kind.value}")
        try:
            source = cls.open(reality.device, size=scenario.camera.size, fps=reality.fps,
                              stall_s=reality.stall_s)
        except RealityError as exc:
            raise scenario.where("reality.device").error(str(exc)) from None
        source._limit = scenario.run.frames_at(source.fps)
        return source

    # -- FrameSource ------------------------------------------------------------------------

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` of every frame."""
        return self._size

    @property
    def fps(self) -> float:
        """The frame rate the run assumes (stated or given)."""
        return self._fps

    @property
    def length(self) -> int | None:
        """Frames the source yields at most (a camera has no length of its own)."""
        return self._limit

    def __iter__(self) -> Iterator[Frame]:
        if self._started:
            raise RealityError(f"{self._where}: a camera source can be iterated once")
        self._started = True
        self._wall0 = self._clock()
        self._thread = threading.Thread(target=self._reader, name="adapt-camera", daemon=True)
        self._thread.start()
        return self._frames()

    def close(self) -> None:
        """Stop reading and release the camera."""
        self._closing.set()
        with self._cond:
            self._cond.notify_all()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=max(self._stall_s, 0.5))
        if self._capture is not None and (self._thread is None or not self._thread.is_alive()):
            self._capture.release()
            self._capture = None

    def __enter__(self) -> "CameraSource":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def status(self) -> dict[str, Any]:
        """How the camera did: frames read and delivered, dropped, the rate it delivered
        frames at (measured over the frames read after the first), the clock, why it stopped
        (``stalled``, ``end-of-stream``, ``frames-done``, or None while running)."""
        with self._cond:
            timed = self._timed
            read, dropped, delivered = self._read, self._dropped, self._delivered
        measured = None
        if timed is not None and timed[0] > 1 and timed[2] > timed[1]:
            measured = round((timed[0] - 1) / (timed[2] - timed[1]), 2)
        return {"device": self._where, "fps": self._fps, "fps_stated": self._stated,
                "fps_measured": measured, "clock": "source" if self._source_clock else "wall",
                "frames_read": read, "frames_delivered": delivered, "frames_dropped": dropped,
                "stall_s": self._stall_s, "stalled": self.stalled, "stopped": self._stopped}

    # -- reading ------------------------------------------------------------------------------

    def _grab(self) -> tuple[NDArray[np.uint8], float] | None:
        """The next frame and its source timestamp (ms; NaN when the source gives none), or
        None when the camera gave nothing."""
        capture = self._capture
        if capture is None:
            return None
        with native_messages() as said:
            ok, image = capture.read()
        if not ok or image is None:
            return None
        ms = float(capture.get(cv2.CAP_PROP_POS_MSEC))
        return self._checked(image, said.detail()), ms

    def _checked(self, image: Any, said: str) -> NDArray[np.uint8]:
        img = np.asarray(image)
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3:
            raise RealityError(f"{self._where}: the camera gives {img.dtype} images of shape "
                               f"{tuple(img.shape)}; expected 8-bit BGR colour{said}")
        h, w = img.shape[:2]
        if (w, h) != self._size:
            raise RealityError(f"{self._where}: the camera gives {w}x{h} images; expected "
                               f"{self._size[0]}x{self._size[1]} (the scenario camera's width "
                               "and height)")
        out = np.ascontiguousarray(img)
        out.setflags(write=False)
        return out

    def _reader(self) -> None:
        """The reading thread: newest frame kept, the one it replaces counted as dropped; a
        file paced at its own timestamps."""
        last = self._clock()
        try:
            while not self._closing.is_set():
                got = self._grab()
                now = self._clock()
                if got is None:
                    if not self._live:
                        self._finish(ended=True)
                        return
                    if now - last > self._stall_s:
                        return  # the loop's wait times out and reports the stall
                    time.sleep(min(0.01, self._stall_s / 10))
                    continue
                last = now
                if not self._live:
                    self._pace(got[1])
                stamp = got[1] / 1000.0 if math.isfinite(got[1]) and got[1] > 0 else now
                with self._cond:
                    n, first, _ = self._timed or (0, stamp, stamp)
                    self._timed = (n + 1, first, stamp)
                    if self._pending is not None:
                        self._dropped += 1
                    self._pending = got
                    self._read += 1
                    self._cond.notify_all()
        except BaseException as exc:  # a bad frame: the loop raises it
            with self._cond:
                self._error = exc
                self._cond.notify_all()

    def _pace(self, ms: float) -> None:
        """Wait until a file's frame is due (its timestamp after the first frame's)."""
        if not math.isfinite(ms) or self._wall0 is None:
            return
        first = self._first_ms if self._first_ms is not None else 0.0
        due = self._wall0 + (ms - first) / 1000.0
        self._closing.wait(max(0.0, due - self._clock()))

    def _finish(self, *, ended: bool) -> None:
        with self._cond:
            self._ended = ended
            self._cond.notify_all()

    def _time(self, ms: float, now: float) -> float:
        """A frame's time: its source timestamp while they increase, else the wall clock."""
        assert self._wall0 is not None
        if self._source_clock:
            first = self._last_ms is None
            if not (math.isfinite(ms) and self._first_ms is not None
                    and (first or ms > self._last_ms)):  # type: ignore[operator]
                self._source_clock = False  # no usable timestamps: the wall clock from here
            self._last_ms = ms
        if self._source_clock:
            assert self._first_ms is not None
            return (ms - self._first_ms) / 1000.0
        return now - self._wall0

    def _frames(self) -> Iterator[Frame]:
        index = 0
        last_t = -math.inf
        while self._limit is None or index < self._limit:
            with self._cond:
                ready = self._cond.wait_for(
                    lambda: self._pending is not None or self._ended or self._error is not None
                    or self._closing.is_set(), timeout=self._stall_s)
                if self._error is not None:
                    raise self._error
                if self._closing.is_set():
                    return
                if not ready:
                    self.stalled = True
                    self._stopped = "stalled"
                    return
                if self._pending is None:  # the file ended
                    self._stopped = "end-of-stream"
                    return
                image, ms = self._pending
                self._pending = None
                self._delivered += 1
                t = max(self._time(ms, self._clock()), last_t)
            last_t = t
            yield Frame(index, t, image)
            index += 1
        self._stopped = "frames-done"
        self.close()
