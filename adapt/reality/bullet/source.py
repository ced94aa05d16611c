"""A reality on PyBullet: frames made by another physics engine and another renderer.

:class:`BulletSource` is a :class:`~adapt.frames.FrameSource` made from a
scenario's ``reality`` section of ``kind: bullet``
(:class:`~adapt.scenario.BulletReality`).  Opening it draws the run's parameters
(:mod:`~adapt.reality.bullet.draw`), makes the surfaces' and balls' images
(:mod:`~adapt.reality.bullet.textures`), builds the bodies in a PyBullet client of
its own (:mod:`~adapt.reality.bullet.bodies`) and measures what each ball's
contacts really do in another (:mod:`~adapt.reality.bullet.calibrate`).  Each
frame ``i`` then

1. steps PyBullet to time ``i / run.fps`` (its own ``dt``): balls enter at their
   throw's time, the robot drives as commanded through :attr:`BulletSource.robot`
   (:mod:`~adapt.reality.bullet.robot`);
2. places the true camera: the scenario's (on the robot: the mount at the robot's
   true pose) moved by the drawn offset (:mod:`adapt.reality.camera`);
3. renders with PyBullet's CPU renderer (TinyRenderer) in the drawn light
   (:mod:`~adapt.reality.bullet.view`) and passes the render through the drawn
   sensor (:mod:`~adapt.reality.bullet.sensor`);
4. records the frame's truth (:class:`~adapt.reality.truth.FrameTruth`, with each
   ball's height and the pixels of it the camera shows) for evaluation only.

It shares no code with the imagination's renderer or physics: of the
imagination it reads only the scenario's world records (geometry) and the
bundled textures' files.  The same seed and the same robot commands give the
same frames and truth.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import replace
from types import MappingProxyType
from typing import Iterator

import numpy as np

from adapt.errors import RealityError
from adapt.frames import Frame
from adapt.geometry import Camera
from adapt.reality.bullet.bodies import Bodies, add_ball, build
from adapt.reality.bullet.calibrate import Effective, measure
from adapt.reality.bullet.client import Client
from adapt.reality.bullet.draw import BallDraw, BulletDraw, child, draw
from adapt.reality.bullet.robot import Drive
from adapt.reality.bullet.sensor import Sensor
from adapt.reality.bullet.textures import ball_image, surface_image, write_textures
from adapt.reality.bullet.view import render
from adapt.reality.camera import nominal_camera, offset_camera
from adapt.reality.truth import (
    DEFAULT_HISTORY,
    FrameTruth,
    ObjectParameters,
    ObjectTruth,
    RecordedTruth,
    TrueParameters,
)
from adapt.scenario import BulletReality, Mount, Scenario
from adapt.scenario.bullet import inside_obstacle, inside_wall
from adapt.seeds import Streams

__all__ = ["BulletSource", "model_parameters"]

#: PyBullet's settings for every client of a reality: restitution down to 5 cm/s, split
#: impulses (no energy from position correction), the same contacts in the same order.
ENGINE = {"numSubSteps": 1, "restitutionVelocityThreshold": 0.05, "useSplitImpulse": 1,
          "deterministicOverlappingPairs": 1}


def model_parameters(ball: BallDraw, effective: Effective, scenario: Scenario,
                     drawn: BulletDraw) -> ObjectParameters:
    """The ball's "true" parameters in the imagination's terms, from what its contacts
    measurably do: the imagination multiplies a ball's restitution and friction with
    the scenario's wall's, so the true ball value is the measured one over the walls'
    (their median); rolling resistance, drag and spin are as measured.  A quantity that
    could not be measured falls back to the drawn coefficients' product."""
    walls = scenario.scene.walls
    wall_e = statistics.median([w.restitution for w in walls]) if walls else 1.0
    wall_f = statistics.median([w.friction for w in walls]) if walls else 1.0
    e = effective.restitution_walls
    if not math.isfinite(e):
        e = ball.restitution * drawn.walls.restitution
    mu = effective.friction_walls
    if not math.isfinite(mu):
        mu = ball.friction * drawn.walls.friction
    c = effective.rolling_resistance if math.isfinite(effective.rolling_resistance) else 0.0
    drag = effective.drag if math.isfinite(effective.drag) else 0.0
    spin = effective.spin if math.isfinite(effective.spin) else 0.0
    return ObjectParameters(ball.name, ball.declared, min(1.0, e / wall_e) if wall_e > 0 else e,
                            mu / wall_f if wall_f > 0 else mu, c, ball.mass, drag, spin,
                            ball.appears, ball.position, ball.velocity)


class BulletSource:
    """Frames of a PyBullet reality (see the module docstring).

    Parameters
    ----------
    scenario : Scenario
        A scenario whose ``reality`` is of ``kind: bullet``.
    streams : Streams
        The run's random streams.
    history : int
        Frames of truth kept.
    calibrate : bool
        Measure the balls' effective contact parameters (about 0.3 s a ball); without,
        the truth reports the drawn coefficients' products.

    Raises
    ------
    RealityError
        PyBullet is not installed (the message names ``pip install 'adapt[bullet]'``),
        the drawn camera offset puts the camera inside a wall or an obstacle, a texture
        cannot be read, or PyBullet fails.
    """

    def __init__(self, scenario: Scenario, *, streams: Streams, history: int = DEFAULT_HISTORY,
                 calibrate: bool = True) -> None:
        reality = scenario.reality
        if not isinstance(reality, BulletReality):
            raise RealityError(f"{scenario.where('reality').location}: expected a bullet reality, "
                               f"got {reality.kind.value}")
        self.scenario = scenario
        self.reality = reality
        self.where = scenario.where("reality.kind").location
        self.drawn = draw(scenario, streams)
        self.client = Client(self.where)
        try:
            self._open(streams, history, calibrate)
        except BaseException:
            self.client.close()
            raise

    def _open(self, streams: Streams, history: int, calibrate: bool) -> None:
        scenario, reality, drawn = self.scenario, self.reality, self.drawn
        c = self.client
        scene = scenario.scene
        c.setGravity(0, 0, -scene.gravity)
        c.setPhysicsEngineParameter(fixedTimeStep=reality.dt, **ENGINE)
        images = [(s.surface, surface_image(s)) for s in drawn.look.surfaces]
        for o in reality.objects:
            images.append((f"ball:{o.name}", ball_image(o.ball.color, drawn.look.ball_marks)))
        self.textures = write_textures(images, c.loadTexture)
        robot = scene.robot
        if robot is not None:
            assert drawn.robot_max_speed is not None and drawn.robot_max_accel is not None
            robot = replace(robot, max_speed=drawn.robot_max_speed,
                            max_accel=drawn.robot_max_accel)
        self.bodies: Bodies = build(c, scene, drawn, reality.wall_thickness, self.textures, robot)
        noise = streams.sequence("reality.noise")
        self._noise = child(noise, "sensor")
        self.robot: Drive | None = None
        if robot is not None and self.bodies.robot is not None:
            self.robot = Drive(c, self.bodies.robot, robot.height, max_speed=robot.max_speed,
                               max_accel=robot.max_accel, slip=drawn.robot_slip,
                               slip_interval=reality.robot.slip_interval, rng=child(noise, "slip"))
        self.dt = reality.dt
        self.steps = 0
        self._waiting = sorted((b for b in drawn.balls), key=lambda b: b.appears or 0.0)
        self._enter(0.0)
        self.effective = {b.name: (measure(b, drawn.floor, drawn.walls, drawn.obstacles,
                                           scene.gravity, reality.dt) if calibrate
                                   else Effective(*(math.nan,) * 7)) for b in drawn.balls}
        objects = tuple(model_parameters(b, self.effective[b.name], scenario, drawn)
                        for b in drawn.balls)
        details = {"pybullet": drawn.as_json(),
                   "measured": {name: e.as_json() for name, e in self.effective.items()}}
        self.parameters = TrueParameters(
            streams.seed, objects, drawn.camera_offset, drawn.camera_rotation_deg,
            drawn.robot_max_speed, drawn.robot_max_accel, drawn.robot_slip,
            MappingProxyType(details))
        self.truth = RecordedTruth(self.parameters, history)
        self.sensor = Sensor(drawn.look, scenario.camera.size)
        self._fps = float(scenario.run.fps)
        self._length = int(scenario.run.frames)
        self._check_camera(self.camera())
        self._started = False
        self._closed = False

    def _check_camera(self, cam: Camera) -> None:
        scene = self.scenario.scene
        p = (float(cam.position[0]), float(cam.position[1]), float(cam.position[2]))
        where = self.scenario.where("reality.camera_offset").location
        text = f"[{p[0]:.3g}, {p[1]:.3g}, {p[2]:.3g}]"
        if p[2] <= 0:
            raise RealityError(f"{where}: the drawn camera offset puts the camera at {text}, not "
                               "above the floor; make the offset smaller")
        i = inside_wall(scene, self.reality.wall_thickness, p)
        j = inside_obstacle(scene.obstacles, p)
        if i is not None or j is not None:
            what = f"the wall {scene.walls[i].name!r}" if i is not None else \
                f"the obstacle {scene.obstacles[j].name!r}"  # type: ignore[index]
            raise RealityError(f"{where}: the drawn camera offset puts the camera at {text}, "
                               f"inside {what}; make the offset smaller or move the camera")

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

    @property
    def time(self) -> float:
        """PyBullet's time now, seconds."""
        return self.steps * self.dt

    def __iter__(self) -> Iterator[Frame]:
        if self._started:
            raise RealityError("a bullet reality is a single run: its frames can be iterated "
                               "once; open the scenario again for another run")
        self._started = True
        return self._frames()

    def close(self) -> None:
        """End the run and release PyBullet."""
        self._closed = True
        self.client.close()

    def _frames(self) -> Iterator[Frame]:
        for index in range(self._length):
            if self._closed:
                return
            yield self.frame(index)

    # -- the world -------------------------------------------------------------------------

    def _enter(self, time: float) -> None:
        """Create the balls whose time has come."""
        while self._waiting and (self._waiting[0].appears or 0.0) <= time + 1e-9:
            b = self._waiting.pop(0)
            body = add_ball(self.client, b, self.textures.get(f"ball:{b.name}"))
            self.bodies.balls[b.name] = body
            self.bodies.names[body] = b.name

    def run_until(self, t: float) -> None:
        """Step PyBullet to time ``t``."""
        c = self.client
        while self.time < t - 0.5 * self.dt:
            now = self.time
            self._enter(now)
            if self.robot is not None:
                self.robot.before_step(now, self.dt)
            c.stepSimulation()
            self.steps += 1
        self._enter(self.time)

    def camera(self) -> Camera:
        """The true camera now."""
        sc, d = self.scenario, self.drawn
        if sc.mount.kind is Mount.ROBOT and self.robot is not None:
            state = self.robot.state()
            nominal = nominal_camera(sc.camera, sc.mount, state.position, state.heading)
            return offset_camera(nominal, d.camera_offset, d.camera_rotation_deg, state.heading)
        return offset_camera(sc.camera, d.camera_offset, d.camera_rotation_deg)

    def frame(self, index: int) -> Frame:
        """Make frame ``index`` (frames must be made in order)."""
        if self._closed:
            raise RealityError("the bullet reality is closed")
        t = index / self._fps
        if t < self.time - 0.5 * self.dt:
            raise RealityError(f"frame {index} is in the past (reality is at {self.time:.4f} s)")
        self.run_until(t)
        cam = self.camera()
        rgb, seg = render(self.client, cam, self.drawn.look)
        image = self.sensor.apply(rgb, seg, self._noise)
        image.setflags(write=False)
        self.truth.record(self.frame_truth(index, t, cam, seg))
        return Frame(index, t, image)

    def frame_truth(self, index: int, t: float, cam: Camera,
                    seg: np.ndarray | None = None) -> FrameTruth:
        """The truth now, as frame ``index`` at time ``t`` seen by ``cam`` (``seg``: the
        render's segmentation, for the pixels of each ball it shows)."""
        c = self.client
        objects: dict[str, ObjectTruth | None] = {}
        for b in self.drawn.balls:
            body = self.bodies.balls.get(b.name)
            if body is None:
                objects[b.name] = None
                continue
            (x, y, z), _ = c.getBasePositionAndOrientation(body)
            (vx, vy, _), _ = c.getBaseVelocity(body)
            pixels = None if seg is None else int(np.count_nonzero(seg == body))
            objects[b.name] = ObjectTruth((float(x), float(y)), (float(vx), float(vy)), float(z),
                                          pixels)
        state = None if self.robot is None else self.robot.state()
        return FrameTruth(index, t, MappingProxyType(objects), cam, state, self.parameters)
