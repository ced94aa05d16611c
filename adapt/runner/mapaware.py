"""The map-aware baseline: the Kalman baseline's estimate, propagated with the map.

The same constant-velocity Kalman filter as :class:`~adapt.runner.baseline.Baseline`,
on the same sightings, but its estimate is propagated by
:class:`~adapt.reflection.Reflector`: rolling to a stop at the ball model's nominal
rolling resistance and reflecting off the scenario's walls and obstacles with the
nominal restitution -- the analytic model a robot-football team writes.  It
predicts at the scenario's horizons and drives a simulated robot (the real robot's
limits and footprint) to the earliest point of its predicted path the robot can
reach, exactly as the Kalman baseline does with its straight line.  This is the
strongest simple peer the mirror is measured against: a simulation kept in step
with the camera has to beat it to be worth its cost.

Examples
--------
>>> from adapt.imagination.scene import Ball, SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("east", (1.0, -1.0), (1.0, 1.0)),))
>>> ball = Ball("ball", radius=0.1, restitution=0.8, rolling_resistance=0.0)
>>> b = MapAwareBaseline(None, reach=0.3, horizons=(1.5,), dt=1 / 30, scene=scene, ball=ball)
>>> for k in range(20):
...     b.step(k / 30, (0.5 * k / 30, 0.0))
>>> [round(v, 2) for v in b.predict(1.5)]   # 1.07 straight on; reflected at x = 0.9
[0.77, 0.0]
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from adapt.imagination import RobotSpec, SceneSpec
from adapt.imagination.scene import Ball
from adapt.reflection import Reflector
from adapt.runner.baseline import Baseline, BaselineSetup

__all__ = ["MapAwareBaseline", "mapaware"]


def mapaware(setup: BaselineSetup) -> "MapAwareBaseline":
    """The map-aware baseline for one object (the keyed collection's ``mapaware``)."""
    assert setup.ball is not None, "the map-aware baseline needs the object's model"
    return MapAwareBaseline(setup.robot, reach=setup.reach, horizons=setup.horizons, dt=setup.dt,
                            scene=setup.scene, ball=setup.ball)


class MapAwareBaseline(Baseline):
    """A Kalman filter whose estimate rolls and reflects off the map (see the module
    docstring); the interface of :class:`~adapt.runner.baseline.Baseline`."""

    def __init__(self, robot: RobotSpec | None, *, reach: float, horizons: Sequence[float],
                 dt: float, scene: SceneSpec, ball: Ball, q: float = 0.3, r: float = 0.005,
                 plan: float = 3.0) -> None:
        super().__init__(robot, reach=reach, horizons=horizons, dt=dt, q=q, r=r, plan=plan,
                         scene=scene)
        self.reflector = Reflector(scene, ball)

    def path(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities ``(N, 2)`` ``times`` seconds after the filter's time:
        the filtered state rolled and reflected off the map."""
        return self.reflector.path(self.kf.position, self.kf.velocity, np.asarray(times, float))
