"""Surfaces: every static plane of a scene, described in world metres.

A scene's static parts are planar convex faces: the floor, both sides of each
wall, and the side faces and top of each obstacle.  :func:`scene_surfaces`
describes each one as a :class:`Surface`; the renderer draws them and the
appearance learning of the Scene Background schema back-projects real frames
onto them (an :class:`~adapt.imagination.appearance.Appearance` is such an
image, drawn in place of the scenario's texture where it is valid).

Face coordinates (also in ``docs/conventions.md``): a surface is the set of
world points ``origin + s * u + t * v`` with ``(s, t)`` (metres) inside its
``polygon``; ``u`` and ``v`` are orthonormal, and ``normal = u x v`` points
to its front side.

=================  ===============  ============  ====  ==================
surface            origin           u             v     front (normal)
=================  ===============  ============  ====  ==================
``floor``          ``(0, 0, 0)``    ``+x``        +y    up (+z)
wall ``W``         ``from`` at z=0  along the     +z    right of from->to;
                                    wall                both sides drawn
``O/side<k>``      corner k at z=0  corner k to   +z    outwards
                                    corner k+1
``O/top``          ``(0, 0, h)``    ``+x``        +y    up
=================  ===============  ============  ====  ==================

A surface image (the image of an appearance, or what a camera frame
back-projects to) covers a rectangle ``extent = (s_min, t_min, s_max, t_max)``
of face coordinates edge to edge: its columns run with ``s`` and its rows run
*down* from ``t_max``, so a wall's image is upright and the floor's image is
a map with ``+y`` up.  Pixel centres follow the pixel convention: the centre
of pixel ``(col, row)`` is at ``s = s_min + (col + 0.5) * (s_max - s_min) /
width`` and ``t = t_max - (row + 0.5) * (t_max - t_min) / height``.

Examples
--------
>>> from adapt.imagination.scene import Obstacle, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 2), (2, 2), height=1.0),),
...                   obstacles=(Obstacle("box", ((0, 0), (1, 0), (1, 1), (0, 1)), height=0.5),))
>>> [s.name for s in scene_surfaces(scene)]
['floor', 'north', 'box/side0', 'box/side1', 'box/side2', 'box/side3', 'box/top']
>>> north = scene_surfaces(scene)[1]
>>> north.normal, north.polygon, north.point(1.0, 0.5)
((0.0, -1.0, 0.0), ((0.0, 0.0), (4.0, 0.0), (4.0, 1.0), (0.0, 1.0)), (-1.0, 2.0, 0.5))
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import ImaginationError
from adapt.geometry import MAX_COORDINATE, Camera
from adapt.imagination.scene import Color, SceneSpec

__all__ = [
    "Surface",
    "scene_surfaces",
    "check_extent",
    "LIGHT",
    "LABEL_SKY",
    "LABEL_FLOOR",
    "LABEL_WALL",
    "LABEL_OBSTACLE",
    "LABEL_BALL",
    "LABEL_ROBOT",
]

Vec3 = tuple[float, float, float]
Extent = tuple[float, float, float, float]
FloatArray = NDArray[np.float64]

LABEL_SKY = 0
LABEL_FLOOR = 1
LABEL_WALL = 1000
LABEL_OBSTACLE = 2000
LABEL_BALL = 3000
LABEL_ROBOT = 4000

#: Direction towards the light (world), fixed.  Each surface is shaded by
#: ``0.6 + 0.4 * max(normal . LIGHT, 0)`` (two-sided walls by ``|normal . LIGHT|``).
LIGHT = np.array([0.35, -0.55, 0.76]) / np.linalg.norm([0.35, -0.55, 0.76])
LIGHT.setflags(write=False)


def _vec3(v: ArrayLike) -> Vec3:
    a = np.asarray(v, dtype=float).reshape(3)
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True, slots=True, eq=False)
class Surface:
    """One static planar face of a scene (see the module docstring).

    Attributes
    ----------
    name : str
        ``"floor"``, a wall's name, or ``"<obstacle>/side<k>"`` and
        ``"<obstacle>/top"``.
    label : int
        Its id in the label image (``1``, ``1000 + i``, ``2000 + i``).
    owner : str
        The scene object it belongs to (``"floor"``, the wall or obstacle name).
    origin, u, v : (x, y, z)
        The plane: world point ``origin + s * u + t * v``; ``u``, ``v`` unit
        and orthogonal.
    polygon : tuple of (s, t), or None
        The face, convex and counter-clockwise in ``(s, t)``; ``None`` for a
        floor without ``extent`` (the whole plane).
    two_sided : bool
        Whether it is drawn from behind too (walls) or only from the side
        ``normal`` points to.
    texture, tile, color
        The scenario's appearance (see :class:`~adapt.imagination.scene.Wall`).
    """

    name: str
    label: int
    owner: str
    origin: Vec3
    u: Vec3
    v: Vec3
    polygon: tuple[tuple[float, float], ...] | None
    two_sided: bool
    texture: str | None
    tile: float
    color: Color

    @property
    def normal(self) -> Vec3:
        """``u x v``: the direction of the front side."""
        return _vec3(np.cross(self.u, self.v))

    @property
    def shade(self) -> float:
        """Brightness factor of the fixed light on this surface (0.6 to 1)."""
        cos = float(np.dot(self.normal, LIGHT))
        if self.two_sided:
            cos = abs(cos)
        return 0.6 + 0.4 * max(cos, 0.0)

    @property
    def extent(self) -> Extent | None:
        """``(s_min, t_min, s_max, t_max)`` of the polygon; ``None`` if unbounded."""
        if self.polygon is None:
            return None
        s = [p[0] for p in self.polygon]
        t = [p[1] for p in self.polygon]
        return (min(s), min(t), max(s), max(t))

    def point(self, s: float, t: float) -> Vec3:
        """The world point at face coordinates ``(s, t)``."""
        return _vec3(np.asarray(self.origin) + s * np.asarray(self.u) + t * np.asarray(self.v))

    def to_world(self, st: ArrayLike) -> FloatArray:
        """World points ``(N, 3)`` of face coordinates ``(N, 2)``."""
        p = np.asarray(st, dtype=float).reshape(-1, 2)
        return np.asarray(self.origin) + p[:, :1] * np.asarray(self.u) + p[:, 1:] * np.asarray(self.v)

    def to_face(self, points: ArrayLike) -> FloatArray:
        """Face coordinates ``(N, 2)`` of world points ``(N, 3)`` (projected onto the plane)."""
        d = np.asarray(points, dtype=float).reshape(-1, 3) - np.asarray(self.origin)
        return np.stack([d @ np.asarray(self.u), d @ np.asarray(self.v)], axis=1)

    def seen_from(self, position: ArrayLike) -> bool:
        """Whether a camera centred at ``position`` can see this surface's drawn side.

        False when the camera is in the surface's plane, or behind a
        one-sided surface.
        """
        d = float(np.dot(np.asarray(position, dtype=float) - np.asarray(self.origin), self.normal))
        return d > 1e-9 or (self.two_sided and d < -1e-9)

    def homography(self, camera: Camera) -> FloatArray:
        """The 3x3 homography from face coordinates ``(s, t, 1)`` to camera pixels.

        ``K [R u | R v | R (origin - C)]``.
        """
        r = camera.rotation
        m = np.column_stack([r @ np.asarray(self.u), r @ np.asarray(self.v),
                             r @ (np.asarray(self.origin) - camera.position)])
        return camera.K @ m

    def image_to_face(self, size: tuple[int, int], extent: Extent | None = None) -> FloatArray:
        """The 3x3 affine map from surface-image pixels ``(col, row, 1)`` to face
        coordinates ``(s, t, 1)``, for an image of ``size = (width, height)``
        covering ``extent`` (default the polygon's).

        Examples
        --------
        >>> from adapt.imagination.scene import SceneSpec, Wall
        >>> wall = scene_surfaces(SceneSpec(walls=(Wall("w", (0, 0), (2, 0), height=1.0),)))[1]
        >>> (wall.image_to_face((200, 100)) @ [0, 0, 1]).round(3).tolist()  # top-left pixel
        [0.005, 0.995, 1.0]
        """
        e = self._extent_or(extent)
        w, h = int(size[0]), int(size[1])
        if w < 1 or h < 1:
            raise ImaginationError(f"size: expected a positive width and height, got {size!r}")
        sx, sy = (e[2] - e[0]) / w, (e[3] - e[1]) / h
        return np.array([[sx, 0.0, e[0] + 0.5 * sx], [0.0, -sy, e[3] - 0.5 * sy], [0.0, 0.0, 1.0]])

    def image_homography(
        self, camera: Camera, size: tuple[int, int], extent: Extent | None = None
    ) -> FloatArray:
        """The 3x3 homography from surface-image pixels to camera pixels.

        A camera frame back-projects onto the surface with
        ``cv2.warpPerspective(frame, H, size, flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP)``;
        use the render's label image to keep only the pixels where this
        surface is what the camera sees.
        """
        return self.homography(camera) @ self.image_to_face(size, extent)

    def _extent_or(self, extent: Extent | None) -> Extent:
        if extent is None:
            if self.polygon is None:
                raise ImaginationError(
                    f"extent: surface {self.name!r} is unbounded (a floor without extent); "
                    "give the extent [s_min, t_min, s_max, t_max] the image covers"
                )
            return self.extent  # type: ignore[return-value]
        return check_extent(extent)


def check_extent(extent: Sequence[float]) -> Extent:
    """``extent`` as ``(s_min, t_min, s_max, t_max)``, checked (finite, ordered, bounded)."""
    try:
        e = [float(x) for x in extent]
    except (TypeError, ValueError):
        raise ImaginationError(
            f"extent: expected [s_min, t_min, s_max, t_max] in metres, got {extent!r}"
        ) from None
    if len(e) != 4 or not all(math.isfinite(x) for x in e) or e[0] >= e[2] or e[1] >= e[3]:
        raise ImaginationError(
            f"extent: expected [s_min, t_min, s_max, t_max] with min < max, got {extent!r}"
        )
    if max(abs(x) for x in e) > MAX_COORDINATE:
        raise ImaginationError(
            f"extent: expected values within +-{MAX_COORDINATE:g} metres, got {e}"
        )
    return (e[0], e[1], e[2], e[3])


def scene_surfaces(scene: SceneSpec) -> tuple[Surface, ...]:
    """Every static surface of ``scene``: the floor, the walls, then each
    obstacle's sides (corner ``k`` to ``k + 1`` of its counter-clockwise
    polygon) and top.

    Raises
    ------
    ImaginationError
        If a derived surface name (``"<obstacle>/top"``) collides with another
        object's name.
    """
    ex, ey, ez = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    out: list[Surface] = []
    fl = scene.floor
    floor_poly = None
    if fl.extent is not None:
        x0, y0, x1, y1 = fl.extent
        floor_poly = ((x0, y0), (x1, y0), (x1, y1), (x0, y1))
    out.append(Surface("floor", LABEL_FLOOR, "floor", (0.0, 0.0, 0.0), ex, ey, floor_poly,
                       False, fl.texture, fl.tile, fl.color))
    for i, wall in enumerate(scene.walls):
        a = np.array([*wall.start, 0.0])
        d = np.array([*wall.end, 0.0]) - a
        length = float(np.linalg.norm(d))
        poly = ((0.0, 0.0), (length, 0.0), (length, wall.height), (0.0, wall.height))
        out.append(Surface(wall.name, LABEL_WALL + i, wall.name, _vec3(a), _vec3(d / length), ez,
                           poly, True, wall.texture, wall.tile, wall.color))
    for i, ob in enumerate(scene.obstacles):
        n = len(ob.polygon)
        for k in range(n):
            a = np.array([*ob.polygon[k], 0.0])
            d = np.array([*ob.polygon[(k + 1) % n], 0.0]) - a
            length = float(np.linalg.norm(d))
            poly = ((0.0, 0.0), (length, 0.0), (length, ob.height), (0.0, ob.height))
            out.append(Surface(f"{ob.name}/side{k}", LABEL_OBSTACLE + i, ob.name, _vec3(a),
                               _vec3(d / length), ez, poly, False, ob.texture, ob.tile, ob.color))
        out.append(Surface(f"{ob.name}/top", LABEL_OBSTACLE + i, ob.name, (0.0, 0.0, ob.height),
                           ex, ey, tuple(ob.polygon), False, ob.texture, ob.tile, ob.color))
    names = [s.name for s in out]
    for s in out:
        if names.count(s.name) > 1:
            raise ImaginationError(
                f"name: surface name {s.name!r} is used twice; rename the object called {s.name!r}"
            )
    return tuple(out)
