"""Seeing a PyBullet reality: a pinhole camera as PyBullet's matrices, and a frame.

:func:`matrices` turns an :class:`~adapt.geometry.Camera` (intrinsics ``fx fy cx
cy``, any principal point, and its pose) into the column-major view and
projection matrices ``getCameraImage`` takes.  The projection is built from the
intrinsics, not from a field of view, so a point projects where
:meth:`Camera.project` puts it: TinyRenderer puts the centre of pixel column
``u`` at normalised device ``x = 2 u / W - 1`` and of row ``v`` at
``y = 1 - 2 (v + 1) / H`` (measured: sphere centroids land within 0.1 px of
``Camera.project``, ``tests/reality/test_bullet.py``).

:func:`render` takes a frame with PyBullet's CPU renderer (TinyRenderer) in the
drawn light; it returns the RGB image and the segmentation (the body id seen at
each pixel, -1 for nothing).

Examples
--------
>>> from adapt.geometry import Camera
>>> cam = Camera.look_at(fx=100, fy=100, cx=39.5, cy=29.5, width=80, height=60,
...                      position=(0, -2, 1), look_at=(0, 0, 0))
>>> view, projection = matrices(cam)
>>> len(view), len(projection), round(projection[0], 3)
(16, 16, 2.5)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.reality.bullet.client import Client
from adapt.reality.bullet.draw import LookDraw

__all__ = ["matrices", "render", "NEAR", "FAR"]

#: Near and far clipping distances, metres.
NEAR = 0.02
FAR = 100.0


def matrices(camera: Camera, near: float = NEAR, far: float = FAR) -> tuple[list[float], list[float]]:
    """``(view, projection)``: 16 floats each, column-major (OpenGL's order)."""
    flip = np.diag([1.0, -1.0, -1.0])  # OpenCV's camera axes (x right, y down, z ahead) to OpenGL's
    rot = flip @ np.asarray(camera.rotation, float)
    view = np.eye(4)
    view[:3, :3] = rot
    view[:3, 3] = -rot @ np.asarray(camera.position, float)
    w, h = camera.width, camera.height
    proj = np.zeros((4, 4))
    proj[0, 0] = 2.0 * camera.fx / w
    proj[0, 2] = 1.0 - 2.0 * camera.cx / w
    proj[1, 1] = 2.0 * camera.fy / h
    proj[1, 2] = 2.0 * (camera.cy + 1.0) / h - 1.0
    proj[2, 2] = -(far + near) / (far - near)
    proj[2, 3] = -2.0 * far * near / (far - near)
    proj[3, 2] = -1.0
    return view.T.reshape(-1).tolist(), proj.T.reshape(-1).tolist()


def render(client: Client, camera: Camera, look: LookDraw
           ) -> tuple[NDArray[np.uint8], NDArray[np.int32]]:
    """``(rgb, segmentation)`` of the scene through ``camera`` in ``look``'s light."""
    view, projection = matrices(camera)
    w, h = camera.width, camera.height
    out = client.getCameraImage(
        w, h, viewMatrix=view, projectionMatrix=projection,
        lightDirection=list(look.light_direction), lightColor=list(look.light_color),
        lightAmbientCoeff=look.ambient, lightDiffuseCoeff=look.diffuse,
        lightSpecularCoeff=look.specular, shadow=int(look.shadows),
        renderer=client.ER_TINY_RENDERER)
    rgba = np.asarray(out[2], np.uint8).reshape(h, w, 4)
    seg = np.asarray(out[4], np.int32).reshape(h, w)
    return np.ascontiguousarray(rgba[:, :, :3]), seg
