"""Which pixels of a fixed camera's recent frames held still.

A background learned from one frame paints whatever moved through it into
the look (a ball rolling in the first frame leaves a copy of itself on the
floor, a *ghost*).  :class:`FrameHistory` keeps the last frames of a camera
that did not move and says, per pixel, whether its colour stayed within a
gate over them (:meth:`FrameHistory.still`; a moving object changes the
pixels it crosses), and what the pixel showed most of the time
(:meth:`FrameHistory.median`: an object that crossed a pixel in less than
half of the frames is gone from it), and where that median can be believed
(:meth:`FrameHistory.settled`: most frames agree with it, the oldest and the
newest among them -- a pixel a rolling ball crossed for a frame or two).  The
caller clears the history when the camera moves (a camera on a robot that
drives).

Examples
--------
>>> import numpy as np
>>> history = FrameHistory(depth=5)
>>> for k in range(5):
...     frame = np.full((20, 40, 3), 100, np.uint8)
...     frame[5:15, 8 * k:8 * k + 8] = 250          # an object crossing the view
...     history.push(frame)
>>> bool(history.median()[10, 4, 0] == 100)          # gone from the median
True
>>> still = history.still(gate=20.0)
>>> bool(still[10, 4]), bool(still[2, 4])            # crossed, never crossed
(False, True)
>>> history.changed((0, 0, 40, 4), gate=20.0)        # a box the object never entered
0.0
"""

from __future__ import annotations

from collections import deque

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import VisionError

__all__ = ["FrameHistory"]

BBox = tuple[int, int, int, int]


class FrameHistory:
    """The last ``depth`` frames of a camera that has not moved (see the module docstring)."""

    def __init__(self, depth: int) -> None:
        if depth < 1:
            raise VisionError(f"depth: expected at least 1 frame, got {depth}")
        self.depth = depth
        self._frames: deque[NDArray[np.uint8]] = deque(maxlen=depth)

    def __len__(self) -> int:
        return len(self._frames)

    def clear(self) -> None:
        """Forget every frame (the camera moved)."""
        self._frames.clear()

    def push(self, image: NDArray[np.uint8]) -> None:
        """Keep ``image`` (a copy) as the newest frame; a frame of another size clears the rest."""
        if self._frames and self._frames[-1].shape != image.shape:
            self._frames.clear()
        self._frames.append(np.array(image, np.uint8, copy=True))

    def _span(self, frames: int | None, box: BBox | None
              ) -> tuple[NDArray[np.uint8], NDArray[np.uint8]] | None:
        """Per-pixel minimum and maximum over the newest ``frames`` frames, inside ``box``."""
        if not self._frames:
            return None
        n = len(self._frames) if frames is None else max(1, min(frames, len(self._frames)))
        recent = list(self._frames)[-n:]
        if box is not None:
            x, y, w, h = box
            hh, ww = recent[0].shape[:2]
            x0, y0, x1, y1 = max(x, 0), max(y, 0), min(x + w, ww), min(y + h, hh)
            if x0 >= x1 or y0 >= y1:
                return None
            recent = [f[y0:y1, x0:x1] for f in recent]
        low = recent[0].copy()
        high = recent[0].copy()
        for f in recent[1:]:
            cv2.min(low, f, dst=low)
            cv2.max(high, f, dst=high)
        return low, high

    def still(self, gate: float, frames: int | None = None, box: BBox | None = None
              ) -> NDArray[np.bool_]:
        """Pixels (of ``box``, the part inside the image; the whole image without) whose
        every channel stayed within ``gate`` grey levels over the newest ``frames`` frames
        (all kept by default); an empty array with no frame."""
        span = self._span(frames, box)
        if span is None:
            return np.zeros((0, 0), bool)
        low, high = span
        spread = cv2.absdiff(high, low)
        if spread.ndim == 3:
            b, g, r = cv2.split(spread)
            spread = cv2.max(cv2.max(b, g), r)
        return np.asarray(spread <= gate)

    def changed(self, box: BBox, gate: float, frames: int | None = None) -> float:
        """The share of ``box``'s pixels that changed by more than ``gate`` over the newest
        ``frames`` frames (0 for an empty box or history)."""
        span = self._span(frames, box)
        if span is None:
            return 0.0
        low, high = span
        spread = cv2.absdiff(high, low)
        worst = spread.max(axis=2) if spread.ndim == 3 else spread
        return float(np.count_nonzero(worst > gate)) / float(worst.size)

    def settled(self, gate: float, share: float, ends: bool = True) -> NDArray[np.bool_]:
        """Pixels whose median (:meth:`median`) shows what lies there: at least ``share``
        of the frames kept lie within ``gate`` grey levels of it (every channel) and, with
        ``ends``, so do the oldest frame and the newest.

        An object that crossed a pixel in a few frames between the oldest and the newest
        is gone from the median there, and the frames before and after it agree.  Where it
        was at the oldest frame or is at the newest, the frames cannot say whether it left
        the background or arrived on it (a ball that stood at the start and rolled away,
        or one that rolled in and stays), and where it stayed in most frames the median is
        its colour: with ``ends`` none of these is settled.  Without, a pixel is settled
        wherever a majority agree (the frames agree on something, even if not on what lies
        under an object).  Every pixel that held still (:meth:`still`) is settled; with
        fewer than three frames only those are.

        Parameters
        ----------
        gate : float
            Grey levels a frame may differ from the median and agree.
        share : float
            The share of the frames that must agree, in (0.5, 1].
        ends : bool
            The oldest frame and the newest must agree too.

        Returns
        -------
        ndarray of bool
            Per pixel (an empty array with no frame).

        Examples
        --------
        >>> import numpy as np
        >>> history = FrameHistory(depth=6)
        >>> for k in range(6):
        ...     frame = np.full((10, 30, 3), 100, np.uint8)
        ...     frame[:, 5 * k:5 * k + 5] = 250      # crossing, 5 px a frame
        ...     history.push(frame)
        >>> settled = history.settled(gate=20.0, share=2 / 3)
        >>> [bool(settled[5, x]) for x in (2, 12, 27)]  # at the oldest, between, at the newest
        [False, True, False]
        >>> bool(history.settled(gate=20.0, share=2 / 3, ends=False)[5, 2])
        True
        >>> bool(history.still(gate=20.0)[5, 12])
        False
        """
        if not 0.5 < share <= 1.0:
            raise VisionError(f"share: expected a share in (0.5, 1], got {share}")
        still = self.still(gate)
        n = len(self._frames)
        if n < 3 or still.all():
            return still
        # only the pixels that changed: a median of every pixel costs a frame's budget
        changed = np.flatnonzero(~still)
        values = np.stack([f.reshape(still.size, -1)[changed]
                           for f in self._frames]).astype(np.int16)
        middle = np.median(values, axis=0)
        near = np.all(np.abs(values - middle) <= gate, axis=-1)
        ok = near.sum(axis=0) >= share * n
        if ends:
            ok &= near[0] & near[-1]
        out = still.copy()
        out.reshape(-1)[changed[ok]] = True
        return out

    def median(self) -> NDArray[np.uint8]:
        """The per-pixel median of the frames kept (the newest frame for one or two).

        Raises
        ------
        VisionError
            With no frame.
        """
        if not self._frames:
            raise VisionError("no frame to take a median of")
        if len(self._frames) < 3:
            return self._frames[-1].copy()
        return np.asarray(np.median(np.stack(self._frames), axis=0).astype(np.uint8))
