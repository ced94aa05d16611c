"""The look of the scene, learned from camera frames.

A scenario knows the geometry of a room (the floor, the walls, the
obstacles) but rarely the exact look of every surface: its tint, its
lighting, where the texture's pattern starts.  The paper textured its walls
by hand with "camera imagery, unwarped"; :class:`AppearanceModel` does it
from the frames, so that the imagination's render looks like the camera's
image and the match-mediated difference shows only what the imagination does
not explain.

**Planes.**  Every surface is a plane, so the camera maps the surface's image
(its face coordinates, ``docs/conventions.md``) to pixels by a homography
(:meth:`Surface.image_homography <adapt.imagination.Surface.image_homography>`).
What lies beyond the surfaces (the render's sky: whatever the scenario does
not model) is learned too, by viewing direction, on the six faces of a cube
around the camera at infinity; each face maps to the image by the
homography ``K R R_f^T K_f^-1`` of a rotation, so it is learned the same way.
:meth:`AppearanceModel.composite` paints the learned sky into a render.

**Back-projection.**  One ``cv2.warpPerspective`` with ``WARP_INVERSE_MAP``
samples the frame at every pixel of a plane's image (only the box that the
view covers).  A pixel of the plane's image is *seen* when it is in front of
the camera, inside the surface's polygon, and its frame pixel shows that
surface (or the sky) in the render's label image, at least ``margin`` pixels
from the label's edge, and is not excluded.  An obstacle's faces share one
label; a point of a face the camera sees whose pixel carries the obstacle's
label *is* what the camera sees there, because the obstacle is convex.

**Accumulation.**  Each plane keeps a float image and a count of the updates
each pixel took.  A pixel seen for the first time takes the frame's value; a
pixel seen before moves the fraction ``rate`` towards it (at least ``1 / n``
on the plane's ``n``-th update, so the first updates average), so sensor
noise averages out and a slow lighting drift is absorbed; a pixel that
differs from what was learned by more than ``gate`` grey levels is left
alone (something that is not the background, or a change too sudden to be
lighting).  The caller excludes what a schema monitors and every unexpected
region.

**Resolution.**  A surface's image is made when it is first seen, covering
what is seen of it with a margin of :data:`SEEN_MARGIN` (cut to its
polygon's extent; it grows, on the same pixel grid, as more is seen), at the
resolution the view needs: the camera's pixels per metre where the surface is
nearest, at most :data:`MAX_PIXELS_PER_METRE` and :data:`MAX_SURFACE_PIXELS`
pixels.  A sky face has half the camera's resolution at its centre (the sky
beyond a room is smooth), at most :data:`MAX_SKY_SIDE` pixels a side.

Invariants: the model never changes a renderer by itself; :meth:`apply`
hands each surface changed since the last call to
:meth:`Renderer.set_appearance <adapt.imagination.Renderer.set_appearance>`.
A surface nothing has seen keeps the scenario's texture or colour, and so do
the unseen pixels of a surface; the sky keeps the renderer's where unseen.

Examples
--------
>>> from adapt.geometry import Camera
>>> from adapt.imagination import Renderer, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 2), (2, 2), height=1.0, texture="builtin:brick"),))
>>> cam = Camera.look_at(fx=200, fy=200, cx=79.5, cy=59.5, width=160, height=120,
...                      position=(0, -1, 0.5), look_at=(0, 2, 0.4))
>>> renderer = Renderer(scene, cam)
>>> frame = renderer.background
>>> real = np.full_like(frame.image, (40, 160, 90))       # a green wall, grey floor
>>> real[frame.labels == 1] = 128
>>> model = AppearanceModel(renderer.surfaces)
>>> learned = model.learn(real, cam, frame.labels)
>>> sorted(learned.surfaces)
['floor', 'north', 'sky/+y']
>>> model.apply(renderer)
('floor', 'north')
>>> inner = cv2.erode((frame.labels == 1000).astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
>>> wall = renderer.background.image[inner]          # the wall, away from its edges
>>> bool(np.abs(wall.astype(int) - (40, 160, 90)).max() <= 1)
True
>>> sky = model.composite(renderer.background.image, frame.labels, cam)[frame.labels == 0]
>>> bool(np.abs(sky.astype(int) - (40, 160, 90)).max() <= 1)   # the sky, learned too
True
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping, Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.errors import AppearanceError
from adapt.files import write_atomic
from adapt.geometry import MAX_COORDINATE, Camera
from adapt.imagination import LABEL_BALL, LABEL_FLOOR, LABEL_SKY, Renderer, Surface
from adapt.native import native_messages

__all__ = [
    "AppearanceModel",
    "LearnedTexture",
    "Learning",
    "SKY_FACES",
    "INDEX",
    "FORMAT",
    "MAX_PIXELS_PER_METRE",
    "MIN_PIXELS_PER_METRE",
    "MAX_SURFACE_PIXELS",
    "MAX_SKY_SIDE",
    "FLOOR_REACH",
    "SEEN_MARGIN",
]

FloatArray = NDArray[np.float64]
Extent = tuple[float, float, float, float]

#: Finest resolution of a learned surface image, pixels per metre.
MAX_PIXELS_PER_METRE = 400.0
#: Coarsest resolution of a learned surface image, pixels per metre.
MIN_PIXELS_PER_METRE = 20.0
#: Most pixels of one learned surface image.
MAX_SURFACE_PIXELS = 500_000
#: Largest side of a sky face's image, pixels.
MAX_SKY_SIDE = 1024
#: An unbounded floor is learned at most this far (metres) from the camera.
FLOOR_REACH = 10.0
#: Metres added around what is seen of a surface when its image is made or grown.
SEEN_MARGIN = 0.5
#: Fewer seen frame pixels than this on a label: nothing is learned there.
MIN_SEEN_PIXELS = 25
#: The file that lists a saved model's planes, and its ``format`` value.
INDEX = "index.json"
FORMAT = "adapt-appearance"
VERSION = 1
#: Labels present in a frame are found on every ``_SAMPLE``-th row and column.
_SAMPLE = 4
#: Replicated pixels around the frame while learning.
_PAD = 2
#: Grey levels a plane's learned image may drift (the mean change of the
#: pixels updated, summed over passes) before it is handed on again.
_DRIFT = 0.5


def _face_rotation(forward: tuple[int, int, int], down: tuple[int, int, int]) -> FloatArray:
    """World-to-face rotation: rows are the face camera's right, down and forward."""
    f, d = np.array(forward, float), np.array(down, float)
    return np.array([np.cross(d, f), d, f])


#: The sky cube's faces: name -> world-to-face rotation (``+y``: looking along +y).
SKY_FACES: Mapping[str, FloatArray] = MappingProxyType({
    "sky/+x": _face_rotation((1, 0, 0), (0, 0, -1)),
    "sky/-x": _face_rotation((-1, 0, 0), (0, 0, -1)),
    "sky/+y": _face_rotation((0, 1, 0), (0, 0, -1)),
    "sky/-y": _face_rotation((0, -1, 0), (0, 0, -1)),
    "sky/+z": _face_rotation((0, 0, 1), (0, 1, 0)),
    "sky/-z": _face_rotation((0, 0, -1), (0, -1, 0)),
})
#: The extent of a sky face's image: the tangents of its 90-degree view.
SKY_EXTENT: Extent = (-1.0, -1.0, 1.0, 1.0)


@dataclass(frozen=True, slots=True, eq=False)
class LearnedTexture:
    """What has been learned of one plane (a surface, or a face of the sky).

    Attributes
    ----------
    name : str
        The surface (or ``sky/+x`` ... ``sky/-z``).
    image : (H, W, 3) uint8 ndarray
        BGR in the surface's face coordinates (``docs/conventions.md``; a sky
        face: as its camera looking out along its axis sees it); black where
        unseen.
    mask : (H, W) bool ndarray
        Seen pixels.
    extent : (s_min, t_min, s_max, t_max)
        Face coordinates the image covers, metres (a sky face: tangents,
        ``(-1, -1, 1, 1)``).
    updates : int
        Learning passes that changed it.
    """

    name: str
    image: NDArray[np.uint8] = field(repr=False)
    mask: NDArray[np.bool_] = field(repr=False)
    extent: Extent
    updates: int = 0

    @property
    def sky(self) -> bool:
        """A face of the sky, not a surface."""
        return self.name in SKY_FACES

    @property
    def coverage(self) -> float:
        """The share of the image seen."""
        return float(np.count_nonzero(self.mask)) / max(self.mask.size, 1)

    @property
    def pixels_per_metre(self) -> tuple[float, float]:
        """Resolution along ``s`` and ``t`` (a sky face: pixels per unit tangent)."""
        h, w = self.mask.shape
        e = self.extent
        return (w / (e[2] - e[0]), h / (e[3] - e[1]))

    def preview(self, max_side: int = 160) -> NDArray[np.uint8]:
        """A small BGRA copy (at most ``max_side`` pixels a side), transparent where unseen."""
        h, w = self.mask.shape
        f = min(1.0, max_side / float(max(h, w)))
        size = (max(1, int(round(w * f))), max(1, int(round(h * f))))
        bgra = cv2.cvtColor(self.image, cv2.COLOR_BGR2BGRA)
        bgra[:, :, 3] = self.mask.view(np.uint8) * np.uint8(255)
        return np.asarray(cv2.resize(bgra, size, interpolation=cv2.INTER_AREA), np.uint8)


@dataclass(frozen=True, slots=True)
class Learning:
    """What one :meth:`AppearanceModel.learn` pass did.

    Attributes
    ----------
    surfaces : mapping of str to int
        Plane-image pixels updated, per plane (planes not seen are absent).
    new : int
        Of those, pixels seen for the first time.
    ms : float
        Its cost, milliseconds.
    """

    surfaces: Mapping[str, int]
    new: int
    ms: float


class _Plane:
    """The learning state of one plane (see the module docstring)."""

    def __init__(self, name: str, extent: Extent, size: tuple[int, int],
                 inside: NDArray[np.uint8] | None = None) -> None:
        self.name = name
        self.extent = extent
        w, h = size
        self.size = (w, h)
        self.image = np.zeros((h, w, 3), np.float32)
        self.count = np.zeros((h, w), np.uint16)
        #: 255 where a learning pass saw the plane but was told to leave it (an object
        #: covered it) while it was still unlearned: see :meth:`AppearanceModel.hidden`.
        self.hidden = np.zeros((h, w), np.uint8)
        self.inside = inside
        self.updates = 0
        self.drift = 0.0
        self.dirty = False

    def to_pixels(self, camera: Camera) -> FloatArray:  # pragma: no cover - abstract
        """Plane-image pixels to ``camera``'s pixels."""
        raise NotImplementedError

    def texture(self) -> LearnedTexture:
        seen = cv2.compare(self.count, 0, cv2.CMP_GT)  # type: ignore[call-overload]
        image = np.asarray(cv2.copyTo(cv2.convertScaleAbs(self.image), seen), np.uint8)  # zero where unseen
        mask = seen > 0
        image.setflags(write=False)
        mask.setflags(write=False)
        return LearnedTexture(self.name, image, mask, self.extent, self.updates)


class _SurfacePlane(_Plane):
    """A scene surface's image over ``extent``."""

    def __init__(self, surface: Surface, extent: Extent, size: tuple[int, int]) -> None:
        super().__init__(surface.name, extent, size, _inside(surface, extent, size))
        self.surface = surface
        self.to_face = surface.image_to_face(size, extent)

    def to_pixels(self, camera: Camera) -> FloatArray:
        return np.asarray(self.surface.homography(camera) @ self.to_face)


def _sky_to_pixels(name: str, n: int, camera: Camera) -> FloatArray:
    """Pixels of the ``n`` x ``n`` image of sky face ``name`` to ``camera``'s pixels:
    ``K R R_f^T K_f^-1`` (a direction seen by both)."""
    f = n / 2.0
    k_inv = np.array([[1.0 / f, 0.0, -(f - 0.5) / f], [0.0, 1.0 / f, -(f - 0.5) / f],
                      [0.0, 0.0, 1.0]])
    return np.asarray(camera.K @ camera.rotation @ SKY_FACES[name].T @ k_inv)


class _SkyPlane(_Plane):
    """A face of the sky cube: an ``n`` x ``n`` image of a 90-degree view."""

    def __init__(self, name: str, n: int) -> None:
        super().__init__(name, SKY_EXTENT, (n, n))

    def to_pixels(self, camera: Camera) -> FloatArray:
        return _sky_to_pixels(self.name, self.size[0], camera)


def _halved(plane: _SurfacePlane) -> _SurfacePlane:
    """The same surface's plane at half the resolution over (about) the same extent: an
    odd last row or column is made whole by growing the extent by one texel."""
    e = plane.extent
    w, h = plane.size
    px, py = (e[2] - e[0]) / w, (e[3] - e[1]) / h
    ew, eh = w + w % 2, h + h % 2
    image = cv2.copyMakeBorder(plane.image, h % 2, 0, 0, w % 2, cv2.BORDER_CONSTANT, value=0)
    count = cv2.copyMakeBorder(plane.count, h % 2, 0, 0, w % 2, cv2.BORDER_CONSTANT, value=0)
    # rows run down from t_max: a new row is added at the top, at t_max + py
    extent = (e[0], e[1], e[2] + (w % 2) * px, e[3] + (h % 2) * py)
    out = _SurfacePlane(plane.surface, extent, (ew // 2, eh // 2))
    seen = (count > 0).astype(np.float32)
    weight = cv2.resize(seen, out.size, interpolation=cv2.INTER_AREA)
    total = cv2.resize(image * seen[:, :, None], out.size, interpolation=cv2.INTER_AREA)
    ok = weight > 0
    out.image[ok] = total[ok] / weight[ok][:, None]
    out.count[ok] = np.maximum(1, cv2.resize(count, out.size, interpolation=cv2.INTER_NEAREST)[ok])
    hidden = cv2.copyMakeBorder(plane.hidden, h % 2, 0, 0, w % 2, cv2.BORDER_CONSTANT, value=0)
    out.hidden[:] = cv2.resize(hidden, out.size, interpolation=cv2.INTER_NEAREST)
    out.updates = plane.updates
    out.dirty = True
    return out


def _inside(surface: Surface, extent: Extent, size: tuple[int, int]) -> NDArray[np.uint8] | None:
    """Surface-image pixels inside the surface's polygon, 255 (None: all of them)."""
    poly = surface.polygon
    if poly is None:
        return None
    e = surface.extent
    assert e is not None
    rect = len(poly) == 4 and all(
        (abs(s - e[0]) < 1e-12 or abs(s - e[2]) < 1e-12) and
        (abs(t - e[1]) < 1e-12 or abs(t - e[3]) < 1e-12) for s, t in poly)
    if rect and e[0] <= extent[0] and e[1] <= extent[1] and e[2] >= extent[2] and e[3] >= extent[3]:
        return None
    w, h = size
    to_px = np.linalg.inv(surface.image_to_face((w, h), extent))
    st = np.c_[np.asarray(poly, float), np.ones(len(poly))] @ to_px.T
    pts = np.round(st[:, :2] / st[:, 2:] * 256).astype(np.int32)  # pixel centres, 8 fraction bits
    inside = np.zeros((h, w), np.uint8)
    cv2.fillConvexPoly(inside, pts, 255, cv2.LINE_8, 8)
    return inside


def _check_image(image: Any, labels: Any, exclude: Any, camera: Camera) -> None:
    if not (isinstance(image, np.ndarray) and image.ndim == 3 and image.shape[2] == 3
            and image.dtype == np.uint8):
        raise AppearanceError("image: expected a BGR uint8 image of shape (H, W, 3), got "
                              f"{getattr(image, 'shape', None)} {getattr(image, 'dtype', None)}")
    hw = image.shape[:2]
    if hw != (camera.height, camera.width):
        raise AppearanceError(f"image: expected the camera's {camera.width}x{camera.height}, "
                              f"got {hw[1]}x{hw[0]}")
    if not isinstance(labels, np.ndarray) or labels.shape != hw:
        raise AppearanceError(f"labels: expected shape {hw} (the image's), got "
                              f"{getattr(labels, 'shape', None)}")
    if exclude is not None and (not isinstance(exclude, np.ndarray) or exclude.shape != hw):
        raise AppearanceError(f"exclude: expected shape {hw} (the image's), got "
                              f"{getattr(exclude, 'shape', None)}")


def _in_plane(points: FloatArray, m: FloatArray) -> FloatArray:
    """Frame pixels ``(N, 2)`` in the plane image whose pixels ``m`` maps to the frame,
    keeping those in front of the camera."""
    try:
        inv = np.linalg.inv(m)
    except np.linalg.LinAlgError:
        return np.empty((0, 2))
    q = np.c_[points, np.ones(len(points))] @ inv.T
    with np.errstate(divide="ignore", invalid="ignore"):
        st = q[:, :2] / q[:, 2:]
    st = st[np.isfinite(st).all(axis=1)]
    return st[np.c_[st, np.ones(len(st))] @ m[2] > 0]


class AppearanceModel:
    """Learned images of a scene's surfaces and of what lies beyond them (see
    the module docstring).

    Parameters
    ----------
    surfaces : sequence of Surface
        The scene's static surfaces (``renderer.surfaces``).
    max_pixels_per_metre, max_surface_pixels : float, int
        Bounds of a surface image's resolution and size.
    sky : bool
        Learn the sky (what the render shows beyond the surfaces) too.
    """

    def __init__(self, surfaces: Sequence[Surface], *,
                 max_pixels_per_metre: float = MAX_PIXELS_PER_METRE,
                 max_surface_pixels: int = MAX_SURFACE_PIXELS, sky: bool = True) -> None:
        self.surfaces = tuple(surfaces)
        self._by_label: dict[int, list[Surface]] = {}
        for s in self.surfaces:
            self._by_label.setdefault(s.label, []).append(s)
        self._names = {s.name: s for s in self.surfaces}
        self.sky = sky and not any(name in self._names for name in SKY_FACES)
        self.max_pixels_per_metre = float(max_pixels_per_metre)
        self.max_surface_pixels = int(max_surface_pixels)
        self._planes: dict[str, _Plane] = {}
        self.passes = 0
        #: Increases whenever the learned sky changes (for callers caching a composite).
        self.sky_version = 0
        self._sky_cache: tuple[tuple[Any, ...], NDArray[np.uint8], NDArray[np.uint8]] | None = None

    # -- what is known ------------------------------------------------------------------

    def __contains__(self, name: object) -> bool:
        return name in self._planes

    @property
    def learned(self) -> tuple[str, ...]:
        """Names of the planes with a learned image: surfaces in scene order, then the sky's faces."""
        order = [s.name for s in self.surfaces] + list(SKY_FACES)
        return tuple(n for n in order if n in self._planes)

    def texture(self, name: str) -> LearnedTexture | None:
        """What has been learned of plane ``name`` (None: nothing yet)."""
        plane = self._planes.get(name)
        return None if plane is None else plane.texture()

    def textures(self) -> dict[str, LearnedTexture]:
        """Every learned plane's texture (:attr:`learned` order)."""
        return {name: self._planes[name].texture() for name in self.learned}

    def unseen(self, camera: Camera, labels: NDArray[np.integer],
               box: tuple[int, int, int, int] | None = None) -> NDArray[np.bool_]:
        """Which pixels of ``labels`` (the render's label image through ``camera``) show a
        surface where its look was never learned -- the floor an object covered when the
        look was first learned, a face no frame has shown -- so that the render there is
        the scenario's guess, not the scene.  The sky and the moving objects are never
        unseen.

        Parameters
        ----------
        camera : Camera
            The camera ``labels`` was rendered through.
        labels : (H, W) int ndarray
            The render's label image.
        box : (x, y, w, h), optional
            Only these pixels (the result has the box's shape); the whole image without.

        Examples
        --------
        >>> from adapt.imagination import Renderer, SceneSpec
        >>> cam = Camera.look_at(fx=100, fy=100, cx=39.5, cy=29.5, width=80, height=60,
        ...                      position=(0, -2, 1.5), look_at=(0, 0, 0))
        >>> frame = Renderer(SceneSpec(), cam).background
        >>> model = AppearanceModel(Renderer(SceneSpec(), cam).surfaces)
        >>> bool(model.unseen(cam, frame.labels)[frame.labels == LABEL_FLOOR].all())
        True
        >>> hidden = np.zeros(frame.labels.shape, bool)
        >>> hidden[40:50, 30:50] = True                  # something stood there
        >>> _ = model.learn(np.full((60, 80, 3), 90, np.uint8), cam, frame.labels, exclude=hidden)
        >>> unseen = model.unseen(cam, frame.labels)
        >>> bool(unseen[42:48, 32:48].all()), int(unseen[:30].sum())
        (True, 0)
        """
        return self._texel_pixels(
            camera, labels, box, lambda plane: np.asarray(cv2.compare(  # type: ignore[call-overload]
                plane.count, 0, cv2.CMP_GT), np.uint8), where=False)

    def hidden(self, camera: Camera, labels: NDArray[np.integer],
               box: tuple[int, int, int, int] | None = None) -> NDArray[np.bool_]:
        """Which pixels of ``labels`` show a surface where its look is unlearned because an
        object covered it when a pass saw it (``learn``'s ``covered``: a ball rolling
        through the first look) -- background to learn once what covered it has gone,
        unlike a face no frame has shown (:meth:`unseen`, of which these pixels are a
        part), or one a pass left for another reason.

        Parameters
        ----------
        camera : Camera
            The camera ``labels`` was rendered through.
        labels : (H, W) int ndarray
            The render's label image.
        box : (x, y, w, h), optional
            Only these pixels (the result has the box's shape); the whole image without.

        Examples
        --------
        >>> from adapt.imagination import Renderer, SceneSpec
        >>> cam = Camera.look_at(fx=100, fy=100, cx=39.5, cy=29.5, width=80, height=60,
        ...                      position=(0, -2, 1.5), look_at=(0, 0, 0))
        >>> frame = Renderer(SceneSpec(), cam).background
        >>> model = AppearanceModel(Renderer(SceneSpec(), cam).surfaces)
        >>> ball = np.zeros(frame.labels.shape, bool)
        >>> ball[40:50, 30:50] = True                     # something rolled there
        >>> _ = model.learn(np.full((60, 80, 3), 90, np.uint8), cam, frame.labels, covered=ball)
        >>> hidden = model.hidden(cam, frame.labels)
        >>> bool(hidden[42:48, 32:48].all()), int(hidden[:30].sum())
        (True, 0)
        >>> _ = model.learn(np.full((60, 80, 3), 90, np.uint8), cam, frame.labels)  # it left
        >>> int(model.hidden(cam, frame.labels).sum())
        0
        """
        return self._texel_pixels(
            camera, labels, box, lambda plane: None if not plane.hidden.any() else np.asarray(
                cv2.bitwise_and(plane.hidden, cv2.compare(  # type: ignore[call-overload]
                    plane.count, 0, cv2.CMP_EQ)), np.uint8), where=True)

    def _texel_pixels(self, camera: Camera, labels: NDArray[np.integer],
                      box: tuple[int, int, int, int] | None,
                      texels: Callable[[_Plane], NDArray[np.uint8] | None], *,
                      where: bool) -> NDArray[np.bool_]:
        """The pixels of ``labels`` (cut to ``box``) showing a surface where the texels
        ``texels(plane)`` marks (255; None: none) of its planes land through ``camera``
        (``where``), or where none does (not ``where``)."""
        h, w = labels.shape[:2]
        x0, y0, bw, bh = (0, 0, w, h) if box is None else box
        x0, y0 = max(0, int(x0)), max(0, int(y0))
        x1, y1 = min(w, x0 + int(bw)), min(h, y0 + int(bh))
        sub = np.asarray(labels[y0:y1, x0:x1])
        out = np.zeros(sub.shape, bool)
        if not sub.size:
            return out
        to_box = np.array([[1.0, 0.0, -x0], [0.0, 1.0, -y0], [0.0, 0.0, 1.0]])
        for label in np.unique(sub).tolist():
            if not LABEL_FLOOR <= label < LABEL_BALL or label not in self._by_label:
                continue
            marked = np.zeros(sub.shape, np.uint8)
            for surface in self._by_label[label]:
                plane = self._planes.get(surface.name)
                if plane is None or not surface.seen_from(camera.position):
                    continue
                mask = texels(plane)
                if mask is not None:
                    marked |= np.asarray(cv2.warpPerspective(
                        mask, to_box @ plane.to_pixels(camera), (x1 - x0, y1 - y0),
                        flags=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT,
                        borderValue=0), np.uint8)
            out |= (sub == label) & ((marked > 0) if where else (marked == 0))
        return out

    def coverage(self) -> dict[str, float]:
        """The share of each learned plane's image that has been seen."""
        return {name: float(np.count_nonzero(self._planes[name].count))
                / self._planes[name].count.size for name in self.learned}

    # -- learning -----------------------------------------------------------------------

    def learn(self, image: NDArray[np.uint8], camera: Camera, labels: NDArray[np.integer], *,
              exclude: NDArray[np.bool_] | None = None, margin: float = 0.0, rate: float = 0.1,
              gate: float | None = None, relearn: NDArray[np.bool_] | None = None,
              new_only: bool = False, covered: NDArray[np.bool_] | None = None) -> Learning:
        """Back-project ``image`` onto every plane ``camera`` sees and learn it.

        Parameters
        ----------
        image : (H, W, 3) uint8 ndarray
            The real frame (BGR), the camera's size.
        camera : Camera
            The pose it was seen from (the synchronised synthetic camera).
        labels : (H, W) int ndarray
            The render's label image for ``camera``: which surface (or moving
            object, or sky) each pixel shows.
        exclude : (H, W) bool ndarray, optional
            Pixels never to learn (what a schema monitors, unexpected regions).
        margin : float
            Pixels next to a label's edge that are not learned.
        rate : float
            Fraction in (0, 1] a seen pixel moves towards the frame per pass.
        gate : float, optional
            Grey levels: a pixel seen before that differs more than this (in
            any channel) is not updated.
        relearn : (H, W) bool ndarray, optional
            Pixels whose texels are learned afresh, taking the frame's value
            whatever was learned before and past the ``gate`` (background
            that an object covered when it was learned, seen uncovered since).
        new_only : bool
            Learn only texels never learned (a view a camera on the robot turned
            to: what was learned stays as it is).
        covered : (H, W) bool ndarray, optional
            Pixels an object covered in ``image`` (excluded too): their texels,
            while unlearned, are marked :meth:`hidden` (a ball rolling through the
            frames a first look is learned from).

        Raises
        ------
        AppearanceError
            If the image, labels or mask do not fit the camera, or ``rate``
            is not in (0, 1].
        """
        started = time.perf_counter()
        _check_image(image, labels, exclude, camera)
        if relearn is not None:
            _check_image(image, labels, relearn, camera)
        if covered is not None:
            _check_image(image, labels, covered, camera)
            exclude = covered if exclude is None else (exclude.astype(bool) | covered)
        if not 0.0 < rate <= 1.0:
            raise AppearanceError(f"rate: expected a fraction in (0, 1], got {rate!r}")
        keep = None if exclude is None else (~exclude.astype(bool)).view(np.uint8)
        hid = None if covered is None or not covered.any() else covered.astype(np.uint8)
        anew = None if relearn is None or not relearn.any() else np.asarray(
            cv2.copyMakeBorder(relearn.astype(np.uint8), _PAD, _PAD, _PAD, _PAD,
                               cv2.BORDER_CONSTANT, value=0), np.uint8)
        m = max(0, int(math.ceil(margin)))
        kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * m + 1, 2 * m + 1)) if m else None
        present = np.unique(labels[::_SAMPLE, ::_SAMPLE]).tolist()
        # The frame and the regions get a border of _PAD replicated pixels, so
        # that the texels at the frame's edge are learned too (renders sample them).
        pad = np.asarray(cv2.copyMakeBorder(image, _PAD, _PAD, _PAD, _PAD, cv2.BORDER_REPLICATE), np.uint8)
        shift = np.array([[1.0, 0.0, _PAD], [0.0, 1.0, _PAD], [0.0, 0.0, 1.0]])
        done: dict[str, int] = {}
        new = 0
        for label in present:
            if label == LABEL_SKY:
                if not self.sky:
                    continue
            elif not LABEL_FLOOR <= label < LABEL_BALL or label not in self._by_label:
                continue
            region = (labels == label).view(np.uint8)
            if kernel is not None:
                region = cv2.erode(region, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=0)
            here: NDArray[np.uint8] | None = None
            if hid is not None:  # the surface's pixels an object covered
                under = cv2.bitwise_and(region, hid)
                if cv2.countNonZero(under):
                    here = np.asarray(cv2.copyMakeBorder(
                        under, _PAD, _PAD, _PAD, _PAD, cv2.BORDER_REPLICATE), np.uint8)
            if keep is not None:
                region = cv2.bitwise_and(region, keep)
            if cv2.countNonZero(region) < MIN_SEEN_PIXELS:
                continue
            region = cv2.copyMakeBorder(region, _PAD, _PAD, _PAD, _PAD, cv2.BORDER_REPLICATE)
            # The region's outline bounds what each plane sees of it.  The sky's, every
            # point of it: a sky face sees only the outline's points whose directions are in
            # front of it, and the corners alone can leave it a sliver (a camera looking
            # down: the frame's top corners on +y, its bottom ones behind it).
            contours, _ = cv2.findContours(
                region, cv2.RETR_EXTERNAL,
                cv2.CHAIN_APPROX_NONE if label == LABEL_SKY else cv2.CHAIN_APPROX_SIMPLE)
            outline = np.concatenate([c.reshape(-1, 2) for c in contours]).astype(np.float64)
            for plane, pts in self._planes_seen(label, camera, shift, outline):
                got = self._update(plane, plane_to_frame=shift @ plane.to_pixels(camera),
                                   image=pad, region=region, points=pts, rate=rate, gate=gate,
                                   relearn=anew, covered=here, new_only=new_only)
                if got is not None:
                    done[plane.name] = got[0]
                    new += got[1]
                    if isinstance(plane, _SkyPlane):
                        self.sky_version += 1
        self.passes += 1
        return Learning(MappingProxyType(done), new, (time.perf_counter() - started) * 1000.0)

    def _planes_seen(self, label: int, camera: Camera, shift: FloatArray, outline: FloatArray
                     ) -> list[tuple[_Plane, FloatArray]]:
        """The planes that the frame pixels of ``label`` (their ``outline``, in
        bordered-frame pixels) may show, each with the outline in its image's
        pixels (made or grown here)."""
        out: list[tuple[_Plane, FloatArray]] = []
        if label == LABEL_SKY:
            for name in SKY_FACES:
                plane = self._planes.get(name)
                n = plane.size[0] if plane is not None else self._sky_side(camera)
                pts = _in_plane(outline, shift @ _sky_to_pixels(name, n, camera))
                if not len(pts) or pts[:, 0].max() < -0.5 or pts[:, 0].min() > n - 0.5 \
                        or pts[:, 1].max() < -0.5 or pts[:, 1].min() > n - 0.5:
                    continue
                if plane is None:
                    self._planes[name] = plane = _SkyPlane(name, n)
                out.append((plane, pts))
            return out
        for surface in self._by_label[label]:
            if not surface.seen_from(camera.position):
                continue
            hom = shift @ surface.homography(camera)  # face -> bordered frame pixels
            face = _in_plane(outline, hom)
            e = surface.extent
            if e is not None and len(face):
                face = np.clip(face, (e[0], e[1]), (e[2], e[3]))
            if len(face) < 2 or np.ptp(face[:, 0]) <= 0 or np.ptp(face[:, 1]) <= 0:
                continue
            plane = self._planes.get(surface.name)
            if plane is None:
                plane = self._new_surface(surface, camera, face)
                self._planes[surface.name] = plane
            else:
                assert isinstance(plane, _SurfacePlane)
                plane = self._grow(plane, camera, face)
            assert isinstance(plane, _SurfacePlane)
            st = np.c_[face, np.ones(len(face))] @ np.linalg.inv(plane.to_face).T
            out.append((plane, st[:, :2] / st[:, 2:]))
        return out

    def _update(self, plane: _Plane, *, plane_to_frame: FloatArray, image: NDArray[np.uint8],
                region: NDArray[np.uint8], points: FloatArray, rate: float, gate: float | None,
                relearn: NDArray[np.uint8] | None = None,
                covered: NDArray[np.uint8] | None = None,
                new_only: bool = False) -> tuple[int, int] | None:
        """Learn ``plane`` from ``image`` where ``region`` is set; ``points`` (plane
        pixels) bound what is seen; where ``relearn`` is set the texels start afresh;
        the unlearned texels where ``covered`` is set are marked hidden; ``new_only``:
        only texels never learned are learned.
        Returns (pixels updated, of them new)."""
        w, h = plane.size
        x0 = max(0, int(math.floor(points[:, 0].min())) - 2)
        y0 = max(0, int(math.floor(points[:, 1].min())) - 2)
        x1 = min(w, int(math.ceil(points[:, 0].max())) + 3)
        y1 = min(h, int(math.ceil(points[:, 1].max())) + 3)
        if x0 >= x1 or y0 >= y1:
            return None
        rw, rh = x1 - x0, y1 - y0
        m = plane_to_frame @ np.array([[1.0, 0.0, x0], [0.0, 1.0, y0], [0.0, 0.0, 1.0]])
        seen = cv2.warpPerspective(region, m, (rw, rh), flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                                   borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        # In front of the camera: the map's third row is positive (a half-plane;
        # linear, so the box's corners decide whether it needs checking).
        front = None
        if min(m[2, 0] * x + m[2, 1] * y + m[2, 2] for x in (0, rw) for y in (0, rh)) <= 0:
            front = (((m[2, 0] * np.arange(rw, dtype=np.float64))[None, :]
                      + (m[2, 1] * np.arange(rh, dtype=np.float64) + m[2, 2])[:, None]) > 0
                     ).view(np.uint8)
            cv2.bitwise_and(seen, front, dst=seen)
        if plane.inside is not None:
            cv2.bitwise_and(seen, plane.inside[y0:y1, x0:x1], dst=seen)
        if covered is not None:
            # in view but left: while unlearned, these texels are what an object covered
            hid = cv2.warpPerspective(covered, m, (rw, rh),
                                      flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                                      borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            if front is not None:
                cv2.bitwise_and(hid, front, dst=hid)
            if plane.inside is not None:
                cv2.bitwise_and(hid, plane.inside[y0:y1, x0:x1], dst=hid)
            cv2.bitwise_and(hid, cv2.compare(plane.count[y0:y1, x0:x1], 0, cv2.CMP_EQ),  # type: ignore[call-overload]
                            dst=hid)
            cv2.bitwise_and(hid, cv2.bitwise_not(seen), dst=hid)
            cv2.bitwise_or(plane.hidden[y0:y1, x0:x1], hid, dst=plane.hidden[y0:y1, x0:x1])
        if cv2.countNonZero(seen) == 0:
            return None
        img = plane.image[y0:y1, x0:x1]
        cnt = plane.count[y0:y1, x0:x1]
        unseen = cv2.compare(cnt, 0, cv2.CMP_EQ)  # type: ignore[call-overload]
        if relearn is not None:
            anew = cv2.warpPerspective(relearn, m, (rw, rh),
                                       flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                                       borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            unseen = cv2.bitwise_or(unseen, cv2.compare(anew, 0, cv2.CMP_GT))  # type: ignore[call-overload]
        fresh = cv2.bitwise_and(seen, unseen)
        old = (np.zeros_like(fresh) if new_only
               else cv2.bitwise_and(seen, cv2.bitwise_not(unseen)))
        n_old = cv2.countNonZero(old)
        if n_old == 0 and cv2.countNonZero(fresh) == 0:
            return None
        sampled = cv2.warpPerspective(image, m, (rw, rh), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                      borderMode=cv2.BORDER_REPLICATE)
        alpha = max(rate, 1.0 / (plane.updates + 1))
        drift = 0.0
        if n_old and gate is not None:
            b, g, r = cv2.split(cv2.absdiff(cv2.convertScaleAbs(img), sampled))
            worst = cv2.max(cv2.max(b, g), r)
            cv2.bitwise_and(old, cv2.compare(worst, float(gate), cv2.CMP_LE),  # type: ignore[call-overload]
                            dst=old)
            n_old = cv2.countNonZero(old)
        if n_old:
            # the mean change, not the mean |change|: sensor noise averages out, a drift does not
            before, after = cv2.mean(img, mask=old), cv2.mean(sampled, mask=old)
            drift = alpha * max(abs(after[c] - before[c]) for c in range(3))
            cv2.accumulateWeighted(sampled, img, alpha, mask=old)
        n_fresh = cv2.countNonZero(fresh)
        if n_fresh:
            cv2.accumulateWeighted(sampled, img, 1.0, mask=fresh)
        if n_fresh + n_old == 0:
            return None
        cv2.add(cnt, 1, dst=cnt, mask=cv2.bitwise_or(fresh, old))  # type: ignore[call-overload]
        plane.updates += 1
        plane.drift += drift
        if n_fresh or plane.drift >= _DRIFT:
            plane.dirty = True
        return n_fresh + n_old, n_fresh

    def _sky_side(self, camera: Camera) -> int:
        n = int(round(max(camera.fx, camera.fy)))  # a 90-degree face at half the camera's resolution
        return max(16, min(MAX_SKY_SIDE, n + n % 2))

    def _resolution(self, surface: Surface, camera: Camera, face: FloatArray) -> float:
        z = camera.to_camera(surface.to_world(face))[:, 2]
        z = z[z > 1e-6]
        near = float(z.min()) if len(z) else 1.0  # a plane's depth is extreme on its outline
        ppm = max(camera.fx, camera.fy) / max(near, 1e-3)
        return float(np.clip(ppm, MIN_PIXELS_PER_METRE, self.max_pixels_per_metre))

    def _size(self, extent: Extent, ppm: float) -> tuple[int, int]:
        w_m, h_m = extent[2] - extent[0], extent[3] - extent[1]
        ppm = min(ppm, math.sqrt(self.max_surface_pixels / (w_m * h_m)))
        return (max(1, int(math.ceil(w_m * ppm))), max(1, int(math.ceil(h_m * ppm))))

    def _seen_extent(self, surface: Surface, camera: Camera, face: FloatArray) -> Extent:
        """What is seen of ``surface`` (face coordinates ``face``), with a margin of
        :data:`SEEN_MARGIN`, cut to the surface (an unbounded floor: to
        :data:`FLOOR_REACH` around the camera)."""
        lo = face.min(axis=0) - SEEN_MARGIN
        hi = face.max(axis=0) + SEEN_MARGIN
        e = surface.extent
        if e is None:
            cx, cy, r = float(camera.position[0]), float(camera.position[1]), FLOOR_REACH
            e = (cx - r, cy - r, cx + r, cy + r)
        lo = np.clip(np.maximum(lo, (e[0], e[1])), -MAX_COORDINATE, MAX_COORDINATE)
        hi = np.clip(np.minimum(hi, (e[2], e[3])), -MAX_COORDINATE, MAX_COORDINATE)
        return (float(lo[0]), float(lo[1]), float(max(hi[0], lo[0] + 0.01)),
                float(max(hi[1], lo[1] + 0.01)))

    def _new_surface(self, surface: Surface, camera: Camera, face: FloatArray) -> _SurfacePlane:
        extent = self._seen_extent(surface, camera, face)
        return _SurfacePlane(surface, extent,
                             self._size(extent, self._resolution(surface, camera, face)))

    def _grow(self, plane: _SurfacePlane, camera: Camera, face: FloatArray) -> _SurfacePlane:
        """The surface's plane covering ``face`` too (on the same pixel grid)."""
        e = plane.extent
        lo, hi = face.min(axis=0), face.max(axis=0)
        tol = 1e-9
        if lo[0] >= e[0] - tol and lo[1] >= e[1] - tol and hi[0] <= e[2] + tol \
                and hi[1] <= e[3] + tol:
            return plane
        want = self._seen_extent(plane.surface, camera, face)
        for _ in range(8):
            e = plane.extent
            w, h = plane.size
            px, py = (e[2] - e[0]) / w, (e[3] - e[1]) / h  # metres per pixel
            left = max(0, int(math.ceil((e[0] - min(want[0], e[0])) / px - 1e-6)))
            right = max(0, int(math.ceil((max(want[2], e[2]) - e[2]) / px - 1e-6)))
            below = max(0, int(math.ceil((e[1] - min(want[1], e[1])) / py - 1e-6)))
            above = max(0, int(math.ceil((max(want[3], e[3]) - e[3]) / py - 1e-6)))
            nw, nh = w + left + right, h + below + above
            if nw * nh <= self.max_surface_pixels:
                break
            plane = _halved(plane)  # too many texels: half the resolution, all it knew kept
        else:  # pragma: no cover - eight halvings cover any reach
            return plane
        grown = _SurfacePlane(plane.surface, (e[0] - left * px, e[1] - below * py,
                                              e[2] + right * px, e[3] + above * py), (nw, nh))
        # rows run down from t_max: the old image starts `above` rows down
        grown.image[above:above + h, left:left + w] = plane.image
        grown.count[above:above + h, left:left + w] = plane.count
        grown.hidden[above:above + h, left:left + w] = plane.hidden
        grown.updates = plane.updates
        grown.dirty = True
        self._planes[plane.name] = grown
        return grown

    # -- rendering ------------------------------------------------------------------------

    def apply(self, renderer: Renderer, *, force: bool = False) -> tuple[str, ...]:
        """Give ``renderer`` (and every renderer sharing its backdrop) each surface
        changed since the last call (``force``: every learned surface); returns
        their names.  The sky is not the renderer's: see :meth:`composite`."""
        changed = []
        for name in self.learned:
            plane = self._planes[name]
            if not isinstance(plane, _SurfacePlane) or not (plane.dirty or force):
                continue
            t = plane.texture()
            if t.mask.any():
                renderer.set_appearance(name, t.image, t.mask, extent=t.extent, aligned=True)
            plane.dirty = False
            plane.drift = 0.0
            changed.append(name)
        return tuple(changed)

    def composite(self, image: NDArray[np.uint8], labels: NDArray[np.integer],
                  camera: Camera) -> NDArray[np.uint8]:
        """``image`` (a render through ``camera`` with label image ``labels``) with
        the learned sky where the render shows the sky; ``image`` itself when
        no sky is learned.  The sky's view is cached per camera and
        :attr:`sky_version`."""
        faces = [p for p in self._planes.values() if isinstance(p, _SkyPlane)]
        if not faces:
            return image
        view, valid = self._sky_view(camera, faces)
        sky = cv2.compare(labels.astype(np.int32), LABEL_SKY, cv2.CMP_EQ)  # type: ignore[call-overload]
        where = cv2.bitwise_and(valid, sky)
        if not cv2.countNonZero(where):
            return image
        out = image.copy()
        cv2.copyTo(view, where, out)
        return out

    def _sky_view(self, camera: Camera, faces: list["_SkyPlane"]
                  ) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
        key = (camera.width, camera.height, camera.K.tobytes(), camera.rotation.tobytes(),
               self.sky_version, len(faces))
        if self._sky_cache is not None and self._sky_cache[0] == key:
            return self._sky_cache[1], self._sky_cache[2]
        w, h = camera.width, camera.height
        view = np.zeros((h, w, 3), np.uint8)
        valid = np.zeros((h, w), np.uint8)
        for plane in faces:
            hom = plane.to_pixels(camera)  # face pixels -> camera pixels
            inv = np.linalg.inv(hom)
            seen = cv2.compare(plane.count, 0, cv2.CMP_GT)  # type: ignore[call-overload]
            bgra = cv2.cvtColor(cv2.convertScaleAbs(plane.image), cv2.COLOR_BGR2BGRA)
            bgra[:, :, 3] = seen
            warped = cv2.warpPerspective(bgra, hom, (w, h), flags=cv2.INTER_LINEAR,
                                         borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            # At the edge of what was seen, a pixel mixes seen and unseen (black,
            # transparent) texels: its colour is the seen ones' (the mix over its alpha).
            alpha = warped[:, :, 3]
            use = cv2.compare(alpha, 64, cv2.CMP_GE)  # type: ignore[call-overload]
            partial = cv2.compare(alpha, 255, cv2.CMP_LT)  # type: ignore[call-overload]
            edge = cv2.bitwise_and(use, partial)
            if cv2.countNonZero(edge):
                ys, xs = np.nonzero(edge)
                mix = warped[ys, xs, :3].astype(np.float32) * (255.0 / alpha[ys, xs, None])
                warped[ys, xs, :3] = np.clip(mix + 0.5, 0, 255).astype(np.uint8)
            # only the rays on the face's side (a half-plane of the image; its
            # corners say whether it cuts the image at all)
            if min(inv[2, 0] * x + inv[2, 1] * y + inv[2, 2] for x in (0, w) for y in (0, h)) <= 0:
                cols = np.arange(w, dtype=np.float64)[None, :]
                rows = np.arange(h, dtype=np.float64)[:, None]
                ahead = (inv[2, 0] * cols + inv[2, 1] * rows + inv[2, 2]) > 0
                cv2.bitwise_and(use, ahead.view(np.uint8) * np.uint8(255), dst=use)
            cv2.copyTo(cv2.cvtColor(warped, cv2.COLOR_BGRA2BGR), use, view)
            cv2.bitwise_or(valid, use, dst=valid)
        self._sky_cache = (key, view, valid)
        return view, valid

    def forget(self) -> None:
        """Forget everything learned (a renderer keeps what it was given)."""
        self._planes.clear()
        self.sky_version += 1

    # -- files ----------------------------------------------------------------------------

    def save(self, folder: str | Path) -> list[Path]:
        """Write every learned plane into ``folder``: ``<name>.png`` (BGR),
        ``<name>.mask.png`` (255 where seen) and :data:`INDEX` listing them with
        their extents (written last, so a folder with an index is complete).
        Returns the files written."""
        out = Path(folder)
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise AppearanceError(f"cannot make the appearance folder {str(out)!r}: "
                                  f"{exc.strerror}") from None
        entries = []
        written: list[Path] = []
        for name, t in self.textures().items():
            stem = _file_stem(name)
            for suffix, array in ((".png", t.image),
                                  (".mask.png", t.mask.view(np.uint8) * np.uint8(255))):
                ok, data = cv2.imencode(".png", array)
                if not ok:  # pragma: no cover - OpenCV encodes any uint8 image
                    raise AppearanceError(f"cannot encode the image of {name!r}")
                written.append(_write(out / f"{stem}{suffix}", data.tobytes()))
            entries.append({"name": name, "kind": "sky" if t.sky else "surface",
                            "image": f"{stem}.png", "mask": f"{stem}.mask.png",
                            "extent": list(t.extent),
                            "pixels_per_metre": [round(v, 3) for v in t.pixels_per_metre],
                            "coverage": round(t.coverage, 4), "updates": t.updates})
        index = {"format": FORMAT, "version": VERSION, "surfaces": entries}
        written.append(_write(out / INDEX, (json.dumps(index, indent=1) + "\n").encode()))
        return written

    def load(self, folder: str | Path) -> tuple[str, ...]:
        """Read a folder written by :meth:`save` (its planes replace what was
        learned of them); returns the planes read.

        Raises
        ------
        AppearanceError
            If the index is missing or malformed, an image or mask is missing,
            unreadable or of the wrong shape, an extent is not valid, or a
            surface is not one of this scene's.  Nothing is changed then.
        """
        base = Path(folder)
        index_path = base / INDEX
        try:
            index = json.loads(index_path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise AppearanceError(f"{index_path}: no such file; expected a folder written by "
                                  "`adapt run` (its appearance/ folder)") from None
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise AppearanceError(f"{index_path}: cannot read it as JSON: {exc}") from None
        if not isinstance(index, dict) or index.get("format") != FORMAT:
            raise AppearanceError(f'{index_path}: not an appearance index (expected "format": '
                                  f'"{FORMAT}")')
        if index.get("version") != VERSION:
            raise AppearanceError(f"{index_path}: version {index.get('version')!r}; this adapt "
                                  f"reads version {VERSION}")
        entries = index.get("surfaces")
        if not isinstance(entries, list):
            raise AppearanceError(f'{index_path}: "surfaces" must be a list')
        loaded: dict[str, _Plane] = {}
        for i, entry in enumerate(entries):
            plane = self._read_entry(base, entry, f"{index_path}: surfaces[{i}]")
            if plane.name in loaded:
                raise AppearanceError(f"{index_path}: surfaces[{i}]: {plane.name!r} is listed twice")
            loaded[plane.name] = plane
        self._planes.update(loaded)
        if any(isinstance(p, _SkyPlane) for p in loaded.values()):
            self.sky_version += 1
        return tuple(n for n in self.learned if n in loaded)

    def _read_entry(self, base: Path, entry: Any, where: str) -> _Plane:
        if not isinstance(entry, dict):
            raise AppearanceError(f"{where}: expected an object")
        name = entry.get("name")
        sky = name in SKY_FACES and name not in self._names
        if not sky and name not in self._names:
            raise AppearanceError(f"{where}: the scene has no surface {name!r}; its surfaces "
                                  f"are {', '.join(self._names)}")
        extent = entry.get("extent")
        try:
            ext = tuple(float(v) for v in extent)  # type: ignore[union-attr]
        except (TypeError, ValueError):
            ext = ()
        if (len(ext) != 4 or not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in ext)
                or ext[0] >= ext[2] or ext[1] >= ext[3]):
            raise AppearanceError(f"{where}: extent must be [s_min, t_min, s_max, t_max] with "
                                  f"min < max, got {extent!r}")
        image = _read_image(base, entry.get("image"), f"{where}.image", cv2.IMREAD_COLOR)
        mask = _read_image(base, entry.get("mask"), f"{where}.mask", cv2.IMREAD_GRAYSCALE)
        if mask.shape != image.shape[:2]:
            raise AppearanceError(f"{where}: the mask is {mask.shape[1]}x{mask.shape[0]} but "
                                  f"the image is {image.shape[1]}x{image.shape[0]}")
        h, w = mask.shape
        if w * h > max(self.max_surface_pixels, MAX_SKY_SIDE ** 2):
            raise AppearanceError(f"{where}: the image has {w * h:,} pixels; at most "
                                  f"{self.max_surface_pixels:,} are learned per surface")
        plane: _Plane
        if sky:
            if w != h or ext != SKY_EXTENT or w > MAX_SKY_SIDE or w % 2:
                raise AppearanceError(f"{where}: a sky face is an even square image of at most "
                                      f"{MAX_SKY_SIDE} pixels a side with extent "
                                      f"{list(SKY_EXTENT)}; got {w}x{h}, {list(ext)}")
            plane = _SkyPlane(str(name), w)
        else:
            plane = _SurfacePlane(self._names[str(name)], (ext[0], ext[1], ext[2], ext[3]), (w, h))
        seen = mask > 127
        plane.image[seen] = image[seen]
        plane.count[seen] = 1
        plane.updates = 1
        plane.dirty = True
        return plane


def _write(path: Path, data: bytes) -> Path:
    try:
        return write_atomic(path, data)
    except OSError as exc:
        raise AppearanceError(f"cannot write {str(path)!r}: {exc.strerror}") from None


def _file_stem(name: str) -> str:
    """A plane's name as a file name (``crate/side0`` -> ``crate__side0``, ``sky/+x`` -> ``sky__+x``)."""
    safe = "".join(c if c.isalnum() or c in "-_.+" else "_" for c in name.replace("/", "__"))
    return safe or "surface"


def _read_image(base: Path, name: object, where: str, flags: int) -> NDArray[np.uint8]:
    if not isinstance(name, str) or not name or Path(name).name != name or name in (".", ".."):
        raise AppearanceError(f"{where}: expected a file name in the folder, got {name!r}")
    path = base / name
    try:
        data = np.fromfile(path, np.uint8)
    except OSError:
        raise AppearanceError(f"{where}: cannot read {str(path)!r}") from None
    with native_messages() as said:  # libpng's own complaint goes into the message
        image = cv2.imdecode(data, flags) if data.size else None
    if image is None or image.dtype != np.uint8:
        raise AppearanceError(f"{where}: {str(path)!r} is not an 8-bit image{said.detail()}")
    return np.asarray(image, np.uint8)
