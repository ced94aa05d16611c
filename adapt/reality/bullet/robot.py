"""The real robot of a PyBullet reality: a body the drive and intercept commands move.

:class:`Drive` is the reality's :class:`~adapt.frames.Actuator`:
``command_robot((vx, vy), omega)`` (m/s in the world frame, rad/s) takes effect
from the next physics step.  Before each step the robot's velocity moves towards
what its wheels really drive at, by at most ``max_accel * dt``:

* the command clipped to ``max_speed``;
* plus wheel slip: ``slip |v|`` times a Gaussian 2-vector, and the turn rate
  times ``1 + slip n``, drawn afresh every ``slip_interval`` seconds (the
  odometry, the commanded motion, does not see it); clipped to ``max_speed``
  again.

The body slides without friction on the floor and keeps upright; walls,
obstacles and balls push it as PyBullet's contacts do (it is heavy: its mass is
the scenario's), so it stops at a wall instead of passing through.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from adapt.reality.bullet.client import Client
from adapt.reality.truth import RobotState

__all__ = ["Drive"]


class Drive:
    """The real robot (see the module docstring)."""

    def __init__(self, client: Client, body: int, height: float, *, max_speed: float,
                 max_accel: float, slip: float, slip_interval: float,
                 rng: np.random.Generator) -> None:
        self.client = client
        self.body = body
        self.height = height
        self.max_speed = max_speed
        self.max_accel = max_accel
        self.slip = slip
        self.slip_interval = slip_interval
        self.rng = rng
        self.command = np.zeros(2)
        self.turn = 0.0
        self._slip = np.zeros(2)
        self._slip_turn = 0.0
        self._next_slip = 0.0
        self.velocity = np.zeros(2)
        self.omega = 0.0

    def command_robot(self, velocity: Sequence[float], angular_velocity: float = 0.0) -> None:
        """Command the robot's velocity (m/s, world frame) and turn rate (rad/s)."""
        v = np.array([float(velocity[0]), float(velocity[1])])
        speed = float(np.linalg.norm(v))
        if not math.isfinite(speed) or not math.isfinite(float(angular_velocity)):
            return  # a command that is not a number moves nothing
        if speed > self.max_speed:
            v *= self.max_speed / speed
        self.command = v
        self.turn = float(angular_velocity)

    def before_step(self, time: float, dt: float) -> None:
        """Set the body's velocity for the step that starts at ``time``."""
        if self.slip > 0 and time >= self._next_slip - 1e-12:
            self._slip = self.rng.standard_normal(2)
            self._slip_turn = float(self.rng.standard_normal())
            self._next_slip = time + self.slip_interval
        want = self.command + self.slip * float(np.linalg.norm(self.command)) * self._slip
        speed = float(np.linalg.norm(want))
        if speed > self.max_speed:
            want *= self.max_speed / speed
        c = self.client
        (vx, vy, _), _ = c.getBaseVelocity(self.body)
        current = np.array([vx, vy])
        dv = want - current
        step = self.max_accel * dt
        norm = float(np.linalg.norm(dv))
        if norm > step:
            dv *= step / norm
        self.velocity = current + dv
        self.omega = self.turn * (1.0 + self.slip * self._slip_turn)
        (x, y, _), q = c.getBasePositionAndOrientation(self.body)
        yaw = c.getEulerFromQuaternion(q)[2]
        c.resetBasePositionAndOrientation(self.body, [x, y, self.height / 2 + 1e-4],
                                          c.getQuaternionFromEuler([0.0, 0.0, yaw]))
        c.resetBaseVelocity(self.body, [float(self.velocity[0]), float(self.velocity[1]), 0.0],
                            [0.0, 0.0, self.omega])

    def state(self) -> RobotState:
        """The true robot now."""
        c = self.client
        (x, y, _), q = c.getBasePositionAndOrientation(self.body)
        (vx, vy, _), (_, _, wz) = c.getBaseVelocity(self.body)
        return RobotState((float(x), float(y)), float(c.getEulerFromQuaternion(q)[2]),
                          (float(vx), float(vy)), float(wz))
