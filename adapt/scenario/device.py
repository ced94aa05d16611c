"""Reading ``reality: {kind: camera, ...}``: a device, a stream URL or a file played live.

``device`` is a device index (``0``, ``1``, ...), a stream URL (anything with
``://``: ``rtsp://host/stream``, ``http://host/video.mjpg``) or a video file,
relative to the scenario; ``fps`` the frame rate the run assumes (default:
the camera's stated one); ``stall_s`` how long the camera may deliver nothing
before the run ends as stalled (default 2 s).  Whether the device can be
opened is known only when the run opens it (:mod:`adapt.reality.live`),
with the position of ``device`` in the message.

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> head = ("camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60, "
...         "position: [0, -2, 1], look_at: [0, 1, 0]}\\nworld: {}\\n")
>>> sc = loads_scenario(head + "reality: {kind: camera, device: 0, fps: 30}\\n")
>>> sc.reality.device, sc.reality.fps, sc.reality.stall_s
(0, 30.0, 2.0)
>>> loads_scenario(head + "reality: {kind: camera, device: -1}\\n")
Traceback (most recent call last):
...
adapt.errors.ScenarioError: <string>:3:33: reality.device: expected a device index (0, 1, ...), a stream URL or a video file, got -1
...
"""

from __future__ import annotations

from adapt.scenario.bounds import bound_of
from adapt.scenario.nodes import Node, NodeReader, join
from adapt.scenario.records import CameraReality

__all__ = ["read_camera_reality", "CAMERA_REALITY_KEYS", "DEFAULT_STALL_S"]

#: The keys of a camera reality, in the documentation's order.
CAMERA_REALITY_KEYS = ("kind", "device", "fps", "stall_s")
#: Seconds without a frame after which a camera has stalled, by default.
DEFAULT_STALL_S = 2.0


def read_camera_reality(reader: NodeReader, node: Node, path: str) -> CameraReality:
    """A ``reality`` section of ``kind: camera``."""
    items = reader.mapping(node, path)
    reader.check_keys(items, CAMERA_REALITY_KEYS, path)
    if "device" not in items:
        raise reader.error(node, path, "missing key 'device' (a device index such as 0, a "
                           "stream URL, or a video file)")
    dnode = items["device"][1]
    dpath = join(path, "device")
    value = reader.scalar(dnode, dpath)
    device: int | str
    if isinstance(value, int) and not isinstance(value, bool) and value >= 0:
        problem = bound_of(dpath).problem(value)
        if problem is not None:
            raise reader.error(dnode, dpath, f"a device index: {problem}")
        device = value
    elif isinstance(value, str) and "://" in value:
        device = value
    elif isinstance(value, str) and value:
        device = str(reader.existing_file(dnode, dpath, "camera file"))
    else:
        raise reader.error(dnode, dpath, "expected a device index (0, 1, ...), a stream URL or "
                           f"a video file, got {reader.describe(dnode)}")
    fps = reader.number(items["fps"][1], join(path, "fps")) if "fps" in items else None
    stall = DEFAULT_STALL_S
    if "stall_s" in items:
        stall = reader.number(items["stall_s"][1], join(path, "stall_s"))
    return CameraReality(device, fps, stall, reader.source(node, path))
