"""One self-contained HTML page to browse a trace (``adapt trace html``).

The page holds everything inline -- styles, script and the trace data -- and
loads nothing from the network.  The trace is embedded compactly so that a
run of tens of thousands of decisions stays responsive:

* one short row per decision cycle for the timeline, which the page renders
  *virtualised* (only the rows in view exist in the DOM);
* working memory as *keyframes* (the whole WM every ``K`` cycles) plus each
  cycle's net *deltas* (the WMEs it added that were still there at its end,
  the timetags it removed that were there at its start); the page rebuilds WM
  at the selected cycle from the nearest keyframe before it;
* each cycle's firings (rule, bindings, matched timetags), retractions,
  candidates and preferences, impasse, ``(write)`` output, schema events and
  MMD frame, shown only for the selected cycle;
* the runner's records (``docs/runner.md``): the schema network whenever it
  changed (``net``: its nodes and port edges, drawn as a graph), each frame's
  MMD summary and regions (``fr``), and the learned look of the surfaces
  (``look``: small PNG previews; at most :data:`MAX_LOOKS` of them, spread over
  the run).  The page shows, for the selected cycle, the latest of each at or
  before it;
* the run's ``mmd.mp4`` when it is beside the trace (``video``: its address
  relative to the page, not embedded), shown at the selected frame; playing it
  moves the selection along.

A WME is embedded as ``[timetag, id, attr, value, flags]`` with the symbols
as Soar prints them; ``flags`` bit 0 is "acceptable" and bit 1 "the value is
an identifier".

Examples
--------
>>> compact_wme([231, {"id": "S1"}, "operator", {"id": "O7"}, True])
[231, 'S1', 'operator', 'O7', 3]
>>> page = render_page({"title": "t", "cycles": []})
>>> page.startswith("<!DOCTYPE html>") and "</script>" in page and "://" not in page
True
"""

from __future__ import annotations

import json
import os
import re
from importlib import resources
from typing import Any
from urllib.parse import quote

from adapt.files import write_atomic
from adapt.traceview.memory import LiveMemory
from adapt.traceview.reader import Trace
from adapt.traceview.show import impasse_text
from adapt.traceview.symbols import id_name, text_of

__all__ = ["compact_wme", "build_payload", "render_page", "write_html", "default_keyframe_interval",
           "MAX_LOOKS", "video_beside", "page_payload", "VIDEO_NAME"]

#: The run's video the page shows when it is beside the trace.
VIDEO_NAME = "mmd.mp4"

#: The most learned-look records a page embeds (spread evenly over the run, the last kept).
MAX_LOOKS = 48
#: Node fields of a ``network`` record the page shows as the node's details.
_NODE_DETAILS = ("object", "aligned", "pixel_error", "inliers", "regions", "unexpected",
                 "appearance", "learned", "message")


def compact_wme(wme: list[Any] | tuple[Any, ...]) -> list[Any]:
    """``[timetag, id, attr, value, flags]`` for the page."""
    tt, ident, attr, value, acceptable = wme
    flags = (1 if acceptable else 0) | (2 if id_name(value) is not None else 0)
    return [tt, text_of(ident), text_of(attr), text_of(value), flags]


def _bindings(bindings: dict[str, Any] | None) -> list[list[str]]:
    return [[var, text_of(val)] for var, val in (bindings or {}).items()
            if not var.startswith("<#")]  # hidden dot-path variables


def default_keyframe_interval(cycles: int) -> int:
    """Cycles between WM keyframes: about 40 keyframes, never closer than 50 cycles apart.

    >>> default_keyframe_interval(100), default_keyframe_interval(10_000)
    (50, 250)
    """
    return max(50, cycles // 40)


def _cycle_entry(cycle: int, records: list[dict[str, Any]], wm: LiveMemory | None) -> dict[str, Any]:
    entry: dict[str, Any] = {"c": cycle}
    firings: list[list[Any]] = []
    retractions: list[list[Any]] = []
    adds: dict[int, list[Any]] = {}  # net: added in this cycle and still there at its end
    removes: list[int] = []  # net: there at the start of the cycle, gone at its end
    writes: list[str] = []
    messages: list[str] = []
    phases: list[str] = []
    for record in records:
        kind = record["kind"]
        if kind == "phase":
            phase = str(record.get("phase"))
            phases.append(phase)
            for f in record.get("firings") or ():
                firings.append([phase, str(f.get("rule")), f.get("level", 0), f.get("support", ""),
                                _bindings(f.get("bindings")), list(f.get("wmes") or ())])
            for f in record.get("retractions") or ():
                retractions.append([phase, str(f.get("rule")), f.get("level", 0),
                                    list(f.get("wmes") or ())])
            if wm is not None:
                # adds first: a WME can be added and removed in one phase
                for a in record.get("adds") or ():
                    adds[a[0]] = compact_wme(a)
                for t in record.get("removes") or ():
                    if adds.pop(t, None) is None:
                        removes.append(t)
                wm.apply(record)
            if record.get("writes"):
                writes.append(str(record["writes"]))
            messages.extend(str(m) for m in record.get("messages") or ())
        elif kind == "decision":
            entry["lv"] = int(record.get("level") or 0)
            selected = record.get("selected")
            if selected:
                entry["op"] = [text_of(selected.get("id")), text_of(selected.get("name"))]
            impasse = record.get("impasse")
            if impasse:
                entry["imp"] = [impasse_text(impasse), text_of(impasse.get("state")),
                                [text_of(i) for i in impasse.get("items") or ()]]
            if record.get("candidates"):
                entry["cand"] = [
                    [text_of(c.get("id")), text_of(c.get("name")),
                     [[k, None if r is None else text_of(r)] for k, r in c.get("preferences") or ()]]
                    for c in record["candidates"]
                ]
            if record.get("removed_goals"):
                entry["rg"] = [text_of(g) for g in record["removed_goals"]]
            if record.get("mmd_frame"):
                entry["frame"] = str(record["mmd_frame"])
        elif kind == "frame":
            entry["fr"] = _frame_entry(record)
        elif kind == "network":
            entry["net"] = _network_entry(record)
        elif kind == "appearance":
            entry["look"] = _look_entry(record)
        elif kind == "schema":
            entry.setdefault("schema", []).append(
                [str(record.get("event", "")), str(record.get("schema", "")),
                 json.dumps(record.get("data")) if record.get("data") is not None else ""])
        if kind in ("phase", "schema") and record.get("mmd_frame"):
            entry["frame"] = str(record["mmd_frame"])
    for key, value in (("f", firings), ("r", retractions), ("a", list(adds.values())), ("x", removes),
                       ("w", "".join(writes)), ("m", messages), ("p", phases)):
        if value:
            entry[key] = value
    return entry


def _number(value: Any, digits: int = 4) -> Any:
    return round(value, digits) if isinstance(value, float) else value


def _frame_entry(record: dict[str, Any]) -> list[Any]:
    """``[frame, t, unexpected, mmd or None, regions]``; a region is
    ``[id, x, y, w, h, area, expected, owner, age]``."""
    mmd = record.get("mmd")
    regions = []
    for r in record.get("regions") or ():
        box = list(r.get("bbox") or (0, 0, 0, 0))[:4]
        regions.append([r.get("id"), *box, r.get("area"), bool(r.get("expected")),
                        r.get("owner"), r.get("age")])
    return [record.get("frame"), _number(record.get("t")), record.get("unexpected_regions", 0),
            {k: _number(v) for k, v in mmd.items()} if isinstance(mmd, dict) else None, regions]


def _network_entry(record: dict[str, Any]) -> dict[str, Any]:
    """``{"frame", "nodes": [[name, type, kind, status, origin, details]], "edges": [[a, b, port]]}``."""
    nodes = []
    for n in record.get("nodes") or ():
        details = {k: _number(n[k]) for k in _NODE_DETAILS if n.get(k) not in (None, "")}
        nodes.append([str(n.get("name", "")), str(n.get("type", "")), str(n.get("kind", "")),
                      str(n.get("status", "")), str(n.get("origin", "")), details])
    edges = [[str(e.get("from", "")), str(e.get("to", "")), str(e.get("port", ""))]
             for e in record.get("edges") or ()]
    return {"frame": record.get("frame"), "nodes": nodes, "edges": edges}


def _look_entry(record: dict[str, Any]) -> dict[str, Any]:
    """``{"frame", "stage", "passes", "ms", "surfaces": [[name, coverage, w, h, image]]}``
    (an image that is not a PNG data URI is left out: the page loads nothing else)."""
    surfaces = []
    for s in record.get("surfaces") or ():
        image = s.get("image")
        ok = isinstance(image, str) and image.startswith("data:image/png;base64,")
        size = list(s.get("size") or (0, 0))[:2]
        surfaces.append([str(s.get("name", "")), _number(s.get("coverage"), 3), *size,
                         image if ok else None])
    return {"frame": record.get("frame"), "stage": record.get("stage"),
            "passes": record.get("passes"), "ms": record.get("ms"), "surfaces": surfaces}


#: Record kinds the runner writes (``docs/runner.md``), apart from the engine's.
_RUN_KINDS = frozenset({"frame", "network", "appearance", "schema", "summary"})


def _thin_looks(cycles: list[dict[str, Any]]) -> None:
    """Keep at most :data:`MAX_LOOKS` learned-look entries, evenly spread, the last kept."""
    at = [i for i, c in enumerate(cycles) if "look" in c]
    if len(at) <= MAX_LOOKS:
        return
    step = (len(at) - 1) / (MAX_LOOKS - 1)
    keep = {at[round(k * step)] for k in range(MAX_LOOKS)}
    for i in at:
        if i not in keep:
            del cycles[i]["look"]


def build_payload(trace: Trace, keyframe_every: int | None = None) -> dict[str, Any]:
    """The page's data: header, footer, per-cycle entries and WM keyframes (streaming the trace)."""
    wm = LiveMemory() if trace.header.level >= 4 else None
    cycles: list[dict[str, Any]] = []
    keyframes: dict[str, list[list[Any]]] = {}
    initial = trace.initial_wmes() if wm is not None else []
    if wm is not None:
        wm.apply({"adds": initial})
    def add(cycle: int, records: list[dict[str, Any]]) -> None:
        nonlocal initial
        entry = _cycle_entry(cycle, records, wm)
        if initial:  # the WMEs from before the first phase join the first cycle's delta
            kept = [compact_wme(w) for w in initial if wm.get(w[0]) is not None]  # type: ignore[union-attr]
            gone = {w[0] for w in initial} - {w[0] for w in kept}
            entry["a"] = kept + entry.get("a", [])
            entry["x"] = [t for t in entry.get("x", []) if t not in gone]
            initial = []
        cycles.append(entry)

    pending: tuple[int, list[dict[str, Any]]] | None = None
    for cycle, records in trace.cycles():
        # The runner writes its records (frame, network, schema events, the look)
        # between two calls of the agent, which stops after a decision phase: they
        # break a cycle in two.  They join the cycle they were written in, and so
        # does the rest of that cycle.
        if pending is not None and (cycle == pending[0]
                                    or all(r.get("kind") in _RUN_KINDS for r in records)):
            pending[1].extend(records)
            continue
        if pending is not None:
            add(*pending)
        pending = (cycle, list(records))
    if pending is not None:
        add(*pending)
    _thin_looks(cycles)
    every = keyframe_every or default_keyframe_interval(len(cycles))
    if wm is not None:
        # The length is known only at the end: replay the compact deltas for the keyframes.
        live: dict[int, list[Any]] = {}
        for index, entry in enumerate(cycles):
            for t in entry.get("x", ()):
                live.pop(t, None)
            for a in entry.get("a", ()):
                live[a[0]] = a
            if (index + 1) % every == 0:
                keyframes[str(index)] = sorted(live.values(), key=lambda w: w[0])
    else:
        every = 0
    header = {k: v for k, v in trace.header.raw.items()}
    return {
        "title": os.path.basename(trace.path),
        "header": header,
        "footer": trace.footer(),
        "notices": list(trace.notices),
        "level": trace.header.level,
        "K": every or 0,
        "keyframes": keyframes,
        "cycles": cycles,
    }


def _asset(name: str) -> str:
    return resources.files("adapt.traceview").joinpath(name).read_text(encoding="utf-8")


def _script_safe(text: str) -> str:
    return text.replace("</", "<\\/").replace("<!--", "<\\!--")


def render_page(payload: dict[str, Any]) -> str:
    """The HTML page for a payload of :func:`build_payload`."""
    data = _script_safe(json.dumps(payload, separators=(",", ":"), ensure_ascii=False))
    title = str(payload.get("title", "trace")).replace("&", "&amp;").replace("<", "&lt;")
    page = _asset("viewer.html")
    return (page.replace("{{TITLE}}", title)
                .replace("/*{{CSS}}*/", _asset("viewer.css"))
                .replace("/*{{DATA}}*/", data)
                .replace("/*{{JS}}*/", _script_safe(_asset("viewer.js"))))


def video_beside(trace_path: str, page: str) -> dict[str, Any] | None:
    """The run's ``mmd.mp4`` beside the trace, as the page refers to it: its address
    relative to the page and its frame rate (from ``report.json`` beside it, when there),
    or None when there is no video.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> run = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (run / "mmd.mp4").write_bytes(b"...")
    >>> _ = (run / "report.json").write_text('{"scenario": "s.yaml", "seed": 1, "fps": 30.0, "frames": [')
    >>> video_beside(str(run / "trace.jsonl"), str(run / "view" / "t.html"))
    {'src': '../mmd.mp4', 'fps': 30.0}
    """
    folder = os.path.dirname(os.path.abspath(trace_path))
    video = os.path.join(folder, VIDEO_NAME)
    if not os.path.isfile(video):
        return None
    fps: float | None = None
    try:
        with open(os.path.join(folder, "report.json"), "rb") as f:
            head = f.read(4096).decode("utf-8", "replace")  # the header comes first
        m = re.search(r'"fps":\s*([0-9.eE+-]+)', head)
        fps = float(m.group(1)) if m else None
    except (OSError, ValueError):
        fps = None
    rel = os.path.relpath(video, os.path.dirname(os.path.abspath(page)))
    return {"src": quote(rel.replace(os.sep, "/")), "fps": fps}


def page_payload(trace: Trace, page: str) -> dict[str, Any]:
    """:func:`build_payload` for a page written at ``page``: with the run's ``mmd.mp4`` when
    it is beside the trace (:func:`video_beside`)."""
    payload = build_payload(trace)
    video = video_beside(trace.path, page)
    if video is not None:
        payload["video"] = video
    return payload


def write_html(trace: Trace, out: str | None = None) -> str:
    """Render ``trace`` into ``out`` (default: beside it, ``.html``) atomically; return the path.
    A run's ``mmd.mp4`` beside the trace is shown in the page, at the selected frame."""
    target = out or os.path.splitext(trace.path)[0] + ".html"
    text = render_page(page_payload(trace, target))
    write_atomic(target, text.encode("utf-8"))
    return target
