"""The synthetic reality: a ground-truth world seen through a true camera.

:class:`SyntheticSource` is a :class:`~adapt.frames.FrameSource` made from a
scenario's ``reality`` section (:class:`~adapt.scenario.SyntheticReality`).
Opening it draws the run's true parameters (:func:`draw_parameters`); each
frame ``i`` then

1. steps reality's physics (:class:`~adapt.reality.physics.RealWorld`) to
   time ``i / run.fps``, with the robot following the commands given to
   :attr:`SyntheticSource.robot` so far;
2. places the true camera: the scenario's nominal camera (on the robot: the
   mount at the *true* robot pose, which slips) moved by the drawn offset
   (:mod:`adapt.reality.camera`);
3. renders the true scene (the texture tiles scaled by
   ``appearance.texture_scale``, their pattern moved by ``texture_phase``,
   :mod:`adapt.reality.surfaces`) with the imagination's renderer, draws the
   spin markers, and applies the appearance
   (:class:`~adapt.reality.appearance.Look`);
4. records the truth of the frame (:class:`~adapt.reality.truth.FrameTruth`)
   in :attr:`SyntheticSource.truth`, which only evaluation may read.

Random numbers come from three streams of the run's seed
(:class:`adapt.seeds.Streams`): ``reality.parameters`` (true parameters,
camera offset), ``reality.events`` (throws) and ``reality.noise`` (sensor
noise, wheel slip).  Each object draws from its own child of a stream, so
adding an object to a scenario does not change what the others draw.  The
same seed and the same robot commands give the same frames and truth.

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> from adapt.seeds import Streams
>>> sc = loads_scenario('''
... camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
...          position: [0, -2, 1], look_at: [0, 1, 0]}
... world:
...   objects: [{name: ball, radius: 0.1, velocity: [0.5, 0]}]
... run: {fps: 10, max_frames: 3}
... ''')
>>> source = SyntheticSource(sc, streams=Streams(1))
>>> [(f.index, f.time, f.image.shape) for f in source]
[(0, 0.0, (60, 80, 3)), (1, 0.1, (60, 80, 3)), (2, 0.2, (60, 80, 3))]
>>> truth = source.truth.at(2)
>>> round(truth.position("ball")[0], 4), round(truth.objects["ball"].velocity[0], 4)
(0.0999, 0.4985)
"""

from __future__ import annotations

import math
from dataclasses import replace
from types import MappingProxyType
from typing import Iterator, Sequence

import numpy as np

from adapt.errors import RealityError
from adapt.frames import Frame
from adapt.geometry import Camera
from adapt.imagination.render import LABEL_BALL, Renderer
from adapt.imagination.scene import RobotSpec, SceneSpec
from adapt.reality.appearance import Look, draw_spin_marker
from adapt.reality.camera import draw_offset, nominal_camera, offset_camera
from adapt.reality.physics import RealWorld, true_scene
from adapt.reality.surfaces import shift_textures
from adapt.reality.truth import (
    DEFAULT_HISTORY,
    FrameTruth,
    ObjectParameters,
    ObjectTruth,
    RecordedTruth,
    TrueParameters,
)
from adapt.scenario import Mount, Scenario, SyntheticReality
from adapt.seeds import Streams

__all__ = ["SyntheticSource", "RealRobot", "draw_parameters", "render_scene"]


def draw_parameters(scenario: Scenario, streams: Streams) -> TrueParameters:
    """Draw the run's true parameters from a synthetic reality's ranges.

    Object ``i`` draws its physical parameters from child ``i + 1`` of the
    ``reality.parameters`` stream and its throw from child ``i`` of
    ``reality.events``; the camera offset draws from child 0 of
    ``reality.parameters``.
    """
    reality = scenario.reality
    assert isinstance(reality, SyntheticReality)
    n = len(reality.objects)
    params = [np.random.default_rng(s) for s in streams.sequence("reality.parameters").spawn(n + 1)]
    events = [np.random.default_rng(s) for s in streams.sequence("reality.events").spawn(max(n, 1))]
    objects = []
    for i, o in enumerate(reality.objects):
        rng = params[i + 1]
        restitution, friction, rolling, mass, drag, spin = (
            r.draw(rng) for r in (o.restitution, o.friction, o.rolling_resistance, o.mass,
                                  o.drag, o.spin))
        appears: float | None = None
        position, velocity = o.ball.position, o.ball.velocity
        if o.throw is not None:
            ev = events[i]
            th = o.throw
            appears = th.time.draw(ev)
            position = (th.x.draw(ev), th.y.draw(ev))
            speed, heading = th.speed.draw(ev), math.radians(th.heading_deg.draw(ev))
            velocity = (speed * math.cos(heading), speed * math.sin(heading))
        objects.append(ObjectParameters(o.name, o.declared, restitution, friction, rolling, mass, drag,
                                        spin, appears, position, velocity))
    offset, rotation = draw_offset(reality.camera, params[0])
    robot = scenario.scene.robot
    truth = reality.robot
    return TrueParameters(
        streams.seed, tuple(objects), offset, rotation,
        None if robot is None else (truth.max_speed or robot.max_speed),
        None if robot is None else (truth.max_accel or robot.max_accel),
        truth.slip if robot is not None else 0.0)


def render_scene(scene: SceneSpec, texture_scale: float) -> SceneSpec:
    """The true scene as the camera sees it: every texture tile scaled."""
    if texture_scale == 1.0:
        return scene
    return replace(
        scene,
        floor=replace(scene.floor, tile=scene.floor.tile * texture_scale),
        walls=tuple(replace(w, tile=w.tile * texture_scale) for w in scene.walls),
        obstacles=tuple(replace(o, tile=o.tile * texture_scale) for o in scene.obstacles))


class RealRobot:
    """The real robot of a synthetic reality: an :class:`~adapt.frames.Actuator`.

    Commands take effect from the next physics step: the robot drives at the
    commanded velocity within its true limits, with wheel slip.
    """

    def __init__(self, world: RealWorld) -> None:
        self._world = world

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Command the robot's velocity (m/s, world frame) and turn rate (rad/s)."""
        self._world.command_robot(velocity, angular_velocity)


class SyntheticSource:
    """Frames of a synthetic reality (see the module docstring).

    Parameters
    ----------
    scenario : Scenario
        A scenario whose ``reality`` is synthetic.
    streams : Streams
        The run's random streams.
    history : int
        Frames of truth kept (older frames' truth is dropped).

    Attributes
    ----------
    robot : RealRobot or None
        The real robot (None when the world has none).
    truth : RecordedTruth
        The truth of the frames made so far (evaluation only).
    parameters : TrueParameters
        What was drawn for this run.
    scene : SceneSpec
        The true scene (true parameters, every object, the real robot).
    render_scene : SceneSpec
        The true scene as rendered (texture tiles scaled).
    world : RealWorld
        Reality's physics.
    look : Look
        The appearance applied to each render.
    renderer : Renderer
        The renderer of the true scene through the current true camera (its
        backdrop holds the texture phase).
    """

    def __init__(self, scenario: Scenario, *, streams: Streams,
                 history: int = DEFAULT_HISTORY) -> None:
        reality = scenario.reality
        if not isinstance(reality, SyntheticReality):
            raise RealityError(f"{scenario.where('reality').location}: expected a synthetic "
                               f"reality, got {reality.kind.value}")
        self.scenario = scenario
        self.reality = reality
        self.parameters = draw_parameters(scenario, streams)
        base = scenario.scene
        robot: RobotSpec | None = None
        if base.robot is not None:
            assert self.parameters.robot_max_speed is not None
            assert self.parameters.robot_max_accel is not None
            robot = replace(base.robot, max_speed=self.parameters.robot_max_speed,
                            max_accel=self.parameters.robot_max_accel)
        scene = true_scene(base, [o.ball for o in reality.objects], self.parameters.objects,
                           robot, reality.dt)
        self.scene = scene
        noise = [np.random.default_rng(s) for s in streams.sequence("reality.noise").spawn(2)]
        self._noise = noise[0]
        self.world = RealWorld(scene, self.parameters.objects, dt=reality.dt,
                               slip=reality.robot.slip, slip_interval=reality.robot.slip_interval,
                               rng=noise[1])
        self.robot: RealRobot | None = RealRobot(self.world) if robot is not None else None
        self.truth = RecordedTruth(self.parameters, history)
        self._fps = float(scenario.run.fps)
        self._length = int(scenario.run.frames)
        self.look = Look(reality.appearance, scenario.camera.size)
        self.render_scene = render_scene(scene, reality.appearance.texture_scale)
        cam = self.camera()
        self.renderer = Renderer(self.render_scene, cam)
        if reality.appearance.texture_phase != (0.0, 0.0):
            shift_textures(self.renderer, reality.appearance.texture_phase,
                           centre=(float(cam.position[0]), float(cam.position[1])))
        self._started = False
        self._closed = False

    # -- FrameSource -----------------------------------------------------------------------

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)``: the scenario camera's."""
        return self.scenario.camera.size

    @property
    def fps(self) -> float:
        """The scenario's ``run.fps``."""
        return self._fps

    @property
    def length(self) -> int:
        """Frames the source yields: ``run.frames``."""
        return self._length

    def __iter__(self) -> Iterator[Frame]:
        if self._started:
            raise RealityError("a synthetic reality is a single run: its frames can be iterated "
                               "once; open the scenario again for another run")
        self._started = True
        return self._frames()

    def close(self) -> None:
        """End the run: iteration stops at the next frame."""
        self._closed = True

    def _frames(self) -> Iterator[Frame]:
        for index in range(self._length):
            if self._closed:
                return
            yield self.frame(index)

    # -- one frame ---------------------------------------------------------------------------

    def camera(self) -> Camera:
        """The true camera now."""
        p = self.parameters
        sc = self.scenario
        state = self.world.robot_state()
        if sc.mount.kind is Mount.ROBOT and state is not None:
            nominal = nominal_camera(sc.camera, sc.mount, state.position, state.heading)
            return offset_camera(nominal, p.camera_offset, p.camera_rotation_deg, state.heading)
        return offset_camera(sc.camera, p.camera_offset, p.camera_rotation_deg)

    def frame(self, index: int) -> Frame:
        """Make frame ``index`` (frames must be made in order)."""
        t = index / self._fps
        if t < self.world.time - 0.5 * self.world.dt:
            raise RealityError(f"frame {index} is in the past (reality is at "
                               f"{self.world.time:.4f} s)")
        self.world.run_until(t)
        cam = self.camera()
        r = self.renderer
        if not (np.array_equal(r.camera.rotation, cam.rotation)
                and np.array_equal(r.camera.position, cam.position)):
            # The same backdrop (textures, phases): only the new pose's background is drawn.
            r = self.renderer = r.with_camera(cam)
        state = self.world.state()
        out = r.render(state)
        image = out.image
        if self.reality.appearance.spin_marker:
            present = set(state.names)
            for i, ball in enumerate(self.scene.balls):
                if ball.name in present:
                    x, y = state.body(ball.name).position
                    draw_spin_marker(image, out.labels, cam, (x, y, ball.radius), ball.radius,
                                     self.world.orientation(ball.name), LABEL_BALL + i)
        image = self.look.apply(image, out.labels, self._noise)
        image.setflags(write=False)
        self.truth.record(self.frame_truth(index, t, cam))
        return Frame(index, t, image)

    def frame_truth(self, index: int, t: float, cam: Camera) -> FrameTruth:
        """The truth now, as frame ``index`` at time ``t`` seen by ``cam``."""
        world = self.world
        objects: dict[str, ObjectTruth | None] = {}
        for name in world.names:
            objects[name] = (ObjectTruth(world.position(name), world.velocity(name))
                             if world.present(name) else None)
        return FrameTruth(index, t, MappingProxyType(objects), cam, world.robot_state(),
                          self.parameters)
