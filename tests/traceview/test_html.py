"""The page's data (keyframes + deltas rebuild WM exactly; the runner's records: the
schema network, each frame's MMD, the learned look) and ``adapt trace html``."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.traceview.html import build_payload, compact_wme, render_page
from adapt.traceview.memory import memory_at
from adapt.traceview.reader import Trace


def replay(payload: dict, index: int) -> set[tuple]:
    """What the page's script does: nearest keyframe at or before ``index``, then deltas."""
    k = (index + 1) // payload["K"] * payload["K"] - 1
    live = {w[0]: w for w in payload["keyframes"].get(str(k), [])} if k >= 0 else {}
    for entry in payload["cycles"][k + 1 : index + 1]:
        for t in entry.get("x", ()):
            live.pop(t)
        for w in entry.get("a", ()):
            live[w[0]] = w
    return {tuple(w) for w in live.values()}


def test_keyframes_and_deltas_rebuild_memory(counter_trace) -> None:
    trace = Trace(counter_trace(130, tie_every=9))
    payload = build_payload(trace, keyframe_every=50)
    assert sorted(payload["keyframes"], key=int) == ["49", "99"]
    for index in (0, 6, 8, 48, 49, 50, 63, 99, 129):
        d = payload["cycles"][index]["c"]
        expected = {tuple(compact_wme(w)) for w in memory_at(trace, d)}
        assert replay(payload, index) == expected, d


def test_cycle_entries(counter_trace) -> None:
    payload = build_payload(Trace(counter_trace(8, tie_every=7, schema_every=4, frames=True)))
    c7 = payload["cycles"][6]
    assert c7["c"] == 7 and c7["imp"] == ["operator tie", "S2", ["O7", "O8"]]
    assert [f[1] for f in c7["f"]] == ["propose*count", "propose*skip", "tie*prefer-count"]
    assert payload["cycles"][3]["schema"][0][:2] == ["activated", "reach"]
    assert payload["cycles"][7]["rg"] == ["S2"] and payload["cycles"][7]["frame"].startswith("data:")


def test_page_is_self_contained_and_script_safe() -> None:
    page = render_page({"title": "x</script><b>", "cycles": [{"c": 1, "w": "</script>"}]})
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert page.count("</script>") == 2  # the data block and the script, nothing injected
    data = page.split('id="trace-data">', 1)[1].split("</script>", 1)[0]
    assert json.loads(data)["cycles"][0]["w"] == "</script>"


def test_cli_writes_next_to_the_trace(capsys, counter_trace, tmp_path) -> None:
    path = counter_trace(5, name="run.jsonl")
    assert main(["trace", "html", str(path)]) == 0
    out = tmp_path / "run.html"
    assert capsys.readouterr().out.strip() == str(out)
    assert out.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")
    assert main(["trace", "html", str(path), "--out", str(tmp_path / "other.html")]) == 0
    assert (tmp_path / "other.html").exists()
    assert not list(tmp_path.glob(".*.tmp"))


# -- the runner's records: the schema network, the frames' MMD, the learned look ---------------

def run_trace(folder: Path, frames: int = 20) -> Path:
    """The trace of a short run of the shipped video with the mirror's rules (the look is
    learned, the ball spawns a schema at frame 14)."""
    from adapt.runner import Runner
    from adapt.scenario import OutputSettings, load_scenario

    root = Path(__file__).resolve().parents[2]
    sc = load_scenario(root / "scenarios" / "video-sequence.yaml",
                       [f"run.max_frames={frames}", "goals=[{name: track, object: ball}]",
                        f"rules=[{root / 'rules' / 'mirror' / 'perception.soar'}]"])
    Runner(sc, out=folder, outputs=OutputSettings(video=False, figures=False)).run()
    return folder / "trace.jsonl"


@pytest.fixture(scope="module")
def run_payload(tmp_path_factory: pytest.TempPathFactory) -> tuple[Trace, dict]:
    trace = Trace(run_trace(tmp_path_factory.mktemp("run")))
    return trace, build_payload(trace)


def test_runner_records_join_the_cycle_they_were_written_in(run_payload) -> None:
    trace, payload = run_payload
    numbers = [c["c"] for c in payload["cycles"]]
    assert numbers == sorted(set(numbers))  # one entry per cycle, in order
    decisions = [r for r in trace.records() if r["kind"] == "decision"]
    assert len(numbers) == len({r["d"] for r in decisions})
    frames = [r["frame"] for r in trace.records() if r["kind"] == "frame"]
    shown = [c["fr"][0] for c in payload["cycles"] if "fr" in c]
    assert shown == frames  # every frame, once, in order


def test_the_network_frames_and_looks_are_in_the_payload(run_payload) -> None:
    trace, payload = run_payload
    records = list(trace.records())
    nets = [c["net"] for c in payload["cycles"] if "net" in c]
    last = [r for r in records if r["kind"] == "network"][-1]
    assert [n[0] for n in nets[-1]["nodes"]] == [n["name"] for n in last["nodes"]]
    ball = next(n for n in nets[-1]["nodes"] if n[0] == "ball")
    assert ball[1:3] == ["foreground-object", "perceptual"] and ball[4] == "bottom-up"
    assert nets[-1]["edges"] == [["background", "ball", "regions"]]
    bg = next(n for n in nets[-1]["nodes"] if n[0] == "background")
    assert bg[5]["appearance"] == "learned" and bg[5]["aligned"] is True
    frame = next(r for r in records if r["kind"] == "frame" and r["regions"])
    entry = next(c["fr"] for c in payload["cycles"] if c.get("fr", [None])[0] == frame["frame"])
    assert entry[3]["pixel_error"] == frame["mmd"]["pixel_error"]
    assert entry[4][0][:6] == [frame["regions"][0]["id"], *frame["regions"][0]["bbox"],
                               frame["regions"][0]["area"]]
    looks = [c["look"] for c in payload["cycles"] if "look" in c]
    assert looks and looks[0]["stage"] == "learned"
    names = [s[0] for s in looks[0]["surfaces"]]
    assert names[:2] == ["floor", "north"]
    assert all(s[4].startswith("data:image/png;base64,") for s in looks[0]["surfaces"])


def test_a_long_run_embeds_a_bounded_number_of_looks(counter_trace) -> None:
    from adapt.traceview.html import MAX_LOOKS

    path = counter_trace(300)
    lines = path.read_text().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        out.append(line)
        r = json.loads(line)
        if r.get("kind") == "decision":
            out.append(json.dumps({"kind": "appearance", "d": r["d"], "frame": r["d"],
                                   "stage": "learned", "passes": r["d"], "ms": 1.0,
                                   "surfaces": [{"name": "floor", "coverage": 0.5,
                                                 "size": [4, 4],
                                                 "image": "https://example.org/x.png"}]}))
    path.write_text("\n".join(out) + "\n")
    payload = build_payload(Trace(path))
    looks = [c for c in payload["cycles"] if "look" in c]
    assert len(looks) == MAX_LOOKS and looks[-1]["c"] == payload["cycles"][-1]["c"]
    assert looks[0]["look"]["surfaces"][0][4] is None  # only data URIs reach the page
    assert "example.org" not in render_page(payload)
