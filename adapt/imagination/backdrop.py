"""The static background of a scene: its surfaces, their appearances, and
a fast renderer for any camera pose.

A :class:`Backdrop` is built once per scene.  It holds the scene's
:class:`~adapt.imagination.surface.Surface` list, the prepared textures (mip
pyramids, loaded once per texture file) and the appearance overrides set at
run time.  Every renderer of the scene shares it (see
:meth:`Renderer.with_camera <adapt.imagination.render.Renderer.with_camera>`).

:meth:`Backdrop.render` draws the background for a camera.  Each surface is a
plane, so the map from pixels to its texture is a homography: a surface is
drawn as one perspective warp of its texture (``cv2.warpPerspective``) and
composited with a depth test.  The inverse depth ``1/z`` of a plane is affine
in pixel coordinates, so the depth test costs one comparison per pixel.
Anti-aliasing of the texture comes from mip-mapping: the pixel-to-texel
footprint is evaluated on an 8-pixel grid and each band of the surface with
the same mip level is warped from that level, as the reference ray-caster
does per pixel.  About 2-5 ms at 640x480 on the bundled scene.

``exact=True`` uses the reference instead: every pixel's ray intersected with
every plane (:mod:`~adapt.imagination.raycast`), tens of milliseconds.  The
two agree on the label of all but edge pixels and on colour within a grey
level or two on average (``tests/imagination/test_backdrop.py``).

Examples
--------
>>> from adapt.geometry import Camera
>>> from adapt.imagination.scene import SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 2), (2, 2), height=1.0, texture="builtin:brick"),))
>>> cam = Camera.look_at(fx=300, fy=300, cx=159.5, cy=119.5, width=320, height=240,
...                      position=(0, -1, 0.5), look_at=(0, 2, 0.3))
>>> backdrop = Backdrop(scene)
>>> image, labels, depth = backdrop.render(cam)
>>> exact = backdrop.render(cam, exact=True)
>>> bool((labels == exact[1]).mean() > 0.99)
True
>>> _ = backdrop.set_appearance("north", np.full((100, 400, 3), 255, np.uint8))
>>> white = backdrop.render(cam)[0][labels == 1000]
>>> bool((white == 255).all())
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping, Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import ImaginationError
from adapt.geometry import Camera
from adapt.imagination.appearance import (
    Appearance,
    Atlas,
    level_matrix,
    prepare_atlas,
    texel_matrix,
)
from adapt.imagination.raycast import FAR, NEAR, Face, draw_face
from adapt.imagination.scene import SceneSpec
from adapt.imagination.surface import Surface, check_extent, scene_surfaces
from adapt.imagination.texture import Texture, load_texture

__all__ = ["Backdrop", "Background", "SKY_HORIZON", "SKY_TOP"]

FloatArray = NDArray[np.float64]

#: Sky colour at the horizon and at the top (BGR).
SKY_HORIZON = np.array([235.0, 225.0, 215.0])
SKY_TOP = np.array([210.0, 170.0, 120.0])

#: Grid step, in pixels, on which the mip level of a surface is evaluated.
_GRID = 8
#: Margin, in pixels, of the frustum that surfaces are clipped to.
_MARGIN = 2.0
#: Sub-pixel bits of the polygon rasterizer.
_SHIFT = 8

#: What a background render is: BGR image, labels and depth (camera z, inf for sky).
Background = tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float32]]


@dataclass(frozen=True, slots=True, eq=False)
class _Prepared:
    """Pose-independent data of one surface."""

    surface: Surface
    origin: FloatArray
    u: FloatArray
    v: FloatArray
    normal: FloatArray
    texture: Texture | None
    texel: FloatArray | None
    shade: float
    fill: tuple[float, float, float, float]
    corners: FloatArray | None  # world corners of the polygon (None: unbounded)

    def seen_from(self, c: FloatArray) -> bool:
        """As :meth:`Surface.seen_from`, without allocating."""
        d = float(self.normal @ (c - self.origin))
        return d > 1e-9 or (self.surface.two_sided and d < -1e-9)

    def world(self, poly: Sequence[tuple[float, float]]) -> FloatArray:
        st = np.asarray(poly, dtype=np.float64)
        return self.origin + st[:, :1] * self.u + st[:, 1:] * self.v


def _prepare(surface: Surface) -> _Prepared:
    texture = load_texture(surface.texture) if surface.texture is not None else None
    shade = surface.shade
    b, g, r = (min(round(c * shade), 255) for c in surface.color[::-1])
    origin, u, v = np.array(surface.origin), np.array(surface.u), np.array(surface.v)
    corners = None
    if surface.polygon is not None:
        st = np.asarray(surface.polygon, dtype=np.float64)
        corners = origin + st[:, :1] * u + st[:, 1:] * v
    return _Prepared(surface, origin, u, v, np.cross(u, v), texture, texel_matrix(surface), shade,
                     (float(b), float(g), float(r), 255.0), corners)


class Backdrop:
    """The static surfaces of a scene with their textures and appearances.

    Parameters
    ----------
    scene : SceneSpec
        Only its floor, walls and obstacles are used.

    Attributes
    ----------
    surfaces : tuple of Surface
        Every static surface (:func:`~adapt.imagination.surface.scene_surfaces`).
    version : int
        Increases with every appearance change; renderers cache a background
        per pose and version.
    """

    def __init__(self, scene: SceneSpec) -> None:
        self.scene = scene
        self.surfaces = scene_surfaces(scene)
        self._index = {s.name: i for i, s in enumerate(self.surfaces)}
        self._prepared = tuple(_prepare(s) for s in self.surfaces)
        self._appearances: dict[str, Appearance] = {}
        self._atlases: dict[str, Atlas] = {}
        self.version = 0

    # -- surfaces and appearances -----------------------------------------------

    def surface(self, name: str) -> Surface:
        """The surface called ``name``."""
        try:
            return self.surfaces[self._index[name]]
        except KeyError:
            raise ImaginationError(
                f"surface: no surface called {name!r}; surfaces: {list(self._index)}"
            ) from None

    @property
    def appearances(self) -> Mapping[str, Appearance]:
        """The appearance overrides in force, by surface name (read-only)."""
        return MappingProxyType(self._appearances)

    def set_appearance(
        self,
        surface: str,
        image: ArrayLike | Appearance,
        mask: ArrayLike | None = None,
        *,
        extent: Sequence[float] | None = None,
        aligned: bool = False,
    ) -> Appearance:
        """Draw ``image`` on ``surface`` where ``mask`` is valid, from now on.

        Parameters
        ----------
        surface : str
            A surface name (:attr:`surfaces`).
        image : (H, W, 3) uint8 ndarray or Appearance
            The surface's look in its own coordinates (``docs/conventions.md``).
        mask : (H, W) ndarray, optional
            Valid pixels (non-zero); default all.  Elsewhere the scenario's
            texture or colour shows.
        extent : (s_min, t_min, s_max, t_max), optional
            Face coordinates the image covers; default the surface's polygon
            (required for a floor without extent).
        aligned : bool
            Mip levels of 2 x 2 averages, exact where the renderer samples
            them (for an appearance learned from a camera; see
            :class:`~adapt.imagination.appearance.Appearance`).

        Returns the :class:`Appearance` stored.  Its preparation (one warp of
        the scenario's texture and a mip pyramid, at the image's resolution)
        happens here, so the next render costs what any render costs.
        """
        target = self.surface(surface)
        if isinstance(image, Appearance):
            if mask is not None or extent is not None or aligned:
                raise ImaginationError(
                    "image: an Appearance carries its own mask, extent and alignment; pass none"
                )
            look = image
        else:
            look = Appearance(image, mask, target._extent_or(
                None if extent is None else check_extent(extent)), aligned)
        atlas = prepare_atlas(target, look)
        self._appearances[surface] = look
        if atlas is None:
            self._atlases.pop(surface, None)
        else:
            self._atlases[surface] = atlas
        self.version += 1
        return look

    def clear_appearance(self, surface: str | None = None) -> None:
        """Return ``surface`` (default: every surface) to the scenario's look."""
        if surface is None:
            self._appearances.clear()
            self._atlases.clear()
        else:
            self.surface(surface)
            self._appearances.pop(surface, None)
            self._atlases.pop(surface, None)
        self.version += 1

    # -- rendering ----------------------------------------------------------------

    def render(self, camera: Camera, *, exact: bool = False) -> Background:
        """The background seen by ``camera``: BGR image, labels and depth.

        ``exact`` ray-casts every pixel (the slow reference) instead of
        warping each surface.
        """
        if exact:
            return self._render_exact(camera)
        return self._render_fast(camera)

    def faces(self, camera: Camera) -> list[Face]:
        """The surfaces ``camera`` can see the drawn side of, as ray-casting faces."""
        c = camera.position
        out = []
        for p in self._prepared:
            s = p.surface
            if not s.seen_from(c):
                continue
            poly = s.polygon if s.polygon is not None else _far_square(c)
            out.append(Face(p.origin, p.u, p.v, poly, s.color, p.texture, p.texel, s.label,
                            p.shade, s.two_sided, self._atlases.get(s.name)))
        return out

    def _render_exact(self, cam: Camera) -> Background:
        h, w = cam.height, cam.width
        image = np.empty((h, w, 3), np.uint8)
        image[:] = _sky(cam).astype(np.uint8)[:, None, :]
        labels = np.zeros((h, w), np.int32)
        depth = np.full((h, w), np.inf, np.float32)
        for face in self.faces(cam):
            draw_face(face, cam, image, labels, depth)
        return image, labels, depth

    def _render_fast(self, cam: Camera) -> Background:
        h, w = cam.height, cam.width
        sky = np.zeros((h, 1, 4), np.uint8)
        sky[:, 0, :3] = _sky(cam).astype(np.uint8)
        image = np.asarray(cv2.resize(sky, (w, h), interpolation=cv2.INTER_NEAREST),  # a fast
                           np.uint8)  # broadcast of the sky column
        labels = np.zeros((h, w), np.int32)
        invz = np.zeros((h, w), np.float32)
        scratch = np.empty((h, w, 4), np.uint8)  # per render: renders may run in threads
        xs = np.arange(w, dtype=np.float32)
        ys = np.arange(h, dtype=np.float32)
        c = cam.position
        frustum = _frustum(cam)
        for p in self._prepared:
            s = p.surface
            if not p.seen_from(c):
                continue
            corners = p.corners if p.corners is not None else p.world(_far_square(c))
            shape = _project(corners, cam, frustum)
            if shape is None:
                continue
            (x0, y0, x1, y1), pts = shape
            bw, bh = x1 - x0, y1 - y0
            vis = np.zeros((bh, bw), np.uint8)
            cv2.fillConvexPoly(vis, pts, 255, cv2.LINE_8, _SHIFT)
            # Inverse depth of the plane, affine in pixel coordinates.
            a, b, k = _inverse_depth(p, cam)
            face_invz = (np.float32(a) * xs[x0:x1])[None, :] + (np.float32(b) * ys[y0:y1]
                                                                  + np.float32(k))[:, None]
            zroi = invz[y0:y1, x0:x1]
            cv2.bitwise_and(vis, cv2.compare(face_invz, zroi, cv2.CMP_GT), dst=vis)
            if not cv2.countNonZero(vis):
                continue
            cv2.copyTo(face_invz, vis, zroi)
            _set(labels[y0:y1, x0:x1], s.label, vis)
            iroi = image[y0:y1, x0:x1]
            sroi = scratch[y0:y1, x0:x1]
            hom = _translation(-x0, -y0) @ s.homography(cam)  # face -> box pixels
            atlas = self._atlases.get(s.name)
            need = vis
            if atlas is not None:
                drawn = _draw_atlas(atlas, p, cam, (x0, y0), hom, vis, sroi, iroi)
                if drawn is not None:
                    need = np.asarray(cv2.bitwise_and(vis, cv2.bitwise_not(drawn)), np.uint8)
                    if not cv2.countNonZero(need):
                        continue
            if p.texture is None or p.texel is None:
                _set(iroi, p.fill, need)
            else:
                box = _warp_levels(p.texture.levels_bgra, p.texel, hom, need, sroi, wrap=True,
                                   tiled=p.texture.levels_tiled)
                if box is not None:
                    bx0, by0, bx1, by1 = box
                    part = sroi[by0:by1, bx0:bx1]
                    cv2.convertScaleAbs(part, dst=part, alpha=p.shade)
                    cv2.copyTo(part, need[by0:by1, bx0:bx1], iroi[by0:by1, bx0:bx1])
        bgr = np.asarray(cv2.cvtColor(image, cv2.COLOR_BGRA2BGR), np.uint8)
        with np.errstate(divide="ignore"):
            depth = np.divide(np.float32(1.0), invz).astype(np.float32, copy=False)
        return bgr, labels, depth

def _draw_atlas(
    atlas: Atlas,
    p: _Prepared,
    cam: Camera,
    origin: tuple[int, int],
    hom: FloatArray,
    vis: NDArray[np.uint8],
    sroi: NDArray[np.uint8],
    iroi: NDArray[np.uint8],
) -> NDArray[np.uint8] | None:
    """Draw an appearance over the visible pixels ``vis`` of its face's box;
    return the mask of the pixels it drew (``None`` if none)."""
    x0, y0 = origin
    if atlas.covers:
        over = vis
    else:
        shape = _project(p.world(atlas.polygon), cam, _frustum(cam))
        if shape is None:
            return None
        (ax0, ay0, _, _), pts = shape
        over = np.zeros_like(vis)
        # The atlas polygon's pixels, in the face's box coordinates.
        shifted = pts + np.array([(ax0 - x0) << _SHIFT, (ay0 - y0) << _SHIFT], np.int32)
        cv2.fillConvexPoly(over, shifted, 255, cv2.LINE_8, _SHIFT)
        cv2.bitwise_and(over, vis, dst=over)
    box = _warp_levels(atlas.levels, atlas.face_to_texel, hom, over, sroi, wrap=False)
    if box is None:
        return None
    bx0, by0, bx1, by1 = box
    cv2.copyTo(sroi[by0:by1, bx0:bx1], over[by0:by1, bx0:bx1], iroi[by0:by1, bx0:bx1])
    return over


def _set(roi: NDArray[Any], value: float | tuple[float, ...], mask: NDArray[np.uint8]) -> None:
    """``roi[mask] = value`` in place, by two masked OpenCV operations (no allocation).

    A region of four pixels or fewer is set with numpy: OpenCV takes a 4x1 array
    for a scalar, and adds a Python number to it as an array of another type.
    """
    if roi.shape[0] * roi.shape[1] <= 4:
        roi[mask.astype(bool)] = value
        return
    cv2.bitwise_and(roi, 0, dst=roi, mask=mask)  # type: ignore[call-overload]
    cv2.add(roi, value, dst=roi, mask=mask)  # type: ignore[call-overload]


def _translation(x0: int, y0: int) -> FloatArray:
    """ROI pixel coordinates to image pixel coordinates."""
    return np.array([[1.0, 0.0, x0], [0.0, 1.0, y0], [0.0, 0.0, 1.0]])


def _far_square(c: FloatArray) -> tuple[tuple[float, float], ...]:
    """The part of an unbounded floor that is drawn: FAR metres around the camera."""
    x, y = float(c[0]), float(c[1])
    return ((x - FAR, y - FAR), (x + FAR, y - FAR), (x + FAR, y + FAR), (x - FAR, y + FAR))


def _sky(cam: Camera) -> FloatArray:
    """Sky colour per image row (BGR): from the horizon colour to the top colour
    by the elevation of the row's central ray."""
    h = cam.height
    ry = (np.arange(h, dtype=np.float64) - cam.cy) / cam.fy
    rays = np.stack([np.zeros(h), ry, np.ones(h)], axis=1) @ cam.rotation
    elev = rays[:, 2] / np.linalg.norm(rays, axis=1)
    k = np.clip(elev, 0.0, 1.0)[:, None] ** 0.5
    return SKY_HORIZON * (1 - k) + SKY_TOP * k


def _inverse_depth(p: _Prepared, cam: Camera) -> tuple[float, float, float]:
    """``(a, b, c)`` with ``1/z = a x + b y + c`` at pixel ``(x, y)`` on the plane."""
    n = cam.rotation @ p.normal
    d = float(n @ (cam.rotation @ (p.origin - cam.position)))
    return (n[0] / (cam.fx * d), n[1] / (cam.fy * d),
            (n[2] - n[0] * cam.cx / cam.fx - n[1] * cam.cy / cam.fy) / d)


def _frustum(cam: Camera) -> list[tuple[float, float, float, float]]:
    """The view frustum (widened by ``_MARGIN`` pixels) as half-spaces
    ``a x + b y + c z + d >= 0`` in camera coordinates."""
    m = _MARGIN
    return [
        (0.0, 0.0, 1.0, -NEAR),
        (cam.fx, 0.0, cam.cx + m, 0.0),
        (-cam.fx, 0.0, cam.width - 1 + m - cam.cx, 0.0),
        (0.0, cam.fy, cam.cy + m, 0.0),
        (0.0, -cam.fy, cam.height - 1 + m - cam.cy, 0.0),
    ]


def _project(
    corners: FloatArray, cam: Camera, frustum: list[tuple[float, float, float, float]]
) -> tuple[tuple[int, int, int, int], NDArray[np.int32]] | None:
    """Clip a convex face (world corners) to the view frustum and project it.

    Returns the pixel box ``(x0, y0, x1, y1)`` (exclusive end) and the corners
    relative to it in fixed point (``_SHIFT`` bits), or ``None`` if nothing is
    in view.  (Plain Python: a face has a handful of corners, and NumPy's cost
    per call would dominate.)
    """
    pc: list[list[float]] = ((corners - cam.position) @ cam.rotation.T).tolist()
    for a, b, c, d in frustum:
        f = [a * x + b * y + c * z + d for x, y, z in pc]
        if min(f) >= 0:
            continue
        if max(f) < 0:
            return None
        out: list[list[float]] = []
        n = len(pc)
        for i in range(n):
            j = (i + 1) % n
            if f[i] >= 0:
                out.append(pc[i])
            if (f[i] >= 0) != (f[j] >= 0):
                r = f[i] / (f[i] - f[j])
                p, q = pc[i], pc[j]
                out.append([p[0] + r * (q[0] - p[0]), p[1] + r * (q[1] - p[1]),
                            p[2] + r * (q[2] - p[2])])
        pc = out
        if len(pc) < 3:
            return None
    fx, fy, cx, cy = cam.fx, cam.fy, cam.cx, cam.cy
    px = [x / z * fx + cx for x, _, z in pc]
    py = [y / z * fy + cy for _, y, z in pc]
    x0 = max(math.floor(min(px)), 0)
    y0 = max(math.floor(min(py)), 0)
    x1 = min(math.ceil(max(px)) + 1, cam.width)
    y1 = min(math.ceil(max(py)) + 1, cam.height)
    if x0 >= x1 or y0 >= y1:
        return None
    scale = float(1 << _SHIFT)
    pts = np.array([(round((u - x0) * scale), round((v - y0) * scale)) for u, v in zip(px, py)],
                   np.int32)
    return (x0, y0, x1, y1), pts


def _warp_levels(
    levels: Sequence[NDArray[np.uint8]],
    texel: FloatArray,
    hom: FloatArray,
    mask: NDArray[np.uint8],
    out: NDArray[np.uint8],
    *,
    wrap: bool,
    tiled: Sequence[NDArray[np.uint8]] | None = None,
) -> tuple[int, int, int, int] | None:
    """Warp a mip-mapped source into ``out`` (a box of the image) where ``mask`` is set.

    ``texel`` maps face coordinates to level-0 source pixels and ``hom`` face
    coordinates to box pixels.  The mip level is chosen on a grid from the
    pixel-to-texel footprint, as the reference does per pixel; each level is
    warped over the box of the pixels that use it.  Returns the part of the
    box written, ``(x0, y0, x1, y1)``, or ``None`` if ``mask`` is empty.
    """
    rx, ry, rw, rh = cv2.boundingRect(mask)
    if rw == 0:
        return None
    m0 = texel @ np.linalg.inv(hom) @ _translation(rx, ry)  # rect pixel -> level-0 texel
    top = len(levels) - 1
    # The footprint varies smoothly and takes its extremes on the rectangle's
    # border: when its corners, edge middles and centre agree on one level,
    # that is the level of the whole rectangle.
    rows = m0.tolist()
    probe = {_level(rows, x, y, top) for x in (0.0, (rw - 1) / 2.0, rw - 1.0)
             for y in (0.0, (rh - 1) / 2.0, rh - 1.0)}
    if len(probe) == 1:
        present = np.array(list(probe), np.uint8)
        grid = present.reshape(1, 1)
        gw = gh = 1
    else:
        gw, gh = -(-rw // _GRID), -(-rh // _GRID)
        gx = np.arange(gw) * _GRID + (_GRID - 1) / 2.0
        gy = np.arange(gh) * _GRID + (_GRID - 1) / 2.0
        px, py = np.meshgrid(np.minimum(gx, rw - 1), np.minimum(gy, rh - 1))
        wz = m0[2, 0] * px + m0[2, 1] * py + m0[2, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = (m0[0, 0] * px + m0[0, 1] * py + m0[0, 2]) / wz
            v = (m0[1, 0] * px + m0[1, 1] * py + m0[1, 2]) / wz
            dux, duy = (m0[0, 0] - u * m0[2, 0]) / wz, (m0[0, 1] - u * m0[2, 1]) / wz
            dvx, dvy = (m0[1, 0] - v * m0[2, 0]) / wz, (m0[1, 1] - v * m0[2, 1]) / wz
            foot = np.maximum(np.hypot(dux, dvx), np.hypot(duy, dvy))
            level = np.floor(np.log2(np.maximum(foot, 1.0)))
        grid = np.where(np.isfinite(level) & (wz > 0), np.clip(level, 0, top), top).astype(np.uint8)
        present = np.unique(grid)
    rect_out = out[ry:ry + rh, rx:rx + rw]
    if len(present) == 1:
        _warp(levels, int(present[0]), m0, (0, 0, rw, rh), rect_out, wrap, tiled)
        return rx, ry, rx + rw, ry + rh
    rect_mask = mask[ry:ry + rh, rx:rx + rw]
    full = cv2.resize(grid, (gw * _GRID, gh * _GRID), interpolation=cv2.INTER_NEAREST)[:rh, :rw]
    for k in present:
        sel = np.asarray(cv2.compare(full, int(k), cv2.CMP_EQ), np.uint8)  # type: ignore[call-overload]
        cv2.bitwise_and(sel, rect_mask, dst=sel)
        x, y, w, h = cv2.boundingRect(sel)
        if w == 0:
            continue
        band = np.empty((h, w, out.shape[2]), np.uint8)
        _warp(levels, int(k), m0, (x, y, x + w, y + h), band, wrap, tiled)
        cv2.copyTo(band, sel[y:y + h, x:x + w], rect_out[y:y + h, x:x + w])
    return rx, ry, rx + rw, ry + rh


def _level(m: list[list[float]], x: float, y: float, top: int) -> int:
    """The mip level of pixel ``(x, y)`` under the pixel-to-texel map ``m``
    (rows of a 3x3 matrix): ``floor(log2(footprint))``, clipped to ``0 .. top``."""
    (a, b, c), (d, e, f), (g, h, i) = m
    wz = g * x + h * y + i
    if not wz > 0:
        return top
    u = (a * x + b * y + c) / wz
    v = (d * x + e * y + f) / wz
    dux, duy = (a - u * g) / wz, (b - u * h) / wz
    dvx, dvy = (d - v * g) / wz, (e - v * h) / wz
    foot = max(math.hypot(dux, dvx), math.hypot(duy, dvy))
    if not math.isfinite(foot):
        return top
    return min(max(int(math.floor(math.log2(max(foot, 1.0)))), 0), top)


def _warp(
    levels: Sequence[NDArray[np.uint8]],
    k: int,
    m0: FloatArray,
    box: tuple[int, int, int, int],
    out: NDArray[np.uint8],
    wrap: bool,
    tiled: Sequence[NDArray[np.uint8]] | None = None,
) -> None:
    """Warp level ``k`` over ``box`` (in face-box pixels) into ``out``, an array
    of the box's size.

    A repeating texture (``wrap``) is read from ``tiled`` (each level repeated
    2x2): the box is cut into parts whose texels span less than one period,
    and each part is moved by whole periods to start inside the image, so that
    OpenCV reads inside the source (its fast path, several times faster than
    wrapping at the border).
    """
    x0, y0, x1, y1 = box
    m = level_matrix(k) @ m0
    if not wrap or tiled is None:
        _warp_part(levels[k], m, box, out, x0, y0, cv2.BORDER_REPLICATE if not wrap
                   else cv2.BORDER_WRAP)
        return
    lh, lw = levels[k].shape[:2]
    parts = [box]
    done = 0
    while parts:
        bx0, by0, bx1, by1 = parts.pop()
        span = _span(m, bx0, by0, bx1, by1)
        if span is None or done > 64 or (bx1 - bx0 <= 8 and by1 - by0 <= 8):
            _warp_part(levels[k], m, (bx0, by0, bx1, by1), out, x0, y0, cv2.BORDER_WRAP)
            done += 1
            continue
        umin, umax, vmin, vmax = span
        wide, tall = (umax - umin) / (lw - 2), (vmax - vmin) / (lh - 2)
        if wide < 1 and tall < 1:
            shifted = m.copy()
            shifted[0] -= math.floor(umin / lw) * lw * m[2]
            shifted[1] -= math.floor(vmin / lh) * lh * m[2]
            _warp_part(tiled[k], shifted, (bx0, by0, bx1, by1), out, x0, y0,
                       cv2.BORDER_WRAP)
            done += 1
        elif wide >= tall and bx1 - bx0 > 8:
            mid = (bx0 + bx1) // 2
            parts += [(bx0, by0, mid, by1), (mid, by0, bx1, by1)]
        elif by1 - by0 > 8:
            mid = (by0 + by1) // 2
            parts += [(bx0, by0, bx1, mid), (bx0, mid, bx1, by1)]
        else:
            mid = (bx0 + bx1) // 2
            parts += [(bx0, by0, mid, by1), (mid, by0, bx1, by1)]


def _span(m: FloatArray, x0: int, y0: int, x1: int, y1: int) -> tuple[float, float, float, float] | None:
    """Range ``(u_min, u_max, v_min, v_max)`` of source coordinates over the
    pixels ``x0 .. x1 - 1``, ``y0 .. y1 - 1`` (a projective map in front of the
    camera takes its extremes at the corners), or ``None`` if undefined."""
    (a, b, c), (d, e, f), (g, h, i) = m.tolist()
    us, vs = [], []
    for x in (x0, x1 - 1):
        for y in (y0, y1 - 1):
            wz = g * x + h * y + i
            if not wz > 0:
                return None
            us.append((a * x + b * y + c) / wz)
            vs.append((d * x + e * y + f) / wz)
    if not all(math.isfinite(t) for t in us + vs):
        return None
    return min(us), max(us), min(vs), max(vs)


def _warp_part(
    src: NDArray[np.uint8],
    m: FloatArray,
    part: tuple[int, int, int, int],
    out: NDArray[np.uint8],
    x0: int,
    y0: int,
    border: int,
) -> None:
    """Warp ``src`` through ``m`` (box pixels -> source pixels) over ``part`` of
    the box into the matching part of ``out`` (whose origin is box pixel ``(x0, y0)``)."""
    px0, py0, px1, py1 = part
    cv2.warpPerspective(src, m @ _translation(px0, py0), (px1 - px0, py1 - py0),
                        dst=out[py0 - y0:py1 - y0, px0 - x0:px1 - x0],
                        flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP, borderMode=border)
