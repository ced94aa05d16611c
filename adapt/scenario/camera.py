"""A camera written back as the scenario's own ``camera`` keys (``adapt sync`` prints it).

:func:`camera_keys` is the inverse of reading the ``camera`` section: the
intrinsics, ``position``, ``look_at`` and ``roll_deg`` of a camera, in the
robot's frame at its starting pose for a camera on the robot
(:meth:`CameraMount.mount_pose <adapt.scenario.records.CameraMount.mount_pose>`);
:func:`camera_yaml` is that section as YAML text to paste over the
scenario's.

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> sc = loads_scenario("camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60, "
...                     "position: [0, -2, 1], look_at: [0, 1, 0]}\\nworld: {}\\n")
>>> keys = camera_keys(sc.camera, sc)
>>> keys["position"], keys["roll_deg"]
([0.0, -2.0, 1.0], 0.0)
>>> print(camera_yaml(keys, "as read"))  # doctest: +ELLIPSIS
camera:                     # as read: paste over the scenario's camera
  fx: 100.0
...
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from adapt.geometry import Camera, look_at_parameters
from adapt.scenario.records import Mount

if TYPE_CHECKING:  # pragma: no cover
    from adapt.scenario import Scenario

__all__ = ["camera_keys", "camera_yaml", "CAMERA_YAML_KEYS"]

#: The keys :func:`camera_yaml` writes, in the scenario's order.
CAMERA_YAML_KEYS = ("fx", "fy", "cx", "cy", "width", "height", "position", "look_at", "roll_deg",
                    "mount")


def camera_keys(camera: Camera, scenario: "Scenario") -> dict[str, Any]:
    """The scenario's ``camera`` keys of ``camera`` (and its world ``rotation``).

    The ``look_at`` is put at the distance of the scenario's own, so the two are easy
    to compare (any point on the viewing axis gives the same camera); for a camera on
    the robot, ``position`` and ``look_at`` are given in the robot's frame at its
    starting pose, as the scenario writes them.

    Raises
    ------
    ImaginationError
        For a camera looking straight up or down (it has no ``look_at`` and roll).
    """
    mount = scenario.mount
    distance = float(np.linalg.norm(np.subtract(mount.look_at, mount.position)))
    target, roll = look_at_parameters(camera.rotation, camera.position,
                                      distance if distance > 0 else 1.0)
    position = np.asarray(camera.position, float)
    robot = scenario.scene.robot
    on_robot = mount.kind is Mount.ROBOT and robot is not None
    if on_robot:
        assert robot is not None
        position, target = mount.mount_pose(position, target, robot.position,
                                            math.radians(robot.heading_deg))
    keys: dict[str, Any] = {
        "fx": float(camera.fx), "fy": float(camera.fy), "cx": float(camera.cx),
        "cy": float(camera.cy), "width": int(camera.width), "height": int(camera.height),
        "position": [round(float(v), 6) + 0.0 for v in position],  # + 0.0: no "-0.0"
        "look_at": [round(float(v), 6) + 0.0 for v in target],
        "roll_deg": round(roll, 5) + 0.0,
    }
    if on_robot:
        keys["mount"] = "robot"
    keys["rotation"] = np.round(camera.rotation, 8).tolist()
    return keys


def camera_yaml(keys: dict[str, Any], note: str) -> str:
    """The ``camera`` section of ``keys`` as YAML text, with ``note`` on its first line."""
    lines = [f"camera:                     # {note}: paste over the scenario's camera"]
    for k in CAMERA_YAML_KEYS:
        if k not in keys:
            continue
        v = keys[k]
        text = "[" + ", ".join(repr(x) for x in v) + "]" if isinstance(v, list) else repr(v)
        lines.append(f"  {k}: {text}")
    return "\n".join(lines)
