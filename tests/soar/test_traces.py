"""Traces of the Soar engine: the same records, read by every ``adapt trace`` command, and
``adapt trace diff`` between a run of each engine."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.traceview.reader import Trace

pytestmark = pytest.mark.soar

EXAMPLES = Path(__file__).resolve().parents[2] / "rules" / "examples"


def traced(rules: Path, engine: str, path: Path, *extra: str) -> Path:
    assert main(["rules", "run", str(rules), "--engine", engine, "--json",
                 "--trace", str(path), *extra]) in (0, 3)
    return path


@pytest.fixture
def water_jug(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> Path:
    path = traced(EXAMPLES / "water-jug.soar", "soar", tmp_path / "wj.jsonl")
    capsys.readouterr()
    return path


def test_every_record_is_valid_and_the_header_says_what_is_absent(water_jug: Path) -> None:
    trace = Trace(water_jug)
    header = trace.header.raw
    assert header["engine"] == "soar" and header["kernel"].startswith("Soar 9.6")
    assert {"firings.bindings", "decision.candidates"} <= set(header["absent"])
    records = list(trace.records())
    assert records[-1]["kind"] == "footer" and records[-1]["decisions"] == 8
    firings = [f for r in records if r["kind"] == "phase" for f in r.get("firings", ())]
    assert len(firings) == 32 and not any("bindings" in f for f in firings)
    assert {f["support"] for f in firings if f["rule"] == "water-jug*apply*fill"} == {"o"}


def test_stats_show_wm_and_html_work_on_a_soar_trace(water_jug: Path, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["trace", "stats", str(water_jug), "--json"]) == 0
    stats = json.loads(capsys.readouterr().out)
    assert stats["decisions"] == 8 and stats["production_firings"] == 32
    assert main(["trace", "show", str(water_jug), "--decisions", "2", "--level", "5"]) == 0
    shown = capsys.readouterr().out
    assert "    2: O: O2 (fill)" in shown and "Firing water-jug*apply*fill\n" in shown
    assert main(["trace", "wm", str(water_jug), "--at", "3", "--depth", "1"]) == 0
    assert "^steps 2" in capsys.readouterr().out
    page = tmp_path / "wj.html"
    assert main(["trace", "html", str(water_jug), "--out", str(page)]) == 0
    assert page.stat().st_size > 10_000


def test_why_does_not_invent_which_firing_made_a_wme(water_jug: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["trace", "why", str(water_jug), "--wme", "(S1 ^steps 2)"]) == 0
    out = capsys.readouterr().out
    assert "by one of the firings of this phase" in out
    assert "water-jug*apply*pour*some" in out


@pytest.mark.parametrize("name", ["blocks-world", "towers-of-hanoi", "operator-no-change"])
def test_diff_between_the_engines_compares_what_both_report(
        name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    own = traced(EXAMPLES / f"{name}.soar", "adapt", tmp_path / "a.jsonl")
    kernel = traced(EXAMPLES / f"{name}.soar", "soar", tmp_path / "s.jsonl")
    capsys.readouterr()
    assert main(["trace", "diff", str(own), str(kernel), "--exit-code"]) == 0
    out = capsys.readouterr().out
    assert "headers differ: engine: 'adapt' vs 'soar'" in out
    assert "note: firings compared by rule only" in out
    assert "^epmem" not in out  # both engines build Soar's memory structures: all compared
    assert out.rstrip().splitlines()[-1].startswith("the traces agree on all ")


def test_diff_finds_where_two_soar_runs_part(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    a = tmp_path / "a.soar"
    a.write_text((EXAMPLES / "water-jug.soar").read_text())
    b = tmp_path / "b.soar"
    b.write_text(a.read_text().replace("fill the big jug", "fill the BIG jug"))
    ta = traced(a, "soar", tmp_path / "a.jsonl")
    tb = traced(b, "soar", tmp_path / "b.jsonl")
    capsys.readouterr()
    assert main(["trace", "diff", str(ta), str(tb), "--exit-code"]) == 1
    out = capsys.readouterr().out
    assert "the traces diverge at decision cycle 2: apply phase, output" in out
    assert "^epmem" not in out and "engine" not in out  # one engine: all of memory compared


@pytest.mark.browser
def test_the_viewer_names_the_engine_and_what_its_trace_lacks(
        water_jug: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import os

    if not os.path.exists("/usr/bin/chromium"):
        pytest.skip("/usr/bin/chromium is missing (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api")
    page_path = tmp_path / "wj.html"
    assert main(["trace", "html", str(water_jug), "--out", str(page_path)]) == 0
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium",
                                    args=["--headless", "--no-sandbox", "--disable-gpu"])
        page = browser.new_page()
        page.goto(page_path.as_uri())
        page.wait_for_selector("#run-summary b")
        summary = page.inner_text("#run-summary")
        notice = page.inner_text("#notices")
        firings = page.inner_text("body")
        browser.close()
    assert "engine soar (Soar 9.6" in summary
    assert notice.startswith("Not in this trace (the engine does not report them): firings.bindings")
    assert "water-jug*propose*initialize" in firings
