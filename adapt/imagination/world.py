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
* **Drag** (a ball's ``drag``, ``d``): the rolling resistance's joint
  resists with ``(c g + d v**2) m`` instead, its force following the speed
  every :data:`DRAG_EVERY` steps (counted from the world's step 0, so a
  world run in one call and step by step still agree).
* **Spin** (a ball with ``floor_friction``): a solid sphere's spin is a
  second velocity ``w``, the one it would roll at, carried by a body of mass
  ``2/5 m`` (the sphere's ``I / r**2``) that touches nothing.  A pivot joint
  with ``max_bias = 0`` and ``max_force = mu m g`` between the ball and that
  body is the floor's sliding friction: while the slip ``w - v`` is not zero
  it pulls the velocity towards the spin at ``mu g`` and the spin towards the
  velocity at ``5/2 mu g`` until they agree, and then the two roll on as one
  (the rolling resistance acts on the spin, ``7/5 c m g``, so a rolling ball
  still slows at ``c g``).  A bounce changes the velocity, not the spin, but
  for the friction of the surface hit: its contact is at the height of the
  ball's centre, where the spin makes the ball's surface slide vertically,
  and friction ``mu_pair`` times the normal impulse ``J`` takes up to
  ``5/2 mu_pair J / m`` of the spin's normal part, at most the ``5/7`` of it
  at which the contact sticks.  A ball rolling head-on at ``V`` into a wall
  of restitution ``e`` with no friction thus leaves at ``e V`` and rolls on
  at ``(5 e - 2) V / 7`` back from the wall (forwards, for ``e < 2/5``); with
  a sticking contact at ``(5 e - 4/7) V / 7``.  The hop a sticking contact
  gives (its vertical impulse) is not modelled: the floor plane is 2D.
* **The robot** is velocity-controlled: a kinematic control body moves at the
  commanded velocity (clipped to ``max_speed``) and a pivot joint with
  ``max_force = m * max_accel`` drags the robot after it, so the robot never
  accelerates faster than ``max_accel``.

Forks for prediction rebuild a fresh space from a :class:`WorldState`
snapshot; that is about four times faster than ``Space.copy()`` and never
touches the original world.

Fast bodies do not tunnel.  pymunk has no continuous collision detection and
a wall has no thickness, so a ball that moves more than its radius in one step
can pass through it.  Each step is therefore divided into ``k`` equal
sub-steps, with ``k`` the smallest number for which no ball (or the robot)
moves more than ``TRAVEL_FRACTION`` (half) of its radius per sub-step.  ``k``
is a function of the state at the start of the step only, so a world run in
one call or step by step follows the same path.  At ordinary speeds ``k = 1``,
and a bound on the speeds the world can reach shows it once (again after a
force, a new state, ball or command) instead of every step.  A step that would need more than ``MAX_SUBSTEPS``
sub-steps is an :class:`~adapt.errors.ImaginationError` (use a smaller ``dt``).

Work is bounded: one call of :meth:`World.step`, :meth:`World.run` or
:meth:`World.run_until` takes at most ``MAX_STEPS`` steps; a longer request is
an error that says so, never a hang.

Hooks (:meth:`World.add_step_hook`) are called before every step, so a
correction force (``apply_force`` lasts one step) acts on every step of
``run`` and ``run_until``.  Balls can be added and removed at run time
(:meth:`World.add_ball`, :meth:`World.remove_ball`); snapshots, forks and
prediction include them, and :attr:`World.balls` gives their records to the
renderer.

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

import copy
import math
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import pymunk

from adapt.errors import ImaginationError
from adapt.imagination.scene import MAX_DT, MIN_DT, Ball, RobotShape, RobotSpec, SceneSpec, Vec2

__all__ = [
    "BodyState",
    "WorldState",
    "Contact",
    "World",
    "StepHook",
    "MAX_STEPS",
    "MAX_SUBSTEPS",
    "TRAVEL_FRACTION",
]

#: Most steps one call of ``step``, ``run`` or ``run_until`` takes (at the
#: default dt of 1/240 s: 4,167 s, over an hour of simulated time).
MAX_STEPS = 1_000_000
#: Most sub-steps a step is divided into to keep fast bodies from tunnelling.
MAX_SUBSTEPS = 64
#: A body moves at most this fraction of its radius per sub-step.
TRAVEL_FRACTION = 0.5

#: A function called with the world before every physics step.
StepHook = Callable[["World"], None]

#: pymunk collision types.
BALL_TYPE = 1
STATIC_TYPE = 2
ROBOT_TYPE = 3

#: Penetration pymunk tolerates, in metres (pymunk's default of 0.1 is meant
#: for pixels).
COLLISION_SLOP = 5e-4

#: The robot's shape restitution (a contact's is the product with the ball's).
ROBOT_RESTITUTION = 0.5

#: Steps between two updates of a drag's force (1/60 s at the default ``dt``).
DRAG_EVERY = 4

#: A solid sphere's ``I / (m r**2)``: the mass its spin velocity carries, per unit of its mass.
SPIN_MASS = 2.0 / 5.0
#: The share of the spin's normal part a sticking wall contact takes (``(5/2) / (1 + 5/2)``).
STICK = 5.0 / 7.0


@dataclass(frozen=True, slots=True)
class BodyState:
    """Pose and velocity of one moving body (a ball or the robot).

    ``slip`` is a spinning ball's spin velocity minus its velocity (zero while
    it rolls; always zero for a ball without ``floor_friction`` and for the
    robot).
    """

    name: str
    position: Vec2
    velocity: Vec2
    angle: float = 0.0
    angular_velocity: float = 0.0
    slip: Vec2 = (0.0, 0.0)


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
    ball_collisions : bool
        Whether balls collide with each other; ``False`` makes each ball a
        copy that runs as if alone in the scene (many rollouts of one ball,
        differently started, in one world: cheaper than as many worlds).

    Attributes
    ----------
    scene : SceneSpec
        The scene, including the balls added at run time (and without those
        removed).
    """

    def __init__(
        self,
        scene: SceneSpec,
        *,
        dt: float | None = None,
        seed: int | None = None,
        state: WorldState | None = None,
        record_contacts: bool = True,
        ball_collisions: bool = True,
    ) -> None:
        self.scene = scene
        value = scene.dt if dt is None else dt
        try:
            self.dt = float(value)
        except (TypeError, ValueError):
            raise ImaginationError(f"dt: expected a number of seconds, got {dt!r}") from None
        if not (math.isfinite(self.dt) and MIN_DT <= self.dt <= MAX_DT):
            raise ImaginationError(
                f"dt: expected a number of seconds from {MIN_DT:g} to {MAX_DT:g}, got {dt!r}"
            )
        self.seed = seed
        self.contacts: list[Contact] = []
        self._steps = 0
        self._time0 = 0.0
        self._command = (0.0, 0.0, 0.0)
        self._balls: dict[str, pymunk.Body] = {}
        self._parts: dict[str, tuple[pymunk.Shape, tuple[pymunk.Constraint, ...]]] = {}
        # a spinning ball's spin body and the floor's friction joint (see the module docstring)
        self._spins: dict[str, tuple[pymunk.Body, pymunk.PivotJoint]] = {}
        self._spin_handlers = False
        # balls with drag: their resistance joint, its force at rest per (m/s)^2, and at rest
        self._drag: dict[str, tuple[pymunk.Constraint, float, float]] = {}
        # a spinning ball's contacts under way: velocity before, normal, friction
        self._touching: dict[tuple[pymunk.Shape, pymunk.Shape],
                             tuple[float, float, float, float, float]] = {}
        self._radius: dict[str, float] = {}  # what a body's travel per sub-step is measured by
        self._robot: pymunk.Body | None = None
        self._names: dict[pymunk.Shape, str] = {}
        self._control: pymunk.Body | None = None
        self._forces: dict[str, tuple[float, float]] = {}
        self._hooks: list[StepHook] = []
        # True once a bound showed that no step needs sub-steps until the next
        # outside change (a force, a state, a ball, a command): see _bound_substeps.
        self._calm = False
        self._record = record_contacts
        self._ball_filter = None if ball_collisions else pymunk.ShapeFilter(group=BALL_TYPE)
        self.space = self._build()
        self._update_extremes()
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
        if self._ball_filter is not None:
            shape.filter = self._ball_filter
        space.add(body, shape)
        joints: tuple[pymunk.Constraint, ...] = ()
        rolling = body
        if ball.floor_friction is not None:
            rolling = pymunk.Body(SPIN_MASS * ball.mass, SPIN_MASS * ball.mass * ball.radius**2)
            rolling.position = ball.position
            rolling.velocity = ball.velocity
            floor = pymunk.PivotJoint(body, rolling, (0.0, 0.0), (0.0, 0.0))
            floor.max_bias = 0.0
            floor.max_force = ball.floor_friction * ball.mass * self.scene.gravity
            space.add(rolling, floor)
            self._spins[ball.name] = (rolling, floor)
            if not self._spin_handlers:
                for other in (STATIC_TYPE, ROBOT_TYPE):
                    space.on_collision(BALL_TYPE, other, begin=self._on_touch,
                                       separate=self._on_part)
                self._spin_handlers = True
        if ball.rolling_resistance > 0 or ball.drag > 0:
            rr = pymunk.PivotJoint(space.static_body, rolling, (0.0, 0.0), (0.0, 0.0))
            rr.max_bias = 0.0
            rr.max_force = self._rolling_force(ball)
            # The same resistance against spinning about the vertical axis.
            spin = pymunk.GearJoint(space.static_body, body, 0.0, 1.0)
            spin.max_bias = 0.0
            spin.max_force = ball.rolling_resistance * ball.mass * self.scene.gravity * ball.radius
            space.add(rr, spin)
            joints = (rr, spin)
            self._set_drag(ball, rr)
        self._balls[ball.name] = body
        if ball.name in self._drag:
            self._update_drag()
        self._parts[ball.name] = (shape, joints)
        self._radius[ball.name] = ball.radius
        self._names[shape] = ball.name

    def _set_drag(self, ball: Ball, rr: pymunk.Constraint) -> None:
        if ball.drag > 0:
            share = (1.0 + SPIN_MASS) if ball.floor_friction is not None else 1.0
            self._drag[ball.name] = (rr, self._rolling_force(ball), ball.drag * ball.mass * share)
            self._update_drag()
        else:
            self._drag.pop(ball.name, None)

    def _update_drag(self) -> None:
        """Each drag's force for the speed now."""
        for name, (rr, rest, per) in self._drag.items():
            body = self._balls.get(name)
            if body is not None:  # (not yet while it is being added)
                vx, vy = body.velocity
                rr.max_force = rest + per * (vx * vx + vy * vy)

    def _rolling_force(self, ball: Ball) -> float:
        """The rolling resistance's largest force: ``c m g``, on the spin of a spinning ball
        ``c (m + 2/5 m) g`` (ball and spin roll together)."""
        mass = ball.mass * (1.0 + SPIN_MASS) if ball.floor_friction is not None else ball.mass
        return ball.rolling_resistance * mass * self.scene.gravity

    def _on_touch(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        """A spinning ball touches something: keep its velocity and the contact's normal and
        friction until they part (a ball that rests against a wall costs nothing more)."""
        ball, other = arbiter.shapes
        if ball in self._names and self._names[ball] in self._spins:
            v = ball.body.velocity  # type: ignore[union-attr]
            n = arbiter.normal
            self._touching[(ball, other)] = (float(v[0]), float(v[1]), float(n[0]), float(n[1]),
                                             float(arbiter.friction))

    def _on_part(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        """A spinning ball's contact ends: the surface's friction takes spin for the impulse
        it gave (the change of the normal velocity), see the module docstring."""
        ball, other = arbiter.shapes
        touch = self._touching.pop((ball, other), None)
        name = self._names.get(ball)
        spin = self._spins.get(name) if name is not None else None
        if touch is None or spin is None or ball.body is None:
            return  # (or the ball has just been taken out of the world)
        vx0, vy0, nx, ny, mu = touch
        v = ball.body.velocity  # type: ignore[union-attr]
        push = abs((v[0] - vx0) * nx + (v[1] - vy0) * ny)  # the normal impulse over the mass
        if push <= 0.0 or mu <= 0.0:
            return
        rolling = spin[0]
        w = rolling.velocity
        wn = w[0] * nx + w[1] * ny  # the spin's normal part
        take = math.copysign(min(2.5 * mu * push, STICK * abs(wn)), wn)
        rolling.velocity = (w[0] - take * nx, w[1] - take * ny)

    def _add_robot(self, space: pymunk.Space, robot: RobotSpec) -> None:
        if robot.shape is RobotShape.DISC:
            moment = pymunk.moment_for_circle(robot.mass, 0.0, robot.radius)
        else:
            moment = pymunk.moment_for_box(robot.mass, robot.size)
        body = pymunk.Body(robot.mass, moment)
        body.position = robot.position
        body.angle = math.radians(robot.heading_deg)
        if robot.shape is RobotShape.DISC:
            shape: pymunk.Shape = pymunk.Circle(body, robot.radius)
        else:
            shape = pymunk.Poly(body, robot.outline())
        shape.elasticity = ROBOT_RESTITUTION
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
        self._robot = body
        self._radius[robot.name] = robot.inner_radius  # how far it may move per sub-step
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

    # -- balls at run time ------------------------------------------------------

    @property
    def balls(self) -> tuple[Ball, ...]:
        """The records of the balls in the world now (pass them to
        :meth:`Renderer.render <adapt.imagination.render.Renderer.render>`)."""
        return self.scene.balls

    def add_ball(
        self,
        ball: Ball,
        position: Sequence[float] | None = None,
        velocity: Sequence[float] | None = None,
    ) -> None:
        """Put a new ball into the running world (for example when perception
        first sees it).

        ``position`` and ``velocity`` (default: the record's) are where it is
        now; its name must be new to the scene.  It takes part from the next
        step, and :attr:`scene`, :attr:`balls`, snapshots and forks include it.

        Examples
        --------
        >>> w = World(SceneSpec())
        >>> w.run(1.0)
        >>> w.add_ball(Ball("thrown", radius=0.05), position=(0.0, 0.0), velocity=(2.0, 0.0))
        >>> w.run(0.5)
        >>> [round(c, 9) for c in w.position("thrown")], w.names, round(w.time, 6)
        ([1.0, 0.0], ('thrown',), 1.5)
        """
        if not isinstance(ball, Ball):
            raise ImaginationError(f"ball: expected a Ball record, got {type(ball).__name__}")
        changes: dict[str, Any] = {}
        if position is not None:
            changes["position"] = tuple(position)
        if velocity is not None:
            changes["velocity"] = tuple(velocity)
        spec = replace(ball, **changes) if changes else ball
        self.scene = replace(self.scene, balls=self.scene.balls + (spec,))
        self._add_ball(self.space, spec)
        self._update_extremes()
        self._calm = False

    def remove_ball(self, name: str) -> None:
        """Take the ball called ``name`` out of the world (its past contacts stay
        in :attr:`contacts`)."""
        if name not in self._balls:
            raise ImaginationError(
                f"no ball called {name!r} in the world; balls: {list(self._balls)}"
            )
        body = self._balls.pop(name)
        shape, joints = self._parts.pop(name)
        self.space.remove(*joints, shape, body)
        self._drag.pop(name, None)
        spin = self._spins.pop(name, None)
        if spin is not None:
            self.space.remove(spin[1], spin[0])
        del self._names[shape]
        del self._radius[name]
        self._forces.pop(name, None)
        self.scene = replace(self.scene, balls=tuple(b for b in self.scene.balls if b.name != name))
        self._update_extremes()
        self._calm = False

    def set_ball_parameters(self, name: str, **values: float | None) -> None:
        """Give a ball new ``restitution``, ``friction``, ``rolling_resistance``,
        ``mass`` or ``floor_friction`` in place (cheaper than building a world;
        ensembles reuse one world this way).  Its position, velocity and slip are
        kept.

        Examples
        --------
        >>> w = World(SceneSpec(balls=(Ball("b", restitution=0.5),)))
        >>> w.set_ball_parameters("b", restitution=0.9, rolling_resistance=0.02)
        >>> w.scene.balls[0].restitution, w.scene.balls[0].rolling_resistance
        (0.9, 0.02)
        """
        if name not in self._balls:
            raise ImaginationError(f"no ball called {name!r} in the world; balls: {list(self._balls)}")
        unknown = set(values) - {"restitution", "friction", "rolling_resistance", "mass",
                                 "floor_friction", "drag"}
        if unknown:
            raise ImaginationError(f"cannot set {sorted(unknown)} of a ball; expected restitution, "
                                   "friction, rolling_resistance, mass, floor_friction or drag")
        old = next(b for b in self.scene.balls if b.name == name)
        new = old.with_parameters(**values)  # checks the values
        shape, joints = self._parts[name]
        if (new.rolling_resistance > 0 or new.drag > 0) != bool(joints) or \
                (new.floor_friction is None) != (old.floor_friction is None):
            state = next(b for b in self.snapshot().bodies if b.name == name)
            self.remove_ball(name)
            self.add_ball(new, position=state.position, velocity=state.velocity)
            if name in self._spins:
                vx, vy = state.velocity
                self._spins[name][0].velocity = (vx + state.slip[0], vy + state.slip[1])
            return
        body = self._balls[name]
        shape.elasticity = new.restitution
        shape.friction = new.friction
        spin_parts = self._spins.get(name)
        if new.mass != old.mass:
            body.mass = new.mass
            body.moment = pymunk.moment_for_circle(new.mass, 0.0, new.radius)
            if spin_parts is not None:
                spin_parts[0].mass = SPIN_MASS * new.mass
                spin_parts[0].moment = SPIN_MASS * new.mass * new.radius**2
        if spin_parts is not None and new.floor_friction is not None:
            spin_parts[1].max_force = new.floor_friction * new.mass * self.scene.gravity
        if joints:
            rr, spin = joints
            rr.max_force = self._rolling_force(new)
            spin.max_force = new.rolling_resistance * new.mass * self.scene.gravity * new.radius
            self._set_drag(new, rr)
        # the same names, the same shapes: the scene's checks hold, so it is copied, not rebuilt
        scene = copy.copy(self.scene)
        object.__setattr__(scene, "balls", tuple(new if b.name == name else b
                                                 for b in self.scene.balls))
        self.scene = scene
        self._update_extremes()
        self._calm = False

    # -- hooks ------------------------------------------------------------------

    def add_step_hook(self, hook: StepHook) -> StepHook:
        """Call ``hook(world)`` before every physics step from now on.

        A hook may apply forces (they act during that step), command the robot,
        or add and remove balls.  Hooks run in the order they were added; forks
        start without hooks.  Returns ``hook``, so it can be used as a
        decorator.  A world without hooks pays nothing for them.

        Examples
        --------
        >>> w = World(SceneSpec(balls=(Ball("b", mass=2.0),)))
        >>> push = w.add_step_hook(lambda world: world.apply_force("b", (4.0, 0.0)))
        >>> w.run(1.0)  # 2 m/s^2 on every step
        >>> round(w.velocity("b")[0], 9)
        2.0
        """
        if not callable(hook):
            raise ImaginationError(f"hook: expected a callable, got {hook!r}")
        self._hooks.append(hook)
        return hook

    def remove_step_hook(self, hook: StepHook) -> None:
        """Stop calling ``hook``."""
        try:
            self._hooks.remove(hook)
        except ValueError:
            raise ImaginationError(f"hook: {hook!r} is not registered") from None

    @property
    def step_hooks(self) -> tuple[StepHook, ...]:
        """The hooks called before every step, in order."""
        return tuple(self._hooks)

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
        """Advance ``n`` fixed steps of ``dt`` (at most :data:`MAX_STEPS`)."""
        if isinstance(n, float) and float(n).is_integer():
            n = int(n)
        if isinstance(n, bool) or not isinstance(n, int):
            raise ImaginationError(f"steps: expected a whole number, got {n!r}")
        if not 0 <= n <= MAX_STEPS:
            raise ImaginationError(
                f"steps: expected 0 to {MAX_STEPS:,} steps per call, got {n:,}"
            )
        if not self._drag:
            self._step(n)
            return
        while n > 0:  # a drag's force follows the speed every DRAG_EVERY steps
            if self._steps % DRAG_EVERY == 0:
                self._update_drag()
            chunk = min(n, DRAG_EVERY - self._steps % DRAG_EVERY)
            self._step(chunk)
            n -= chunk

    def _step(self, n: int) -> None:
        if n == 0:
            return
        if self._hooks:
            for _ in range(n):
                for hook in tuple(self._hooks):
                    hook(self)
                self._advance(self._substeps())
            return
        if self._forces:  # a force acts in the first step only
            self._advance(self._substeps())
            n -= 1
        if not self._calm:
            if self._bound_substeps() > 1:
                for _ in range(n):
                    self._advance(self._substeps())
                return
            self._calm = True
        # No body can need sub-steps during this call: plain pymunk steps.
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

    def _advance(self, k: int) -> None:
        """One step of ``dt`` in ``k`` sub-steps; forces last the whole step."""
        if k == 1:
            self.space.step(self.dt)
        else:
            h = self.dt / k
            for i in range(k):
                if i and self._forces:
                    for name, f in self._forces.items():
                        body = self.body(name)
                        body.apply_force_at_world_point(f, body.position)
                self.space.step(h)
        self._forces.clear()
        self._steps += 1

    def _substeps(self) -> int:
        """Sub-steps the next step needs, from the bodies' speeds now."""
        worst, who = 0.0, ""
        forces = self._forces
        for name, body in self._moving():
            vx, vy = body.velocity
            speed = math.hypot(vx, vy)
            if forces and name in forces:
                speed += math.hypot(*forces[name]) * self.dt / body.mass
            rate = speed / self._radius[name]
            if rate > worst:
                worst, who = rate, name
        k = math.ceil(worst * self.dt / TRAVEL_FRACTION - 1e-9)
        if k > MAX_SUBSTEPS:
            speed = worst * self._radius[who]
            raise ImaginationError(
                f"{who!r} moves at {speed:.4g} m/s, {speed * self.dt:.4g} m per step of "
                f"{self.dt:.4g} s: more than {MAX_SUBSTEPS} sub-steps can resolve without "
                "passing through walls; use a smaller dt"
            )
        return max(k, 1)

    def _moving(self) -> list[tuple[str, pymunk.Body]]:
        """(name, body) of the balls, then the robot."""
        items = list(self._balls.items())
        if self._robot is not None and self.scene.robot is not None:
            items.append((self.scene.robot.name, self._robot))
        return items

    def _bound_substeps(self) -> int:
        """Sub-steps some step of a call without hooks or pending forces may
        need, at most.

        No force acts then except rolling resistance (which slows), contacts
        (restitution at most 1) and the robot's drive.  A robot contact
        (restitution at most 0.5) sends a ball back at no more than
        ``0.5 v + 1.5 V``, with ``V`` a bound on the robot's speed, so a ball
        keeps below ``max(v, 3 V)``; contacts between balls only share energy.
        Hence no ball is faster than ``sqrt(2 (E + 4.5 V^2 M) / m_min)`` (``E``
        the balls' kinetic energy, spin included as it can turn into speed at a
        contact; ``M`` their mass), or, when balls pass through each other, than
        ``sqrt(E_i / m_i + 9 V^2)`` for each ball alone.  A margin of 20% covers
        pymunk's overlap correction.  (pymunk's ``kinetic_energy`` is ``m v^2 + I w^2``: twice
        the energy.)
        """
        twice = 0.0
        for body in self._balls.values():
            twice += body.kinetic_energy
        for rolling, _ in self._spins.values():  # spin can turn into speed
            twice += rolling.kinetic_energy
        rate = 0.0
        vr = 0.0
        robot = self._robot
        if robot is not None:
            spec = self.scene.robot
            assert spec is not None
            vr = (max(math.sqrt(robot.kinetic_energy / spec.mass), spec.max_speed)
                  + math.sqrt(twice / spec.mass))
            rate = vr / self._radius[spec.name]
        if self._balls and self._ball_filter is not None:
            # balls that pass through each other share no energy: each is bounded alone
            for name, body in self._balls.items():
                own = body.kinetic_energy
                if name in self._spins:
                    own += self._spins[name][0].kinetic_energy
                top = math.sqrt(own / body.mass + 9.0 * vr * vr)
                rate = max(rate, top / self._radius[name])
        elif self._balls:
            mass, light, small = self._ball_extremes
            top = math.sqrt((twice + 9.0 * vr * vr * mass) / light)
            rate = max(rate, top / small)
        return max(1, math.ceil(1.2 * rate * self.dt / TRAVEL_FRACTION - 1e-9))

    def _update_extremes(self) -> None:
        """Total mass, smallest mass and smallest radius of the balls."""
        balls = self.scene.balls
        self._ball_extremes = (sum(b.mass for b in balls), min(b.mass for b in balls),
                               min(b.radius for b in balls)) if balls else (0.0, 1.0, 1.0)

    def run(self, seconds: float) -> None:
        """Advance by ``seconds`` (rounded to whole steps; at most :data:`MAX_STEPS`)."""
        self.step(self._steps_for(seconds, "run"))

    def run_until(self, time: float) -> None:
        """Advance until :attr:`time` reaches ``time`` (rounded to whole steps;
        nothing if it is already past)."""
        try:
            t = float(time)
        except (TypeError, ValueError):
            raise ImaginationError(f"run_until: expected a time in seconds, got {time!r}") from None
        if not math.isfinite(t):
            raise ImaginationError(f"run_until: expected a finite time in seconds, got {time!r}")
        self.step(self._steps_for(max(0.0, t - self.time), "run_until"))

    def steps_for(self, seconds: float, what: str = "seconds") -> int:
        """The number of steps ``run(seconds)`` takes, checked against
        :data:`MAX_STEPS`; an error message starts with ``what``.

        Examples
        --------
        >>> w = World(SceneSpec(dt=0.01))
        >>> w.steps_for(2.0)
        200
        >>> w.steps_for(1e9, "--t")
        Traceback (most recent call last):
        ...
        adapt.errors.ImaginationError: --t: 1e+09 s is 100,000,000,000 steps of 0.01 s; a call takes at most 1,000,000 steps (10,000 s): run it in parts
        """
        return self._steps_for(seconds, what)

    def _steps_for(self, seconds: float, what: str) -> int:
        try:
            s = float(seconds)
        except (TypeError, ValueError):
            raise ImaginationError(f"{what}: expected a number of seconds, got {seconds!r}") from None
        if not math.isfinite(s) or s < 0:
            raise ImaginationError(
                f"{what}: expected a non-negative number of seconds, got {seconds!r}"
            )
        steps = s / self.dt
        if steps > MAX_STEPS + 0.5:
            raise ImaginationError(
                f"{what}: {s:g} s is {steps:,.0f} steps of {self.dt:.4g} s; a call takes at most "
                f"{MAX_STEPS:,} steps ({MAX_STEPS * self.dt:,.0f} s): run it in parts"
            )
        return int(round(steps))

    # -- state ----------------------------------------------------------------

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the moving bodies (balls, then the robot)."""
        names = tuple(self._balls)
        if self._robot is not None and self.scene.robot is not None:
            names += (self.scene.robot.name,)
        return names

    def body(self, name: str) -> pymunk.Body:
        """The pymunk body of a ball or the robot (for read access)."""
        body = self._balls.get(name)
        if body is not None:
            return body
        if self._robot is not None and self.scene.robot is not None and name == self.scene.robot.name:
            return self._robot
        raise ImaginationError(
            f"no moving body called {name!r}; bodies: {list(self.names)}"
        )

    def position(self, name: str) -> Vec2:
        """Current ``(x, y)`` of a body."""
        p = self.body(name).position
        return (float(p[0]), float(p[1]))

    def velocity(self, name: str) -> Vec2:
        """Current ``(vx, vy)`` of a body."""
        v = self.body(name).velocity
        return (float(v[0]), float(v[1]))

    def slip(self, name: str) -> Vec2:
        """Current spin velocity minus velocity of a body (zero for one without spin).

        Examples
        --------
        >>> from adapt.imagination.scene import Wall
        >>> scene = SceneSpec(balls=(Ball("b", velocity=(1.0, 0.0), restitution=0.5,
        ...                                friction=0.0, floor_friction=0.3),),
        ...                   walls=(Wall("east", (0.5, -1.0), (0.5, 1.0)),))
        >>> w = World(scene)
        >>> w.run(0.405)         # the bounce reverses the velocity, not the spin
        >>> [round(c, 1) for c in w.velocity("b")], [round(c, 1) for c in w.slip("b")]
        ([-0.5, 0.0], [1.5, 0.0])
        >>> w.run(1.0)           # rolling again, at about (5 e - 2) / 7 of the speed it came at
        >>> [round(c, 2) for c in w.velocity("b")], [round(c, 3) for c in w.slip("b")]
        ([-0.08, 0.0], [0.0, 0.0])
        """
        self.body(name)
        spin = self._spins.get(name)
        if spin is None:
            return (0.0, 0.0)
        w, v = spin[0].velocity, self.body(name).velocity
        return (float(w[0] - v[0]), float(w[1] - v[1]))

    def snapshot(self) -> WorldState:
        """A frozen copy of the current state."""
        bodies = []
        for name in self.names:
            body = self.body(name)
            p, v = body.position, body.velocity
            slip = (0.0, 0.0)
            spin = self._spins.get(name)
            if spin is not None:
                w = spin[0].velocity
                slip = (float(w[0] - v[0]), float(w[1] - v[1]))
            bodies.append(
                BodyState(
                    name,
                    (float(p[0]), float(p[1])),
                    (float(v[0]), float(v[1])),
                    float(body.angle),
                    float(body.angular_velocity),
                    slip,
                )
            )
        return WorldState(self.time, self._steps, tuple(bodies), self._command)

    def set_velocity(self, name: str, velocity: Sequence[float],
                     slip: Sequence[float] | None = None) -> None:
        """Give a body a new velocity where it stands, at once (no force, no contact).

        A spinning ball's spin moves with it: its ``slip`` is kept, or set to the one
        given (ignored for a body without spin).

        Examples
        --------
        >>> w = World(SceneSpec(balls=(Ball("b", velocity=(1.0, 0.0), floor_friction=0.3),)))
        >>> w.set_velocity("b", (0.0, 0.5))
        >>> w.velocity("b"), w.slip("b")
        ((0.0, 0.5), (0.0, 0.0))
        >>> w.run(1.0)
        >>> [round(c, 3) for c in w.position("b")]
        [0.0, 0.5]
        """
        body = self.body(name)
        vx, vy = float(velocity[0]), float(velocity[1])
        if not (math.isfinite(vx) and math.isfinite(vy)):
            raise ImaginationError(f"velocity: expected two finite numbers, got {tuple(velocity)!r}")
        kept = self.slip(name) if slip is None else (float(slip[0]), float(slip[1]))
        body.velocity = (vx, vy)
        spin = self._spins.get(name)
        if spin is not None:
            spin[0].velocity = (vx + kept[0], vy + kept[1])
        self._calm = False

    def set_state(self, state: WorldState) -> None:
        """Put the bodies into a snapshot's state (positions, velocities, time).

        Bodies the snapshot does not mention keep their state; a body it names
        that this world lacks is an error (add a ball first with
        :meth:`add_ball`).
        """
        for b in state.bodies:
            if b.name not in self.names:
                raise ImaginationError(
                    f"no moving body called {b.name!r} in this world (bodies: "
                    f"{list(self.names)}); add a ball with add_ball before setting its state"
                )
        for b in state.bodies:
            body = self.body(b.name)
            body.position = b.position
            body.velocity = b.velocity
            body.angle = b.angle
            body.angular_velocity = b.angular_velocity
            self.space.reindex_shapes_for_body(body)
            spin = self._spins.get(b.name)
            if spin is not None:
                spin[0].position = b.position
                spin[0].velocity = (b.velocity[0] + b.slip[0], b.velocity[1] + b.slip[1])
        self._calm = False
        self._time0 = state.time - state.step * self.dt
        self._steps = state.step
        self.command_robot(state.command[:2], state.command[2])
        if self._control is not None and self._robot is not None:
            self._control.position = self._robot.position
            self._control.angle = self._robot.angle

    def fork(
        self, state: WorldState | None = None, *, scene: SceneSpec | None = None,
        record_contacts: bool = True,
    ) -> "World":
        """A new, independent world in ``state`` (default: the current one).

        ``scene`` swaps the scene (for example other ball parameters); its
        moving bodies must carry the same names.  The original world is not
        touched.  The fork has the balls of :attr:`scene` (those added at run
        time too) and no step hooks.

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
        applied before each step: from a step hook (:meth:`add_step_hook`).
        Forces applied to the same body before one step add up.
        """
        body = self.body(name)
        try:
            fx, fy = float(force[0]), float(force[1])
        except (TypeError, ValueError, IndexError):
            raise ImaginationError(f"force: expected [fx, fy] in newtons, got {force!r}") from None
        if not (math.isfinite(fx) and math.isfinite(fy)):
            raise ImaginationError(f"force: expected finite newtons, got {[fx, fy]}")
        body.apply_force_at_world_point((fx, fy), body.position)
        self._calm = False
        px, py = self._forces.get(name, (0.0, 0.0))
        self._forces[name] = (px + fx, py + fy)

    @property
    def robot_command(self) -> tuple[float, float, float]:
        """The robot's commanded ``(vx, vy, turn rate)`` (zeros without a robot or command)."""
        return self._command

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Command the robot's velocity (m/s, clipped to ``max_speed``) and turn rate (rad/s)."""
        try:
            vx, vy, w = float(velocity[0]), float(velocity[1]), float(angular_velocity)
        except (TypeError, ValueError, IndexError):
            raise ImaginationError(
                f"command: expected a velocity [vx, vy] and a turn rate, got {velocity!r}, "
                f"{angular_velocity!r}"
            ) from None
        if not (math.isfinite(vx) and math.isfinite(vy) and math.isfinite(w)):
            raise ImaginationError(f"command: expected finite numbers, got {[vx, vy, w]}")
        if self.scene.robot is None or self._control is None:
            if vx or vy or w:
                raise ImaginationError("the scene has no robot to command")
            self._command = (0.0, 0.0, 0.0)
            return
        speed = math.hypot(vx, vy)
        limit = self.scene.robot.max_speed
        if speed > limit:
            vx, vy = vx * limit / speed, vy * limit / speed
        self._command = (vx, vy, w)
        self._calm = False
        self._control.velocity = (vx, vy)
        self._control.angular_velocity = w

