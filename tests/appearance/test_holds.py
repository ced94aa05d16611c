"""Perception that holds on a reality whose look it learns (issue 20, item 2): a ball
rolling from the first frame seen by a camera outside the arena, a ghost in the learned
look, a ball that leaves the box its schema was spawned on, and what the summary says
of a goal's object never seen."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from adapt.runner import Runner
from adapt.scenario import OutputSettings, loads_scenario

from . import checks as C

QUIET = OutputSettings(report=False, trace=False, video=False, figures=False)
RULES = C.ROOT / "rules" / "mirror" / "perception.soar"

#: The appearance checks' room (its look unknown to the scenario) seen from outside: the
#: camera 1.6 m up behind a 12 cm south wall, looking down over it; the ball rolling from
#: the first frame.
OUTSIDE = f"""
seed: 3
camera: {{fx: 230.0, fy: 230.0, cx: 159.5, cy: 119.5, width: 320, height: 240,
          position: [0.0, -1.6, 1.6], look_at: [0.0, 1.2, 0.0]}}
world:
  floor: {{texture: gravel, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}}
  walls:
    - {{name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}}
    - {{name: east,  from: [2.5, 3.0],  to: [2.5, -1.0], height: 1.0, texture: brick, tile: 0.6}}
    - {{name: south, from: [2.5, -1.0], to: [-2.5, -1.0], height: 0.12, texture: brick, tile: 0.6}}
    - {{name: west,  from: [-2.5, -1.0], to: [-2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}}
  obstacles:
    - {{name: crate, polygon: [[-1.3, 2.35], [-0.75, 2.35], [-0.75, 2.85], [-1.3, 2.85]], height: 0.4, color: [150, 110, 60]}}
  objects:
    - {{name: ball, radius: 0.11, mass: 0.45, color: [230, 60, 30], create: when_seen}}
reality:
  camera_offset: [0.01, -0.01, 0.005]
  camera_offset_deg: [0.5, -0.3, 0.4]
  appearance: {{brightness: 6, contrast: 1.05, color_shift: [4, 0, -4], gradient: 0.25,
               blur: 0.6, noise: 2.5, texture_scale: 1.12, texture_phase: [0.23, 0.11],
               tint: [0.92, 1.0, 1.08]}}
  objects:
    - name: ball
      throw: {{t: 0.0, x: -1.2, y: 0.6, speed: 1.6, heading_deg: 15}}
goals: [{{name: watch, object: ball}}]
rules: [{RULES}]
schemas:
  scene-background: {{appearance: "on"}}
run: {{fps: 15, duration: 2.4}}
"""


class Frames:
    """The frame records' sightings of the ball, beside the truth (evaluation)."""

    def __init__(self) -> None:
        self.truth: Any = None
        self.rows: list[dict[str, Any]] = []

    def frame(self, record: Any) -> None:
        t = self.truth.at(record.index)
        ball = t.objects.get("ball") if t is not None else None
        tracked = record.tracked_object("ball")
        self.rows.append({"t": record.time, "names": [x.name for x in record.tracked],
                          "truth": None if ball is None else ball.position,
                          "observed": None if tracked is None else tracked.observed,
                          "stage": None if record.background is None
                          else record.background.stage.value})


def run(text: str, tmp_path: Path | None = None) -> tuple[dict[str, Any], Frames]:
    sc = loads_scenario(text, file="outside.yaml", base=C.HERE)
    rec = Frames()
    runner = Runner(sc, out=None, seed=sc.seed, outputs=QUIET, listeners=(rec,))
    rec.truth = runner.truth
    return runner.run().summary, rec


@pytest.fixture(scope="module")
def outside() -> tuple[dict[str, Any], Frames]:
    return run(OUTSIDE)


def test_a_ball_rolling_from_the_first_frame_is_never_learned_nor_a_ghost(outside) -> None:
    summary, rec = outside
    # one schema, for the ball: none spawned on the spot it left, none for anything else
    names = {n for row in rec.rows for n in row["names"]}
    assert names == {"ball"}, names
    assert summary["events"].get("spawned", 0) == 1
    learned = [row for row in rec.rows if row["stage"] == "learned"]
    assert learned
    seen = [row for row in learned if row["observed"] is not None]
    near = [row for row in seen if math.dist(row["observed"], row["truth"]) < 2 * 0.11]
    assert len(seen) >= 0.8 * len(learned) and len(near) == len(seen), (len(learned), len(seen))
    g = summary["goal_objects"]["ball"]
    assert not g["never_seen"] and g["first_seen_s"] < 1.0 and g["lost"] == 0


def test_the_summary_says_a_goals_object_was_never_seen() -> None:
    # the ball is thrown after the run ends: the goal's object never shows
    text = OUTSIDE.replace("throw: {t: 0.0,", "throw: {t: 9.0,").replace("duration: 2.4",
                                                                          "duration: 1.0")
    summary, rec = run(text)
    g = summary["goal_objects"]["ball"]
    assert g["never_seen"] and g["frames_seen"] == 0 and g["unseen_s"] == pytest.approx(1.0)
    from adapt.cli.run import summary_lines

    assert "the goal's object 'ball' was never seen (1 s)" in summary_lines(summary)


def _ghost_network(rows: slice, cols: slice) -> tuple[Any, Any, list[Any]]:
    """A network whose Scene Background learned the synthetic reality's look, then a ghost in
    it at ``rows, cols`` (the look of a patch of floor learned wrong: an object at rest when it
    was learned, gone since); and the reality's frames."""
    from adapt.mirror import Mirror
    from adapt.reality import open_reality
    from adapt.scenario import RealityKind, load_scenario
    from adapt.schemas import SchemaNetwork
    from adapt.schemas.background import AppearanceStage, SceneBackground
    from adapt.seeds import Streams

    sc = load_scenario(C.SYNTHETIC)
    net = SchemaNetwork(Mirror(sc.scene, sc.camera), frame_interval=1 / 15,
                        models={m.name: m for m in sc.objects}, reality=RealityKind.SYNTHETIC)
    bg = net.instantiate("scene-background", parameters={"appearance": "on", "learn_every": 2})
    assert isinstance(bg, SceneBackground)
    source = open_reality(sc, streams=Streams(sc.seed or 0))
    try:
        frames = [f for f, _ in zip(source, range(16))]  # the ball is thrown at 0.6 s: 9 frames
    finally:
        source.close()
    for f in frames[:6]:
        net.perceive(f)
    assert bg.stage is AppearanceStage.LEARNED and not [r for r in bg.regions if not r.expected]
    labels = net.mirror.render().labels
    painted = frames[5].image.copy()
    spot = np.zeros(labels.shape, bool)
    spot[rows, cols] = True
    painted[spot] = (30, 30, 220)
    net.mirror.learn_appearance(painted, labels, relearn=spot)
    return net, bg, frames


def _over(bg: Any, rows: slice, cols: slice) -> list[Any]:
    """The regions ``bg`` reports over ``rows, cols``."""
    return [r for r in bg.regions if r.bbox[0] < cols.stop and r.bbox[0] + r.bbox[2] > cols.start
            and r.bbox[1] < rows.stop and r.bbox[1] + r.bbox[3] > rows.start]


def test_a_ghost_in_the_learned_look_is_still_never_spawned_for_and_repaired() -> None:
    from adapt.frames import Frame

    rows, cols = slice(150, 170), slice(200, 225)
    net, bg, frames = _ghost_network(rows, cols)
    ghost = []
    for k in range(6, 16):
        f = frames[k]
        net.perceive(Frame(f.index, 6 / 15 + (k - 5) / 15, frames[5].image))  # nothing moves
        ghost.append(_over(bg, rows, cols))
    assert ghost[0] and all(r.still and not r.expected for found in ghost for r in found)
    assert not ghost[-1], "the look was repaired where the camera sees floor, still"


@pytest.mark.parametrize("colour, kept", [((230, 60, 30), True), ((30, 30, 220), False)])
def test_a_still_object_nothing_follows_is_never_learned_into_the_look(
        colour: tuple[int, int, int], kept: bool) -> None:
    # bench/foreign.py's throw 23 (a camera on the robot): the ball lost, at rest in plain view,
    # a region still and unfollowed; the camera stood still but far from synchronised, and
    # what held still was learned afresh -- the ball with it, into the floor, where nothing
    # could find it again.  A still region the colour of a declared object (the red ball) on
    # texels the look learned is kept; one of no object's colour is the look's error, repaired
    import cv2

    from adapt.frames import Frame

    rows, cols = slice(150, 170), slice(200, 225)
    net, bg, frames = _ghost_network(slice(0, 0), slice(0, 0))  # the look learned right
    image = frames[5].image.copy()
    cv2.circle(image, (212, 160), 10, colour[::-1], -1)  # (frames are BGR)
    found = []
    for k in range(6, 22):
        net.perceive(Frame(frames[5].index + k - 5, 6 / 15 + (k - 5) / 15, image))
        found.append(_over(bg, rows, cols))
    # (still once its box held still over STILL_REGION_FRAMES frames)
    assert found[0] and all(r.still and not r.expected for f in found[3:] for r in f)
    assert bg.learn_passes > 3  # the look was refined meanwhile
    left = sum(r.area for r in found[-1])
    if kept:  # whole, and still taken for the ball
        assert left >= 0.9 * found[0][0].area and found[-1][0].looks_like == "ball", found[-1]
    else:  # repaired, but for a few pixels of its rim (38 of 313 when written)
        assert left < 0.2 * found[0][0].area, found[-1]


def test_a_small_ghost_is_still_through_a_few_noisy_pixels() -> None:
    # robot camera 8 of bench/foreign.py at 320x240: dozens of small regions of a look
    # learned wrong, each a few pixels of the sensor's noise away from "not still" (one pixel
    # is 3 % of a 7 x 5 box) on one frame or another, and six objects the scenario does not
    # know spawned for them
    from adapt.frames import Frame

    rows, cols = slice(150, 156), slice(200, 207)
    net, bg, frames = _ghost_network(rows, cols)
    rng = np.random.default_rng(3)
    reports = []
    for k in range(6, 16):
        image = frames[5].image.copy()
        # a pixel of noise on the ghost, another every frame (three over the frames a
        # region is judged still by)
        y, x = int(rng.integers(150, 156)), int(rng.integers(200, 207))
        image[y, x] = np.clip(image[y, x].astype(int) + 90, 0, 255)
        net.perceive(Frame(frames[k].index, 6 / 15 + (k - 5) / 15, image))
        reports += _over(bg, rows, cols) if len(bg.history) >= 3 else []
    assert reports and all(r.still and not r.expected for r in reports), \
        [(r.bbox, r.age, r.still) for r in reports]


def test_a_ball_hidden_for_a_while_is_found_again_along_its_path() -> None:
    # a pillar between the camera and the ball's path hides it for about half a second
    # (longer than lost_after): found again where its track and its imagined body go,
    # and never taken for another object
    pillar = ("    - {name: pillar, polygon: [[0.35, 0.05], [0.75, 0.05], [0.75, 0.3], [0.35, 0.3]], "
              "height: 0.9, color: [90, 90, 160]}\n")
    text = OUTSIDE.replace("  objects:\n    - {name: ball", pillar + "  objects:\n    - {name: ball")
    summary, rec = run(text)
    names = {n for row in rec.rows for n in row["names"]}
    assert names == {"ball"}, names
    g = summary["goal_objects"]["ball"]
    assert g["lost"] >= 1 and not g["lost_at_end"], g
    seen = [row for row in rec.rows if row["observed"] is not None]
    assert all(math.dist(row["observed"], row["truth"]) < 2 * 0.11 for row in seen)


@pytest.mark.parametrize("size", [(160, 120), (80, 60)])
def test_a_ball_a_few_pixels_across_is_seen_on_most_frames(size: tuple[int, int]) -> None:
    # at 160x120 the ball is 4-5 px in radius: one pixel of blur at its top makes a
    # radius fitted freely half as large again, so the ball's image is recognised by its
    # area and its outline where the known radius fits it (bench/foreign.py --small lost
    # a quarter of the visible frames to the free radius); at 80x60 it is 2 px in radius,
    # too few columns for an outline, and placed by its centroid (it was never seen)
    w, h = size
    f = 230.0 * w / 320
    text = OUTSIDE.replace("fx: 230.0, fy: 230.0, cx: 159.5, cy: 119.5, width: 320, height: 240",
                           f"fx: {f}, fy: {f}, cx: {w / 2 - 0.5}, cy: {h / 2 - 0.5}, "
                           f"width: {w}, height: {h}")
    _, rec = run(text)
    assert {n for row in rec.rows for n in row["names"]} == {"ball"}
    learned = [row for row in rec.rows if row["stage"] == "learned"]
    seen = [row for row in learned if row["observed"] is not None]
    assert len(seen) >= 0.8 * len(learned), (len(seen), len(learned))
    assert all(math.dist(row["observed"], row["truth"]) < 2 * 0.11 for row in seen)


def _behind_the_robot(y: float, fps: int) -> Frames:
    """The outside view with a robot standing at (0, 0.85) and the ball rolling east behind
    it at ``y`` (in the image: just above it, or partly hidden by it)."""
    text = OUTSIDE.replace(
        "  objects:\n    - {name: ball",
        "  robot: {shape: disc, radius: 0.2, position: [0.0, 0.85], heading_deg: 90, "
        "max_speed: 0.8, max_accel: 1.5, mass: 10.0, height: 0.3, color: [40, 40, 45]}\n"
        "  objects:\n    - {name: ball", 1)
    text = text.replace("throw: {t: 0.0, x: -1.2, y: 0.6, speed: 1.6, heading_deg: 15}",
                        f"throw: {{t: 0.0, x: -1.2, y: {y}, speed: 1.4, heading_deg: 0}}")
    text = text.replace("run: {fps: 15, duration: 2.4}", f"run: {{fps: {fps}, duration: 2.4}}")
    assert "robot: {shape" in text and f"y: {y}" in text and f"fps: {fps}" in text
    _, rec = run(text)
    assert {n for row in rec.rows for n in row["names"]} == {"ball"}
    return rec


def test_a_ball_passing_just_behind_the_robot_keeps_its_pixels() -> None:
    # the imagined robot's pixels, grown by a margin for its odometry's error, are left
    # out of the ball's search; a ball rolling just behind it (in the image, just above
    # it) lost its lower part to that margin and was missed on half the frames there
    rec = _behind_the_robot(1.35, 15)
    learned = [row for row in rec.rows if row["stage"] == "learned"]
    behind = [row for row in learned if abs(row["truth"][0]) < 0.45]  # the robot's 0.2 m + 0.25
    assert len(behind) >= 8
    seen = [row for row in behind if row["observed"] is not None]
    assert len(seen) >= 0.9 * len(behind), (len(seen), len(behind))
    assert all(math.dist(row["observed"], row["truth"]) < 0.11 for row in seen)


def test_a_ball_partly_hidden_by_the_robot_is_seen_by_what_shows() -> None:
    # nearer, the robot hides the ball: wholly for a while, then all but a quarter of it
    # as it comes out beside the robot (53 of its 200 pixels at x = 0.17 m); its blob was
    # tested against the whole ball's area and refused, and is now tested against what the
    # imagined robot leaves of it
    rec = _behind_the_robot(1.2, 30)
    learned = [row for row in rec.rows if row["stage"] == "learned"]
    hidden = [i for i, row in enumerate(learned) if abs(row["truth"][0]) < 0.1]
    assert hidden and all(learned[i]["observed"] is None for i in hidden)  # wholly behind it
    out = [row for row in learned[hidden[-1] + 1:] if row["truth"][0] >= 0.16]
    assert len(out) >= 6
    # the first of them may show only a sliver past the robot's margin narrower than the
    # blobs' opening (3 px: no blob at all; x = 0.17 m, with the camera as the edge fit
    # leaves it since ede26d5); from the next on, each is seen
    first, rest = out[0], out[1:]
    assert first["truth"][0] < 0.2
    assert all(row["observed"] is not None for row in rest), [
        round(row["truth"][0], 2) for row in rest if row["observed"] is None]
    seen = [row for row in out if row["observed"] is not None]
    assert all(math.dist(row["observed"], row["truth"]) < 0.05 for row in seen)


@pytest.mark.parametrize("in_step", [True, False])
def test_frames_without_matches_are_compared_through_the_structures_alignment(
        monkeypatch: pytest.MonkeyPatch, in_step: bool) -> None:
    # a view whose texture the renderer aliases differently as the camera turns gives no
    # matches (bench/foreign.py's robot cameras); the structure still aligns it: the frame
    # is compared through that, the ball followed, and the look kept (it used to be
    # forgotten and learned again after 10 such frames); regions are reported only by a
    # fixed camera whose matches last left it in step
    import adapt.schemas.background as background_module
    import adapt.vision.mmd as mmd_module
    from adapt.schemas.background import SceneBackground
    from adapt.vision.homography import Alignment

    failing = range(16, 30)
    state = {"fail": False}
    real_sync, real_align = SceneBackground._sync, mmd_module._align

    def sync(self: Any, frame: Any, *args: Any, **kw: Any) -> Any:
        state["fail"] = frame.index in failing
        return real_sync(self, frame, *args, **kw)

    def align(*args: Any, **kw: Any) -> Any:
        matches, alignment = real_align(*args, **kw)
        if state["fail"]:
            alignment = Alignment(None, np.zeros(len(matches), bool), "none", "no matches (forced)")
        return matches, alignment

    monkeypatch.setattr(SceneBackground, "_sync", sync)
    monkeypatch.setattr(mmd_module, "_align", align)
    if not in_step:  # no error is small enough: as a camera out of step
        monkeypatch.setattr(background_module, "HELD_IN_STEP", -1.0)
    held: list[dict[str, Any]] = []
    settled: list[float] = []

    class Held(Frames):
        def frame(self, record: Any) -> None:
            super().frame(record)
            bg = record.background
            schema = next(x for x in runner.network.ordered() if x.name == "background")
            settled.append(schema._settled)
            if record.index in failing and bg is not None and bg.mmd is not None:
                held.append({"held": bg.mmd.alignment.held, "regions": len(bg.regions),
                             "trusted": bg.trusted, "row": self.rows[-1]})

    sc = loads_scenario(OUTSIDE, file="outside.yaml", base=C.HERE)
    rec = Held()
    runner = Runner(sc, out=None, seed=sc.seed, outputs=QUIET, listeners=(rec,))
    rec.truth = runner.truth
    runner.run()
    assert len(held) == len(failing) and all(h["held"] and h["trusted"] for h in held)
    # a fixed camera in step compares the frame through the camera its matches last
    # corrected, which has not moved: it reports regions as it would with matches (a
    # camera on the robot, which may have turned since, reports none)
    if in_step:
        assert any(h["regions"] > 0 for h in held)
    else:
        assert all(h["regions"] == 0 for h in held)
    assert all(h["row"]["stage"] == "learned" for h in held)
    seen = [h["row"] for h in held if h["row"]["observed"] is not None]
    assert len(seen) >= 0.8 * len(held), len(seen)
    assert all(math.dist(row["observed"], row["truth"]) < 2 * 0.11 for row in seen)
    assert {n for row in rec.rows for n in row["names"]} == {"ball"}
    bg = next(x for x in runner.network.ordered() if x.name == "background")
    assert bg.summary()["structure_held"] == len(failing)
    # a held H_e's error (0 by construction) is no measurement of the camera: the smoothed
    # error the false-jump filter compares with stays what the matches last said
    before = settled[failing[0] - 1]
    assert before < 1e9 and all(v == before for v in settled[failing[0]:failing[-1] + 1])


def test_a_misfit_of_an_unknown_object_kilometres_wide_is_refused(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # a blob near the horizon can fit a sphere 8e9 m wide (seed 49 of bench/foreign.py):
    # a radius like that passes any test of where it stands, and cannot be a body
    import dataclasses

    import adapt.schemas.foreground as foreground
    from adapt.mirror import Mirror
    from adapt.reality import open_reality
    from adapt.scenario import RealityKind, load_scenario
    from adapt.schemas import Origin, SchemaNetwork
    from adapt.seeds import Streams

    real = foreground.fit_ball

    def wide(*args: Any, **kw: Any) -> Any:
        fit = real(*args, **kw)
        return None if fit is None else dataclasses.replace(fit, radius=8.09e9)

    monkeypatch.setattr(foreground, "fit_ball", wide)
    sc = load_scenario(C.SYNTHETIC)
    net = SchemaNetwork(Mirror(sc.scene, sc.camera), frame_interval=1 / 15,
                        models={m.name: m for m in sc.objects}, reality=RealityKind.SYNTHETIC)
    bg = net.instantiate("scene-background", parameters={"appearance": "on", "learn_every": 2})
    source = open_reality(sc, streams=Streams(sc.seed or 0))
    unknown = None
    try:
        for f, _ in zip(source, range(32)):  # the ball comes into view at frame 24
            net.perceive(f)
            regions = [r for r in bg.regions if not r.expected]
            if unknown is None and regions:
                unknown = net.instantiate("foreground-object", origin=Origin.BOTTOM_UP,
                                          parameters={"region": regions[0].id})
    finally:
        source.close()
    assert isinstance(unknown, foreground.ForegroundObject)
    assert unknown.refused > 0 and unknown.sightings == 0 and unknown.ball is None
