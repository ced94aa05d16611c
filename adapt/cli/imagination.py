"""``adapt render`` and ``adapt imagine``: the imagination from the command line.

``adapt render SCENARIO.yaml --out frame.png [--t SECONDS] [--labels L.png]``
    simulates the scenario to time ``t`` and writes what its camera sees.
``adapt imagine SCENARIO.yaml --horizon S [--json] [--video PATH]``
    predicts from the scenario's initial state and prints the contact events,
    the predicted positions and, when the scenario has a robot, the earliest
    intercept.

Before any work, every output path is checked: two outputs may not be one
file, no output may be an input (the scenario or one of its textures), and
each must be a writable file name.  Every file is then written atomically (a
temporary file in the same directory, then a rename), so nothing is left
half-written.  The work is bounded by the imagination's documented limits
(``docs/imagination.md``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any, Iterable

from adapt.cli.values import seed_number
from adapt.errors import AdaptError, ImaginationError
from adapt.files import Output, atomic_path, check_outputs, write_output

#: Most frames ``imagine --video`` writes (20 minutes at 30 frames/s).
MAX_VIDEO_FRAMES = 36_000
#: Highest ``--fps``.
MAX_FPS = 1000.0

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
    p.add_argument("--seed", type=seed_number, default=None, metavar="N",
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
    q.add_argument("--seed", type=seed_number, default=None, metavar="N",
                   help="random seed (default: the scenario's seed)")
    q.set_defaults(func=_imagine)


def _check_outputs(outputs: Iterable[tuple[str, Path]], inputs: Any) -> None:
    """Refuse, before any work, outputs that would collide, replace an input, or
    cannot be written (:func:`adapt.files.check_outputs`)."""
    check_outputs([Output(option, path) for option, path in outputs], inputs)


def _write(path: Path, data: bytes, option: str) -> None:
    """Write atomically, creating missing folders; errors name the output, never a temporary file."""
    write_output(Output(option, path), data)


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


def _world(sc: Any, dt: float | None, seed: int | None, option: str = "--dt") -> Any:
    from adapt.imagination import World

    try:
        return World(sc.scene, dt=dt, seed=seed)
    except ImaginationError as exc:
        msg = str(exc)
        if dt is not None and msg.startswith("dt: "):
            raise ImaginationError(f"{option}: {msg[len('dt: '):]}") from None
        raise


def _render(args: argparse.Namespace) -> int:
    import math

    import numpy as np

    from adapt.imagination import Renderer
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario)
    if not (math.isfinite(args.t) and args.t >= 0):
        raise ImaginationError(f"--t must be a non-negative number of seconds, got {args.t}")
    outputs = [("--out", Path(args.out))]
    _check_image_path(Path(args.out), "--out")
    if args.labels:
        _check_image_path(Path(args.labels), "--labels", sixteen_bit=True)
        outputs.append(("--labels", Path(args.labels)))
    _check_outputs(outputs, sc.inputs())
    world = _world(sc, None, sc.seed if args.seed is None else args.seed)
    world.steps_for(args.t, "--t")  # refuses, before any work, a time too far ahead
    world.run_until(args.t)
    out = Renderer(sc.scene, sc.camera).render(world.snapshot(), balls=world.balls)
    target = Path(args.out)
    encoded = [(target, _encode(target, out.image), "--out")]
    if args.labels:
        lpath = Path(args.labels)
        encoded.append((lpath, _encode(lpath, out.labels.astype(np.uint16)), "--labels"))
    for path, data, option in encoded:
        _write(path, data, option)
    print(f"wrote {target} ({sc.camera.width}x{sc.camera.height}, t={world.time:.4f} s)")
    return 0


def _imagine(args: argparse.Namespace) -> int:
    import math

    import numpy as np

    from adapt.imagination import MAX_SAMPLES, intercept, intercept_reach, rollout
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario)
    if not (math.isfinite(args.horizon) and args.horizon > 0):
        raise ImaginationError(f"--horizon must be a positive number of seconds, got {args.horizon}")
    if args.dt is not None and not args.dt > 0:
        raise ImaginationError(f"--dt must be a positive number of seconds, got {args.dt}")
    if args.samples is not None and not 1 <= args.samples <= MAX_SAMPLES:
        raise ImaginationError(f"--samples must be from 1 to {MAX_SAMPLES:,}, got {args.samples}")
    video = Path(args.video) if args.video else None
    if video is not None:
        _check_video(video, args.fps, args.horizon)
        _check_outputs([("--video", video)], sc.inputs())
    seed = sc.seed if args.seed is None else args.seed
    world = _world(sc, args.dt, seed)
    steps = world.steps_for(args.horizon, "--horizon")
    n = args.samples if args.samples is not None else min(int(round(args.horizon * 10)) + 1,
                                                          MAX_SAMPLES)
    times = list(np.linspace(0.0, args.horizon, n)) if n > 1 else [args.horizon]
    path = rollout(world, args.horizon, times=times, body=args.body)
    hit = None
    robot = sc.scene.robot
    if robot is not None:
        # Every step, or as many evenly spaced samples as a rollout keeps.
        fine = min(steps + 1, MAX_SAMPLES)
        dense = rollout(world, args.horizon, body=path.body,
                        times=None if fine == steps + 1 else list(np.linspace(0.0, args.horizon, fine)))
        hit = intercept(dense, robot.position, robot.max_speed, robot.max_accel,
                        reach=intercept_reach(sc.scene.ball(path.body), robot))
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
    if video is not None:
        result["video"] = _write_video(video, sc, world, args.horizon, args.fps)
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
    if video is not None:
        print(f"wrote {args.video} ({result['video']['frames']} frames)")
    return 0


_CODECS = {".mp4": "mp4v", ".avi": "MJPG"}


def _check_video(path: Path, fps: float, horizon: float) -> None:
    import math

    if path.suffix.lower() not in _CODECS:
        raise AdaptError(f"--video {str(path)!r}: expected a .mp4 or .avi file name")
    if not (math.isfinite(fps) and 0 < fps <= MAX_FPS):
        raise AdaptError(f"--fps must be a positive number up to {MAX_FPS:g}, got {fps}")
    frames = int(horizon * fps) + 1
    if frames > MAX_VIDEO_FRAMES:
        raise AdaptError(f"--video: {horizon:g} s at {fps:g} frames/s is {frames:,} frames; "
                         f"at most {MAX_VIDEO_FRAMES:,}: shorten --horizon or lower --fps")


def _write_video(path: Path, sc: Any, world: Any, horizon: float, fps: float) -> dict[str, Any]:
    import cv2

    from adapt.imagination import Renderer

    ext = path.suffix.lower()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path, suffix=ext) as tmp:
            writer = cv2.VideoWriter(tmp, cv2.VideoWriter_fourcc(*_CODECS[ext]), fps,  # type: ignore[attr-defined]
                                     (sc.camera.width, sc.camera.height))
            if not writer.isOpened():
                raise AdaptError(f"--video {str(path)!r}: OpenCV cannot write {ext} video here")
            renderer = Renderer(sc.scene, sc.camera)
            fork = world.fork()
            frames = int(horizon * fps) + 1
            t0 = fork.time
            for k in range(frames):
                fork.run_until(t0 + k / fps)
                writer.write(renderer.render(fork.snapshot(), balls=fork.balls).image)
            writer.release()
    except OSError as exc:
        raise AdaptError(f"--video {str(path)!r}: cannot write it ({exc.strerror or exc})") from None
    return {"path": str(path), "frames": frames, "fps": fps}
