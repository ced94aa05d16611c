"""Where a ball is, from its silhouette: exact under perspective.

A sphere of radius ``r`` whose centre ``C`` is at distance ``D`` from the
camera centre ``O`` is seen as the cone of rays ``v`` with
``angle(v, C - O) = asin(r / D)``.  :func:`fit_ball` finds the floor
position ``(x, y)`` of a ball resting on the floor (centre at height ``r``),
and ``r`` itself when it is unknown, by Gauss-Newton on those angles for the
rays of the silhouette's *upper* outline: a contact shadow on the floor only
adds to the lower part of the silhouette, and points that disagree with the
cone (shadow, occlusion) are dropped and the fit repeated.

:func:`upper_outline` extracts the outline, :func:`silhouette_circle` a first
guess (a circle fitted to it).  A ball too small in the image for an outline
(a few pixels across) is placed by its silhouette's centroid instead
(:func:`fit_small_ball`).

Examples
--------
>>> from adapt.geometry import Camera
>>> cam = Camera.look_at(fx=525, fy=525, cx=319.5, cy=239.5, width=640, height=480,
...                      position=(0, -0.6, 0.6), look_at=(0, 3, 0.3))
>>> yy, xx = np.mgrid[0:480, 0:640]
>>> rays = cam.pixel_ray(np.c_[xx.ravel(), yy.ravel()])
>>> c = np.array([0.8, 1.2, 0.15])
>>> to_c = (c - cam.position) / np.linalg.norm(c - cam.position)
>>> inside = rays @ to_c >= np.cos(np.arcsin(0.15 / np.linalg.norm(c - cam.position)))
>>> mask = inside.reshape(480, 640)
>>> fit = fit_ball(mask, (0, 0), cam, radius=None)
>>> [round(v, 2) for v in (*fit.position, fit.radius)]
[0.8, 1.2, 0.15]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.geometry import Camera

__all__ = ["BallFit", "fit_ball", "fit_small_ball", "upper_outline", "silhouette_circle",
           "image_area", "visible_area", "silhouette_length", "limb_points"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class BallFit:
    """A ball found from its silhouette.

    ``position`` is the floor ``(x, y)`` of its centre, ``radius`` its radius
    (metres), ``rms_deg`` the RMS angular residual of the outline points used,
    ``points`` how many were used.
    """

    position: tuple[float, float]
    radius: float
    rms_deg: float
    points: int


def upper_outline(mask: NDArray[np.bool_]) -> FloatArray:
    """``(x, y)`` of the upper edge of every column of ``mask`` (column order): the
    top-most pixel's centre moved up half a pixel, to the boundary itself."""
    cols = np.flatnonzero(mask.any(axis=0))
    if len(cols) == 0:
        return np.zeros((0, 2))
    tops = mask[:, cols].argmax(axis=0).astype(np.float64) - 0.5
    return np.c_[cols.astype(np.float64), tops]


def _circle(pts: FloatArray) -> tuple[float, float, float] | None:
    a = np.c_[2 * pts[:, 0], 2 * pts[:, 1], np.ones(len(pts))]
    b = pts[:, 0] ** 2 + pts[:, 1] ** 2
    sol, *_ = np.linalg.lstsq(a, b, rcond=None)
    cx, cy, c = (float(v) for v in sol)
    r2 = c + cx * cx + cy * cy
    return (cx, cy, math.sqrt(r2)) if r2 > 0 else None


def silhouette_circle(mask: NDArray[np.bool_]) -> tuple[float, float, float] | None:
    """Centre ``(x, y)`` and radius (pixels) of a circle fitted to the upper outline,
    robustly (outline points below the centre or far from the circle are dropped).

    Examples
    --------
    >>> yy, xx = np.mgrid[0:60, 0:60]
    >>> disc = (xx - 30) ** 2 + (yy - 25) ** 2 <= 15 ** 2
    >>> disc[30:45, 5:55] = True                        # a "shadow" below the centre
    >>> [round(v) for v in silhouette_circle(disc)]
    [30, 25, 15]
    """
    pts = upper_outline(mask)
    if len(pts) < 6:
        return None
    # start from the middle of the outline: the top of a ball, away from what lies beside it
    lo, hi = np.percentile(pts[:, 0], [20, 80])
    keep = (pts[:, 0] >= lo) & (pts[:, 0] <= hi)
    if keep.sum() < 6:
        keep = np.ones(len(pts), bool)
    fit = None
    for _ in range(5):
        if keep.sum() < 6:
            break
        found = _circle(pts[keep])
        if found is None:
            break
        fit = found
        cx, cy, r = fit
        resid = np.abs(np.hypot(pts[:, 0] - cx, pts[:, 1] - cy) - r)
        new = (pts[:, 1] <= cy) & (resid <= max(1.0, 2.5 * float(np.median(resid[keep]))))
        if np.array_equal(new, keep):
            break
        keep = new
    return fit


def fit_ball(mask: NDArray[np.bool_], offset: tuple[int, int], camera: Camera, *,
             radius: float | None, to_camera: Callable[[FloatArray], FloatArray] | None = None,
             iterations: int = 12) -> BallFit | None:
    """The floor position (and radius, when ``radius`` is None) of a ball from its silhouette.

    Parameters
    ----------
    mask : (h, w) bool ndarray
        The silhouette (a contact shadow below it does no harm).
    offset : (x, y)
        Where ``mask``'s top-left pixel is in the image.
    camera : Camera
        The camera the image is seen through.
    radius : float or None
        The ball's radius, or None to estimate it.
    to_camera : callable, optional
        Maps image pixels ``(N, 2)`` into ``camera``'s pixels (for an image
        that ``camera`` sees through a homography).

    Returns
    -------
    BallFit or None
        None when the outline is too short or the fit does not converge.
    """
    circle = silhouette_circle(mask)
    pts = upper_outline(mask)
    if circle is None or len(pts) < 6:
        return None
    cx, cy, _ = circle
    pts = pts[pts[:, 1] <= cy + 0.5]
    if len(pts) < 6:
        return None
    pix = pts + np.array([offset[0], offset[1]], float)
    centre_pix = np.array([[cx + offset[0], cy + offset[1]]])
    if to_camera is not None:
        pix = to_camera(pix)
        centre_pix = to_camera(centre_pix)
    rays = camera.pixel_ray(pix)
    origin = camera.position
    # first guess: the circle's centre ray; radius from the circle's angular size
    u = camera.pixel_ray(centre_pix)[0]
    ang = float(np.median(np.arccos(np.clip(rays @ u, -1.0, 1.0))))
    sin_a = math.sin(ang)
    if radius is None:
        if sin_a - u[2] <= 1e-6:
            return None
        d = origin[2] / (sin_a - u[2])
        r0 = d * sin_a
    else:
        r0 = radius
        if abs(u[2]) < 1e-9:
            return None
        d = (r0 - origin[2]) / u[2]
    c0 = origin + d * u
    params = np.array([c0[0], c0[1], r0] if radius is None else [c0[0], c0[1]], float)

    def residuals(p: FloatArray, use: NDArray[np.bool_]) -> FloatArray:
        r = p[2] if radius is None else radius
        centre = np.array([p[0], p[1], r])
        dvec = centre - origin
        dist = float(np.linalg.norm(dvec))
        if dist <= r:
            return np.full(int(use.sum()), 10.0)
        w = dvec / dist
        return np.arccos(np.clip(rays[use] @ w, -1.0, 1.0)) - math.asin(r / dist)

    use = np.ones(len(rays), bool)
    for _ in range(3):
        for _ in range(iterations):
            f = residuals(params, use)
            jac = np.empty((len(f), len(params)))
            for k in range(len(params)):
                step = np.zeros_like(params)
                step[k] = 1e-6
                jac[:, k] = (residuals(params + step, use) - f) / 1e-6
            delta, *_ = np.linalg.lstsq(jac, -f, rcond=None)
            params = params + delta
            if radius is None and params[2] <= 1e-3:
                return None
            if float(np.abs(delta).max()) < 1e-7:
                break
        resid = np.abs(residuals(params, np.ones(len(rays), bool)))
        keep = resid <= max(np.radians(0.15), 3.0 * float(np.median(resid[use])))
        if keep.sum() < 6 or np.array_equal(keep, use):
            break
        use = keep
    f = residuals(params, use)
    if not np.isfinite(params).all():
        return None
    r = float(params[2]) if radius is None else float(radius)
    return BallFit((float(params[0]), float(params[1])), r,
                   float(np.degrees(np.sqrt(np.mean(f**2)))), int(use.sum()))


def fit_small_ball(centroid: tuple[float, float], camera: Camera, radius: float, *,
                   to_camera: Callable[[FloatArray], FloatArray] | None = None) -> BallFit | None:
    """The floor position of a ball of known ``radius`` whose image is too small for an
    outline (a few pixels across): its centre is on the ray through the silhouette's
    ``centroid`` (image pixels), at the height of its radius.

    The fit has no outline (``points`` 0, ``rms_deg`` 0); None when that ray does not come
    down to the ball's height in front of the camera.

    Examples
    --------
    >>> cam = Camera.look_at(fx=525, fy=525, cx=319.5, cy=239.5, width=640, height=480,
    ...                      position=(0, -0.6, 0.6), look_at=(0, 3, 0.3))
    >>> seen = cam.project(np.array([[0.8, 4.0, 0.1]]))[0]
    >>> fit = fit_small_ball((float(seen[0]), float(seen[1])), cam, 0.1)
    >>> [round(v, 3) for v in fit.position], fit.points
    ([0.8, 4.0], 0)
    >>> fit_small_ball((319.5, 0.0), cam, 0.1) is None     # above the horizon
    True
    """
    pix = np.array([centroid], float)
    if to_camera is not None:
        pix = to_camera(pix)
    ray = camera.pixel_ray(pix)[0]
    origin = camera.position
    if ray[2] >= -1e-9 or origin[2] <= radius:
        return None
    t = (radius - float(origin[2])) / float(ray[2])
    at = origin + t * ray
    if not np.isfinite(at).all():
        return None
    return BallFit((float(at[0]), float(at[1])), float(radius), 0.0, 0)


def limb_points(eye: ArrayLike, centre: ArrayLike, radius: float, n: int = 32) -> FloatArray | None:
    """``n`` points (world, ``(n, 3)``) of the outline a sphere of ``radius`` centred at
    ``centre`` shows to an eye at ``eye``: the circle where the rays from the eye touch it.
    Their images bound the sphere's image. None when the eye is inside the sphere.

    Examples
    --------
    >>> pts = limb_points((0, 0, 0), (0, 5, 0), 1.0)
    >>> bool(np.allclose(np.linalg.norm(pts - (0, 5, 0), axis=1), 1.0))  # on the sphere
    True
    >>> bool(np.allclose(np.einsum("ij,ij->i", pts - (0, 5, 0), pts), 0.0))  # rays touch it
    True
    >>> limb_points((0, 0, 0), (0, 0.5, 0), 1.0) is None                 # inside it
    True
    """
    o = np.asarray(eye, float).reshape(3)
    c = np.asarray(centre, float).reshape(3)
    d = float(np.linalg.norm(c - o))
    if not d > radius:
        return None
    w = (c - o) / d
    # the circle's centre and radius: (d^2 - r^2) / d from the eye, r sqrt(d^2 - r^2) / d
    middle = o + w * (d * d - radius * radius) / d
    size = radius * math.sqrt(d * d - radius * radius) / d
    a = np.cross(w, (0.0, 0.0, 1.0) if abs(w[2]) < 0.9 else (1.0, 0.0, 0.0))
    a /= np.linalg.norm(a)
    b = np.cross(w, a)
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return middle + size * (np.outer(np.cos(t), a) + np.outer(np.sin(t), b))


def image_area(camera: Camera, centre: ArrayLike, radius: float) -> float:
    """The area (pixels) of the image of a sphere of ``radius`` centred at ``centre`` (world).

    A sphere seen from distance ``D`` subtends a cone of half-angle ``α = asin(r / D)``;
    its image, with its centre ``θ`` off the optical axis, is the ellipse of area
    ``π fx fy sin²α cos α / (cos²θ - sin²α)^(3/2)`` -- on the axis the disc of radius
    ``f tan α``.  ``inf`` when the cone reaches the image plane's horizon (or the camera
    is inside the sphere).

    Examples
    --------
    >>> cam = Camera.look_at(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
    ...                      position=(0, 0, 1), look_at=(0, 4, 1))
    >>> round(image_area(cam, (0, 4, 1), 0.1), 1)     # on the axis: a disc of f r / sqrt(D² - r²)
    491.2
    >>> round(image_area(cam, (1.5, 4, 1), 0.1), 1)   # off the axis: a larger ellipse
    524.6
    """
    pc = camera.to_camera(np.asarray(centre, float).reshape(1, 3))[0]
    d = float(np.linalg.norm(pc))
    if d <= radius:
        return math.inf
    sin_a = radius / d
    cos_t = float(pc[2]) / d
    cone = cos_t * cos_t - sin_a * sin_a
    if cos_t <= 0 or cone <= 0:
        return math.inf
    return math.pi * camera.fx * camera.fy * sin_a * sin_a * math.sqrt(1 - sin_a * sin_a) / cone ** 1.5


def visible_area(camera: Camera, centre: ArrayLike, radius: float,
                 size: tuple[int, int] | None = None, *,
                 hidden: NDArray[np.bool_] | None = None, hidden_at: tuple[int, int] = (0, 0),
                 to_camera: Callable[[FloatArray], FloatArray] | None = None) -> float:
    """The area (pixels) of the image of a sphere that can show in an image of ``size``
    ``(width, height)``: its pixels inside the image (anywhere, without ``size``) and not
    ``hidden``.

    :func:`image_area` when the image holds it whole and nothing hides it; else its pixels
    counted.  ``hidden`` is a mask of pixels something else covers (in front of the
    sphere, or a part of the image that is not searched), whose top-left pixel is at
    ``hidden_at`` in the image.  ``to_camera`` maps the image's pixels into ``camera``'s (an
    image that ``camera`` sees through a homography); the area is in the image's pixels.

    Examples
    --------
    >>> cam = Camera.look_at(fx=500, fy=500, cx=319.5, cy=239.5, width=640, height=480,
    ...                      position=(0, 0, 1), look_at=(0, 4, 1))
    >>> whole = visible_area(cam, (0, 4, 1), 0.1, (640, 480))
    >>> round(whole, 1)                                        # in view, nothing in front
    491.2
    >>> below = np.zeros((480, 640), bool)
    >>> below[240:] = True                                     # its lower half hidden
    >>> round(visible_area(cam, (0, 4, 1), 0.1, (640, 480), hidden=below) / whole, 1)
    0.5
    >>> round(visible_area(cam, (0, 4, 1), 0.1, (320, 480)) / whole, 1)   # cut by the side
    0.5
    """
    area = image_area(camera, centre, radius)
    if not math.isfinite(area):
        return area
    c = np.asarray(centre, float).reshape(3)
    pc = camera.to_camera(c.reshape(1, 3))[0]
    seen = np.array([[camera.fx * pc[0] / pc[2] + camera.cx, camera.fy * pc[1] / pc[2] + camera.cy]])
    if to_camera is not None:
        # the image pixel that shows the centre: one Newton step from the camera's pixel,
        # plenty for a homography near the identity
        seen = seen - (to_camera(seen) - seen)
    # the ellipse's semi-major axis is at most 3 equivalent radii while its axes' ratio is
    # at most 9 (beyond, near the horizon, it is no ball's image anyway)
    reach = 3.0 * math.sqrt(area / math.pi) + 2.0
    x, y = float(seen[0, 0]), float(seen[0, 1])
    x0, x1 = int(math.floor(x - reach)), int(math.ceil(x + reach))
    y0, y1 = int(math.floor(y - reach)), int(math.ceil(y + reach))
    inside = True
    if size is not None:
        w, h = size
        inside = x0 >= 0 and y0 >= 0 and x1 <= w - 1 and y1 <= h - 1
        x0, x1, y0, y1 = max(x0, 0), min(x1, w - 1), max(y0, 0), min(y1, h - 1)
        if x0 > x1 or y0 > y1:
            return 0.0
    to_c = c - camera.position
    dist = float(np.linalg.norm(to_c))
    cos_cone = math.cos(math.asin(radius / dist))

    def disc(bx0: int, by0: int, bx1: int, by1: int) -> NDArray[np.bool_]:
        """The sphere's pixels in the box (inclusive bounds), within an image's size."""
        yy, xx = np.mgrid[by0:by1 + 1, bx0:bx1 + 1]
        pix = np.c_[xx.ravel(), yy.ravel()].astype(np.float64)
        if to_camera is not None:
            pix = to_camera(pix)
        return (camera.pixel_ray(pix) @ (to_c / dist) >= cos_cone).reshape(yy.shape)

    # counted only within the frame (when the box crosses its edges) and within what is
    # hidden: never more pixels than the images have, however large the ellipse
    shows = area if inside else float(np.count_nonzero(disc(x0, y0, x1, y1)))
    if hidden is not None:
        hx, hy = hidden_at
        ox0, oy0 = max(x0, hx), max(y0, hy)
        ox1, oy1 = min(x1, hx + hidden.shape[1] - 1), min(y1, hy + hidden.shape[0] - 1)
        if ox0 <= ox1 and oy0 <= oy1:
            part = hidden[oy0 - hy:oy1 - hy + 1, ox0 - hx:ox1 - hx + 1]
            if part.any():
                shows -= float(np.count_nonzero(disc(ox0, oy0, ox1, oy1) & part))
    return max(shows, 0.0)


def silhouette_length(mask: NDArray[np.bool_]) -> float:
    """The length (pixels) of a silhouette along its longest axis: that of the ellipse with
    its second moments (``4 sqrt(λ_max)`` of their covariance; a disc's diameter, a
    streak's length), 0 for an empty mask.

    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:41, 0:41]
    >>> round(silhouette_length((xx - 20) ** 2 + (yy - 20) ** 2 <= 15 ** 2), 1)  # radius 15
    30.1
    >>> round(silhouette_length(np.ones((21, 8), bool)), 1)  # a streak 21 long
    24.2
    """
    ys, xs = np.nonzero(mask)
    if len(xs) < 2:
        return 0.0 if len(xs) == 0 else 1.0
    cov = np.cov(np.vstack([xs, ys]).astype(np.float64), bias=True)
    return float(4.0 * math.sqrt(max(float(np.linalg.eigvalsh(cov)[-1]), 0.0)))
