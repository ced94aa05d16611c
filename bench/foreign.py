"""The mirror on realities it did not write: randomized PyBullet realities (issue 20).

Run ``python bench/foreign.py`` (50 throws at 640x480, 6 s each; 13-20 minutes with
``--jobs 2`` on 2 cores, most of it PyBullet's CPU renderer; ``--small``, 320x240:
about 6 minutes) or quicker with ``--throws 10 --small --duration 4``.  Needs ``pip install 'adapt[bullet]'``.

Each throw is its own arena, drawn from its seed here (never tuned to one reality):

* a rectangular arena 2.5-4.5 m x 2.5-4 m, walls 0.25-1 m high, 0-3 obstacles (boxes and
  wedges, 0.15-0.5 m high), a disc robot in its south part facing north;
* the camera, a third of the throws each: **outside** the arena 2-2.5 m high behind a low
  (8-15 cm) south wall, looking down over it; **inside**, fixed 1.2-2 m high at a side or
  corner; **on the robot**, 0.45-0.7 m up; its focal length fitted to the arena;
* a ball of radius 8-13 cm and a saturated colour, known only by wide ranges (restitution,
  friction, rolling resistance, and the floor's friction: a real ball spins), either
  **rolling from frame 0** or **thrown** after 0.3-1 s (from up to 30 cm above the floor),
  at 1.2-3 m/s across the arena, where the camera sees it;
* the reality's own ranges at their (wide) defaults: PyBullet's restitution, friction,
  rolling and spinning friction, damping and spin of the ball; the surfaces'; textures
  (the scenario's, bundled photographs or procedural patterns), light, gain, vignette,
  blur, noise; the camera's mounting offset (2 cm, 1 degree); wheel slip up to 5 %.

The scenario says what a new user would write: the room measured, its look unknown
(``scene-background: {appearance: "on"}``), the ball ``create: when_seen``.

Figures, each a median over throws of each throw's value (ratios taken per throw):

* **coverage**: of the frames where the ball is visible (at least a fifth of its disc
  shows in the true camera's image: PyBullet's segmentation), the share where the ball's
  schema observed it within two radii of the truth; and where the rest went: before the
  look was learned, with the ball at the robot (within 10 cm of touching it), with no schema
  for the ball, with its schema not finding it, or found further off;
* **spurious schemas**: object schemas spawned for something the scenario does not have;
* **the Scene Background**: the share of frames with the camera aligned, and the throws in
  which the surfaces' look was never learned (``appearance: "on"`` waits for the camera to be
  aligned to the scene's structure first: without a look there are no regions);
* **tracking**: observed and imagined against the truth;
* **prediction** 0.5 s and 1.0 s ahead, with and without a contact inside the horizon,
  of the mirror, the Kalman baseline and the map-aware baseline, and the ratios;
* **confidence**: the share of frames after the first contact with a 1 s prediction of
  confidence >= 0.7, and the share of those within the catch reach;
* **interception** of reachable throws by the robot and by both baselines' robots, and
  whether the agent's own ``^caught`` (its rules' "caught ball at t=..." write) agrees with
  the evaluation's (the true bodies met), as ``bench/mirror.py`` reports it;
* **frames/s** of the loop without the reality's own cost (PyBullet's physics, its
  renderer and the sensor), and that cost, as ``bench/runner.py`` reports it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

CAMERAS = ("outside", "inside", "robot")
COLORS = ((230, 60, 30), (240, 150, 20), (235, 220, 40), (40, 90, 220), (220, 50, 160),
          (40, 190, 80), (250, 250, 250))
#: A ball counts as visible when this share of its disc shows in the true image.
VISIBLE = 0.2
#: An observation within this many radii of the truth is tracking.
TRACKED_RADII = 2.0
#: Why a visible frame was not tracked, in this order: the look not learned yet; the ball
#: within NEAR_ROBOT of touching the robot (m); the ball's schema not there (not spawned,
#: or the ball taken for another object); the schema there but not finding it; found, but
#: further off than TRACKED_RADII.
MISSED = ("no look", "at the robot", "no schema", "not found", "off")
NEAR_ROBOT = 0.1


def _box(cx: float, cy: float, w: float, h: float, angle: float) -> list[list[float]]:
    c, s = math.cos(angle), math.sin(angle)
    return [[round(cx + c * x - s * y, 3), round(cy + s * x + c * y, 3)]
            for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]


def _wedge(cx: float, cy: float, size: float, angle: float) -> list[list[float]]:
    pts = []
    for k in range(3):
        a = angle + 2 * math.pi * k / 3
        pts.append([round(cx + size * 0.6 * math.cos(a), 3), round(cy + size * 0.6 * math.sin(a), 3)])
    return pts


def _fit_focal(position: np.ndarray, target: np.ndarray, points: np.ndarray, width: int,
               height: int) -> float:
    """The largest focal length (pixels) that keeps ``points`` in the image, 8 % margin."""
    from adapt.geometry import Camera

    cam = Camera.look_at(fx=100.0, fy=100.0, cx=(width - 1) / 2, cy=(height - 1) / 2,
                         width=width, height=height, position=tuple(position), look_at=tuple(target))
    local = cam.to_camera(points)
    local = local[local[:, 2] > 1.0]  # what is near the camera's own side may fall outside
    if len(local) == 0:
        return 0.5 * width
    x = np.abs(local[:, 0] / local[:, 2]).max()
    y = np.abs(local[:, 1] / local[:, 2]).max()
    return float(min(0.46 * width / max(x, 1e-6), 0.46 * height / max(y, 1e-6)))


def scenario_text(seed: int, small: bool = False, duration: float = 6.0) -> tuple[str, dict[str, Any]]:
    """A randomized foreign scenario for ``seed``, and what was chosen (for the report)."""
    from adapt.geometry import Camera

    rng = np.random.default_rng([seed, 2020])
    width, height = (320, 240) if small else (640, 480)
    W, D = float(rng.uniform(2.5, 4.5)), float(rng.uniform(2.5, 4.0))
    x0, y0, x1, y1 = -W / 2, -D / 2, W / 2, D / 2
    kind = CAMERAS[seed % 3]
    south = float(rng.uniform(0.08, 0.15)) if kind == "outside" else float(rng.uniform(0.25, 1.0))
    heights = [float(rng.uniform(0.25, 1.0)) for _ in range(3)]
    walls = [("north", (x0, y1), (x1, y1), heights[0]), ("east", (x1, y1), (x1, y0), heights[1]),
             ("south", (x1, y0), (x0, y0), south), ("west", (x0, y0), (x0, y1), heights[2])]
    radius = float(rng.uniform(0.08, 0.13))
    robot_r = float(rng.uniform(0.15, 0.25))
    robot = (float(rng.uniform(-0.3, 0.3) * W), y0 + robot_r + float(rng.uniform(0.25, 0.5)))
    heading = 90.0 + float(rng.uniform(-20, 20))
    obstacles = []
    for _ in range(int(rng.integers(0, 4))):
        for _try in range(50):
            size = float(rng.uniform(0.25, 0.6))
            cx = float(rng.uniform(x0 + 0.35 + size, x1 - 0.35 - size))
            cy = float(rng.uniform(y0 + 0.9 + size, y1 - 0.35 - size))
            if any(math.dist((cx, cy), (ox, oy)) < size + os_ + 0.4 for ox, oy, os_ in
                   [(o[0], o[1], o[2]) for o in obstacles]):
                continue
            if math.dist((cx, cy), robot) < size + robot_r + 0.4:
                continue
            poly = _box(cx, cy, size, float(rng.uniform(0.5, 1.0)) * size,
                        float(rng.uniform(0, math.pi))) if rng.random() < 0.6 else \
                _wedge(cx, cy, size, float(rng.uniform(0, 2 * math.pi)))
            obstacles.append((cx, cy, size, poly, float(rng.uniform(0.15, 0.5))))
            break
    corners = [(x, y, 0.0) for x in (x0, x1) for y in (y0, y1)]
    tops = [(x, y, h) for (_, a, b, h) in walls for (x, y) in (a, b)]
    arena = np.array(corners + tops, float)
    mount = ""
    if kind == "outside":
        position = np.array([float(rng.uniform(-0.3, 0.3)) * W, y0 - float(rng.uniform(0.3, 0.8)),
                             float(rng.uniform(2.0, 2.5))])
        target = np.array([float(rng.uniform(-0.1, 0.1)) * W, -0.15 * D, 0.0])
    elif kind == "inside":
        side = int(rng.integers(0, 3))
        px = (x0 + 0.15, x1 - 0.15, float(rng.uniform(-0.3, 0.3)) * W)[side]
        position = np.array([px, y0 + 0.15, float(rng.uniform(1.2, 2.0))])
        target = np.array([-0.3 * px, 0.1 * D, 0.0])
    if kind in ("outside", "inside"):
        focal = _fit_focal(position, target, arena, width, height)
        focal = float(min(max(focal, 0.45 * width), 1.2 * width))
        camera = (f"camera: {{fx: {focal:.1f}, fy: {focal:.1f}, cx: {(width - 1) / 2}, "
                  f"cy: {(height - 1) / 2}, width: {width}, height: {height}, "
                  f"position: {[round(float(v), 3) for v in position]}, "
                  f"look_at: {[round(float(v), 3) for v in target]}}}\n")
        cam = Camera.look_at(fx=focal, fy=focal, cx=(width - 1) / 2, cy=(height - 1) / 2,
                             width=width, height=height, position=tuple(position),
                             look_at=tuple(target))
    else:
        up = float(rng.uniform(0.45, 0.7))
        focal = float(rng.uniform(0.7, 0.85)) * width
        look = [3.0, 0.0, round(float(rng.uniform(0.1, 0.3)), 3)]
        mount = "robot"
        camera = (f"camera: {{mount: robot, fx: {focal:.1f}, fy: {focal:.1f}, cx: {(width - 1) / 2}, "
                  f"cy: {(height - 1) / 2}, width: {width}, height: {height}, "
                  f"position: [0.0, 0.0, {up:.3f}], look_at: {look}}}\n")
        h = math.radians(heading)
        rot = np.array([[math.cos(h), -math.sin(h), 0], [math.sin(h), math.cos(h), 0], [0, 0, 1]])
        cam = Camera.look_at(fx=focal, fy=focal, cx=(width - 1) / 2, cy=(height - 1) / 2,
                             width=width, height=height,
                             position=tuple(rot @ np.array([0, 0, up]) + [*robot, 0]),
                             look_at=tuple(rot @ np.array(look) + [*robot, 0]))
    # the throw: where the camera sees it, clear of the walls, obstacles and robot
    from_frame_0 = bool(rng.random() < 0.5)
    clear = radius + 0.08
    throw = None
    for _try in range(500):
        tx = float(rng.uniform(x0 + clear, x1 - clear))
        ty = float(rng.uniform(y0 + clear, y1 - clear))
        if math.dist((tx, ty), robot) < robot_r + radius + 0.3:
            continue
        if any(math.dist((tx, ty), (o[0], o[1])) < o[2] + radius + 0.1 for o in obstacles):
            continue
        local = cam.to_camera(np.array([[tx, ty, radius]]))[0]
        if local[2] < 0.3:
            continue
        u, v = cam.project(np.array([[tx, ty, radius]]))[0]
        if not (0.1 * width < u < 0.9 * width and 0.15 * height < v < 0.9 * height):
            continue
        aim = (float(rng.uniform(x0 + 0.3, x1 - 0.3)), float(rng.uniform(0.0, y1 - 0.3)))
        if math.dist(aim, (tx, ty)) < 0.5:
            continue
        throw = (tx, ty, math.degrees(math.atan2(aim[1] - ty, aim[0] - tx)))
        break
    if throw is None:  # a camera that sees little of the arena: throw from its middle
        throw = (0.0, 0.0, float(rng.uniform(0, 360)))
    speed = float(rng.uniform(1.2, 3.0))
    t0 = 0.0 if from_frame_0 else float(rng.uniform(0.3, 1.0))
    drop = 0.0 if from_frame_0 else float(rng.choice([0.0, rng.uniform(0.0, 0.3)]))
    color = COLORS[int(rng.integers(len(COLORS)))]
    floor_tex = ("gravel", "grass")[int(rng.integers(2))]
    lines = [f"seed: {seed}", camera.rstrip(), "world:",
             f"  floor: {{texture: {floor_tex}, tile: 0.8, extent: "
             f"{[round(x0, 3), round(y0, 3), round(x1, 3), round(y1, 3)]}}}", "  walls:"]
    for name, a, b, h in walls:
        lines.append(f"    - {{name: {name}, from: {[round(a[0], 3), round(a[1], 3)]}, "
                     f"to: {[round(b[0], 3), round(b[1], 3)]}, height: {h:.3f}, texture: brick, "
                     "tile: 0.6, restitution: 0.9}")
    if obstacles:
        lines.append("  obstacles:")
        for i, (_, _, _, poly, h) in enumerate(obstacles):
            c = [int(v) for v in rng.integers(40, 200, 3)]
            lines.append(f"    - {{name: obstacle{i}, polygon: {poly}, height: {h:.3f}, color: {c}}}")
    lines += ["  objects:",
              f"    - {{name: ball, radius: {radius:.3f}, mass: 0.4, color: {list(color)}, "
              "create: when_seen,",
              "       ranges: {restitution: [0.5, 0.95], friction: [0.1, 0.6], "
              "rolling_resistance: [0.005, 0.06], floor_friction: [0.1, 1.2]}}",
              f"  robot: {{shape: disc, radius: {robot_r:.3f}, position: "
              f"{[round(robot[0], 3), round(robot[1], 3)]}, heading_deg: {heading:.1f}, "
              f"max_speed: {float(rng.uniform(0.6, 1.0)):.2f}, "
              f"max_accel: {float(rng.uniform(1.0, 2.0)):.2f}, mass: 10, height: 0.3, "
              "color: [40, 40, 45]}",
              "reality:", "  kind: bullet", "  camera_offset: 0.02", "  camera_offset_deg: 1.0",
              "  robot: {slip: [0.0, 0.05]}", "  objects:",
              f"    - {{name: ball, throw: {{t: {t0:.3f}, x: {throw[0]:.3f}, y: {throw[1]:.3f}, "
              f"speed: {speed:.3f}, heading_deg: {throw[2]:.1f}, height: {drop:.3f}}}}}",
              "goals: [{name: intercept, object: ball}]",
              "rules: [../rules/mirror/perception.soar, ../rules/mirror/intercept.soar]",
              "schemas:",
              f"  scene-background: {{appearance: \"on\", mmd_pixels: 76800"
              f"{', full_pose: true' if mount else ''}}}",
              f"run: {{fps: 30, duration: {duration}}}",
              "predict: {horizons: [0.5, 1.0], every: 1, ensemble: 8}", ""]
    chosen = {"camera": kind, "arena": [round(W, 2), round(D, 2)], "obstacles": len(obstacles),
              "south_wall": round(south, 3), "from_frame_0": from_frame_0, "radius": round(radius, 3)}
    return "\n".join(lines), chosen


def one(seed: int, small: bool, duration: float, extra: tuple[str, ...]) -> dict[str, Any]:
    """Run one throw; its figures (or its error)."""
    import cv2

    cv2.setNumThreads(1)
    from adapt.runner import Runner
    from adapt.scenario import OutputSettings, loads_scenario

    text, chosen = scenario_text(seed, small, duration)
    out: dict[str, Any] = {"seed": seed, **chosen}
    try:
        sc = loads_scenario(text, file=f"foreign-{seed}.yaml", base=ROOT / "scenarios",
                            overrides=list(extra))
        quiet = OutputSettings(report=False, trace=False, video=False, figures=False)
        recording = Recording(sc)
        said: list[str] = []  # the rules' writes: "caught ball at t=..." is the agent's own ^caught
        started = time.perf_counter()
        runner = Runner(sc, out=None, seed=seed, outputs=quiet, listeners=(recording,),
                        on_write=said.append)
        recording.truth = runner.truth
        summary = runner.run().summary
        out["wall_s"] = time.perf_counter() - started
    except Exception as exc:  # a throw that fails is counted and named, not the end of the bench
        import traceback

        return {**out, "error": f"{type(exc).__name__}: {exc}",
                "where": traceback.format_exc(limit=-4)}
    out.update(_figures(summary, recording.frames, sc))
    caught = re.search(r"caught ball at t=([0-9.]+)", "".join(said))
    out["agent_caught_t"] = float(caught.group(1)) if caught else None
    return out


class Recording:
    """A listener on the runner's frame records: what the figures need of each frame, with
    the frame's truth (the bench is evaluation: it may read the truth)."""

    def __init__(self, scenario: Any) -> None:
        self.scenario = scenario
        self.truth: Any = None
        self.frames: list[dict[str, Any]] = []

    def frame(self, record: Any) -> None:
        truth = None if self.truth is None else self.truth.at(record.index)
        ball = truth.objects.get("ball") if truth is not None else None
        visible = False
        if ball is not None and ball.pixels is not None and truth.camera is not None:
            r = self.scenario.model("ball").ball.radius
            depth = float(truth.camera.to_camera(np.array([[*ball.position, ball.height]]))[0, 2])
            disc = math.pi * (truth.camera.fx * r / depth) ** 2 if depth > 0.05 else math.inf
            visible = ball.pixels >= max(4.0, VISIBLE * disc)
        tracked = record.tracked_object("ball")
        percept = record.percept_of("ball")
        prediction = None if percept is None else percept.prediction
        confident = prediction is not None and any(
            h.horizon == 1.0 and h.confidence >= 0.7 for h in prediction.horizons)
        bg = record.background
        robot = None if truth is None or truth.robot is None else truth.robot.position
        self.frames.append({
            "has_schema": tracked is not None,
            "robot_m": None if ball is None or robot is None
            else math.dist(ball.position, robot),
            "t": record.time, "visible": visible,
            "truth": None if ball is None else list(ball.position),
            "velocity": None if ball is None else list(ball.velocity),
            "observed": None if tracked is None or tracked.observed is None
            else list(tracked.observed),
            "confident": confident, "names": [t.name for t in record.tracked],
            "aligned": bg is not None and bg.aligned,
            "learned": bg is not None and bg.stage.value == "learned"})


def _figures(summary: dict[str, Any], frames: list[dict[str, Any]], sc: Any) -> dict[str, Any]:
    r = sc.model("ball").ball.radius
    declared = {m.name for m in sc.objects}
    visible = [f for f in frames if f["visible"]]

    def on_it(f: dict[str, Any]) -> bool:
        """Observed within TRACKED_RADII of the truth."""
        return f["observed"] is not None and math.dist(f["observed"], f["truth"]) <= TRACKED_RADII * r

    seen = [f for f in visible if f["observed"] is not None]
    tracked = [f for f in seen if on_it(f)]
    robot = sc.scene.robot
    near = (robot.outer_radius + r + NEAR_ROBOT) if robot is not None else -1.0
    missed = {key: 0 for key in MISSED}
    for f in visible:
        if on_it(f):
            continue
        if not f["learned"]:
            missed["no look"] += 1
        elif f["robot_m"] is not None and f["robot_m"] <= near:
            missed["at the robot"] += 1
        elif not f["has_schema"]:
            missed["no schema"] += 1
        elif f["observed"] is None:
            missed["not found"] += 1
        else:
            missed["off"] += 1
    spurious = sorted({n for f in frames for n in f["names"] if n not in declared})
    # the first contact: the true velocity turned by more than 20 degrees between frames
    first = None
    for a, b in zip(frames, frames[1:]):
        va, vb = a["velocity"], b["velocity"]
        if va is None or vb is None or math.hypot(*va) < 0.05 or math.hypot(*vb) < 0.05:
            continue
        c = (va[0] * vb[0] + va[1] * vb[1]) / (math.hypot(*va) * math.hypot(*vb))
        if math.degrees(math.acos(max(-1.0, min(1.0, c)))) > 20:
            first = b["t"]
            break
    caught_t = (summary.get("intercept") or {}).get("t")
    after = [f for f in frames if first is not None and f["t"] > first and f["truth"] is not None
             and (caught_t is None or f["t"] < caught_t)]
    stages = summary.get("stage_ms") or {}
    loop_ms = sum(v for k, v in stages.items() if k != "reality")
    return {
        "visible_frames": len(visible), "frames": len(frames),
        "coverage": len(tracked) / len(visible) if visible else None,
        "seen_share": len(seen) / len(visible) if visible else None,
        "missed": missed,
        "spurious": len(spurious), "spurious_names": spurious,
        "aligned_share": sum(f.get("aligned", False) for f in frames) / len(frames) if frames else None,
        "learned_share": sum(f.get("learned", False) for f in frames) / len(frames) if frames else None,
        "tracking_m": ((summary.get("tracking_error_m") or {}).get("ball") or {}).get("median"),
        "imagined_m": ((summary.get("imagination_error_m") or {}).get("ball") or {}).get("median"),
        "prediction": summary.get("prediction_error_m") or {},
        "confident_after_contact": (sum(f["confident"] for f in after) / len(after)) if after else None,
        "confidence": summary.get("confidence") or {},
        "intercept": summary.get("intercept") or {},
        "baseline": summary.get("baseline") or {}, "mapaware": summary.get("mapaware") or {},
        "loop_ms": loop_ms, "reality_ms": stages.get("reality"),
        "true_parameters": (summary.get("true_parameters") or {}).get("ball"),
    }


def med(values: list[float]) -> float | None:
    return statistics.median(values) if values else None


def cm(v: float | None) -> str:
    return "n/a" if v is None else f"{100 * v:.1f} cm"


def pct(v: float | None) -> str:
    return "n/a" if v is None else f"{100 * v:.0f}%"


def ratio(v: float | None) -> str:
    return "n/a" if v is None else f"{v:.2f}x"


def report(runs: list[dict[str, Any]]) -> None:
    ok = [r for r in runs if not r.get("error")]
    for kind in ("all",) + CAMERAS:
        group = ok if kind == "all" else [r for r in ok if r["camera"] == kind]
        if not group:
            continue
        cover = [r["coverage"] for r in group if r["coverage"] is not None]
        seen = [r["seen_share"] for r in group if r["seen_share"] is not None]
        print(f"{kind} ({len(group)} throws): coverage {pct(med(cover))} median "
              f"(mean {pct(sum(cover) / len(cover) if cover else None)}; target >= 95%); "
              f"observed at all {pct(med(seen))}; spurious schemas "
              f"{sum(r['spurious'] for r in group)} in all (target 0), "
              f"{sum(1 for r in group if r['spurious'])} throws with any")
    for kind in ("all",) + CAMERAS:
        group = ok if kind == "all" else [r for r in ok if r["camera"] == kind]
        visible = sum(r["visible_frames"] for r in group)
        if not group or not visible:
            continue
        print(f"  visible frames not tracked, {kind} ({visible} visible): " + ", ".join(
            f"{key} {pct(sum(r['missed'][key] for r in group) / visible)}" for key in MISSED))
    never = [r for r in ok if not r.get("learned_share")]
    aligned = [r["aligned_share"] for r in ok if r.get("aligned_share") is not None]
    print(f"the Scene Background: frames with the camera aligned {pct(med(aligned))} median; "
          f"the look never learned in {len(never)} of {len(ok)} throws ("
          + ", ".join(f"{sum(1 for r in never if r['camera'] == k)} {k}" for k in CAMERAS)
          + "): no region, nothing tracked there")
    track = [r["tracking_m"] for r in ok if r["tracking_m"] is not None]
    imag = [r["imagined_m"] for r in ok if r["imagined_m"] is not None]
    print(f"tracking: observed {cm(med(track))}, imagined {cm(med(imag))} (median over "
          f"{len(track)} throws that observed the ball of each throw's median)")
    print("prediction error (median over throws; ratios per throw, then the median):")
    for h in ("0.5", "1"):
        for key, label in (("bounce", "with a contact"), ("no_bounce", "without")):
            vals: dict[str, list[float]] = {"mirror": [], "baseline": [], "mapaware": []}
            r_kf, r_map, r_mk = [], [], []
            for r in ok:
                p = r["prediction"].get(h) or {}
                got = {s: (p.get(s) or {}).get(f"{key}_median") for s in vals}
                for s, v in got.items():
                    if v is not None:
                        vals[s].append(v)
                m, b, a = got["mirror"], got["baseline"], got["mapaware"]
                if m is not None and b:
                    r_kf.append(m / b)
                if m is not None and a:
                    r_map.append(m / a)
                if a is not None and b:
                    r_mk.append(a / b)
            target = ""
            if h == "1" and key == "bounce":
                target = " (target mirror/map-aware <= 0.5x)"
            if h == "1" and key == "no_bounce":
                target = " (target mirror/Kalman <= 0.7x)"
            print(f"  {h} s {label:<15} mirror {cm(med(vals['mirror']))}, Kalman "
                  f"{cm(med(vals['baseline']))}, map-aware {cm(med(vals['mapaware']))}; "
                  f"mirror/Kalman {ratio(med(r_kf))}, mirror/map-aware {ratio(med(r_map))}, "
                  f"map-aware/Kalman {ratio(med(r_mk))} [{len(r_map)} throws]{target}")
    after = [r["confident_after_contact"] for r in ok if r["confident_after_contact"] is not None]
    confident = sum((r["confidence"] or {}).get("confident", 0) for r in ok)
    within = sum(round(((r["confidence"] or {}).get("within_reach") or 0.0)
                       * (r["confidence"] or {}).get("confident", 0)) for r in ok)
    print(f"confidence: frames after the first contact with a confident (>= 0.7) 1 s prediction "
          f"{pct(med(after))} median over {len(after)} throws (target >= 60%); "
          f"{confident} confident predictions, {pct(within / confident if confident else None)} "
          "within the catch reach (target >= 90%)")
    reach = [r for r in ok if (r["intercept"] or {}).get("reachable")]
    n = len(reach)

    def caught(key: str) -> str:
        k = sum(1 for r in reach if (r[key] or {}).get("caught"))
        return f"{k}/{n} ({100 * k / n if n else 0:.0f}%)"

    print(f"interception of reachable throws: robot {caught('intercept')} (target >= 95% and at "
          f"least the map-aware robot's); Kalman robot {caught('baseline')}; map-aware robot "
          f"{caught('mapaware')}; {len(ok) - n} throws out of reach")
    agree = [r for r in ok if (r.get("agent_caught_t") is not None)
             == bool((r["intercept"] or {}).get("caught"))]
    said = [r["seed"] for r in ok if r.get("agent_caught_t") is not None
            and not (r["intercept"] or {}).get("caught")]
    print(f"  caught, the agent's own ^caught against the evaluation's (the true bodies met): "
          f"agree in {len(agree)}/{len(ok)} throws; said caught but not in seeds "
          + (", ".join(map(str, said)) or "none") + "; caught but not said in seeds "
          + (", ".join(str(r["seed"]) for r in ok if r not in agree and r["seed"] not in said)
             or "none"))
    loop = [r["loop_ms"] for r in ok if r.get("loop_ms")]
    real = [r["reality_ms"] for r in ok if r.get("reality_ms")]
    if loop:
        print(f"speed: the loop {1000 / med(loop):.1f} frames/s without the reality "  # type: ignore[operator]
              f"({med(loop):.1f} ms a frame, median per throw; target >= 30 at 640x480); the "
              f"reality (PyBullet's physics, TinyRenderer, the sensor) {med(real):.1f} ms a frame; "
              "measured on a shared machine")
    failed = [r for r in runs if r.get("error")]
    for r in failed:
        print(f"seed {r['seed']} FAILED: {r['error']}\n{r.get('where', '')}", file=sys.stderr)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--throws", type=int, default=50)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--duration", type=float, default=6.0, help="seconds of reality a throw")
    ap.add_argument("--small", action="store_true", help="320x240 instead of 640x480")
    ap.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1))
    ap.add_argument("--json", metavar="PATH", help="also write every throw's figures here")
    ap.add_argument("--show", metavar="SEED", type=int, help="print one throw's scenario and stop")
    ap.add_argument("--out", metavar="FOLDER", help="with --show: run that throw and write its "
                    "outputs (report, trace, video, figures) into FOLDER")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="extra",
                    help="one more override of every throw's scenario (repeatable)")
    args = ap.parse_args()
    if args.show is not None:
        text = scenario_text(args.show, args.small, args.duration)[0]
        if args.out is None:
            print(text)
            return 0
        from adapt.runner import Runner
        from adapt.scenario import loads_scenario

        sc = loads_scenario(text, file=f"foreign-{args.show}.yaml", base=ROOT / "scenarios",
                            overrides=args.extra)
        result = Runner(sc, out=args.out, seed=args.show).run()
        print(json.dumps({k: result.summary.get(k) for k in ("frames", "schemas", "intercept")}))
        return 0
    seeds = list(range(args.first_seed, args.first_seed + args.throws))
    started = time.perf_counter()
    runs = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for k, r in enumerate(pool.map(one, seeds, [args.small] * len(seeds),
                                       [args.duration] * len(seeds),
                                       [tuple(args.extra)] * len(seeds))):
            runs.append(r)
            # each throw as it ends, so a long bench shows its progress and keeps what it did
            print(f"[{k + 1}/{len(seeds)}] seed {r['seed']} ({r['camera']} camera): "
                  + (f"FAILED {r['error']}" if r.get("error") else
                     f"coverage {pct(r['coverage'])}, {r['spurious']} spurious, "
                     f"{r['wall_s']:.0f} s"), file=sys.stderr, flush=True)
            if args.json:
                Path(args.json).write_text(json.dumps(runs, indent=1))
    wall = time.perf_counter() - started
    failed = sum(1 for r in runs if r.get("error"))
    size = "320x240" if args.small else "640x480"
    print(f"{len(runs)} throws ({failed} failed) over randomized PyBullet realities, {size}, "
          f"{args.duration:g} s each, in {wall:.0f} s with {args.jobs} job(s); seeds "
          f"{seeds[0]}-{seeds[-1]}; cameras: "
          + ", ".join(f"{sum(1 for r in runs if r.get('camera') == k)} {k}" for k in CAMERAS))
    report(runs)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
