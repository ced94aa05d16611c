"""Reality's physics: the imagination's world, plus what its model lacks.

:class:`RealWorld` is built on :class:`adapt.imagination.World` (the same
scene records, walls, obstacles, restitution, friction and rolling
resistance inside pymunk) and adds, on every one of its own, finer steps
(``reality.dt``, 1/960 s by default), physics that the imagination's model
does not share, so that no choice of the model's parameters fits it exactly:

* **speed-dependent rolling drag**: a deceleration ``drag * v**2`` (``drag``
  in 1/m) against the motion, on top of the constant rolling resistance;
* **spin through a bounce**: a rolling ball spins, and a bounce reverses its
  velocity but not its spin at once.  The ball keeps a slip velocity ``u``
  (spin velocity minus linear velocity, zero while it rolls cleanly); at a
  bounce that changes the velocity by ``dv``, the slip grows by
  ``-spin * dv`` (``spin`` = 0: the spin follows the ball at once, as in the
  model; 1: all of it is kept, as for a solid ball whose wall contact does
  not grip).  Friction with the floor then brings spin and velocity
  together: the slip decays as ``exp(-t / SPIN_TIME)`` and a solid sphere's
  linear velocity takes ``2/7`` of what it loses.  A ball that hits a wall
  head-on at ``V`` with restitution ``e`` leaves at ``e V`` and settles, over
  a few tenths of a second, to ``e V - (2/7) spin (1 + e) V``;
* **objects that appear** at their drawn time and place (a throw): they
  enter the world (:meth:`World.add_ball <adapt.imagination.World.add_ball>`)
  at the first step at or after that time, and are not present before;
* **a robot with its own dynamics**: the true speed and acceleration limits,
  and wheel slip -- the velocity it really drives at is the commanded one
  plus ``slip * |v|`` times a Gaussian vector (and the turn rate times
  ``1 + slip * n``), redrawn every ``slip_interval`` seconds from the
  ``reality.noise`` stream; it never exceeds its speed limit, and the pymunk
  drive never accelerates it faster than its acceleration limit.

All of it runs in one step hook (:meth:`World.add_step_hook
<adapt.imagination.World.add_step_hook>`), before each step: it looks at
what the last step did, places the objects whose time has come, redraws the
slip, and applies the drag and spin forces for the step.  A bounce is
recognised as a change of velocity over one step that the drag, the spin
transfer and the rolling resistance cannot explain (more than ``2 c g dt``).

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec
>>> from adapt.reality.truth import ObjectParameters
>>> p = ObjectParameters("b", True, 0.8, 0.3, 0.0, 0.4, 0.5, 0.0, None, (0.0, 0.0), (2.0, 0.0))
>>> w = RealWorld(SceneSpec(balls=(Ball("b", velocity=(2.0, 0.0)),)), (p,), dt=1 / 960)
>>> w.run_until(1.0)
>>> round(w.velocity("b")[0], 3)    # dv/dt = -0.5 v**2: v = 2 / (1 + 0.5 * 2 * t)
1.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from adapt.errors import RealityError
from adapt.geometry import rotation_exp
from adapt.imagination.scene import Ball, RobotSpec, SceneSpec, Vec2
from adapt.imagination.world import World, WorldState
from adapt.reality.truth import ObjectParameters, RobotState

__all__ = ["RealWorld", "SPIN_TIME", "ROLLING_SHARE", "true_scene"]

#: Time constant of the slip's decay after a bounce, seconds.
SPIN_TIME = 0.1
#: Share of the slip that a solid sphere's linear velocity takes (I = 2/5 m r^2).
ROLLING_SHARE = 2.0 / 7.0


def true_scene(scene: SceneSpec, balls: Sequence[Ball], objects: Sequence[ObjectParameters],
               robot: RobotSpec | None, dt: float) -> SceneSpec:
    """The scene of reality: the world's static parts, every true object with
    its drawn parameters (``balls[i]`` gives the look of ``objects[i]``), the
    real robot, and reality's time step."""
    true_balls = tuple(
        replace(b, restitution=p.restitution, friction=p.friction,
                rolling_resistance=p.rolling_resistance, mass=p.mass, position=p.position,
                velocity=p.velocity)
        for b, p in zip(balls, objects, strict=True))
    return replace(scene, balls=true_balls, robot=robot, dt=dt)


@dataclass(slots=True)
class _Ball:
    """Reality's own state of one ball beyond pymunk's."""

    record: Ball
    mass: float
    drag: float
    spin: float
    appear_step: int | None   # None: present from the start
    threshold: float          # a velocity change above this in one step is a bounce
    present: bool = False
    ux: float = 0.0           # slip velocity (spin minus linear), m/s
    uy: float = 0.0
    roll: tuple[float, float, float] = (0.0, 0.0, 0.0)  # rotation vector not yet applied
    orientation: np.ndarray | None = None

    @property
    def name(self) -> str:
        return self.record.name


class RealWorld:
    """A ground-truth world: the imagination's physics plus reality's own.

    Parameters
    ----------
    scene : SceneSpec
        The true scene (see :func:`true_scene`): ``scene.balls[i]`` is the
        ball of ``objects[i]``, at the position and velocity it starts or
        appears with.
    objects : sequence of ObjectParameters
        What was drawn for each object (drag, spin, when it appears).
    dt : float
        Reality's physics step, seconds.
    slip, slip_interval : float
        Wheel slip of the robot (fraction of the commanded velocity) and how
        often it is redrawn (seconds).
    rng : numpy.random.Generator, optional
        The ``reality.noise`` stream, for the slip (needed when ``slip > 0``).
    """

    def __init__(self, scene: SceneSpec, objects: Sequence[ObjectParameters], *, dt: float,
                 slip: float = 0.0, slip_interval: float = 0.2,
                 rng: np.random.Generator | None = None) -> None:
        if [b.name for b in scene.balls] != [o.name for o in objects]:
            raise ValueError("scene.balls and objects must name the same balls in one order")
        if slip > 0 and rng is None:
            raise ValueError("wheel slip needs a random generator")
        self.dt = float(dt)
        self._balls: list[_Ball] = []
        for b, o in zip(scene.balls, objects):
            step = None if o.appears is None else int(math.ceil(o.appears / self.dt - 1e-9))
            self._balls.append(_Ball(
                b, o.mass, o.drag, o.spin, step,
                2.0 * o.rolling_resistance * scene.gravity * self.dt + 1e-6,
                present=step is None, orientation=np.eye(3)))
        start = tuple(b.record for b in self._balls if b.present)
        self.world = World(replace(scene, balls=start), dt=self.dt, record_contacts=False)
        self._robot = scene.robot
        self._command = (0.0, 0.0, 0.0)
        self._slip = float(slip)
        self._slip_every = max(1, int(round(slip_interval / self.dt)))
        self._rng = rng
        self._noise = (0.0, 0.0, 0.0)
        self._expected: list[tuple[_Ball, float, float]] = []
        self.world.add_step_hook(self._before_step)
        self._appear()

# -- the robot (an Actuator) -------------------------------------------------------

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Command the real robot: velocity (m/s, world frame) and turn rate (rad/s).

        Raises
        ------
        RealityError
            Without a robot, or for a command that is not a finite number.
        """
        try:
            vx, vy, w = float(velocity[0]), float(velocity[1]), float(angular_velocity)
        except (TypeError, ValueError, IndexError):
            raise RealityError(f"a robot command is a velocity (vx, vy) in m/s and a turn rate "
                               f"in rad/s, got {velocity!r}, {angular_velocity!r}") from None
        if not all(math.isfinite(x) for x in (vx, vy, w)):
            raise RealityError(f"a robot command must be finite, got ({vx}, {vy}), {w}")
        if self._robot is None:
            raise RealityError("this reality has no robot to command")
        self._command = (vx, vy, w)
        self._drive()

    @property
    def command(self) -> tuple[float, float, float]:
        """The last command ``(vx, vy, omega)`` as given (before limits and slip)."""
        return self._command

    def _drive(self) -> None:
        vx, vy, w = self._command
        if self._robot is None:
            return
        speed = math.hypot(vx, vy)
        limit = self._robot.max_speed
        if speed > limit:
            vx, vy, speed = vx * limit / speed, vy * limit / speed, limit
        nx, ny, nw = self._noise
        vx, vy = vx + self._slip * speed * nx, vy + self._slip * speed * ny
        self.world.command_robot((vx, vy), w * (1.0 + self._slip * nw))  # clips to max_speed

    # -- time ------------------------------------------------------------------------------

    @property
    def time(self) -> float:
        """Reality's time, seconds."""
        return self.world.time

    def run_until(self, time: float) -> None:
        """Step until reality's time reaches ``time`` (to the nearest step)."""
        self.world.run_until(time)
        self._observe()
        self._appear()
        self._turn_balls()

    def step(self) -> None:
        """One step of ``dt`` with reality's drag, spin, throws and slip."""
        self.world.step(1)
        self._observe()
        self._appear()

    def _before_step(self, world: World) -> None:
        """The step hook: what the last step did, then this step's events and forces."""
        self._observe()
        self._appear()
        dt = self.dt
        if self._slip > 0 and world.steps % self._slip_every == 0:
            assert self._rng is not None
            n = self._rng.standard_normal(3)
            self._noise = (float(n[0]), float(n[1]), float(n[2]))
            self._drive()
        decay = 1.0 - math.exp(-dt / SPIN_TIME)
        for b in self._balls:
            if not b.present:
                continue
            vx, vy = world.velocity(b.name)
            speed = math.hypot(vx, vy)
            # Drag, and the share of the decaying slip the linear velocity takes.
            ax = -b.drag * speed * vx
            ay = -b.drag * speed * vy
            if b.ux or b.uy:
                dux, duy = b.ux * decay, b.uy * decay
                b.ux -= dux
                b.uy -= duy
                ax += ROLLING_SHARE * dux / dt
                ay += ROLLING_SHARE * duy / dt
                if abs(b.ux) + abs(b.uy) < 1e-9:
                    b.ux = b.uy = 0.0
            if ax or ay:
                world.apply_force(b.name, (b.mass * ax, b.mass * ay))
            self._expected.append((b, vx + ax * dt, vy + ay * dt))

    def _observe(self) -> None:
        """Take what the last step did: bounces feed the slip, rolling turns the balls."""
        if not self._expected:
            return
        dt = self.dt
        for b, ex, ey in self._expected:
            vx, vy = self.world.velocity(b.name)
            dx, dy = vx - ex, vy - ey
            if b.spin > 0 and math.hypot(dx, dy) > b.threshold:
                b.ux -= b.spin * dx
                b.uy -= b.spin * dy
            # The ball turns with its spin velocity (linear plus slip).
            sx, sy = vx + b.ux, vy + b.uy
            k = dt / b.record.radius
            rx, ry, rz = b.roll
            b.roll = (rx - sy * k, ry + sx * k, rz)
        self._expected.clear()

    def _appear(self) -> None:
        """Put the objects whose time has come into the world (before a step)."""
        for b in self._balls:
            if not b.present and b.appear_step is not None \
                    and self.world.steps >= b.appear_step:
                self.world.add_ball(b.record)
                b.present = True

    def _turn_balls(self) -> None:
        for b in self._balls:
            if b.roll != (0.0, 0.0, 0.0):
                assert b.orientation is not None
                b.orientation = rotation_exp(b.roll) @ b.orientation
                b.roll = (0.0, 0.0, 0.0)

    # -- state -----------------------------------------------------------------------------

    @property
    def names(self) -> tuple[str, ...]:
        """The balls of reality, present or not."""
        return tuple(b.name for b in self._balls)

    def present(self, name: str) -> bool:
        """Whether the object has appeared."""
        return self._ball(name).present

    def _ball(self, name: str) -> _Ball:
        for b in self._balls:
            if b.name == name:
                return b
        raise KeyError(name)

    def position(self, name: str) -> Vec2:
        """A ball's or the robot's ``(x, y)``."""
        return self.world.position(name)

    def velocity(self, name: str) -> Vec2:
        """A ball's or the robot's ``(vx, vy)``."""
        return self.world.velocity(name)

    def slip(self, name: str) -> Vec2:
        """A ball's slip velocity (spin minus linear), m/s."""
        b = self._ball(name)
        return (b.ux, b.uy)

    def orientation(self, name: str) -> np.ndarray:
        """A ball's 3D orientation (body-to-world rotation) from its rolling."""
        self._turn_balls()
        o = self._ball(name).orientation
        assert o is not None
        return o.copy()

    def state(self) -> WorldState:
        """The present bodies, for rendering."""
        return self.world.snapshot()

    def robot_state(self) -> RobotState | None:
        """The true robot, or None."""
        if self._robot is None:
            return None
        body = self.world.body(self._robot.name)
        p, v = body.position, body.velocity
        return RobotState((float(p[0]), float(p[1])), float(body.angle),
                          (float(v[0]), float(v[1])), float(body.angular_velocity))
