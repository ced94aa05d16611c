"""``--seeds`` and ``--set``: what they give, and positioned errors for what they cannot."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from adapt.errors import ScenarioError, SweepSpecError
from adapt.sweep.grid import parse_axis, parse_seeds
from adapt.sweep.plan import cell_hash, make_plan


def test_seeds_lists_and_inclusive_ranges() -> None:
    assert parse_seeds("1-200") == tuple(range(1, 201))
    assert parse_seeds("3, 1,10-12") == (3, 1, 10, 11, 12)
    assert parse_seeds("0") == (0,)


@pytest.mark.parametrize("text, col, words", [
    ("", 1, "expected a seed"),
    ("1,,3", 3, "expected a seed"),
    ("1-5,x", 5, "got 'x'"),
    ("-3", 1, "expected a seed"),
    ("1-5,4", 5, "seed 4 is given twice (first at column 1)"),
    ("9-2", 1, "runs backwards"),
    ("1.5", 1, "expected a seed"),
])
def test_bad_seeds_point_at_their_column(text: str, col: int, words: str) -> None:
    with pytest.raises(SweepSpecError) as err:
        parse_seeds(text)
    assert err.value.file == "--seeds" and err.value.col == col
    assert words in err.value.message
    assert str(err.value).splitlines()[1].strip() == text.strip() or not text.strip()


def test_set_values_ranges_and_bracketed_commas() -> None:
    a = parse_axis("world.objects.ball.restitution=0.5:0.9:0.1")
    assert a.values == [0.5, 0.6, 0.7, 0.8, 0.9]  # decimal steps: no 0.7000000000000001
    assert a.numeric
    b = parse_axis("reality.camera_offset_deg=[1, 0, 0],[2,0,0], 3")
    assert b.values == [[1, 0, 0], [2, 0, 0], 3] and not b.numeric
    assert [i.col for i in b.items] == [27, 37, 46]
    c = parse_axis("run.fps=30:10:-10,60")
    assert c.values == [30, 20, 10, 60]
    d = parse_axis("schemas.scene-background.mode='a,b',c")
    assert d.values == ["a,b", "c"]


@pytest.mark.parametrize("text, col, words", [
    ("world.dt", 9, "expected KEY=VALUES"),
    ("=1,2", 1, "expected KEY=VALUES"),
    ("world.dt=0.01,,0.02", 15, "an empty value"),
    ("world.dt=0.01,0.010", 15, "given twice"),
    ("run.fps=1:10:0", 9, "step of lo:hi:step is 0"),
    ("run.fps=10:1:1", 9, "never reaches 1"),
    ("run.fps=0:1e9:1", 9, "at most"),
])
def test_bad_set_points_at_its_column(text: str, col: int, words: str) -> None:
    with pytest.raises(SweepSpecError) as err:
        parse_axis(text)
    assert err.value.file == "--set" and err.value.col == col
    assert words in err.value.message


@given(st.integers(-50, 50), st.integers(1, 40), st.integers(1, 9))
def test_a_range_steps_exactly_and_includes_its_end(lo: int, n: int, step: int) -> None:
    hi = lo + (n - 1) * step
    text = f"x={lo / 10}:{hi / 10}:{step / 10}"
    values = parse_axis(text).values
    assert len(values) == n
    assert values[0] == lo / 10 and values[-1] == hi / 10
    assert all(round(b - a, 9) == step / 10 for a, b in zip(values, values[1:]))


def test_cells_are_named_by_their_overrides_not_their_place() -> None:
    assert cell_hash((("a", 1), ("b", 2))) == cell_hash((("b", 2), ("a", 1)))
    assert cell_hash((("a", 1),)) != cell_hash((("a", 1.5),))


def test_plan_is_the_product_seed_by_seed(room: Path) -> None:
    plan = make_plan(room, seeds="1-3", sets=["reality.appearance.noise=1,2",
                                              "reality.appearance.blur=0:1:0.5"])
    assert len(plan.cells) == 6 and len(plan.runs) == 18
    assert [r.seed for r in plan.runs[:7]] == [1] * 6 + [2]
    assert plan.runs[0].overrides == ("reality.appearance.noise=1", "reality.appearance.blur=0.0")
    assert len({r.key for r in plan.runs}) == 18
    assert make_plan(room).seeds == (0,)  # the scenario has no seed: 0, as a run would


def test_a_value_the_scenario_refuses_is_reported_at_its_column(room: Path) -> None:
    text = "reality.appearance.noise=1, 2,-4"
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=[text])
    e = err.value
    assert (e.file, e.col) == ("--set", text.index("-4") + 1)
    assert e.source_line == text and "reality.appearance.noise" in e.message


def test_a_refused_value_of_a_range_points_at_the_range(room: Path) -> None:
    text = "reality.appearance.noise=90:110:10"
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=[text])
    assert err.value.col == 26 and "(the value 110 of the range)" in err.value.message


def test_a_key_path_that_names_nothing_is_refused(room: Path) -> None:
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=["reality.objects.nobody.radius=0.1,0.2"])
    assert err.value.file == "--set" and "no item named 'nobody'" in err.value.message
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=["reality.apperance.noise=1"])
    assert "did you mean 'appearance'" in err.value.message


def test_a_combination_the_scenario_refuses_names_its_cell(room: Path) -> None:
    # each value alone is fine; run.duration beside run.max_frames, both set, is not (one
    # --set of either alone replaces the file's other)
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=["run.max_frames=5", "run.duration=1,2"])
    assert "max_frames" in str(err.value)


def test_schema_parameters_are_checked_before_running(room: Path) -> None:
    with pytest.raises(ScenarioError) as err:
        make_plan(room, sets=["schemas.scene-background.nonsense=1"])
    assert err.value.file == "--set" and "unknown parameter" in err.value.message


def test_seeds_are_swept_with_seeds_and_an_axis_once(room: Path) -> None:
    with pytest.raises(SweepSpecError, match="swept with --seeds"):
        make_plan(room, sets=["seed=1,2"])
    with pytest.raises(SweepSpecError, match="set twice"):
        make_plan(room, sets=["run.fps=10", "run.fps=20"])
    with pytest.raises(SweepSpecError, match="--max-frames must be at least 1"):
        make_plan(room, max_frames=0)


def test_a_plugin_file_is_part_of_the_scenarios_fingerprint(tmp_path: Path) -> None:
    # a sweep never mixes runs of two versions of its scenario: a changed plugin is one
    (tmp_path / "extra.py").write_text("VALUE = 1\n")
    scenario = tmp_path / "s.yaml"
    root = Path(__file__).resolve().parents[2]
    base = (root / "scenarios" / "background-sync.yaml").read_text()
    scenario.write_text("plugins: [extra.py]\n" + base.replace("../rules", str(root / "rules")))
    before = make_plan(scenario).fingerprint
    assert make_plan(scenario).fingerprint == before
    (tmp_path / "extra.py").write_text("VALUE = 2\n")
    assert make_plan(scenario).fingerprint != before
