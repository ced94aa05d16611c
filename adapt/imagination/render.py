"""The rasterizer: what the camera should see of a scene.

:class:`Renderer` draws a :class:`~adapt.imagination.scene.SceneSpec` through
a :class:`~adapt.geometry.Camera` into a BGR ``uint8`` image and a label image
(``int32``, the id of the object seen at each pixel):

* the **static background** (sky, the textured floor, walls and obstacle
  faces, each shaded by a fixed light, or an appearance set at run time) comes
  from the scene's :class:`~adapt.imagination.backdrop.Backdrop`: one
  perspective warp per surface, a few milliseconds for a new camera pose
  (``exact=True`` ray-casts every pixel instead: the slow reference).  It is
  cached per camera pose and appearance version;
* **moving objects** are drawn over a copy of it for each frame: balls as
  shaded spheres with an anti-aliased outline and a contact shadow on the
  floor, and the robot as a flat-shaded prism.  :attr:`RenderResult.boxes`
  gives the pixel box of each one's visible part.

Label ids (also in ``docs/conventions.md``):

========================  =============================================
id                        what
========================  =============================================
``0``                     nothing (sky)
``1``                     the floor
``1000 + i``              ``scene.walls[i]``
``2000 + i``              ``scene.obstacles[i]``
``3000 + i``              ``balls[i]`` (the scene's, or those passed to
                          :meth:`Renderer.render`)
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
>>> sorted(out.names[int(i)] for i in set(out.labels.ravel().tolist()))
['ball', 'floor', 'north', 'sky']
>>> out.boxes["ball"]  # x, y, width, height of the visible part
(145, 145, 30, 30)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping, Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.geometry import Camera
from adapt.imagination.appearance import Appearance
from adapt.imagination.backdrop import Backdrop
from adapt.imagination.raycast import NEAR, draw_face, pixel_bbox, prism_faces
from adapt.imagination.scene import Ball, RobotSpec, SceneSpec
from adapt.imagination.surface import (
    LABEL_BALL,
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_ROBOT,
    LABEL_SKY,
    LABEL_WALL,
    LIGHT,
    Surface,
)
from adapt.imagination.texture import load_texture
from adapt.imagination.world import BodyState, WorldState

__all__ = [
    "Renderer",
    "RenderResult",
    "Box",
    "label_names",
    "initial_state",
    "LABEL_SKY",
    "LABEL_FLOOR",
    "LABEL_WALL",
    "LABEL_OBSTACLE",
    "LABEL_BALL",
    "LABEL_ROBOT",
]

FloatArray = NDArray[np.float64]

#: A pixel box ``(x, y, width, height)``: columns ``x .. x + width - 1`` and
#: rows ``y .. y + height - 1``.
Box = tuple[int, int, int, int]

_EMPTY_BOXES: Mapping[str, Box] = MappingProxyType({})


@dataclass(frozen=True, slots=True, eq=False)
class RenderResult:
    """One rendered frame.

    Attributes
    ----------
    image : (H, W, 3) uint8 ndarray
        BGR colour image.
    labels : (H, W) int32 ndarray
        Object id per pixel (see the module docstring).
    boxes : mapping of str to (x, y, width, height)
        For each moving object drawn (balls and the robot), the pixel box of
        the pixels labelled with it, that is its visible part; an object that
        is out of view or hidden is absent.
    names : mapping of int to str
        Label id to object name for this frame (as :func:`label_names`).
    """

    image: NDArray[np.uint8]
    labels: NDArray[np.int32]
    boxes: Mapping[str, Box] = field(default_factory=lambda: _EMPTY_BOXES)
    names: Mapping[int, str] = field(default_factory=lambda: MappingProxyType({}))


def label_names(scene: SceneSpec, balls: Sequence[Ball] | None = None) -> dict[int, str]:
    """Label id -> object name for a scene (``0`` is ``"sky"``, ``1`` ``"floor"``).

    ``balls`` replaces the scene's balls (the balls of a world that gained or
    lost some at run time).

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
    for i, b in enumerate(scene.balls if balls is None else balls):
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


class Renderer:
    """Renders a scene through a camera; caches the static background.

    Parameters
    ----------
    scene : SceneSpec
    camera : Camera
    exact : bool
        Ray-cast the background per pixel (the slow reference) instead of
        warping each surface.
    backdrop : Backdrop, optional
        The scene's static surfaces and appearances, shared between renderers
        (default: a new one for ``scene``).
    """

    def __init__(
        self,
        scene: SceneSpec,
        camera: Camera,
        *,
        exact: bool = False,
        backdrop: Backdrop | None = None,
    ) -> None:
        self.scene = scene
        self.camera = camera
        self.exact = exact
        self.backdrop = Backdrop(scene) if backdrop is None else backdrop
        h, w = camera.height, camera.width
        self._rx = (np.arange(w, dtype=np.float64) - camera.cx) / camera.fx  # ray x per column
        self._ry = (np.arange(h, dtype=np.float64) - camera.cy) / camera.fy  # ray y per row
        self._light_cam = camera.rotation @ LIGHT
        self._bg: tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float32]] | None = None
        self._bg_version = -1

    def with_camera(self, camera: Camera) -> "Renderer":
        """A renderer of the same scene through another camera.

        It shares this renderer's :class:`Backdrop` (prepared textures and
        appearances), so only the new pose's background is drawn: a few
        milliseconds.
        """
        return Renderer(self.scene, camera, exact=self.exact, backdrop=self.backdrop)

    def view(self, camera: Camera) -> NDArray[np.uint8]:
        """What ``camera`` sees of the scene in its initial state: the render callback
        the camera loop takes (:func:`adapt.vision.sync.synchronise`)."""
        return self.with_camera(camera).render().image

    # -- surfaces and appearance ------------------------------------------------

    @property
    def surfaces(self) -> tuple[Surface, ...]:
        """The scene's static surfaces (:func:`~adapt.imagination.surface.scene_surfaces`)."""
        return self.backdrop.surfaces

    def set_appearance(
        self,
        surface: str,
        image: ArrayLike | Appearance,
        mask: ArrayLike | None = None,
        *,
        extent: Sequence[float] | None = None,
        aligned: bool = False,
    ) -> Appearance:
        """Draw an image on a surface where ``mask`` is valid
        (:meth:`Backdrop.set_appearance`); every renderer sharing the backdrop
        sees it from its next render."""
        return self.backdrop.set_appearance(surface, image, mask, extent=extent, aligned=aligned)

    def clear_appearance(self, surface: str | None = None) -> None:
        """Return a surface (default: all) to the scenario's look."""
        self.backdrop.clear_appearance(surface)

    # -- background -----------------------------------------------------------

    @property
    def background(self) -> RenderResult:
        """The static background (read-only arrays), rendered on first use."""
        image, labels, _ = self._background()
        return RenderResult(image, labels, _EMPTY_BOXES,
                            MappingProxyType(label_names(self.scene, ())))

    @property
    def background_depth(self) -> NDArray[np.float32]:
        """The static background's depth (camera ``z`` of each pixel, ``inf`` where
        nothing is; read-only), of the same render as :attr:`background`."""
        return self._background()[2]

    def _background(self) -> tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float32]]:
        if self._bg is None or self._bg_version != self.backdrop.version:
            version = self.backdrop.version
            image, labels, depth = self.backdrop.render(self.camera, exact=self.exact)
            for a in (image, labels, depth):
                a.setflags(write=False)
            self._bg = (image, labels, depth)
            self._bg_version = version
        return self._bg

    # -- frames ---------------------------------------------------------------

    def render(
        self, state: WorldState | None = None, *, balls: Sequence[Ball] | None = None
    ) -> RenderResult:
        """Render the moving objects of ``state`` over the cached background.

        Parameters
        ----------
        state : WorldState, optional
            Default: the scene's initial state.
        balls : sequence of Ball, optional
            The ball records to draw (default the scene's); pass
            ``world.balls`` for a world that gained or lost balls at run time.
            A ball is drawn when ``state`` has a body of its name.
        """
        if state is None:
            state = initial_state(self.scene)
        drawn = self.scene.balls if balls is None else tuple(balls)
        bg_image, bg_labels, bg_depth = self._background()
        image = bg_image.copy()
        labels = bg_labels.copy()
        depth = bg_depth.copy()
        poses = {b.name: b for b in state.bodies}
        regions: list[tuple[str, int, tuple[int, int, int, int]]] = []
        robot = self.scene.robot
        if robot is not None and robot.name in poses:
            box = self._draw_robot(robot, poses[robot.name], image, labels, depth)
            if box is not None:
                regions.append((robot.name, LABEL_ROBOT, box))
        for ball in drawn:
            pose = poses.get(ball.name)
            if pose is not None:
                self._draw_shadow(ball, pose.position, image, bg_labels)
        for i, ball in enumerate(drawn):
            pose = poses.get(ball.name)
            if pose is not None:
                box = self._draw_ball(ball, pose, LABEL_BALL + i, image, labels, depth)
                if box is not None:
                    regions.append((ball.name, LABEL_BALL + i, box))
        boxes: dict[str, Box] = {}
        for name, label, (x0, y0, x1, y1) in regions:
            x, y, w, h = cv2.boundingRect((labels[y0:y1, x0:x1] == label).view(np.uint8))
            if w > 0:
                boxes[name] = (x0 + x, y0 + y, w, h)
        return RenderResult(image, labels, MappingProxyType(boxes),
                            MappingProxyType(label_names(self.scene, drawn)))

    def _sphere_bbox(self, center: FloatArray, radius: float) -> tuple[int, int, int, int] | None:
        cam = self.camera
        corners = center + radius * np.array(
            [[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float
        )
        pc = cam.to_camera(corners)
        if pc[:, 2].min() <= NEAR:
            return None
        return pixel_bbox(pc, cam)

    def _draw_ball(
        self,
        ball: Ball,
        pose: BodyState,
        label: int,
        image: NDArray[np.uint8],
        labels: NDArray[np.int32],
        depth: NDArray[np.float32],
    ) -> tuple[int, int, int, int] | None:
        cam = self.camera
        r = ball.radius
        center = np.array([pose.position[0], pose.position[1], r])
        box = self._sphere_bbox(center, r)
        if box is None:
            return None
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
            return None
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
        return box

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
    ) -> tuple[int, int, int, int] | None:
        ca, sa = math.cos(pose.angle), math.sin(pose.angle)
        x, y = pose.position
        outline = tuple(
            (x + ca * px - sa * py, y + sa * px + ca * py) for px, py in robot.outline()
        )
        if not self._prism_in_view(outline, robot.height):
            return None
        boxes = [draw_face(face, self.camera, image, labels, depth)
                 for face in prism_faces(outline, robot.height, robot.color, LABEL_ROBOT,
                                         self.camera.position)]
        drawn = [b for b in boxes if b is not None]
        if not drawn:
            return None
        return (min(b[0] for b in drawn), min(b[1] for b in drawn),
                max(b[2] for b in drawn), max(b[3] for b in drawn))

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
