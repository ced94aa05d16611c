"""The Scene Background schema's appearance learning: when it is on, what the rules
see, how often it learns, what it never learns, the trace record, re-acquisition."""

from __future__ import annotations

import base64
import dataclasses

import cv2
import numpy as np
import pytest

from adapt.engine import Agent
from adapt.frames import Frame
from adapt.mirror import Mirror
from adapt.reality import open_reality
from adapt.reality.camera import offset_camera
from adapt.runner.trace import APPEARANCE_EVERY, AppearanceTrace
from adapt.scenario import RealityKind, Scenario, load_scenario
from adapt.schemas import SchemaNetwork
from adapt.schemas.background import REACQUIRE_AFTER, AppearanceStage, SceneBackground
from adapt.seeds import Streams

from . import checks as C


@pytest.fixture(scope="module")
def video() -> Scenario:
    return load_scenario(C.VIDEO)


def frames(sc: Scenario, n: int) -> list[Frame]:
    source = open_reality(sc, streams=Streams(sc.seed or 0))
    try:
        return [f for f, _ in zip(source, range(n))]
    finally:
        source.close()


def network(sc: Scenario, reality: str, camera=None) -> SchemaNetwork:
    return SchemaNetwork(Mirror(sc.scene, camera or sc.camera), frame_interval=1 / 15,
                         models={m.name: m for m in sc.objects}, reality=RealityKind(reality))


@pytest.mark.parametrize("reality, mode, stage", [
    ("video", "auto", AppearanceStage.STRUCTURE),
    ("bullet", "auto", AppearanceStage.STRUCTURE),   # another renderer's look is not known either
    ("synthetic", "auto", AppearanceStage.OFF),
    ("synthetic", "on", AppearanceStage.STRUCTURE),
    ("video", "off", AppearanceStage.OFF),
])
def test_auto_learns_a_videos_look_and_leaves_a_synthetic_alone(video, reality, mode, stage) -> None:
    bg = network(video, reality).instantiate("scene-background",
                                             parameters={"appearance": mode})
    assert isinstance(bg, SceneBackground) and bg.stage is stage


def test_a_loaded_look_is_refined_without_aligning_the_structure_first(video, tmp_path) -> None:
    net = network(video, "video")
    bg = net.instantiate("scene-background")
    for f in frames(video, 2):
        net.perceive(f)
    assert bg.stage is AppearanceStage.LEARNED
    net.mirror.save_appearance(tmp_path / "look")
    again = network(video, "video")
    again.mirror.load_appearance(tmp_path / "look")
    bg2 = again.instantiate("scene-background")
    assert bg2.stage is AppearanceStage.LEARNED
    # from the nominal camera, the MMD with the loaded look synchronises it (no structure)
    errors = []
    for f in frames(video, 10):
        again.perceive(f)
        assert bg2.result is not None and bg2.result.aligned
        errors.append(bg2.pixel_error)
    assert errors[0] > 2.0 and max(errors[-3:]) < 0.5, errors
    assert not [r for r in bg2.regions if not r.expected]
    turn = again.mirror.camera.rotation @ net.mirror.camera.rotation.T
    angle = np.arccos(np.clip((np.trace(turn) - 1) / 2, -1, 1))
    assert angle * video.camera.fx < 0.5  # the same camera as the run that learned, within tolerance


RULES = """
sp {watch*appearance
   (state <s> ^io.input-link <in>)
   (<in> ^frame.index <i> ^schema <x>)
   (<x> ^type scene-background ^appearance <a> ^status <st>)
-->
   (write |frame | <i> | | <a> | | <st> (crlf))}

sp {watch*structure-error
   (state <s> ^io.input-link.schema <x>)
   (<x> ^structure-error <e>)
-->
   (write |error | <e> (crlf))}
"""


def test_the_rules_see_the_stage_and_the_structure_error(video) -> None:
    far = offset_camera(video.camera, (0.0, 0.0, 0.0), (4.0, -3.0, 2.0))
    net = network(video, "video", camera=far)
    net.instantiate("scene-background", "background")
    agent = Agent(seed=1)
    agent.load_text(RULES)
    agent.on_input(net.write_input)
    agent.on_output(net.on_output)
    out: list[str] = []
    agent.on_write(out.append)
    for f in frames(video, 6):
        net.perceive(f)
        agent.run(1, footer=False)
    text = "".join(out)
    assert "frame 0 structure waiting" in text and "error " in text
    assert "learned running" in text


def test_learning_every_k_synchronised_frames(video) -> None:
    net = network(video, "video")
    bg = net.instantiate("scene-background", parameters={"learn_every": 4})
    passes = []
    for f in frames(video, 12):
        net.perceive(f)
        passes.append(bg.learn_passes)
    first = next(i for i, p in enumerate(passes) if p)
    assert passes[first] == 1
    assert passes[-1] == 1 + (11 - first) // 4


def test_what_a_schema_monitors_is_never_learned(video) -> None:
    net = network(video, "video")
    bg = net.instantiate("scene-background", parameters={"learn_every": 1})
    box = (100, 170, 60, 40)  # a part of the floor
    net.monitored_boxes = lambda exclude=None: [("somebody", box)]  # type: ignore[method-assign]
    for f in frames(video, 8):
        x, y, w, h = box
        image = f.image.copy()
        image[y:y + h, x:x + w] = (20, 20, 240)  # red, where "somebody" looks
        net.perceive(Frame(f.index, f.time, image))
    assert bg.learn_passes >= 6
    floor = net.mirror.appearance.texture("floor")
    assert floor is not None and floor.coverage > 0.2
    img = floor.image.astype(int)
    red = (img[:, :, 2] - np.maximum(img[:, :, 0], img[:, :, 1]) > 60) & floor.mask
    assert not red.any()


def test_the_trace_record_is_rate_limited_and_shows_previews(video) -> None:
    net = network(video, "video")
    bg = net.instantiate("scene-background")
    for f in frames(video, 2):
        net.perceive(f)
    looks = AppearanceTrace(net.mirror.appearance)
    percept = bg.percept
    assert percept is not None and percept.frame == 1
    first = looks.record(percept)
    assert first is not None and first["stage"] == "learned" and first["passes"] == 1
    names = [s["name"] for s in first["surfaces"]]
    assert names[0] == "floor" and "north" in names and "sky/+y" in names
    for s in first["surfaces"]:
        assert s["image"].startswith("data:image/png;base64,")
        png = base64.b64decode(s["image"].split(",", 1)[1])
        img = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
        assert img.shape[2] == 4 and max(img.shape[:2]) <= 160 and 0 < s["coverage"] <= 1
    # later records: only when the look changed, and ever more rarely
    recorded = []
    passes = percept.learn_passes
    for frame in range(2, 2 + 8 * APPEARANCE_EVERY):
        if frame % 10 == 0:
            passes += 1  # a refinement pass, as every 10 frames
        if looks.record(dataclasses.replace(percept, frame=frame, learn_passes=passes)):
            recorded.append(frame - 1)
    assert recorded == [APPEARANCE_EVERY, 3 * APPEARANCE_EVERY, 7 * APPEARANCE_EVERY]  # 30, 60, 120
    last = dataclasses.replace(percept, frame=2 + 8 * APPEARANCE_EVERY, learn_passes=passes)
    assert looks.record(last) is None  # nothing new


def blank(f: Frame) -> Frame:
    return Frame(f.index, f.time, np.full_like(f.image, 127))


def test_a_lost_view_aligns_the_structure_again(video) -> None:
    net = network(video, "video")
    bg = net.instantiate("scene-background")
    fs = frames(video, 4)
    for f in fs[:2]:
        net.perceive(f)
    assert bg.stage is AppearanceStage.LEARNED
    for k in range(REACQUIRE_AFTER):
        net.perceive(blank(Frame(2 + k, (2 + k) / 15, fs[0].image)))
    assert bg.stage is AppearanceStage.STRUCTURE and net.mirror.appearance.learned == ()
    net.perceive(Frame(20, 20 / 15, fs[2].image))
    net.perceive(Frame(21, 21 / 15, fs[3].image))
    assert bg.stage is AppearanceStage.LEARNED and bg.pixel_error < 0.5


def test_a_camera_on_the_robot_moves_from_the_frame_its_robot_is_driven() -> None:
    # held-out throw 110 of bench/foreign.py: the real robot set off between two frames while
    # its odometry had not yet carried the camera MOUNT_MOVED, and the view's shift, taken
    # for a still camera's, spawned a schema for a ghost it had shaken loose
    from adapt.scenario import Mount

    sc = load_scenario(C.ROOT / "scenarios" / "bouncing-ball.yaml")
    assert sc.mount.kind is Mount.ROBOT
    mirror = Mirror(sc.scene, sc.camera,
                    camera_follows_robot=lambda p, h: sc.mount.camera_at(sc.camera, p, h))
    net = SchemaNetwork(mirror, frame_interval=1 / 30, models={m.name: m for m in sc.objects},
                        reality=RealityKind.SYNTHETIC)
    bg = net.instantiate("scene-background", parameters={"appearance": "off"})
    assert isinstance(bg, SceneBackground)
    shots = frames(sc, 3)
    net.perceive(shots[0])
    assert not bg.camera_moving
    net.command_robot((0.3, 0.0))  # driven, and not a step of the imagination yet
    net.perceive(shots[1])
    assert bg.camera_moving
    net.command_robot((0.0, 0.0))  # stopped at once: the odometry never carried it
    net.perceive(shots[2])
    assert not bg.camera_moving


def test_a_camera_on_the_robot_is_never_turned_far_by_one_step() -> None:
    # held-out throw 107 of bench/foreign.py: a robot camera a few pixels out of step took a
    # step whose H_e moved the image by 1,054 px (a false alignment, 16 degrees off); the
    # jump filter held only for a camera that had been synchronised, so it was believed, the
    # structure's alignment kept the camera 20-23 degrees off, and the sightings were 30 cm
    # off for 25 frames.  The odometry carries such a camera: a step that far is refused, for
    # up to `glitches` frames in a row, synchronised or not; a fixed camera's filter is as before
    from adapt.schemas.background import MOUNTED_JUMP
    from adapt.vision.scale import image_scale

    sc = load_scenario(C.ROOT / "scenarios" / "bouncing-ball.yaml")
    frame = Frame(0, 0.0, np.zeros((sc.camera.height, sc.camera.width, 3), np.uint8))
    scale = image_scale(frame.image.shape)
    for mounted in (True, False):
        follows = (lambda p, h: sc.mount.camera_at(sc.camera, p, h)) if mounted else None
        net = SchemaNetwork(Mirror(sc.scene, sc.camera, camera_follows_robot=follows),
                            frame_interval=1 / 30, models={m.name: m for m in sc.objects},
                            reality=RealityKind.SYNTHETIC)
        bg = net.instantiate("scene-background", parameters={"appearance": "off"})
        assert isinstance(bg, SceneBackground)
        bg._settled = 16.0 * scale  # out of step
        far, near = 1.5 * MOUNTED_JUMP * scale, 0.5 * MOUNTED_JUMP * scale
        assert bg._implausible(far, frame) is mounted
        assert not bg._implausible(near, frame)
        bg._settled = 0.5 * scale  # synchronised: the jump filter, for either
        assert bg._implausible(near, frame)
        bg._glitches = int(bg.parameters["glitches"])  # refused that often: believed
        assert not bg._implausible(far, frame)
