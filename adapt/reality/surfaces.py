"""The real surfaces' texture phase: where their pattern starts.

A real floor or wall shows the scenario's texture, but its pattern does not
start where the scenario's does.  :func:`shift_textures` gives every
textured surface of the renderer's scene an appearance
(:meth:`Renderer.set_appearance <adapt.imagination.Renderer.set_appearance>`):
the scenario's texture, at the surface's tile size, sampled at face
coordinates ``(s + phase_s, t + phase_t)`` and shaded as the renderer shades
the surface.  Each image has the texture's own resolution up to
:data:`MAX_PIXELS_PER_METRE` and at most :data:`MAX_SURFACE_PIXELS` pixels.
A floor without an extent is covered over a square of :data:`FLOOR_REACH`
metres around ``centre`` (beyond it the pattern starts where the model's does).

Examples
--------
>>> from adapt.geometry import Camera
>>> from adapt.imagination import Renderer
>>> from adapt.imagination.scene import SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2, 2), (2, 2), height=1.0, texture="builtin:brick"),))
>>> cam = Camera.look_at(fx=100, fy=100, cx=40, cy=30, width=80, height=60,
...                      position=(0, -1, 0.5), look_at=(0, 2, 0.3))
>>> r = Renderer(scene, cam)
>>> shift_textures(r, (0.1, 0.05), centre=(0.0, -1.0))
('floor', 'north')
"""

from __future__ import annotations

import math
from typing import Sequence

import cv2
import numpy as np

from adapt.imagination import Renderer
from adapt.imagination.appearance import texel_matrix
from adapt.imagination.surface import Surface
from adapt.imagination.texture import load_texture

__all__ = ["shift_textures", "phased_image", "MAX_PIXELS_PER_METRE", "MAX_SURFACE_PIXELS",
           "FLOOR_REACH"]

#: Finest resolution of a phased surface image, pixels per metre.
MAX_PIXELS_PER_METRE = 400.0
#: Most pixels of one phased surface image.
MAX_SURFACE_PIXELS = 4_000_000
#: Half the side of the square of an unbounded floor that gets the phase, metres.
FLOOR_REACH = 10.0


def phased_image(surface: Surface, phase: Sequence[float],
                 extent: tuple[float, float, float, float]) -> np.ndarray:
    """The surface's texture over ``extent``, its pattern moved by ``phase``
    (metres), shaded by the renderer's fixed light; BGR uint8."""
    assert surface.texture is not None
    texture = load_texture(surface.texture)
    w_m, h_m = extent[2] - extent[0], extent[3] - extent[1]
    ppm = min(texture.size[0] / surface.tile, texture.size[1] / surface.tile,
              MAX_PIXELS_PER_METRE, math.sqrt(MAX_SURFACE_PIXELS / (w_m * h_m)))
    w, h = max(1, int(math.ceil(w_m * ppm))), max(1, int(math.ceil(h_m * ppm)))
    tex = texel_matrix(surface)
    assert tex is not None
    shift = np.array([[1.0, 0.0, float(phase[0])], [0.0, 1.0, float(phase[1])], [0.0, 0.0, 1.0]])
    to_tex = tex @ shift @ surface.image_to_face((w, h), extent)
    # Texels per image pixel: sample the mip level that has about one.
    foot = max(abs(to_tex[0, 0]), abs(to_tex[1, 1]))
    k = int(np.clip(math.floor(math.log2(max(foot, 1.0))), 0, len(texture.levels) - 1))
    f = 2.0 ** -k
    src = texture.levels[k]
    lh, lw = src.shape[:2]
    mx = np.mod(f * (to_tex[0, 0] * np.arange(w) + to_tex[0, 2]) + 0.5 * f - 0.5, lw)
    my = np.mod(f * (to_tex[1, 1] * np.arange(h) + to_tex[1, 2]) + 0.5 * f - 0.5, lh)
    image = cv2.remap(src, np.repeat(mx[None, :].astype(np.float32), h, axis=0),
                      np.repeat(my[:, None].astype(np.float32), w, axis=1),
                      cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)
    return np.asarray(cv2.convertScaleAbs(image, alpha=surface.shade), np.uint8)


def shift_textures(renderer: Renderer, phase: Sequence[float],
                   centre: Sequence[float]) -> tuple[str, ...]:
    """Give each textured surface of ``renderer``'s scene its phased texture;
    returns the names of the surfaces changed.

    ``centre`` ``(x, y)`` places the square of an unbounded floor.  Every
    renderer sharing the renderer's backdrop sees the change.
    """
    changed = []
    for surface in renderer.surfaces:
        if surface.texture is None:
            continue
        extent = surface.extent
        if extent is None:
            x, y = float(centre[0]), float(centre[1])
            extent = (x - FLOOR_REACH, y - FLOOR_REACH, x + FLOOR_REACH, y + FLOOR_REACH)
        renderer.set_appearance(surface.name, phased_image(surface, phase, extent), extent=extent)
        changed.append(surface.name)
    return tuple(changed)
