"""Cost of one synthetic-reality frame at 640x480, and of a PyBullet reality's (figures, not tests).

Run ``python bench/reality.py`` (about a minute; ``--bullet`` for the PyBullet
reality's figures instead, which need ``pip install 'adapt[bullet]'``).  The scene is the bundled room (`scenarios/room.yaml`)
with a reality section that turns every effect on (drag, spin, a thrown
object of reality only, a camera offset, tint, gradient, contrast, colour
shift, blur, noise, texture scale and phase, spin markers).  Opening the
source (drawing, building the world, the phased surface textures) is
printed apart.  It prints the median
cost of a whole frame (physics to the frame's time + render + spin markers
+ appearance + truth) for a fixed camera and for a camera on a moving
robot, the share of each stage, and -- as a peer measured in the same
process -- the imagination rendering the same state over its cached
background.

With ``--bullet``: the median cost of a frame of ``scenarios/foreign-fixed.yaml``
(a fixed camera over the arena) and ``foreign-robot.yaml`` (a camera on a moving
robot) at 640x480 and 320x240, stage by stage (PyBullet's physics to the
frame's time, the true camera, TinyRenderer, the sensor, the truth), beside the
synthetic reality's fixed-camera frame of the same size in the same process.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from adapt.imagination import LABEL_BALL, Renderer  # noqa: E402
from adapt.reality import SyntheticSource  # noqa: E402
from adapt.reality.appearance import draw_spin_marker  # noqa: E402
from adapt.scenario import loads_scenario  # noqa: E402
from adapt.seeds import Streams  # noqa: E402

REALITY = """
reality:
  camera_offset: 0.02
  camera_offset_deg: 1.5
  appearance: {brightness: 8, contrast: 1.1, color_shift: [5, 0, -5], gradient: 0.3,
               gradient_deg: 20, blur: 0.8, noise: 3, texture_scale: 1.15,
               tint: [0.95, 1.0, 1.08], texture_phase: [0.23, 0.11], spin_marker: true}
  robot: {slip: 0.1}
  objects:
    - {name: ball, restitution: [0.6, 0.8], drag: 0.05, spin: 0.4}
    - {name: box, radius: 0.15, color: [20, 200, 20],
       throw: {t: 0.2, x: 1.5, y: 0.5, speed: 1, heading_deg: 150}}
run: {fps: 30, max_frames: 200}
"""

FRAMES = 90
OPENING: list[float] = []


def scenario(robot_camera: bool):  # type: ignore[no-untyped-def]
    text = (ROOT / "scenarios" / "room.yaml").read_text()
    if robot_camera:
        text = text.replace("  position: [0.0, -0.6, 0.6]\n  look_at: [0.0, 3.0, 0.3]\n",
                            "  position: [0.1, 0.0, 0.6]\n  look_at: [2.0, 0.0, 0.3]\n"
                            "  mount: robot\n")
    return loads_scenario(text + REALITY)


def stages(robot_camera: bool) -> dict[str, list[float]]:
    """The same work as SyntheticSource.frame, stage by stage."""
    t = time.perf_counter()
    src = SyntheticSource(scenario(robot_camera), streams=Streams(1))
    OPENING.append(time.perf_counter() - t)
    if robot_camera:
        src.robot.command_robot((0.3, 0.4), 0.5)
    out: dict[str, list[float]] = {k: [] for k in ("physics", "camera", "render", "markers",
                                                  "appearance", "truth", "peer render")}
    look = src.look
    rng = np.random.default_rng(0)
    renderer = src.renderer
    peer = Renderer(src.scene, src.scenario.camera)
    for i in range(FRAMES):
        t0 = time.perf_counter()
        src.world.run_until(i / src.fps)
        t1 = time.perf_counter()
        cam = src.camera()
        t2 = time.perf_counter()
        if not (np.array_equal(renderer.camera.rotation, cam.rotation)
                and np.array_equal(renderer.camera.position, cam.position)):
            renderer = renderer.with_camera(cam)   # as the source does: the backdrop is shared
        state = src.world.state()
        r = renderer.render(state)
        t3 = time.perf_counter()
        image = r.image
        for k, ball in enumerate(src.scene.balls):
            if ball.name in state.names:
                x, y = state.body(ball.name).position
                draw_spin_marker(image, r.labels, cam, (x, y, ball.radius), ball.radius,
                                 src.world.orientation(ball.name), LABEL_BALL + k)
        t4 = time.perf_counter()
        look.apply(image, r.labels, rng)
        t5 = time.perf_counter()
        src.truth.record(src.frame_truth(i, i / src.fps, cam))
        t6 = time.perf_counter()
        peer.render(state)
        t7 = time.perf_counter()
        if i == 0:
            continue
        for k, v in zip(out, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t6 - t5, t7 - t6)):
            out[k].append(v)
    return out


SMALL = ("camera.width=320", "camera.height=240", "camera.cx=159.5", "camera.cy=119.5")


def bullet_stages(name: str, small: bool, frames: int) -> dict[str, list[float]]:
    """The same work as BulletSource.frame, stage by stage."""
    from adapt.reality.bullet import BulletSource
    from adapt.reality.bullet.view import render
    from adapt.scenario import load_scenario

    sc = load_scenario(ROOT / "scenarios" / name)
    if small:
        f = sc.camera.fx / 2
        sc = load_scenario(ROOT / "scenarios" / name,
                           overrides=[*SMALL, f"camera.fx={f}", f"camera.fy={f}"])
    t = time.perf_counter()
    src = BulletSource(sc, streams=Streams(1))
    OPENING.append(time.perf_counter() - t)
    if src.robot is not None:
        src.robot.command_robot((0.3, 0.4), 0.5)
    out: dict[str, list[float]] = {k: [] for k in ("physics", "camera", "render", "sensor",
                                                  "truth")}
    rng = np.random.default_rng(0)
    for i in range(frames):
        t0 = time.perf_counter()
        src.run_until(i / src.fps)
        t1 = time.perf_counter()
        cam = src.camera()
        t2 = time.perf_counter()
        rgb, seg = render(src.client, cam, src.drawn.look)
        t3 = time.perf_counter()
        src.sensor.apply(rgb, seg, rng)
        t4 = time.perf_counter()
        src.truth.record(src.frame_truth(i, i / src.fps, cam, seg))
        t5 = time.perf_counter()
        if i == 0:
            continue
        for k, v in zip(out, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4)):
            out[k].append(v)
    src.close()
    return out


def synthetic_peer(small: bool, frames: int) -> float:
    """Median seconds of a whole synthetic fixed-camera frame of the same size."""
    text = (ROOT / "scenarios" / "room.yaml").read_text()
    sc = loads_scenario(text + REALITY, overrides=(*SMALL, "camera.fx=262.5", "camera.fy=262.5")
                        if small else ())
    src = SyntheticSource(sc, streams=Streams(1))
    times = []
    for i in range(frames):
        t = time.perf_counter()
        src.frame(i)
        times.append(time.perf_counter() - t)
    return statistics.median(times[1:])


def bullet(frames: int) -> int:
    cv2.setNumThreads(1)
    print(f"one PyBullet-reality frame: PyBullet's physics to the frame's time + true camera + "
          f"TinyRenderer + sensor + truth; medians of {frames - 1} frames, OpenCV 1 thread")
    for small in (False, True):
        size = "320x240" if small else "640x480"
        peer = synthetic_peer(small, frames)
        for name, label in (("foreign-fixed.yaml", "fixed camera over the arena"),
                            ("foreign-robot.yaml", "camera on a moving robot")):
            runs = bullet_stages(name, small, frames)
            whole = statistics.median([sum(v) for v in zip(*runs.values())])
            parts = {k: statistics.median(v) for k, v in runs.items()}
            print(f"{size}, {label} ({name}): {whole * 1e3:.1f} ms ({1 / whole:.1f} frames/s); "
                  f"the synthetic reality's frame (fixed camera) {peer * 1e3:.1f} ms: "
                  f"{whole / peer:.1f}x that")
            print("  " + "  ".join(f"{k} {v * 1e3:.2f} ms ({100 * v / sum(parts.values()):.0f}%)"
                                   for k, v in parts.items()))
    print(f"opening a PyBullet reality (draws, textures, bodies, the contacts' calibration): "
          f"median {statistics.median(OPENING) * 1e3:.0f} ms")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bullet", action="store_true", help="the PyBullet reality's figures")
    ap.add_argument("--frames", type=int, default=FRAMES)
    args = ap.parse_args()
    if args.bullet:
        return bullet(args.frames)
    print("one 640x480 synthetic frame: physics to the frame's time + true camera + render + "
          f"spin markers + appearance + truth; medians of {FRAMES - 1} frames")
    for threads in (1, 2):
        cv2.setNumThreads(threads)
        for robot_camera in (False, True):
            label = "camera on a moving robot" if robot_camera else "fixed camera"
            runs = stages(robot_camera)
            peer = statistics.median(runs.pop("peer render"))
            totals = [sum(v) for v in zip(*runs.values())]
            whole = statistics.median(totals)
            parts = {k: statistics.median(v) for k, v in runs.items()}
            print(f"{label}, OpenCV threads = {threads}: {whole * 1e3:.1f} ms "
                  f"({1 / whole:.0f} frames/s)")
            shares = "  ".join(f"{k} {v * 1e3:.2f} ms ({100 * v / sum(parts.values()):.0f}%)"
                               for k, v in parts.items())
            print(f"  {shares}")
            print(f"  peer (the imagination rendering the same state over its cached background): "
                  f"{peer * 1e3:.2f} ms; a reality frame costs {whole / peer:.1f}x that")
    print(f"opening a source (with the phased textures of 5 surfaces): median "
          f"{statistics.median(OPENING) * 1e3:.0f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
