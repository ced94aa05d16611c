"""The evaluation's reachability oracle (:meth:`adapt.runner.evaluation.Evaluation.reachable`)."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.runner.evaluation import Evaluation
from adapt.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


@pytest.fixture()
def evaluation() -> Evaluation:
    """An evaluation of bouncing-ball.yaml that saw a ball in the far corner for half a second,
    from the robot's start: out of reach of a robot of 0.8 m/s in that time."""
    sc = load_scenario(SCENARIOS / "bouncing-ball.yaml")
    ev = Evaluation(sc, truth=object(), baselines=("kalman", "mapaware"))  # type: ignore[arg-type]
    ev._appeared = (0.0, (0.0, -0.6))
    for k in range(16):
        ev._path.append((k / 30.0, 2.3 - 0.01 * k, 2.8))
    return ev


def test_a_path_no_robot_can_reach_in_time_is_out_of_reach(evaluation: Evaluation) -> None:
    assert evaluation.reachable() is False


@pytest.mark.parametrize("who", ["robot", "kalman", "mapaware"])
def test_a_robot_that_met_the_object_proves_it_reachable(evaluation: Evaluation, who: str) -> None:
    # the true path after the real robot met the object is the robot's doing (it may have
    # pushed it away); a meeting is the proof that a robot could
    if who == "robot":
        evaluation.caught = 0.4
    else:
        evaluation.baselines_caught[who] = 0.4
    assert evaluation.reachable() is True
