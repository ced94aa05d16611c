"""Camera and lens benchmark (issue 22): undistortion per frame, and encoding ``mmd.mp4``.

Run as ``python bench/camera.py`` (about half a minute on 2 cores).  Prints medians of
repeated timings, each beside a peer timed in the same process:

* undistorting a 640x480 BGR frame with the maps made once (``cv2.remap``, what the
  runner does per frame), against ``cv2.undistort`` (maps made every call) and against a
  plain copy of the frame;
* making the maps once (``cv2.initUndistortRectifyMap``), and the distorted view of a
  synthetic reality (the inverse maps, made once, then ``cv2.remap``);
* writing one ``mmd.mp4`` frame (three 640x480 panels and the caption bar: 1920x496, moving,
  with sensor noise) as VP9 (``vp09``: browsers play it) and as MPEG-4 Part 2 (``mp4v``,
  the default).  Encoding VP9 is slower still on a run's real panels (``docs/performance.md``).

``--json`` prints the figures as JSON.  Timings on the shared machine are noisy: read the
ratios against the peers.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from adapt.frames import VideoSink  # noqa: E402
from adapt.lens import Distorter, Lens, Undistorter  # noqa: E402

SIZE = (640, 480)
#: A wide-angle webcam's lens: strong barrel distortion and a little tangential.
COEFFS = (-0.32, 0.12, 0.001, -0.0008, -0.02)


def frame(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    img = (rng.random((SIZE[1], SIZE[0], 3)) * 255).astype(np.uint8)
    return np.asarray(cv2.GaussianBlur(img, (0, 0), 3), np.uint8)


def median_ms(fn, repeats: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for i in range(repeats):
        t0 = time.perf_counter()
        fn(i)
        times.append(1000.0 * (time.perf_counter() - t0))
    return statistics.median(times)


def lens_figures(repeats: int) -> dict[str, float]:
    lens = Lens.pinhole(525.0, 525.0, 319.5, 239.5, SIZE, COEFFS)
    frames = [frame(i) for i in range(8)]
    undistort = Undistorter(lens)
    k, d = np.asarray(lens.matrix), np.asarray(lens.distortion)
    out = {
        "undistort_ms": median_ms(lambda i: undistort(frames[i % 8]), repeats),
        "cv2_undistort_ms": median_ms(lambda i: cv2.undistort(frames[i % 8], k, d), repeats),
        "copy_ms": median_ms(lambda i: frames[i % 8].copy(), repeats),
        "maps_once_ms": median_ms(lambda i: Undistorter(lens), max(5, repeats // 10)),
        "distort_maps_once_ms": median_ms(lambda i: Distorter(lens), max(3, repeats // 20)),
    }
    distort = Distorter(lens)
    out["distort_ms"] = median_ms(lambda i: distort(frames[i % 8]), repeats)
    return out


def video_figures(frames: int) -> dict[str, float]:
    w, h = 3 * SIZE[0], SIZE[1] + 16
    base = cv2.resize(frame(0), (w, h)).astype(np.int16)
    rng = np.random.default_rng(1)
    # the panels move and carry sensor noise (sigma 2, as the synthetic reality's), new each frame
    panels = [np.clip(np.roll(base, 4 * i, axis=1) + rng.normal(0, 2, base.shape), 0, 255)
              .astype(np.uint8) for i in range(frames)]
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for codec in ("vp09", "mp4v"):
            path = Path(tmp) / f"{codec}.mp4"
            with VideoSink(path, 30.0, (w, h), codec=codec) as sink:
                t0 = time.perf_counter()
                for image in panels:
                    sink.write(image)
                took = time.perf_counter() - t0
            out[f"{codec}_ms_per_frame"] = 1000.0 * took / frames
            out[f"{codec}_kb_per_frame"] = path.stat().st_size / 1024 / frames
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=200)
    ap.add_argument("--video-frames", type=int, default=30)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    figures = {**lens_figures(args.repeats), **video_figures(args.video_frames)}
    if args.json:
        print(json.dumps({k: round(v, 3) for k, v in figures.items()}, indent=1))
        return
    f = figures
    print(f"Undistortion at {SIZE[0]}x{SIZE[1]}, k = {COEFFS} (median of {args.repeats})")
    print(f"  per frame, maps made once (cv2.remap)        {f['undistort_ms']:8.2f} ms")
    print(f"  peer: cv2.undistort (maps every call)        {f['cv2_undistort_ms']:8.2f} ms   "
          f"ratio {f['cv2_undistort_ms'] / f['undistort_ms']:.1f}x")
    print(f"  peer: a copy of the frame                    {f['copy_ms']:8.2f} ms   "
          f"ratio {f['undistort_ms'] / f['copy_ms']:.1f}x")
    print(f"  making the maps, once per run                {f['maps_once_ms']:8.2f} ms")
    print(f"  a synthetic reality's lens: per frame        {f['distort_ms']:8.2f} ms "
          f"(its maps once: {f['distort_maps_once_ms']:.0f} ms)")
    print(f"mmd.mp4 at 1920x496 (three 640x480 panels), {args.video_frames} frames")
    for codec, name in (("vp09", "VP9 (browsers play it)"), ("mp4v", "MPEG-4 Part 2 (the default)")):
        print(f"  {name:<34} {f[f'{codec}_ms_per_frame']:8.1f} ms a frame, "
              f"{f[f'{codec}_kb_per_frame']:6.1f} kB a frame")
    print(f"  ratio VP9 / MPEG-4                           "
          f"{f['vp09_ms_per_frame'] / f['mp4v_ms_per_frame']:.1f}x")


if __name__ == "__main__":
    main()
