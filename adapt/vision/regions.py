"""Difference regions: what in the MMD image ``I_d`` deserves attention.

:func:`find_regions` thresholds ``I_d``, cleans the binary image with a
morphological opening (removes specks) and closing (fills pinholes), and
returns its connected components as frozen :class:`Region` records, largest
first.  :func:`label_regions` marks each region *expected* when it overlaps a
region a perceptual schema already monitors, and *unexpected* otherwise.

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

from dataclasses import dataclass, field, replace
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["Region", "find_regions", "label_regions", "THRESHOLD", "MIN_AREA", "MIN_OVERLAP"]

#: ``I_d`` above this (grey levels, 0-255) is difference.
THRESHOLD = 30.0
#: Components smaller than this (pixels) are dropped.
MIN_AREA = 40
#: A region is expected when at least this fraction of its bounding box lies
#: inside a monitored box.
MIN_OVERLAP = 0.3
#: Side of the square structuring element of the opening (closing uses 2x+1).
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
    min_area: int = MIN_AREA,
    open_size: int = OPEN_SIZE,
) -> tuple[Region, ...]:
    """Connected regions of ``difference > threshold``, largest first.

    Parameters
    ----------
    difference : (H, W) ndarray
        An MMD image (``MMDResult.difference``), grey levels.
    threshold : float
        Difference level that counts.
    min_area : int
        Smallest region kept, pixels (after cleaning).
    open_size : int
        Opening kernel side; 0 or 1 disables cleaning.
    """
    d = np.asarray(difference)
    if d.ndim != 2:
        raise ValueError(f"difference must be a 2-D image, got shape {d.shape}")
    binary = (d > threshold).astype(np.uint8)
    if open_size > 1:
        k = cv2.getStructuringElement(cv2.MORPH_RECT, (open_size, open_size))
        binary = cv2.morphologyEx(binary, cv2.MORPH_OPEN, k)  # type: ignore[assignment]
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
        replace(r, expected=any(_overlap(r.bbox, b) >= min_overlap for b in boxes))  # type: ignore[arg-type]
        for r in regions
    )
