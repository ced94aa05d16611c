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
from adapt.files import Output, check_outputs, write_output

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
    from adapt.vision.images import encode_image

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
    encoded = [(Output("--out", Path(args.out)), encode_image(args.out, out.image))]
    if args.labels:
        encoded.append((Output("--labels", Path(args.labels)),
                        encode_image(args.labels, out.labels.astype(np.uint16))))
    for output, data in encoded:
        write_output(output, data)
    print(f"wrote {args.out} ({sc.camera.width}x{sc.camera.height}, t={world.time:.4f} s)")
    return 0


def _imagine(args: argparse.Namespace) -> int:
    from adapt.imagination.outlook import look_ahead
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario)
    _check_imagine_args(args)
    video = Path(args.video) if args.video else None
    if video is not None:
        _check_video(video, args.fps, args.horizon)
        _check_outputs([("--video", video)], sc.inputs())
    seed = sc.seed if args.seed is None else args.seed
    world = _world(sc, args.dt, seed)
    outlook = look_ahead(world, args.horizon, samples=args.samples, body=args.body,
                         what="--horizon")
    result = _outlook_json(args, outlook, seed)
    if video is not None:
        result["video"] = _write_video(video, sc, world, args.horizon, args.fps)
    if args.json:
        print(json.dumps(result))
        return 0
    for line in _outlook_lines(args, outlook, result):
        print(line)
    return 0


def _check_imagine_args(args: argparse.Namespace) -> None:
    import math

    from adapt.imagination import MAX_SAMPLES

    if not (math.isfinite(args.horizon) and args.horizon > 0):
        raise ImaginationError(f"--horizon must be a positive number of seconds, got {args.horizon}")
    if args.dt is not None and not args.dt > 0:
        raise ImaginationError(f"--dt must be a positive number of seconds, got {args.dt}")
    if args.samples is not None and not 1 <= args.samples <= MAX_SAMPLES:
        raise ImaginationError(f"--samples must be from 1 to {MAX_SAMPLES:,}, got {args.samples}")


def _outlook_json(args: argparse.Namespace, outlook: Any, seed: int | None) -> dict[str, Any]:
    path, hit = outlook.path, outlook.meeting
    return {
        "scenario": str(args.scenario), "body": path.body, "dt": outlook.dt, "seed": seed,
        "horizon": args.horizon,
        "contacts": [{"t": c.time, "position": list(c.position), "surface": c.surface,
                      "ball": c.ball, "speed": c.speed} for c in path.contacts],
        "trajectory": [{"t": float(t), "position": p.tolist(), "velocity": v.tolist()}
                       for t, p, v in zip(path.times, path.positions, path.velocities)],
        "intercept": None if hit is None else {
            "t": hit.time, "position": list(hit.position), "travel": hit.travel,
            "robot": outlook.robot},
    }


def _outlook_lines(args: argparse.Namespace, outlook: Any, result: dict[str, Any]) -> list[str]:
    path, hit, robot = outlook.path, outlook.meeting, outlook.robot
    lines = [f"{path.body}: {len(path.contacts)} contact(s) within {args.horizon:g} s "
             f"(dt = {outlook.dt:.6g} s)"]
    for c in result["contacts"]:
        x, y = c["position"]
        lines.append(f"  t={c['t']:7.3f} s  hit {c['surface']:<12} at ({x:+.3f}, {y:+.3f}) m"
                     f"  speed {c['speed']:.3f} m/s")
    lines.append("predicted positions:")
    for s in result["trajectory"]:
        (x, y), (vx, vy) = s["position"], s["velocity"]
        lines.append(f"  t={s['t']:7.3f} s  ({x:+.3f}, {y:+.3f}) m  v=({vx:+.3f}, {vy:+.3f}) m/s")
    if robot is not None and hit is None:
        lines.append(f"intercept: {robot} cannot reach {path.body} within {args.horizon:g} s")
    elif robot is not None:
        lines.append(f"intercept: {robot} meets {path.body} at t={hit.time:.3f} s at "
                     f"({hit.position[0]:+.3f}, {hit.position[1]:+.3f}) m after {hit.travel:.3f} m")
    if "video" in result:
        lines.append(f"wrote {args.video} ({result['video']['frames']} frames)")
    return lines


def _check_video(path: Path, fps: float, horizon: float) -> None:
    import math

    from adapt.frames import VIDEO_CODECS

    if path.suffix.lower() not in VIDEO_CODECS:
        raise AdaptError(f"--video {str(path)!r}: expected a .mp4 or .avi file name")
    if not (math.isfinite(fps) and 0 < fps <= MAX_FPS):
        raise AdaptError(f"--fps must be a positive number up to {MAX_FPS:g}, got {fps}")
    frames = int(horizon * fps) + 1
    if frames > MAX_VIDEO_FRAMES:
        raise AdaptError(f"--video: {horizon:g} s at {fps:g} frames/s is {frames:,} frames; "
                         f"at most {MAX_VIDEO_FRAMES:,}: shorten --horizon or lower --fps")


def _write_video(path: Path, sc: Any, world: Any, horizon: float, fps: float) -> dict[str, Any]:
    from adapt.frames import VideoSink
    from adapt.imagination.outlook import frames_ahead

    try:
        with VideoSink(path, fps, (sc.camera.width, sc.camera.height)) as sink:
            for image in frames_ahead(world, sc.camera, horizon, fps):
                sink.write(image)
    except OSError as exc:
        raise AdaptError(f"--video {str(path)!r}: cannot write it ({exc.strerror or exc})") from None
    except AdaptError as exc:
        raise AdaptError(f"--video {str(path)!r}: {exc}") from None
    return {"path": str(path), "frames": sink.frames, "fps": fps}
