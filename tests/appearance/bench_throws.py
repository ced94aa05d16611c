"""The throws of ``bench/foreign.py --small`` as scenarios, for tests that replay one."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path
from typing import Any

from adapt.runner import Runner
from adapt.scenario import OutputSettings, Scenario, loads_scenario

ROOT = Path(__file__).resolve().parents[2]
#: No outputs written: a test reads the run's frames through a listener.
QUIET = OutputSettings(report=False, trace=False, video=False, figures=False)


def scenario_text(seed: int, duration: float, small: bool = True) -> str:
    """Throw ``seed``'s scenario YAML at 320x240 (640x480 unless ``small``), ``duration``
    seconds long."""
    spec = importlib.util.spec_from_file_location("_bench_foreign", ROOT / "bench" / "foreign.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return str(module.scenario_text(seed, small, duration)[0])


def throw(seed: int, duration: float, *overrides: str, small: bool = True) -> Scenario:
    """Throw ``seed``'s scenario, read as ``bench/foreign.py`` reads it (with ``--set``
    style ``overrides``, ``KEY=VALUE``; at 640x480 unless ``small``)."""
    return loads_scenario(scenario_text(seed, duration, small), file=f"foreign-{seed}.yaml",
                          base=ROOT / "scenarios", overrides=list(overrides))


class Rows:
    """A listener: per frame, the object schemas' names, the ball's sighting and what is
    true of the ball and the robot (evaluation: a test may read the truth)."""

    def __init__(self) -> None:
        self.truth: Any = None
        self.rows: list[dict[str, Any]] = []

    def frame(self, record: Any) -> None:
        t = self.truth.at(record.index)
        ball = t.objects.get("ball")  # None before it is thrown
        tracked = record.tracked_object("ball")
        self.rows.append({"names": {x.name for x in record.tracked},
                          "truth": None if ball is None else ball.position,
                          "height": None if ball is None else ball.height,
                          "robot": None if t.robot is None else t.robot.position,
                          "observed": None if tracked is None else tracked.observed})


def replay(seed: int, duration: float, small: bool = True
           ) -> tuple[Scenario, list[dict[str, Any]]]:
    """Throw ``seed`` run for ``duration`` seconds (at 640x480 unless ``small``): its
    scenario, and its frames' rows."""
    sc = throw(seed, duration, small=small)
    rows = Rows()
    runner = Runner(sc, out=None, seed=seed, outputs=QUIET, listeners=(rows,))
    rows.truth = runner.truth
    runner.run()
    return sc, rows.rows


#: A sighting within this many of the ball's radii of the truth is on it.
ON_RADII = 2.0


def sightings(sc: Scenario, rows: list[dict[str, Any]]) -> tuple[list[int], list[int]]:
    """The frames (indices into ``rows``) in which the ball was sighted, and those of them
    whose sighting was within :data:`ON_RADII` of the ball's radii of the truth."""
    radius = sc.model("ball").ball.radius
    seen = [i for i, r in enumerate(rows) if r["observed"] is not None]
    on = [i for i in seen if math.dist(rows[i]["observed"], rows[i]["truth"]) < ON_RADII * radius]
    return seen, on
