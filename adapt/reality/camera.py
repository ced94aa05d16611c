"""The true camera: the scenario's nominal camera, moved by a mounting error.

A synthetic reality's camera is not where the scenario says.  Its
:class:`~adapt.scenario.CameraOffset` is drawn once per run
(:func:`draw_offset`): ``position`` metres ``[dx, dy, dz]`` and
``rotation_deg`` ``[pan, tilt, roll]``; a scalar in the scenario means that
magnitude in a direction drawn from the seed (uniform on the sphere).

The offset is applied to the nominal pose (:func:`offset_camera`):

* ``pan`` turns the camera about the world's up axis (positive: to the
  left, counter-clockwise seen from above);
* ``tilt`` turns it about its own ``x`` axis (positive: the view goes up);
* ``roll`` turns it about its viewing axis, with the sign of the scenario's
  ``roll_deg`` (positive: the scene appears turned counter-clockwise);
* ``position`` is added to the camera centre -- in the world frame for a
  fixed camera, in the robot's frame (turning with it) for a camera on the
  robot, since it is then an error of the mount.

Examples
--------
>>> import numpy as np
>>> from adapt.geometry import Camera
>>> cam = Camera.look_at(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
...                      position=(0, 0, 1), look_at=(0, 5, 1))
>>> panned = offset_camera(cam, (0.0, 0.0, 0.0), (90.0, 0.0, 0.0))
>>> panned.rotation[2].round(6).tolist()   # now looking along -x
[-1.0, 0.0, 0.0]
>>> offset_camera(cam, (0.1, 0.0, 0.0), (0.0, 0.0, 0.0), heading=np.pi / 2).position.round(6).tolist()
[0.0, 0.1, 1.0]
"""

from __future__ import annotations

import math

import numpy as np

from adapt.geometry import Camera, rotation_exp
from adapt.imagination.scene import Vec2
from adapt.scenario.records import CameraMount, CameraOffset, Mount

__all__ = ["draw_offset", "offset_camera", "nominal_camera"]

Vec3 = tuple[float, float, float]


def _direction(rng: np.random.Generator) -> np.ndarray:
    """A unit vector uniform on the sphere."""
    while True:
        v = rng.standard_normal(3)
        n = float(np.linalg.norm(v))
        if n > 1e-9:
            return v / n


def draw_offset(offset: CameraOffset, rng: np.random.Generator) -> tuple[Vec3, Vec3]:
    """The run's ``(position, rotation_deg)`` offset.

    A fixed offset is returned as given; a random magnitude is spread over a
    direction drawn from ``rng`` (position first, then rotation).

    Examples
    --------
    >>> import numpy as np
    >>> from adapt.scenario import CameraOffset
    >>> p, r = draw_offset(CameraOffset(random_rotation=2.0), np.random.default_rng(3))
    >>> p, round(float(np.linalg.norm(r)), 9)
    ((0.0, 0.0, 0.0), 2.0)
    """
    position = np.array(offset.position, float)
    rotation = np.array(offset.rotation_deg, float)
    if offset.random_position is not None:
        position = offset.random_position * _direction(rng)
    if offset.random_rotation is not None:
        rotation = offset.random_rotation * _direction(rng)
    p = (float(position[0]), float(position[1]), float(position[2]))
    r = (float(rotation[0]), float(rotation[1]), float(rotation[2]))
    return p, r


def offset_camera(nominal: Camera, position: Vec3, rotation_deg: Vec3,
                  heading: float | None = None) -> Camera:
    """The nominal camera moved by an offset.

    ``heading`` (radians) is the robot's for a camera on the robot: the
    position offset then turns with it; None for a fixed camera.
    """
    pan, tilt, roll = (math.radians(a) for a in rotation_deg)
    # World-to-camera R: panning the camera by +pan about world up turns its
    # camera-to-world rotation by Rz(pan), i.e. R <- R Rz(-pan); tilt and roll
    # turn it about its own axes, R <- Rz_cam(-roll) Rx_cam(-tilt) R.
    r = nominal.rotation @ rotation_exp([0.0, 0.0, -pan])
    r = rotation_exp([-tilt, 0.0, 0.0]) @ r
    r = rotation_exp([0.0, 0.0, -roll]) @ r
    d = np.array(position, float)
    if heading is not None:
        c, s = math.cos(heading), math.sin(heading)
        d = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ d
    return nominal.with_pose(r, nominal.position + d)


def nominal_camera(camera: Camera, mount: CameraMount, robot_position: Vec2 | None,
                   heading: float | None) -> Camera:
    """Where the scenario's camera is for a robot pose: the scenario camera
    itself when fixed; on the robot, the mount composed with the pose."""
    if robot_position is None or heading is None or mount.kind is Mount.FIXED:
        return camera
    p, t = mount.world_pose(robot_position, heading)
    return Camera.look_at(fx=camera.fx, fy=camera.fy, cx=camera.cx, cy=camera.cy,
                          width=camera.width, height=camera.height, position=p, look_at=t,
                          roll_deg=mount.roll_deg)
