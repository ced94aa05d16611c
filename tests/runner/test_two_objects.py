"""Two objects in one run (issue 22): each gets its own foreground-object schema, spawned for
its own difference region, told apart by the region's colour; when the colours cannot tell
them apart, the network refuses a second owner for one region and the rules print why."""

from __future__ import annotations

from pathlib import Path

import adapt

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "examples" / "two_balls" / "two-balls.yaml"
GOALS = ["goals=[{name: intercept, object: ball}, {name: watch, object: ball2}]",
         "rules=[../../rules/mirror/perception.soar]"]


def spawned(run: adapt.Run) -> dict[str, object]:
    """Each spawned schema's parameters, as the frame records' events say."""
    out: dict[str, object] = {}
    for record in run:
        for e in record.events:
            if e.kind.value == "spawned":
                out[e.schema] = e.data["parameters"]
    return out


def test_two_balls_of_two_colours_get_a_schema_each_for_their_own_region() -> None:
    with adapt.start(SCENARIO, overrides=GOALS, max_frames=55) as run:
        found = spawned(run)
    assert sorted(found) == ["ball", "ball2"], found
    regions = {name: p["region"] for name, p in found.items()}  # type: ignore[index]
    assert regions["ball"] != regions["ball2"]
    assert run.result is not None and "failed" not in run.result.summary["writes"]


def test_two_balls_of_one_colour_are_refused_a_second_owner_for_one_region() -> None:
    same = GOALS + ["world.objects.ball2.color=[230, 60, 30]"]
    with adapt.start(SCENARIO, overrides=same, max_frames=20) as run:
        found = spawned(run)
    assert len(found) == 1, found
    writes = run.result.summary["writes"] if run.result else ""
    assert "command ^instantiate failed: region " in writes and "already has an owner" in writes
