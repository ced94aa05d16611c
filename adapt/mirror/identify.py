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
from typing import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

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
}
#: Nudge of each unknown for the forward differences (metres, m/s, or the parameter's unit).
STEPS: dict[str, float] = {
    "x": 0.002, "y": 0.002, "vx": 0.02, "vy": 0.02, "ux": 0.05, "uy": 0.05,
    "restitution": 0.03, "friction": 0.05, "rolling_resistance": 0.003, "floor_friction": 0.05,
}
#: Parameters that a window without a contact does not inform.
CONTACT_PARAMETERS = ("restitution", "friction")
#: A path whose slip stays below this (m/s) does not inform the floor's friction.
MIN_SLIP = 0.05
#: The start state's prior, relative to where the last fitted path had the ball:
#: standard deviations of position (m), velocity and slip (m/s).
START_STD = {"position": 0.01, "velocity": 0.1, "slip": 0.3}
#: Damping factors of the candidate steps, relative to the current one.
DAMPING = (0.3, 3.0)
#: Least sightings before a fit.
MIN_SIGHTINGS = 4


@dataclass(frozen=True, slots=True)
class Fit:
    """The identifier's answer at the time of its latest sighting.

    ``parameters`` and ``std`` are the fitted parameters' means and standard
    deviations; ``residual`` the RMS distance of the window's sightings from
    the fitted path (metres); ``contacts`` the contacts on that path.
    """

    time: float
    position: Vec2
    velocity: Vec2
    slip: Vec2
    parameters: Mapping[str, float]
    std: Mapping[str, float]
    residual: float
    sightings: int
    contacts: int


#: A state on a path: position, velocity, slip.
State = tuple[Vec2, Vec2, Vec2]


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
    noise : float
        The sightings' noise, metres (standard deviation).
    dt : float, optional
        The rollouts' physics step (default the scene's).
    """

    def __init__(self, scene: SceneSpec, ball: Ball, priors: Mapping[str, tuple[float, float]],
                 *, window: float = 1.2, noise: float = 0.005, dt: float | None = None) -> None:
        for key in priors:
            if key not in PARAMETERS:
                raise ValueError(f"cannot fit {key!r}; expected one of {', '.join(PARAMETERS)}")
        self.scene = replace(scene, balls=(), robot=None)
        self.ball = ball
        self.window = float(window)
        self.noise = float(noise)
        self.dt = self.scene.dt if dt is None else float(dt)
        self.spin = ball.floor_friction is not None
        self.names = tuple(priors)
        self.prior = np.array([float(priors[k][0]) for k in self.names])
        self.prior_std = np.array([max(float(priors[k][1]), 1e-6) for k in self.names])
        self.theta = self.prior.copy()
        self.theta_std = self.prior_std.copy()
        self._sightings: list[tuple[float, float, float]] = []
        self._path: dict[float, State] = {}
        self._contacts = 0
        self._slipping = False
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
             ) -> tuple[FloatArray, list[list[State]], list[int]]:
        """Roll copies through the window, each from its start ``(x, y, vx, vy[, ux, uy])``
        with its parameters: positions ``(K, N, 2)`` at the sighting times, the states of
        the first ``full`` copies there, and each copy's contact count."""
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
        states: list[list[State]] = [[] for _ in range(full)]
        done = 0
        for i, (t, _, _) in enumerate(window):
            k = int(round((t - t0) / self.dt))
            if k > done:
                world.step(k - done)
                done = k
            for j, b in enumerate(handles):
                p = b.position
                out[j, i] = (p[0], p[1])
                if j < full:
                    v = b.velocity
                    states[j].append(((float(p[0]), float(p[1])), (float(v[0]), float(v[1])),
                                      world.slip(f"copy{j}")))
        self.simulated_s += n * done * self.dt
        counts = [0] * n
        for c in world.contacts:
            counts[int(c.ball[4:])] += 1
        return out, states, counts

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
        # what the window can inform (see the module docstring)
        fresh = window[0][0] - self._since < self.window
        free = []
        for i, k in enumerate(keys):
            if k in ("ux", "uy") and not fresh:
                continue
            if k in CONTACT_PARAMETERS and not self._contacts:
                continue
            if k == "floor_friction" and not (self._slipping or fresh):
                continue
            free.append(i)

        def residuals(pos: FloatArray, v: FloatArray) -> FloatArray:
            return np.concatenate([((pos - obs) / self.noise).ravel(), (v - prior_x) / prior_std])

        xs = [x]
        for i in free:
            xn = x.copy()
            xn[i] += STEPS[keys[i]]
            xs.append(xn)
        pos, states, counts = self._run([v[:ns] for v in xs], [v[ns:] for v in xs], full=1)
        r0 = residuals(pos[0], x)
        m = len(r0) - len(keys)
        jac = np.zeros((len(r0), len(keys)))
        for col, i in enumerate(free):
            jac[:m, i] = (pos[col + 1] - pos[0]).ravel() / (self.noise * STEPS[keys[i]])
        jac[m:, :] = np.diag(1.0 / prior_std)
        jtj = jac.T @ jac
        g = jac.T @ r0
        cands = []
        for f in DAMPING:
            a = jtj + self._damping * f * np.diag(np.diag(jtj))
            try:
                xc = x - np.linalg.solve(a, g)
            except np.linalg.LinAlgError:
                continue
            for i, key in enumerate(self.names):
                xc[ns + i] = min(max(xc[ns + i], PARAMETERS[key][0]), PARAMETERS[key][1])
            cands.append(xc)
        best_x, best_states, best_count = x, states[0], counts[0]
        best_cost = float(r0 @ r0)
        if cands:
            pos_c, states_c, counts_c = self._run([v[:ns] for v in cands],
                                                  [v[ns:] for v in cands], full=len(cands))
            costs = [float(np.sum(residuals(pos_c[c], cands[c]) ** 2)) for c in range(len(cands))]
            c = int(np.argmin(costs))
            if costs[c] < best_cost:
                best_x, best_states, best_count, best_cost = cands[c], states_c[c], counts_c[c], \
                    costs[c]
                self._damping = max(self._damping * DAMPING[c] / 3.0, 1e-4)
                pos = pos_c[c:c + 1]
            else:
                self._damping = min(self._damping * 4.0, 1e4)
        self._path = {round(s[0], 6): st for s, st in zip(window, best_states)}
        self._contacts = best_count
        self._slipping = any(math.hypot(*st[2]) > MIN_SLIP for st in best_states)
        try:
            std = np.sqrt(np.clip(np.diag(np.linalg.inv(jtj)), 0.0, None))
        except np.linalg.LinAlgError:
            std = prior_std
        now = window[-1][0]
        self.theta = best_x[ns:].copy()
        self.theta_std = std[ns:]
        if now - self._retired >= self.window:
            # what the window taught becomes the prior of what follows (no sighting twice)
            self.prior = self.theta.copy()
            self.prior_std = np.maximum(std[ns:], 1e-4)
            self._retired = now
        resid = pos[0] - obs
        p, v, u = best_states[-1]
        return Fit(now, p, v, u, dict(zip(self.names, (float(t) for t in self.theta))),
                   dict(zip(self.names, (float(s) for s in self.theta_std))),
                   float(np.sqrt((resid ** 2).sum(axis=1).mean())), len(window), best_count)
