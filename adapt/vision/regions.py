"""Difference regions: what in the MMD image ``I_d`` deserves attention.

:func:`find_regions` thresholds ``I_d``, cleans the binary image with a
morphological opening (removes specks) and closing (fills pinholes), and
returns its connected components as frozen :class:`Region` records, largest
first.  :func:`label_regions` marks each region *expected* when it overlaps a
region a perceptual schema already monitors, and *unexpected* otherwise
(:func:`best_overlap` says which monitored box explains it).

The smallest area and the cleaning kernel are given for a 640x480 image and
scaled with the difference image's size (:mod:`~adapt.vision.scale`), so the
same scene gives the same regions, scaled, at any resolution.
:func:`to_input` maps regions found on a working image (an MMD of a large
image) back to the input's pixels.

Examples
--------
>>> import numpy as np
>>> d = np.zeros((60, 80), np.float32)
>>> d[10:20, 30:50] = 90.0
>>> (r,) = find_regions(d)
>>> r.bbox, r.centroid, r.area, r.mean_difference
((30, 10, 20, 10), (39.5, 14.5), 200, 90.0)
>>> [x.expected for x in label_regions([r], [(25, 5, 20, 20)])]
[True]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.vision.scale import WorkingFrame, image_scale

__all__ = [
    "Region",
    "find_regions",
    "label_regions",
    "best_overlap",
    "to_input",
    "THRESHOLD",
    "MIN_AREA",
    "MIN_OVERLAP",
    "OPEN_SIZE",
]

#: ``I_d`` above this (grey levels, 0-255) is difference.
THRESHOLD = 30.0
#: Components smaller than this (pixels at 640x480; scaled with the image's
#: area) are dropped.
MIN_AREA = 40
#: A region is expected when at least this fraction of its bounding box lies
#: inside a monitored box.
MIN_OVERLAP = 0.3
#: Side of the square structuring element of the opening (closing uses 2x+1),
#: pixels at 640x480 (scaled with the image).
OPEN_SIZE = 3

BBox = tuple[int, int, int, int]


@dataclass(frozen=True, slots=True, eq=False)
class Region:
    """One connected region of difference.

    Attributes
    ----------
    bbox : (x, y, w, h)
        Bounding box in pixels.
    centroid : (x, y)
        Centre of mass of the region's pixels.
    area : int
        Number of pixels.
    mean_difference : float
        Mean ``I_d`` over the region, grey levels.
    silhouette : (h, w) bool ndarray
        The region's pixels inside ``bbox``.
    expected : bool
        Whether a monitored region explains it (see :func:`label_regions`).
    """

    bbox: BBox
    centroid: tuple[float, float]
    area: int
    mean_difference: float
    silhouette: NDArray[np.bool_] = field(repr=False)
    expected: bool = False

    def to_mask(self, shape: tuple[int, ...]) -> NDArray[np.bool_]:
        """The region as a full-size boolean image of ``shape`` (``(H, W)``)."""
        out = np.zeros(shape[:2], bool)
        x, y, w, h = self.bbox
        out[y : y + h, x : x + w] = self.silhouette
        return out

    def as_dict(self) -> dict[str, object]:
        """The JSON form: ``bbox``, ``centroid``, ``area``, ``mean_difference``, ``expected``."""
        return {
            "bbox": list(self.bbox),
            "centroid": [round(self.centroid[0], 2), round(self.centroid[1], 2)],
            "area": self.area,
            "mean_difference": round(self.mean_difference, 2),
            "expected": self.expected,
        }


def find_regions(
    difference: NDArray,
    *,
    threshold: float = THRESHOLD,
    min_area: int | None = None,
    open_size: int | None = None,
    close: bool = True,
) -> tuple[Region, ...]:
    """Connected regions of ``difference > threshold``, largest first.

    Parameters
    ----------
    difference : (H, W) ndarray
        An MMD image (``MMDResult.difference``), grey levels.
    threshold : float
        Difference level that counts (grey levels; not scaled).
    min_area : int, optional
        Smallest region kept, pixels (after cleaning); :data:`MIN_AREA` scaled
        with the image's area by default.
    open_size : int, optional
        Opening kernel side; 0 or 1 disables cleaning; :data:`OPEN_SIZE`
        scaled with the image by default.
    close : bool
        Also close the opened image (fills pinholes; joins parts less than
        about ``open_size`` apart).  An object schema looking for one blob in
        a small window opens only.
    """
    d = np.asarray(difference)
    if d.ndim != 2:
        raise ValueError(f"difference must be a 2-D image, got shape {d.shape}")
    s = image_scale(d.shape)
    if min_area is None:
        min_area = max(1, int(math.floor(MIN_AREA * s * s + 0.5)))
    if open_size is None:
        open_size = max(1, int(math.floor(OPEN_SIZE * s + 0.5)))
    binary = (d > threshold).astype(np.uint8)
    if open_size > 1:
        k = cv2.getStructuringElement(cv2.MORPH_RECT, (open_size, open_size))
        binary = cv2.morphologyEx(binary, cv2.MORPH_OPEN, k)  # type: ignore[assignment]
        if close:
            k2 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * open_size + 1,) * 2)
            binary = cv2.morphologyEx(binary, cv2.MORPH_CLOSE, k2)  # type: ignore[assignment]
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(binary, connectivity=8)
    found = []
    for i in range(1, n):
        x, y, w, h, area = (int(v) for v in stats[i])
        if area < min_area:
            continue
        sil = labels[y : y + h, x : x + w] == i
        mean = float(d[y : y + h, x : x + w][sil].mean())
        cx, cy = (float(v) for v in centroids[i])
        found.append(Region((x, y, w, h), (cx, cy), area, mean, sil))
    found.sort(key=lambda r: -r.area)
    return tuple(found)


def _overlap(region: BBox, box: BBox) -> float:
    x, y, w, h = region
    bx, by, bw, bh = box
    ix = max(0, min(x + w, bx + bw) - max(x, bx))
    iy = max(0, min(y + h, by + bh) - max(y, by))
    return ix * iy / max(w * h, 1)


def best_overlap(bbox: BBox, boxes: Sequence[BBox], *,
                 min_overlap: float = MIN_OVERLAP) -> int | None:
    """The index of the box in ``boxes`` that holds the largest fraction of ``bbox`` (the
    first of equals), when that fraction is at least ``min_overlap``; None otherwise.

    Examples
    --------
    >>> best_overlap((0, 0, 10, 10), [(8, 0, 10, 10), (5, 0, 10, 10)])
    1
    >>> best_overlap((0, 0, 10, 10), [(8, 0, 10, 10)]) is None
    True
    """
    best, found = 0.0, None
    for i, box in enumerate(boxes):
        share = _overlap(bbox, box)
        if share > best:
            best, found = share, i
    return found if best >= min_overlap else None


def label_regions(
    regions: Sequence[Region],
    monitored: Sequence[Sequence[float]],
    *,
    min_overlap: float = MIN_OVERLAP,
) -> tuple[Region, ...]:
    """Copies of ``regions`` with ``expected`` set.

    Parameters
    ----------
    regions : sequence of Region
    monitored : sequence of (x, y, w, h)
        Boxes perceptual schemas already watch (for example a tracked ball's
        predicted box).
    min_overlap : float
        Fraction of a region's bounding box that must lie in one monitored box
        for the region to be expected.
    """
    boxes = [tuple(int(round(v)) for v in b) for b in monitored]
    for b in boxes:
        if len(b) != 4:
            raise ValueError(f"a monitored region must be (x, y, w, h), got {b}")
    return tuple(
        replace(r, expected=best_overlap(r.bbox, boxes, min_overlap=min_overlap) is not None)  # type: ignore[arg-type]
        for r in regions
    )


def to_input(regions: Sequence[Region], frame: WorkingFrame) -> tuple[Region, ...]:
    """Regions found on ``frame``'s working image, in the input image's pixels.

    The bounding box is scaled edge to edge, the centroid as a pixel centre,
    the area by both factors, and the silhouette is resized (nearest
    neighbour) to the new box; ``mean_difference`` and ``expected`` are kept.
    Without a reduction the regions are returned as they are.

    Examples
    --------
    >>> from adapt.vision.scale import working_frame
    >>> d = np.zeros((480, 640), np.float32)
    >>> d[100:120, 200:240] = 90.0
    >>> (r,) = to_input(find_regions(d), working_frame((960, 1280)))
    >>> r.bbox, r.centroid, r.area, r.silhouette.shape
    ((400, 200, 80, 40), (439.5, 219.5), 3200, (40, 80))
    """
    if not frame.reduces:
        return tuple(regions)
    fx, fy = frame.factor
    ih, iw = frame.input_shape
    out = []
    for r in regions:
        x, y, w, h = r.bbox
        x0, y0 = int(math.floor(x * fx + 0.5)), int(math.floor(y * fy + 0.5))
        x1 = min(iw, int(math.floor((x + w) * fx + 0.5)))
        y1 = min(ih, int(math.floor((y + h) * fy + 0.5)))
        bw, bh = max(1, x1 - x0), max(1, y1 - y0)
        sil = cv2.resize(r.silhouette.astype(np.uint8), (bw, bh), interpolation=cv2.INTER_NEAREST)
        (cx, cy) = frame.to_input([r.centroid])[0]
        out.append(
            replace(
                r,
                bbox=(x0, y0, bw, bh),
                centroid=(float(cx), float(cy)),
                area=int(round(r.area * fx * fy)),
                silhouette=sil.astype(bool),
            )
        )
    return tuple(out)
