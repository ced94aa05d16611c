"""The map-aware analytic predictor: straight lines, a rolling deceleration and specular
reflections off the known walls and obstacles.

It is what robot-football teams write to predict a ball: from a position and a
velocity (a Kalman filter's estimate, say) the ball rolls in a straight line,
slowing at a constant ``c g`` (the ball model's nominal rolling resistance)
until it stops, and reflects off every wall and obstacle of the map it meets:
the velocity's component along the surface's normal is reversed and scaled by
the nominal restitution (the ball's times the surface's, as the imagination
combines them); the component along the surface is kept.  A ball of radius
``r`` meets a wall when its centre comes within ``r`` of the wall's segment
(a face, or an end as a round corner) and an obstacle when it comes within
``r`` of its polygon.  No spin, no friction at a contact, no other ball.

The baseline the mirror must beat on realities it did not write
(``adapt/runner/mapaware.py`` drives a robot with it).

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
>>> model = Reflector(scene, Ball("ball", radius=0.1, restitution=0.8, rolling_resistance=0.0))
>>> positions, velocities = model.path((0.0, 0.0), (1.0, 0.0), [0.5, 1.5])
>>> positions.round(3).tolist(), velocities.round(3).tolist()
([[0.5, 0.0], [0.42, 0.0]], [[1.0, 0.0], [-0.8, 0.0]])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from adapt.imagination.scene import Ball, SceneSpec

__all__ = ["Reflector", "Hit", "MAX_BOUNCES", "REST_SPEED"]

#: Most reflections a path follows (a ball trapped in a corner stops there).
MAX_BOUNCES = 200
#: Below this speed the ball is at rest, m/s.
REST_SPEED = 1e-3

FloatArray = NDArray[np.float64]
Vec2 = tuple[float, float]


@dataclass(frozen=True, slots=True)
class Hit:
    """Where a rolling ball's straight path first meets a surface: ``distance`` along
    the path, the surface's outward ``normal`` there, its ``restitution`` and ``name``."""

    distance: float
    normal: Vec2
    restitution: float
    name: str


@dataclass(frozen=True, slots=True)
class _Face:
    """A segment ``a-b`` the ball's centre stays ``r`` away from."""

    a: Vec2
    b: Vec2
    restitution: float
    name: str


class Reflector:
    """The analytic predictor of one ball in one scene (see the module docstring).

    Parameters
    ----------
    scene : SceneSpec
        The walls and obstacles (the map); ``scene.gravity`` scales the deceleration.
    ball : Ball
        Its ``radius``, nominal ``restitution`` and ``rolling_resistance``.
    """

    def __init__(self, scene: SceneSpec, ball: Ball) -> None:
        self.radius = float(ball.radius)
        self.deceleration = float(ball.rolling_resistance) * float(scene.gravity)
        faces: list[_Face] = []
        for w in scene.walls:
            faces.append(_Face(w.start, w.end, ball.restitution * w.restitution, w.name))
        for o in scene.obstacles:
            n = len(o.polygon)
            for k in range(n):
                faces.append(_Face(o.polygon[k], o.polygon[(k + 1) % n],
                                   ball.restitution * o.restitution, o.name))
        self.faces = tuple(faces)

    # -- one straight piece -------------------------------------------------------------------

    def first_hit(self, position: Sequence[float] | FloatArray,
                  direction: Sequence[float] | FloatArray) -> Hit | None:
        """The first surface a ball at ``position`` rolling along the unit ``direction``
        meets (None: none, however far)."""
        px, py = float(position[0]), float(position[1])
        dx, dy = float(direction[0]), float(direction[1])
        r = self.radius
        best: Hit | None = None
        for f in self.faces:
            (ax, ay), (bx, by) = f.a, f.b
            ex, ey = bx - ax, by - ay
            length = math.hypot(ex, ey)
            if length < 1e-12:
                continue
            ux, uy = ex / length, ey / length
            # both sides of the segment: the side the ball's centre is on faces it
            nx, ny = -uy, ux
            side = (px - ax) * nx + (py - ay) * ny
            if side < 0:
                nx, ny, side = -nx, -ny, -side
            approach = dx * nx + dy * ny
            if approach < -1e-12:
                s = max(0.0, (side - r) / -approach)
                hx, hy = px + s * dx, py + s * dy
                along = (hx - ax) * ux + (hy - ay) * uy
                if 0.0 <= along <= length and (best is None or s < best.distance):
                    best = Hit(s, (nx, ny), f.restitution, f.name)
            for cx, cy in (f.a, f.b):  # the ends, as round corners
                s_c = _circle(px - cx, py - cy, dx, dy, r)
                if s_c is not None and (best is None or s_c < best.distance):
                    hx, hy = px + s_c * dx - cx, py + s_c * dy - cy
                    norm = math.hypot(hx, hy) or 1.0
                    best = Hit(s_c, (hx / norm, hy / norm), f.restitution, f.name)
        return best

    # -- the path ---------------------------------------------------------------------------

    def path(self, position: Sequence[float] | FloatArray, velocity: Sequence[float] | FloatArray,
             times: Sequence[float] | FloatArray) -> tuple[FloatArray, FloatArray]:
        """Positions and velocities at ``times`` (seconds after now, increasing, >= 0) of a
        ball at ``position`` moving at ``velocity`` now: ``(N, 2)`` arrays each."""
        ts = np.asarray(times, float)
        positions = np.zeros((len(ts), 2))
        velocities = np.zeros((len(ts), 2))
        p = np.array(position[:2], float)
        v = np.array(velocity[:2], float)
        t0 = 0.0  # the time of the current piece's start
        a = self.deceleration
        k = 0
        bounces = 0
        while k < len(ts):
            speed = float(np.hypot(*v))
            if speed < REST_SPEED or bounces >= MAX_BOUNCES:
                positions[k:] = p
                velocities[k:] = 0.0
                break
            d = v / speed
            stop = speed / a if a > 0 else math.inf
            hit = self.first_hit(p, d)
            t_hit = math.inf
            if hit is not None:
                t_hit = _time_to(hit.distance, speed, a)
            end = min(t_hit, stop)
            while k < len(ts) and ts[k] - t0 <= end:
                dt = ts[k] - t0
                positions[k] = p + d * (speed * dt - 0.5 * a * dt * dt)
                velocities[k] = d * (speed - a * dt)
                k += 1
            if k >= len(ts) or not math.isfinite(end):
                break
            if end == stop and stop <= t_hit:
                p = p + d * (0.5 * speed * stop)
                v = np.zeros(2)
                t0 += stop
                continue
            assert hit is not None
            p = p + d * hit.distance
            arrive = d * (speed - a * t_hit)
            n = np.array(hit.normal)
            vn = float(arrive @ n)
            v = arrive - (1.0 + hit.restitution) * vn * n
            t0 += t_hit
            bounces += 1
        return positions, velocities


def _time_to(distance: float, speed: float, deceleration: float) -> float:
    """When a ball at ``speed`` slowing at ``deceleration`` has rolled ``distance`` (inf:
    it stops before)."""
    if deceleration <= 0:
        return distance / speed
    disc = speed * speed - 2.0 * deceleration * distance
    if disc < 0:
        return math.inf
    return (speed - math.sqrt(disc)) / deceleration


def _circle(qx: float, qy: float, dx: float, dy: float, r: float) -> float | None:
    """The first ``s >= 0`` where ``|q + s d| = r`` while approaching the circle's centre
    (0 when already inside it and approaching); None when it does not come that close."""
    b = qx * dx + qy * dy
    if b >= 0:
        return None  # moving away from the corner
    c = qx * qx + qy * qy - r * r
    if c <= 0:
        return 0.0
    disc = b * b - c
    if disc < 0:
        return None
    return -b - math.sqrt(disc)
