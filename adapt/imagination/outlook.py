"""What the imagination expects from a world's state, ahead of time (``adapt imagine``).

:func:`look_ahead` rolls a world forward on a fork: the path of one ball,
sampled evenly, its contacts, and -- when the scene has a robot -- the
earliest point of the ball's path the robot can reach (its intercept, on a
dense rollout).  :func:`frames_ahead` renders the forked world frame by
frame, for a video of what is expected.

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> world = World(SceneSpec(walls=(Wall("north", (-2, 1), (2, 1)),),
...                         balls=(Ball("b", radius=0.1, velocity=(0.0, 1.5)),)))
>>> out = look_ahead(world, 1.0, samples=3)
>>> out.path.body, len(out.path.times), [c.surface for c in out.path.contacts], out.meeting
('b', 3, ['north'], None)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination.predict import MAX_SAMPLES, Intercept, Trajectory, intercept, intercept_reach, rollout
from adapt.imagination.render import Renderer
from adapt.imagination.world import World

__all__ = ["Outlook", "look_ahead", "frames_ahead"]


@dataclass(frozen=True, slots=True, eq=False)
class Outlook:
    """A world's expected future: ``path`` (the ball ``path.body``, sampled), and the
    robot's earliest ``meeting`` with it (None without a robot, or out of reach)."""

    horizon: float
    dt: float
    path: Trajectory
    robot: str | None = None
    meeting: Intercept | None = None


def look_ahead(world: World, horizon: float, *, samples: int | None = None,
               body: str | None = None, what: str = "horizon") -> Outlook:
    """Roll ``world`` forward ``horizon`` seconds on a fork (see the module docstring).

    ``samples`` evenly spaced points of the path (10 a second and one by default);
    ``body`` the ball to follow (the first by default); ``what`` names the horizon in
    the error for one too far ahead.

    Raises
    ------
    ImaginationError
        A horizon too far ahead, an unknown body, too many samples.
    """
    steps = world.steps_for(horizon, what)
    n = samples if samples is not None else min(int(round(horizon * 10)) + 1, MAX_SAMPLES)
    times = list(np.linspace(0.0, horizon, n)) if n > 1 else [horizon]
    path = rollout(world, horizon, times=times, body=body)
    robot = world.scene.robot
    if robot is None:
        return Outlook(horizon, world.dt, path)
    # every step, or as many evenly spaced samples as a rollout keeps
    fine = min(steps + 1, MAX_SAMPLES)
    dense = rollout(world, horizon, body=path.body,
                    times=None if fine == steps + 1 else list(np.linspace(0.0, horizon, fine)))
    hit = intercept(dense, robot.position, robot.max_speed, robot.max_accel,
                    reach=intercept_reach(world.scene.ball(path.body), robot))
    return Outlook(horizon, world.dt, path, robot.name, hit)


def frames_ahead(world: World, camera: Camera, horizon: float, fps: float
                 ) -> Iterator[NDArray[np.uint8]]:
    """What ``camera`` would see of ``world`` run on (on a fork) for ``horizon`` seconds,
    ``fps`` frames a second from now."""
    renderer = Renderer(world.scene, camera)
    fork = world.fork()
    t0 = fork.time
    for k in range(int(horizon * fps) + 1):
        fork.run_until(t0 + k / fps)
        yield renderer.render(fork.snapshot(), balls=fork.balls).image
