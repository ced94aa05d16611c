"""The frames of ``mmd.mp4``: real | synthetic | MMD side by side, schemas' boxes drawn.

Each panel is the camera's size; the three are put side by side with a thin
caption bar.  Boxes: the region a schema monitors, in its own colour, with
its name; unexpected regions in red.  :class:`VideoOutput` is the listener
that writes one such frame per frame record.

Examples
--------
>>> import numpy as np
>>> real = np.zeros((48, 64, 3), np.uint8)
>>> out = side_by_side(real, real, np.zeros((48, 64), np.float32), [], [], frame=3, time=0.1)
>>> out.shape
(64, 192, 3)
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.frames import VideoSink
from adapt.scenario import VideoCodec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.record import FrameRecord

__all__ = ["side_by_side", "panel", "VideoOutput", "CAPTION", "FOURCC"]

#: The four-character code of each ``outputs.video_codec`` in an ``.mp4``.
FOURCC = {VideoCodec.VP9: "vp09", VideoCodec.MPEG4: "mp4v"}

#: Height of the caption bar above the panels, pixels.
CAPTION = 16

_PALETTE = [(255, 200, 0), (0, 220, 255), (255, 0, 255), (0, 255, 120), (255, 128, 0)]
_UNEXPECTED = (40, 40, 255)

BBox = tuple[int, int, int, int]


def _box(img: NDArray[np.uint8], box: BBox, color: tuple[int, int, int], label: str) -> None:
    x, y, w, h = (int(v) for v in box)
    cv2.rectangle(img, (x, y), (x + w - 1, y + h - 1), color, 1, cv2.LINE_AA)
    if label:
        cv2.putText(img, label, (x, max(y - 3, 9)), cv2.FONT_HERSHEY_SIMPLEX, 0.35, color, 1,
                    cv2.LINE_AA)


def side_by_side(real: NDArray[np.uint8], synthetic: NDArray[np.uint8] | None,
                 difference: NDArray[np.float32] | None,
                 monitored: Sequence[tuple[str, BBox]], unexpected: Sequence[BBox], *,
                 frame: int, time: float, note: str = "") -> NDArray[np.uint8]:
    """One video frame (see the module docstring)."""
    h, w = real.shape[:2]
    left = np.ascontiguousarray(real.copy())
    mid = (np.zeros_like(left) if synthetic is None else np.ascontiguousarray(synthetic.copy()))
    if difference is None:
        right = np.zeros_like(left)
    else:
        d = np.clip(difference * 2.0, 0, 255).astype(np.uint8)
        if d.shape[:2] != (h, w):  # MMD works at a bounded resolution
            d = cv2.resize(d, (w, h), interpolation=cv2.INTER_NEAREST)
        right = cv2.cvtColor(d, cv2.COLOR_GRAY2BGR)
    colors: dict[str, tuple[int, int, int]] = {}
    for name, box in monitored:
        color = colors.setdefault(name, _PALETTE[len(colors) % len(_PALETTE)])
        for panel in (left, right):
            _box(panel, box, color, name)
    for box in unexpected:
        for panel in (left, right):
            _box(panel, box, _UNEXPECTED, "?")
    bar = np.full((CAPTION, 3 * w, 3), 24, np.uint8)
    for i, title in enumerate(("real", "synthetic (imagination)", "MMD")):
        cv2.putText(bar, title, (i * w + 4, CAPTION - 4), cv2.FONT_HERSHEY_SIMPLEX, 0.4,
                    (230, 230, 230), 1, cv2.LINE_AA)
    text = f"frame {frame}  t={time:.2f} s" + (f"  {note}" if note else "")
    size = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.4, 1)[0][0]
    cv2.putText(bar, text, (3 * w - size - 4, CAPTION - 4), cv2.FONT_HERSHEY_SIMPLEX, 0.4,
                (200, 230, 255), 1, cv2.LINE_AA)
    return np.vstack([bar, np.hstack([left, mid, right])])


def panel(record: "FrameRecord") -> NDArray[np.uint8]:
    """The video frame of a frame record."""
    bg = record.background
    note = ""
    if bg is not None and not math.isnan(bg.pixel_error):
        note = f"camera error {bg.pixel_error:.2f} px"
    return side_by_side(record.frame.image, None if bg is None else bg.synthetic,
                        None if bg is None or bg.mmd is None else bg.mmd.difference,
                        record.monitored, [] if bg is None else [r.bbox for r in bg.unexpected],
                        frame=record.index, time=record.time, note=note)


class VideoOutput:
    """``mmd.mp4``, a listener on the frame records (written atomically: :class:`VideoSink`)."""

    def __init__(self, path: str | os.PathLike[str], fps: float, size: tuple[int, int],
                 codec: VideoCodec = VideoCodec.MPEG4) -> None:
        self.path = Path(path)
        self.fps = fps
        self.size = size
        self.codec = codec
        self.sink: VideoSink | None = None

    def frame(self, record: "FrameRecord") -> None:
        """Write the record's panels."""
        if self.sink is None:
            w, h = self.size
            fourcc = FOURCC[self.codec] if self.path.suffix.lower() == ".mp4" else None
            self.sink = VideoSink(self.path, self.fps, (3 * w, h + CAPTION), codec=fourcc)
        self.sink.write(panel(record))

    def close(self) -> Path | None:
        """Finish the video; its path, or None when no frame was written."""
        if self.sink is None:
            return None
        self.sink.close()
        return self.sink.path
