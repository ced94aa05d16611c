"""Identification: the ball's state and physical parameters, fitted by imagined rollouts.

The imagination can say where a ball started at ``t0`` with a velocity (and
a spin) and given parameters would have been at each later time.  The
:class:`Identifier` turns that around: it keeps the sightings of the last
``window`` seconds and looks for the start -- position, velocity, slip -- and
the parameters (restitution, friction, rolling resistance, the floor's
friction) whose rollout passes closest to them, bounces included.  The
state *now* is the end of that rollout, and the parameters are what the
imagined ball takes on: the paper's "adapt the simulation parameters of the
object so that it more closely follows observed behavior", by the model
itself rather than by straight lines fitted on each side of a kink.

Each frame does one Levenberg-Marquardt step of that moving-horizon fit,
starting from the last one's answer (the window moves on by a frame, so the
start is the last fitted path's state at the window's new first sighting):

1. one rollout of the window, in one world, of ``1 + n`` copies of the ball
   that pass through each other (``World(..., ball_collisions=False)``): the
   current guess and one copy per unknown nudged by a small step, which
   gives the residuals and their Jacobian by forward differences;
2. a second rollout of two candidate steps (two damping factors), and the
   best of them and the current guess is kept.

The residuals are the sightings' distances from the path, in units of their
noise, plus a Gaussian prior on each unknown.  A parameter's prior is what
was known before the window: the scenario's range at first, and every
``window`` seconds the fit's own answer (with its uncertainty from the
fit's curvature), so that what a bounce taught is kept after it has left
the window and no sighting counts twice.  The start state's prior is where
the last fitted path had the ball, loose enough for the sightings to move
it.  An unknown that nothing in the window informs is not nudged (it keeps
its prior; a copy fewer to roll out): restitution and friction without a
contact on the path, the floor's friction while the ball rolls without
slipping, and the start's slip once the path carries it (the model makes
slip at the contacts; it is fitted only for a ball first seen, which may
have been thrown spinning).

Examples
--------
A ball rolling at 1 m/s in x towards a wall at x = 1 with restitution 0.6;
the fit starts from restitution 0.9 and learns it from the sightings:

>>> from adapt.imagination import Ball, SceneSpec, Wall, World
>>> scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
>>> truth = World(SceneSpec(walls=scene.walls, balls=(Ball("b", radius=0.1,
...               velocity=(1.0, 0.0), restitution=0.6),)))
>>> ident = Identifier(scene, Ball("b", radius=0.1), {"restitution": (0.9, 0.2)},
...                    window=1.5, noise=0.002)
>>> for k in range(46):
...     truth.run_until(k / 30)
...     fit = ident.observe(k / 30, truth.position("b"))
>>> round(fit.parameters["restitution"], 2), [round(v, 2) for v in fit.velocity]
(0.6, [-0.6, 0.0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from adapt.errors import ImaginationError
from adapt.imagination.scene import Ball, SceneSpec, Vec2
from adapt.imagination.world import BodyState, World, WorldState

__all__ = ["Fit", "Identifier", "PARAMETERS", "STEPS"]

FloatArray = NDArray[np.float64]

#: The parameters the identifier can fit, and the bounds each is kept in.
PARAMETERS: dict[str, tuple[float, float]] = {
    "restitution": (0.0, 1.0),
    "friction": (0.0, 3.0),
    "rolling_resistance": (0.0, 1.0),
    "floor_friction": (0.0, 3.0),
    "drag": (0.0, 3.0),
}
#: Nudge of each unknown for the forward differences (metres, m/s, or the parameter's unit).
STEPS: dict[str, float] = {
    "x": 0.002, "y": 0.002, "vx": 0.02, "vy": 0.02, "ux": 0.05, "uy": 0.05,
    "restitution": 0.03, "friction": 0.05, "rolling_resistance": 0.003, "floor_friction": 0.05,
    "drag": 0.02,
}
#: How far each parameter may drift, as a standard deviation per ``window`` (it is added to
#: the prior's when the window's answer becomes the prior): the model is not reality, and
#: what fits it best changes a little as the ball does (an effective rolling resistance with
#: the speed, say); a prior that only narrowed would hold a stale value against the sightings.
DRIFT: dict[str, float] = {
    "restitution": 0.02, "friction": 0.05, "rolling_resistance": 0.004, "floor_friction": 0.05,
    "drag": 0.01,
}
#: Parameters that a window without a contact does not inform.
CONTACT_PARAMETERS = ("restitution", "friction")
#: A path whose slip stays below this (m/s) does not inform the floor's friction.
MIN_SLIP = 0.05
#: A ball slower than this (m/s) all through the window informs no parameter (at rest).
MIN_SPEED = 0.05
#: The start state's prior, relative to where the last fitted path had the ball:
#: standard deviations of position (m), velocity and slip (m/s).
START_STD = {"position": 0.01, "velocity": 0.1, "slip": 0.3}
#: Damping factors of the candidate steps, relative to the current one.
DAMPING = (0.3, 3.0)
#: The next window starts within this many seconds of this one's start (the frames
#: between two fits, a few missed), so the fitted path's state is kept only there.
START_SPAN = 0.3
#: Most Levenberg-Marquardt steps in one fit: more than one only while the path fits the
#: sightings worse than :data:`REFIT_CHI2` times their noise's chi-square.
MAX_ITERATIONS = 3
REFIT_CHI2 = 4.0
#: A window's answer on rolling becomes the prior of what follows only when its path fits
#: the sightings within this chi-square per degree of freedom.
RETIRE_CHI2 = 2.0
#: Least sightings before a fit.
MIN_SIGHTINGS = 4
#: A sighting further than this from the path (in noise sigmas) pulls on it linearly, not
#: quadratically (Huber's loss): a wild sighting moves the fit little, while many sightings
#: off the path (an unmodelled bounce) still pull it over.
HUBER = 3.0
#: The gate: a sighting further than this from the fitted path (noise sigmas) is an outlier;
#: up to :data:`MAX_OUTLIERS` of them are left out of the fit's chi-square (more are the
#: path not fitting, and count).
OUTLIER = 8.0
MAX_OUTLIERS = 1


@dataclass(frozen=True, slots=True)
class Fit:
    """The identifier's answer at the time of its latest sighting.

    ``parameters`` and ``std`` are the fitted parameters' means and standard
    deviations; ``residual`` the RMS distance of the window's sightings from
    the fitted path (metres, outliers left out); ``contact`` whether that path
    meets a surface; ``chi2`` the sightings' chi-square per degree of freedom, at
    least 1 (about 1: the path passes as close as the noise allows; much more: it
    does not fit them yet, and its state is not to be trusted); ``outliers`` the
    sightings the gate left out of it (:data:`OUTLIER`).
    """

    time: float
    position: Vec2
    velocity: Vec2
    slip: Vec2
    parameters: Mapping[str, float]
    std: Mapping[str, float]
    residual: float
    sightings: int
    contact: bool
    chi2: float
    outliers: int = 0


#: A state on a path: position, velocity, slip.
State = tuple[Vec2, Vec2, Vec2]


@dataclass(slots=True)
class _Best:
    """The best guess so far in one fit: its unknowns, its path's positions at the
    sightings and kept states, its first contact, its sightings' chi-square and its cost
    (the chi-square with the priors')."""

    x: FloatArray
    positions: FloatArray | None
    states: dict[int, State]
    contact: float
    chi2: float
    cost: float


class Identifier:
    """The moving-horizon fit of one ball (see the module docstring).

    Parameters
    ----------
    scene : SceneSpec
        The static scene (walls, obstacles); its balls and robot are ignored.
    ball : Ball
        The ball's model: radius, mass, and the values of the parameters not fitted.
        With ``floor_friction`` set, the model has spin and the fit a slip.
    priors : mapping of str to (mean, std)
        The parameters to fit (keys of :data:`PARAMETERS`) and what is known of them.
    window : float
        Seconds of sightings fitted.
    every : int
        Frames with a sighting between two fits (the others only keep the sighting).
    noise : float
        The sightings' noise, metres (standard deviation); the attribute ``noise`` may
        change between sightings (the object schema gives it their measured scatter) and
        counts from the next fit on.
    dt : float, optional
        The rollouts' physics step (default the scene's).
    """

    def __init__(self, scene: SceneSpec, ball: Ball, priors: Mapping[str, tuple[float, float]],
                 *, window: float = 0.9, every: int = 1, noise: float = 0.005,
                 dt: float | None = None) -> None:
        for key, prior in priors.items():
            if key not in PARAMETERS:
                raise ImaginationError(
                    f"cannot fit {key!r}; expected one of {', '.join(PARAMETERS)}")
            mean, std = prior
            if not (math.isfinite(mean) and math.isfinite(std) and std >= 0):
                raise ImaginationError(f"{key}: expected a finite mean and a standard "
                                       f"deviation >= 0, got {prior!r}")
        for name, value, low in (("window", window, 0.0), ("noise", noise, 0.0)):
            if not (math.isfinite(value) and value > low):
                raise ImaginationError(f"{name}: expected a positive number, got {value!r}")
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise ImaginationError(f"every: expected a whole number >= 1, got {every!r}")
        if ball.floor_friction is None and "floor_friction" in priors:
            raise ImaginationError("floor_friction: the ball has no spin to fit it for "
                                   "(give its model a floor_friction)")
        self.scene = replace(scene, balls=(), robot=None)
        self.ball = ball
        self.window = float(window)
        self.every = every
        self._count = 0
        self.noise = float(noise)
        self.dt = self.scene.dt if dt is None else float(dt)
        self.spin = ball.floor_friction is not None
        self.names = tuple(priors)
        self.prior = np.array([float(priors[k][0]) for k in self.names])
        self.prior_std = np.array([max(float(priors[k][1]), 1e-6) for k in self.names])
        self.theta = self.prior.copy()
        self.theta_std = self.prior_std.copy()
        #: What was known before any sighting: no fit is less certain than that.
        self._known_std = self.prior_std.copy()
        #: Fits that informed each parameter (it was fitted, not kept), by name.
        self.counts = {k: 0 for k in self.names}
        self._sightings: list[tuple[float, float, float]] = []
        self._path: dict[float, State] = {}
        self._contact = math.inf   # the first contact on the last fitted path
        self._slipping = False
        self._moving = True
        self._since = math.inf     # when the current path started (a first sighting, a gap)
        self._damping = 1e-2
        self._retired = -math.inf
        self._worlds: dict[int, World] = {}
        self._set: dict[tuple[int, int], tuple[float, ...]] = {}
        self.fit: Fit | None = None
        #: Seconds of rollouts simulated (all copies), for the record.
        self.simulated_s = 0.0

    # -- sightings -------------------------------------------------------------------------

    def observe(self, time: float, position: Sequence[float] | None) -> Fit | None:
        """Take one frame's sighting (None: not seen) and fit; returns the fit (None before
        :data:`MIN_SIGHTINGS` sightings)."""
        if position is None:
            return self.fit
        now = float(time)
        self._sightings.append((now, float(position[0]), float(position[1])))
        if self._retired == -math.inf:
            self._retired = now
        first = now - self.window - 1e-9
        self._sightings = [s for s in self._sightings if s[0] >= first]
        if len(self._sightings) < MIN_SIGHTINGS:
            return self.fit
        self._count += 1
        if self.fit is None or (self._count - 1) % self.every == 0:
            self.fit = self._step()
        return self.fit

    def _start(self) -> tuple[State, bool]:
        """The window's start state: the last path's state then (and False), or a line through
        the first sightings (and True: a new path)."""
        t0 = self._sightings[0][0]
        state = self._path.get(round(t0, 6))
        if state is not None:
            return state, False
        a = np.array(self._sightings[:6])
        tt = a[:, 0] - t0
        m = np.c_[np.ones_like(tt), tt]
        sol, *_ = np.linalg.lstsq(m, a[:, 1:3], rcond=None)
        return (((float(sol[0, 0]), float(sol[0, 1])), (float(sol[1, 0]), float(sol[1, 1])),
                 (0.0, 0.0)), True)

    # -- rollouts ----------------------------------------------------------------------------

    def _world(self, copies: int) -> World:
        world = self._worlds.get(copies)
        if world is None:
            balls = tuple(replace(self.ball, name=f"copy{k}") for k in range(copies))
            world = World(replace(self.scene, balls=balls), dt=self.dt, ball_collisions=False)
            self._worlds[copies] = world
        return world

    def _run(self, starts: Sequence[FloatArray], params: Sequence[FloatArray], full: int = 0
             ) -> tuple[FloatArray, list[dict[int, State]], list[float]]:
        """Roll copies through the window, each from its start ``(x, y, vx, vy[, ux, uy])``
        with its parameters: positions ``(K, N, 2)`` at the sighting times, the states of
        the first ``full`` copies where the next windows may start (the sightings of the
        window's first :data:`START_SPAN` seconds) and at the last sighting, by index, and
        the time of each copy's first contact (``inf``: none)."""
        n = len(starts)
        world = self._world(n)
        window = self._sightings
        t0 = window[0][0]
        bodies = []
        for k in range(n):
            name = f"copy{k}"
            values = tuple(float(np.clip(v, *PARAMETERS[key]))
                           for key, v in zip(self.names, params[k]))
            if self._set.get((n, k)) != values:
                world.set_ball_parameters(name, **dict(zip(self.names, values)))  # type: ignore[arg-type]
                self._set[(n, k)] = values
            x = starts[k]
            slip = (float(x[4]), float(x[5])) if self.spin else (0.0, 0.0)
            bodies.append(BodyState(name, (float(x[0]), float(x[1])), (float(x[2]), float(x[3])),
                                    slip=slip))
        world.set_state(WorldState(t0, 0, tuple(bodies)))
        world.contacts.clear()
        handles = [world.body(f"copy{k}") for k in range(n)]
        out = np.empty((n, len(window), 2))
        states: list[dict[int, State]] = [{} for _ in range(full)]
        last = len(window) - 1
        done = 0
        for i, (t, _, _) in enumerate(window):
            k = int(round((t - t0) / self.dt))
            if k > done:
                world.step(k - done)
                done = k
            keep = full if (t - t0 <= START_SPAN or i == last) else 0
            for j, b in enumerate(handles):
                p = b.position
                out[j, i] = (p[0], p[1])
                if j < keep:
                    v = b.velocity
                    states[j][i] = ((float(p[0]), float(p[1])), (float(v[0]), float(v[1])),
                                    world.slip(f"copy{j}"))
        self.simulated_s += n * done * self.dt
        firsts = [math.inf] * n
        for c in world.contacts:
            k = int(c.ball[4:])
            firsts[k] = min(firsts[k], c.time)
        return out, states, firsts

    # -- one step of the fit -------------------------------------------------------------------

    def _step(self) -> Fit:
        window = self._sightings
        obs = np.array([(s[1], s[2]) for s in window])
        state, new = self._start()
        if new:
            self._since = window[0][0]
        (px, py), (vx, vy), (ux, uy) = state
        keys: tuple[str, ...] = ("x", "y", "vx", "vy") + (("ux", "uy") if self.spin else ())
        ns = len(keys)
        keys += self.names
        x = np.array([px, py, vx, vy] + ([ux, uy] if self.spin else []) + list(self.theta))
        prior_x = x.copy()
        prior_x[ns:] = self.prior
        sstd = [START_STD["position"]] * 2 + [START_STD["velocity"]] * 2
        sstd += [START_STD["slip"]] * 2 if self.spin else []
        prior_std = np.concatenate([sstd, self.prior_std])
        if self._contact < window[0][0]:
            # the contact that taught what a contact teaches has left the window: that is
            # now what is known before it (and it counts once)
            self._retire(CONTACT_PARAMETERS + ("floor_friction",))
            prior_x[ns:] = self.prior
            prior_std[ns:] = self.prior_std
        contact = self._contact < math.inf
        # what the window can inform (see the module docstring)
        fresh = window[0][0] - self._since < self.window
        free = []
        for i, k in enumerate(keys):
            if i >= ns and not (self._moving or fresh):
                continue
            if k in ("ux", "uy") and not fresh:
                continue
            if k in CONTACT_PARAMETERS and not contact:
                continue
            if k == "floor_friction" and not (self._slipping or fresh or contact):
                continue
            free.append(i)

        def residuals(pos: FloatArray, v: FloatArray) -> FloatArray:
            return np.concatenate([_huber((pos - obs) / self.noise).ravel(),
                                   (v - prior_x) / prior_std])

        best = _Best(x, None, {}, math.inf, math.inf, math.inf)
        jtj = np.eye(len(free))
        fitted = list(free)  # the parameters jtj is for (free may grow after the last step)
        for _ in range(MAX_ITERATIONS):
            best, jtj = self._iterate(best, free, keys, ns, residuals, prior_std)
            fitted = list(free)
            if best.contact < math.inf and not contact:
                # the path meets a surface it did not before: what a contact teaches is
                # free from now on (this fit too)
                contact = True
                free = sorted(set(free) | {i for i, k in enumerate(keys)
                                           if k in CONTACT_PARAMETERS + ("floor_friction",)})
                continue
            # sightings far off the path (a new contact, a parameter far from its prior):
            # another step now rather than a frame of poor predictions
            if best.chi2 / max(obs.size - len(free), 1) <= REFIT_CHI2:
                break
        assert best.positions is not None
        self._path = {round(window[i][0], 6): st for i, st in best.states.items()}
        self._contact = best.contact
        self._slipping = any(math.hypot(*st[2]) > MIN_SLIP for st in best.states.values())
        self._moving = any(math.hypot(*st[1]) > MIN_SPEED for st in best.states.values())
        # the fit's uncertainty, widened by how much worse than the noise the path fits (a
        # fit not yet converged, or a model that does not fit, is not to be trusted more)
        sigmas = np.hypot(*(best.positions - obs).T) / self.noise
        out = sigmas > OUTLIER
        if out.sum() > MAX_OUTLIERS:
            out[:] = False
        inliers = ~out
        chi2 = float(np.sum(sigmas[inliers] ** 2)) / max(2 * int(inliers.sum()) - len(free), 1)
        scale = math.sqrt(max(1.0, chi2))
        std = np.concatenate([prior_std[:ns], self.theta_std])
        try:
            std[fitted] = scale * np.sqrt(np.clip(np.diag(np.linalg.inv(jtj)), 0.0, None))
        except np.linalg.LinAlgError:
            pass
        now = window[-1][0]
        for i in fitted:
            if i >= ns:
                self.counts[keys[i]] += 1
        self.theta = best.x[ns:].copy()
        self.theta_std = np.minimum(std[ns:], self._known_std)
        if now - self._retired >= self.window:
            # what the window taught of rolling becomes the prior of what follows (no
            # sighting counts twice) -- if the path fits it: a window the model does not
            # fit (a hop, a slide it cannot follow) teaches nothing to keep
            if chi2 <= RETIRE_CHI2:
                self._retire(tuple(k for k in self.names if k not in CONTACT_PARAMETERS
                                   and k != "floor_friction"))
            self._retired = now
        resid = (best.positions - obs)[inliers]
        p, v, u = best.states[len(window) - 1]
        return Fit(now, p, v, u, dict(zip(self.names, (float(t) for t in self.theta))),
                   dict(zip(self.names, (float(s) for s in self.theta_std))),
                   float(np.sqrt((resid ** 2).sum(axis=1).mean())), len(window),
                   best.contact < math.inf, scale * scale, int(out.sum()))

    def _iterate(self, start: "_Best", free: list[int], keys: tuple[str, ...], ns: int,
                 residuals: Callable[[FloatArray, FloatArray], FloatArray],
                 prior_std: FloatArray) -> tuple["_Best", FloatArray]:
        """One Levenberg-Marquardt step from ``start.x``: the Jacobian's rollout, then the
        candidates'; the best of them and the start (and ``J^T J`` over ``free``)."""
        x = start.x
        xs = [x]
        for i in free:
            xn = x.copy()
            xn[i] += STEPS[keys[i]]
            xs.append(xn)
        pos, states, firsts = self._run([v[:ns] for v in xs], [v[ns:] for v in xs], full=1)
        r0 = residuals(pos[0], x)
        m = len(r0) - len(keys)
        jf = np.zeros((len(r0), len(free)))
        for col, i in enumerate(free):
            jf[:m, col] = (pos[col + 1] - pos[0]).ravel() / (self.noise * STEPS[keys[i]])
            jf[m + i, col] = 1.0 / prior_std[i]
        # the unknowns not nudged stay as they are (their prior would pull them back)
        jtj = jf.T @ jf
        g = jf.T @ r0
        best = _Best(x, pos[0], states[0], firsts[0], float(np.sum(r0[:m] ** 2)),
                     float(r0 @ r0))
        cands = []
        for f in DAMPING:
            a = jtj + self._damping * f * np.diag(np.diag(jtj))
            try:
                xc = x.copy()
                xc[free] -= np.linalg.solve(a, g)
            except np.linalg.LinAlgError:
                continue
            for i, key in enumerate(self.names):
                xc[ns + i] = min(max(xc[ns + i], PARAMETERS[key][0]), PARAMETERS[key][1])
            cands.append(xc)
        if cands:
            pos_c, states_c, firsts_c = self._run([v[:ns] for v in cands],
                                                  [v[ns:] for v in cands], full=len(cands))
            rs = [residuals(pos_c[c], cands[c]) for c in range(len(cands))]
            costs = [float(r @ r) for r in rs]
            c = int(np.argmin(costs))
            if costs[c] < best.cost:
                best = _Best(cands[c], pos_c[c], states_c[c], firsts_c[c],
                             float(np.sum(rs[c][:m] ** 2)), costs[c])
                self._damping = max(self._damping * DAMPING[c] / 3.0, 1e-4)
            else:
                self._damping = min(self._damping * 4.0, 1e4)
        return best, jtj

    def _retire(self, names: Sequence[str]) -> None:
        """The current estimates of ``names`` become their priors (widened by their drift)."""
        for k in names:
            if k in self.names:
                i = self.names.index(k)
                self.prior[i] = self.theta[i]
                self.prior_std[i] = min(math.hypot(float(self.theta_std[i]), DRIFT[k]),
                                        float(self._known_std[i]))
                self.theta_std[i] = self.prior_std[i]


def _huber(r: FloatArray) -> FloatArray:
    """Residuals ``(N, 2)`` in noise sigmas, rescaled so that their squares sum to Huber's
    loss (a sighting's squared distance up to :data:`HUBER`, linear beyond).

    Examples
    --------
    >>> _huber(np.array([[0.0, 2.0], [0.0, 5.0]])).tolist()
    [[0.0, 2.0], [0.0, 4.58257569495584]]
    """
    d = np.hypot(r[:, 0], r[:, 1])
    far = d > HUBER
    scale = np.ones_like(d)
    scale[far] = np.sqrt(2.0 * HUBER * d[far] - HUBER * HUBER) / d[far]
    return r * scale[:, None]

