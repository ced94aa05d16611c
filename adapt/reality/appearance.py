"""How reality's camera image differs from the imagination's render.

A synthetic reality renders its true scene with the imagination's
:class:`~adapt.imagination.Renderer` (the texture scale is already in the
true scene's tiles) and then makes it look like a camera's image with
:class:`Look`, whose parameters are the scenario's
:class:`~adapt.scenario.RealAppearance`.  In order, per pixel and channel:

1. **tint**: the static surfaces (floor, walls, obstacles; found in the
   label image) are multiplied by ``tint`` ``(b, g, r)``; the sky, balls and
   the robot are not;
2. **spin marker** (``spin_marker``): six dark dots on each ball, at the
   ends of its body axes, turning with its rolling, drawn where the ball is
   seen (:func:`draw_spin_marker`);
3. **lighting gradient**: a gain falling linearly from 1 on one side of the
   image to ``1 - gradient`` on the other, along the direction
   ``gradient_deg`` (0: bright on the left, dark on the right; 90: bright at
   the top, dark at the bottom);
4. **contrast and brightness**: ``(v - 128) * contrast + 128 + brightness``;
5. **colour shift**: ``color_shift`` ``(b, g, r)`` added;
6. **blur**: a Gaussian of ``blur`` pixels (sigma);
7. **sensor noise**: Gaussian, ``noise`` grey levels (sigma), independent
   per pixel, channel and frame, from the ``reality.noise`` stream (see
   :class:`Look`: never beyond 4.1 sigma), then clipping to ``0..255`` and
   rounding.

Examples
--------
>>> import numpy as np
>>> from adapt.scenario import RealAppearance
>>> look = Look(RealAppearance(brightness=20.0, gradient=0.5), (4, 2))
>>> img = np.full((2, 4, 3), 100, np.uint8)
>>> out = look.apply(img, np.ones((2, 4), np.int32), np.random.default_rng(0))
>>> out[0, :, 0].tolist()          # 100 * (1 .. 0.5) + 20, left to right
[120, 103, 87, 70]
"""

from __future__ import annotations

import functools
import math
import statistics

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination.render import LABEL_BALL, LABEL_FLOOR
from adapt.scenario.records import RealAppearance

__all__ = ["Look", "lighting_gain", "draw_spin_marker", "MARKER_SIZE", "MARKER_DARKNESS"]

#: Radius of a spin-marker dot, as a fraction of the ball's radius.
MARKER_SIZE = 0.28
#: A marker dot keeps this fraction of the pixel's brightness.
MARKER_DARKNESS = 0.3

#: Sensor noise draws from a table of this many equally likely Gaussian quantiles.
NOISE_LEVELS = 256

#: The six body directions that carry a marker dot.
_DOTS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)


def lighting_gain(size: tuple[int, int], gradient: float, gradient_deg: float) -> NDArray[np.float32]:
    """The lighting gain ``(H, W)``: 1 on the bright side, ``1 - gradient`` on the dark.

    Examples
    --------
    >>> lighting_gain((3, 3), 0.5, 90.0)[:, 0].tolist()    # top to bottom
    [1.0, 0.75, 0.5]
    """
    w, h = size
    a = math.radians(gradient_deg)
    dx, dy = math.cos(a), math.sin(a)
    xs = np.arange(w, dtype=np.float64)[None, :]
    ys = np.arange(h, dtype=np.float64)[:, None]
    proj = xs * dx + ys * dy
    corners = [0.0, (w - 1) * dx, (h - 1) * dy, (w - 1) * dx + (h - 1) * dy]
    lo, hi = min(corners), max(corners)
    f = (proj - lo) / (hi - lo) if hi - lo > 1e-12 else np.zeros_like(proj)
    return (1.0 - gradient * f).astype(np.float32)


@functools.lru_cache(maxsize=1)
def _normal_quantiles() -> NDArray[np.float32]:
    """The standard normal's quantiles at ``(k + 0.5) / 256``, scaled to unit
    variance, as a ``(1, 256)`` table for :func:`cv2.LUT`."""
    dist = statistics.NormalDist()
    q = np.array([dist.inv_cdf((k + 0.5) / NOISE_LEVELS) for k in range(NOISE_LEVELS)])
    table = (q / q.std()).astype(np.float32).reshape(1, NOISE_LEVELS)
    table.setflags(write=False)
    return table


class Look:
    """Applies an :class:`~adapt.scenario.RealAppearance` to rendered frames of one size.

    The per-pixel gain (lighting times contrast), the offsets, the noise
    table and the work buffers are made once; :meth:`apply` costs a few
    OpenCV passes per frame.  A ``Look`` is not shared between threads.

    Sensor noise is the sum of two draws from a table of 256 equally likely
    Gaussian quantiles, divided by sqrt 2: Gaussian to well below a grey
    level for the sigmas a camera has, never beyond 4.1 sigma, and several
    times cheaper than ``Generator.standard_normal``.
    """

    def __init__(self, appearance: RealAppearance, size: tuple[int, int]) -> None:
        self.appearance = appearance
        self.size = (int(size[0]), int(size[1]))
        a = appearance
        w, h = self.size
        light = lighting_gain(self.size, a.gradient, a.gradient_deg) * np.float32(a.contrast)
        self._gain = np.ascontiguousarray(np.repeat(light[:, :, None], 3, axis=2))
        offset = np.array([128.0 * (1.0 - a.contrast) + a.brightness + c for c in a.color_shift],
                          np.float32)
        self._offset = np.ascontiguousarray(np.broadcast_to(offset, (h, w, 3)))
        self._tinted = a.tint != (1.0, 1.0, 1.0)
        # gain * tint = gain + surface * gain * (tint - 1)
        self._tint_delta = (self._gain * (np.array(a.tint, np.float32) - 1.0)
                            if self._tinted else None)
        self._noise = (_normal_quantiles() * np.float32(a.noise / math.sqrt(2.0))
                       if a.noise > 0 else None)
        self._out = np.empty((h, w, 3), np.float32)
        self._work = np.empty((h, w, 3), np.float32)
        self._mask = np.empty((h, w, 3), np.uint8)

    def apply(self, image: NDArray[np.uint8], labels: NDArray[np.int32],
              rng: np.random.Generator | None) -> NDArray[np.uint8]:
        """The camera's image of a render (``image`` BGR, ``labels`` its label image).

        ``rng`` draws the sensor noise (it may be None when ``noise`` is 0).
        The spin marker is drawn separately (:func:`draw_spin_marker`), before this.
        """
        a = self.appearance
        if image.shape != self._gain.shape:
            raise ValueError(f"expected a {self.size[0]}x{self.size[1]} BGR image, got "
                             f"shape {image.shape}")
        # Work buffers are kept: fresh 640x480 float images cost more in page
        # faults than the arithmetic (measured about 2x).
        out, work, gain = self._out, self._work, self._gain
        if self._tint_delta is not None:
            s = ((labels >= LABEL_FLOOR) & (labels < LABEL_BALL)).view(np.uint8)
            cv2.merge((s, s, s), dst=self._mask)
            cv2.multiply(self._mask, self._tint_delta, dst=work, dtype=cv2.CV_32F)
            cv2.add(work, self._gain, dst=work)
            gain = work
        cv2.multiply(image, gain, dst=out, dtype=cv2.CV_32F)
        cv2.add(out, self._offset, dst=out)
        if a.blur > 0:
            cv2.GaussianBlur(out, (0, 0), a.blur, dst=work)
            out, work = work, out
        if self._noise is not None:
            assert rng is not None, "sensor noise needs a generator"
            draws = np.frombuffer(rng.bytes(2 * image.size), np.uint8).reshape(2, *image.shape)
            for k in range(2):
                cv2.LUT(draws[k], self._noise, dst=work)
                cv2.add(out, work, dst=out)
        np.clip(out, 0.0, 255.0, out=out)
        np.rint(out, out=out)
        return out.astype(np.uint8)


def draw_spin_marker(image: NDArray[np.uint8], labels: NDArray[np.int32], camera: Camera,
                     center: tuple[float, float, float], radius: float,
                     orientation: NDArray[np.float64], label: int) -> int:
    """Darken six dots on a ball (its body axes turned by ``orientation``)
    where the ball's ``label`` is seen; returns how many dots face the camera.

    The dots are drawn as the ellipses a round spot on the sphere projects
    to, clipped to the ball's own pixels, in place.
    """
    c = np.asarray(center, float)
    dirs = _DOTS @ np.asarray(orientation, float).T      # body axes in the world
    points = c + radius * dirs
    to_cam = camera.position - points
    facing = np.einsum("ij,ij->i", dirs, to_cam) > 0
    if not facing.any():
        return 0
    pc = camera.to_camera(points[facing])
    if pc[:, 2].min() <= 1e-6:
        return 0
    px = camera.project(points[facing])
    dist = np.linalg.norm(to_cam[facing], axis=1)
    # Foreshortening: the spot's circle seen at angle acos(n . view).
    cosv = np.einsum("ij,ij->i", dirs[facing], to_cam[facing]) / dist
    major = MARKER_SIZE * radius * camera.fx / pc[:, 2]
    # Direction of the normal in the image: the ellipse's minor axis lies along it.
    depth = float(camera.to_camera(c[None, :])[0, 2])
    if depth <= 1e-6:
        return 0  # the ball's centre is level with the camera or behind it (the camera at the ball)
    centre_px = camera.project(c[None, :])[0]
    h, w = labels.shape
    r_px = radius * camera.fx / depth + 2.0
    if not (np.isfinite(centre_px).all() and math.isfinite(r_px)):
        return 0
    x0, x1 = max(int(centre_px[0] - r_px), 0), min(int(centre_px[0] + r_px) + 2, w)
    y0, y1 = max(int(centre_px[1] - r_px), 0), min(int(centre_px[1] + r_px) + 2, h)
    if x0 >= x1 or y0 >= y1:
        return 0
    mask = np.zeros((y1 - y0, x1 - x0), np.uint8)
    for (u, v), a, k in zip(px, major, cosv):
        d = np.array([u, v]) - centre_px
        angle = math.degrees(math.atan2(d[1], d[0])) if np.hypot(*d) > 1e-6 else 0.0
        axes = (max(a * max(k, 0.05), 0.5), max(a, 0.5))   # (along the normal, across it)
        cv2.ellipse(mask, ((float(u - x0), float(v - y0)), (2 * axes[0], 2 * axes[1]), angle),
                    255, -1, cv2.LINE_AA)
    own = labels[y0:y1, x0:x1] == label
    weight = (mask.astype(np.float32) / 255.0) * own
    view = image[y0:y1, x0:x1]
    dark = view.astype(np.float32) * (1.0 - (1.0 - MARKER_DARKNESS) * weight[:, :, None])
    view[:] = np.rint(dark).astype(np.uint8)
    return int(facing.sum())
