"""The identification (adapt/mirror/identify.py) on tracks the imagination itself makes, with
noise: what it learns, what it keeps, and when it says it does not fit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adapt.errors import ImaginationError
from adapt.imagination import Ball, SceneSpec, Wall, World
from adapt.imagination.world import BodyState, WorldState
from adapt.mirror.identify import DAMPING, MAX_ITERATIONS, OUTLIER, Identifier

WALLS = (Wall("east", (1.5, -2.0), (1.5, 2.0)), Wall("west", (-1.5, -2.0), (-1.5, 2.0)))
BOX = WALLS + (Wall("north", (-2.0, 1.5), (2.0, 1.5)), Wall("south", (-2.0, -1.5), (2.0, -1.5)))
G = 9.81
FPS = 30.0


def track(ball: Ball, seconds: float, *, slip: tuple[float, float] = (0.0, 0.0),
          noise: float = 0.003, seed: int = 1, walls: tuple[Wall, ...] = WALLS
          ) -> list[tuple[float, tuple[float, float], tuple[float, float]]]:
    """(time, noisy sighting, true velocity) of ``ball`` at 30 frames/s."""
    world = World(SceneSpec(walls=walls, balls=(ball,)))
    world.set_state(WorldState(0.0, 0, (BodyState(ball.name, ball.position, ball.velocity,
                                                  slip=slip),)))
    rng = np.random.default_rng(seed)
    out = []
    for k in range(int(seconds * FPS) + 1):
        world.run_until(k / FPS)
        x, y = world.position(ball.name)
        n = rng.normal(0.0, noise, 2)
        out.append((k / FPS, (x + n[0], y + n[1]), world.velocity(ball.name)))
    return out


def identify(ident: Identifier, sightings: list) -> list:
    return [ident.observe(t, p) for t, p, _ in sightings]


def model(**kw: float | None) -> Ball:
    return Ball("b", radius=0.1, **kw)  # type: ignore[arg-type]


@pytest.mark.parametrize("e", [0.4, 0.7, 0.95])
def test_the_restitution_of_a_head_on_bounce_is_learned(e: float) -> None:
    truth = model(restitution=e, velocity=(1.5, 0.0))
    ident = Identifier(SceneSpec(walls=WALLS), model(), {"restitution": (0.7, 0.17)},
                       noise=0.003)
    fits = identify(ident, track(truth, 1.6))
    assert fits[-1].parameters["restitution"] == pytest.approx(e, abs=0.03)
    assert fits[-1].velocity[0] == pytest.approx(-e * 1.5, abs=0.04)
    assert fits[-1].contact and ident.counts["restitution"] > 0


@pytest.mark.parametrize("mu", [0.2, 0.5, 0.8])
def test_the_friction_of_a_glancing_bounce_is_learned(mu: float) -> None:
    # a glancing hit slips all through the contact: the wall takes mu_pair (1 + e) v_n of
    # the tangential speed (mu_pair = mu x the wall's 0.5); 0.8 m/s in, 2 m/s along
    truth = model(restitution=0.7, friction=mu, velocity=(0.8, 2.0), position=(0.5, -1.0))
    ident = Identifier(SceneSpec(walls=WALLS), model(), {"restitution": (0.8, 0.15),
                                                         "friction": (0.4, 0.3)}, noise=0.003)
    fits = identify(ident, track(truth, 2.0))
    end = fits[-1]
    assert end.parameters["friction"] == pytest.approx(mu, abs=0.05)
    assert end.parameters["restitution"] == pytest.approx(0.7, abs=0.03)
    assert end.velocity[0] == pytest.approx(-0.7 * 0.8, abs=0.01)
    assert end.velocity[1] == pytest.approx(2.0 - 0.5 * mu * 1.7 * 0.8, abs=0.01)


@pytest.mark.parametrize("c", [0.01, 0.03, 0.06])
def test_rolling_resistance_alone_is_learned_from_the_deceleration(c: float) -> None:
    # a ball rolling on slows at c g: v(t) = v0 - c g t
    truth = model(rolling_resistance=c, velocity=(0.0, 2.0))
    ident = Identifier(SceneSpec(), model(), {"rolling_resistance": (0.02, 0.02)}, noise=0.003)
    fits = identify(ident, track(truth, 2.0, walls=()))
    assert fits[-1].parameters["rolling_resistance"] == pytest.approx(c, abs=0.002)
    assert fits[-1].velocity[1] == pytest.approx(2.0 - c * G * 2.0, abs=0.01)
    assert fits[-1].std["rolling_resistance"] < 0.005


def test_the_gate_refuses_one_wild_sighting_but_not_a_path_that_goes_elsewhere() -> None:
    truth = model(velocity=(0.8, 0.3))
    sightings = track(truth, 1.2, walls=())
    wild = list(sightings)
    t, (x, y), v = wild[20]
    wild[20] = (t, (x, y + 0.3), v)           # 100 sigmas off, once
    clean = identify(Identifier(SceneSpec(), model(), {}, noise=0.003), sightings)
    fits = identify(Identifier(SceneSpec(), model(), {}, noise=0.003), wild)
    assert [f.outliers for f in fits[21:24]] == [1, 1, 1]
    assert fits[-1].chi2 < 2.0                   # it is left out of the chi-square ...
    for a, b in zip(fits[21:], clean[21:]):      # ... and hardly moves the fit
        assert math.dist(a.position, b.position) < 0.01
        assert math.dist(a.velocity, b.velocity) < 0.05
    # two sightings as far off are the path not fitting: the gate counts them
    ident = Identifier(SceneSpec(), model(), {}, noise=0.003)
    twice = list(sightings)
    for k in (20, 21):
        t, (x, y), v = twice[k]
        twice[k] = (t, (x, y + 0.3), v)
    fits = identify(ident, twice)
    assert fits[21].outliers == 0 and fits[21].chi2 > 4.0 * OUTLIER


def test_the_work_of_a_fit_is_bounded() -> None:
    # each fit rolls out at most MAX_ITERATIONS times 1 + n (the Jacobian) + the candidates
    # copies of the window; on a bouncing track a fit every other frame costs a small part of
    # that (bench/bullet_tracks.py --identify prints the milliseconds a frame)
    truth = model(restitution=0.6, friction=0.5, rolling_resistance=0.02, velocity=(2.0, 1.3))
    priors = {"restitution": (0.8, 0.15), "friction": (0.4, 0.3),
              "rolling_resistance": (0.02, 0.02)}
    ident = Identifier(SceneSpec(walls=BOX), model(), priors, noise=0.003, every=2, dt=1 / 240)
    worst = MAX_ITERATIONS * (1 + 4 + len(priors) + len(DAMPING)) * ident.window
    simulated = []
    fits = []
    for t, p, _ in track(truth, 4.0, walls=BOX):
        before = ident.simulated_s
        fits.append(ident.observe(t, p))
        simulated.append(ident.simulated_s - before)
    assert max(simulated) <= worst + 1e-9
    assert sum(simulated) / len(simulated) < worst / 5
    assert fits[-1].parameters["restitution"] == pytest.approx(0.6, abs=0.05)
    assert fits[-1].parameters["rolling_resistance"] == pytest.approx(0.02, abs=0.003)


def test_what_a_bounce_taught_is_kept_after_it_leaves_the_window() -> None:
    truth = model(restitution=0.45, velocity=(2.0, 0.0))
    ident = Identifier(SceneSpec(walls=WALLS), model(), {"restitution": (0.8, 0.1)},
                       window=0.6, noise=0.003)
    fits = identify(ident, track(truth, 2.5))   # east at 0.7 s, west at about 3.6 s
    assert not fits[-1].contact                 # the bounce is long out of the window
    assert fits[-1].parameters["restitution"] == pytest.approx(0.45, abs=0.04)
    assert fits[-1].std["restitution"] < 0.05


def test_rolling_resistance_and_drag_are_learned_from_rolling() -> None:
    truth = model(rolling_resistance=0.03, drag=0.2, velocity=(0.0, 2.5))
    ident = Identifier(SceneSpec(), model(), {"rolling_resistance": (0.02, 0.015),
                                              "drag": (0.05, 0.05)}, window=1.2, noise=0.002)
    fits = identify(ident, track(truth, 2.4, walls=()))
    end = fits[-1]
    # the two trade off against each other; what they do together is what counts: the
    # deceleration at the speeds of the track
    for v in (1.0, 2.0):
        fitted = end.parameters["rolling_resistance"] * 9.81 + end.parameters["drag"] * v * v
        assert fitted == pytest.approx(0.03 * 9.81 + 0.2 * v * v, rel=0.15)
    assert not end.contact and ident.counts["rolling_resistance"] > 0


def test_the_floor_friction_of_a_ball_thrown_sliding_is_learned() -> None:
    # launched without spin: it slides until it rolls at 5/7 of its speed, at mu g
    truth = model(floor_friction=0.25, velocity=(2.8, 0.0), position=(-1.3, 0.0))
    ident = Identifier(SceneSpec(walls=WALLS), model(floor_friction=0.6),
                       {"floor_friction": (0.6, 0.3)}, window=0.9, noise=0.002)
    fits = identify(ident, track(truth, 0.6, slip=(-2.8, 0.0)))
    assert fits[-1].parameters["floor_friction"] == pytest.approx(0.25, abs=0.05)
    # it rolls from (2/7) v0 / (mu g) = 0.33 s on, at 5/7 of v0
    assert fits[-1].velocity[0] == pytest.approx(5.0 / 7.0 * 2.8, abs=0.05)
    assert fits[-1].slip[0] == pytest.approx(0.0, abs=0.05)


def test_a_window_the_model_does_not_fit_does_not_become_the_prior() -> None:
    # for a second the ball does what the model cannot follow (it wobbles sideways, as a
    # hopping ball seen with parallax does, and slows at 1.5 m/s^2), then it rolls on at
    # c = 0.02: what the misfit window made of the rolling resistance is not kept as the
    # prior, so the rolling is learned sooner
    ident = Identifier(SceneSpec(), model(), {"rolling_resistance": (0.02, 0.01)}, noise=0.003)
    rng = np.random.default_rng(3)
    x, v = 0.0, 2.5
    fits = {}
    for k in range(int(2.0 * FPS) + 1):
        t = k / FPS
        wobble = 0.015 * math.sin(2 * math.pi * 4 * t) if t < 1.0 else 0.0
        fits[k] = ident.observe(t, (x + rng.normal(0, 0.003), wobble + rng.normal(0, 0.003)))
        a = 1.5 if t < 1.0 else 0.02 * G
        x += v / FPS - 0.5 * a / FPS ** 2
        v -= a / FPS
    assert fits[30].chi2 > 4.0                   # the model does not follow the first second
    assert fits[54].parameters["rolling_resistance"] == pytest.approx(0.02, abs=0.006)
    assert max(f.std["rolling_resistance"] for f in fits.values() if f) <= 0.01 + 1e-12


def test_a_parameter_nothing_informs_keeps_its_prior() -> None:
    truth = model(restitution=0.3, velocity=(0.5, 0.2))   # no wall within reach
    ident = Identifier(SceneSpec(walls=WALLS), model(), {"restitution": (0.7, 0.1),
                                                         "friction": (0.4, 0.2)}, noise=0.003)
    fits = identify(ident, track(truth, 1.5))
    assert fits[-1].parameters == {"restitution": 0.7, "friction": 0.4}
    assert ident.counts == {"restitution": 0, "friction": 0}
    assert not fits[-1].contact


def test_a_path_that_fits_has_a_chi_square_near_one_and_one_that_does_not_says_so() -> None:
    truth = model(velocity=(0.8, 0.0))
    ident = Identifier(SceneSpec(walls=WALLS), model(), {}, noise=0.003)
    fits = identify(ident, track(truth, 1.0))
    assert fits[-1].chi2 < 2.0
    # the ball is kicked sideways, as nothing in the model can: once two sightings are off
    # (one alone may be a wild sighting: the gate's), the path no longer fits
    t0 = 1.0 + 1 / FPS
    kicked = [(t0 + k / FPS, (0.8 * (t0 + k / FPS) + 0.0, 0.6 * k / FPS)) for k in range(4)]
    fits = [ident.observe(t, p) for t, p in kicked]
    assert fits[2] is not None and fits[2].outliers == 1
    assert fits[3] is not None and fits[3].chi2 > 4.0


def test_the_identification_needs_a_few_sightings_and_skips_the_missed_ones() -> None:
    ident = Identifier(SceneSpec(), model(), {}, noise=0.003)
    assert [ident.observe(k / FPS, (0.1 * k, 0.0)) for k in range(3)] == [None, None, None]
    assert ident.observe(3 / FPS, None) is None
    fit = ident.observe(4 / FPS, (0.4, 0.0))
    assert fit is not None and fit.velocity[0] == pytest.approx(3.0, abs=0.1)
    assert ident.observe(5 / FPS, None) is fit


def test_bad_settings_are_refused() -> None:
    scene = SceneSpec()
    with pytest.raises(ImaginationError, match="cannot fit 'spin'"):
        Identifier(scene, model(), {"spin": (0.5, 0.1)})
    with pytest.raises(ImaginationError, match="restitution: expected a finite mean"):
        Identifier(scene, model(), {"restitution": (math.nan, 0.1)})
    with pytest.raises(ImaginationError, match="window: expected a positive number"):
        Identifier(scene, model(), {}, window=0.0)
    with pytest.raises(ImaginationError, match="every: expected a whole number"):
        Identifier(scene, model(), {}, every=0)
    with pytest.raises(ImaginationError, match="floor_friction: the ball has no spin"):
        Identifier(scene, model(), {"floor_friction": (0.5, 0.2)})


def test_a_contact_first_met_on_the_last_step_of_a_fit_frees_what_a_contact_teaches(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # every fit takes all its steps, and the third of each finds the path meeting a wall
    # for the first time: the contact's parameters are free from then on, though no step
    # of this fit moved them (their uncertainty is still the prior's)
    import dataclasses

    import adapt.mirror.identify as module

    monkeypatch.setattr(module, "REFIT_CHI2", -1.0)
    real = Identifier._iterate
    calls: list[int] = []

    def late(self: Identifier, start: object, free: list[int], *rest: object) -> object:
        best, jtj = real(self, start, free, *rest)  # type: ignore[arg-type]
        calls.append(len(free))
        if len(calls) % MAX_ITERATIONS == 0 and best.contact == math.inf:
            best = dataclasses.replace(best, contact=1e9)
        return best, jtj

    monkeypatch.setattr(Identifier, "_iterate", late)
    ident = Identifier(SceneSpec(walls=WALLS), model(), {"restitution": (0.7, 0.17)},
                       noise=0.003)
    first = None
    for t, p, _ in track(model(velocity=(0.5, 0.0)), 0.5):
        first = ident.observe(t, p)
        if first is not None:
            break
    assert first is not None and first.contact
    assert calls == [4] * MAX_ITERATIONS                # restitution was never stepped...
    assert first.std["restitution"] == pytest.approx(0.17)   # ...so it keeps its prior's
    assert ident.counts["restitution"] == 0
