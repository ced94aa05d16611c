"""The rasterizer: what the camera should see of a scene.

:class:`Renderer` draws a :class:`~adapt.imagination.scene.SceneSpec` through
a :class:`~adapt.geometry.Camera` into a BGR ``uint8`` image and a label image
(``int32``, the id of the object seen at each pixel).  Every surface is
ray-cast per pixel, so perspective, occlusion (a depth buffer) and texture
mapping are exact at pixel centres:

* the **static background** (sky, textured floor, textured walls, the visible
  faces of obstacles, each face shaded by a fixed light) is rendered once per
  camera pose and cached;
* **moving objects** are drawn over a copy of it for each frame: balls as
  shaded spheres with an anti-aliased outline and a contact shadow on the
  floor, and the robot as a flat-shaded prism.

Label ids (also in ``docs/conventions.md``):

========================  =============================================
id                        what
========================  =============================================
``0``                     nothing (sky)
``1``                     the floor
``1000 + i``              ``scene.walls[i]``
``2000 + i``              ``scene.obstacles[i]``
``3000 + i``              ``scene.balls[i]``
``4000``                  the robot
========================  =============================================

:func:`label_names` maps the ids of a scene to object names.

Examples
--------
>>> from adapt.geometry import Camera
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 2), (2, 2), height=1.0),),
...                   balls=(Ball("ball", radius=0.1, position=(0.0, 1.0)),))
>>> cam = Camera.look_at(fx=300, fy=300, cx=159.5, cy=119.5, width=320, height=240,
...                      position=(0, -1, 0.5), look_at=(0, 2, 0.3))
>>> out = Renderer(scene, cam).render()
>>> out.image.shape, out.image.dtype, out.labels.dtype
((240, 320, 3), dtype('uint8'), dtype('int32'))
>>> sorted(label_names(scene)[int(i)] for i in set(out.labels.ravel().tolist()))
['ball', 'floor', 'north', 'sky']
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination.scene import Ball, Color, RobotSpec, SceneSpec
from adapt.imagination.texture import Texture, load_texture
from adapt.imagination.world import BodyState, WorldState

__all__ = [
    "Renderer",
    "RenderResult",
    "label_names",
    "initial_state",
    "LABEL_SKY",
    "LABEL_FLOOR",
    "LABEL_WALL",
    "LABEL_OBSTACLE",
    "LABEL_BALL",
    "LABEL_ROBOT",
]

LABEL_SKY = 0
LABEL_FLOOR = 1
LABEL_WALL = 1000
LABEL_OBSTACLE = 2000
LABEL_BALL = 3000
LABEL_ROBOT = 4000

#: Near clipping distance in metres (camera z).
NEAR = 0.01
#: The floor reaches this far from the camera when it has no extent.
FAR = 200.0
#: Direction towards the light (world), fixed.
LIGHT = np.array([0.35, -0.55, 0.76]) / np.linalg.norm([0.35, -0.55, 0.76])
#: Sky colour at the horizon and at the top (BGR).
SKY_HORIZON = np.array([235.0, 225.0, 215.0])
SKY_TOP = np.array([210.0, 170.0, 120.0])

FloatArray = NDArray[np.float64]


def _pixel_bbox(pc: NDArray[np.float64], cam: Camera) -> tuple[int, int, int, int] | None:
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


@dataclass(frozen=True, slots=True, eq=False)
class RenderResult:
    """One rendered frame.

    Attributes
    ----------
    image : (H, W, 3) uint8 ndarray
        BGR colour image.
    labels : (H, W) int32 ndarray
        Object id per pixel (see the module docstring).
    """

    image: NDArray[np.uint8]
    labels: NDArray[np.int32]


def label_names(scene: SceneSpec) -> dict[int, str]:
    """Label id -> object name for a scene (``0`` is ``"sky"``, ``1`` ``"floor"``).

    Examples
    --------
    >>> from adapt.imagination.scene import Ball, SceneSpec
    >>> label_names(SceneSpec(balls=(Ball("b"),)))
    {0: 'sky', 1: 'floor', 3000: 'b'}
    """
    names = {LABEL_SKY: "sky", LABEL_FLOOR: "floor"}
    for i, w in enumerate(scene.walls):
        names[LABEL_WALL + i] = w.name
    for i, o in enumerate(scene.obstacles):
        names[LABEL_OBSTACLE + i] = o.name
    for i, b in enumerate(scene.balls):
        names[LABEL_BALL + i] = b.name
    if scene.robot is not None:
        names[LABEL_ROBOT] = scene.robot.name
    return names


def initial_state(scene: SceneSpec) -> WorldState:
    """The scene's initial state (time 0) as a :class:`WorldState`."""
    bodies = [BodyState(b.name, b.position, b.velocity) for b in scene.balls]
    if scene.robot is not None:
        r = scene.robot
        bodies.append(BodyState(r.name, r.position, (0.0, 0.0), math.radians(r.heading_deg)))
    return WorldState(0.0, 0, tuple(bodies))


@dataclass(frozen=True, slots=True, eq=False)
class _Face:
    """A planar convex face: points ``origin + s*u + t*v`` with ``(s, t)`` in ``polygon``."""

    origin: FloatArray
    u: FloatArray
    v: FloatArray
    polygon: tuple[tuple[float, float], ...]
    color: Color
    texture: str | None
    tile: float
    label: int
    two_sided: bool = False


class Renderer:
    """Renders a scene through a camera; caches the static background.

    Parameters
    ----------
    scene : SceneSpec
    camera : Camera
    """

    def __init__(self, scene: SceneSpec, camera: Camera) -> None:
        self.scene = scene
        self.camera = camera
        h, w = camera.height, camera.width
        xs = (np.arange(w, dtype=np.float64) - camera.cx) / camera.fx
        ys = (np.arange(h, dtype=np.float64) - camera.cy) / camera.fy
        self._rx = xs  # ray x per column (camera frame, z = 1)
        self._ry = ys  # ray y per row
        self._light_cam = camera.rotation @ LIGHT
        self._bg: tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float32]] | None = None
        self._floor_label_cache: NDArray[np.bool_] | None = None

    def with_camera(self, camera: Camera) -> "Renderer":
        """A renderer of the same scene through another camera (new background)."""
        return Renderer(self.scene, camera)

    # -- background -----------------------------------------------------------

    @property
    def background(self) -> RenderResult:
        """The static background (read-only arrays), rendered on first use."""
        image, labels, _ = self._background()
        return RenderResult(image, labels)

    def _background(self) -> tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float32]]:
        if self._bg is None:
            cam = self.camera
            h, w = cam.height, cam.width
            image = np.empty((h, w, 3), np.uint8)
            image[:] = self._sky(h).astype(np.uint8)[:, None, :]
            labels = np.zeros((h, w), np.int32)
            depth = np.full((h, w), np.inf, np.float32)
            for face in self._static_faces():
                self._draw_face(face, image, labels, depth)
            for a in (image, labels, depth):
                a.setflags(write=False)
            self._bg = (image, labels, depth)
        return self._bg

    def _sky(self, h: int) -> FloatArray:
        # Elevation of each row's central ray: blend from horizon to top colour.
        cam = self.camera
        rays = np.stack([np.zeros(h), self._ry, np.ones(h)], axis=1) @ cam.rotation
        elev = rays[:, 2] / np.linalg.norm(rays, axis=1)
        k = np.clip(elev, 0.0, 1.0)[:, None] ** 0.5
        return SKY_HORIZON * (1 - k) + SKY_TOP * k

    def _static_faces(self) -> list[_Face]:
        scene, cam = self.scene, self.camera
        c = cam.position
        ex, ey, ez = np.eye(3)
        faces: list[_Face] = []
        fl = scene.floor
        if fl.extent is not None:
            x0, y0, x1, y1 = fl.extent
        else:
            x0, y0, x1, y1 = c[0] - FAR, c[1] - FAR, c[0] + FAR, c[1] + FAR
        faces.append(
            _Face(np.zeros(3), ex, ey, ((x0, y0), (x1, y0), (x1, y1), (x0, y1)),
                  fl.color, fl.texture, fl.tile, LABEL_FLOOR)
        )
        for i, wall in enumerate(scene.walls):
            a = np.array([*wall.start, 0.0])
            d = np.array([*wall.end, 0.0]) - a
            length = float(np.linalg.norm(d))
            faces.append(
                _Face(a, d / length, ez,
                      ((0.0, 0.0), (length, 0.0), (length, wall.height), (0.0, wall.height)),
                      wall.color, wall.texture, wall.tile, LABEL_WALL + i, two_sided=True)
            )
        for i, ob in enumerate(scene.obstacles):
            faces.extend(
                _prism_faces(ob.polygon, ob.height, ob.color, ob.texture, ob.tile,
                             LABEL_OBSTACLE + i, c)
            )
        return faces

    # -- faces ----------------------------------------------------------------

    def _face_bbox(self, face: _Face) -> tuple[int, int, int, int] | None:
        """Pixel bbox ``(x0, y0, x1, y1)`` (exclusive end) of a face, or None."""
        cam = self.camera
        pts = np.array([face.origin + s * face.u + t * face.v for s, t in face.polygon])
        pc = cam.to_camera(pts)
        pc = _clip_near(pc, NEAR)
        if len(pc) == 0:
            return None
        return _pixel_bbox(pc, cam)

    def _draw_face(
        self,
        face: _Face,
        image: NDArray[np.uint8],
        labels: NDArray[np.int32],
        depth: NDArray[np.float32],
    ) -> None:
        box = self._face_bbox(face)
        if box is None:
            return
        x0, y0, x1, y1 = box
        cam = self.camera
        r = cam.rotation
        o = r @ (face.origin - cam.position)
        uc, vc = r @ face.u, r @ face.v
        n = np.cross(uc, vc)
        dx = self._rx[x0:x1][None, :]
        dy = self._ry[y0:y1][:, None]
        denom = n[0] * dx + n[1] * dy + n[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = (n @ o) / denom
        # Camera-frame point lam * (dx, dy, 1) minus the origin, in face coordinates.
        px, py, pz = lam * dx - o[0], lam * dy - o[1], lam - o[2]
        s = uc[0] * px + uc[1] * py + uc[2] * pz
        t = vc[0] * px + vc[1] * py + vc[2] * pz
        inside = (lam > NEAR) & np.isfinite(lam)
        poly = face.polygon
        for k in range(len(poly)):
            (sa, ta), (sb, tb) = poly[k], poly[(k + 1) % len(poly)]
            inside &= (sb - sa) * (t - ta) - (tb - ta) * (s - sa) >= 0
        dview = depth[y0:y1, x0:x1]
        inside &= lam < dview
        if not inside.any():
            return
        # Shading: Lambert with an ambient term; two-sided faces light both sides.
        nw = np.cross(face.u, face.v)
        cos = float(nw @ LIGHT)
        if face.two_sided:
            cos = abs(cos)
        shade = 0.6 + 0.4 * max(cos, 0.0)
        if face.texture is None:
            bgr = np.array(face.color[::-1], np.float64) * shade
            colors = np.broadcast_to(bgr, (*s.shape, 3))
        else:
            colors = _sample_texture(load_texture(face.texture), s, t, face.tile, inside) * shade
        iview = image[y0:y1, x0:x1]
        iview[inside] = np.clip(colors[inside], 0, 255).astype(np.uint8)
        labels[y0:y1, x0:x1][inside] = face.label
        dview[inside] = lam[inside]

    # -- frames ---------------------------------------------------------------

    def render(self, state: WorldState | None = None) -> RenderResult:
        """Render the moving objects in ``state`` (default: the scene's
        initial state) over the cached background."""
        if state is None:
            state = initial_state(self.scene)
        bg_image, bg_labels, bg_depth = self._background()
        image = bg_image.copy()
        labels = bg_labels.copy()
        depth = bg_depth.copy()
        poses = {b.name: b for b in state.bodies}
        robot = self.scene.robot
        if robot is not None and robot.name in poses:
            self._draw_robot(robot, poses[robot.name], image, labels, depth)
        for ball in self.scene.balls:
            pose = poses.get(ball.name)
            if pose is not None:
                self._draw_shadow(ball, pose.position, image, bg_labels)
        for i, ball in enumerate(self.scene.balls):
            pose = poses.get(ball.name)
            if pose is not None:
                self._draw_ball(ball, pose, LABEL_BALL + i, image, labels, depth)
        return RenderResult(image, labels)

    def _sphere_bbox(self, center: FloatArray, radius: float) -> tuple[int, int, int, int] | None:
        cam = self.camera
        corners = center + radius * np.array(
            [[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float
        )
        pc = cam.to_camera(corners)
        if pc[:, 2].min() <= NEAR:
            return None
        return _pixel_bbox(pc, cam)

    def _draw_ball(
        self,
        ball: Ball,
        pose: BodyState,
        label: int,
        image: NDArray[np.uint8],
        labels: NDArray[np.int32],
        depth: NDArray[np.float32],
    ) -> None:
        cam = self.camera
        r = ball.radius
        center = np.array([pose.position[0], pose.position[1], r])
        box = self._sphere_bbox(center, r)
        if box is None:
            return
        x0, y0, x1, y1 = box
        sc = cam.rotation @ (center - cam.position)
        dx = self._rx[x0:x1][None, :]
        dy = self._ry[y0:y1][:, None]
        # Ray lam * (dx, dy, 1) against the sphere |X - sc| = r.
        a = dx * dx + dy * dy + 1.0
        b = dx * sc[0] + dy * sc[1] + sc[2]
        cc = float(sc @ sc) - r * r
        disc = b * b - a * cc
        # Anti-aliasing: signed distance (in pixels) of the ray from the silhouette.
        dist2 = np.maximum(float(sc @ sc) - b * b / a, 0.0)
        edge = (r - np.sqrt(dist2)) * cam.fx / float(sc[2])
        cover = np.clip(edge + 0.5, 0.0, 1.0)
        lam = (b - np.sqrt(np.maximum(disc, 0.0))) / a
        dview = depth[y0:y1, x0:x1]
        visible = (cover > 0) & (lam < dview)
        if not visible.any():
            return
        # Normal in camera coordinates, shading with a specular highlight.
        nx = (lam * dx - sc[0]) / r
        ny = (lam * dy - sc[1]) / r
        nz = (lam - sc[2]) / r
        lc = self._light_cam
        lam_dot = np.maximum(nx * lc[0] + ny * lc[1] + nz * lc[2], 0.0)
        # Blinn highlight with the view direction of the ball's centre.
        half = lc - sc / math.sqrt(float(sc @ sc))
        half /= np.linalg.norm(half)
        spec = np.maximum(nx * half[0] + ny * half[1] + nz * half[2], 0.0) ** 40
        if ball.texture is None:
            base = np.broadcast_to(np.array(ball.color[::-1], float), (*a.shape, 3))
        else:
            base = self._ball_texture(ball, pose, nx, ny, nz)
        color = base * (0.35 + 0.65 * lam_dot)[..., None] + 200.0 * spec[..., None]
        iview = image[y0:y1, x0:x1]
        w = np.where(visible, cover, 0.0)[..., None]
        iview[:] = np.clip(iview * (1.0 - w) + color * w, 0, 255).astype(np.uint8)
        solid = visible & (cover >= 0.5)
        labels[y0:y1, x0:x1][solid] = label
        dview[solid] = lam[solid]

    def _ball_texture(
        self, ball: Ball, pose: BodyState, nx: FloatArray, ny: FloatArray, nz: FloatArray
    ) -> FloatArray:
        assert ball.texture is not None
        tex = load_texture(ball.texture).levels[0]
        rt = self.camera.rotation.T
        wx = rt[0, 0] * nx + rt[0, 1] * ny + rt[0, 2] * nz
        wy = rt[1, 0] * nx + rt[1, 1] * ny + rt[1, 2] * nz
        wz = rt[2, 0] * nx + rt[2, 1] * ny + rt[2, 2] * nz
        lon = np.arctan2(wy, wx) - pose.angle
        lat = np.arcsin(np.clip(wz, -1.0, 1.0))
        th, tw = tex.shape[:2]
        col = ((lon / (2 * np.pi)) % 1.0 * (tw - 1)).astype(np.intp)
        row = ((0.5 - lat / np.pi) * (th - 1)).astype(np.intp)
        return tex[row, col].astype(np.float64)

    def _draw_shadow(
        self,
        ball: Ball,
        position: tuple[float, float],
        image: NDArray[np.uint8],
        bg_labels: NDArray[np.int32],
    ) -> None:
        cam = self.camera
        r = ball.radius
        # A soft dark ellipse where the sphere's centre casts its shadow along the light.
        sx = position[0] - LIGHT[0] / LIGHT[2] * r
        sy = position[1] - LIGHT[1] / LIGHT[2] * r
        reach = 2.5 * r
        ring = np.array(
            [[sx + reach * math.cos(a), sy + reach * math.sin(a), 0.0]
             for a in np.linspace(0, 2 * math.pi, 12, endpoint=False)]
        )
        pc = cam.to_camera(ring)
        if pc[:, 2].min() <= NEAR:
            return
        px = pc[:, 0] / pc[:, 2] * cam.fx + cam.cx
        py = pc[:, 1] / pc[:, 2] * cam.fy + cam.cy
        x0, y0 = max(int(px.min()) - 1, 0), max(int(py.min()) - 1, 0)
        x1, y1 = min(int(px.max()) + 2, cam.width), min(int(py.max()) + 2, cam.height)
        if x0 >= x1 or y0 >= y1:
            return
        # Floor point of each pixel's ray: camera centre + lam * R^T (dx, dy, 1).
        rt = cam.rotation.T
        dx = self._rx[x0:x1][None, :]
        dy = self._ry[y0:y1][:, None]
        wz = rt[2, 0] * dx + rt[2, 1] * dy + rt[2, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = -cam.position[2] / wz
        fx_ = cam.position[0] + lam * (rt[0, 0] * dx + rt[0, 1] * dy + rt[0, 2]) - sx
        fy_ = cam.position[1] + lam * (rt[1, 0] * dx + rt[1, 1] * dy + rt[1, 2]) - sy
        d2 = (fx_ * fx_ + fy_ * fy_) / r**2
        dark = 1.0 - 0.6 * np.exp(-d2)
        floor = (bg_labels[y0:y1, x0:x1] == LABEL_FLOOR) & (lam > 0) & (d2 < 6.0)
        if not floor.any():
            return
        view = image[y0:y1, x0:x1]
        view[floor] = (view[floor] * dark[floor][:, None]).astype(np.uint8)

    def _draw_robot(
        self,
        robot: RobotSpec,
        pose: BodyState,
        image: NDArray[np.uint8],
        labels: NDArray[np.int32],
        depth: NDArray[np.float32],
    ) -> None:
        ca, sa = math.cos(pose.angle), math.sin(pose.angle)
        x, y = pose.position
        outline = tuple(
            (x + ca * px - sa * py, y + sa * px + ca * py) for px, py in robot.outline()
        )
        if not self._prism_in_view(outline, robot.height):
            return
        for face in _prism_faces(outline, robot.height, robot.color, None, 1.0,
                                 LABEL_ROBOT, self.camera.position):
            self._draw_face(face, image, labels, depth)

    def _prism_in_view(self, polygon: Sequence[tuple[float, float]], height: float) -> bool:
        """Whether any part of a prism can fall inside the image (conservative)."""
        cam = self.camera
        n = len(polygon)
        base = np.array([[px, py, 0.0] for px, py in polygon])
        top = base + np.array([0.0, 0.0, height])
        pc = cam.to_camera(np.vstack([base, top]))
        idx = np.arange(n)
        ea = np.concatenate([idx, idx + n, idx])
        eb = np.concatenate([(idx + 1) % n, (idx + 1) % n + n, idx + n])
        za, zb = pc[ea, 2], pc[eb, 2]
        cross = (za - NEAR) * (zb - NEAR) < 0
        f = (NEAR - za[cross]) / (zb[cross] - za[cross])
        cut = pc[ea[cross]] + f[:, None] * (pc[eb[cross]] - pc[ea[cross]])
        pts = np.vstack([pc[pc[:, 2] >= NEAR], cut])
        if len(pts) == 0:
            return False
        px = pts[:, 0] / pts[:, 2] * cam.fx + cam.cx
        py = pts[:, 1] / pts[:, 2] * cam.fy + cam.cy
        return bool(px.max() >= -1 and px.min() <= cam.width and py.max() >= -1
                    and py.min() <= cam.height)


def _prism_faces(
    polygon: Sequence[tuple[float, float]],
    height: float,
    color: Color,
    texture: str | None,
    tile: float,
    label: int,
    camera_position: FloatArray,
) -> list[_Face]:
    """The faces of a vertical prism over a CCW convex polygon that face the camera."""
    faces: list[_Face] = []
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
            _Face(a, u, ez, ((0.0, 0.0), (length, 0.0), (length, height), (0.0, height)),
                  color, texture, tile, label)
        )
    if c[2] > height:
        faces.append(
            _Face(np.array([0.0, 0.0, height]), np.array([1.0, 0.0, 0.0]),
                  np.array([0.0, 1.0, 0.0]), tuple(polygon), color, texture, tile, label)
        )
    return faces


def _clip_near(points: FloatArray, near: float) -> FloatArray:
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


def _sample_texture(
    tex: Texture, s: FloatArray, t: FloatArray, tile: float, mask: NDArray[np.bool_]
) -> FloatArray:
    """BGR colours of face coordinates ``(s, t)`` (metres), mip-mapped."""
    w, h = tex.size
    u = np.where(mask, s, 0.0) * (w / tile)
    v = -np.where(mask, t, 0.0) * (h / tile)
    # Texels per pixel from the screen-space derivatives; pick a mip level.
    if u.shape[0] > 1 and u.shape[1] > 1:
        du_y, du_x = np.gradient(u)
        dv_y, dv_x = np.gradient(v)
        foot = np.maximum(np.hypot(du_x, dv_x), np.hypot(du_y, dv_y))
    else:
        foot = np.ones_like(u)
    level = np.clip(np.floor(np.log2(np.maximum(foot, 1.0))), 0, len(tex.levels) - 1)
    level = level.astype(np.intp)
    out = np.zeros((*u.shape, 3), np.float64)
    for k in np.unique(level[mask]):
        img = tex.levels[int(k)]
        lh, lw = img.shape[:2]
        scale = 2.0 ** -int(k)
        mx = np.mod(u * scale, lw).astype(np.float32)
        my = np.mod(v * scale, lh).astype(np.float32)
        sampled = cv2.remap(img, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)
        sel = mask & (level == k)
        out[sel] = sampled[sel]
    return out
