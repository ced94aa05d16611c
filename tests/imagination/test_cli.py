"""``adapt render`` and ``adapt imagine`` through ``adapt.cli.main``."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.cli import main
from adapt.imagination import LABEL_BALL, Renderer, World
from adapt.scenario import Scenario

BUNDLED = Path(__file__).resolve().parents[2] / "scenarios" / "room.yaml"


def test_render_writes_the_frame_and_labels(tmp_path: Path, bundled: Scenario,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    out, lab = tmp_path / "f.png", tmp_path / "sub" / "l.png"
    assert main(["render", str(BUNDLED), "--out", str(out), "--t", "1.5", "--labels", str(lab)]) == 0
    image = cv2.imread(str(out))
    labels = cv2.imread(str(lab), cv2.IMREAD_UNCHANGED)
    world = World(bundled.scene)
    world.run(1.5)
    expected = Renderer(bundled.scene, bundled.camera).render(world.snapshot())
    assert np.array_equal(image, expected.image)
    assert np.array_equal(labels.astype(np.int32), expected.labels)
    assert (labels == LABEL_BALL).any()
    assert "wrote" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.png", "sub"]  # no temp files left


def test_imagine_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["imagine", str(BUNDLED), "--horizon", "3", "--json", "--samples", "7"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [c["surface"] for c in data["contacts"]][:2] == ["north", "wedge"]
    assert set(data["contacts"][0]) >= {"t", "position", "surface"}
    assert len(data["trajectory"]) == 7 and data["trajectory"][-1]["t"] == pytest.approx(3.0)
    assert data["trajectory"][0]["position"] == pytest.approx([-2.1, 0.9])
    assert data["trajectory"][0]["velocity"] == pytest.approx([1.6, 1.5])
    assert "intercept" in data


def test_imagine_text_dt_and_intercept(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["imagine", str(BUNDLED), "--horizon", "5", "--dt", "0.008333333333333333"]) == 0
    text = capsys.readouterr().out
    assert "hit north" in text and "dt = 0.00833333 s" in text
    assert "intercept: robot meets ball at t=" in text


def test_imagine_video(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    video = tmp_path / "v.avi"
    assert main(["imagine", str(BUNDLED), "--horizon", "0.5", "--video", str(video),
                 "--fps", "10"]) == 0
    cap = cv2.VideoCapture(str(video))
    frames = 0
    while cap.read()[0]:
        frames += 1
    assert frames == 6
    assert [p.name for p in tmp_path.iterdir()] == ["v.avi"]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["imagine", "missing.yaml", "--horizon", "1"], "missing.yaml:1:1: no such scenario file"),
        (["imagine", str(BUNDLED), "--horizon", "-1"], "--horizon"),
        (["imagine", str(BUNDLED), "--horizon", "1", "--video", "x.gif"], ".mp4 or .avi"),
        (["render", str(BUNDLED), "--out", "x.png", "--t", "-2"], "--t"),
        (["imagine", str(BUNDLED), "--horizon", "1", "--body", "nobody"], "nobody"),
        (["imagine", str(BUNDLED), "--horizon", "0"], "--horizon must be a positive number"),
        (["render", str(BUNDLED), "--out", "x.txt"], "cannot write images of type '.txt'"),
        (["render", str(BUNDLED), "--out", "x"], "(no extension)"),
        (["render", str(BUNDLED), "--out", ".", "--t", "0"], "is a directory"),
        (["render", str(BUNDLED), "--out", "x.png", "--labels", "l.jpg"], "16-bit"),
        (["render", str(BUNDLED), "--out", "x.png", "--t", "inf"], "--t"),
    ],
)
def test_bad_arguments_are_errors(argv: list[str], message: str,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 1
    assert message in capsys.readouterr().err


def test_bad_scenario_error_is_located(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(BUNDLED.read_text().replace("radius: 0.11", "radius: -0.11"))
    assert main(["render", str(bad), "--out", str(tmp_path / "x.png")]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:" in err and "world.objects[0].radius" in err
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize(
    "argv, message",
    [
        (["render", str(BUNDLED), "--out", "{d}/same.png", "--labels", "{d}/same.png"],
         "is the same file as --out"),
        (["render", str(BUNDLED), "--out", "{d}/a.png", "--labels", "{d}/./a.png"],
         "is the same file as --out"),
        (["render", str(BUNDLED), "--out", "{d}/a.png", "--t", "1e9"],
         "--t: 1e+09 s is 240,000,000,000 steps"),
        (["imagine", str(BUNDLED), "--horizon", "1e9"], "--horizon: 1e+09 s is"),
        (["imagine", str(BUNDLED), "--horizon", "1", "--samples", "100000000"],
         "--samples must be from 1 to 100,000"),
        (["imagine", str(BUNDLED), "--horizon", "1", "--dt", "1e-9"], "--dt: expected"),
        (["imagine", str(BUNDLED), "--horizon", "1", "--video", "{d}/v.mp4", "--fps", "1e9"],
         "--fps must be"),
        (["imagine", str(BUNDLED), "--horizon", "4000", "--video", "{d}/v.mp4"],
         "120,001 frames; at most 36,000"),
        (["render", str(BUNDLED), "--out", "/proc/adapt-x.png"], "cannot write in the folder"),
    ],
)
def test_outputs_and_work_are_checked_before_anything_is_written(
    tmp_path: Path, argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = [a.replace("{d}", str(tmp_path)) for a in argv]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert err.startswith("adapt: error: ") and message in err, err
    assert ".tmp" not in err
    assert list(tmp_path.iterdir()) == []


def test_no_output_replaces_an_input(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import shutil

    from adapt.imagination.texture import texture_path

    scenario = tmp_path / "s.yaml"
    shutil.copy(texture_path("builtin:grass"), tmp_path / "g.png")
    scenario.write_text(BUNDLED.read_text().replace("texture: gravel", "texture: g.png"))
    before = scenario.read_bytes(), (tmp_path / "g.png").read_bytes()
    assert main(["render", str(scenario), "--out", str(tmp_path / "g.png")]) == 1
    assert "is the scenario's world.floor.texture" in capsys.readouterr().err
    assert main(["imagine", str(scenario), "--horizon", "1", "--video",
                 str(tmp_path / "s.yaml")]) == 1
    assert main(["render", str(scenario), "--out", str(tmp_path / "x.png"), "--labels",
                 str(scenario)]) == 1
    assert (scenario.read_bytes(), (tmp_path / "g.png").read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.png", "s.yaml"]


def test_render_refuses_an_output_that_is_not_a_regular_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import os

    (tmp_path / "dir.png").mkdir()
    assert main(["render", str(BUNDLED), "--out", str(tmp_path / "dir.png")]) == 1
    assert "is a directory" in capsys.readouterr().err
    os.mkfifo(tmp_path / "pipe.png")
    assert main(["render", str(BUNDLED), "--out", str(tmp_path / "x.png"), "--labels",
                 str(tmp_path / "pipe.png")]) == 1
    assert "is not a regular file" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.png", "pipe.png"]


def test_imagine_reports_the_intercept_with_the_public_reach(
    capsys: pytest.CaptureFixture[str], bundled: Scenario
) -> None:
    from adapt.imagination import intercept, intercept_reach, rollout

    assert main(["imagine", str(BUNDLED), "--horizon", "4", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    robot = bundled.scene.robot
    assert robot is not None
    world = World(bundled.scene)
    hit = intercept(rollout(world, 4.0), robot.position, robot.max_speed, robot.max_accel,
                    reach=intercept_reach(bundled.scene.balls[0], robot))
    assert hit is not None and data["intercept"]["t"] == pytest.approx(hit.time)
