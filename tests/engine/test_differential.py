"""Differential tests: each agent runs in the real Soar kernel and in adapt.

Every ``.soar`` file in ``tests/engine/agents/`` and ``rules/examples/`` is
run in real Soar (PyPI ``soar-sml``, in a child process, once per session)
and in adapt; ``halted``, ``stop_reason``, ``decisions``, ``operators``,
``impasses`` and the output, segment by segment per decision (writes of one
segment compared as a multiset), must agree.  The expected behaviour is
always what Soar does in the same test run, never a stored answer.
"""

from __future__ import annotations

import warnings
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from .soar_harness import (
    DEFAULT_MAX_DECISIONS,
    Report,
    first_difference,
    max_decisions_of,
    run_adapt,
    run_soar,
    run_soar_many,
)

AGENTS = sorted((Path(__file__).parent / "agents").glob("*.soar"))
EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "rules" / "examples").glob("*.soar"))
ALL_FILES = AGENTS + EXAMPLES


def _soar_importable() -> bool:
    with warnings.catch_warnings():  # SWIG's import-time DeprecationWarning
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            import soar_sml  # noqa: F401  (the kernel itself only ever runs in a child)
        except ImportError:
            return False
    return True


requires_soar = pytest.mark.skipif(
    not _soar_importable(),
    reason="soar_sml (PyPI soar-sml, the real Soar kernel) cannot be imported: "
    "differential tests against real Soar are skipped",
)


def _orders_like_soars_rete(path: Path) -> bool:
    """The agent says (``# order: Soar's Rete``) that its run depends on the
    order in which Soar's Rete finds matches."""
    return "# order: Soar's Rete" in path.read_text(encoding="utf-8")


def _file_id(path: Path) -> str:
    return f"{path.parent.name}/{path.stem}"


@pytest.fixture(scope="session")
def soar_reports(request: pytest.FixtureRequest) -> dict[Path, Report]:
    """Real Soar's report for every selected file, two child processes at a time."""
    wanted: set[Path] = set()
    for item in request.session.items:
        params: dict[str, Any] = getattr(getattr(item, "callspec", None), "params", {})
        if isinstance(params.get("agent_file"), Path):
            wanted.add(params["agent_file"])
    return run_soar_many(sorted(wanted) or ALL_FILES, jobs=2)


@requires_soar
@pytest.mark.soar
@pytest.mark.parametrize("trace_level", [None, 5], ids=["untraced", "traced"])
@pytest.mark.parametrize("matcher", ["rete", "naive"])
@pytest.mark.parametrize("agent_file", ALL_FILES, ids=_file_id)
def test_agent_behaves_as_in_real_soar(agent_file: Path, matcher: str, trace_level: int | None,
                                       soar_reports: dict[Path, Report]) -> None:
    """Every agent, with both matchers, with and without a (full) trace: a
    trace is a listener and must not change the run."""
    if matcher == "naive" and _orders_like_soars_rete(agent_file):
        pytest.skip("the run depends on the order Soar's Rete finds matches in (a random "
                    "choice, identifier numbers), which only adapt's Rete reproduces; the "
                    "brute-force matcher is the reference for what matches, not for its order")
    soar = soar_reports[agent_file]
    adapt = run_adapt(agent_file, matcher=matcher, trace_level=trace_level)
    difference = first_difference(soar, adapt)
    assert difference is None, f"{_file_id(agent_file)} ({matcher}, {trace_level}): {difference}"


@requires_soar
@pytest.mark.soar
@pytest.mark.parametrize("trace_level", [None, 5], ids=["untraced", "traced"])
@pytest.mark.parametrize("agent_file", ALL_FILES, ids=_file_id)
def test_the_soar_engine_gives_the_kernels_own_report(agent_file: Path, trace_level: int | None,
                                                      soar_reports: dict[Path, Report]) -> None:
    """adapt's Soar engine (the kernel behind adapt's interface, with or without a full
    trace) gives what soar-sml gives when driven directly: the same decisions, writes,
    halt and stop reason, production firings and kernel messages."""
    soar = soar_reports[agent_file]
    ours = run_adapt(agent_file, engine="soar", trace_level=trace_level)
    difference = first_difference(soar, ours)
    assert difference is None, f"{_file_id(agent_file)} (soar engine): {difference}"
    assert ours["production_firings"] == soar["production_firings"]
    # the same messages (a printed error and the XML trace's messages of one decision
    # cycle may reach the two in another order)
    assert Counter(ours["messages"]) == Counter(soar["messages"])


@requires_soar
@pytest.mark.soar
@pytest.mark.parametrize("agent_file", ALL_FILES, ids=_file_id)
def test_agent_is_well_formed_in_real_soar(agent_file: Path,
                                           soar_reports: dict[Path, Report]) -> None:
    """Each agent loads and halts in Soar; a bounded one declares its bound."""
    soar = soar_reports[agent_file]
    assert not soar.get("error"), soar.get("error")
    if max_decisions_of(agent_file) == DEFAULT_MAX_DECISIONS:
        assert soar["halted"] and soar["stop_reason"] == "halt", soar["stop_reason"]
    else:
        assert not soar["halted"], "a bounded agent must not halt"


def test_suite_has_the_required_agents() -> None:
    substate_agents = [p for p in AGENTS if p.stem.startswith("sub_")]
    own_agents = [p for p in AGENTS if not p.stem.startswith(("sub_", "pref_"))]
    assert len(own_agents) >= 20 and len(substate_agents) >= 8
    names = {p.stem for p in EXAMPLES}
    assert {"water-jug", "blocks-world", "towers-of-hanoi", "missionaries-cannibals",
            "operator-no-change"} <= names


# ---- the comparison itself (no Soar needed) --------------------------------


def _report(**fields: Any) -> Report:
    base: Report = {"halted": True, "stop_reason": "halt", "decisions": 2, "output": "a\nb\n",
                    "operators": [[1, 0, "go"], [2, 0, "stop"]], "impasses": [],
                    "writes": [[1, "a\n"], [1, "b\n"]]}
    base.update(fields)
    return base


def test_identical_reports_have_no_difference() -> None:
    assert first_difference(_report(), _report()) is None


def test_writes_within_one_decision_may_come_in_any_order() -> None:
    swapped = _report(output="b\na\n", writes=[[1, "b\n"], [1, "a\n"]])
    assert first_difference(_report(), swapped) is None


def test_a_write_in_another_decision_is_reported_with_its_decision() -> None:
    moved = _report(writes=[[1, "a\n"], [2, "b\n"]])
    assert first_difference(_report(), moved) == (
        'decision 1: writes after it: Soar ["a\\n", "b\\n"], adapt ["a\\n"]')


def test_a_different_selection_names_the_decision() -> None:
    other = _report(operators=[[1, 0, "go"], [2, 0, "wait"]])
    assert first_difference(_report(), other) == (
        'decision 2: selection: Soar [[0, "stop"]], adapt [[0, "wait"]]')


def test_an_impasse_difference_comes_before_later_ones() -> None:
    other = _report(impasses=[[1, 1, "tie", "operator"]], decisions=3)
    assert first_difference(_report(), other).startswith("decision 1: impasse")


def test_without_segments_the_whole_output_is_compared() -> None:
    unsegmented = {k: v for k, v in _report(output="a\nc\n").items() if k != "writes"}
    assert first_difference(_report(), unsegmented) == (
        "output line 2 (Soar wrote it after decision 1): Soar 'b\\n', adapt 'c\\n'")


def test_an_adapt_error_is_reported() -> None:
    assert first_difference(_report(), {"error": "boom"}) == "adapt failed: boom"


@requires_soar
@pytest.mark.soar
@pytest.mark.parametrize("bound", [0, 1, 3])
def test_a_decision_bound_stops_as_in_real_soar(bound: int) -> None:
    """``run 0`` runs one decision in Soar; the bound is the same with or without a trace."""
    water_jug = next(p for p in EXAMPLES if p.stem == "water-jug")
    soar = run_soar(water_jug, max_decisions=bound)
    for trace_level in (None, 5):
        adapt = run_adapt(water_jug, max_decisions=bound, trace_level=trace_level)
        difference = first_difference(soar, adapt)
        assert difference is None, f"run {bound} (trace {trace_level}): {difference}"
        assert adapt["decisions"] == max(bound, 1) and adapt["stop_reason"] == "max-decisions"
