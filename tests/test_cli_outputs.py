"""No command replaces its own input, and every output is checked before any work
(``adapt/files.py``: one mechanism for every command that writes)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.errors import OutputError
from adapt.files import Output, atomic_path, check_outputs, same_file, write_output

ROOT = Path(__file__).resolve().parents[1]
WATER_JUG = ROOT / "rules" / "examples" / "water-jug.soar"


@pytest.fixture()
def rules(tmp_path: Path) -> Path:
    path = tmp_path / "x.soar"
    path.write_bytes(WATER_JUG.read_bytes())
    return path


@pytest.fixture()
def trace(tmp_path: Path, rules: Path) -> Path:
    path = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(rules), "--trace", str(path), "--json"]) == 0
    return path


def _error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert err.startswith("adapt: error: ") and "Traceback" not in err, err
    return err


def test_rules_run_refuses_a_trace_that_is_its_rule_file(rules: Path, capsys) -> None:
    before = rules.read_bytes()
    assert main(["rules", "run", str(rules), "--trace", str(rules)]) == 1
    assert "is a rule file of the run" in _error(capsys)
    assert rules.read_bytes() == before


def test_rules_run_refuses_the_rule_file_through_a_symlink_and_a_hard_link(
        rules: Path, tmp_path: Path, capsys) -> None:
    (tmp_path / "link.jsonl").symlink_to(rules)
    os.link(rules, tmp_path / "hard.jsonl")
    before = rules.read_bytes()
    for alias in ("link.jsonl", "hard.jsonl"):
        assert main(["rules", "run", str(rules), "--trace", str(tmp_path / alias)]) == 1
        assert "is a rule file of the run" in _error(capsys)
    assert rules.read_bytes() == before


def test_rules_run_refuses_a_trace_name_that_is_not_json_lines(rules: Path, tmp_path: Path,
                                                               capsys) -> None:
    assert main(["rules", "run", str(rules), "--trace", str(tmp_path / "t.soar")]) == 1
    assert "expected a .jsonl or .ndjson file name" in _error(capsys)
    assert not (tmp_path / "t.soar").exists()


def test_rules_run_makes_the_trace_folder(rules: Path, tmp_path: Path, capsys) -> None:
    target = tmp_path / "new" / "deeper" / "t.jsonl"
    assert main(["rules", "run", str(rules), "--trace", str(target)]) == 0
    assert target.read_text().splitlines()[-1].startswith('{"kind":"footer"')


def test_trace_html_refuses_to_replace_the_trace(trace: Path, capsys) -> None:
    before = trace.read_bytes()
    assert main(["trace", "html", str(trace), "--out", str(trace)]) == 1
    assert "is the trace; an output never replaces an input" in _error(capsys)
    assert trace.read_bytes() == before


def test_trace_html_default_output_that_would_be_the_trace(tmp_path: Path, trace: Path,
                                                           capsys) -> None:
    named_html = tmp_path / "run.html"
    named_html.write_bytes(trace.read_bytes())
    assert main(["trace", "html", str(named_html)]) == 1
    assert "the HTML page" in _error(capsys)
    assert named_html.read_bytes() == trace.read_bytes()


def test_trace_html_checks_the_extension_and_makes_the_folder(trace: Path, tmp_path: Path,
                                                              capsys) -> None:
    assert main(["trace", "html", str(trace), "--out", str(tmp_path / "page.txt")]) == 1
    assert "expected a .html or .htm file name" in _error(capsys)
    target = tmp_path / "a" / "b" / "page.html"
    assert main(["trace", "html", str(trace), "--out", str(target)]) == 0
    assert capsys.readouterr().out.strip() == str(target)
    assert target.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_messages_never_name_a_temporary_file(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(OSError) as caught:
        with atomic_path(blocker / "x.png"):
            pass
    assert caught.value.filename == str(blocker / "x.png") and ".tmp" not in str(caught.value)
    with pytest.raises(OutputError) as refused:
        write_output(Output("--out", Path("/proc/adapt-test.png")), b"x")
    assert "--out '/proc/adapt-test.png'" in str(refused.value) and ".tmp" not in str(refused.value)


def test_check_outputs_refuses_one_file_twice_and_an_input(tmp_path: Path) -> None:
    a = tmp_path / "a.png"
    with pytest.raises(OutputError, match="is the same file as --out"):
        check_outputs([Output("--out", a), Output("--labels", tmp_path / "." / "a.png")])
    with pytest.raises(OutputError, match="is the scenario"):
        check_outputs([Output("--out", tmp_path / "s.yaml")], [("the scenario", tmp_path / "s.yaml")])
    check_outputs([Output("--out", a, (".png",))], [("the scenario", tmp_path / "s.yaml")])
    assert not a.exists()  # checking writes nothing


def test_same_file() -> None:
    assert same_file("a/../b", "b") and not same_file("a", "b")


def test_a_folder_output_may_hold_no_input_and_no_output_goes_inside_an_input_folder(
        tmp_path: Path) -> None:
    from adapt.files import Inputs

    texture = tmp_path / "out" / "figures" / "mine.png"
    texture.parent.mkdir(parents=True)
    texture.write_bytes(b"png")
    inputs = Inputs([("the scenario's world.floor.texture", texture)])
    figures = Output("the figures output", tmp_path / "out" / "figures", folder=True)
    with pytest.raises(OutputError, match=r"would hold the scenario's world.floor.texture"):
        check_outputs([figures], inputs)
    check_outputs([Output("the figures output", tmp_path / "elsewhere", folder=True)], inputs)
    look = tmp_path / "look"
    look.mkdir()
    inputs.add("the learned appearance", look, folder=True)
    with pytest.raises(OutputError, match="is inside the learned appearance"):
        check_outputs([Output("--out", look / "deeper" / "report.json")], inputs)
    with pytest.raises(OutputError, match="is the learned appearance"):
        check_outputs([Output("the appearance output", look, folder=True)], inputs)
    os.link(texture, tmp_path / "hard.png")
    with pytest.raises(OutputError, match="is the scenario's world.floor.texture"):
        check_outputs([Output("--out", tmp_path / "hard.png")], inputs)


def test_a_scenario_lists_every_file_it_names(tmp_path: Path) -> None:
    from dataclasses import replace

    from adapt.scenario import load_scenario

    scenario = load_scenario(ROOT / "scenarios" / "video-sequence.yaml")
    named = {i.what.split(" (")[0]: i for i in scenario.inputs()}
    frames = sorted((ROOT / "scenarios" / "video" / "frames").glob("*.jpg"))
    assert sum(i.what.startswith("a frame of") for i in scenario.inputs()) == len(frames)
    assert named["the scenario's reality.ground_truth"].path.name == "truth.csv"
    room = load_scenario(ROOT / "scenarios" / "room.yaml")
    texture = tmp_path / "t.png"
    texture.write_bytes(b"x")
    floor = replace(room.scene.floor, texture=str(texture))
    changed = replace(room, scene=replace(room.scene, floor=floor), appearance=tmp_path)
    whats = [i.what for i in changed.inputs()]
    assert "the scenario's world.floor.texture" in whats
    assert "the scenario's world.appearance (a learned appearance)" in whats
    assert [i.folder for i in changed.inputs() if "appearance" in i.what] == [True]
