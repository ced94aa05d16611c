"""Exact ray casting of planar faces: the reference renderer.

Every pixel's ray (through the pixel centre) is intersected with each face's
plane; the nearest hit inside the face's polygon wins (a depth buffer of
camera ``z``) and is coloured by sampling the face's texture at the exact
hit point, with a mip level chosen per pixel from the texel footprint.  This
is slow (tens of milliseconds per 640x480 background) but has no
approximation beyond bilinear texture filtering, so the fast planar-warp
renderer (:mod:`~adapt.imagination.backdrop`) is tested against it.  The robot
(a prism that moves) is drawn with it every frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination.appearance import Atlas, level_matrix
from adapt.imagination.scene import Color
from adapt.imagination.surface import LIGHT
from adapt.imagination.texture import Texture

__all__ = ["Face", "prism_faces", "draw_face", "clip_near", "pixel_bbox", "NEAR", "FAR"]

FloatArray = NDArray[np.float64]

#: Near clipping distance in metres (camera z).
NEAR = 0.01
#: A floor without extent reaches this far from the camera.
FAR = 200.0


@dataclass(frozen=True, slots=True, eq=False)
class Face:
    """A planar convex face: points ``origin + s*u + t*v`` with ``(s, t)`` in ``polygon``.

    ``texel`` maps ``(s, t, 1)`` to level-0 texel coordinates of ``texture``
    (``None`` paints ``color``); ``shade`` multiplies the colour; ``atlas``
    is an appearance drawn (unshaded) over the part of the face it covers.
    """

    origin: FloatArray
    u: FloatArray
    v: FloatArray
    polygon: tuple[tuple[float, float], ...]
    color: Color
    texture: Texture | None
    texel: FloatArray | None
    label: int
    shade: float
    two_sided: bool = False
    atlas: Atlas | None = None


def pixel_bbox(pc: FloatArray, cam: Camera) -> tuple[int, int, int, int] | None:
    """Pixel bounding box ``(x0, y0, x1, y1)`` (exclusive end, one pixel of margin) of points
    in camera coordinates in front of the camera, clipped to the image; ``None`` when empty."""
    px = pc[:, 0] / pc[:, 2] * cam.fx + cam.cx
    py = pc[:, 1] / pc[:, 2] * cam.fy + cam.cy
    x0 = max(int(math.floor(px.min())) - 1, 0)
    y0 = max(int(math.floor(py.min())) - 1, 0)
    x1 = min(int(math.ceil(px.max())) + 2, cam.width)
    y1 = min(int(math.ceil(py.max())) + 2, cam.height)
    if x0 >= x1 or y0 >= y1:
        return None
    return x0, y0, x1, y1


def clip_near(points: FloatArray, near: float = NEAR) -> FloatArray:
    """Clip a convex polygon (camera coordinates, ``(N, 3)``) to ``z >= near``."""
    out: list[FloatArray] = []
    n = len(points)
    for i in range(n):
        p, q = points[i], points[(i + 1) % n]
        pin, qin = p[2] >= near, q[2] >= near
        if pin:
            out.append(p)
        if pin != qin:
            f = (near - p[2]) / (q[2] - p[2])
            out.append(p + f * (q - p))
    return np.array(out).reshape(-1, 3)


def _shade(u: FloatArray, v: FloatArray, two_sided: bool) -> float:
    cos = float(np.cross(u, v) @ LIGHT)
    if two_sided:
        cos = abs(cos)
    return 0.6 + 0.4 * max(cos, 0.0)


def prism_faces(
    polygon: Sequence[tuple[float, float]],
    height: float,
    color: Color,
    label: int,
    camera_position: FloatArray,
) -> list[Face]:
    """The untextured faces of a vertical prism over a CCW convex polygon that
    face the camera (the robot's)."""
    faces: list[Face] = []
    c = camera_position
    ez = np.array([0.0, 0.0, 1.0])
    n = len(polygon)
    for k in range(n):
        a = np.array([*polygon[k], 0.0])
        b = np.array([*polygon[(k + 1) % n], 0.0])
        d = b - a
        length = float(np.linalg.norm(d))
        u = d / length
        outward = np.array([u[1], -u[0], 0.0])
        if outward @ (c - a) <= 0:
            continue
        faces.append(
            Face(a, u, ez, ((0.0, 0.0), (length, 0.0), (length, height), (0.0, height)),
                 color, None, None, label, _shade(u, ez, False))
        )
    if c[2] > height:
        ex, ey = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
        faces.append(Face(np.array([0.0, 0.0, height]), ex, ey, tuple(polygon), color, None,
                          None, label, _shade(ex, ey, False)))
    return faces


def face_bbox(face: Face, cam: Camera) -> tuple[int, int, int, int] | None:
    """Pixel bbox ``(x0, y0, x1, y1)`` (exclusive end) of a face, or None."""
    pts = np.array([face.origin + s * face.u + t * face.v for s, t in face.polygon])
    pc = clip_near(cam.to_camera(pts), NEAR)
    if len(pc) == 0:
        return None
    return pixel_bbox(pc, cam)


def draw_face(
    face: Face,
    cam: Camera,
    image: NDArray[np.uint8],
    labels: NDArray[np.int32],
    depth: NDArray[np.float32],
) -> tuple[int, int, int, int] | None:
    """Ray-cast ``face`` into ``image``, ``labels`` and ``depth`` (camera z);
    return the pixel box ``(x0, y0, x1, y1)`` it drew in, or ``None``."""
    box = face_bbox(face, cam)
    if box is None:
        return None
    x0, y0, x1, y1 = box
    r = cam.rotation
    o = r @ (face.origin - cam.position)
    uc, vc = r @ face.u, r @ face.v
    n = np.cross(uc, vc)
    dx = ((np.arange(x0, x1, dtype=np.float64) - cam.cx) / cam.fx)[None, :]
    dy = ((np.arange(y0, y1, dtype=np.float64) - cam.cy) / cam.fy)[:, None]
    denom = n[0] * dx + n[1] * dy + n[2]
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = (n @ o) / denom
    # Camera-frame point lam * (dx, dy, 1) minus the origin, in face coordinates.
    px, py, pz = lam * dx - o[0], lam * dy - o[1], lam - o[2]
    s = uc[0] * px + uc[1] * py + uc[2] * pz
    t = vc[0] * px + vc[1] * py + vc[2] * pz
    inside = (lam > NEAR) & np.isfinite(lam)
    inside &= _in_polygon(face.polygon, s, t)
    dview = depth[y0:y1, x0:x1]
    inside &= lam < dview
    if not inside.any():
        return None
    if face.texture is None or face.texel is None:
        bgr = np.array(face.color[::-1], np.float64) * face.shade
        colors = np.broadcast_to(bgr, (*s.shape, 3)).copy()
    else:
        colors = _sample(face.texture.levels, face.texel, s, t, inside, wrap=True)[..., :3]
        colors *= face.shade
    if face.atlas is not None:
        over = inside & _in_polygon(face.atlas.polygon, s, t)
        if over.any():
            got = _sample(face.atlas.levels, face.atlas.face_to_texel, s, t, over, wrap=False)
            colors[over] = got[..., :3][over]
    iview = image[y0:y1, x0:x1]
    iview[inside] = np.clip(np.round(colors[inside]), 0, 255).astype(np.uint8)
    labels[y0:y1, x0:x1][inside] = face.label
    dview[inside] = lam[inside]
    return box


def _in_polygon(poly: Sequence[tuple[float, float]], s: FloatArray, t: FloatArray) -> NDArray[np.bool_]:
    inside = np.ones(s.shape, bool)
    for k in range(len(poly)):
        (sa, ta), (sb, tb) = poly[k], poly[(k + 1) % len(poly)]
        inside &= (sb - sa) * (t - ta) - (tb - ta) * (s - sa) >= 0
    return inside


def _sample(
    levels: Sequence[NDArray[np.uint8]],
    texel: FloatArray,
    s: FloatArray,
    t: FloatArray,
    mask: NDArray[np.bool_],
    *,
    wrap: bool,
) -> FloatArray:
    """Colours (float, as many channels as the levels) at face coordinates
    ``(s, t)`` through the affine ``texel`` map, mip-mapped per pixel; a
    wrapping texture or a clamped atlas."""
    ss, tt = np.where(mask, s, 0.0), np.where(mask, t, 0.0)
    u = texel[0, 0] * ss + texel[0, 1] * tt + texel[0, 2]
    v = texel[1, 0] * ss + texel[1, 1] * tt + texel[1, 2]
    # Texels per pixel from the screen-space derivatives; pick a mip level.
    if u.shape[0] > 1 and u.shape[1] > 1:
        du_y, du_x = np.gradient(u)
        dv_y, dv_x = np.gradient(v)
        foot = np.maximum(np.hypot(du_x, dv_x), np.hypot(du_y, dv_y))
    else:
        foot = np.ones_like(u)
    level = np.clip(np.floor(np.log2(np.maximum(foot, 1.0))), 0, len(levels) - 1)
    level = level.astype(np.intp)
    channels = levels[0].shape[2]
    out = np.zeros((*u.shape, channels), np.float64)
    border = cv2.BORDER_WRAP if wrap else cv2.BORDER_REPLICATE
    for k in np.unique(level[mask]):
        img = levels[int(k)]
        lh, lw = img.shape[:2]
        m = level_matrix(int(k))
        mx = m[0, 0] * u + m[0, 2]
        my = m[1, 1] * v + m[1, 2]
        if wrap:
            mx, my = np.mod(mx, lw), np.mod(my, lh)
        sampled = cv2.remap(img, mx.astype(np.float32), my.astype(np.float32), cv2.INTER_LINEAR,
                            borderMode=border)
        sel = mask & (level == k)
        out[sel] = sampled[sel]
    return out
