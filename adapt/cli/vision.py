"""``adapt mmd`` and ``adapt sync``: the vision subcommands.

``adapt mmd REAL SYNTH [--out DIR] [--json] [--exact-mask]`` compares a real
image with a synthetic one and prints (``--json``)::

    {"homography": [[...], [...], [...]] | null,   # synthetic pixels -> real pixels
     "inliers": n,
     "regions": [{"bbox": [x, y, w, h], "centroid": [x, y], "area": a,
                  "mean_difference": d, "expected": false}, ...],
     "ms": t,                                       # matching + H + warp + mask + difference + regions
     "aligned": true, "reason": "", "method": "lk", "known_fraction": f,
     "working_size": [w, h]}

Homography and regions are in REAL's pixels.  With ``--out`` it writes
``warped.png``, ``mask.png`` and ``mmd.png`` (at the working resolution).  It
exits with :attr:`~adapt.cli.exits.Exit.NO_ALIGNMENT` (7) when the images
cannot be aligned.

``adapt sync SCENARIO.yaml --real IMAGE [--out DIR] [--gain G] [--max-iter N]
[--tolerance PX] [--full-pose] [--json]`` starts the synthetic camera at the
scenario's nominal pose and turns it until the rendered view agrees with
IMAGE.  It prints one line per iteration as it runs, one ``wrote`` line per
file, and the corrected camera as the scenario's own ``camera`` keys.  With
``--json`` the progress goes to standard error and standard output holds
``{"iterations": [{"iteration", "pixel_error", "inliers", "correction_deg",
"rotation", "position"}, ...], "converged", "outcome", "reason", "camera":
{"fx", "fy", "cx", "cy", "width", "height", "position", "look_at",
"roll_deg", "rotation"}}``.  With ``--out`` it writes one strip per step,
``step_NN.png`` (real | synthetic with its corners | warped | mask | MMD), as
the step completes, and ``sync.json`` (the same JSON) at the end.  Exit
status: 0 converged, 7 no alignment, 8 not converged within ``--max-iter``.

Every file is written atomically (temporary file, then rename), and no output
may be one of the inputs.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any, Iterable, Sequence

from adapt.cli.exits import Exit
from adapt.errors import AdaptError, ImageError, VisionError
from adapt.files import Input, Inputs, Output, check_outputs, write_atomic

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add ``mmd`` and ``sync`` to the ``adapt`` subcommands."""
    p = sub.add_parser(
        "mmd",
        help="match-mediated difference of a real and a synthetic image",
        description="Align SYNTH to REAL by matched corners, and show what SYNTH does not explain. "
        "Images larger than 640x480 are analysed at that many pixels; the homography and the "
        "regions are given in REAL's pixels. Exit status 7 when the images cannot be aligned.",
    )
    p.add_argument("real", metavar="REAL", help="the real (camera) image")
    p.add_argument("synthetic", metavar="SYNTH", help="the synthetic (rendered) image")
    p.add_argument("--out", metavar="DIR", help="write warped.png, mask.png and mmd.png here")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--exact-mask", action="store_true", help="use the exact (slow) mask")
    p.set_defaults(func=_run_mmd)

    s = sub.add_parser(
        "sync",
        help="synchronise a scenario's synthetic camera with a real image",
        description="Turn the synthetic camera from the scenario's nominal pose until "
        "its rendered view agrees with the real image (paper eq. 3), and print the corrected "
        "camera as scenario keys. Exit status 0 converged, 7 no alignment, 8 not converged "
        "within --max-iter.",
    )
    s.add_argument("scenario", metavar="SCENARIO.yaml")
    s.add_argument("--real", metavar="IMAGE", required=True, help="the real image")
    s.add_argument("--out", metavar="DIR", help="write step_NN.png strips and sync.json here")
    s.add_argument("--gain", type=float, default=0.5, metavar="G", help="correction gain g in (0, 1] (default 0.5)")
    s.add_argument("--max-iter", type=int, default=10, metavar="N", help="most renders (default 10)")
    s.add_argument("--tolerance", type=float, default=None, metavar="PX",
                   help="stop below this pixel error (default 0.5 at 640x480, scaled with the image)")
    s.add_argument("--full-pose", action="store_true",
                   help="also correct the position, from the floor's homography (floor-dominated views)")
    s.add_argument("--json", action="store_true", help="print the result as JSON (progress on stderr)")
    s.set_defaults(func=_run_sync)


def _refuse_overwriting(inputs: Sequence[tuple[str, str]], outputs: Sequence[Path],
                        more: Iterable[Input] = ()) -> None:
    """Raise before anything is written if an output is an input (``more``: a scenario's
    own) or cannot be written (:func:`adapt.files.check_outputs`; the folder is created
    later)."""
    check_outputs([Output("--out", p, (p.suffix,)) for p in outputs],
                  Inputs([*(Input(f"the input {path!r} ({what})", Path(path))
                            for what, path in inputs), *more]))


def _out_dir(path: str | None) -> Path | None:
    if path is None:
        return None
    d = Path(path)
    if d.exists() and not d.is_dir():
        raise ImageError(f"{path}: is a file, expected an output directory")
    try:
        d.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ImageError(f"{path}: cannot create the output directory ({exc.strerror or exc})") from exc
    return d


def _write_json(path: Path, data: object) -> None:
    try:
        write_atomic(path, (json.dumps(data, indent=2) + "\n").encode("utf-8"))
    except OSError as exc:
        raise ImageError(f"{path}: cannot write ({exc.strerror or exc})") from exc


def _panels(result: Any) -> tuple[Any, Any, Any]:
    """8-bit images of the warped synthetic image, the mask and the MMD image."""
    import numpy as np

    mask = np.clip(np.rint(result.mask * 255.0), 0, 255).astype(np.uint8)
    diff = np.clip(np.rint(result.difference), 0, 255).astype(np.uint8)
    return result.warped, mask, diff


def _size(shape: Sequence[int]) -> str:
    return f"{shape[1]}x{shape[0]}"


def _mmd_json(result: Any, regions: Any, ms: float) -> dict[str, object]:
    h = result.homography
    return {
        "homography": None if h is None else [[float(v) for v in row] for row in h],
        "inliers": result.n_inliers,
        "regions": [r.as_dict() for r in regions],
        "ms": round(ms, 2),
        "aligned": result.aligned,
        "reason": result.alignment.reason,
        "method": result.matches.method,
        "known_fraction": round(float(result.known.mean()), 4),
        "working_size": [result.frame.shape[1], result.frame.shape[0]],
    }


def _run_mmd(args: argparse.Namespace) -> int:
    from adapt.vision.images import check_pair, read_image, write_image
    from adapt.vision.mmd import mmd
    from adapt.vision.threads import DEFAULT_THREADS, set_threads

    names = ("warped.png", "mask.png", "mmd.png")
    if args.out is not None:
        _refuse_overwriting([("real", args.real), ("synthetic", args.synthetic)],
                           [Path(args.out) / n for n in names])
    set_threads(DEFAULT_THREADS)
    real = read_image(args.real)
    synthetic = read_image(args.synthetic)
    check_pair(real, synthetic, sources=(args.real, args.synthetic))
    out = _out_dir(args.out)
    t0 = time.perf_counter()
    result = mmd(real, synthetic, exact=args.exact_mask)
    regions = result.regions()
    ms = (time.perf_counter() - t0) * 1e3
    written = []
    if out is not None:
        for name, image in zip(names, _panels(result)):
            written.append(write_image(out / name, image))
    data = _mmd_json(result, regions, ms)
    if args.json:
        print(json.dumps(data))
    else:
        work = ""
        if result.frame.reduces:
            work = f", analysed at {_size(result.frame.shape)}"
        if result.aligned:
            print(f"aligned: {result.n_inliers} inliers ({result.matches.method}), {ms:.1f} ms{work}")
        else:
            print(f"no alignment: {result.alignment.reason} ({ms:.1f} ms{work})")
        for r in regions:
            x, y, w, h = r.bbox
            print(f"  unexpected region at ({x}, {y}) {w}x{h}, area {r.area}, "
                  f"mean difference {r.mean_difference:.0f}")
        for path in written:
            print(f"wrote {path}")
    return int(Exit.OK if result.aligned else Exit.NO_ALIGNMENT)


def _strip(path: Path, real: Any, step: Any) -> Path:
    """Figure-4-style strip: real | synthetic with corners | warped | mask | MMD."""
    from adapt.figures import Panel, write_strip

    res = step.result
    inl = res.alignment.inliers
    pts = res.matches.synthetic_points
    warped, mask, diff = _panels(res)
    if math.isnan(step.pixel_error):
        title = f"step {step.iteration}: no alignment ({res.alignment.reason})"
    else:
        title = (f"step {step.iteration}: pixel error {step.pixel_error:.2f} px, {step.n_inliers} inliers, "
                 f"correction {step.correction_deg:.3f} deg")
    row = [
        Panel("real", real),
        Panel("synthetic, corners (green: inliers, red: outliers)", step.synthetic,
              points=[(pts[inl], "lime"), (pts[~inl], "red")]),
        Panel("warped synthetic", warped),
        Panel("mask I_m", mask),
        Panel("MMD I_d (0-255)", diff, vmin=0, vmax=255),
    ]
    return write_strip(path, [row], title=title)


def _check_sync_args(args: argparse.Namespace) -> None:
    if not 0.0 < args.gain <= 1.0:
        raise VisionError(f"--gain must be in (0, 1], got {args.gain}")
    if args.max_iter < 1:
        raise VisionError(f"--max-iter must be at least 1, got {args.max_iter}")
    if args.max_iter > 1000:
        raise VisionError(f"--max-iter must be at most 1000, got {args.max_iter}")
    if args.tolerance is not None and not (math.isfinite(args.tolerance) and args.tolerance > 0):
        raise VisionError(f"--tolerance must be a positive number of pixels, got {args.tolerance}")


def _step_line(step: Any) -> str:
    if math.isnan(step.pixel_error):
        return f"step {step.iteration}: no alignment: {step.result.alignment.reason}"
    return (f"step {step.iteration}: pixel error {step.pixel_error:.3f} px, "
            f"{step.n_inliers} inliers ({step.result.matches.method}), "
            f"correction {step.correction_deg:.3f} deg")


def _run_sync(args: argparse.Namespace) -> int:
    from adapt.imagination import Renderer
    from adapt.scenario import load_scenario
    from adapt.vision.images import check_image, read_image
    from adapt.vision.sync import synchronise
    from adapt.vision.threads import DEFAULT_THREADS, set_threads

    _check_sync_args(args)
    scenario = load_scenario(args.scenario)
    if args.out is not None:  # nothing the scenario names either (its textures)
        outs = [Path(args.out) / f"step_{i:02d}.png" for i in range(args.max_iter)]
        _refuse_overwriting([("real", args.real)], outs + [Path(args.out) / "sync.json"],
                            scenario.inputs())
    set_threads(DEFAULT_THREADS)
    real = check_image(read_image(args.real), "real", source=args.real)
    cam = scenario.camera
    if real.shape[:2] != (cam.height, cam.width):
        raise VisionError(
            f"{args.real}: the image is {real.shape[1]}x{real.shape[0]} pixels but the scenario's "
            f"camera renders {cam.width}x{cam.height}: use an image of the camera's size"
        )
    out = _out_dir(args.out)
    progress = sys.stderr if args.json else sys.stdout

    def on_step(step: Any) -> None:
        print(_step_line(step), file=progress, flush=True)
        if out is not None:
            path = _strip(out / f"step_{step.iteration:02d}.png", real, step)
            print(f"wrote {path}", file=progress, flush=True)

    result = synchronise(real, cam, Renderer(scenario.scene, cam).view, gain=args.gain,
                         tolerance=args.tolerance, max_iterations=args.max_iter,
                         full_pose=args.full_pose, on_step=on_step)
    data = _sync_json(result, scenario)
    if out is not None:
        _write_json(out / "sync.json", data)
        print(f"wrote {out / 'sync.json'}", file=progress, flush=True)
    if args.json:
        print(json.dumps(data))
    else:
        _print_sync(result, data["camera"])
    return int({"converged": Exit.OK, "no alignment": Exit.NO_ALIGNMENT}.get(
        result.outcome, Exit.NOT_CONVERGED))


def _sync_json(result: Any, scenario: Any) -> dict[str, Any]:
    import numpy as np

    from adapt.scenario.camera import camera_keys

    try:
        keys = camera_keys(result.camera, scenario)
    except AdaptError:  # a camera looking straight up or down has no look_at / roll
        keys = {"rotation": np.round(result.camera.rotation, 8).tolist(),
                "position": np.round(result.camera.position, 8).tolist()}
    return {"iterations": [s.as_dict() for s in result.steps], "converged": result.converged,
            "outcome": result.outcome, "reason": result.reason, "camera": keys}


def _print_sync(result: Any, keys: dict[str, Any]) -> None:
    from adapt.scenario.camera import camera_yaml

    print(("converged: " if result.converged else "not converged: ") + result.reason)
    moved = result.converged or len(result.steps) > 1 or result.outcome == "iteration limit"
    if "look_at" in keys and moved:
        note = ("synchronised with the real image" if result.converged
                else "after the last correction (not converged)")
        print(camera_yaml(keys, note))
    elif moved:
        print(f"camera rotation {keys['rotation']}, position {keys['position']}")
