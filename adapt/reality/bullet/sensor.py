"""The camera's sensor in a PyBullet reality: what happens to a render before it is a frame.

In this order, per frame (each number drawn per run, ``reality.look``):

1. where nothing was drawn (segmentation -1), the room beyond: a vertical
   gradient between two drawn colours;
2. exposure: every channel times ``gain``;
3. vignetting: the image darkens towards its corners, by ``vignette`` at the
   corners (``1 - vignette r^2``, ``r`` the distance from the centre over the
   half diagonal);
4. optics: a Gaussian blur of ``blur`` pixels;
5. sensor noise: Gaussian, ``noise`` grey levels, independent per pixel, channel and
   frame;
6. RGB (PyBullet's order) to BGR (adapt's).

Examples
--------
>>> import numpy as np
>>> from adapt.reality.bullet.draw import LookDraw
>>> look = LookDraw((), (0, 0, 1), (1, 1, 1), 0.6, 0.4, 0.0, False, True, 1.0, 0.0, 0.0, 0.0,
...                 ((200, 200, 200), (100, 100, 100)))
>>> rgb = np.zeros((4, 6, 3), np.uint8); rgb[..., 0] = 250
>>> seg = np.zeros((4, 6), np.int32); seg[0, 0] = -1
>>> out = Sensor(look, (6, 4)).apply(rgb, seg, np.random.default_rng(0))
>>> out[1, 1].tolist(), out[0, 0].tolist()
([0, 0, 250], [200, 200, 200])
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.reality.bullet.draw import LookDraw

__all__ = ["Sensor"]


class Sensor:
    """Turns a render into a frame (see the module docstring)."""

    def __init__(self, look: LookDraw, size: tuple[int, int]) -> None:
        w, h = size
        self.look = look
        top, bottom = (np.array(c, np.float32) for c in look.background)
        f = np.linspace(0.0, 1.0, h, dtype=np.float32)[:, None, None]
        self.background = np.broadcast_to(top * (1 - f) + bottom * f, (h, w, 3)).astype(np.float32)
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        r2 = ((xx - (w - 1) / 2) ** 2 + (yy - (h - 1) / 2) ** 2) / (((w - 1) / 2) ** 2 + ((h - 1) / 2) ** 2)
        self.scale = (look.gain * (1.0 - look.vignette * r2))[..., None].astype(np.float32)

    def apply(self, rgb: NDArray[np.uint8], seg: NDArray[np.int32],
              rng: np.random.Generator) -> NDArray[np.uint8]:
        """The frame (BGR ``uint8``) a render becomes; ``rng`` draws the noise."""
        image = rgb.astype(np.float32)
        empty = seg < 0
        if empty.any():
            image[empty] = self.background[empty]
        image *= self.scale
        if self.look.blur > 0:
            image = np.asarray(cv2.GaussianBlur(image, (0, 0), self.look.blur), np.float32)
        if self.look.noise > 0:
            image += rng.standard_normal(image.shape, dtype=np.float32) * np.float32(self.look.noise)
        out = np.clip(image + 0.5, 0, 255).astype(np.uint8)
        return np.ascontiguousarray(out[:, :, ::-1])
