"""``adapt mmd`` and ``adapt sync`` through ``adapt.cli.main``."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.cli import main
from adapt.cli.exits import Exit
from adapt.geometry import rotation_exp
from adapt.vision.homography import corner_error

from . import scenes

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios" / "room.yaml"


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
    assert main(["mmd", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--json"]) == Exit.NO_ALIGNMENT == 7
    data = json.loads(capsys.readouterr().out)
    assert data["homography"] is None and data["inliers"] == 0 and data["regions"] == []
    assert data["aligned"] is False and data["reason"]
    assert main(["mmd", str(tmp_path / "a.png"), str(tmp_path / "b.png")]) == Exit.NO_ALIGNMENT
    assert capsys.readouterr().out.startswith("no alignment: ")


def test_mmd_human_output(pair_files, capsys):
    d, *_ = pair_files
    assert main(["mmd", str(d / "real.png"), str(d / "synth.png")]) == 0
    out = capsys.readouterr().out
    assert "aligned" in out and "unexpected region" in out


@pytest.mark.parametrize(
    "kind, message",
    [
        ("missing", "other.png: no such file"),
        ("garbage", "decode"),
        ("small", "other.png is 320x240 pixels"),
        ("tiny", "other.png: synthetic image is 1x1 pixels: expected at least 32x32 pixels"),
    ],
)
def test_mmd_bad_input_is_a_clean_error(pair_files, tmp_path, capsys, kind, message):
    d, *_ = pair_files
    other = tmp_path / "other.png"
    if kind == "garbage":
        other.write_bytes(b"\x89PNG but not really")
    elif kind == "small":
        cv2.imwrite(str(other), cv2.resize(cv2.imread(str(d / "synth.png")), (320, 240)))
    elif kind == "tiny":
        cv2.imwrite(str(other), np.zeros((1, 1, 3), np.uint8))
    out = tmp_path / "out"
    status = main(["mmd", str(d / "real.png"), str(other), "--out", str(out)])
    err = capsys.readouterr().err
    assert status == Exit.ERROR
    assert err.startswith("adapt: error:") and message in err and "Traceback" not in err
    assert "image image" not in err
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("kind", ["grey", "grey16", "colour16"])
def test_mmd_accepts_grey_and_16_bit_real_images(pair_files, tmp_path, capsys, kind):
    d, h_true, silhouette = pair_files
    real = cv2.imread(str(d / "real.png"))
    if kind.startswith("grey"):
        real = cv2.cvtColor(real, cv2.COLOR_BGR2GRAY)
    if kind.endswith("16"):
        real = real.astype(np.uint16) * 257
    cv2.imwrite(str(tmp_path / "real.png"), real)
    assert main(["mmd", str(tmp_path / "real.png"), str(d / "synth.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert corner_error(np.array(data["homography"]), h_true, (480, 640)) < 1.0
    # the object, and only the object, differs (in grey the blue ball on red coffee
    # has less contrast, so it may come in pieces)
    ys, xs = np.nonzero(silhouette)
    assert data["regions"]
    for region in data["regions"]:
        x, y, w, h = region["bbox"]
        assert xs.min() - 5 <= x and x + w <= xs.max() + 6 and ys.min() - 5 <= y and y + h <= ys.max() + 6
    assert sum(r["area"] for r in data["regions"]) > 0.6 * silhouette.sum()


def test_mmd_never_writes_over_an_input(pair_files, tmp_path, capsys):
    d, *_ = pair_files
    real = tmp_path / "mmd.png"
    real.write_bytes((d / "real.png").read_bytes())
    before = real.read_bytes()
    status = main(["mmd", str(real), str(d / "synth.png"), "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert status == Exit.ERROR and "is the input" in err and "Traceback" not in err
    assert real.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mmd.png"]


def test_mmd_of_a_large_pair_reports_real_pixels(tmp_path, capsys):
    # 3200x2400: analysed at 640x480, answered in the input's pixels
    world = cv2.resize(scenes.world("room"), (3600, 2700), interpolation=cv2.INTER_CUBIC)
    cv2.imwrite(str(tmp_path / "s.png"), world[100:2500, 200:3400])
    cv2.imwrite(str(tmp_path / "r.png"), world[140:2540, 170:3370])  # synthetic -> real: (+30, -40)
    assert main(["mmd", str(tmp_path / "r.png"), str(tmp_path / "s.png"), "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert "analysed at 640x480" in out
    assert cv2.imread(str(tmp_path / "o" / "mmd.png"), cv2.IMREAD_UNCHANGED).shape == (480, 640)
    assert main(["mmd", str(tmp_path / "r.png"), str(tmp_path / "s.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    shift = np.array([[1, 0, 30.0], [0, 1, -40.0], [0, 0, 1]])
    assert data["working_size"] == [640, 480]
    assert corner_error(np.array(data["homography"]), shift, (2400, 3200)) < 1.5  # 0.3 working px


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
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert status == Exit.OK, data["reason"]
    assert data["converged"] and data["outcome"] == "converged"
    errors = [it["pixel_error"] for it in data["iterations"]]
    assert errors[0] > 20 and errors[-1] < 0.5
    assert {"iteration", "pixel_error", "inliers"} <= set(data["iterations"][0])
    final = np.array(data["camera"]["rotation"])
    angle = np.degrees(np.arccos(np.clip((np.trace(final @ real_cam.rotation.T) - 1) / 2, -1, 1)))
    assert angle < 0.1
    # progress and "wrote" lines go to stderr with --json, in the order they happened
    lines = captured.err.splitlines()
    expected = []
    for i in range(len(errors)):
        expected += [f"step {i}: pixel error {errors[i]:.3f} px", f"wrote {out / f'step_{i:02d}.png'}"]
    expected.append(f"wrote {out / 'sync.json'}")
    assert len(lines) == len(expected)
    assert all(line.startswith(e) for line, e in zip(lines, expected)), lines
    strips = sorted(out.glob("step_*.png"))
    assert len(strips) == len(errors)
    img = cv2.imread(str(strips[0]))
    assert img is not None and img.shape[1] > 4 * img.shape[0]  # five panels side by side
    assert json.loads((out / "sync.json").read_text())["iterations"] == data["iterations"]


def test_sync_prints_progress_and_the_camera_as_scenario_keys(scenario_real, capsys):
    import yaml

    from adapt.geometry import Camera

    real_path, real_cam = scenario_real
    status = main(["sync", str(SCENARIO), "--real", str(real_path), "--gain", "0.7", "--max-iter", "8"])
    out = capsys.readouterr().out
    assert status == Exit.OK
    lines = out.splitlines()
    steps = [line for line in lines if line.startswith("step ")]
    assert len(steps) >= 2 and all("px" in x and "inliers" in x and "correction" in x for x in steps)
    assert lines.index(steps[-1]) < lines.index(next(x for x in lines if x.startswith("converged")))
    block = out[out.index("camera:"):]
    keys = yaml.safe_load(block)["camera"]
    assert set(keys) == {"fx", "fy", "cx", "cy", "width", "height", "position", "look_at", "roll_deg"}
    cam = Camera.look_at(**keys)  # pasted back into a scenario, it is the synchronised camera
    angle = np.degrees(np.arccos(np.clip((np.trace(cam.rotation @ real_cam.rotation.T) - 1) / 2, -1, 1)))
    assert angle < 0.1
    # the printed look_at lies at the scenario's own look_at distance
    assert np.linalg.norm(np.array(keys["look_at"]) - [0.0, 3.0, 0.3]) < 0.3


def test_sync_exit_statuses(scenario_real, tmp_path, capsys):
    real_path, _ = scenario_real
    # not converged within --max-iter: its own status, and the camera so far
    assert main(["sync", str(SCENARIO), "--real", str(real_path), "--max-iter", "2"]) == Exit.NOT_CONVERGED == 8
    out = capsys.readouterr().out
    assert "not converged: pixel error still" in out and "look_at:" in out
    # a real image nothing can be aligned with
    flat = tmp_path / "flat.png"
    cv2.imwrite(str(flat), np.full((480, 640), 128, np.uint8))
    assert main(["sync", str(SCENARIO), "--real", str(flat), "--json"]) == Exit.NO_ALIGNMENT == 7
    data = json.loads(capsys.readouterr().out)
    assert data["outcome"] == "no alignment" and not data["converged"]


def test_sync_accepts_a_grey_16_bit_real_image(scenario_real, tmp_path, capsys):
    real_path, real_cam = scenario_real
    grey16 = cv2.cvtColor(cv2.imread(str(real_path)), cv2.COLOR_BGR2GRAY).astype(np.uint16) * 257
    path = tmp_path / "grey16.png"
    cv2.imwrite(str(path), grey16)
    assert main(["sync", str(SCENARIO), "--real", str(path), "--gain", "0.7", "--max-iter", "8",
                 "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    final = np.array(data["camera"]["rotation"])
    angle = np.degrees(np.arccos(np.clip((np.trace(final @ real_cam.rotation.T) - 1) / 2, -1, 1)))
    assert angle < 0.1


def test_sync_never_writes_over_an_input(scenario_real, tmp_path, capsys):
    real_path, _ = scenario_real
    real = tmp_path / "step_00.png"
    real.write_bytes(real_path.read_bytes())
    before = real.read_bytes()
    assert main(["sync", str(SCENARIO), "--real", str(real), "--out", str(tmp_path)]) == Exit.ERROR
    assert "is the input" in capsys.readouterr().err
    assert real.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["step_00.png"]


def test_sync_bad_input(scenario_real, tmp_path, capsys):
    real_path, _ = scenario_real
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), np.zeros((100, 100, 3), np.uint8))
    assert main(["sync", str(SCENARIO), "--real", str(small)]) == 1
    assert "small.png: the image is 100x100 pixels but the scenario's camera renders 640x480" in capsys.readouterr().err
    tiny = tmp_path / "tiny.png"
    cv2.imwrite(str(tiny), np.zeros((1, 1), np.uint8))
    assert main(["sync", str(SCENARIO), "--real", str(tiny)]) == 1
    assert "tiny.png: real image is 1x1 pixels: expected at least 32x32 pixels" in capsys.readouterr().err
    assert main(["sync", str(SCENARIO), "--real", str(real_path), "--tolerance", "-1"]) == 1
    assert "--tolerance" in capsys.readouterr().err
    assert main(["sync", str(SCENARIO), "--real", str(real_path), "--gain", "0"]) == 1
    assert "--gain" in capsys.readouterr().err
    assert main(["sync", str(tmp_path / "none.yaml"), "--real", str(real_path)]) == 1
    assert "no such scenario" in capsys.readouterr().err


ROBOT_SCENARIO = """\
camera:
  {fx: 525.0, fy: 525.0, cx: 319.5, cy: 239.5, width: 640, height: 480,
   position: [0.1, 0.0, 0.55], look_at: [3.1, 0.0, 0.3], roll_deg: 0.0, mount: robot}
world:
  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
  obstacles:
    - {name: crate, polygon: [[-1.3, 2.35], [-0.75, 2.35], [-0.75, 2.85], [-1.3, 2.85]], height: 0.4, color: [150, 110, 60]}
  robot: {position: [0.2, -0.5], heading_deg: 90.0, max_speed: 1.0, max_accel: 2.0}
"""


def test_sync_prints_a_robot_mounted_camera_in_the_robots_frame(tmp_path, capsys):
    import yaml

    from adapt.imagination import Renderer
    from adapt.scenario import load_scenario

    path = tmp_path / "robot.yaml"
    path.write_text(ROBOT_SCENARIO)
    sc = load_scenario(path)
    real_cam = sc.camera.with_rotation(rotation_exp([0.015, -0.02, 0.03]) @ sc.camera.rotation)
    cv2.imwrite(str(tmp_path / "real.png"), Renderer(sc.scene, real_cam).render().image)
    assert main(["sync", str(path), "--real", str(tmp_path / "real.png"), "--gain", "0.7"]) == Exit.OK
    out = capsys.readouterr().out
    keys = yaml.safe_load(out[out.index("camera:"):])["camera"]
    assert keys["mount"] == "robot"
    # pasted back, the scenario's camera is the synchronised one
    pasted = ROBOT_SCENARIO.split("world:")[0].split("\n", 1)[0] + "\n  " + yaml.safe_dump(
        keys, default_flow_style=True).strip() + "\nworld:" + ROBOT_SCENARIO.split("world:")[1]
    (tmp_path / "pasted.yaml").write_text(pasted)
    cam = load_scenario(tmp_path / "pasted.yaml").camera
    angle = np.degrees(np.arccos(np.clip((np.trace(cam.rotation @ real_cam.rotation.T) - 1) / 2, -1, 1)))
    assert angle < 0.1
    assert np.allclose(cam.position, real_cam.position, atol=1e-6)
    assert keys["position"] == pytest.approx([0.1, 0.0, 0.55], abs=1e-6)  # robot frame, unchanged
