"""One output guard for every command (issue 21): no output -- a file, or any file a folder
output will hold -- replaces anything the command reads; one run per output folder; no
temporary file outlives a killed run."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.cli import main
from adapt.files import TEMP_PREFIX, lock_folder

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "rules" / "mirror" / "perception.soar"

#: The bundled room at 80x60 pixels; FLOOR is the floor's texture, FRAMES the run's length.
SMALL = """
camera: {fx: 65.625, fy: 65.625, cx: 39.5, cy: 29.5, width: 80, height: 60,
         position: [0.0, -0.6, 0.6], look_at: [0.0, 3.0, 0.3]}
world:
  floor: {texture: FLOOR, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
goals: [{name: watch}]
rules: [RULES]
run: {fps: 10, max_frames: FRAMES}
"""


def small(folder: Path, texture: str = "gravel", frames: int = 3) -> Path:
    path = folder / "s.yaml"
    path.write_text(SMALL.replace("FLOOR", texture).replace("RULES", str(RULES))
                    .replace("FRAMES", str(frames)), encoding="utf-8")
    return path


def _texture(path: Path) -> bytes:
    path.parent.mkdir(parents=True, exist_ok=True)
    image = np.random.default_rng(1).integers(0, 255, (32, 32, 3), dtype=np.uint8)
    path.write_bytes(cv2.imencode(".png", image)[1].tobytes())
    return path.read_bytes()


def _refused(capsys: pytest.CaptureFixture[str], *words: str) -> str:
    err = capsys.readouterr().err
    assert "\nadapt: error: " in "\n" + err and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    return err


# -- 1. a figure of the run may not replace a texture -------------------------------------

def test_a_run_refuses_a_figure_that_would_replace_its_floor_texture(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    before = _texture(tmp_path / "out" / "figures" / "floor.png")
    scenario = small(tmp_path, "out/figures/floor.png")
    assert main(["run", str(scenario), "--out", "out", "--no-video"]) == 1
    _refused(capsys, "world.floor.texture", "out/figures", "never replaces an input")
    assert (tmp_path / "out" / "figures" / "floor.png").read_bytes() == before
    assert sorted(p.name for p in (tmp_path / "out").rglob("*")) == ["figures", "floor.png"]


def test_a_run_refuses_every_file_of_a_folder_output_through_a_symlink(
        tmp_path: Path, capsys) -> None:
    before = _texture(tmp_path / "textures" / "floor.png")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "figures").symlink_to(tmp_path / "textures")
    scenario = small(tmp_path, str(tmp_path / "textures" / "floor.png"))
    assert main(["run", str(scenario), "--out", str(tmp_path / "out"), "--no-video"]) == 1
    _refused(capsys, "world.floor.texture")
    assert (tmp_path / "textures" / "floor.png").read_bytes() == before


# -- 2. a sweep's table may not replace a video scenario's ground truth ---------------------

def test_a_sweep_into_the_scenario_folder_keeps_the_ground_truth(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys) -> None:
    pytest.importorskip("distributed")
    video = ROOT / "scenarios" / "video"
    (tmp_path / "frames").mkdir()
    for frame in sorted((video / "frames").glob("*.jpg"))[:3]:
        (tmp_path / "frames" / frame.name).write_bytes(frame.read_bytes())
    truth = (video / "truth.csv").read_bytes()
    (tmp_path / "runs.csv").write_bytes(truth)
    text = (ROOT / "scenarios" / "video-sequence.yaml").read_text(encoding="utf-8")
    text = text.replace("video/frames/", "frames/").replace("video/truth.csv", "runs.csv")
    text = text.replace("../rules/", str(ROOT / "rules") + "/")
    (tmp_path / "v.yaml").write_text(text, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", "v.yaml", "--seeds", "1", "--out", ".", "--workers", "1",
                 "--max-frames", "2"]) == 1
    _refused(capsys, "runs.csv", "reality.ground_truth", "never replaces an input")
    assert (tmp_path / "runs.csv").read_bytes() == truth
    assert not (tmp_path / "runs.jsonl").exists() and not (tmp_path / "sweep.json").exists()


# -- 3. a file the rules source is an input too ---------------------------------------------

def test_rules_run_refuses_a_trace_that_is_a_sourced_file(tmp_path: Path,
                                                           monkeypatch: pytest.MonkeyPatch,
                                                           capsys) -> None:
    monkeypatch.chdir(tmp_path)
    lib = tmp_path / "lib.jsonl"
    lib.write_bytes((ROOT / "rules" / "examples" / "water-jug.soar").read_bytes())
    (tmp_path / "top.soar").write_text("source lib.jsonl\n", encoding="utf-8")
    before = lib.read_bytes()
    assert main(["rules", "run", "top.soar", "--trace", "lib.jsonl"]) == 1
    _refused(capsys, "lib.jsonl", "sourced", "never replaces an input")
    assert lib.read_bytes() == before


def test_a_run_refuses_an_output_that_its_rules_source(tmp_path: Path, capsys) -> None:
    (tmp_path / "out").mkdir()
    lib = tmp_path / "out" / "trace.jsonl"
    lib.write_bytes(RULES.read_bytes())
    top = tmp_path / "top.soar"
    top.write_text("source out/trace.jsonl\n", encoding="utf-8")
    scenario = small(tmp_path)
    scenario.write_text(scenario.read_text().replace(str(RULES), str(top)))
    before = lib.read_bytes()
    assert main(["run", str(scenario), "--out", str(tmp_path / "out"), "--no-video",
                 "--no-figures"]) == 1
    _refused(capsys, "trace.jsonl", "sourced by the scenario's rules[0]")
    assert lib.read_bytes() == before


# -- 4. one run per output folder ------------------------------------------------------------

def test_a_run_refuses_a_folder_another_run_is_writing_into(tmp_path: Path, capsys) -> None:
    scenario = small(tmp_path)
    out = tmp_path / "out"
    with lock_folder(out):  # another run (or sweep) holds the folder
        assert main(["run", str(scenario), "--out", str(out), "--no-video"]) == 1
        _refused(capsys, "another adapt", str(out))
        assert sorted(p.name for p in out.iterdir()) == [".adapt.lock"]
    assert main(["run", str(scenario), "--out", str(out), "--no-video"]) == 0
    assert (out / "report.json").is_file()


def test_two_runs_into_one_folder_at_once(tmp_path: Path) -> None:
    scenario = small(tmp_path, frames=400)
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    args = [sys.executable, "-m", "adapt", "run", str(scenario), "--out", str(out),
            "--no-video", "--quiet"]
    first = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        _wait_for(lambda: any(p.name.startswith(TEMP_PREFIX) for p in _files(out)), first)
        second = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120)
        assert second.returncode == 1, second.stderr
        assert "another adapt" in second.stderr
    finally:
        first.send_signal(signal.SIGINT)
        first.communicate(timeout=120)
    assert first.returncode == 130
    report = json.loads((out / "report.json").read_text())
    assert report["summary"]["interrupted"] is True


# -- 5. no temporary file outlives a killed run ---------------------------------------------

def _files(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.is_file()] if folder.exists() else []


def _wait_for(condition, process: subprocess.Popen, timeout: float = 120.0) -> None:  # type: ignore[type-arg,no-untyped-def]
    end = time.monotonic() + timeout
    while not condition():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < end, "the run never started writing"
        time.sleep(0.05)


def test_a_later_run_removes_what_a_killed_run_left(tmp_path: Path) -> None:
    scenario = small(tmp_path, frames=400)
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    args = [sys.executable, "-m", "adapt", "run", str(scenario), "--out", str(out), "--quiet"]
    killed = subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        _wait_for(lambda: len([p for p in _files(out) if p.name.startswith(".")]) >= 3, killed)
        time.sleep(0.3)
    finally:
        killed.kill()  # SIGKILL: nothing of the run's own clean-up runs
        killed.wait()
    left = [p for p in _files(out) if p.name.startswith(".") and p.name != ".adapt.lock"]
    assert left and all(p.name.startswith(TEMP_PREFIX) for p in left), left
    again = small(tmp_path, frames=2)
    assert main(["run", str(again), "--out", str(out), "--no-video", "--no-figures",
                 "--quiet"]) == 0
    assert [p for p in _files(out) if p.name.startswith(TEMP_PREFIX)] == []
    assert (out / "report.json").is_file() and (out / "trace.jsonl").is_file()
