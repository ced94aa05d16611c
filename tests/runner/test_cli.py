"""``adapt run``, ``adapt check`` and ``adapt schemas list`` from the command line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def adapt(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "adapt", *args], cwd=cwd, capture_output=True,
                          text=True, timeout=600)


def test_the_main_job_runs_and_writes_its_outputs(tmp_path: Path) -> None:
    # the README's main job, for a few frames
    out = tmp_path / "run"
    proc = adapt("run", "scenarios/bouncing-ball.yaml", "--max-frames", "20", "--out", str(out),
                 "--set", "camera.width=320", "--set", "camera.height=240",
                 "--set", "camera.fx=262.5", "--set", "camera.fy=262.5",
                 "--set", "camera.cx=159.5", "--set", "camera.cy=119.5")
    assert proc.returncode == 0, proc.stderr
    assert "ran 20 frames" in proc.stdout and "Traceback" not in proc.stderr
    report = json.loads((out / "report.json").read_text())
    assert len(report["frames"]) == 20 and report["summary"]["frames"] == 20
    for name in ("trace.jsonl", "mmd.mp4", "figures/sync.png", "figures/camera.png"):
        assert (out / name).stat().st_size > 0, name


def test_run_json_prints_the_summary_and_set_overrides(tmp_path: Path) -> None:
    proc = adapt("run", "scenarios/rolling-ball.yaml", "--json", "--quiet", "--no-video",
                 "--no-figures", "--max-frames", "3", "--out", str(tmp_path / "r"),
                 "--set", "camera.width=320", "--set", "camera.height=240",
                 "--set", "camera.cx=159.5", "--set", "camera.cy=119.5", "--seed", "11")
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["frames"] == 3
    assert json.loads((tmp_path / "r" / "report.json").read_text())["seed"] == 11


def test_a_bad_override_is_an_error_at_its_place() -> None:
    proc = adapt("run", "scenarios/bouncing-ball.yaml", "--set", "predict.evidence=-1")
    assert proc.returncode == 1
    assert "--set:1:18: predict.evidence: expected a non-negative integer" in proc.stderr
    proc = adapt("check", "scenarios/bouncing-ball.yaml", "--set", "world.nosuch=1")
    assert proc.returncode == 1 and "adapt: error:" in proc.stderr and "nosuch" in proc.stderr


def test_check_reads_the_scenario_and_its_rules() -> None:
    proc = adapt("check", "scenarios/bouncing-ball.yaml", "--json")
    assert proc.returncode == 0, proc.stderr
    found = json.loads(proc.stdout)
    text = json.dumps(found)
    assert "intercept.soar" in text and "perception.soar" in text


def test_schemas_list_names_every_type() -> None:
    proc = adapt("schemas", "list", "--json")
    assert proc.returncode == 0, proc.stderr
    names = {t["name"] for t in json.loads(proc.stdout)}
    assert names == {"scene-background", "foreground-object", "drive", "intercept", "search"}
    text = adapt("schemas", "list").stdout
    assert "intercept" in text and "turn_rate" in text
