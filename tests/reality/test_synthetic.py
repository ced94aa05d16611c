"""The synthetic reality as a frame source: timing, determinism, the true camera,
objects of reality only, and the truth it records."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from adapt.errors import RealityError
from adapt.frames import FrameSource
from adapt.geometry import rotation_log
from adapt.imagination import Renderer
from adapt.reality import RealitySource, SyntheticSource, open_reality
from adapt.reality.truth import TrueParameters
from adapt.scenario import load_scenario
from adapt.seeds import Streams

from .conftest import CAMERA, WORLD, scenario, source

NOISY = ("  appearance: {noise: 3}\n"
         "  objects: [{name: ball, restitution: [0.5, 0.9], drag: [0.0, 0.5]}]\n")


def test_frames_come_at_the_run_rate_for_the_run_length() -> None:
    sc = scenario(run="run: {fps: 25, max_frames: 7}\n")
    src = open_reality(sc, streams=Streams(1))
    assert isinstance(src, RealitySource) and isinstance(src, FrameSource)
    assert src.size == (160, 120) and src.fps == 25.0
    frames = list(src)
    assert [f.index for f in frames] == list(range(7))
    assert [f.time for f in frames] == pytest.approx([i / 25 for i in range(7)])
    for f in frames:
        assert f.image.shape == (120, 160, 3) and f.image.dtype == np.uint8
        assert not f.image.flags.writeable
    # The truth is at the frame's time.
    assert src.truth.at(6).time == pytest.approx(6 / 25)
    assert src.truth.at(6).position("ball")[1] > src.truth.at(0).position("ball")[1]


def test_the_same_seed_gives_the_same_frames_and_truth_and_others_differ() -> None:
    sc = scenario(NOISY)
    runs = [source(sc, seed) for seed in (5, 5, 6)]
    frames = [[f.image for f in s] for s in runs]
    assert all(np.array_equal(a, b) for a, b in zip(frames[0], frames[1]))
    assert not any(np.array_equal(a, b) for a, b in zip(frames[0], frames[2]))
    t = [[s.truth.at(i) for i in range(10)] for s in runs]
    assert [x.position("ball") for x in t[0]] == [x.position("ball") for x in t[1]]
    assert t[0][9].position("ball") != t[2][9].position("ball")
    assert runs[0].parameters == runs[1].parameters != runs[2].parameters


def test_a_run_is_iterated_once_and_stops_when_closed() -> None:
    src = source(scenario())
    it = iter(src)
    next(it)
    src.close()
    assert list(it) == []
    with pytest.raises(RealityError, match="iterated once"):
        iter(src)


def test_truth_memory_is_bounded() -> None:
    sc = scenario(run="run: {fps: 10, max_frames: 12}\n")
    src = SyntheticSource(sc, streams=Streams(1), history=4)
    for _ in src:
        pass
    assert src.truth.at(7) is None and src.truth.at(8).index == 8 and src.truth.at(11).index == 11
    assert src.truth.at(12) is None


def test_truth_records_the_drawn_parameters() -> None:
    src = source(scenario(NOISY + "  camera_offset_deg: 2.0\n"), 3)
    p = src.parameters
    assert isinstance(p, TrueParameters) and p.seed == 3
    assert 0.5 <= p.object("ball").restitution <= 0.9
    assert math.isclose(float(np.linalg.norm(p.camera_rotation_deg)), 2.0)
    next(iter(src))
    assert src.truth.at(0).parameters is p
    assert p.as_json()["objects"][0]["name"] == "ball"


# -- the true camera ---------------------------------------------------------------------------

def test_a_neutral_reality_renders_exactly_what_the_imagination_renders() -> None:
    sc = scenario("  appearance: {noise: 0, blur: 0}\n")
    frame = next(iter(source(sc)))
    model = Renderer(sc.scene, sc.camera).render()
    assert np.array_equal(frame.image, model.image)


def test_the_true_camera_is_the_nominal_one_moved_by_the_offset() -> None:
    sc = scenario("  camera_offset: [0.05, 0.0, -0.02]\n  camera_offset_deg: [3.0, 0.0, 0.0]\n"
                  "  appearance: {noise: 0, blur: 0}\n")
    src = source(sc)
    frame = next(iter(src))
    cam = src.truth.at(0).camera
    assert cam.position == pytest.approx(sc.camera.position + [0.05, 0.0, -0.02])
    # A pan turns the camera about world up: its relative rotation is 3 degrees about z.
    rel = sc.camera.rotation.T @ cam.rotation
    assert np.degrees(rotation_log(rel)) == pytest.approx([0.0, 0.0, -3.0], abs=1e-9)
    # The viewing direction keeps its elevation and turns 3 degrees to the left.
    f0, f1 = sc.camera.rotation[2], cam.rotation[2]
    assert f1[2] == pytest.approx(f0[2])
    assert math.degrees(math.atan2(f1[1], f1[0]) - math.atan2(f0[1], f0[0])) == pytest.approx(3.0)
    # And that is the camera the image was rendered with.
    assert np.array_equal(frame.image, Renderer(sc.scene, cam).render().image)
    nominal = Renderer(sc.scene, sc.camera).render().image
    assert np.abs(frame.image.astype(int) - nominal).mean() > 5


def test_tilt_and_roll_turn_the_camera_about_its_own_axes() -> None:
    sc = scenario("  camera_offset_deg: [0.0, 2.0, -4.0]\n")
    cam = source(sc).camera()
    rel = cam.rotation @ sc.camera.rotation.T          # camera-frame rotation
    w = np.degrees(rotation_log(rel))
    assert w == pytest.approx([-2.0, 0.0, 4.0], abs=0.1)  # tilt about x, roll about z
    # A positive tilt looks up.
    assert cam.rotation[2][2] > sc.camera.rotation[2][2]


def test_a_random_offset_has_the_given_magnitude_in_a_seeded_direction() -> None:
    sc = scenario("  camera_offset: 0.03\n  camera_offset_deg: 1.5\n")
    draws = [source(sc, seed).parameters for seed in (1, 2, 1)]
    for p in draws:
        assert float(np.linalg.norm(p.camera_offset)) == pytest.approx(0.03)
        assert float(np.linalg.norm(p.camera_rotation_deg)) == pytest.approx(1.5)
    assert draws[0].camera_offset == draws[2].camera_offset != draws[1].camera_offset


# -- objects of reality only ---------------------------------------------------------------

def test_an_unexpected_object_shows_in_the_frames_after_it_appears() -> None:
    sc = scenario("  appearance: {noise: 0, blur: 0}\n  objects:\n"
                  "    - {name: box, radius: 0.15, color: [20, 220, 20], "
                  "throw: {t: 0.3, x: -0.8, y: 1.0}}\n")
    src = source(sc)
    cam = sc.camera
    u, v = cam.project(np.array([[-0.8, 1.0, 0.15]]))[0]
    seen = []
    for f in src:
        b, g, r = f.image[int(round(v)), int(round(u))].astype(int)
        seen.append(g > 150 and g > r + 60 and g > b + 60)
        assert (src.truth.at(f.index).position("box") is not None) == (f.time >= 0.3 - 1e-9)
    assert seen == [t >= 0.3 - 1e-9 for t in np.arange(10) / 10]
    assert not src.parameters.object("box").declared


def test_a_scenario_that_is_not_synthetic_is_refused(tmp_path: Path) -> None:
    (tmp_path / "a.png").write_bytes(b"")
    (tmp_path / "s.yaml").write_text(CAMERA + WORLD + "reality: {kind: video, path: '*.png', fps: 5}\n")
    sc = load_scenario(tmp_path / "s.yaml")
    with pytest.raises(RealityError, match="expected a synthetic reality"):
        SyntheticSource(sc, streams=Streams(1))
