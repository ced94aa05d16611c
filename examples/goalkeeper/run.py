"""The goalkeeper over many throws, beside a Kalman-driven keeper in the same runs.

    python examples/goalkeeper/run.py --throws 50 --out runs/goalkeeper

Each throw is one run of ``goalkeeper.yaml`` with its own seed (the throw's place, speed
and heading, the ball's true parameters), through adapt's Python API.  The Kalman keeper
is a baseline of the run (:func:`keeper.kalman_keeper`): it sees the same sightings and
drives a simulated robot with the real robot's limits.  Both are scored against the
ground truth of the run's report:

* **kept out**: the real ball never crossed the goal line between the posts (the real
  robot is a body of reality's physics: standing in the way stops the ball);
* **in reach**: when the true ball first came within reach of the line (robot radius plus
  ball radius), the keeper -- the real robot, or the Kalman keeper's simulated one --
  stood across its way: less than that reach from it along the line.  This is the figure both keepers have.

Throws that miss the goal by more than the ball's radius count for neither.
"""

from __future__ import annotations

import argparse
import importlib
import json
import statistics
import sys
from pathlib import Path
from typing import Any

import adapt

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "goalkeeper.yaml"


class Keepers:
    """A frame listener: where each keeper stands, frame by frame."""

    def __init__(self) -> None:
        self.real: dict[int, tuple[float, float] | None] = {}
        self.kalman: dict[int, tuple[float, float] | None] = {}

    def frame(self, record: adapt.FrameRecord) -> None:
        state = record.baselines.get("kalman-keeper")
        self.kalman[record.index] = None if state is None else state.robots.get("ball")


def score(report: dict[str, Any], keepers: Keepers, goal: dict[str, float], radius: float,
          robot_radius: float) -> dict[str, Any]:
    """One throw's outcome (see the module docstring)."""
    line, left, right = goal["line_y"], goal["left"], goal["right"]
    reach = radius + robot_radius
    frames = [f for f in report["frames"] if f.get("truth", {}).get("ball") is not None]
    crossed = any(f["truth"]["ball"][1] < line - radius
                  and left - radius <= f["truth"]["ball"][0] <= right + radius for f in frames)
    arrive = next((f for f in frames if f["truth"]["ball"][1] <= line + reach), None)
    if arrive is None or not left - radius <= arrive["truth"]["ball"][0] <= right + radius:
        return {"on_target": False}
    ball = arrive["truth"]["ball"]
    real = arrive.get("truth_robot")
    kalman = keepers.kalman.get(arrive["index"])
    return {"on_target": True, "kept_out": not crossed, "arrival_t": arrive["t"],
            "mirror_in_reach": real is not None and abs(real[0] - ball[0]) <= reach,
            "kalman_in_reach": kalman is not None and abs(kalman[0] - ball[0]) <= reach}


def throws(n: int, out: Path, first_seed: int = 0, max_frames: int | None = None
           ) -> list[dict[str, Any]]:
    """Run ``n`` throws (seeds ``first_seed`` on) and score each."""
    sc = adapt.load_scenario(SCENARIO)
    keeper = importlib.import_module(sc.plugins[0].module)  # the plugin, as the scenario loaded it
    settings = sc.schema_settings("goal-keeper")
    goal = {k: float(settings.parameters[k]) if settings else 0.0
            for k in ("line_y", "left", "right")}
    radius = sc.model("ball").ball.radius
    assert sc.scene.robot is not None
    results = []
    for seed in range(first_seed, first_seed + n):
        keepers = Keepers()
        folder = out / f"seed{seed}"
        adapt.run(sc, out=folder, seed=seed, max_frames=max_frames, listeners=[keepers],
                  baselines={"kalman-keeper": keeper.kalman_keeper(**goal)})
        report = json.loads((folder / "report.json").read_text())
        results.append({"seed": seed, **score(report, keepers, goal, radius,
                                              sc.scene.robot.radius)})
    return results


def rates(results: list[dict[str, Any]]) -> dict[str, Any]:
    """The success rates over the throws on target."""
    on = [r for r in results if r["on_target"]]

    def share(key: str) -> float | None:
        return round(statistics.mean(bool(r[key]) for r in on), 3) if on else None

    return {"throws": len(results), "on_target": len(on), "mirror_kept_out": share("kept_out"),
            "mirror_in_reach": share("mirror_in_reach"), "kalman_in_reach": share("kalman_in_reach")}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--throws", type=int, default=50)
    p.add_argument("--first-seed", type=int, default=0)
    p.add_argument("--out", type=Path, default=Path("runs/goalkeeper"))
    args = p.parse_args(argv)
    results = throws(args.throws, args.out, args.first_seed)
    summary = rates(results)
    (args.out / "throws.json").write_text(json.dumps({"throws": results, "rates": summary},
                                                     indent=1))
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
