"""Prediction faster than real time, with a confidence.

From the synchronised imagination, :class:`Predictor` forks a world whose
ball starts where it is observed, moving as it is estimated to move, with
the current parameter estimates, and without the robot (the object's own
path is what an intercept is planned on; the robot is the rules' to move),
and rolls it out (the *nominal*
prediction: positions at the horizons, the contacts on the way -- time,
place, surface -- and a dense trajectory for planning an intercept).  An
ensemble of forks with parameters drawn from the estimates' uncertainty and
the velocity's gives the *spread* at each horizon.  A :class:`Residuals`
record keeps how far recent predictions at each horizon landed from where
the object was then seen.

The confidence at horizon ``h`` is ``1 - exp(-(r / sigma_h)^2)`` with
``sigma_h^2 = spread_h^2 + residual_h^2`` and ``r`` the catch radius: the
chance that the object comes within ``r`` of the prediction when its error is
a 2D Gaussian of RMS ``sigma_h`` (0.63 when that equals the catch radius; the
rules commit at 0.7, ``sigma_h`` at most 0.91 ``r``).  A confidence needs evidence:
until :data:`EVIDENCE` predictions at a horizon have been scored against
sightings, each missing one counts in ``residual_h`` as an error of one catch
radius -- or, once a shorter horizon ``h'`` has its evidence, as that
horizon's residual scaled by ``(h / h')^2`` (errors grow at least linearly
with the horizon, and faster across a bounce) -- so the confidence starts at
most 0.63, below the rules' 0.7, and rises only as predictions prove out.  Before a bounce has been seen,
an unknown restitution spreads the ensemble wide wherever a bounce falls
inside the horizon, so the confidence is low; it rises when the estimate
narrows.

Examples
--------
>>> from adapt.imagination import Ball, SceneSpec, Wall, World
>>> world = World(SceneSpec(walls=(Wall("north", (-2, 1), (2, 1)),),
...                         balls=(Ball("b", radius=0.1, restitution=0.8),)))
>>> p = Predictor((0.5, 1.0), members=8, catch_radius=0.3, seed=1)
>>> est = {"restitution": (0.8, 0.0)}
>>> pred = p.predict(world, "b", (0.0, 0.0), (0.0, 1.5), est)
>>> [h.bounce for h in pred.horizons], [c.surface for c in pred.contacts]
([False, True], ['north'])
>>> round(pred.horizons[1].position[1], 2), round(pred.horizons[0].confidence, 3)  # no evidence yet
(0.43, 0.632)
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass, replace
from typing import Mapping, Sequence

import numpy as np

from adapt.imagination import World
from adapt.imagination.predict import Trajectory, ensemble, rollout
from adapt.imagination.world import BodyState, Contact

__all__ = ["HorizonPrediction", "Prediction", "Predictor", "Residuals", "confidence",
           "REST_SPEED", "EVIDENCE"]

#: Scored predictions at a horizon before its residual is taken at its word (the missing
#: ones count as errors of one catch radius).
EVIDENCE = 3

#: The ball parameters a prediction takes from the estimates.
FITTED = ("restitution", "friction", "rolling_resistance", "floor_friction", "drag")

#: Below this speed (m/s) an object is at rest: its prediction needs no rollout.
REST_SPEED = 0.02
#: How far ahead the path of an object at rest reaches (seconds): far enough to drive to it.
REST_PLAN = 60.0


def confidence(sigma: float, catch_radius: float) -> float:
    """``1 - exp(-(r / sigma)^2)``: the chance that the object comes within the catch
    radius ``r`` of the prediction when its error is a 2D Gaussian of RMS ``sigma``.

    Examples
    --------
    >>> confidence(0.0, 0.3), round(confidence(0.3, 0.3), 3), round(confidence(0.6, 0.3), 3)
    (1.0, 0.632, 0.221)
    """
    if sigma <= 0.0:
        return 1.0
    return 1.0 - math.exp(-((catch_radius / sigma) ** 2))


@dataclass(frozen=True, slots=True)
class HorizonPrediction:
    """Where the object is predicted ``horizon`` seconds ahead."""

    horizon: float
    position: tuple[float, float]
    spread: float
    residual: float
    confidence: float
    bounce: bool

    def as_json(self) -> dict[str, object]:
        """The report's form."""
        return {"horizon": self.horizon,
                "position": [round(self.position[0], 4), round(self.position[1], 4)],
                "spread": round(self.spread, 4), "residual": round(self.residual, 4),
                "confidence": round(self.confidence, 4), "bounce": self.bounce}


@dataclass(frozen=True, slots=True, eq=False)
class Prediction:
    """One prediction, made at world time ``time``."""

    time: float
    body: str
    horizons: tuple[HorizonPrediction, ...]
    contacts: tuple[Contact, ...]
    trajectory: Trajectory
    parameters: Mapping[str, float]

    def at(self, horizon: float) -> HorizonPrediction | None:
        """The prediction for ``horizon`` (None when it is not one of them)."""
        for h in self.horizons:
            if abs(h.horizon - horizon) < 1e-9:
                return h
        return None

    def contacts_json(self) -> list[dict[str, object]]:
        """The predicted contacts, for the report."""
        return [{"t": round(c.time, 4), "position": [round(c.position[0], 4),
                                                      round(c.position[1], 4)],
                 "surface": c.surface, "speed": round(c.speed, 4)} for c in self.contacts]


class Residuals:
    """How far recent predictions at each horizon landed from the sightings.

    :meth:`expect` records a prediction for a future time; :meth:`observe`
    scores every recorded prediction whose time has come (within half a
    frame) against a sighting; :meth:`rms` is the RMS of the last ``keep``
    scores at a horizon (0 before any).  Predictions that foresaw a contact
    within their horizon are also kept apart: a bounce is its own evidence
    (rolling that came true says nothing of how the object bounces).
    """

    def __init__(self, horizons: Sequence[float], keep: int = 10,
                 evidence: int = EVIDENCE) -> None:
        self.evidence = evidence
        self._pending: dict[float, deque[tuple[float, float, float, bool]]] = {
            h: deque(maxlen=512) for h in horizons}
        self._errors: dict[float, deque[float]] = {h: deque(maxlen=max(keep, evidence))
                                                   for h in horizons}
        self._bounces: dict[float, deque[float]] = {h: deque(maxlen=max(keep, evidence))
                                                    for h in horizons}

    def expect(self, horizon: float, time: float, position: Sequence[float],
               bounce: bool = False) -> None:
        """A prediction that the object is at ``position`` at ``time`` (after a contact it
        foresaw, when ``bounce``)."""
        self._pending[horizon].append((time, float(position[0]), float(position[1]), bounce))

    def observe(self, time: float, position: Sequence[float], tolerance: float) -> None:
        """Score the predictions for about ``time`` against a sighting."""
        for h, queue in self._pending.items():
            while queue and queue[0][0] < time - tolerance:
                queue.popleft()
            while queue and abs(queue[0][0] - time) <= tolerance:
                _, x, y, bounce = queue.popleft()
                error = math.hypot(x - position[0], y - position[1])
                self._errors[h].append(error)
                if bounce:
                    self._bounces[h].append(error)

    def rms(self, horizon: float) -> float:
        """RMS error of the recent predictions at ``horizon`` (0 before any)."""
        e = self._errors.get(horizon)
        if not e:
            return 0.0
        return math.sqrt(sum(v * v for v in e) / len(e))

    def sigma(self, horizon: float, prior: float, bounce: bool = False) -> float:
        """The residual the confidence uses: the RMS of the recent scores with each of the
        ``evidence`` scores not yet made counted as an error of ``prior``, or of the
        longest shorter horizon's residual times ``(horizon / shorter)^2`` once that one
        has its evidence.  For a prediction across a contact (``bounce``), the scores are
        those of the predictions that foresaw one.

        Examples
        --------
        >>> r = Residuals((0.5, 1.0))
        >>> r.sigma(1.0, prior=0.3)
        0.3
        >>> r.expect(1.0, 2.0, (0.0, 0.0)); r.observe(2.0, (0.0, 0.0), 0.01)
        >>> round(r.sigma(1.0, prior=0.3), 3)
        0.245
        >>> for t in (1.0, 1.1, 1.2):
        ...     r.expect(0.5, t, (0.0, 0.01)); r.observe(t, (0.0, 0.0), 0.01)
        >>> round(r.sigma(1.0, prior=0.3), 3)  # the missing two count as 4 x 1 cm
        0.033
        """
        errors = self._bounces if bounce else self._errors
        e = errors.get(horizon) or ()
        missing = max(0, self.evidence - len(e))
        shorter = [h for h in errors if h < horizon and len(errors[h]) >= max(self.evidence, 1)]
        if missing and shorter:
            h = max(shorter)
            kept = errors[h]
            prior = math.sqrt(sum(v * v for v in kept) / len(kept)) * (horizon / h) ** 2
        n = len(e) + missing
        return math.sqrt((sum(v * v for v in e) + missing * prior * prior) / n) if n else 0.0

    def count(self, horizon: float) -> int:
        """How many predictions at ``horizon`` have been scored recently."""
        return len(self._errors.get(horizon, ()))


class Predictor:
    """Nominal rollout plus an ensemble (see the module docstring).

    Parameters
    ----------
    horizons : sequence of float
        Seconds ahead.
    members : int
        Ensemble size (0: no ensemble, the spread is 0).
    catch_radius : float
        ``r`` of the confidence, metres.
    plan : float
        How far ahead the dense trajectory for planning reaches (at least the
        largest horizon), seconds.
    seed : int or Generator
        The ensemble's random stream.
    evidence : int
        Scored predictions per horizon before its residual is taken at its word
        (:meth:`Residuals.sigma`).
    """

    def __init__(self, horizons: Sequence[float], *, members: int, catch_radius: float,
                 plan: float = 3.0, seed: int | np.random.Generator | None = None,
                 evidence: int = EVIDENCE) -> None:
        self.horizons = tuple(sorted(horizons))
        self.members = members
        self.catch_radius = catch_radius
        self.plan = max(plan, self.horizons[-1])
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self.residuals = Residuals(self.horizons, evidence=evidence)
        #: Seconds of imagination rolled out, and the wall-clock seconds it took.
        self.simulated_s = 0.0
        self.wall_s = 0.0

    def predict(self, world: World, body: str, position: Sequence[float],
                velocity: Sequence[float], estimates: Mapping[str, tuple[float, float]],
                *, velocity_std: float = 0.0, slip: Sequence[float] = (0.0, 0.0),
                since: float = 0.0) -> Prediction:
        """Predict ``body`` from ``position`` and ``velocity`` (and, for a ball with spin,
        ``slip``), which it had ``since`` seconds before the world's time.

        ``estimates`` maps ball parameters (``restitution``, ``friction``,
        ``rolling_resistance``, and ``floor_friction`` and ``drag`` where they are
        estimated) to ``(mean, std)``; ``velocity_std`` is the velocity estimate's
        standard deviation (m/s), drawn into the ensemble as speed and heading when the
        speed is more than twice it.  The horizons count from the world's time.
        """
        if math.hypot(velocity[0], velocity[1]) < REST_SPEED and math.hypot(*slip) < REST_SPEED:
            return self._at_rest(world, body, position, estimates)
        started = time.perf_counter()
        out = self._predict(world, body, position, velocity, estimates, velocity_std,
                            (float(slip[0]), float(slip[1])), max(0.0, float(since)))
        self.wall_s += time.perf_counter() - started
        return out

    def _predict(self, world: World, body: str, position: Sequence[float],
                 velocity: Sequence[float], estimates: Mapping[str, tuple[float, float]],
                 velocity_std: float, slip: tuple[float, float], since: float) -> Prediction:
        state = world.snapshot()
        scene = world.scene
        robot = scene.robot.name if scene.robot is not None else None
        # the object's own path: the robot, which the rules move, is left out of the fork
        bodies = tuple(
            BodyState(b.name, (float(position[0]), float(position[1])),
                      (float(velocity[0]), float(velocity[1])), b.angle, 0.0, slip)
            if b.name == body else b for b in state.bodies if b.name != robot)
        lead = int(round(since / world.dt))  # whole steps before the world's time
        start = replace(state, bodies=bodies, command=(0.0, 0.0, 0.0),
                        time=state.time - lead * world.dt, step=state.step - lead)
        ball = next(b for b in scene.balls if b.name == body)
        changes = {}
        for key, (mean, _) in estimates.items():
            if key == "restitution":
                changes[key] = min(max(mean, 0.0), 1.0)
            elif key in FITTED and (key != "floor_friction" or ball.floor_friction is not None):
                changes[key] = max(mean, 0.0)
        nominal_ball = ball.with_parameters(**changes)
        nominal_scene = replace(scene, robot=None,
                                balls=tuple(nominal_ball if b.name == body else b
                                            for b in scene.balls))
        fork = world.fork(start, scene=nominal_scene)
        if lead:  # from when the state was known to the world's time
            fork.step(lead)
            self.simulated_s += lead * fork.dt
        steps_per = max(1, int(round((1.0 / 60.0) / fork.dt)))
        n = int(round(self.plan / fork.dt))
        times = [k * fork.dt for k in range(0, n + 1, steps_per)]
        path = rollout(fork, self.plan, times=times, body=body)
        self.simulated_s += self.plan
        spread = [0.0] * len(self.horizons)
        if self.members > 0:
            ranges = {}
            for key, (mean, std) in estimates.items():
                if std > 0 and key in changes:
                    half = math.sqrt(3.0) * std
                    lo, hi = mean - half, mean + half
                    if key == "restitution":
                        lo, hi = max(lo, 0.0), min(hi, 1.0)
                    else:
                        lo = max(lo, 0.0)
                    if hi > lo:
                        ranges[key] = (lo, hi)
            speed = math.hypot(velocity[0], velocity[1])
            # the ensemble turns and scales the velocity: that describes its uncertainty
            # only when the speed is well above it (a ball at rest stays at rest)
            if velocity_std > 0 and speed > 2.0 * velocity_std:
                half = math.sqrt(3.0) * velocity_std
                ranges["speed_scale"] = (max(0.0, 1.0 - half / speed), 1.0 + half / speed)
                turn = math.degrees(min(math.pi / 2, math.atan2(velocity_std, speed)))
                ranges["heading_deg"] = (-math.sqrt(3.0) * turn, math.sqrt(3.0) * turn)
            if ranges:
                ens = ensemble(fork, self.horizons[-1], ranges, n=self.members,
                               times=list(self.horizons), body=body, seed=self.rng,
                               percentiles=())
                self.simulated_s += self.members * self.horizons[-1]
                for i, h in enumerate(self.horizons):
                    nominal = np.array(path.position_at(fork.time + h))
                    d = ens.samples[:, i, :] - nominal[None, :]
                    spread[i] = float(np.sqrt((d**2).sum(axis=1).mean()))
        t0 = fork.time
        contacts = tuple(c for c in path.contacts if c.ball == body)
        out = []
        for i, h in enumerate(self.horizons):
            p = path.position_at(t0 + h)
            resid = self.residuals.rms(h)
            bounce = any(t0 < c.time <= t0 + h + 1e-9 for c in contacts)
            sigma = math.hypot(spread[i], self.residuals.sigma(h, self.catch_radius, bounce))
            out.append(HorizonPrediction(h, p, spread[i], resid,
                                         confidence(sigma, self.catch_radius), bounce))
            self.residuals.expect(h, t0 + h, p, bounce)
        params = {k: float(v) for k in FITTED
                  if (v := getattr(nominal_ball, k)) is not None}
        return Prediction(t0, body, tuple(out), contacts, path, params)

    def _at_rest(self, world: World, body: str, position: Sequence[float],
                 estimates: Mapping[str, tuple[float, float]]) -> Prediction:
        """An object at rest stays where it is (unless something hits it): no rollout."""
        t0 = world.time
        p = (float(position[0]), float(position[1]))
        # it will still be there: plan over a long time, not only the usual horizon
        times = np.array([t0, t0 + max(self.plan, REST_PLAN)])
        path = Trajectory(body, times, np.array([p, p]), np.zeros((2, 2)), ())
        out = []
        for h in self.horizons:
            resid = self.residuals.rms(h)
            sigma = self.residuals.sigma(h, self.catch_radius)
            out.append(HorizonPrediction(h, p, 0.0, resid, confidence(sigma, self.catch_radius),
                                         False))
            self.residuals.expect(h, t0 + h, p)
        return Prediction(t0, body, tuple(out), (), path, {k: v[0] for k, v in estimates.items()})
