"""``adapt mmd`` and ``adapt sync``: the vision subcommands.

``adapt mmd REAL SYNTH [--out DIR] [--json]`` compares a real image with a
synthetic one and prints (``--json``)::

    {"homography": [[...], [...], [...]] | null,   # synthetic pixels -> real pixels
     "inliers": n,
     "regions": [{"bbox": [x, y, w, h], "centroid": [x, y], "area": a,
                  "mean_difference": d, "expected": false}, ...],
     "ms": t,                                       # matching + H + warp + mask + difference + regions
     "aligned": true, "reason": "", "method": "lk", "known_fraction": f}

With ``--out`` it writes ``warped.png``, ``mask.png`` and ``mmd.png``.

``adapt sync SCENARIO.yaml --real IMAGE [--out DIR] [--gain G] [--max-iter N]
[--tolerance PX] [--json]`` starts the synthetic camera at the scenario's
nominal pose and turns it until the rendered view agrees with IMAGE, printing
``{"iterations": [{"iteration", "pixel_error", "inliers", "correction_deg",
"rotation", "position"}, ...], "converged", "reason", "camera": {"rotation",
"position"}}``.  With ``--out`` it writes one strip per step,
``step_NN.png`` (real | synthetic with its inlier corners | warped | mask |
MMD), and ``sync.json`` (the same JSON).

Every file is written atomically (temporary file, then rename).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

from adapt.errors import ImageError
from adapt.files import write_atomic

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add ``mmd`` and ``sync`` to the ``adapt`` subcommands."""
    p = sub.add_parser(
        "mmd",
        help="match-mediated difference of a real and a synthetic image",
        description="Align SYNTH to REAL by matched corners, and show what SYNTH does not explain.",
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
        "its rendered view agrees with the real image (paper eq. 3).",
    )
    s.add_argument("scenario", metavar="SCENARIO.yaml")
    s.add_argument("--real", metavar="IMAGE", required=True, help="the real image")
    s.add_argument("--out", metavar="DIR", help="write step_NN.png strips and sync.json here")
    s.add_argument("--gain", type=float, default=0.5, metavar="G", help="correction gain g in (0, 1] (default 0.5)")
    s.add_argument("--max-iter", type=int, default=10, metavar="N", help="most renders (default 10)")
    s.add_argument("--tolerance", type=float, default=0.5, metavar="PX", help="stop below this pixel error (default 0.5)")
    s.add_argument("--json", action="store_true", help="print the result as JSON")
    s.set_defaults(func=_run_sync)


def _out_dir(path: str | None) -> Path | None:
    if path is None:
        return None
    d = Path(path)
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
    }


def _run_mmd(args: argparse.Namespace) -> int:
    from adapt.vision.images import read_image, write_image
    from adapt.vision.mmd import mmd
    from adapt.vision.regions import find_regions, label_regions
    from adapt.vision.threads import DEFAULT_THREADS, set_threads

    set_threads(DEFAULT_THREADS)
    real = read_image(args.real)
    synthetic = read_image(args.synthetic)
    out = _out_dir(args.out)
    t0 = time.perf_counter()
    result = mmd(real, synthetic, exact=args.exact_mask)
    regions = label_regions(find_regions(result.difference), [])
    ms = (time.perf_counter() - t0) * 1e3
    if out is not None:
        warped, mask, diff = _panels(result)
        write_image(out / "warped.png", warped)
        write_image(out / "mask.png", mask)
        write_image(out / "mmd.png", diff)
    data = _mmd_json(result, regions, ms)
    if args.json:
        print(json.dumps(data))
    else:
        if result.aligned:
            print(f"aligned: {result.n_inliers} inliers ({result.matches.method}), {ms:.1f} ms")
        else:
            print(f"no alignment: {result.alignment.reason} ({ms:.1f} ms)")
        for r in regions:
            x, y, w, h = r.bbox
            print(f"  unexpected region at ({x}, {y}) {w}x{h}, area {r.area}, "
                  f"mean difference {r.mean_difference:.0f}")
        if out is not None:
            print(f"wrote {out / 'warped.png'}, {out / 'mask.png'}, {out / 'mmd.png'}")
    return 0


def _strip(real: Any, step: Any) -> Any:
    """Figure-4-style strip: real | synthetic with corners | warped | mask | MMD."""
    import cv2
    import numpy as np

    def bgr(img: Any) -> Any:
        from adapt.vision.images import as_uint8

        u8 = as_uint8(img)
        return cv2.cvtColor(u8, cv2.COLOR_GRAY2BGR) if u8.ndim == 2 else u8

    res = step.result
    syn = bgr(step.synthetic).copy()
    inl = res.alignment.inliers
    for (x, y), good in zip(res.matches.synthetic_points, inl):
        cv2.circle(syn, (int(round(x)), int(round(y))), 3, (0, 255, 0) if good else (0, 0, 255), 1,
                   cv2.LINE_AA)
    warped, mask, diff = _panels(res)
    panels = [bgr(real), syn, bgr(warped), bgr(mask), bgr(diff)]
    text = f"step {step.iteration}: error {step.pixel_error:.2f} px, {step.n_inliers} inliers"
    cv2.putText(panels[0], text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 255, 255), 1, cv2.LINE_AA)
    return np.hstack(panels)


def _run_sync(args: argparse.Namespace) -> int:
    import numpy as np

    from adapt.errors import VisionError
    from adapt.imagination import Renderer
    from adapt.scenario import load_scenario
    from adapt.vision.images import read_image, write_image
    from adapt.vision.sync import synchronise
    from adapt.vision.threads import DEFAULT_THREADS, set_threads

    if not 0.0 < args.gain <= 1.0:
        raise VisionError(f"--gain must be in (0, 1], got {args.gain}")
    if args.max_iter < 1:
        raise VisionError(f"--max-iter must be at least 1, got {args.max_iter}")
    set_threads(DEFAULT_THREADS)
    scenario = load_scenario(args.scenario)
    real = read_image(args.real)
    cam = scenario.camera
    if real.shape[:2] != (cam.height, cam.width):
        raise VisionError(
            f"{args.real} is {real.shape[1]}x{real.shape[0]} pixels but the scenario's camera "
            f"renders {cam.width}x{cam.height}: use an image of the camera's size"
        )
    if real.ndim == 2:
        import cv2

        real = cv2.cvtColor(real, cv2.COLOR_GRAY2BGR)  # type: ignore[assignment]
    out = _out_dir(args.out)
    renderer = Renderer(scenario.scene, cam)

    def render(camera: Any) -> Any:
        return renderer.with_camera(camera).render().image

    result = synchronise(
        real, cam, render, gain=args.gain, tolerance=args.tolerance, max_iterations=args.max_iter
    )
    data = {
        "iterations": [s.as_dict() for s in result.steps],
        "converged": result.converged,
        "reason": result.reason,
        "camera": {
            "rotation": np.round(result.camera.rotation, 8).tolist(),
            "position": np.round(result.camera.position, 8).tolist(),
        },
    }
    if out is not None:
        for step in result.steps:
            write_image(out / f"step_{step.iteration:02d}.png", _strip(real, step))
        _write_json(out / "sync.json", data)
    if args.json:
        print(json.dumps(data))
    else:
        for s in result.steps:
            print(f"step {s.iteration}: pixel error {s.pixel_error:.3f}, {s.n_inliers} inliers, "
                  f"turned {s.correction_deg:.3f} deg")
        print(("converged: " if result.converged else "not converged: ") + result.reason)
    return 0 if result.converged else 1
