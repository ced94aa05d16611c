"""``adapt mmd`` and ``adapt sync`` through ``adapt.cli.main``."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.cli import main
from adapt.geometry import rotation_exp
from adapt.vision.homography import corner_error

from . import scenes

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios" / "bouncing-ball.yaml"


@pytest.fixture(scope="module")
def pair_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("pair")
    real, synthetic, h_true, *_ = scenes.pair("coffee", 3)
    real, silhouette = scenes.paste_object(real, np.random.default_rng(4))
    cv2.imwrite(str(d / "real.png"), real)
    cv2.imwrite(str(d / "synth.png"), synthetic)
    return d, h_true, silhouette


def test_mmd_json_contract(pair_files, tmp_path, capsys):
    d, h_true, silhouette = pair_files
    out = tmp_path / "out"
    assert main(["mmd", str(d / "real.png"), str(d / "synth.png"), "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {"homography", "inliers", "regions", "ms"} <= set(data)
    h = np.array(data["homography"])
    assert h.shape == (3, 3) and corner_error(h, h_true, (480, 640)) < 1.0
    assert data["inliers"] >= 12 and data["ms"] > 0
    (region,) = data["regions"]
    assert {"bbox", "centroid", "area"} <= set(region)
    x, y, w, hh = region["bbox"]
    ys, xs = np.nonzero(silhouette)
    assert abs(x - xs.min()) < 10 and abs(y - ys.min()) < 10
    assert region["area"] == pytest.approx(silhouette.sum(), rel=0.3)
    for name in ("warped.png", "mask.png", "mmd.png"):
        img = cv2.imread(str(out / name), cv2.IMREAD_UNCHANGED)
        assert img is not None and img.shape[:2] == (480, 640)
    assert sorted(p.name for p in out.iterdir()) == ["mask.png", "mmd.png", "warped.png"]


def test_mmd_without_alignment_prints_null(tmp_path, capsys):
    blank = np.full((480, 640, 3), 100, np.uint8)
    cv2.imwrite(str(tmp_path / "a.png"), blank)
    cv2.imwrite(str(tmp_path / "b.png"), blank)
    assert main(["mmd", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["homography"] is None and data["inliers"] == 0 and data["regions"] == []
    assert data["aligned"] is False and data["reason"]


def test_mmd_human_output(pair_files, capsys):
    d, *_ = pair_files
    assert main(["mmd", str(d / "real.png"), str(d / "synth.png")]) == 0
    out = capsys.readouterr().out
    assert "aligned" in out and "unexpected region" in out


@pytest.mark.parametrize(
    "kind, message",
    [("missing", "no such file"), ("garbage", "decode"), ("grey", "grey"), ("small", "320x240")],
)
def test_mmd_bad_input_is_a_clean_error(pair_files, tmp_path, capsys, kind, message):
    d, *_ = pair_files
    other = tmp_path / "other.png"
    if kind == "garbage":
        other.write_bytes(b"\x89PNG but not really")
    elif kind == "grey":
        cv2.imwrite(str(other), cv2.imread(str(d / "synth.png"), cv2.IMREAD_GRAYSCALE))
    elif kind == "small":
        cv2.imwrite(str(other), cv2.resize(cv2.imread(str(d / "synth.png")), (320, 240)))
    out = tmp_path / "out"
    status = main(["mmd", str(d / "real.png"), str(other), "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 1
    assert err.startswith("adapt: error:") and message in err and "Traceback" not in err
    assert not out.exists() or not any(out.iterdir())


@pytest.fixture(scope="module")
def scenario_real(tmp_path_factory):
    from adapt.imagination import Renderer
    from adapt.scenario import load_scenario

    sc = load_scenario(SCENARIO)
    real_cam = sc.camera.with_rotation(rotation_exp([0.02, -0.03, 0.04]) @ sc.camera.rotation)
    img = Renderer(sc.scene, real_cam).render().image
    img = scenes.sensor_noise(img, np.random.default_rng(0), 3.0)
    d = tmp_path_factory.mktemp("sync")
    cv2.imwrite(str(d / "real.png"), img)
    return d / "real.png", real_cam


def test_sync_converges_and_writes_strips(scenario_real, tmp_path, capsys):
    real_path, real_cam = scenario_real
    out = tmp_path / "sync"
    status = main(["sync", str(SCENARIO), "--real", str(real_path), "--out", str(out),
                   "--gain", "0.7", "--max-iter", "8", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert status == 0, data["reason"]
    assert data["converged"]
    errors = [it["pixel_error"] for it in data["iterations"]]
    assert errors[0] > 20 and errors[-1] < 0.5
    assert {"iteration", "pixel_error", "inliers"} <= set(data["iterations"][0])
    final = np.array(data["camera"]["rotation"])
    angle = np.degrees(np.arccos(np.clip((np.trace(final @ real_cam.rotation.T) - 1) / 2, -1, 1)))
    assert angle < 0.1
    strips = sorted(out.glob("step_*.png"))
    assert len(strips) == len(errors)
    assert cv2.imread(str(strips[0])).shape == (480, 5 * 640, 3)
    assert json.loads((out / "sync.json").read_text())["iterations"] == data["iterations"]


def test_sync_bad_input(scenario_real, tmp_path, capsys):
    real_path, _ = scenario_real
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), np.zeros((100, 100, 3), np.uint8))
    assert main(["sync", str(SCENARIO), "--real", str(small)]) == 1
    assert "renders 640x480" in capsys.readouterr().err
    assert main(["sync", str(SCENARIO), "--real", str(real_path), "--gain", "0"]) == 1
    assert "--gain" in capsys.readouterr().err
    assert main(["sync", str(tmp_path / "none.yaml"), "--real", str(real_path)]) == 1
    assert "no such scenario" in capsys.readouterr().err
