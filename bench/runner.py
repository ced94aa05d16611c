"""The scenario runner's loop: speed per stage, and memory on a long run (figures, not tests).

Run ``python bench/runner.py`` (about two minutes; ``--memory-frames 100000``
for the long-run figure, about 15-25 minutes).  OpenCV is limited to one
thread and the process to one core where the platform allows, so the figures
are "on one core".  The peer is real time: 30 frames/s.

Figures (issue 9, issue 10):

* **static camera, Scene Background only** (``scenarios/background-sync.yaml``
  at 640x480, after synchronisation): frames/s of the loop without the
  reality's own cost (the synthetic reality renders and degrades its frames:
  that is the world's cost, not the robot's), with each stage's share;
* **the whole loop** (``scenarios/bouncing-ball.yaml``: camera on a moving
  robot, MMD and full-pose correction every frame, the ball's schema with
  prediction, the intercept schema, decision cycles): the same figures, and
  how many times real time the rollouts inside the loop run; and the same loop
  with the ball's identification off, its peer (the object schema's ms a frame
  with and without it);
* **the decision stage on both engines** (``--only engines``; issue 23): the
  bouncing ball's loop run on adapt's own engine and on the Soar kernel
  (``engine: soar``), the two alternating round by round in this process;
  the decision stage (the agent's decision cycles, with the input-link
  writes and the output-link commands of the schema network inside them)
  in ms a frame and a decision cycle, medians over the rounds, and their
  ratio;
* **a new camera pose**: the background render at 640x480 (ms, median);
* **memory**: peak resident memory after 1,000 frames and after N more
  frames of a run whose rules fire every frame (input changes every frame, a
  wait operator every decision), with a cheap frame source (a fixed image
  with fresh noise) so the long run measures what the loop keeps, not image
  generation.  Flat means the ratio stays about 1.
"""

from __future__ import annotations

import argparse
import gc
import os
import resource
import statistics
import sys
import time
from pathlib import Path
from typing import Iterator

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from adapt.frames import Frame  # noqa: E402
from adapt.geometry import rotation_exp  # noqa: E402
from adapt.imagination import Renderer  # noqa: E402
from adapt.runner import Runner  # noqa: E402
from adapt.scenario import OutputSettings, load_scenario  # noqa: E402

QUIET = OutputSettings(report=False, trace=False, video=False, figures=False)


def one_core() -> str:
    cv2.setNumThreads(1)
    try:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
        return "pinned to one core, OpenCV 1 thread"
    except (AttributeError, OSError):
        return "OpenCV 1 thread (no core pinning here)"


def loop(path: Path, frames: int, skip: int, overrides: tuple[str, ...] = ()) -> dict[str, float]:
    """Run ``frames`` frames; per-stage ms over the frames after ``skip``."""
    sc = load_scenario(path, overrides=list(overrides))
    runner = Runner(sc, out=None, max_frames=frames, outputs=QUIET)
    marks: list[dict[str, float]] = []
    runner.on_progress = lambda p: marks.append(dict(runner.stats.stage_s))
    runner.run()
    a, b = marks[skip - 1], marks[-1]
    n = len(marks) - skip
    out = {k: 1000.0 * (b[k] - a[k]) / n for k in b}
    summary = runner.summary(1.0, False, None)
    out["rollouts_x"] = summary["rollouts"]["times_real_time"] or 0.0
    out["schemas"] = summary["schema_ms"]  # type: ignore[assignment]
    return out


def report(name: str, ms: dict[str, float]) -> None:
    loop_ms = sum(v for k, v in ms.items() if k not in ("reality", "rollouts_x", "schemas"))
    print(f"{name}: {1000.0 / loop_ms:5.1f} frames/s without the reality "
          f"({loop_ms:.1f} ms a frame; {1000.0 / (loop_ms + ms['reality']):.1f} frames/s with its "
          f"{ms['reality']:.1f} ms) -> {1000.0 / loop_ms / 30.0:.2f}x real time (target >= 1)")
    for k in ("perception", "decisions", "action", "physics", "outputs"):
        print(f"    {k:<11} {ms[k]:7.2f} ms  {100 * ms[k] / loop_ms:5.1f}%")
    for k, v in ms["schemas"].items():  # type: ignore[union-attr]
        print(f"      {k:<22} {v:7.2f} ms a frame (whole run)")
    if ms.get("rollouts_x"):
        print(f"    rollouts inside the loop: {ms['rollouts_x']:.0f}x real time (target >= 500)")


def engines(frames: int, rounds: int) -> None:
    """The bouncing ball's decision stage on both engines, alternating round by round."""
    from adapt.engine import engine_build

    path = ROOT / "scenarios" / "bouncing-ball.yaml"
    per_frame = load_scenario(path).run.decisions_per_frame
    skip = min(30, frames // 2)
    ms: dict[str, list[float]] = {"adapt": [], "soar": []}
    for _ in range(rounds):
        for engine in ms:
            ms[engine].append(loop(path, frames, skip, (f"engine={engine}",))["decisions"])
    own, soar = (statistics.median(ms[e]) for e in ("adapt", "soar"))
    print(f"decision stage, bouncing-ball.yaml ({frames} frames, the last {frames - skip}; "
          f"{per_frame} decision cycles a frame; medians of {rounds} alternating rounds):")
    print(f"    own engine ({engine_build()}): {own:6.2f} ms a frame, "
          f"{own / per_frame:6.3f} ms a decision cycle")
    print(f"    Soar engine (the kernel in its process): {soar:6.2f} ms a frame, "
          f"{soar / per_frame:6.3f} ms a decision cycle")
    print(f"    Soar engine / own engine: {soar / own:.2f}x "
          f"(rounds: own {', '.join(f'{v:.2f}' for v in ms['adapt'])}; "
          f"soar {', '.join(f'{v:.2f}' for v in ms['soar'])} ms a frame)")


def new_pose(runs: int) -> float:
    sc = load_scenario(ROOT / "scenarios" / "bouncing-ball.yaml")
    base = Renderer(sc.scene, sc.camera)
    _ = base.background  # textures prepared once
    rng = np.random.default_rng(0)
    times = []
    for _ in range(runs):
        cam = sc.camera.with_rotation(rotation_exp(rng.normal(0, 0.01, 3)) @ sc.camera.rotation)
        t = time.perf_counter()
        _ = base.with_camera(cam).background
        times.append(time.perf_counter() - t)
    return 1000.0 * statistics.median(times)


class NoisyStill:
    """A fixed rendered frame with fresh sensor noise each time: a cheap frame source."""

    def __init__(self, image: np.ndarray, frames: int, fps: float) -> None:
        self.image = image
        self.frames = frames
        self._fps = fps
        self.robot = None
        self.truth = None

    @property
    def size(self) -> tuple[int, int]:
        return (self.image.shape[1], self.image.shape[0])

    @property
    def fps(self) -> float:
        return self._fps

    def __iter__(self) -> Iterator[Frame]:
        rng = np.random.default_rng(0)
        noise = rng.integers(-3, 4, (16, *self.image.shape), dtype=np.int16)
        for i in range(self.frames):
            img = np.clip(self.image.astype(np.int16) + noise[i % 16], 0, 255).astype(np.uint8)
            yield Frame(i, i / self._fps, img)

    def close(self) -> None:
        pass


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def memory(frames: int) -> None:
    text = (ROOT / "scenarios" / "background-sync.yaml").read_text()
    small = text.replace("fx: 525.0", "fx: 131.25").replace("fy: 525.0", "fy: 131.25") \
        .replace("cx: 319.5", "cx: 79.5").replace("cy: 239.5", "cy: 59.5") \
        .replace("width: 640", "width: 160").replace("height: 480", "height: 120")
    from adapt.scenario import loads_scenario

    sc = loads_scenario(small + "\n", file="memory.yaml", base=ROOT / "scenarios")
    image = Renderer(sc.scene, sc.camera).background.image.copy()
    first = 1000
    source = NoisyStill(image, first + frames, sc.run.fps)
    from dataclasses import replace

    sc = replace(sc, run=replace(sc.run, max_frames=first + frames, duration=None))
    runner = Runner(sc, source=source, out=None, outputs=QUIET)
    peaks: dict[int, float] = {}
    started = time.perf_counter()

    def progress(p) -> None:  # type: ignore[no-untyped-def]
        if p.frame in (first, first + frames) or p.frame % 10000 == 0:
            gc.collect()
            peaks[p.frame] = peak_mb()
            print(f"    frame {p.frame:>7}: peak {peaks[p.frame]:7.1f} MB "
                  f"({time.perf_counter() - started:6.0f} s)", flush=True)

    runner.on_progress = progress
    result = runner.run()
    a, b = peaks[first], peaks[max(peaks)]
    print(f"memory: peak {a:.1f} MB after {first:,} frames, {b:.1f} MB after {max(peaks):,} "
          f"(ratio {b / a:.3f}; target <= 1.0 + noise); {result.summary['decisions']:,} decisions, "
          f"{runner.agent.operator_count:,} operators selected")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=150, help="frames per loop figure")
    ap.add_argument("--memory-frames", type=int, default=20_000,
                    help="frames after the first 1,000 for the memory figure (100000 for the "
                    "issue's figure)")
    ap.add_argument("--only", choices=("engines",), default=None,
                    help="only the decision stage on both engines")
    ap.add_argument("--rounds", type=int, default=3,
                    help="alternating rounds of the two engines (--only engines and the default)")
    args = ap.parse_args()
    print(one_core())
    if args.only == "engines":
        engines(args.frames, args.rounds)
        return 0
    print(f"new camera pose: background render {new_pose(40):.2f} ms at 640x480 "
          f"(median of 40; target <= 10 ms)")
    report("static camera, Scene Background (background-sync.yaml, 640x480)",
           loop(ROOT / "scenarios" / "background-sync.yaml", args.frames, 30))
    report("whole loop (bouncing-ball.yaml: camera on the robot, ball, intercept, 640x480)",
           loop(ROOT / "scenarios" / "bouncing-ball.yaml", args.frames, 30))
    report("the same, identification off (its peer: schemas.foreground-object.identify=false)",
           loop(ROOT / "scenarios" / "bouncing-ball.yaml", args.frames, 30,
                ("schemas.foreground-object.identify=false",)))
    engines(args.frames, args.rounds)
    memory(args.memory_frames)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
