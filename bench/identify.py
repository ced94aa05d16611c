"""Identification on PyBullet tracks: where the error 1.0 s ahead across a bounce goes.

Each throw is a track of ``bench/bullet_tracks.py`` (PyBullet's 3D sphere with spin,
rolling friction and soft contacts; sightings on the ground plane with parallax,
noise and missed frames).  The sightings are fed, frame by frame, to what the
object schema does with them (``adapt/schemas/foreground.py``, no images): its gated
Kalman filter restarted at the bounces the line-fit estimator sees, the estimator,
and the identifier (:class:`adapt.mirror.identify.Identifier`, the schema's
``identify_window`` and ``identify_every``), and to the two baselines of the runner.
Every third frame each predicts 1.0 s ahead:

* ``kalman`` -- the constant-velocity Kalman baseline;
* ``map-aware`` -- the same filter rolled and reflected off the map with nominal
  parameters (``adapt/reflection.py``);
* ``mirror, identify`` -- an imagined rollout from the identified state and
  parameters while the fit passes the chi-square gate, else from the filter's state
  (the schema's ``_predict``);
* ``mirror, no identify`` -- from the filter's state with the line fits' parameters;
* the decomposition: ``true state + best`` (the true position, velocity and slip,
  with the parameters the identifier fits on the noise-free true track, afterwards),
  ``true state + online`` (the identification's parameters then), ``identified
  state + best``, and the true state with the best parameters but the online
  restitution, or the online rolling resistance and floor friction.

The imagination's ball has spin (a ``floor_friction`` range, as the foreign
scenarios give); the priors are the ranges a user would write for an unknown ball.
Aggregation: per throw the median error of the predictions with a contact (a jump
of the true velocity) inside the second -- all of them, those before the track's first
contact and those after --, and of those without; then the median over
throws, and the median over throws of each throw's ratio to the Kalman baseline's
and to the map-aware predictor's.  The identification's cost is its own wall time a
frame (timing on a shared machine is noisy: the ratios and the medians are what
count).

``python bench/identify.py --throws 20`` (about 1 s of work per track second).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from bullet_tracks import FPS, Track, make_track  # noqa: E402

from adapt.imagination import Ball, World  # noqa: E402
from adapt.imagination.scene import SceneSpec  # noqa: E402
from adapt.imagination.world import BodyState, WorldState  # noqa: E402
from adapt.kalman import ConstantVelocityKF  # noqa: E402
from adapt.mirror.identify import Fit, Identifier  # noqa: E402
from adapt.reflection import Reflector  # noqa: E402
from adapt.schemas.estimator import PARAMETERS, ParameterEstimator  # noqa: E402
from adapt.schemas.foreground import FIT_AGE, FIT_CHI2, FOREGROUND_OBJECT  # noqa: E402

HORIZON = 1.0
EVERY = 3
#: What a user writes for a ball whose behaviour is unknown (ranges; the nominal is the middle).
RANGES = {"restitution": (0.3, 0.95), "friction": (0.0, 1.0),
          "rolling_resistance": (0.0, 0.06), "floor_friction": (0.1, 1.2)}
#: A jump of the true velocity between two frames larger than this (m/s) is a contact.
CONTACT_JUMP = 0.1
KINDS = (("bounce", "a contact inside the second"),
         ("bounce, first", "the first contact inside the second (none seen before)"),
         ("bounce, one seen", "a contact inside the second, after one seen"),
         ("free", "no contact"))
VARIANTS = ("kalman", "map-aware", "mirror, identify", "mirror, no identify",
            "true state + best", "true state + online", "identified state + best",
            "true state + best, online e", "true state + best, online rolling")


def defaults() -> dict[str, Any]:
    return {p.name: p.default for p in FOREGROUND_OBJECT.parameters}


def nominal_ball(track: Track) -> Ball:
    mid = {k: (lo + hi) / 2 for k, (lo, hi) in RANGES.items()}
    return Ball("ball", radius=track.radius, mass=track.scene.balls[0].mass,
                restitution=mid["restitution"], friction=mid["friction"],
                rolling_resistance=mid["rolling_resistance"], floor_friction=mid["floor_friction"])


def priors(ball: Ball) -> dict[str, tuple[float, float]]:
    return {k: (float(getattr(ball, k)), (hi - lo) / math.sqrt(12.0)) for k, (lo, hi) in RANGES.items()}


class Roller:
    """One imagined ball rolled out from a state with given parameters."""

    def __init__(self, scene: SceneSpec, ball: Ball) -> None:
        self.world = World(SceneSpec(walls=scene.walls, obstacles=scene.obstacles, balls=(ball,)))
        self.ball = ball

    def __call__(self, position: Any, velocity: Any, slip: Any, params: dict[str, float],
                 seconds: float) -> tuple[float, float]:
        values = {k: (min(max(v, 0.0), 1.0) if k == "restitution" else max(v, 0.0))
                  for k, v in params.items()}
        self.world.set_ball_parameters("ball", **values)  # type: ignore[arg-type]
        self.world.set_state(WorldState(0.0, 0, (BodyState(
            "ball", (float(position[0]), float(position[1])),
            (float(velocity[0]), float(velocity[1])), slip=(float(slip[0]), float(slip[1]))),)))
        self.world.step(int(round(seconds / self.world.dt)))
        return self.world.position("ball")


def true_slip(track: Track, i: int) -> tuple[float, float]:
    """The spin's rolling velocity minus the velocity (the imagination's slip)."""
    w = track.spin[i]
    r = track.radius
    return (float(r * w[1] - track.velocity[i, 0]), float(-r * w[0] - track.velocity[i, 1]))


def best_parameters(track: Track, ball: Ball, window: float, every: int) -> dict[str, float]:
    """The identifier's parameters after the whole noise-free true track."""
    ident = Identifier(track.scene, ball, priors(ball), window=window, every=every, noise=0.001)
    fit: Fit | None = None
    for t, p in zip(track.times, track.truth):
        fit = ident.observe(float(t), (float(p[0]), float(p[1])))
    assert fit is not None
    return dict(fit.parameters)


def one(seed: int) -> dict[str, Any]:
    track = make_track(seed)
    par = defaults()
    ball = nominal_ball(track)
    window, every = float(par["identify_window"]), int(par["identify_every"])
    noise = float(par["measurement_noise"])
    best = best_parameters(track, ball, window, every)
    kf = ConstantVelocityKF(q=float(par["process_noise"]), r=noise, gate=float(par["gate"]))
    mid = {k: float(getattr(ball, k)) for k in PARAMETERS}
    estimator = ParameterEstimator({k: RANGES[k] for k in PARAMETERS}, nominal=mid,
                                   scene=track.scene, gravity=track.scene.gravity,
                                   radius=track.radius)
    ident = Identifier(track.scene, ball, priors(ball), window=window, every=every, noise=noise)
    base = ConstantVelocityKF(q=0.3, r=0.005)
    reflector = Reflector(track.scene, ball)
    roll = Roller(track.scene, ball)
    fit: Fit | None = None
    steps = int(round(HORIZON * FPS))
    vel = track.velocity[:, :2]
    jump = np.r_[np.linalg.norm(np.diff(vel, axis=0), axis=1) > CONTACT_JUMP, False]
    errors: dict[str, dict[str, list[float]]] = {v: {k: [] for k, _ in KINDS} for v in VARIANTS}
    ms: list[float] = []
    gated = 0
    predictions = 0
    seen = 0
    for i, (t, p) in enumerate(track.sightings()):
        kf.step(t, p)
        base.step(t, p)
        if p is not None:
            seen += 1
            bounce = estimator.observe(t, p)
            started = time.perf_counter()
            fit = ident.observe(t, p)
            ms.append(1000 * (time.perf_counter() - started))
            if bounce is not None and estimator.last_after is not None:
                t0, p0, v0 = estimator.last_after
                kf.reset(t, p0 + v0 * (t - t0), v0, estimator.noise, 0.1)  # type: ignore[arg-type]
        if p is None or i % EVERY or i + steps >= len(track.times) or fit is None or seen < 10:
            continue
        target = track.truth[i + steps, :2]
        kind = "free" if not jump[i:i + steps].any() else \
            "bounce, one seen" if jump[:i].any() else "bounce, first"
        online = dict(fit.parameters)
        line = {k: e.mean for k, e in estimator.estimates().items()}
        line["floor_friction"] = float(ball.floor_friction or 0.0)
        out: dict[str, tuple[float, float]] = {
            "kalman": tuple(np.array(base.position) + HORIZON * np.array(base.velocity)),  # type: ignore[dict-item]
            "map-aware": tuple(reflector.path(base.position, base.velocity, [HORIZON])[0][0]),  # type: ignore[dict-item]
        }
        since = t - fit.time
        fresh = 0.0 <= since <= FIT_AGE + 1e-9 and fit.chi2 <= FIT_CHI2
        gated += not fresh
        if fresh:
            out["mirror, identify"] = roll(fit.position, fit.velocity, fit.slip, online, HORIZON + since)
            out["identified state + best"] = roll(fit.position, fit.velocity, fit.slip, best,
                                                  HORIZON + since)
        else:
            out["mirror, identify"] = roll(kf.position, kf.velocity, (0, 0), online, HORIZON)
            out["identified state + best"] = roll(kf.position, kf.velocity, (0, 0), best, HORIZON)
        out["mirror, no identify"] = roll(kf.position, kf.velocity, (0, 0), line, HORIZON)
        slip = true_slip(track, i)
        out["true state + best"] = roll(track.truth[i, :2], vel[i], slip, best, HORIZON)
        out["true state + online"] = roll(track.truth[i, :2], vel[i], slip, online, HORIZON)
        out["true state + best, online e"] = roll(
            track.truth[i, :2], vel[i], slip, {**best, "restitution": online["restitution"]},
            HORIZON)
        out["true state + best, online rolling"] = roll(
            track.truth[i, :2], vel[i], slip, {**best, **{k: online[k] for k in (
                "rolling_resistance", "floor_friction")}}, HORIZON)
        predictions += 1
        for name, q in out.items():
            errors[name][kind].append(float(math.dist(q, target)))
            if kind != "free":
                errors[name]["bounce"].append(errors[name][kind][-1])
    return {"seed": seed, "errors": errors, "ms": ms, "gated": gated, "predictions": predictions,
            "simulated": ident.simulated_s / len(track.times),
            "best": best, "online": dict(fit.parameters) if fit else {},
            "true": {k: track.params[k] for k in ("restitution", "lateral_friction",
                                                   "rolling_friction", "linear_damping")}}


def med(values: list[float]) -> float | None:
    return statistics.median(values) if values else None


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--throws", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=1)
    args = ap.parse_args()
    started = time.perf_counter()
    runs = []
    for seed in range(args.first_seed, args.first_seed + args.throws):
        r = one(seed)
        runs.append(r)
        b = {k: round(v, 3) for k, v in r["best"].items()}
        print(f"seed {seed}: {r['predictions']} predictions ({r['gated']} gated to the filter); "
              f"best fitted {b}", file=sys.stderr)
    print(f"{len(runs)} PyBullet tracks in {time.perf_counter() - started:.0f} s; 1.0 s ahead, "
          f"per-throw medians, then the median over throws")
    for kind, label in KINDS:
        print(f"{label}:")
        for name in VARIANTS:
            mine, to_kalman, to_aware = [], [], []
            for r in runs:
                m = med(r["errors"][name][kind])
                k = med(r["errors"]["kalman"][kind])
                a = med(r["errors"]["map-aware"][kind])
                if m is None or k is None or a is None:
                    continue
                mine.append(m)
                to_kalman.append(m / k if k > 0 else math.nan)
                to_aware.append(m / a if a > 0 else math.nan)
            if mine:
                wins = sum(r < 1.0 for r in to_aware)
                print(f"  {name:<34} {100 * med(mine):6.1f} cm (mean {100 * float(np.mean(mine)):5.1f})"  # type: ignore[operator]
                      f"   {med(to_kalman):.3f}x Kalman   {med(to_aware):.2f}x map-aware, "
                      f"better in {wins} of {len(mine)} throws")
    ms = [v for r in runs for v in r["ms"]]
    print(f"identification: {statistics.median(ms):.1f} ms a frame median, "
          f"{float(np.mean(ms)):.1f} mean, {float(np.percentile(ms, 95)):.1f} at the 95th "
          f"percentile ({len(ms)} frames; identify_every={defaults()['identify_every']})")
    simulated = float(np.mean([r["simulated"] for r in runs]))
    print(f"  its work: {simulated:.2f} s of imagination rolled out a frame (mean; the copies of the "
          f"ball together), at {simulated * 1000 / float(np.mean(ms)):.0f}x real time here")
    gated = sum(r["gated"] for r in runs)
    total = sum(r["predictions"] for r in runs)
    print(f"the chi-square gate sent {gated} of {total} predictions to the filter's state")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
