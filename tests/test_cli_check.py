"""``adapt check`` refuses first what ``adapt run`` would refuse (issue 21): each value the issue
found passing ``check`` and failing ``run`` is refused by ``check``, at its ``--set`` column, under
the scenario's own key; places, the video and the ground truth are checked too."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from adapt.cli import main

ROOT = Path(__file__).resolve().parents[1]
BALL = ROOT / "scenarios" / "bouncing-ball.yaml"

#: (overrides, the key path the error names)
REFUSED = [
    (["reality.dt=1e9"], "reality.dt"),
    (["reality.camera_offset=[1e300, 0, 0]"], "reality.camera_offset[0]"),
    (["reality.camera_offset_deg=[1e300, 0, 0]"], "reality.camera_offset_deg[0]"),
    (["reality.appearance.texture_scale=1e300"], "reality.appearance.texture_scale"),
    (["reality.objects.ball.drag=1e300"], "reality.objects[0].drag"),
    (["reality.objects.ball.mass=1e300"], "reality.objects[0].mass"),
    (["reality.objects.ball.friction=1e300"], "reality.objects[0].friction"),
    (["reality.objects.ball.throw.x=1e9"], "reality.objects[0].throw.x"),
    (["reality.robot.max_speed=1e300"], "reality.robot.max_speed"),
    (["predict.ensemble=1000", "predict.horizons=[60]"], "predict.ensemble"),
    (["schemas.scene-background.mmd_pixels=1e300"], "schemas.scene-background.mmd_pixels"),
    (["camera.width=1", "camera.height=1"], "camera.width"),
    (["camera.width=8192", "camera.height=8192"], "camera.height"),
    (["schemas.foreground-object.k=1e300"], "schemas.foreground-object.k"),
    (["schemas.foreground-object.damping=1e300"], "schemas.foreground-object.damping"),
    (["schemas.foreground-object.max_accel=1e300"], "schemas.foreground-object.max_accel"),
    (["schemas.foreground-object.gate=1e300"], "schemas.foreground-object.gate"),
    (["schemas.intercept.timeout=1e300"], "schemas.intercept.timeout"),
    (["reality.appearance.brightness=1e300"], "reality.appearance.brightness"),
    (["reality.appearance.contrast=1e300"], "reality.appearance.contrast"),
    (["reality.appearance.color_shift=[1e300, 0, 0]"], "reality.appearance.color_shift[0]"),
    (["world.robot.position=[9, 9]"], "world.robot.position"),  # outside the walls
    (["world.robot.position=[-1.0, 2.6]"], "world.robot.position"),  # in the crate
    (["reality.objects.ball.throw.x=[-2.6, -0.6]"], "reality.objects[0].throw.x"),  # into a wall
    (["world.dt=0.1", "reality.objects.ball.throw.speed=100"],
     "reality.objects[0].throw.speed"),  # a ball through a wall in one step
    (["reality.appearance.texture_scale=0.01", "world.floor.tile=0.05"],
     "reality.appearance.texture_scale"),  # a real tile below a millimetre
]


@pytest.mark.parametrize("sets, key", REFUSED, ids=lambda v: str(v)[:40])
def test_check_refuses_at_the_value_under_the_scenarios_key(capsys, sets: list[str],
                                                            key: str) -> None:
    argv = ["check", str(BALL)]
    for s in sets:
        argv += ["--set", s]
    assert main(argv) == 1
    err = capsys.readouterr().err
    first = err.splitlines()[0]
    assert first.startswith("adapt: error: --set:1:"), err
    assert f": {key}: " in first, err
    assert "tile:" not in first and not any(len(word) > 40 for word in first.split()), err


def test_run_refuses_what_check_refuses(capsys, tmp_path: Path) -> None:
    """The same reader, the same message: run refuses before it writes anything."""
    argv = ["--set", "world.robot.position=[9, 9]"]
    assert main(["check", str(BALL), *argv]) == 1
    said = capsys.readouterr().err
    assert main(["run", str(BALL), *argv, "--out", str(tmp_path / "out")]) == 1
    assert capsys.readouterr().err == said
    assert not (tmp_path / "out").exists()


def test_check_reads_the_ground_truth(tmp_path: Path, capsys) -> None:
    """A bad row of the ground-truth CSV fails check at its file:line:col (x = 1e300 here)."""
    folder = tmp_path / "scenarios"
    shutil.copytree(ROOT / "scenarios" / "video", folder / "video")
    shutil.copy(ROOT / "scenarios" / "video-sequence.yaml", folder)
    truth = folder / "video" / "truth.csv"
    lines = truth.read_text(encoding="utf-8").splitlines()
    lines[2] = "0.6,ball,1e300,1.030843,1.434622,0.304938"
    truth.write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert main(["check", str(folder / "video-sequence.yaml")]) == 1
    err = capsys.readouterr().err
    assert f"{truth}:3:10: column 'x': expected at most 10000 metres either way" in err, err


def test_check_opens_the_video(tmp_path: Path, capsys) -> None:
    """A video file OpenCV cannot open fails check, not the run."""
    (tmp_path / "clip.mp4").write_bytes(b"not a video at all" * 10)
    text = (ROOT / "scenarios" / "video-sequence.yaml").read_text(encoding="utf-8")
    text = text.replace("path: video/frames/*.jpg", "path: clip.mp4").replace(
        "ground_truth: video/truth.csv", "")
    (tmp_path / "s.yaml").write_text(text, encoding="utf-8")
    assert main(["check", str(tmp_path / "s.yaml")]) == 1
    assert "OpenCV cannot open it as a video" in capsys.readouterr().err
