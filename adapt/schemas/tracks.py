"""Difference regions followed from frame to frame.

The MMD finds regions anew in every frame; the rules need to know that the
region in front of them has been there for a while (an object, not sensor
noise) and which schema, if any, owns it.  :class:`RegionTracker` matches
each frame's regions to the tracks of the previous frames (greedily, by
bounding-box overlap, then by centroid distance), keeps a track's id and age
while it is seen, lets it miss a few frames, and remembers the schema a
track was assigned to.

Examples
--------
>>> import numpy as np
>>> from adapt.vision.regions import Region
>>> def region(x, y):
...     return Region((x, y, 10, 10), (x + 5.0, y + 5.0), 100, 50.0, np.ones((10, 10), bool))
>>> t = RegionTracker()
>>> [(k.id, k.age) for k in t.update([region(10, 10)], frame=0)]
[(1, 1)]
>>> [(k.id, k.age) for k in t.update([region(13, 11), region(60, 60)], frame=1)]
[(1, 2), (2, 1)]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

from adapt.vision.regions import Region

__all__ = ["Track", "RegionTracker", "MAX_MISSES", "MIN_IOU"]

#: A track not matched for more than this many frames is dropped.
MAX_MISSES = 2
#: Boxes overlapping at least this much (intersection over union) are the same region.
MIN_IOU = 0.2

BBox = tuple[int, int, int, int]


@dataclass(slots=True, eq=False)
class Track:
    """A region followed over frames.

    Attributes
    ----------
    id : int
        Stable while the track lives (1, 2, ...; never reused).
    region : Region
        The latest matching region.
    age : int
        Frames since it was first seen (1 on its first frame).
    misses : int
        Consecutive frames without a match (0 when seen this frame).
    owner : str or None
        The schema the track was assigned to.
    first_frame : int
    """

    id: int
    region: Region
    first_frame: int
    age: int = 1
    misses: int = 0
    owner: str | None = None
    history: list[tuple[float, float]] = field(default_factory=list)

    @property
    def seen(self) -> bool:
        """Matched in the latest frame."""
        return self.misses == 0


def iou(a: BBox, b: BBox) -> float:
    """Intersection over union of two ``(x, y, w, h)`` boxes.

    Examples
    --------
    >>> iou((0, 0, 10, 10), (5, 0, 10, 10))
    0.3333333333333333
    """
    ix = max(0, min(a[0] + a[2], b[0] + b[2]) - max(a[0], b[0]))
    iy = max(0, min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1]))
    inter = ix * iy
    union = a[2] * a[3] + b[2] * b[3] - inter
    return inter / union if union > 0 else 0.0


class RegionTracker:
    """Follows regions over frames (see the module docstring)."""

    def __init__(self, *, max_misses: int = MAX_MISSES, min_iou: float = MIN_IOU) -> None:
        self.max_misses = max_misses
        self.min_iou = min_iou
        self.tracks: list[Track] = []
        self._next = 1

    def update(self, regions: Sequence[Region], frame: int) -> list[Track]:
        """Match this frame's regions; returns the tracks seen in this frame, in region order."""
        pairs: list[tuple[float, int, int]] = []
        for ti, t in enumerate(self.tracks):
            tb = t.region.bbox
            reach = max(tb[2], tb[3]) * (1.0 + t.misses)
            for ri, r in enumerate(regions):
                o = iou(tb, r.bbox)
                if o >= self.min_iou:
                    pairs.append((2.0 + o, ti, ri))
                    continue
                d = math.dist(t.region.centroid, r.centroid)
                if d <= reach:
                    pairs.append((1.0 - d / (reach + 1e-9), ti, ri))
        pairs.sort(reverse=True)
        used_t: set[int] = set()
        match: dict[int, int] = {}
        for _, ti, ri in pairs:
            if ti in used_t or ri in match:
                continue
            used_t.add(ti)
            match[ri] = ti
        out: list[Track] = []
        for ri, r in enumerate(regions):
            if ri in match:
                t = self.tracks[match[ri]]
                t.region = r
                t.age += 1
                t.misses = 0
            else:
                t = Track(self._next, r, frame)
                self._next += 1
                self.tracks.append(t)
            t.history.append(r.centroid)
            if len(t.history) > 8:
                del t.history[0]
            out.append(t)
        seen = {id(t) for t in out}
        for t in self.tracks:
            if id(t) not in seen:
                t.misses += 1
        self.tracks = [t for t in self.tracks if t.misses <= self.max_misses]
        return out

    def get(self, track_id: int) -> Track | None:
        """The live track with ``track_id``."""
        for t in self.tracks:
            if t.id == track_id:
                return t
        return None

    def assign(self, track_id: int, owner: str) -> bool:
        """Give a track to a schema; False when no such track lives."""
        t = self.get(track_id)
        if t is None:
            return False
        t.owner = owner
        return True
