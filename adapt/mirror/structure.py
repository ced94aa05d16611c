"""The scene's structure as the synthetic camera sees it: which surface each pixel shows.

Appearance learning back-projects the real image onto the surfaces with the
camera pose as currently estimated, and a render of what it learned
reproduces the real image *whatever* that pose: a pose error is absorbed
into the textures, where no later comparison can see it.  The pose must be
right before the textures are learned, and before they are learned the
textures cannot be what aligns it.  What the geometry alone decides is the
*structure* of the image: where each surface lies.  :func:`face_labels`
gives that label image, with each obstacle's faces told apart (its sides
and top are lit differently, and the edges between them are structure too);
:mod:`adapt.vision.registration` registers it to the real image (the mirror
knows the surfaces, vision the images; the Scene Background schema joins
them).

Examples
--------
>>> from adapt.imagination import LABEL_OBSTACLE, Obstacle, Renderer, SceneSpec
>>> box = Obstacle("box", ((-0.3, 1.0), (0.3, 1.0), (0.3, 1.6), (-0.3, 1.6)), 0.4)
>>> cam = Camera.look_at(fx=200, fy=200, cx=80, cy=60, width=160, height=120,
...                      position=(0.8, -1.0, 1.2), look_at=(0.0, 1.3, 0.2))
>>> r = Renderer(SceneSpec(obstacles=(box,)), cam)
>>> split = face_labels(r.background.labels, r.surfaces, cam)
>>> faces = set(np.unique(split[r.background.labels == LABEL_OBSTACLE]).tolist())
>>> len(faces) >= 2 and all(f < 0 for f in faces)
True
"""

from __future__ import annotations

from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination import LABEL_BALL, LABEL_OBSTACLE, Surface

__all__ = ["face_labels"]


def face_labels(labels: NDArray[np.integer], surfaces: Sequence[Surface], camera: Camera
                ) -> NDArray[np.int32]:
    """``labels`` with each obstacle's faces told apart.

    The render gives one label to all faces of an obstacle, but its sides and
    top are lit differently, and the edges between them are structure too.
    Each face the camera sees the front of is drawn (its polygon projected)
    over its obstacle's pixels with a label of its own, ``-(1 + i)`` for the
    ``i``-th surface (faces of a convex obstacle seen from outside do not
    overlap in the image).  A face with a corner behind the camera keeps its
    obstacle's label.
    """
    out = np.asarray(labels, np.int32).copy()
    h, w = out.shape
    present = set(np.unique(out[::4, ::4]).tolist())
    for i, surface in enumerate(surfaces):
        if not (LABEL_OBSTACLE <= surface.label < LABEL_BALL) or surface.label not in present:
            continue
        if surface.polygon is None or not surface.seen_from(camera.position):
            continue
        corners = surface.to_world(surface.polygon)
        if camera.to_camera(corners)[:, 2].min() <= 1e-3:
            continue
        px = camera.project(corners)
        if not np.isfinite(px).all() or np.abs(px).max() > 4 * (w + h):
            continue
        poly = np.zeros((h, w), np.uint8)
        cv2.fillConvexPoly(poly, np.round(px * 256).astype(np.int32), 1, cv2.LINE_8, 8)
        out[(poly != 0) & (labels == surface.label)] = -(1 + i)
    return out


