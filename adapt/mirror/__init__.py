"""The mirror: the imagination that perception keeps in step with reality.

A :class:`Mirror` holds the imagination's :class:`~adapt.imagination.World`,
the synthetic camera (which the Scene Background schema corrects so that it
sees what the real camera sees), a renderer for that camera, and the look of
the scene's surfaces learned from the camera
(:class:`~adapt.mirror.appearance.AppearanceModel`).  Schemas act on the
mirror only through this class: they move the camera, add and remove bodies
(an object is created in the imagination where it is first perceived), push
bodies on every physics step (the paper's spring correction), command the
imagined robot (odometry), and teach it the surfaces' look.

The package imports the imagination and geometry only: no vision, no rules.
Its modules: :mod:`~adapt.mirror.appearance` (the learned look: back-projection
of frames onto the surfaces, saving and loading it) and
:mod:`~adapt.mirror.structure` (aligning the camera to the scene's structure
before its look is known).

Invariants:

* the world only moves forward, in whole fixed steps (``step_to``), and the
  step hooks run before every step;
* the renderer always matches the current camera; a new camera costs one
  background render (a few milliseconds: one warp per surface), a new body
  nothing;
* a camera on the robot follows the imagined robot's pose (the commanded
  motion: odometry); a correction from the Scene Background schema moves the
  imagined robot by the camera's horizontal move and turn (visual odometry
  over slipping wheels), and keeps the rest as the camera's pose on its
  mount;
* what the appearance model learns is handed to the renderer's backdrop at
  once (:meth:`Mirror.learn_appearance`), so every later render, through any
  camera, shows it.

Examples
--------
>>> from adapt.geometry import Camera
>>> from adapt.imagination import Ball, SceneSpec
>>> cam = Camera.look_at(fx=200, fy=200, cx=80, cy=60, width=160, height=120,
...                      position=(0, -2, 1), look_at=(0, 1, 0))
>>> m = Mirror(SceneSpec(), cam)
>>> m.add_ball(Ball("b", radius=0.1), (0.0, 0.0), (1.0, 0.0))
>>> pushes = []
>>> m.add_hook(lambda t: pushes.append(t))
>>> m.step_to(0.5)
>>> round(m.world.position("b")[0], 3), len(pushes) == m.world.steps
(0.5, True)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import replace
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination import Ball, Renderer, RenderResult, SceneSpec, World
from adapt.mirror.appearance import AppearanceModel, Learning

__all__ = ["Mirror", "StepHook", "AppearanceModel", "Learning"]

#: A callback run before every physics step, with the world time at the step's start.
StepHook = Callable[[float], None]


class Mirror:
    """The imagination kept in step with reality (see the module docstring).

    Parameters
    ----------
    scene : SceneSpec
        The imagination's starting scene.
    camera : Camera
        The synthetic camera's starting pose (the scenario's nominal one).
    seed : int, optional
        The world's default seed (prediction ensembles).
    camera_follows_robot : callable, optional
        ``f(position, heading) -> Camera`` for a camera on the robot: the
        camera the mount gives for an imagined robot pose.
    """

    def __init__(self, scene: SceneSpec, camera: Camera, *, seed: int | None = None,
                 camera_follows_robot: Callable[[tuple[float, float], float], Camera] | None = None,
                 ) -> None:
        self.world = World(scene, seed=seed, record_contacts=False)
        self._mount = camera_follows_robot
        self._correction = (np.eye(3), np.zeros(3))  # camera pose relative to the mount
        self.camera = camera
        self._declared = camera
        self._renderer = Renderer(scene, camera)
        self.appearance = AppearanceModel(self._renderer.surfaces)
        self._background: tuple[tuple[Any, ...], RenderResult] | None = None
        self._hooks: dict[StepHook, Callable[[World], None]] = {}
        self.camera_changes = 0

    # -- time -----------------------------------------------------------------

    @property
    def time(self) -> float:
        """The imagination's time, seconds."""
        return self.world.time

    def step_to(self, time: float) -> None:
        """Advance the world in whole steps to ``time``, running the hooks before each step."""
        self.world.run_until(time)
        if self._mount is not None:
            self._follow_robot()

    def add_hook(self, hook: StepHook) -> None:
        """Run ``hook(time)`` before every physics step."""
        if hook not in self._hooks:
            self._hooks[hook] = self.world.add_step_hook(lambda world: hook(world.time))

    def remove_hook(self, hook: StepHook) -> None:
        """Stop running ``hook``."""
        adapter = self._hooks.pop(hook, None)
        if adapter is not None:
            self.world.remove_step_hook(adapter)

    # -- the camera -----------------------------------------------------------------

    def set_camera(self, camera: Camera) -> None:
        """Use ``camera`` as the synthetic camera (a correction from the Scene Background).

        For a camera on the robot, the correction says where the robot really
        is: the camera's horizontal move and its turn about the vertical are
        the robot's (its odometry drifts, the camera sees it), so the imagined
        robot is moved and turned by them; what is left (height, tilt, roll) is
        kept as the camera's pose relative to its mount and moves with the
        robot from then on.
        """
        if self._mount is not None:
            (x, y), heading = self._robot_pose()
            mounted = self._mount((x, y), heading)
            dx, dy = camera.position[:2] - mounted.position[:2]
            turn = _yaw(camera.rotation) - _yaw(mounted.rotation)
            turn = (turn + math.pi) % (2 * math.pi) - math.pi
            self._move_robot((x + dx, y + dy), heading + turn)
            mounted = self._mount(*self._robot_pose())
            self._correction = (camera.rotation @ mounted.rotation.T,
                                camera.position - mounted.position)
        self._use_camera(camera)

    def _move_robot(self, position: tuple[float, float], heading: float) -> None:
        robot = self.world.scene.robot
        assert robot is not None
        state = self.world.snapshot()
        bodies = tuple(replace(b, position=(float(position[0]), float(position[1])),
                               angle=float(heading)) if b.name == robot.name else b
                       for b in state.bodies)
        self.world.set_state(replace(state, bodies=bodies))

    def declared_camera(self) -> Camera:
        """The camera where the scenario puts it, before any correction: a fixed camera's
        nominal pose, or the mount's at the imagined robot's pose."""
        if self._mount is not None:
            return self._mount(*self._robot_pose())
        return self._declared

    def _use_camera(self, camera: Camera) -> None:
        if camera is self.camera:
            return
        self.camera = camera
        self._renderer = self._renderer.with_camera(camera)
        self.camera_changes += 1

    def _follow_robot(self) -> None:
        assert self._mount is not None
        mounted = self._mount(*self._robot_pose())
        rc, dc = self._correction
        cam = mounted.with_pose(rc @ mounted.rotation, mounted.position + dc)
        moved = (np.abs(cam.position - self.camera.position).max() > 1e-9
                 or np.abs(cam.rotation - self.camera.rotation).max() > 1e-12)
        if moved:
            self._use_camera(cam)

    # -- rendering --------------------------------------------------------------------

    def render(self) -> RenderResult:
        """What the synthetic camera sees now (with the learned sky, if any)."""
        r = self._renderer.render(self.world.snapshot(), balls=self.world.balls)
        image = self.appearance.composite(r.image, r.labels, self.camera)
        return r if image is r.image else dataclasses.replace(r, image=image)

    @property
    def background(self) -> RenderResult:
        """The static background through the current camera (with the learned sky)."""
        bg = self._renderer.background
        # the renderer itself, not its id: a new renderer may reuse a freed one's id
        key = (self._renderer, self._renderer.backdrop.version, self.appearance.sky_version)
        cached = self._background
        if cached is not None and cached[0][0] is key[0] and cached[0][1:] == key[1:]:
            return cached[1]
        image = self.appearance.composite(bg.image, bg.labels, self.camera)
        if image is not bg.image:
            image.setflags(write=False)
            bg = dataclasses.replace(bg, image=image)
        self._background = (key, bg)
        return bg

    @property
    def renderer(self) -> Renderer:
        """The renderer of the current camera (its backdrop holds the surfaces' appearances)."""
        return self._renderer

    # -- the surfaces' look ----------------------------------------------------------------

    def learn_appearance(self, image: NDArray[np.uint8], labels: NDArray[np.integer], *,
                         exclude: NDArray[np.bool_] | None = None, margin: float = 0.0,
                         rate: float = 0.1, gate: float | None = None,
                         relearn: NDArray[np.bool_] | None = None,
                         new_only: bool = False,
                         covered: NDArray[np.bool_] | None = None) -> Learning:
        """Learn the surfaces' look from a real ``image`` seen through the current
        camera (:meth:`AppearanceModel.learn
        <adapt.mirror.appearance.AppearanceModel.learn>`; ``labels`` is this
        camera's render's label image) and show it in every render from now on."""
        learned = self.appearance.learn(image, self.camera, labels, exclude=exclude,
                                        margin=margin, rate=rate, gate=gate, relearn=relearn,
                                        new_only=new_only, covered=covered)
        self.appearance.apply(self._renderer)
        return learned

    def load_appearance(self, folder: str | Path) -> tuple[str, ...]:
        """Use the surfaces' look saved in ``folder`` (by :meth:`save_appearance`);
        returns the surfaces read."""
        names = self.appearance.load(folder)
        self.appearance.apply(self._renderer)
        return names

    def save_appearance(self, folder: str | Path) -> list[Path]:
        """Write what has been learned of the surfaces' look into ``folder``."""
        return self.appearance.save(folder)

    # -- bodies ---------------------------------------------------------------------------

    @property
    def scene(self) -> SceneSpec:
        """The imagination's current scene (with the bodies added since the start)."""
        return self.world.scene

    def has_body(self, name: str) -> bool:
        """True when a body called ``name`` is in the imagination."""
        return name in self.world.names

    def add_ball(self, ball: Ball, position: Sequence[float], velocity: Sequence[float]) -> None:
        """Create ``ball`` in the imagination at ``position`` with ``velocity``."""
        self.world.add_ball(ball, position=position, velocity=velocity)

    def remove_ball(self, name: str) -> None:
        """Take the ball called ``name`` out of the imagination (nothing when it is not there)."""
        if self.has_body(name):
            self.world.remove_ball(name)

    def replace_ball(self, ball: Ball) -> None:
        """Give an existing ball new parameters (restitution, friction, ...), keeping its
        position and velocity."""
        p, v = self.world.position(ball.name), self.world.velocity(ball.name)
        self.world.remove_ball(ball.name)
        self.world.add_ball(ball, position=p, velocity=v)

    # -- the robot -------------------------------------------------------------------------

    def _robot_pose(self) -> tuple[tuple[float, float], float]:
        robot = self.world.scene.robot
        assert robot is not None
        body = self.world.body(robot.name)
        return (float(body.position[0]), float(body.position[1])), float(body.angle)

    @property
    def mounted(self) -> bool:
        """True when the camera rides on the robot (it moves when the robot drives)."""
        return self._mount is not None

    def robot_pose(self) -> tuple[tuple[float, float], float] | None:
        """The imagined robot's ``((x, y), heading)`` (odometry), or None without a robot."""
        if self.world.scene.robot is None:
            return None
        return self._robot_pose()

    def robot_driven(self) -> bool:
        """Whether the imagined robot is commanded to move (a camera on it is carried as the
        real robot starts, before its odometry has gone far)."""
        return any(v != 0.0 for v in self.world.robot_command)

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Drive the imagined robot (the commanded motion: odometry)."""
        self.world.command_robot(velocity, angular_velocity)


def _yaw(rotation: np.ndarray) -> float:
    """Heading of a camera's viewing direction on the floor (radians from +x)."""
    forward = rotation[2]  # the camera's z axis in world coordinates
    return math.atan2(float(forward[1]), float(forward[0]))
