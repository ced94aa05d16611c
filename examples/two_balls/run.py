"""Two balls over many seeds, beside a robot that always chases the nearest ball.

    python examples/two_balls/run.py --runs 20 --out runs/two-balls

Each run is ``two-balls.yaml`` with its own seed (the throws, the balls' true
parameters), through adapt's Python API.  The nearest-ball chaser is a baseline of the
run (:func:`options.nearest_chaser`): it sees the same sightings and drives one simulated
robot with the real robot's limits.  Both robots are scored the same way, against the
ground truth in the run's report: a ball is **caught** when the robot -- the real one, or
the chaser's simulated one -- comes within its radius plus the ball's (plus 3 cm) of the
true ball.  The figure is the share of balls caught.
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import statistics
import sys
from pathlib import Path
from typing import Any

import adapt

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "two-balls.yaml"
BALLS = ("ball", "ball2")


class Chaser:
    """A frame listener: where the nearest-ball chaser's robot is, frame by frame."""

    def __init__(self) -> None:
        self.where: dict[int, tuple[float, float] | None] = {}

    def frame(self, record: adapt.FrameRecord) -> None:
        state = record.baselines.get("nearest")
        robots = [] if state is None else [p for p in state.robots.values() if p is not None]
        self.where[record.index] = robots[0] if robots else None


def caught(report: dict[str, Any], chaser: Chaser, reach: float) -> dict[str, dict[str, bool]]:
    """Which balls each robot caught (see the module docstring)."""
    out = {"mirror": {b: False for b in BALLS}, "nearest": {b: False for b in BALLS}}
    for f in report["frames"]:
        truth = f.get("truth", {})
        robots = {"mirror": f.get("truth_robot"), "nearest": chaser.where.get(f["index"])}
        for ball in BALLS:
            where = truth.get(ball)
            if where is None:
                continue
            for who, robot in robots.items():
                if robot is not None and math.dist(robot, where) <= reach:
                    out[who][ball] = True
    return out


def runs(n: int, out: Path, first_seed: int = 0, max_frames: int | None = None
         ) -> list[dict[str, Any]]:
    """Run ``n`` seeds and score each."""
    sc = adapt.load_scenario(SCENARIO)
    options = importlib.import_module(sc.plugins[0].module)
    assert sc.scene.robot is not None
    reach = sc.scene.robot.radius + sc.model("ball").ball.radius + options.MARGIN
    results = []
    for seed in range(first_seed, first_seed + n):
        chaser = Chaser()
        folder = out / f"seed{seed}"
        result = adapt.run(sc, out=folder, seed=seed, max_frames=max_frames, listeners=[chaser],
                           baselines={"nearest": options.nearest_chaser()})
        report = json.loads((folder / "report.json").read_text())
        results.append({"seed": seed, "writes": result.summary.get("writes", ""),
                        **caught(report, chaser, reach)})
    return results


def rates(results: list[dict[str, Any]]) -> dict[str, Any]:
    """The share of balls each robot caught."""
    def share(who: str) -> float | None:
        got = [r[who][b] for r in results for b in BALLS]
        return round(statistics.mean(got), 3) if got else None

    return {"runs": len(results), "balls": len(results) * len(BALLS),
            "mirror_caught": share("mirror"), "nearest_caught": share("nearest")}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--runs", type=int, default=20)
    p.add_argument("--first-seed", type=int, default=0)
    p.add_argument("--out", type=Path, default=Path("runs/two-balls"))
    args = p.parse_args(argv)
    results = runs(args.runs, args.out, args.first_seed)
    summary = rates(results)
    (args.out / "runs.json").write_text(json.dumps({"runs": results, "rates": summary}, indent=1))
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
