"""MMD benchmark (issue 5): accuracy, speed, camera loop and unexpected objects.

Run as ``python bench/mmd.py`` (a couple of minutes on 2 cores).  Scenes: the
shipped photographs as a textured plane world (``tests/vision/scenes.py``),
640x480, f = 525 px; the synthetic view is offset by up to 3 deg pan/tilt and
5 deg roll and given a renderer look (blur 1.2, 12-level posterisation,
per-channel gain and bias); the real view gets sensor noise (sigma 5).
Prints medians next to their targets.  OpenCV uses 2 threads.

The scale section renders the bundled scenario at 320x240 ... 2560x1920 (the
real view with the ball, a camera turned by 1.5 deg and moved 1 cm, sensor
noise; the synthetic view without the ball) and counts the regions; then it
times an 8000x6000 pair, in process and through ``adapt mmd`` in a child
process (wall time and peak memory).
"""

from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from adapt.geometry import rotation_exp  # noqa: E402
from adapt.vision.homography import corner_error  # noqa: E402
from adapt.vision.matching import prepare  # noqa: E402
from adapt.vision.mmd import mmd  # noqa: E402
from adapt.vision.regions import find_regions, label_regions  # noqa: E402
from adapt.vision.sync import synchronise  # noqa: E402
from adapt.vision.threads import DEFAULT_THREADS, set_threads  # noqa: E402
from tests.vision import scenes  # noqa: E402

SCENES = ("room", "coffee", "brick", "gravel", "grass")


def line(label: str, value: str, target: str, ok: bool | None) -> None:
    mark = "" if ok is None else ("  ok" if ok else "  MISSED")
    print(f"  {label:<52} {value:>16}   target {target}{mark}")


def accuracy_and_speed(seeds: int) -> None:
    print(f"H_e accuracy and MMD time ({len(SCENES)} scenes x {seeds} offsets, 640x480)")
    errors, cold, warm = [], [], []
    per_scene = {}
    for name in SCENES:
        e_scene = []
        for seed in range(seeds):
            real, synthetic, h_true, *_ = scenes.pair(name, 1000 + seed)
            t_cold, t_warm = [], []
            for _ in range(3):  # best of 3 against the shared machine
                t0 = time.perf_counter()
                r = mmd(real, synthetic)
                find_regions(r.difference)
                t_cold.append(time.perf_counter() - t0)
                ps = prepare(synthetic)  # the rendered background's corners, cached
                t0 = time.perf_counter()
                r2 = mmd(real, ps)
                find_regions(r2.difference)
                t_warm.append(time.perf_counter() - t0)
            cold.append(min(t_cold) * 1e3)
            warm.append(min(t_warm) * 1e3)
            e = corner_error(r.homography, h_true, real.shape) if r.aligned else np.inf
            errors.append(e)
            e_scene.append(e)
        per_scene[name] = float(np.median(e_scene))
    med = float(np.median(errors))
    line("median corner error of H_e (px)", f"{med:.3f}", "<= 0.3", med <= 0.3)
    print("    per scene: " + ", ".join(f"{k} {v:.2f}" for k, v in per_scene.items())
          + f"; p90 {np.percentile(errors, 90):.2f}, failures {int(np.sum(~np.isfinite(errors)))}")
    line("MMD ms/frame, synthetic corners cached", f"{np.median(warm):.1f}", "<= 15", np.median(warm) <= 15)
    line("MMD ms/frame, corners detected per frame", f"{np.median(cold):.1f}", "<= 15", np.median(cold) <= 15)


class PlanarPhoto:
    def __init__(self, name: str, seed: int) -> None:
        self.world = scenes.world(name)
        self.rng = np.random.default_rng(seed)

    def __call__(self, cam):  # type: ignore[no-untyped-def]
        return scenes.renderer_look(scenes.view(self.world, cam), self.rng)


def start_at(real_cam, offset_px: float, rng):  # type: ignore[no-untyped-def]
    """A start rotation whose true corner error is about ``offset_px``."""
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    lo, hi = 0.0, 0.5
    for _ in range(40):
        mid = (lo + hi) / 2
        cam = real_cam.with_rotation(rotation_exp(axis * mid) @ real_cam.rotation)
        e = corner_error(scenes.true_homography(real_cam, cam), np.eye(3), (480, 640))
        lo, hi = (mid, hi) if e < offset_px else (lo, mid)
    return cam


def run_loop(name: str, seed: int, offset_px: float, max_iterations: int = 10):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    real_cam = scenes.camera(rotation_exp(np.deg2rad(rng.uniform(-2, 2, 3))))
    world = scenes.world(name)
    real = scenes.sensor_noise(scenes.view(world, real_cam), rng)
    start = start_at(real_cam, offset_px, rng)
    res = synchronise(real, start, PlanarPhoto(name, seed), gain=0.5, tolerance=0.5,
                      max_iterations=max_iterations)
    true_err = corner_error(scenes.true_homography(real_cam, res.camera), np.eye(3), (480, 640))
    return res, true_err


def camera_loop(seeds: int) -> None:
    print("camera loop, g = 0.5, from 35 px")
    iters, finals = [], []
    for name in ("room", "coffee", "brick"):
        for seed in range(seeds):
            res, true_err = run_loop(name, 2000 + seed, 35.0)
            # corrections applied before the check that stopped the loop
            iters.append(len(res.steps) - 1 if res.converged else np.inf)
            finals.append(true_err)
    it, fe = float(np.median(iters)), float(np.median(finals))
    line("corrections to reach < 0.5 px (median)", f"{it:.0f}", "<= 8", it <= 8)
    line("true corner error at the end (median px)", f"{fe:.3f}", "< 0.5", fe < 0.5)
    line("runs converged", f"{int(np.isfinite(iters).sum())}/{len(iters)}", "all", bool(np.isfinite(iters).all()))
    print("capture range (recovered to < 0.5 px true error in <= 14 renders, 10 starts, room)")
    largest = 0.0
    for offset in (35, 60, 90, 120, 160, 200, 260, 320):
        ok = 0
        for seed in range(10):
            res, true_err = run_loop("room", 3000 + seed, float(offset), max_iterations=14)
            ok += int(res.converged and true_err < 0.5)
        print(f"    {offset:>4} px: {ok}/10")
        if ok >= 9:
            largest = float(offset)
        else:
            break
    line("capture range (largest offset recovered 9/10)", f"{largest:.0f} px", "report", None)


def unexpected_object(seeds: int) -> None:
    print("unexpected object in the real view")
    ious, largest = [], []
    for name in SCENES:
        for seed in range(seeds):
            real, synthetic, *_ = scenes.pair(name, 4000 + seed)
            real, sil = scenes.paste_object(real, np.random.default_rng(5000 + seed))
            regions = label_regions(find_regions(mmd(real, synthetic).difference), [])
            unexpected = [r for r in regions if not r.expected]
            if not unexpected:
                ious.append(0.0)
                largest.append(False)
                continue
            top = max(unexpected, key=lambda r: r.area)
            m = top.to_mask(real.shape)
            ious.append(float((m & sil).sum() / (m | sil).sum()))
            largest.append(True)
    med = float(np.median(ious))
    line("IoU of the largest unexpected region (median)", f"{med:.3f}", ">= 0.7", med >= 0.7)
    share = float(np.mean(np.array(ious) >= 0.7))
    line("share of frames where it is the object (IoU >= 0.7)", f"{share:.0%}", "report", None)


def _scaled_camera(cam, k: float):  # type: ignore[no-untyped-def]
    return replace(cam, fx=cam.fx * k, fy=cam.fy * k, cx=(cam.cx + 0.5) * k - 0.5,
                   cy=(cam.cy + 0.5) * k - 0.5, width=round(cam.width * k), height=round(cam.height * k))


def scale() -> None:
    import cv2

    from adapt.imagination import Renderer, World
    from adapt.scenario import load_scenario

    print("the same scene at several resolutions (bundled scenario, ball only in the real view)")
    sc = load_scenario(ROOT / "scenarios" / "room.yaml")
    world = World(sc.scene, seed=sc.seed)
    world.run(1.5)
    state = world.snapshot()
    empty = replace(sc.scene, balls=())
    areas = {}
    for k in (0.5, 1.0, 2.0, 4.0):
        cam = _scaled_camera(sc.camera, k)
        real_cam = cam.with_pose(rotation_exp([0.01, -0.015, 0.02]) @ cam.rotation, cam.position + [0.01, 0, 0])
        real = scenes.sensor_noise(Renderer(sc.scene, real_cam).render(state).image, np.random.default_rng(0), 3.0)
        synthetic = Renderer(empty, cam).render().image
        times = []
        for _ in range(3):
            t0 = time.perf_counter()
            r = mmd(real, synthetic)
            regions = r.regions()
            times.append(time.perf_counter() - t0)
        areas[k] = regions[0].area / k**2 if regions else float("nan")
        print(f"    {cam.width}x{cam.height}: {len(regions)} region(s), ball area / k^2 = {areas[k]:.0f} px, "
              f"{min(times) * 1e3:.1f} ms")
    spread = (max(areas.values()) - min(areas.values())) / areas[1.0]
    line("ball area spread across resolutions (scaled)", f"{spread:.1%}", "report", None)

    print("an 8000x6000 pair (gravel, shifted 75 px, one object)")
    w = cv2.resize(scenes.world("gravel"), (8400, 6300), interpolation=cv2.INTER_LINEAR)
    synthetic = np.ascontiguousarray(w[150:6150, 200:8200])
    real = w[100:6100, 275:8275].copy()
    cv2.circle(real, (5000, 2000), 600, (255, 255, 255), -1)
    small_r, small_s, *_ = scenes.pair("gravel", 1000)
    t_big, t_small = [], []
    for _ in range(3):
        t0 = time.perf_counter()
        rb = mmd(real, synthetic)
        rb.regions()
        t_big.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        rs = mmd(small_r, small_s)
        rs.regions()
        t_small.append(time.perf_counter() - t0)
    big, small = min(t_big) * 1e3, min(t_small) * 1e3
    line("MMD 8000x6000 in process (ms, best of 3)", f"{big:.0f}", "report", None)
    line("  ratio to 640x480 in the same run", f"{big / small:.1f}x", "report", None)
    with tempfile.TemporaryDirectory() as d:
        cv2.imwrite(str(Path(d) / "r.png"), real)
        cv2.imwrite(str(Path(d) / "s.png"), synthetic)
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "adapt", "mmd", str(Path(d) / "r.png"), str(Path(d) / "s.png")],
                              cwd=ROOT, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        print(f"    adapt mmd: exit {proc.returncode}, {proc.stdout.splitlines()[0] if proc.stdout else proc.stderr}")
        line("adapt mmd 8000x6000 PNGs: wall time (s)", f"{wall:.1f}", "report (was 124 s)", None)
        line("  peak memory of the child (MB)", f"{max(rss, before) / 1024:.0f}", "report (was 11.4 GB)", None)


def main() -> None:
    set_threads(DEFAULT_THREADS)
    t0 = time.perf_counter()
    accuracy_and_speed(seeds=8)
    camera_loop(seeds=4)
    unexpected_object(seeds=4)
    scale()
    print(f"(benchmark ran in {time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
