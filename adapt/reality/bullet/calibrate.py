"""What a PyBullet ball's contacts really do, measured from PyBullet's own contacts.

The coefficients passed to PyBullet are not what a ball does: PyBullet combines
a ball's with a surface's (restitution and friction multiply), its solver adds
losses of its own, a rolling ball keeps its spin through a bounce, and damping
acts on top of rolling friction.  So the "true" parameters a PyBullet reality
reports for evaluation are **measured**, per run, in a separate PyBullet client
with the run's drawn values (:func:`measure`), by three short experiments with
the ball rolling (its spin that of rolling without slip, as a ball on the floor has):

* **roll**: on the floor alone from 3 m/s until it stops; the deceleration
  ``a(v)`` is fitted by ``c g + drag v^2`` (least squares over ``0.1 < v``):
  ``rolling_resistance = c``, ``drag``;
* **head-on**: at 1.5 m/s into a wall (and into an obstacle): the normal speed
  just after the contact over the one just before is the **restitution**; the
  speed 0.5 s later (the rolling loss put back) over the one before is the
  **settled restitution**: the ball's forward spin, kept through the bounce,
  slows it on the floor afterwards.  ``spin`` is what the synthetic reality
  calls it: ``(e - settled) 7 / (2 (1 + e))``, the share of the spin kept;
* **oblique**: at 1.5 m/s and 45 degrees into the wall: the tangential speed lost
  in the contact over ``(1 + e)`` times the normal speed is the **friction**.

Each takes a few thousand steps of a few microseconds.  :class:`Effective`
holds the results; a quantity an experiment could not measure (a ball too slow
to reach the wall) is NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from adapt.reality.bullet.client import Client
from adapt.reality.bullet.draw import BallDraw, SurfaceDraw

__all__ = ["Effective", "measure", "ROLL_SPEED", "HIT_SPEED"]

#: Speed the roll starts at, and the speed the ball hits the wall at, m/s.
ROLL_SPEED = 3.0
HIT_SPEED = 1.5
#: How long after a contact the settled speed is read, seconds.
SETTLE = 0.5


@dataclass(frozen=True, slots=True)
class Effective:
    """A ball's contacts as measured (see the module docstring); NaN: not measured."""

    rolling_resistance: float
    drag: float
    restitution_walls: float
    settled_walls: float
    spin: float
    friction_walls: float
    restitution_obstacles: float

    def as_json(self) -> dict[str, Any]:
        """A JSON-ready dict (NaN as None)."""
        return {k: (None if not math.isfinite(v) else round(v, 5))
                for k, v in ((f, getattr(self, f)) for f in self.__dataclass_fields__)}


def _world(ball: BallDraw, floor: SurfaceDraw, gravity: float, dt: float,
           surface: SurfaceDraw | None, heading_deg: float = 0.0,
           speed: float = HIT_SPEED) -> tuple[Client, int]:
    """A client with the floor, maybe a wall or obstacle box whose face is at ``x = 1``,
    and the ball rolling from ``x = 0.4`` at ``speed`` along ``heading_deg``."""
    c = Client()
    c.setGravity(0, 0, -gravity)
    c.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=1, restitutionVelocityThreshold=0.05,
                                useSplitImpulse=1, deterministicOverlappingPairs=1)
    plane = c.createMultiBody(baseMass=0, baseCollisionShapeIndex=c.createCollisionShape(c.GEOM_PLANE))
    c.changeDynamics(plane, -1, restitution=floor.restitution, lateralFriction=floor.friction,
                     rollingFriction=floor.rolling_friction,
                     spinningFriction=floor.spinning_friction, contactProcessingThreshold=0.0)
    if surface is not None:
        box = c.createCollisionShape(c.GEOM_BOX, halfExtents=[0.1, 3.0, 0.5])
        wall = c.createMultiBody(baseMass=0, baseCollisionShapeIndex=box, basePosition=[1.1, 0, 0.5])
        c.changeDynamics(wall, -1, restitution=surface.restitution,
                         lateralFriction=surface.friction,
                         rollingFriction=surface.rolling_friction,
                         spinningFriction=surface.spinning_friction, contactProcessingThreshold=0.0)
    r = ball.radius
    body = c.createMultiBody(baseMass=ball.mass,
                             baseCollisionShapeIndex=c.createCollisionShape(c.GEOM_SPHERE, radius=r),
                             basePosition=[0.4 if surface is not None else 0.0, 0, r])
    c.changeDynamics(body, -1, restitution=ball.restitution, lateralFriction=ball.friction,
                     rollingFriction=ball.rolling_friction, spinningFriction=ball.spinning_friction,
                     linearDamping=ball.damping, angularDamping=ball.damping,
                     contactProcessingThreshold=0.0,
                     activationState=c.ACTIVATION_STATE_DISABLE_SLEEPING)
    h = math.radians(heading_deg)
    v = (speed * math.cos(h), speed * math.sin(h))
    c.resetBaseVelocity(body, [v[0], v[1], 0.0], [-v[1] / r, v[0] / r, 0.0])
    return c, body


def _run(c: Client, body: int, seconds: float, dt: float) -> np.ndarray:
    """``(t, vx, vy)`` after each step for ``seconds``."""
    out = []
    for k in range(int(round(seconds / dt))):
        c.stepSimulation()
        (vx, vy, _), _ = c.getBaseVelocity(body)
        out.append(((k + 1) * dt, vx, vy))
    return np.array(out)


def _roll(ball: BallDraw, floor: SurfaceDraw, gravity: float, dt: float) -> tuple[float, float]:
    """``(c, drag)`` from a roll on the floor."""
    c, body = _world(ball, floor, gravity, dt, None, speed=ROLL_SPEED)
    with c:
        track = _run(c, body, 6.0, dt)
    t = track[:, 0]
    speed = np.hypot(track[:, 1], track[:, 2])
    k = max(1, int(round(0.02 / dt)))
    ts, vs = t[::k], speed[::k]
    if len(vs) < 3:
        return math.nan, math.nan
    decel = -(vs[2:] - vs[:-2]) / (ts[2:] - ts[:-2])
    v = vs[1:-1]
    keep = v > 0.1
    if keep.sum() < 3:
        return math.nan, math.nan
    a, v = decel[keep], v[keep]
    design = np.stack([np.full_like(v, gravity), v ** 2], axis=1)
    (c_fit, drag), *_ = np.linalg.lstsq(design, a, rcond=None)
    if drag < 0:
        c_fit, drag = float(np.mean(a)) / gravity, 0.0
    return max(0.0, float(c_fit)), float(drag)


def _hit(ball: BallDraw, floor: SurfaceDraw, surface: SurfaceDraw, gravity: float, dt: float,
         heading_deg: float) -> tuple[float, float, float, float, float, float] | None:
    """``(vn_before, vt_before, vn_after, vt_after, vn_settled, t_settle)`` of a hit on the
    wall at ``x = 1`` (normal ``-x``), or None when the ball never came back."""
    c, body = _world(ball, floor, gravity, dt, surface, heading_deg)
    with c:
        track = _run(c, body, 2.0 + SETTLE, dt)
    vx, vy = track[:, 1], track[:, 2]
    back = np.nonzero(vx < 0)[0]
    if len(back) == 0:
        return None
    i = int(back[0])
    before = max(0, i - int(round(0.01 / dt)))
    j = before
    # the contact's start: the first step whose normal speed fell by more than 2 %
    while j < i and vx[j + 1] > 0.98 * vx[j]:
        j += 1
    window = track[i:i + int(round(0.02 / dt)) + 1]
    k = i + int(np.argmin(window[:, 1]))
    settle = min(len(vx) - 1, i + int(round(SETTLE / dt)))
    return (float(vx[j]), float(vy[j]), float(-vx[k]), float(vy[k]), float(-vx[settle]),
            float(track[settle, 0] - track[k, 0]))


def measure(ball: BallDraw, floor: SurfaceDraw, walls: SurfaceDraw, obstacles: SurfaceDraw,
            gravity: float, dt: float) -> Effective:
    """The ball's effective contact parameters (see the module docstring)."""
    c_fit, drag = _roll(ball, floor, gravity, dt)
    e = settled = spin = mu = e_obs = math.nan
    head = _hit(ball, floor, walls, gravity, dt, 0.0)
    if head is not None and head[0] > 0:
        vn, _, back, _, later, seconds = head
        e = back / vn
        if math.isfinite(c_fit):
            later += (c_fit * gravity + drag * later ** 2) * seconds
        settled = later / vn
        spin = min(1.0, max(0.0, (e - settled) * 7.0 / (2.0 * (1.0 + e))))
    oblique = _hit(ball, floor, walls, gravity, dt, 45.0)
    if oblique is not None and oblique[0] > 0:
        vn, vt, back, vt_after, _, _ = oblique
        e45 = back / vn
        mu = max(0.0, (vt - vt_after) / ((1.0 + e45) * vn))
    obst = _hit(ball, floor, obstacles, gravity, dt, 0.0)
    if obst is not None and obst[0] > 0:
        e_obs = obst[2] / obst[0]
    return Effective(c_fit, drag, e, settled, spin, mu, e_obs)
