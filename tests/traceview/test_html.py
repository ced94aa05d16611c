"""The page's data (keyframes + deltas rebuild WM exactly) and ``adapt trace html``."""

from __future__ import annotations

import json
import re

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
