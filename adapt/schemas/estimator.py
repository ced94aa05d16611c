"""Online estimates of a ball's restitution, friction and rolling resistance.

What is known before an object is seen is a range per parameter (the
scenario's ``ranges``); :class:`ParameterEstimator` turns each observed
event into a measurement and narrows the range into an estimate with an
uncertainty, so predictions improve as the run goes on:

* **a bounce** (the velocity turns abruptly): the velocities before and
  after are straight-line fits of the sightings on each side; the surface
  hit is the static surface nearest to where the two lines meet; with its
  normal ``n``, the measured restitution of the pair is
  ``e = -(v_after . n) / (v_before . n)`` and, as the physics combines them
  by product, the ball's is ``e / e_surface``; the friction of the pair,
  from the tangential speed lost, is ``dv_t / ((1 + e) |v_n|)``, the ball's
  ``/ mu_surface``;
* **free rolling** between bounces: a quadratic fit of the positions gives
  the deceleration along the motion, and the rolling resistance is
  ``deceleration / g``.  The fit spans the whole stretch since the last
  bounce (up to :data:`ROLL_SPAN`), refitted as it grows, and the stretch's
  one measurement replaces its previous one (a quadratic term's noise falls
  with the square of the span: one long fit is worth far more than many short
  ones).

Each parameter is a Gaussian (mean, standard deviation): the prior is the
range's middle with the standard deviation of a uniform draw over it, and
each measurement updates it with its own variance.  The estimate is free to
leave the range when reality does; :attr:`Estimate.surprise` says by how
many prior standard deviations it has.

Examples
--------
>>> est = ParameterEstimator({"restitution": (0.6, 0.9)}, nominal={"restitution": 0.75})
>>> est.estimate("restitution").std > 0.08
True
>>> est.measure("restitution", 0.66, 0.02)
>>> e = est.estimate("restitution")
>>> round(e.mean, 3), e.std < 0.02, e.count
(0.665, True, 1)
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from adapt.imagination.scene import SceneSpec

__all__ = ["Estimate", "Bounce", "ParameterEstimator", "PARAMETERS", "nearest_surface",
           "surprise"]

#: The parameters estimated.
PARAMETERS = ("restitution", "friction", "rolling_resistance")

#: Sightings fitted on each side of a bounce.
SIDE = 5
#: Least time of free rolling fitted for the rolling resistance, seconds.
MIN_ROLL = 0.3
#: Longest stretch of free rolling fitted (the latest part), seconds.
ROLL_SPAN = 2.5
#: Speeds below which nothing is measured (a ball at rest says nothing), m/s.
MIN_SPEED = 0.15
#: A bounce measured outside these restitutions of the pair is not one off a flat surface.
MIN_PAIR_RESTITUTION, MAX_PAIR_RESTITUTION = 0.05, 1.05


@dataclass(frozen=True, slots=True)
class Estimate:
    """A parameter's current estimate.

    ``surprise`` is how far (in prior standard deviations) the mean lies
    outside the prior range; 0 inside it.
    """

    name: str
    mean: float
    std: float
    count: int
    surprise: float

    def as_json(self) -> dict[str, float | int]:
        """JSON form."""
        return {"mean": round(self.mean, 4), "std": round(self.std, 4), "n": self.count,
                "surprise": round(self.surprise, 2)}


def surprise(mean: float, low: float, high: float) -> float:
    """How far ``mean`` lies outside the prior range ``[low, high]``, in the standard
    deviations of a uniform draw over it (0 inside it).

    Examples
    --------
    >>> surprise(0.5, 0.4, 0.7), round(surprise(0.9, 0.4, 0.7), 2)
    (0.0, 2.31)
    """
    outside = max(low - mean, mean - high, 0.0)
    pstd = (high - low) / math.sqrt(12.0)
    return outside / pstd if pstd > 0 else (0.0 if outside < 1e-9 else math.inf)


@dataclass(frozen=True, slots=True)
class Bounce:
    """A bounce seen in the sightings."""

    time: float
    surface: str
    position: tuple[float, float]
    normal: tuple[float, float]
    speed_in: float
    restitution: float | None
    friction: float | None


def nearest_surface(scene: SceneSpec, point: Sequence[float]
                    ) -> tuple[str, float, tuple[float, float], float, float] | None:
    """The static surface nearest to ``point``: ``(name, distance, normal towards the point,
    restitution, friction)``, or None in an empty scene.

    Examples
    --------
    >>> from adapt.imagination.scene import Wall
    >>> s = SceneSpec(walls=(Wall("east", (1, -1), (1, 1), restitution=0.9),))
    >>> name, d, n, e, mu = nearest_surface(s, (0.8, 0.2))
    >>> name, round(d, 3), [round(v, 3) for v in n], e
    ('east', 0.2, [-1.0, 0.0], 0.9)
    """
    best = None
    px, py = float(point[0]), float(point[1])
    segments: list[tuple[str, tuple[float, float], tuple[float, float], float, float]] = []
    for w in scene.walls:
        segments.append((w.name, w.start, w.end, w.restitution, w.friction))
    for ob in scene.obstacles:
        poly = ob.polygon
        for i in range(len(poly)):
            segments.append((ob.name, poly[i], poly[(i + 1) % len(poly)], ob.restitution,
                             ob.friction))
    for name, a, b, e, mu in segments:
        ax, ay = a
        dx, dy = b[0] - ax, b[1] - ay
        length2 = dx * dx + dy * dy
        t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2))
        cx, cy = ax + t * dx, ay + t * dy
        d = math.hypot(px - cx, py - cy)
        if best is None or d < best[1]:
            n = ((px - cx) / d, (py - cy) / d) if d > 1e-9 else (-dy / math.sqrt(length2),
                                                                    dx / math.sqrt(length2))
            best = (name, d, n, e, mu)
    return best


class ParameterEstimator:
    """Estimates of ball parameters from sightings (see the module docstring).

    Parameters
    ----------
    ranges : mapping of str to (low, high)
        The prior range of each parameter; a parameter with no range is
        fixed at its nominal value (it is still measured, for the record).
    nominal : mapping of str to float
        The model's values.
    scene : SceneSpec, optional
        The static surfaces (bounces are only measured with a scene).
    gravity : float
        m/s².
    radius : float
        The ball's radius (its centre is this far from a surface it touches).
    """

    def __init__(self, ranges: Mapping[str, tuple[float, float]], *,
                 nominal: Mapping[str, float] | None = None, scene: SceneSpec | None = None,
                 gravity: float = 9.81, radius: float = 0.1) -> None:
        self.scene = scene
        self.gravity = gravity
        self.radius = radius
        self._prior: dict[str, tuple[float, float, float, float]] = {}
        self._post: dict[str, tuple[float, float, int]] = {}
        nominal = dict(nominal or {})
        for name in set(ranges) | set(nominal):
            lo, hi = ranges.get(name, (nominal.get(name, 0.0), nominal.get(name, 0.0)))
            mean = nominal.get(name, (lo + hi) / 2.0)
            std = (hi - lo) / math.sqrt(12.0)
            self._prior[name] = (lo, hi, mean, std)
            self._post[name] = (mean, std, 0)
        self.bounces: list[Bounce] = []
        #: ``(time, position, velocity)`` of the line fitted after the last bounce.
        self.last_after: tuple[float, np.ndarray, np.ndarray] | None = None
        self._track: deque[tuple[float, float, float]] = deque(maxlen=120)
        self._residuals: deque[float] = deque(maxlen=60)
        self._quiet_until = -math.inf
        self._candidate: tuple[float, list[tuple[float, float, float]],
                               list[tuple[float, float, float]]] | None = None
        self._roll_from = -math.inf
        #: The rolling resistance's estimate before the current stretch was measured.
        self._roll_base: tuple[float, float, int] | None = None
        self._roll_next = -math.inf

    # -- estimates --------------------------------------------------------------------

    def estimate(self, name: str) -> Estimate:
        """The current estimate of ``name``."""
        mean, std, n = self._post[name]
        lo, hi, _, _ = self._prior[name]
        return Estimate(name, mean, std, n, surprise(mean, lo, hi))

    def estimates(self) -> dict[str, Estimate]:
        """Every estimate, by name."""
        return {name: self.estimate(name) for name in sorted(self._post)}

    def measure(self, name: str, value: float, std: float) -> None:
        """Blend one measurement of ``name`` (value, standard deviation) into its estimate."""
        if name not in self._post or not (math.isfinite(value) and std > 0):
            return
        self._post[name] = _blend(self._post[name], value, std)

    # -- sightings ---------------------------------------------------------------------------

    @property
    def noise(self) -> float:
        """The sightings' noise, metres: the median residual of recent straight
        stretches (a bounce-free half window), at least 2 mm; 5 mm before any."""
        if not self._residuals:
            return 0.005
        return max(float(np.median(self._residuals)), 0.002)

    def observe(self, time: float, position: Sequence[float], *, noise: float | None = None
                ) -> Bounce | None:
        """Take one sighting; returns a :class:`Bounce` when one has just been measured.

        A bounce is a kink in the path: the last ``2 * SIDE`` sightings do not lie on
        one straight line (their residual is many times the noise) while each half
        nearly does.  It is measured at the split where the halves are straightest
        (the kink in the window's middle), so about :data:`SIDE` frames after it
        happened.
        """
        self._track.append((float(time), float(position[0]), float(position[1])))
        out = None
        window = list(self._track)[-2 * SIDE:]
        candidate = None
        if noise is None:
            noise = self.noise
        if len(window) == 2 * SIDE and window[0][0] > self._quiet_until:
            whole = self._fit(window, window[SIDE][0])
            first = self._fit(window[:SIDE], window[SIDE][0])
            second = self._fit(window[SIDE:], window[SIDE][0])
            if whole and whole[2] < max(2.5 * noise, 0.003):
                self._residuals.append(whole[2])
            if whole and first and second and whole[2] > max(4.0 * noise, 0.004):
                score = max(first[2], second[2]) / whole[2]
                if score < 0.5:
                    candidate = (score, window[:SIDE], window[SIDE:])
        best = self._candidate
        if candidate is not None and (best is None or candidate[0] <= best[0]):
            self._candidate = candidate          # the kink moves towards the window's middle
        elif best is not None:
            # the split got worse (or the kink left the window): the best one was the bounce
            self._candidate = None
            out = self._bounce(best[1], best[2], noise)
            self._quiet_until = best[2][-1][0]
        self._roll(noise)
        return out

    def _fit(self, pts: list[tuple[float, float, float]], t0: float
             ) -> tuple[np.ndarray, np.ndarray, float] | None:
        """Straight line through sightings: position at ``t0``, velocity, residual RMS."""
        if len(pts) < 3:
            return None
        a = np.array(pts)
        t = a[:, 0] - t0
        m = np.c_[np.ones_like(t), t]
        sol, *_ = np.linalg.lstsq(m, a[:, 1:3], rcond=None)
        resid = a[:, 1:3] - m @ sol
        return sol[0], sol[1], float(np.sqrt((resid**2).sum(axis=1).mean()))

    def _bounce(self, before: list[tuple[float, float, float]],
                after: list[tuple[float, float, float]], noise: float) -> Bounce | None:
        if self.scene is None:
            return None
        t_jump = after[0][0]
        fb = self._fit(before, t_jump)
        fa = self._fit(after, t_jump)
        if fb is None or fa is None:
            return None
        pb, vb, _ = fb
        pa, va, _ = fa
        if np.linalg.norm(vb) < MIN_SPEED:
            return None
        # where the two lines come closest: the contact, roughly
        dv = vb - va
        tc = float(np.dot(pa - pb, dv) / np.dot(dv, dv)) if np.dot(dv, dv) > 1e-12 else 0.0
        contact = pb + vb * tc
        found = nearest_surface(self.scene, contact)  # type: ignore[arg-type]
        if found is None or found[1] > 3.0 * self.radius + 0.05:
            return None
        name, _, n, e_surf, mu_surf = found
        nv = np.array(n)
        vn_in, vn_out = float(vb @ nv), float(va @ nv)
        if vn_in >= -MIN_SPEED / 2 or vn_out <= 0:
            return None
        e_pair = -vn_out / vn_in
        if not MIN_PAIR_RESTITUTION <= e_pair <= MAX_PAIR_RESTITUTION:
            return None  # a corner, or two bounces in one window: the normal is not the surface's
        span = max(after[-1][0] - after[0][0], 1e-3)
        sv = noise * math.sqrt(12.0 / len(after)) / span  # velocity noise of a line fit
        e_std = math.hypot(sv / abs(vn_in), sv * e_pair / abs(vn_in)) + 0.01
        e_ball = e_pair / max(e_surf, 1e-6)
        self.measure("restitution", e_ball, e_std / max(e_surf, 1e-6))
        tangent = np.array([-nv[1], nv[0]])
        vt_in, vt_out = float(vb @ tangent), float(va @ tangent)
        mu_ball = None
        if abs(vt_in) > MIN_SPEED and abs(vt_out) < abs(vt_in):
            mu_pair = (abs(vt_in) - abs(vt_out)) / ((1.0 + e_pair) * abs(vn_in))
            if mu_pair <= 2.0:
                mu_ball = mu_pair / max(mu_surf, 1e-6)
                self.measure("friction", mu_ball, (2 * sv / ((1.0 + e_pair) * abs(vn_in)) + 0.05)
                             / max(mu_surf, 1e-6))
        bounce = Bounce(t_jump, name, (float(contact[0]), float(contact[1])),
                        (float(n[0]), float(n[1])), float(np.linalg.norm(vb)), e_ball, mu_ball)
        self.bounces.append(bounce)
        if len(self.bounces) > 64:
            del self.bounces[0]
        # rolling is measured afresh after the bounce
        self._roll_from = t_jump + 0.05
        self._roll_base = None
        self.last_after = (t_jump, pa, va)
        return bounce

    def _roll(self, noise: float) -> None:
        """The current stretch of free rolling (since the last bounce, the latest
        :data:`ROLL_SPAN` of it) measured again every :data:`MIN_ROLL` / 2 seconds; its
        measurement replaces the stretch's previous one."""
        if "rolling_resistance" not in self._post or self._candidate is not None:
            return
        now = self._track[-1][0]
        pts = [p for p in self._track if p[0] > max(self._roll_from, now - ROLL_SPAN)]
        if len(pts) < 8 or pts[-1][0] - pts[0][0] < MIN_ROLL or now < self._roll_next:
            return
        self._roll_next = now + MIN_ROLL / 2.0
        a = np.array(pts)
        t = a[:, 0] - a[-1, 0]
        m = np.c_[np.ones_like(t), t, 0.5 * t * t]
        sol, *_ = np.linalg.lstsq(m, a[:, 1:3], rcond=None)
        resid = a[:, 1:3] - m @ sol
        if float(np.sqrt((resid**2).sum(axis=1).mean())) > max(3.0 * noise, 0.004):
            return  # not one smooth stretch: a bounce inside it
        v, acc = sol[1], sol[2]
        speed = float(np.linalg.norm(v))
        if speed < MIN_SPEED:
            return
        decel = -float(acc @ v) / speed
        span = float(t[-1] - t[0]) or 1e-3
        acc_std = noise * math.sqrt(720.0 / len(pts)) / span**2  # a quadratic term's noise
        if self._roll_base is None:
            self._roll_base = self._post["rolling_resistance"]
        self._post["rolling_resistance"] = _blend(self._roll_base, max(decel, 0.0) / self.gravity,
                                                  acc_std / self.gravity + 0.003)


def _blend(prior: tuple[float, float, int], value: float, std: float
           ) -> tuple[float, float, int]:
    """A Gaussian ``(mean, std, count)`` updated with one measurement (a fixed parameter,
    ``std`` 0, keeps its value and counts the evidence)."""
    mean, pstd, n = prior
    if pstd <= 0:
        return (mean, pstd, n + 1)
    w0, w1 = 1.0 / pstd**2, 1.0 / std**2
    return ((mean * w0 + value * w1) / (w0 + w1), math.sqrt(1.0 / (w0 + w1)), n + 1)
