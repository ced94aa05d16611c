"""Ball tracks made by PyBullet, for developing identification offline (no rendering).

A sphere rolls on a floor inside a square arena of box walls with two prism
obstacles; everything physical is drawn per seed from wide ranges
(restitution, lateral, rolling and spinning friction of the ball and of each
surface, damping, the ball's size and mass, its start: rolling, sliding,
spinning sideways or dropped), and PyBullet's own 3D contacts decide what
happens.  The track is sampled at 30 frames/s: the true centre, velocity and
spin, and a *sighting* -- the centre as a camera above the arena would place
it on the ground plane (a ball off the floor, after a hop, is seen further
from the camera), with noise growing with the distance, and a few frames
missed.

The scene the observer knows (wall faces and obstacle outlines as segments
and polygons, the ball's radius) comes with each track as an
:class:`adapt.imagination.SceneSpec`; nothing in it says how the ball
behaves.

``python bench/bullet_tracks.py --seeds 3`` prints a summary of a few tracks.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from adapt.imagination.scene import Ball, Obstacle, SceneSpec, Wall  # noqa: E402

FPS = 30.0
#: Half the arena's side, metres (a 3 m x 3 m arena).
HALF = 1.5
#: Wall thickness, metres.
THICK = 0.12


@dataclass(frozen=True)
class Track:
    """One throw: what the observer knows and sees, and the truth."""

    seed: int
    scene: SceneSpec          # walls (inner faces) and obstacles; the ball's radius
    radius: float
    params: dict[str, float]  # what was passed to PyBullet (for the record)
    times: np.ndarray         # (T,) seconds
    truth: np.ndarray         # (T, 3) true centre x, y and height above resting (z - r)
    velocity: np.ndarray      # (T, 3) true linear velocity
    spin: np.ndarray          # (T, 3) true angular velocity, rad/s
    seen: np.ndarray          # (T, 2) sighting on the ground plane; NaN when missed
    camera: tuple[float, float, float]
    noise: float              # sighting noise at 2.5 m from the camera, metres

    def sightings(self) -> list[tuple[float, tuple[float, float] | None]]:
        """``(time, position or None)`` per frame."""
        out: list[tuple[float, tuple[float, float] | None]] = []
        for t, p in zip(self.times, self.seen):
            out.append((float(t), None if np.isnan(p[0]) else (float(p[0]), float(p[1]))))
        return out


def _convex(rng: np.random.Generator, centre: np.ndarray, size: float) -> list[tuple[float, float]]:
    """A random convex outline: a rotated box or a triangle."""
    angle = rng.uniform(0, math.pi)
    if rng.random() < 0.6:
        a, b = size * rng.uniform(0.5, 1.0), size * rng.uniform(0.35, 0.8)
        corners = [(-a, -b), (a, -b), (a, b), (-a, b)]
    else:
        corners = [(size * math.cos(t), size * math.sin(t))
                   for t in np.sort(rng.uniform(0, 2 * math.pi, 3))]
        # keep it fat: redraw thin triangles as equilateral-ish ones
        area = abs((corners[1][0] - corners[0][0]) * (corners[2][1] - corners[0][1])
                   - (corners[2][0] - corners[0][0]) * (corners[1][1] - corners[0][1])) / 2
        if area < 0.5 * size * size:
            corners = [(size * math.cos(t), size * math.sin(t))
                       for t in (0.0, 2.1, 4.2)]
    c, s = math.cos(angle), math.sin(angle)
    return [(float(centre[0] + c * x - s * y), float(centre[1] + s * x + c * y)) for x, y in corners]


def _inside(poly: list[tuple[float, float]], p: np.ndarray, margin: float) -> bool:
    """``p`` within ``margin`` of the convex polygon (or inside it)."""
    n = len(poly)
    area = sum(poly[i][0] * poly[(i + 1) % n][1] - poly[(i + 1) % n][0] * poly[i][1]
               for i in range(n))
    sign = 1.0 if area > 0 else -1.0
    worst = -math.inf
    for i in range(n):
        ax, ay = poly[i]
        bx, by = poly[(i + 1) % n]
        ex, ey = bx - ax, by - ay
        length = math.hypot(ex, ey)
        # outward distance from this edge's line
        d = sign * ((p[0] - ax) * ey - (p[1] - ay) * ex) / length
        worst = max(worst, d)
    return worst < margin


def make_track(seed: int, duration: float = 6.0) -> Track:
    """One randomized throw (see the module docstring)."""
    import pybullet as pb

    rng = np.random.default_rng([seed, 20])
    client = pb.connect(pb.DIRECT)
    try:
        return _make(pb, client, rng, seed, duration)
    finally:
        pb.disconnect(client)


def _make(pb, client: int, rng: np.random.Generator, seed: int, duration: float) -> Track:  # type: ignore[no-untyped-def]
    # every body's contact processing threshold is 0: with Bullet's default a finer step loses
    # restitution (a wall bounce of 0.8 x 1.0 keeps 0.82 of the normal speed at 1/240 s, 0.41
    # at 1/480 s and nothing at 1/960 s)
    dt = float(rng.choice([1 / 240, 1 / 480, 1 / 960]))
    pb.setGravity(0, 0, -9.81, physicsClientId=client)
    pb.setTimeStep(dt, physicsClientId=client)
    radius = float(rng.uniform(0.06, 0.12))
    params: dict[str, float] = {"dt": dt, "radius": radius}
    floor = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client),
                               physicsClientId=client)
    params["floor_friction"] = float(rng.uniform(0.4, 1.2))
    params["floor_restitution"] = float(rng.uniform(0.2, 0.7))
    pb.changeDynamics(floor, -1, lateralFriction=params["floor_friction"],
                      restitution=params["floor_restitution"], contactProcessingThreshold=0.0,
                      physicsClientId=client)
    walls: list[Wall] = []
    corners = [(-HALF, -HALF), (HALF, -HALF), (HALF, HALF), (-HALF, HALF)]
    names = ["south", "east", "north", "west"]
    for i, name in enumerate(names):
        a, b = np.array(corners[i]), np.array(corners[(i + 1) % 4])
        height = float(rng.uniform(max(0.12, radius + 0.01), 0.5))
        e_w, mu_w = float(rng.uniform(0.6, 1.0)), float(rng.uniform(0.2, 1.0))
        params[f"{name}_restitution"], params[f"{name}_friction"] = e_w, mu_w
        mid = (a + b) / 2
        along = (b - a) / np.linalg.norm(b - a)
        out = np.array([along[1], -along[0]])  # outward (the arena is counter-clockwise)
        centre = mid + out * THICK / 2
        half = [HALF + THICK, THICK / 2, height / 2] if abs(along[0]) > 0.5 else \
            [THICK / 2, HALF + THICK, height / 2]
        body = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half,
                                                             physicsClientId=client),
                                  basePosition=[centre[0], centre[1], height / 2],
                                  physicsClientId=client)
        pb.changeDynamics(body, -1, restitution=e_w, lateralFriction=mu_w,
                          contactProcessingThreshold=0.0, physicsClientId=client)
        walls.append(Wall(name, tuple(a), tuple(b), height=height))  # type: ignore[arg-type]
    obstacles: list[Obstacle] = []
    placed: list[np.ndarray] = []
    while len(obstacles) < 2:
        centre = rng.uniform(-0.9, 0.9, 2)
        if any(np.linalg.norm(centre - c) < 0.9 for c in placed):
            continue
        size = float(rng.uniform(0.15, 0.3))
        poly = _convex(rng, centre, size)
        height = float(rng.uniform(0.2, 0.5))
        e_o, mu_o = float(rng.uniform(0.6, 1.0)), float(rng.uniform(0.2, 1.0))
        k = len(obstacles)
        params[f"obstacle{k}_restitution"], params[f"obstacle{k}_friction"] = e_o, mu_o
        verts = [[x, y, z] for z in (0.0, height) for x, y in poly]
        shape = pb.createCollisionShape(pb.GEOM_MESH, vertices=verts, physicsClientId=client)
        body = pb.createMultiBody(0, shape, physicsClientId=client)
        pb.changeDynamics(body, -1, restitution=e_o, lateralFriction=mu_o,
                          contactProcessingThreshold=0.0, physicsClientId=client)
        obstacles.append(Obstacle(f"obstacle{k}", tuple(poly), height=height))  # type: ignore[arg-type]
        placed.append(centre)
    # the ball
    mass = float(rng.uniform(0.1, 1.0))
    params.update(mass=mass, restitution=float(rng.uniform(0.5, 0.95)),
                  lateral_friction=float(rng.uniform(0.2, 0.9)),
                  # a rolling deceleration of about (5/7) rf g / r: 0.003 g to 0.04 g
                  rolling_friction=float(rng.uniform(0.0042, 0.056) * radius),
                  spinning_friction=float(rng.uniform(0.0, 0.005)),
                  linear_damping=float(rng.uniform(0.0, 0.06)),
                  angular_damping=float(rng.uniform(0.0, 0.1)))
    while True:
        start = rng.uniform(-HALF + radius + 0.1, HALF - radius - 0.1, 2)
        if not any(_inside(list(o.polygon), start, radius + 0.1) for o in obstacles):
            break
    speed = float(rng.uniform(1.0, 3.5))
    heading = float(rng.uniform(0, 2 * math.pi))
    v = speed * np.array([math.cos(heading), math.sin(heading)])
    kind = rng.random()
    roll = 1.0 if kind < 0.55 else float(rng.uniform(-0.3, 1.2))
    side = float(rng.uniform(-10, 10)) if rng.random() < 0.4 else 0.0
    drop = float(rng.uniform(0.02, 0.3)) if rng.random() < 0.25 else 0.0
    params.update(speed=speed, roll=roll, side_spin=side, drop=drop)
    ball = pb.createMultiBody(mass, pb.createCollisionShape(pb.GEOM_SPHERE, radius=radius,
                                                            physicsClientId=client),
                              basePosition=[start[0], start[1], radius + drop],
                              physicsClientId=client)
    pb.changeDynamics(ball, -1, restitution=params["restitution"],
                      lateralFriction=params["lateral_friction"],
                      rollingFriction=params["rolling_friction"],
                      spinningFriction=params["spinning_friction"],
                      linearDamping=params["linear_damping"],
                      angularDamping=params["angular_damping"], contactProcessingThreshold=0.0,
                      physicsClientId=client)
    # rolling without slipping at v: omega = z x v / r
    w = roll * np.array([-v[1], v[0], 0.0]) / radius
    w[2] = side
    pb.resetBaseVelocity(ball, [v[0], v[1], 0.0], w.tolist(), physicsClientId=client)
    # the camera: outside the arena above a wall, or above it
    if rng.random() < 0.6:
        cam = (float(rng.uniform(-1.0, 1.0)), float(-HALF - rng.uniform(0.2, 0.8)),
               float(rng.uniform(1.8, 2.8)))
    else:
        cam = (float(rng.uniform(-0.5, 0.5)), float(rng.uniform(-0.5, 0.5)),
               float(rng.uniform(2.5, 3.5)))
    noise = float(rng.uniform(0.001, 0.005))
    steps_per = int(round(1.0 / (FPS * dt)))
    n = int(round(duration * FPS)) + 1
    times = np.arange(n) / FPS
    truth = np.empty((n, 3))
    vel = np.empty((n, 3))
    spin = np.empty((n, 3))
    for i in range(n):
        if i:
            for _ in range(steps_per):
                pb.stepSimulation(physicsClientId=client)
        p, _ = pb.getBasePositionAndOrientation(ball, physicsClientId=client)
        lv, av = pb.getBaseVelocity(ball, physicsClientId=client)
        truth[i] = (p[0], p[1], p[2] - radius)
        vel[i] = lv
        spin[i] = av
    # sightings: the ray from the camera through the centre, met with the plane z = r
    c = np.array(cam)
    centre = np.c_[truth[:, :2], truth[:, 2] + radius]
    scale = (c[2] - radius) / np.maximum(c[2] - centre[:, 2], 1e-3)
    ground = c[None, :2] + (centre[:, :2] - c[None, :2]) * scale[:, None]
    dist = np.linalg.norm(centre - c[None, :], axis=1)
    seen = ground + rng.standard_normal((n, 2)) * (noise * dist / 2.5)[:, None]
    seen[rng.random(n) < 0.03] = np.nan
    scene = SceneSpec(walls=tuple(walls), obstacles=tuple(obstacles),
                      balls=(Ball("ball", radius=radius, mass=mass),))
    return Track(seed, scene, radius, params, times, truth, vel, spin, seen, cam, noise)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    for seed in range(1, args.seeds + 1):
        t = make_track(seed)
        speed = np.linalg.norm(t.velocity[:, :2], axis=1)
        hop = float(t.truth[:, 2].max())
        err = np.nanmedian(np.linalg.norm(t.seen - t.truth[:, :2], axis=1))
        print(f"seed {seed}: r={t.radius:.3f} e={t.params['restitution']:.2f} "
              f"mu={t.params['lateral_friction']:.2f} speed {speed[0]:.2f} -> {speed[-1]:.2f} m/s, "
              f"highest hop {100 * hop:.1f} cm, sighting error {1000 * err:.1f} mm")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
