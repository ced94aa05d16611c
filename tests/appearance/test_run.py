"""`adapt run` with appearance learning: the run folder's appearance/, the trace's
records, figures/appearance.png; a later scenario reusing the look (world.appearance);
bad folders and outputs that would replace an input."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from adapt.cli import main
from adapt.errors import OutputError, ScenarioError
from adapt.runner import Runner
from adapt.scenario import OutputSettings, load_scenario

from . import checks as C

RULES = C.ROOT / "rules" / "mirror" / "perception.soar"


def video_scenario(tmp_path: Path, extra: str = "", frames: int = 20, name: str = "video.yaml"
                   ) -> Path:
    """The shipped video scenario, written into ``tmp_path`` with absolute paths, a goal
    to track the ball and the mirror's rules."""
    text = C.VIDEO.read_text(encoding="utf-8")
    video = C.VIDEO.parent / "video"
    text = text.replace("path: video/frames/*.jpg", f"path: {video}/frames/*.jpg")
    text = text.replace("ground_truth: video/truth.csv", f"ground_truth: {video}/truth.csv")
    text += (f"\ngoals: [{{name: track, object: ball}}]\nrules: [{RULES}]\n"
             f"run: {{max_frames: {frames}}}\n")
    if extra:
        text = text.replace("world:\n", "world:\n" + extra, 1)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def first_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    tmp = tmp_path_factory.mktemp("look")
    out = tmp / "run"
    assert main(["run", str(video_scenario(tmp, frames=22)), "--out", str(out), "--quiet",
                 "--no-video"]) == 0
    return out


def test_a_run_writes_the_look_it_learned(first_run: Path) -> None:
    index = json.loads((first_run / "appearance" / "index.json").read_text())
    names = [e["name"] for e in index["surfaces"]]
    assert names[:2] == ["floor", "north"] and "sky/+y" in names
    floor = index["surfaces"][0]
    x0, y0, x1, y1 = floor["extent"]  # what is seen of the floor, with a margin, cut to it
    assert (x0, x1, y1) == (-2.5, 2.5, 3.0) and -1.0 < y0 < 0.5 and floor["coverage"] > 0.3
    image = cv2.imread(str(first_run / "appearance" / floor["image"]))
    mask = cv2.imread(str(first_run / "appearance" / floor["mask"]), cv2.IMREAD_GRAYSCALE)
    assert image.shape[:2] == mask.shape and set(np.unique(mask)) == {0, 255}
    assert not list((first_run / "appearance").glob(".*"))  # no temporary files left
    # the ball went through the view and was tracked, but is not on the learned floor
    img = image.astype(int)
    red = (img[:, :, 2] - np.maximum(img[:, :, 0], img[:, :, 1]) > 60) & (mask > 0)
    assert not red.any()


def test_the_trace_and_the_figures_show_the_look(first_run: Path) -> None:
    records = [json.loads(line) for line in (first_run / "trace.jsonl").open()]
    looks = [r for r in records if r["kind"] == "appearance"]
    assert looks and looks[0]["stage"] == "learned"
    assert all(s["image"].startswith("data:image/png;base64,") for s in looks[0]["surfaces"])
    nets = [r for r in records if r["kind"] == "network"]
    bg = next(n for n in nets[-1]["nodes"] if n["type"] == "scene-background")
    assert bg["appearance"] == "learned" and bg["learned"] >= 5
    frames = [r for r in records if r["kind"] == "frame"]
    first = next(i for i, f in enumerate(frames) if f["mmd"]["aligned"])
    assert first <= 3 and all(f["mmd"]["aligned"] for f in frames[first:])
    fig = cv2.imread(str(first_run / "figures" / "appearance.png"))
    assert fig is not None and fig.shape[1] > 900
    summary = json.loads((first_run / "report.json").read_text())["summary"]
    assert summary["events"].get("spawned") == 1  # the ball, and nothing else


def test_a_later_scenario_starts_from_the_saved_look(first_run: Path, tmp_path: Path) -> None:
    folder = first_run / "appearance"
    path = video_scenario(tmp_path, extra=f"  appearance: {folder}\n", frames=12)
    sc = load_scenario(path)
    assert sc.appearance == folder
    res = Runner(sc, out=tmp_path / "again", outputs=OutputSettings(video=False, figures=False)).run()
    frames = json.loads((tmp_path / "again" / "report.json").read_text())["frames"]
    # frame 0 is before the rules put the schema in place; then no structure stage
    assert all(f["mmd"]["aligned"] for f in frames[1:])
    assert [f["unexpected_regions"] for f in frames[-4:]] == [0, 0, 0, 0]
    # refined once (every 10 frames: at frame 10), so written again
    assert res.error is None and (tmp_path / "again" / "appearance" / "index.json").exists()


def test_world_appearance_must_name_a_saved_look(tmp_path: Path) -> None:
    missing = video_scenario(tmp_path, extra="  appearance: nowhere\n")
    with pytest.raises(ScenarioError, match=r"video\.yaml:\d+:\d+: world\.appearance: "
                                            r"appearance folder .*nowhere' not found"):
        load_scenario(missing)
    (tmp_path / "empty").mkdir()
    empty = video_scenario(tmp_path, extra="  appearance: empty\n", name="empty.yaml")
    with pytest.raises(ScenarioError, match="has no index.json"):
        load_scenario(empty)
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "index.json").write_text("[1, 2]")
    bad = video_scenario(tmp_path, extra="  appearance: bad\n", name="bad.yaml")
    sc = load_scenario(bad)  # the file exists; what it says is read when the run starts
    with pytest.raises(ScenarioError, match=r"world\.appearance: .*not an appearance index"):
        Runner(sc)


def test_a_run_never_writes_over_the_look_it_starts_from(first_run: Path, tmp_path: Path) -> None:
    path = video_scenario(tmp_path, extra=f"  appearance: {first_run / 'appearance'}\n")
    with pytest.raises(OutputError, match="appearance output .* is the scenario's world.appearance"
                                          ".* never replaces an input"):
        Runner(load_scenario(path), out=first_run)
