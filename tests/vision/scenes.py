"""Seeded test data for vision: the shipped photographs as a textured plane
"world" seen through rotated cameras (vision.md section 4).

The world image is what a reference camera (rotation I, f = 525 px, 1280x960)
sees; a 640x480 camera with the same focal length and world-to-camera rotation
``R`` sees ``warp(world, K R K_w^-1)``.  For two such cameras the true
homography from the synthetic view to the real one is exactly
``K R_r R_s^T K^-1`` (pure rotation).
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera, rotation_exp

TEXTURES = Path(__file__).resolve().parents[2] / "adapt" / "data" / "textures"
F = 525.0
WIDTH, HEIGHT = 640, 480
WORLD_W, WORLD_H = 1280, 960
K_WORLD = np.array([[F, 0, (WORLD_W - 1) / 2], [0, F, (WORLD_H - 1) / 2], [0, 0, 1.0]])


def _texture(name: str) -> NDArray[np.uint8]:
    img = cv2.imread(str(TEXTURES / f"{name}.png"), cv2.IMREAD_UNCHANGED)
    assert img is not None, name
    return img


def world(name: str) -> NDArray[np.uint8]:
    """The 1280x960 world plane: ``brick``, ``gravel``, ``grass`` (grey,
    mirrored tiles), ``coffee`` (colour, resized) or ``room`` (brick wall over
    a gravel floor, grey)."""
    if name == "room":
        wall = world("brick")[: WORLD_H // 2]
        floor = world("gravel")[WORLD_H // 2 :]
        return np.ascontiguousarray(np.vstack([wall, floor]))
    tex = _texture(name)
    if name == "coffee":
        return cv2.resize(tex, (WORLD_W, WORLD_H), interpolation=cv2.INTER_CUBIC)
    th, tw = tex.shape[:2]
    return cv2.copyMakeBorder(
        tex, 0, WORLD_H - th, 0, WORLD_W - tw, cv2.BORDER_REFLECT
    )


def camera(rotation: NDArray | None = None) -> Camera:
    """The 640x480 view camera at the world origin."""
    r = np.eye(3) if rotation is None else rotation
    return Camera(F, F, (WIDTH - 1) / 2, (HEIGHT - 1) / 2, WIDTH, HEIGHT, r, np.zeros(3))


def view(world_image: NDArray[np.uint8], cam: Camera) -> NDArray[np.uint8]:
    """What ``cam`` sees of the world plane."""
    h = cam.K @ cam.rotation @ np.linalg.inv(K_WORLD)
    return cv2.warpPerspective(world_image, h, cam.size, flags=cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_REFLECT)


def true_homography(real_cam: Camera, synthetic_cam: Camera) -> NDArray[np.float64]:
    """Synthetic pixels -> real pixels for two rotated cameras."""
    h = real_cam.K @ real_cam.rotation @ synthetic_cam.rotation.T @ np.linalg.inv(synthetic_cam.K)
    return h / h[2, 2]


def random_offset(
    rng: np.random.Generator, pan_tilt_deg: float = 3.0, roll_deg: float = 5.0
) -> NDArray[np.float64]:
    """A rotation with tilt, pan in ``±pan_tilt_deg`` and roll in ``±roll_deg``."""
    t, p = np.deg2rad(rng.uniform(-pan_tilt_deg, pan_tilt_deg, 2))
    r = np.deg2rad(rng.uniform(-roll_deg, roll_deg))
    return rotation_exp([t, p, r])


def renderer_look(image: NDArray[np.uint8], rng: np.random.Generator) -> NDArray[np.uint8]:
    """Blur (sigma 1.2), posterise to 12 levels, shift each channel's gain and bias."""
    out = cv2.GaussianBlur(image, (0, 0), 1.2).astype(np.float64)
    levels = 12
    out = np.round(out / 255.0 * (levels - 1)) * (255.0 / (levels - 1))
    c = 1 if out.ndim == 2 else out.shape[2]
    gain = rng.uniform(0.8, 1.2, c)
    bias = rng.uniform(-20.0, 20.0, c)
    out = out * gain + bias if c > 1 else out * gain[0] + bias[0]
    return np.clip(np.round(out), 0, 255).astype(np.uint8)


def sensor_noise(
    image: NDArray[np.uint8], rng: np.random.Generator, sigma: float = 5.0
) -> NDArray[np.uint8]:
    """Add Gaussian noise."""
    return np.clip(image + rng.normal(0.0, sigma, image.shape), 0, 255).astype(np.uint8)


def paste_object(
    image: NDArray[np.uint8],
    rng: np.random.Generator,
    *,
    radius: tuple[float, float] = (45.0, 70.0),
) -> tuple[NDArray[np.uint8], NDArray[np.bool_]]:
    """Paste a shaded ellipse (a "ball") at a random place well inside the view.

    Returns the new image and the object's silhouette.
    """
    h, w = image.shape[:2]
    a, b = rng.uniform(*radius, 2)
    cx = rng.uniform(a + 60, w - a - 60)
    cy = rng.uniform(b + 60, h - b - 60)
    yy, xx = np.mgrid[0:h, 0:w]
    d2 = ((xx - cx) / a) ** 2 + ((yy - cy) / b) ** 2
    sil = d2 <= 1.0
    shade = 0.6 + 0.4 * np.clip(1.0 - ((xx - cx + a / 3) ** 2 + (yy - cy + b / 3) ** 2) / (a * b), 0, 1)
    out = image.copy()
    if image.ndim == 3:
        # the palette colour (BGR) farthest from what the ball covers
        palette = np.array([[40, 60, 230], [230, 90, 30], [40, 200, 40], [30, 230, 240]], float)
        local = image[sil].reshape(-1, 3).mean(axis=0)
        colour = palette[int(np.argmax(np.linalg.norm(palette - local, axis=1)))]
        out[sil] = np.clip(shade[sil, None] * colour, 0, 255).astype(np.uint8)
    else:
        base = 255.0 if image[sil].mean() < 128 else 20.0
        out[sil] = np.clip(shade[sil] * base, 0, 255).astype(np.uint8)
    return out, sil


def pair(
    name: str,
    seed: int,
    *,
    pan_tilt_deg: float = 3.0,
    roll_deg: float = 5.0,
    look: bool = True,
    noise: bool = True,
) -> tuple[NDArray[np.uint8], NDArray[np.uint8], NDArray[np.float64], Camera, Camera]:
    """``(real, synthetic, H_true, real_cam, synthetic_cam)`` for one seed."""
    rng = np.random.default_rng(seed)
    w = world(name)
    real_cam = camera(rotation_exp(np.deg2rad(rng.uniform(-2, 2, 3))))
    syn_cam = real_cam.with_rotation(random_offset(rng, pan_tilt_deg, roll_deg) @ real_cam.rotation)
    real = view(w, real_cam)
    synthetic = view(w, syn_cam)
    if look:
        synthetic = renderer_look(synthetic, rng)
    if noise:
        real = sensor_noise(real, rng)
    return real, synthetic, true_homography(real_cam, syn_cam), real_cam, syn_cam
