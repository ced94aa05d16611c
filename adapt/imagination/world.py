"""The physics world: a pymunk 7 space built from a :class:`SceneSpec`.

The physics is 2D in the floor plane ``(x, y)`` (seen from above, so pymunk's
gravity is zero) and steps with a fixed ``dt`` (default 1/240 s).  It is
deterministic: the same scene, state and commands give the same trajectory.

Modelling choices, all inside pymunk's C solver so a step stays cheap:

* **Restitution and friction** are pymunk's: a contact's restitution and
  friction are the *products* of the two shapes' values.
* **Rolling resistance** of a ball is a "top-down friction" joint: a
  :class:`pymunk.PivotJoint` between the static body and the ball's centre
  with ``max_bias = 0`` and ``max_force = c m g``.  It removes at most
  ``c g dt`` of speed per step and never reverses the motion: a ball rolling
  at ``v`` stops after ``v**2 / (2 c g)`` metres.  There is no global damping.
* **The robot** is velocity-controlled: a kinematic control body moves at the
  commanded velocity (clipped to ``max_speed``) and a pivot joint with
  ``max_force = m * max_accel`` drags the robot after it, so the robot never
  accelerates faster than ``max_accel``.

Forks for prediction rebuild a fresh space from a :class:`WorldState`
snapshot; that is about four times faster than ``Space.copy()`` and never
touches the original world.

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> scene = SceneSpec(balls=(Ball("ball", radius=0.1, velocity=(1.0, 0.0)),),
...                   walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
>>> world = World(scene)
>>> world.run(1.0)
>>> [(c.surface, round(c.time, 2)) for c in world.contacts]
[('east', 0.9)]
>>> round(world.snapshot().body("ball").velocity[0], 3)
-0.8
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import pymunk

from adapt.errors import ImaginationError
from adapt.imagination.scene import Ball, RobotSpec, SceneSpec, Vec2

__all__ = ["BodyState", "WorldState", "Contact", "World"]

#: pymunk collision types.
BALL_TYPE = 1
STATIC_TYPE = 2
ROBOT_TYPE = 3

#: Penetration pymunk tolerates, in metres (pymunk's default of 0.1 is meant
#: for pixels).
COLLISION_SLOP = 5e-4


@dataclass(frozen=True, slots=True)
class BodyState:
    """Pose and velocity of one moving body (a ball or the robot)."""

    name: str
    position: Vec2
    velocity: Vec2
    angle: float = 0.0
    angular_velocity: float = 0.0


@dataclass(frozen=True, slots=True)
class WorldState:
    """A snapshot of everything that changes in a :class:`World`.

    ``command`` is the robot's commanded ``(vx, vy, omega)``.
    """

    time: float
    step: int
    bodies: tuple[BodyState, ...]
    command: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def body(self, name: str) -> BodyState:
        """The state of the body called ``name``."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise ImaginationError(
            f"no body called {name!r} in the state; bodies: {[b.name for b in self.bodies]}"
        )

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the bodies, in scene order (balls, then the robot)."""
        return tuple(b.name for b in self.bodies)


@dataclass(frozen=True, slots=True)
class Contact:
    """A ball started touching a surface.

    ``time`` is the end of the step in which the contact began, ``position``
    the contact point on the floor plane, ``surface`` the name of what was hit
    (a wall, an obstacle, another ball or the robot) and ``speed`` the ball's
    speed at that moment.
    """

    time: float
    ball: str
    surface: str
    position: Vec2
    speed: float


class World:
    """A running physics world built from a scene.

    Parameters
    ----------
    scene : SceneSpec
        What to build.
    dt : float, optional
        Fixed time step in seconds; default ``scene.dt`` (1/240 s).
    seed : int, optional
        Default seed of the imagination's random draws (ensembles use it when
        given none).  The physics itself has no randomness.
    state : WorldState, optional
        Start from this snapshot instead of the scene's initial state.
    record_contacts : bool
        Keep a log of :class:`Contact` events in :attr:`contacts`.
    """

    def __init__(
        self,
        scene: SceneSpec,
        *,
        dt: float | None = None,
        seed: int | None = None,
        state: WorldState | None = None,
        record_contacts: bool = True,
    ) -> None:
        self.scene = scene
        self.dt = float(scene.dt if dt is None else dt)
        if not math.isfinite(self.dt) or self.dt <= 0:
            raise ImaginationError(f"dt: expected a positive number of seconds, got {dt!r}")
        self.seed = seed
        self.contacts: list[Contact] = []
        self._steps = 0
        self._time0 = 0.0
        self._command = (0.0, 0.0, 0.0)
        self._bodies: dict[str, pymunk.Body] = {}
        self._names: dict[pymunk.Shape, str] = {}
        self._control: pymunk.Body | None = None
        self._record = record_contacts
        self.space = self._build()
        if state is not None:
            self.set_state(state)

    # -- construction -------------------------------------------------------

    def _build(self) -> pymunk.Space:
        scene = self.scene
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        space.collision_slop = COLLISION_SLOP
        static = space.static_body
        shapes: list[pymunk.Shape] = []
        for wall in scene.walls:
            seg = pymunk.Segment(static, wall.start, wall.end, 0.0)
            seg.elasticity = wall.restitution
            seg.friction = wall.friction
            seg.collision_type = STATIC_TYPE
            self._names[seg] = wall.name
            shapes.append(seg)
        for obstacle in scene.obstacles:
            poly = pymunk.Poly(static, obstacle.polygon, radius=0.0)
            poly.elasticity = obstacle.restitution
            poly.friction = obstacle.friction
            poly.collision_type = STATIC_TYPE
            self._names[poly] = obstacle.name
            shapes.append(poly)
        space.add(*shapes)
        for ball in scene.balls:
            self._add_ball(space, ball)
        if scene.robot is not None:
            self._add_robot(space, scene.robot)
        if self._record:
            space.on_collision(BALL_TYPE, None, begin=self._on_begin)
        return space

    def _add_ball(self, space: pymunk.Space, ball: Ball) -> None:
        body = pymunk.Body(ball.mass, pymunk.moment_for_circle(ball.mass, 0.0, ball.radius))
        body.position = ball.position
        body.velocity = ball.velocity
        shape = pymunk.Circle(body, ball.radius)
        shape.elasticity = ball.restitution
        shape.friction = ball.friction
        shape.collision_type = BALL_TYPE
        space.add(body, shape)
        if ball.rolling_resistance > 0:
            rr = pymunk.PivotJoint(space.static_body, body, (0.0, 0.0), (0.0, 0.0))
            rr.max_bias = 0.0
            rr.max_force = ball.rolling_resistance * ball.mass * self.scene.gravity
            # The same resistance against spinning about the vertical axis.
            spin = pymunk.GearJoint(space.static_body, body, 0.0, 1.0)
            spin.max_bias = 0.0
            spin.max_force = rr.max_force * ball.radius
            space.add(rr, spin)
        self._bodies[ball.name] = body
        self._names[shape] = ball.name

    def _add_robot(self, space: pymunk.Space, robot: RobotSpec) -> None:
        if robot.shape == "disc":
            moment = pymunk.moment_for_circle(robot.mass, 0.0, robot.radius)
        else:
            moment = pymunk.moment_for_box(robot.mass, robot.size)
        body = pymunk.Body(robot.mass, moment)
        body.position = robot.position
        body.angle = math.radians(robot.heading_deg)
        if robot.shape == "disc":
            shape: pymunk.Shape = pymunk.Circle(body, robot.radius)
        else:
            shape = pymunk.Poly(body, robot.outline())
        shape.elasticity = 0.5
        shape.friction = 0.5
        shape.collision_type = ROBOT_TYPE
        control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        control.position = robot.position
        drive = pymunk.PivotJoint(control, body, (0.0, 0.0), (0.0, 0.0))
        drive.max_bias = 0.0
        drive.max_force = robot.mass * robot.max_accel
        turn = pymunk.GearJoint(control, body, 0.0, 1.0)
        turn.max_bias = 0.0
        turn.max_force = robot.mass * robot.max_accel * max(robot.radius, max(robot.size))
        space.add(body, shape, control, drive, turn)
        self._bodies[robot.name] = body
        self._names[shape] = robot.name
        self._control = control

    def _on_begin(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        a, b = arbiter.shapes
        if a.collision_type != BALL_TYPE:
            a, b = b, a
        ball = self._names.get(a)
        surface = self._names.get(b)
        if ball is None or surface is None:
            return
        time = self._time0 + (self._steps + 1) * self.dt
        if self.contacts:
            last = self.contacts[-1]
            if last.time == time and last.ball == ball and last.surface == surface:
                return
        points = arbiter.contact_point_set.points
        if points:
            p = points[0].point_a if arbiter.shapes[0] is a else points[0].point_b
            pos = (float(p[0]), float(p[1]))
        else:
            pos = (float(a.body.position[0]), float(a.body.position[1]))  # type: ignore[union-attr]
        v = a.body.velocity  # type: ignore[union-attr]
        self.contacts.append(Contact(time, ball, surface, pos, float(math.hypot(v[0], v[1]))))

    # -- time -----------------------------------------------------------------

    @property
    def time(self) -> float:
        """Simulated time in seconds."""
        return self._time0 + self._steps * self.dt

    @property
    def steps(self) -> int:
        """Steps taken since the state's time origin."""
        return self._steps

    def step(self, n: int = 1) -> None:
        """Advance ``n`` fixed steps of ``dt``."""
        space_step = self.space.step
        dt = self.dt
        if self._record:
            for _ in range(n):
                space_step(dt)
                self._steps += 1
        else:
            for _ in range(n):
                space_step(dt)
            self._steps += n

    def run(self, seconds: float) -> None:
        """Advance by ``seconds`` (rounded to whole steps)."""
        if seconds < 0:
            raise ImaginationError(f"cannot run backwards ({seconds} s)")
        self.step(int(round(seconds / self.dt)))

    def run_until(self, time: float) -> None:
        """Advance until :attr:`time` reaches ``time`` (rounded to whole steps)."""
        self.run(max(0.0, time - self.time))

    # -- state ----------------------------------------------------------------

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the moving bodies (balls, then the robot)."""
        return tuple(self._bodies)

    def body(self, name: str) -> pymunk.Body:
        """The pymunk body of a ball or the robot (for read access)."""
        try:
            return self._bodies[name]
        except KeyError:
            raise ImaginationError(
                f"no moving body called {name!r}; bodies: {list(self._bodies)}"
            ) from None

    def position(self, name: str) -> Vec2:
        """Current ``(x, y)`` of a body."""
        p = self.body(name).position
        return (float(p[0]), float(p[1]))

    def velocity(self, name: str) -> Vec2:
        """Current ``(vx, vy)`` of a body."""
        v = self.body(name).velocity
        return (float(v[0]), float(v[1]))

    def snapshot(self) -> WorldState:
        """A frozen copy of the current state."""
        bodies = []
        for name, body in self._bodies.items():
            p, v = body.position, body.velocity
            bodies.append(
                BodyState(
                    name,
                    (float(p[0]), float(p[1])),
                    (float(v[0]), float(v[1])),
                    float(body.angle),
                    float(body.angular_velocity),
                )
            )
        return WorldState(self.time, self._steps, tuple(bodies), self._command)

    def set_state(self, state: WorldState) -> None:
        """Put the bodies into a snapshot's state (positions, velocities, time).

        Bodies the snapshot does not mention keep their state; a body it names
        that this world lacks is an error.
        """
        for b in state.bodies:
            body = self.body(b.name)
            body.position = b.position
            body.velocity = b.velocity
            body.angle = b.angle
            body.angular_velocity = b.angular_velocity
            self.space.reindex_shapes_for_body(body)
        self._time0 = state.time - state.step * self.dt
        self._steps = state.step
        self.command_robot(state.command[:2], state.command[2])
        if self._control is not None and self.scene.robot is not None:
            robot = self._bodies[self.scene.robot.name]
            self._control.position = robot.position
            self._control.angle = robot.angle

    def fork(
        self, state: WorldState | None = None, *, scene: SceneSpec | None = None,
        record_contacts: bool = True,
    ) -> "World":
        """A new, independent world in ``state`` (default: the current one).

        ``scene`` swaps the scene (for example other ball parameters); its
        moving bodies must carry the same names.  The original world is not
        touched.

        Examples
        --------
        >>> from adapt.imagination.scene import Ball, SceneSpec
        >>> w = World(SceneSpec(balls=(Ball("b", velocity=(1.0, 0.0)),)))
        >>> f = w.fork()
        >>> f.run(1.0)
        >>> w.position("b"), round(f.position("b")[0], 6)
        ((0.0, 0.0), 1.0)
        """
        return World(
            self.scene if scene is None else scene,
            dt=self.dt,
            seed=self.seed,
            state=self.snapshot() if state is None else state,
            record_contacts=record_contacts,
        )

    # -- actions --------------------------------------------------------------

    def apply_force(self, name: str, force: Sequence[float]) -> None:
        """Push a body's centre with ``force`` newtons during the next step only.

        pymunk clears forces after every step, so a spring correction must be
        applied before each step.
        """
        body = self.body(name)
        body.apply_force_at_world_point((float(force[0]), float(force[1])), body.position)

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Command the robot's velocity (m/s, clipped to ``max_speed``) and turn rate (rad/s)."""
        vx, vy = float(velocity[0]), float(velocity[1])
        if self.scene.robot is None or self._control is None:
            if vx or vy or angular_velocity:
                raise ImaginationError("the scene has no robot to command")
            self._command = (0.0, 0.0, 0.0)
            return
        speed = math.hypot(vx, vy)
        limit = self.scene.robot.max_speed
        if speed > limit:
            vx, vy = vx * limit / speed, vy * limit / speed
        self._command = (vx, vy, float(angular_velocity))
        self._control.velocity = (vx, vy)
        self._control.angular_velocity = float(angular_velocity)
