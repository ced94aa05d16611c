"""``adapt render`` and ``adapt imagine``: the imagination from the command line.

``adapt render SCENARIO.yaml --out frame.png [--t SECONDS] [--labels L.png]``
    simulates the scenario to time ``t`` and writes what its camera sees.
``adapt imagine SCENARIO.yaml --horizon S [--json] [--video PATH]``
    predicts from the scenario's initial state and prints the contact events,
    the predicted positions and, when the scenario has a robot, the earliest
    intercept.

Every file is written atomically (a temporary file in the same directory,
then a rename), so nothing is left half-written.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from adapt.errors import AdaptError, ImaginationError
from adapt.files import atomic_path, write_atomic

__all__ = ["register"]


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """Add the ``render`` and ``imagine`` subcommands."""
    p = sub.add_parser("render", help="render a scenario's camera view at a time",
                       description="Simulate SCENARIO to time --t and write the camera image.")
    p.add_argument("scenario", metavar="SCENARIO.yaml")
    p.add_argument("--out", required=True, metavar="FRAME.png", help="image file to write")
    p.add_argument("--t", type=float, default=0.0, metavar="SECONDS",
                   help="simulated time to render (default 0)")
    p.add_argument("--labels", metavar="LABELS.png",
                   help="also write the label image (16-bit PNG of object ids)")
    p.add_argument("--seed", type=int, default=None, metavar="N",
                   help="random seed (default: the scenario's seed)")
    p.set_defaults(func=_render)

    q = sub.add_parser("imagine", help="predict a scenario ahead of time",
                       description="Predict SCENARIO from its initial state: contact events, "
                                   "positions and the robot's earliest intercept.")
    q.add_argument("scenario", metavar="SCENARIO.yaml")
    q.add_argument("--horizon", type=float, required=True, metavar="S", help="seconds ahead")
    q.add_argument("--json", action="store_true", help="print one JSON object")
    q.add_argument("--video", metavar="PATH", help="write the predicted view (.mp4 or .avi)")
    q.add_argument("--fps", type=float, default=30.0, metavar="FPS", help="video frame rate (default 30)")
    q.add_argument("--dt", type=float, default=None, metavar="SECONDS",
                   help="physics step in seconds (default: the scenario's, 1/240)")
    q.add_argument("--samples", type=int, default=None, metavar="N",
                   help="number of evenly spaced trajectory samples (default: 10 per second + 1)")
    q.add_argument("--body", default=None, metavar="NAME", help="ball to follow (default: the first)")
    q.add_argument("--seed", type=int, default=None, metavar="N",
                   help="random seed (default: the scenario's seed)")
    q.set_defaults(func=_imagine)


def _atomic_write(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, data)


def _check_image_path(path: Path, option: str, sixteen_bit: bool = False) -> None:
    """Refuse, before any work, an output path no image can be written to."""
    import cv2

    if path.is_dir():
        raise AdaptError(f"{option} {str(path)!r} is a directory; expected an image file name "
                         "such as frame.png")
    ext = path.suffix.lower()
    allowed = (".png", ".tif", ".tiff") if sixteen_bit else None
    if allowed is not None and ext not in allowed:
        raise AdaptError(f"{option} {str(path)!r}: the label image is 16-bit; expected a "
                         ".png or .tif file name")
    if not ext or not cv2.haveImageWriter(f"x{ext}"):
        raise AdaptError(f"{option} {str(path)!r}: cannot write images of type "
                         f"{ext or '(no extension)'!r}; expected .png, .jpg, .bmp or .tif")


def _encode(path: Path, image: Any) -> bytes:
    import cv2

    ext = path.suffix.lower() or ".png"
    ok, buf = cv2.imencode(ext, image)
    if not ok:
        raise AdaptError(f"cannot encode an image as {ext!r} for {str(path)!r}")
    return bytes(buf)


def _render(args: argparse.Namespace) -> int:
    import numpy as np

    from adapt.imagination import Renderer, World
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario)
    if not 0 <= args.t < float("inf"):
        raise ImaginationError(f"--t must be a non-negative number of seconds, got {args.t}")
    _check_image_path(Path(args.out), "--out")
    if args.labels:
        _check_image_path(Path(args.labels), "--labels", sixteen_bit=True)
    world = World(sc.scene, seed=sc.seed if args.seed is None else args.seed)
    world.run_until(args.t)
    out = Renderer(sc.scene, sc.camera).render(world.snapshot())
    target = Path(args.out)
    _atomic_write(target, _encode(target, out.image))
    if args.labels:
        lpath = Path(args.labels)
        _atomic_write(lpath, _encode(lpath, out.labels.astype(np.uint16)))
    print(f"wrote {target} ({sc.camera.width}x{sc.camera.height}, t={world.time:.4f} s)")
    return 0


def _imagine(args: argparse.Namespace) -> int:
    import numpy as np

    from adapt.imagination import World, intercept, rollout
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario)
    if not 0 < args.horizon < float("inf"):
        raise ImaginationError(f"--horizon must be a positive number of seconds, got {args.horizon}")
    if args.dt is not None and not args.dt > 0:
        raise ImaginationError(f"--dt must be a positive number of seconds, got {args.dt}")
    seed = sc.seed if args.seed is None else args.seed
    world = World(sc.scene, dt=args.dt, seed=seed)
    n = args.samples if args.samples is not None else int(round(args.horizon * 10)) + 1
    if n < 1:
        raise ImaginationError(f"--samples must be at least 1, got {n}")
    times = list(np.linspace(0.0, args.horizon, n)) if n > 1 else [args.horizon]
    path = rollout(world, args.horizon, times=times, body=args.body)
    dense = rollout(world, args.horizon, body=path.body)
    hit = None
    robot = sc.scene.robot
    if robot is not None:
        ball = sc.scene.ball(path.body)
        hit = intercept(dense, robot.position, robot.max_speed, robot.max_accel,
                        reach=ball.radius + (robot.radius if robot.shape == "disc"
                                             else min(robot.size) / 2.0))
    result: dict[str, Any] = {
        "scenario": str(args.scenario),
        "body": path.body,
        "dt": world.dt,
        "seed": seed,
        "horizon": args.horizon,
        "contacts": [
            {"t": c.time, "position": list(c.position), "surface": c.surface, "ball": c.ball,
             "speed": c.speed}
            for c in path.contacts
        ],
        "trajectory": [
            {"t": float(t), "position": p.tolist(), "velocity": v.tolist()}
            for t, p, v in zip(path.times, path.positions, path.velocities)
        ],
        "intercept": None if hit is None else {
            "t": hit.time, "position": list(hit.position), "travel": hit.travel,
            "robot": robot.name if robot else None,
        },
    }
    if args.video:
        result["video"] = _write_video(Path(args.video), sc, world, args.horizon, args.fps)
    if args.json:
        print(json.dumps(result))
        return 0
    print(f"{path.body}: {len(path.contacts)} contact(s) within {args.horizon:g} s "
          f"(dt = {world.dt:.6g} s)")
    for c in result["contacts"]:
        x, y = c["position"]
        print(f"  t={c['t']:7.3f} s  hit {c['surface']:<12} at ({x:+.3f}, {y:+.3f}) m"
              f"  speed {c['speed']:.3f} m/s")
    print("predicted positions:")
    for s in result["trajectory"]:
        (x, y), (vx, vy) = s["position"], s["velocity"]
        print(f"  t={s['t']:7.3f} s  ({x:+.3f}, {y:+.3f}) m  v=({vx:+.3f}, {vy:+.3f}) m/s")
    if robot is not None:
        if hit is None:
            print(f"intercept: {robot.name} cannot reach {path.body} within {args.horizon:g} s")
        else:
            print(f"intercept: {robot.name} meets {path.body} at t={hit.time:.3f} s at "
                  f"({hit.position[0]:+.3f}, {hit.position[1]:+.3f}) m after {hit.travel:.3f} m")
    if args.video:
        print(f"wrote {args.video} ({result['video']['frames']} frames)")
    return 0


def _write_video(path: Path, sc: Any, world: Any, horizon: float, fps: float) -> dict[str, Any]:
    import cv2

    from adapt.imagination import Renderer

    codecs = {".mp4": "mp4v", ".avi": "MJPG"}
    ext = path.suffix.lower()
    if ext not in codecs:
        raise AdaptError(f"--video {str(path)!r}: expected a .mp4 or .avi file name")
    if not fps > 0:
        raise AdaptError(f"--fps must be positive, got {fps}")
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, suffix=ext) as tmp:
        writer = cv2.VideoWriter(tmp, cv2.VideoWriter_fourcc(*codecs[ext]), fps,  # type: ignore[attr-defined]
                                 (sc.camera.width, sc.camera.height))
        if not writer.isOpened():
            raise AdaptError(f"OpenCV cannot write {ext} video here")
        renderer = Renderer(sc.scene, sc.camera)
        fork = world.fork()
        frames = int(horizon * fps) + 1
        t0 = fork.time
        for k in range(frames):
            fork.run_until(t0 + k / fps)
            writer.write(renderer.render(fork.snapshot()).image)
        writer.release()
    return {"path": str(path), "frames": frames, "fps": fps}
