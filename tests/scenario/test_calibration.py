"""Calibration files (OpenCV FileStorage YAML and XML, ROS camera_info) and the camera's
``distortion`` and ``calibration`` keys: what they give, and every bad file at its line."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.errors import ScenarioError
from adapt.lens import LensSource
from adapt.reality import open_reality
from adapt.runner import Runner
from adapt.scenario import OutputSettings, load_scenario, loads_scenario
from adapt.scenario.calibration import read_calibration
from adapt.seeds import Streams

K = np.array([[300.0, 0.0, 159.5], [0.0, 301.0, 119.5], [0.0, 0.0, 1.0]])
D = np.array([[-0.28, 0.09, 0.001, -0.002, 0.01]])

ROS = """image_width: 320
image_height: 240
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [300.0, 0.0, 159.5, 0.0, 301.0, 119.5, 0.0, 0.0, 1.0]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.28, 0.09, 0.001, -0.002, 0.01]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
projection_matrix:
  rows: 3
  cols: 4
  data: [250.0, 0.0, 155.0, 0.0, 0.0, 252.0, 117.0, 0.0, 0.0, 0.0, 1.0, 0.0]
"""


def opencv_file(path: Path) -> Path:
    """A calibration as OpenCV itself writes it (``cv::FileStorage``, YAML or XML by name)."""
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 320)
    fs.write("image_height", 240)
    fs.write("camera_matrix", K)
    fs.write("distortion_coefficients", D)
    fs.write("avg_reprojection_error", 0.21)  # other keys a calibration writes are ignored
    fs.release()
    return path


@pytest.mark.parametrize("name", ["cam.yaml", "cam.xml", "cam.yml"])
def test_opencvs_own_files_are_read(tmp_path: Path, name: str) -> None:
    lens = read_calibration(opencv_file(tmp_path / name))
    assert lens.size == (320, 240) and np.array_equal(lens.matrix, K)
    assert lens.distortion == tuple(D.ravel()) and np.array_equal(lens.projection, K)  # type: ignore[arg-type]
    assert lens.intrinsics == (300.0, 301.0, 159.5, 119.5) and lens.file == str(tmp_path / name)


def test_a_ros_camera_info_is_read_with_its_projection(tmp_path: Path) -> None:
    (tmp_path / "ros.yaml").write_text(ROS)
    lens = read_calibration(tmp_path / "ros.yaml")
    assert lens.distortion == tuple(D.ravel()) and np.array_equal(lens.matrix, K)
    assert lens.intrinsics == (250.0, 252.0, 155.0, 117.0)  # the rectified image's camera
    assert np.array_equal(lens.rectification, np.eye(3))
    eight = ROS.replace("plumb_bob", "rational_polynomial").replace(
        "cols: 5\n  data: [-0.28, 0.09, 0.001, -0.002, 0.01]",
        "cols: 8\n  data: [-0.28, 0.09, 0.001, -0.002, 0.01, 0.1, 0.0, 0.0]")
    (tmp_path / "ros8.yaml").write_text(eight)
    assert len(read_calibration(tmp_path / "ros8.yaml").distortion) == 8


def test_the_opencv_tutorials_capitalised_keys_are_read(tmp_path: Path) -> None:
    text = (tmp_path / "c.yml")
    opencv_file(text)
    t = text.read_text().replace("camera_matrix", "Camera_Matrix").replace(
        "distortion_coefficients", "Distortion_Coefficients").replace("image_width", "image_Width")
    text.write_text(t)
    assert read_calibration(text).size == (320, 240)


#: (what to replace in ROS, line:col of the error, the message)
BAD = [
    ("rows: 3\n  cols: 3\n  data: [300.0", "5:3", r"camera_matrix: missing key 'rows' of the matrix"),
    ("image_width: 320", "1:14", r"image_width: expected a positive whole number, got '-320'"),
    ("distortion_model: plumb_bob", "8:19", r"distortion_model: unknown distortion model 'equidistant'; expected "
     r"plumb_bob or rational_polynomial"),
    ("cols: 5\n  data: [-0.28, 0.09, 0.001, -0.002, 0.01]", "10:9",
     "distortion_coefficients: expected a 1x5 matrix, got 1x4"),
    ("data: [300.0, 0.0, 159.5", "7:10", r"camera_matrix.data\[0\]: expected a number, got 'abc'"),
    ("cols: 4\n  data: [250.0, 0.0, 155.0, 0.0,", "20:9",
     r"projection_matrix.data: expected 12 numbers \(3x4\), got 11"),
    ("image_height: 240\n", "1:1", "missing key 'image_height'"),
]


def _bad(text: str, what: str) -> str:
    if what.startswith("rows: 3\n  cols: 3\n  data: [300.0"):
        return text.replace(what, "cols: 3\n  data: [300.0", 1)
    if what == "image_width: 320":
        return text.replace(what, "image_width: -320")
    if what == "distortion_model: plumb_bob":
        return text.replace(what, "distortion_model: equidistant")
    if what.startswith("cols: 5"):
        return text.replace(what, "cols: 4\n  data: [-0.28, 0.09, 0.001, -0.002]")
    if what.startswith("data: [300.0"):
        return text.replace("data: [300.0", "data: [abc")
    if what.startswith("cols: 4"):
        return text.replace(what, "cols: 4\n  data: [250.0, 0.0, 155.0,")
    return text.replace(what, "")


@pytest.mark.parametrize("what, where, message", BAD)
def test_a_bad_calibration_is_an_error_at_its_line(tmp_path: Path, what: str, where: str,
                                                  message: str) -> None:
    path = tmp_path / "ros.yaml"
    path.write_text(_bad(ROS, what))
    with pytest.raises(ScenarioError, match=f"ros.yaml:{where}: {message}"):
        read_calibration(path)


def test_bad_xml_and_files_that_are_no_calibration(tmp_path: Path) -> None:
    xml = opencv_file(tmp_path / "cam.xml")
    xml.write_text(xml.read_text().replace("<rows>3</rows>", "<rows>3</rows", 1))
    with pytest.raises(ScenarioError, match=r"cam.xml:7:3: not valid XML"):
        read_calibration(xml)
    xml = opencv_file(tmp_path / "two.xml")
    xml.write_text(xml.read_text().replace("<rows>3</rows>", "<rows>2</rows>", 1))
    with pytest.raises(ScenarioError, match=r"two.xml:6:3: camera_matrix: expected a 3x3 matrix, "
                       "got 2x3"):
        read_calibration(xml)
    for text, message in (("", "empty"), ("[1, 2]", "expected a mapping of keys"),
                          ("a: [", "not valid YAML")):
        (tmp_path / "x.yaml").write_text(text)
        with pytest.raises(ScenarioError, match=message):
            read_calibration(tmp_path / "x.yaml")
    (tmp_path / "bin.yaml").write_bytes(b"\xff\xfe\x00\x81" * 10)
    with pytest.raises(ScenarioError, match="not a text file"):
        read_calibration(tmp_path / "bin.yaml")


HEAD = "world: {}\n"
POSE = "position: [0, -2, 1], look_at: [0, 1, 0]"


def test_the_camera_takes_its_intrinsics_from_the_calibration(tmp_path: Path) -> None:
    (tmp_path / "ros.yaml").write_text(ROS)
    (tmp_path / "s.yaml").write_text(f"camera: {{calibration: ros.yaml, {POSE}}}\n" + HEAD)
    sc = load_scenario(tmp_path / "s.yaml")
    cam = sc.camera
    assert (cam.fx, cam.fy, cam.cx, cam.cy, cam.width, cam.height) == (250, 252, 155, 117, 320, 240)
    assert sc.lens is not None and sc.lens.distortion == tuple(D.ravel())
    assert sc.inputs().find(tmp_path / "ros.yaml") is not None  # no output may replace it


def test_distortion_beside_the_scenarios_own_intrinsics() -> None:
    sc = loads_scenario("camera: {fx: 300, fy: 300, cx: 159.5, cy: 119.5, width: 320, "
                        f"height: 240, {POSE}, distortion: [-0.2, 0.05, 0, 0, 0]}}\n" + HEAD)
    assert sc.lens is not None and sc.lens.intrinsics == (300, 300, 159.5, 119.5)
    assert sc.lens.distortion == (-0.2, 0.05, 0.0, 0.0, 0.0) and sc.lens.size == (320, 240)
    assert loads_scenario(f"camera: {{fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, {POSE}}}\n"
                          + HEAD).lens is None


@pytest.mark.parametrize("camera, where, message", [
    (f"{{calibration: ros.yaml, fx: 300, {POSE}}}", "1:33", "camera.fx: the calibration file "
     "gives the camera's intrinsics and distortion; remove this key"),
    (f"{{calibration: ros.yaml, distortion: [0, 0, 0, 0], {POSE}}}", "1:33", "camera.distortion: the calibration file"),
    (f"{{calibration: nothing.yaml, {POSE}}}", "1:23", "camera.calibration: calibration file .* not found"),
    (f"{{fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, {POSE}, distortion: [0.1, 0, 0]}}",
     "1:115", r"camera.distortion: expected \[k1, k2, p1, p2, k3\] \(4, 5 or 8 numbers in OpenCV's order\), got 3 values"),
    (f"{{fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, {POSE}, distortion: [a, 0, 0, 0]}}",
     "1:116", r"camera.distortion\[0\]: expected a number"),
    (f"{{fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, {POSE}, distortion: [0, 0, 0, 1e9]}}",
     "1:125", r"camera.distortion\[3\]: expected a number from -1000 to 1000, got 1000000000"),
    ("{calibration: ros.yaml, look_at: [0, 1, 0]}", "1:9", "camera: missing key 'position'"),
])
def test_bad_camera_lens_keys_are_positioned_errors(tmp_path: Path, camera: str, where: str,
                                                    message: str) -> None:
    (tmp_path / "ros.yaml").write_text(ROS)
    (tmp_path / "s.yaml").write_text(f"camera: {camera}\n" + HEAD)
    with pytest.raises(ScenarioError, match=f"s.yaml:{where}: {message}"):
        load_scenario(tmp_path / "s.yaml")


def test_an_error_in_the_calibration_also_names_the_scenarios_line(tmp_path: Path) -> None:
    (tmp_path / "ros.yaml").write_text(ROS.replace("plumb_bob", "fisheye"))
    (tmp_path / "s.yaml").write_text(f"camera: {{calibration: ros.yaml, {POSE}}}\n" + HEAD)
    with pytest.raises(ScenarioError) as info:
        load_scenario(tmp_path / "s.yaml")
    text = str(info.value)
    assert "ros.yaml:8:19: distortion_model: unknown distortion model 'fisheye'" in text
    assert "(the camera.calibration of " in text and "s.yaml:1:23)" in text
    assert "distortion_model: fisheye" in text  # the calibration file's line, with a caret


ROOM = """world:
  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.5, 2.5, 3.0]}
  walls:
    - {name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}
run: {fps: 10, max_frames: 3}
"""
CAMERA = ("camera: {fx: 160, fy: 160, cx: 79.5, cy: 59.5, width: 160, height: 120, "
          "position: [0.0, -1.0, 1.0], look_at: [0.0, 2.0, 0.2]%s}\n")


def test_a_synthetic_reality_is_seen_through_the_lens_and_the_runner_undistorts_it() -> None:
    plain = loads_scenario(CAMERA % "" + ROOM)
    lensed = loads_scenario(CAMERA % ", distortion: [-0.3, 0.1, 0, 0, 0]" + ROOM)
    ideal = [f.image for f in open_reality(plain, streams=Streams(4))]
    raw = [f.image for f in open_reality(lensed, streams=Streams(4))]
    runner = Runner(lensed, seed=4, outputs=OutputSettings(video=False, figures=False))
    assert isinstance(runner.source, LensSource)
    seen = [f.image for f in runner.source]
    runner.close()

    def error(a: np.ndarray, b: np.ndarray) -> float:
        return float(np.abs(a[12:-12, 12:-12].astype(int) - b[12:-12, 12:-12]).mean())

    for i in range(3):
        assert error(raw[i], ideal[i]) > 3 * error(seen[i], ideal[i])
        assert error(seen[i], ideal[i]) < 4.0


@pytest.mark.parametrize("old, new, where, message", [
    ("image_width: 320", "image_width: 16", "1:14", r"image_width: expected an integer from 32 to "
     r"8192 pixels, got 16 \(as for camera.width\)"),
    ("[-0.28, 0.09,", "[-0.28, 5e4,", "10:3", r"distortion_coefficients: expected a number from "
     r"-1000 to 1000, got 50000 \(as for camera.distortion\)"),
    ("[300.0, 0.0, 159.5,", "[3e7, 0.0, 159.5,", "5:3",
     r"camera_matrix: expected at most 1000000 pixels, got 30000000 \(as for camera.fx\)"),
])
def test_a_calibration_files_numbers_keep_the_scenario_keys_bounds(
        tmp_path: Path, old: str, new: str, where: str, message: str) -> None:
    """The file is no scenario (no BOUNDS keys of its own), but its numbers become the
    camera's: held to the bounds of camera.width, camera.fx, camera.distortion, at the
    file's line and column."""
    assert old in ROS
    (tmp_path / "ros.yaml").write_text(ROS.replace(old, new))
    (tmp_path / "s.yaml").write_text(f"camera: {{calibration: ros.yaml, {POSE}}}\n" + HEAD)
    with pytest.raises(ScenarioError, match=f"ros.yaml:{where}: {message}"):
        load_scenario(tmp_path / "s.yaml")
