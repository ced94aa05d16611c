"""Prediction: run forks of a world ahead of time.

* :func:`rollout` - one fork run to a horizon, sampled at requested times, with
  the contact events on the way;
* :func:`intercept` / :func:`time_to_reach` - the earliest point of a
  predicted path that a robot with a maximum speed and acceleration can reach
  in time; :func:`intercept_reach` - how close the robot's centre must come to
  a ball's;
* :func:`ensemble` - N seeded rollouts with ball parameters drawn from ranges,
  summarised by mean and percentile positions.

A fork never disturbs the world it was taken from.  Times are world times in
seconds (a rollout from a world at ``t = 2`` samples ``2 + offset``).

Work is bounded: a rollout runs at most ``MAX_STEPS`` steps (see
:mod:`~adapt.imagination.world`) and keeps at most :data:`MAX_SAMPLES`
samples; an ensemble has at most :data:`MAX_MEMBERS` members, keeps at most
:data:`MAX_ENSEMBLE_VALUES` positions and runs at most
:data:`MAX_ENSEMBLE_STEPS` steps in all.  Beyond these an
:class:`~adapt.errors.ImaginationError` says which limit and by how much.

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> from adapt.imagination.world import World
>>> scene = SceneSpec(balls=(Ball("ball", radius=0.1, velocity=(1.0, 0.0)),),
...                   walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
>>> path = rollout(World(scene), 1.5, times=[0.5, 1.5])
>>> path.positions.round(3).tolist()
[[0.5, 0.0], [0.427, 0.0]]
>>> [c.surface for c in path.contacts]
['east']
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from adapt.errors import ImaginationError
from adapt.imagination.scene import Ball, RobotSpec, Vec2
from adapt.imagination.world import MAX_STEPS, BodyState, Contact, World, WorldState

__all__ = [
    "Trajectory",
    "Intercept",
    "Ensemble",
    "ENSEMBLE_PARAMETERS",
    "rollout",
    "time_to_reach",
    "intercept",
    "intercept_reach",
    "meets",
    "CONTACT",
    "ensemble",
    "MAX_SAMPLES",
    "MAX_MEMBERS",
    "MAX_ENSEMBLE_VALUES",
    "MAX_ENSEMBLE_STEPS",
]

#: Most samples a rollout keeps.
MAX_SAMPLES = 100_000
#: Most members of an ensemble.
MAX_MEMBERS = 10_000
#: Most positions an ensemble keeps (members x sample times).
MAX_ENSEMBLE_VALUES = 2_000_000
#: Most physics steps an ensemble runs, all members together.
MAX_ENSEMBLE_STEPS = 5 * MAX_STEPS

FloatArray = NDArray[np.float64]

#: Parameters an ensemble may vary: ball properties, and ``speed_scale``
#: (factor on the initial speed) and ``heading_deg`` (turn of the initial
#: velocity, degrees counter-clockwise).
ENSEMBLE_PARAMETERS = (
    "restitution",
    "friction",
    "rolling_resistance",
    "mass",
    "floor_friction",
    "drag",
    "speed_scale",
    "heading_deg",
)


@dataclass(frozen=True, slots=True, eq=False)
class Trajectory:
    """A predicted path of one body.

    Attributes
    ----------
    body : str
        The body's name.
    times : (T,) ndarray
        World times of the samples (whole physics steps).
    positions, velocities : (T, 2) ndarray
        ``(x, y)`` and ``(vx, vy)`` at those times.
    contacts : tuple of Contact
        Contacts of any ball during the rollout, in time order.
    """

    body: str
    times: FloatArray
    positions: FloatArray
    velocities: FloatArray
    contacts: tuple[Contact, ...]

    def position_at(self, time: float) -> Vec2:
        """Position at ``time``, linearly interpolated between samples."""
        x = float(np.interp(time, self.times, self.positions[:, 0]))
        y = float(np.interp(time, self.times, self.positions[:, 1]))
        return (x, y)


@dataclass(frozen=True, slots=True)
class Intercept:
    """Where and when a robot can first meet a predicted path.

    ``time`` is the world time of the meeting, ``position`` the ball's
    position then, ``travel`` the distance the robot covers (its centre stops
    ``reach`` short of the ball) and ``robot_time`` how long that takes it,
    never more than ``time - start``.
    """

    time: float
    position: Vec2
    travel: float
    robot_time: float


@dataclass(frozen=True, slots=True, eq=False)
class Ensemble:
    """Summary of N rollouts with drawn parameters.

    Attributes
    ----------
    times : (T,) ndarray
        Sample times.
    samples : (N, T, 2) ndarray
        Every member's position at every time.
    mean : (T, 2) ndarray
        Mean position.
    percentiles : dict of float to (T, 2) ndarray
        Per-axis percentiles of the position (``x`` and ``y`` separately).
    parameters : dict of str to (N,) ndarray
        The drawn values of each varied parameter.
    """

    body: str
    times: FloatArray
    samples: FloatArray
    mean: FloatArray
    percentiles: dict[float, FloatArray]
    parameters: dict[str, FloatArray]

    @property
    def spread(self) -> FloatArray:
        """RMS distance of the members from the mean at each time, ``(T,)``."""
        d = self.samples - self.mean[None]
        return np.sqrt((d**2).sum(axis=2).mean(axis=0))


def _default_body(world: World, body: str | None) -> str:
    if body is not None:
        world.body(body)  # raises if unknown
        return body
    if not world.scene.balls:
        raise ImaginationError("the scene has no ball to predict")
    return world.scene.balls[0].name


def _offsets(horizon: float, times: Sequence[float] | None, world: World) -> list[int]:
    try:
        h = float(horizon)
    except (TypeError, ValueError):
        raise ImaginationError(f"horizon: expected a number of seconds, got {horizon!r}") from None
    if not math.isfinite(h) or h < 0:
        raise ImaginationError(f"horizon: expected a non-negative number of seconds, got {horizon}")
    total = world.steps_for(h, "horizon")
    dt = world.dt
    if times is None:
        if total + 1 > MAX_SAMPLES:
            raise ImaginationError(
                f"horizon: sampling every step of {h:g} s keeps {total + 1:,} samples; at most "
                f"{MAX_SAMPLES:,}: pass the sample times"
            )
        return list(range(total + 1))
    if len(times) > MAX_SAMPLES:
        raise ImaginationError(
            f"times: {len(times):,} sample times; a rollout keeps at most {MAX_SAMPLES:,}"
        )
    steps = []
    for t in times:
        if not 0 <= t <= h + 1e-12:
            raise ImaginationError(f"sample time {t} is outside [0, {h}] (seconds ahead)")
        steps.append(int(round(t / dt)))
    return sorted(set(steps))


def rollout(
    world: World,
    horizon: float,
    *,
    times: Sequence[float] | None = None,
    body: str | None = None,
    state: WorldState | None = None,
) -> Trajectory:
    """Run a fork of ``world`` for ``horizon`` seconds.

    Parameters
    ----------
    world : World
        Left untouched.
    horizon : float
        Seconds ahead.
    times : sequence of float, optional
        Offsets (seconds ahead, ``0..horizon``) to sample; default every step.
        Each is rounded to a whole step.
    body : str, optional
        Which body to follow; default the first ball.
    state : WorldState, optional
        Start from this state instead of the world's current one.
    """
    name = _default_body(world, body)
    steps = _offsets(horizon, times, world)
    fork = world.fork(state, record_contacts=True)
    b = fork.body(name)
    out_t = np.empty(len(steps))
    out_p = np.empty((len(steps), 2))
    out_v = np.empty((len(steps), 2))
    done = 0
    for i, k in enumerate(steps):
        if k > done:
            fork.step(k - done)
            done = k
        out_t[i] = fork.time
        p, v = b.position, b.velocity
        out_p[i] = (p[0], p[1])
        out_v[i] = (v[0], v[1])
    total = fork.steps_for(horizon, "horizon")
    if total > done:
        fork.step(total - done)  # contacts up to the horizon even past the last sample
    return Trajectory(name, out_t, out_p, out_v, tuple(fork.contacts))


def time_to_reach(distance: float, max_speed: float, max_accel: float) -> float:
    """Shortest time to cover ``distance`` from rest with bounded speed and acceleration.

    The robot accelerates at ``max_accel`` up to ``max_speed`` and cruises; it
    need not stop at the end.

    Examples
    --------
    >>> time_to_reach(1.0, max_speed=10.0, max_accel=2.0)  # sqrt(2 d / a)
    1.0
    >>> time_to_reach(3.0, max_speed=1.0, max_accel=2.0)   # d/v + v/(2a)
    3.25
    """
    if distance <= 0:
        return 0.0
    ramp = max_speed * max_speed / (2.0 * max_accel)
    if distance <= ramp:
        return math.sqrt(2.0 * distance / max_accel)
    return distance / max_speed + max_speed / (2.0 * max_accel)


#: Bodies in contact are this close to touching and still meet (metres): the physics keeps them
#: a hair apart, and a frame falls between two physics steps.
CONTACT = 0.02


def meets(distance: float, reach: float) -> bool:
    """Whether the robot's body meets the ball: their centres ``distance`` apart, within the
    catch ``reach`` (:func:`intercept_reach`) and :data:`CONTACT`.  What "caught" means, for
    the agent's ``^caught`` (on what it perceives), the evaluation (on the truth) and the
    baselines' robots alike.

    Examples
    --------
    >>> meets(0.3698, 0.36), meets(0.39, 0.36)
    (True, False)
    """
    return distance <= reach + CONTACT


def intercept_reach(ball: Ball, robot: RobotSpec) -> float:
    """How close the robot's centre must come to the ball's centre to meet it.

    The ball's radius plus the robot's radius (a disc) or half its smaller
    side (a box: the distance from its centre to its nearest side).

    Examples
    --------
    >>> from adapt.imagination.scene import RobotShape
    >>> intercept_reach(Ball("b", radius=0.1), RobotSpec(shape=RobotShape.DISC, radius=0.25))
    0.35
    >>> intercept_reach(Ball("b", radius=0.1), RobotSpec(shape=RobotShape.BOX, size=(0.6, 0.4)))
    0.30000000000000004
    """
    return ball.radius + robot.inner_radius


def intercept(
    trajectory: Trajectory,
    robot_position: Sequence[float],
    max_speed: float,
    max_accel: float,
    *,
    reach: float = 0.0,
    start: float | None = None,
) -> Intercept | None:
    """The earliest point of ``trajectory`` a robot starting at rest can reach in time.

    The robot starts at ``start`` (default the trajectory's first time); it
    meets the ball when its centre is within ``reach`` of the ball's centre
    (for example the sum of the two radii).  Between samples the path is
    linear and the meeting time is refined by bisection.  Returns ``None`` if
    the robot cannot make it within the trajectory.

    Examples
    --------
    >>> t = np.linspace(0.0, 4.0, 41)
    >>> path = Trajectory("ball", t, np.stack([t, np.full_like(t, 2.0)], 1),
    ...                   np.tile([1.0, 0.0], (41, 1)), ())
    >>> hit = intercept(path, (3.0, 0.0), max_speed=2.0, max_accel=4.0)
    >>> round(hit.time, 3), [round(c, 3) for c in hit.position]
    (1.5, [1.5, 2.0])
    """
    if max_speed <= 0 or max_accel <= 0:
        raise ImaginationError("intercept: max_speed and max_accel must be positive")
    t0 = float(trajectory.times[0]) if start is None else float(start)
    rx, ry = float(robot_position[0]), float(robot_position[1])

    def slack(time: float, pos: Sequence[float]) -> float:
        d = max(0.0, math.hypot(pos[0] - rx, pos[1] - ry) - reach)
        return (time - t0) - time_to_reach(d, max_speed, max_accel)

    times, pos = trajectory.times, trajectory.positions
    prev: int | None = None
    for k in range(len(times)):
        if times[k] < t0:
            continue
        if slack(float(times[k]), pos[k]) >= 0:
            lo_t, hi_t = (float(times[prev]), float(times[k])) if prev is not None else (
                float(times[k]), float(times[k]))
            for _ in range(40):
                if hi_t - lo_t < 1e-9:
                    break
                mid = 0.5 * (lo_t + hi_t)
                if slack(mid, trajectory.position_at(mid)) >= 0:
                    hi_t = mid
                else:
                    lo_t = mid
            p = trajectory.position_at(hi_t)
            travel = max(0.0, math.hypot(p[0] - rx, p[1] - ry) - reach)
            return Intercept(hi_t, p, travel, time_to_reach(travel, max_speed, max_accel))
        prev = k
    return None


def ensemble(
    world: World,
    horizon: float,
    ranges: Mapping[str, tuple[float, float]],
    *,
    n: int = 100,
    times: Sequence[float] | None = None,
    body: str | None = None,
    percentiles: Sequence[float] = (5.0, 50.0, 95.0),
    seed: int | np.random.Generator | None = None,
    state: WorldState | None = None,
) -> Ensemble:
    """``n`` rollouts of forks of ``world`` with parameters drawn uniformly from ``ranges``.

    Parameters
    ----------
    ranges : mapping of str to (low, high)
        Parameters of the followed ball to vary (see
        :data:`ENSEMBLE_PARAMETERS`); others keep the scene's values.
    times : sequence of float, optional
        Offsets to sample (default: 21 evenly spaced from 0 to ``horizon``).
    seed : int or Generator, optional
        Default ``world.seed``.  The same seed gives the same ensemble.

    Examples
    --------
    >>> from adapt.imagination.scene import Ball, SceneSpec
    >>> w = World(SceneSpec(balls=(Ball("b", velocity=(1.0, 0.0)),)))
    >>> e = ensemble(w, 1.0, {"speed_scale": (0.5, 1.5)}, n=50, times=[1.0], seed=1)
    >>> bool(abs(e.mean[-1, 0] - 1.0) < 0.1), bool(e.percentiles[95.0][-1, 0] > 1.3)
    (True, True)
    """
    name = _default_body(world, body)
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_MEMBERS:
        raise ImaginationError(f"n: expected an ensemble size from 1 to {MAX_MEMBERS:,}, got {n!r}")
    for key, (lo, hi) in ranges.items():
        if key not in ENSEMBLE_PARAMETERS:
            raise ImaginationError(
                f"cannot vary {key!r}; expected one of {', '.join(ENSEMBLE_PARAMETERS)}"
            )
        if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise ImaginationError(f"{key}: expected a range low <= high, got ({lo}, {hi})")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(
        world.seed if seed is None else seed
    )
    if times is None:
        times = list(np.linspace(0.0, horizon, 21))
    steps = _offsets(horizon, times, world)
    if n * len(steps) > MAX_ENSEMBLE_VALUES:
        raise ImaginationError(
            f"n: {n:,} members x {len(steps):,} sample times keep {n * len(steps):,} positions; "
            f"at most {MAX_ENSEMBLE_VALUES:,}"
        )
    if n * (steps[-1] if steps else 0) > MAX_ENSEMBLE_STEPS:
        raise ImaginationError(
            f"n: {n:,} members x {steps[-1]:,} steps is {n * steps[-1]:,} physics steps; "
            f"an ensemble runs at most {MAX_ENSEMBLE_STEPS:,}"
        )
    start = world.snapshot() if state is None else state
    scene = world.scene
    base_ball = scene.ball(name) if any(b.name == name for b in scene.balls) else None
    if base_ball is None:
        raise ImaginationError(f"{name!r} is not a ball; ensembles vary ball parameters")
    drawn = {key: rng.uniform(lo, hi, size=n) for key, (lo, hi) in ranges.items()}
    if scene.robot is None and len(scene.balls) == 1:
        samples, out_t = _members_together(world, base_ball, start, drawn, n, steps)
    else:
        samples, out_t = _members_in_turn(world, base_ball, start, drawn, n, steps)
    pct = {float(q): np.percentile(samples, q, axis=0) for q in percentiles}
    return Ensemble(name, out_t, samples, samples.mean(axis=0), pct, drawn)


#: The ball parameters a member may draw (the others turn and scale its velocity).
_MEMBER_PARAMETERS = ("restitution", "friction", "rolling_resistance", "mass", "floor_friction",
                      "drag")


def _member(drawn: Mapping[str, FloatArray], m: int) -> tuple[dict[str, float], dict[str, float]]:
    """Member ``m``'s draws, and those of them that are ball parameters."""
    values = {k: float(v[m]) for k, v in drawn.items()}
    return values, {k: values[k] for k in _MEMBER_PARAMETERS if k in values}


def _members_in_turn(world: World, ball: Ball, start: WorldState,
                     drawn: Mapping[str, FloatArray], n: int, steps: Sequence[int]
                     ) -> tuple[FloatArray, FloatArray]:
    """The members one after another in one fork of the whole scene (other balls, the
    robot): each gets its parameters in place and the start state (building a world per
    member costs about as much as a second of physics)."""
    name = ball.name
    samples = np.empty((n, len(steps), 2))
    out_t = np.empty(len(steps))
    fork = World(world.scene, dt=world.dt, seed=world.seed, state=start, record_contacts=False)
    for m in range(n):
        values, params = _member(drawn, m)
        if params:
            fork.set_ball_parameters(name, **params)  # type: ignore[arg-type]
        fork.set_state(_member_state(start, name, values))
        b = fork.body(name)
        done = 0
        for i, k in enumerate(steps):
            if k > done:
                fork.step(k - done)
                done = k
            p = b.position
            samples[m, i] = (p[0], p[1])
            out_t[i] = fork.time
    return samples, out_t


def _members_together(world: World, ball: Ball, start: WorldState,
                      drawn: Mapping[str, FloatArray], n: int, steps: Sequence[int]
                      ) -> tuple[FloatArray, FloatArray]:
    """Every member a copy of the ball in one world, the copies passing through one
    another: when the ball is the scene's only moving body, the same rollouts as one
    after another (but that the fastest copy sets every copy's sub-steps), for one
    physics step per time step instead of one per member."""
    scene = world.scene
    taken = {w.name for w in scene.walls} | {o.name for o in scene.obstacles}
    prefix = ball.name + "#"
    while any(t.startswith(prefix) for t in taken):
        prefix += "#"
    names = [f"{prefix}{m}" for m in range(n)]
    own = WorldState(start.time, start.step, (start.body(ball.name),), start.command)
    copies, bodies = [], []
    for m, copy in enumerate(names):
        values, params = _member(drawn, m)
        copies.append(replace(ball, name=copy).with_parameters(**params))  # type: ignore[arg-type]
        bodies.append(replace(_member_state(own, ball.name, values).bodies[0], name=copy))
    fork = World(replace(scene, balls=tuple(copies)), dt=world.dt, seed=world.seed,
                 record_contacts=False, ball_collisions=False)
    fork.set_state(WorldState(start.time, start.step, tuple(bodies), start.command))
    handles = [fork.body(c) for c in names]
    samples = np.empty((n, len(steps), 2))
    out_t = np.empty(len(steps))
    done = 0
    for i, k in enumerate(steps):
        if k > done:
            fork.step(k - done)
            done = k
        for m, b in enumerate(handles):
            p = b.position
            samples[m, i] = (p[0], p[1])
        out_t[i] = fork.time
    return samples, out_t


def _member_state(state: WorldState, name: str, values: dict[str, float]) -> WorldState:
    """``state`` with ``name``'s velocity scaled and turned by the member's draws."""
    scale = values.get("speed_scale", 1.0)
    turn = math.radians(values.get("heading_deg", 0.0))
    if scale == 1.0 and turn == 0.0:
        return state
    bodies = []
    for b in state.bodies:
        if b.name == name:
            c, s = math.cos(turn), math.sin(turn)
            vx, vy = b.velocity
            b = BodyState(b.name, b.position,
                          (scale * (c * vx - s * vy), scale * (s * vx + c * vy)),
                          b.angle, b.angular_velocity, b.slip)
        bodies.append(b)
    return replace(state, bodies=tuple(bodies))
