"""The runner's loop on a test reality: synchronisation, bottom-up spawning, outputs,
determinism, interrupts and failures."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from adapt.errors import OutputError, RunError
from adapt.imagination import Ball
from adapt.runner import Runner
from adapt.scenario import OutputSettings, Scenario

from .conftest import room
from .sources import RenderedSource

TURN = (0.012, -0.018, 0.01)  # about 6 px at 320x240
QUIET = OutputSettings(video=False, figures=False)


def source(sc: Scenario, frames: int = 60, **kw: object) -> RenderedSource:
    return RenderedSource(sc.scene, sc.camera, frames=frames, turn=kw.pop("turn", TURN), **kw)  # type: ignore[arg-type]


def frames_of(out: Path) -> list[dict]:
    return json.loads((out / "report.json").read_text())["frames"]


def test_the_background_synchronises_and_the_mmd_goes_quiet(scenario: Scenario, tmp_path: Path) -> None:
    res = Runner(scenario, source=source(scenario, 40), out=tmp_path,
                 outputs=QUIET).run()
    frames = frames_of(tmp_path)
    errors = [f["mmd"]["pixel_error"] for f in frames if f.get("mmd", {}).get("aligned")]
    assert errors[0] > 3.0, errors[:3]
    assert max(errors[-10:]) < 0.5, errors[-10:]
    assert all(f["unexpected_regions"] == 0 for f in frames[-10:])
    assert res.summary["events"]["instantiated"] == 1 and "spawned" not in res.summary["events"]
    assert frames[-1]["schemas"] == ["background"]


def test_an_object_in_reality_only_gets_one_schema_and_a_body_where_it_is(tmp_path: Path) -> None:
    sc = room()
    stranger = Ball("stranger", radius=0.12, position=(0.7, 1.4), color=(30, 200, 40))
    res = Runner(sc, source=source(sc, 50, extra=[(12, stranger)]), out=tmp_path,
                 outputs=QUIET).run()
    assert res.summary["events"].get("spawned") == 1
    frames = frames_of(tmp_path)
    spawned_at = next(f["index"] for f in frames if len(f["schemas"]) == 2)
    assert 12 + 2 <= spawned_at <= 12 + 8   # it persisted a few frames first
    (name,) = [n for n in frames[-1]["schemas"] if n != "background"]
    seen = frames[-1]["objects"][name]
    assert seen["imagined"] is not None
    assert abs(seen["imagined"][0] - 0.7) < 0.02 and abs(seen["imagined"][1] - 1.4) < 0.02
    # once it is monitored, its region is expected: nothing unexpected is left
    assert all(f["unexpected_regions"] == 0 for f in frames[-15:])
    trace = [json.loads(line) for line in (tmp_path / "trace.jsonl").read_text().splitlines()]
    kinds = [r["event"] for r in trace if r["kind"] == "schema"]
    assert kinds.count("spawned") == 1 and kinds.count("created") == 1


def test_sensor_noise_spawns_nothing(tmp_path: Path) -> None:
    sc = room()
    res = Runner(sc, source=source(sc, 40, noise=6.0), out=None).run()
    assert "spawned" not in res.summary["events"]


def test_a_declared_object_is_created_when_seen_and_named_by_the_goal() -> None:
    sc = room(objects="  objects:\n    - {name: ball, radius: 0.11, create: when_seen, "
                      "color: [230, 60, 30]}\n",
              extra="reality:\n  objects: [{name: ball, throw: {t: 0.3, x: 0, y: 1}}]\n")
    sc = replace(sc, goals=(replace(sc.goals[0], attributes=(("object", "ball"),)),))
    assert sc.scene.balls == ()  # not in the imagination at the start
    ball = Ball("ball", radius=0.11, position=(-0.4, 1.6), color=(230, 60, 30))
    runner = Runner(sc, source=source(sc, 40, extra=[(8, ball)]), out=None)
    res = runner.run()
    assert res.summary["schemas"] == ["background", "ball"]
    assert res.summary["events"]["spawned"] == 1 and res.summary["events"]["created"] == 1
    x, y = runner.mirror.world.position("ball")
    assert abs(x + 0.4) < 0.025 and abs(y - 1.6) < 0.025  # 320x240: a pixel is ~7 mm here


def test_the_same_seed_gives_the_same_report(tmp_path: Path) -> None:
    sc = room()
    stranger = Ball("stranger", radius=0.12, position=(0.7, 1.4), color=(30, 200, 40))
    outs = []
    for k in range(2):
        out = tmp_path / str(k)
        Runner(sc, source=source(sc, 30, extra=[(5, stranger)]), out=out,
               outputs=QUIET).run()
        frames = frames_of(out)
        for f in frames:
            f["mmd"].pop("ms", None)
        outs.append(frames)
    assert outs[0] == outs[1]


def test_an_interrupted_run_leaves_complete_outputs(tmp_path: Path) -> None:
    sc = room()
    res = Runner(sc, source=source(sc, 30, interrupt_at=7), out=tmp_path,
                 outputs=OutputSettings(figures=False)).run()
    assert res.interrupted
    report = json.loads((tmp_path / "report.json").read_text())
    assert len(report["frames"]) == 7 and report["summary"]["interrupted"] is True
    lines = (tmp_path / "trace.jsonl").read_text().splitlines()
    footer = [json.loads(x) for x in lines if '"kind":"footer"' in x]
    assert len(footer) == 1 and footer[0]["stop_reason"] == "interrupted"
    assert (tmp_path / "mmd.mp4").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [".adapt.lock", "mmd.mp4", "report.json",
                                                         "trace.jsonl"]  # no temporary file left


def test_a_failed_run_leaves_a_valid_report_and_raises(tmp_path: Path) -> None:
    sc = room()
    with pytest.raises(RuntimeError, match="cable"):
        Runner(sc, source=source(sc, 30, fail_at=4), out=tmp_path,
               outputs=QUIET).run()
    report = json.loads((tmp_path / "report.json").read_text())
    assert len(report["frames"]) == 4 and "cable" in report["summary"]["error"]


def test_report_keys_are_the_contract(tmp_path: Path) -> None:
    sc = room()
    Runner(sc, source=source(sc, 5), out=tmp_path,
           outputs=QUIET).run()
    report = json.loads((tmp_path / "report.json").read_text())
    for key in ("scenario", "seed", "fps", "frames", "summary"):
        assert key in report
    for f in report["frames"]:
        assert {"index", "t", "schemas", "unexpected_regions", "objects",
                "predictions"} <= set(f)


def test_frames_of_the_wrong_size_are_refused() -> None:
    sc = room()
    src = source(sc, 5)
    src.true_camera = src.true_camera.__class__(100, 100, 50, 50, 100, 80,
                                                src.true_camera.rotation, src.true_camera.position)
    with pytest.raises(RunError, match="100x80 but the scenario's camera is 320x240"):
        Runner(sc, source=src, out=None)


def test_outputs_never_replace_inputs(tmp_path: Path) -> None:
    sc = room()
    (tmp_path / "report.json").write_text("{}")
    sc = replace(sc, path=tmp_path / "report.json")
    with pytest.raises(OutputError, match="report output .* is the scenario; an output never "
                                          "replaces an input"):
        Runner(sc, source=source(sc, 3), out=tmp_path)
    assert (tmp_path / "report.json").read_text() == "{}"
    rules = tmp_path / "figures" / "mine.soar"
    rules.parent.mkdir()
    rules.write_text((Path(sc.rules[0].path)).read_text())
    inside = replace(room(), rules=(replace(sc.rules[0], path=rules),))
    with pytest.raises(OutputError, match="the figures output .* would hold the scenario's "
                                          r"rules\[0\] \(a rule file\)"):
        Runner(inside, source=source(inside, 3), out=tmp_path)
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(RunError, match="is a file"):
        Runner(room(), source=source(room(), 3), out=f)


def _footer(out: Path) -> dict:
    lines = (out / "trace.jsonl").read_text().splitlines()
    return json.loads(lines[-1])


def test_the_trace_says_why_the_run_stopped(tmp_path: Path, capsys) -> None:
    """Issue 21: a run that ended normally said "stopped: max-decisions" (its last slice's)."""
    from adapt.cli import main
    from adapt.traceview.html import build_payload
    from adapt.traceview.reader import Trace

    sc = room()
    res = Runner(sc, source=source(sc, 5), out=tmp_path / "done", outputs=QUIET).run()
    assert res.summary["stopped"] == "end-of-frames"
    footer = _footer(tmp_path / "done")
    assert footer["kind"] == "footer" and footer["stop_reason"] == "end-of-frames"
    assert main(["trace", "stats", str(tmp_path / "done" / "trace.jsonl")]) == 0
    assert "(stopped: end-of-frames)" in capsys.readouterr().out
    payload = build_payload(Trace(tmp_path / "done" / "trace.jsonl"))
    assert payload["footer"]["stop_reason"] == "end-of-frames"

    with pytest.raises(RuntimeError, match="cable"):
        Runner(sc, source=source(sc, 30, fail_at=4), out=tmp_path / "failed", outputs=QUIET).run()
    footer = _footer(tmp_path / "failed")
    assert footer["stop_reason"] == "error" and "cable" in footer["error"]
    assert main(["trace", "stats", str(tmp_path / "failed" / "trace.jsonl")]) == 0
    assert "(stopped: error: RuntimeError: " in capsys.readouterr().out

    halting = tmp_path / "halt.soar"
    halting.write_text("sp {halt (state <s> ^superstate nil) --> (halt)}\n")
    sc = replace(sc, rules=(replace(sc.rules[0], path=halting),))
    res = Runner(sc, source=source(sc, 5), out=tmp_path / "halted", outputs=QUIET).run()
    assert res.summary["stopped"] == "halt" and _footer(tmp_path / "halted")["stop_reason"] == "halt"


def test_every_listener_takes_one_typed_record_a_frame_before_the_imagination_steps(
        tmp_path: Path) -> None:
    from adapt.runner import FrameRecord

    sc = room()
    stranger = Ball("stranger", radius=0.12, position=(0.7, 1.4), color=(30, 200, 40))
    records: list[FrameRecord] = []
    times: list[float] = []

    class Keep:
        def frame(self, record: FrameRecord) -> None:
            records.append(record)
            times.append(runner.mirror.time)

    runner = Runner(sc, source=source(sc, 30, extra=[(6, stranger)]), out=tmp_path,
                    outputs=QUIET, listeners=(Keep(),))
    runner.run()
    frames = frames_of(tmp_path)
    assert [r.index for r in records] == [f["index"] for f in frames] == list(range(30))
    # as of the frame's time: the imagination has not stepped on yet
    assert all(abs(t - r.time) < 1e-9 for t, r in zip(times, records))
    last = records[-1]
    assert last.schemas == tuple(frames[-1]["schemas"])
    assert last.background is not None and last.background.frame == last.index
    (obj,) = last.objects
    tracked = last.tracked_object(obj.object)
    assert tracked is not None and tracked.imagined is not None
    assert [round(v, 4) for v in tracked.imagined] == frames[-1]["objects"][obj.object]["imagined"]
    spawned = [e for r in records for e in r.events if e.kind.value == "spawned"]
    assert len(spawned) == 1
    assert sum(r.subscene is not None for r in records) >= 2   # instantiated, then spawned


def test_the_baselines_are_a_keyed_collection_the_report_names_kalman_baseline(tmp_path: Path) -> None:
    from adapt.runner.baseline import report_key

    sc = room(objects="  objects:\n    - {name: ball, radius: 0.11, create: when_seen, "
                      "color: [230, 60, 30]}\n",
              extra="reality:\n  objects: [{name: ball, throw: {t: 0.3, x: 0, y: 1}}]\n")
    sc = replace(sc, goals=(replace(sc.goals[0], attributes=(("object", "ball"),)),))
    ball = Ball("ball", radius=0.11, position=(-0.4, 1.6), velocity=(0.4, 0.2),
                color=(230, 60, 30))
    runner = Runner(sc, source=source(sc, 30, extra=[(4, ball)]), out=tmp_path, outputs=QUIET)
    assert list(runner.baselines) == ["kalman", "mapaware"] and report_key("kalman") == "baseline"
    runner.run()
    frames = frames_of(tmp_path)
    followed = [f for f in frames if f["baseline"].get("ball")]
    assert followed and all(set(p) == {"horizon", "position"} for p in followed[-1]["baseline"]["ball"])
    # the map-aware baseline under its own name, on the same sightings and horizons
    assert all([p["horizon"] for p in f["mapaware"]["ball"]] ==
               [p["horizon"] for p in f["baseline"]["ball"]] for f in followed)
    assert "ball" in runner.baselines["kalman"].objects
    assert "ball" in runner.baselines["mapaware"].objects


def test_a_video_runs_as_long_as_its_frames_at_its_own_rate(tmp_path: Path) -> None:
    from adapt.runner import run_length
    from adapt.scenario import load_scenario

    root = Path(__file__).resolve().parents[2]
    sc = load_scenario(root / "scenarios" / "video-sequence.yaml")
    assert sc.run.frames == 300                      # 10 s at the run's default 30 frames/s
    length = run_length(sc)
    assert (length.fps, length.frames) == (15.0, 36)  # 36 images at 15 frames/s
    seen: list[tuple[int, int]] = []
    res = Runner(sc, out=tmp_path, outputs=QUIET,
                 on_progress=lambda p: seen.append((p.frame, p.frames))).run()
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["frames_planned"] == 36 == res.summary["frames"] == len(report["frames"])
    assert seen[-1] == (36, 36)
