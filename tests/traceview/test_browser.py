"""The HTML viewer driven in headless Chromium, as a person would use it.

Expected values come from the Python side (:func:`memory_at`, the trace's
own records), never from the page's file text.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from adapt.traceview.html import write_html
from adapt.traceview.memory import memory_at
from adapt.traceview.reader import Trace
from adapt.traceview.symbols import text_of

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(not os.path.exists(CHROMIUM),
                       reason=f"{CHROMIUM} is missing (apt-get install chromium)"),
]


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


@pytest.fixture
def page(browser):
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.errors = []  # type: ignore[attr-defined]
    pg.requests = []  # type: ignore[attr-defined]
    pg.on("pageerror", lambda e: pg.errors.append(str(e)))
    pg.on("console", lambda m: pg.errors.append(m.text) if m.type == "error" else None)
    pg.on("request", lambda r: pg.requests.append(r.url))
    yield pg
    pg.close()


def open_page(page, path: Path) -> None:
    page.goto(path.as_uri())
    page.wait_for_selector("body[data-ready='1']", timeout=30_000)


def select(page, d: int) -> None:
    page.locator(f"#timeline .row[data-d='{d}']").click()
    page.wait_for_selector(f"body[data-selected='{d}']", timeout=10_000)


def test_click_through_a_run(page, counter_trace, tmp_path) -> None:
    trace = Trace(counter_trace(40, tie_every=7, schema_every=5, frames=True))
    html = Path(write_html(trace, str(tmp_path / "view.html")))
    open_page(page, html)

    # the timeline lists the decisions, in order, as Soar prints them
    rows = page.locator("#timeline .row")
    assert rows.count() >= 30
    first = rows.nth(0)
    assert (first.locator(".d").inner_text(), first.locator(".what").inner_text()) == (
        "1", "O: O1 (count)")
    assert page.locator("#timeline .row[data-d='7'] .what").inner_text() == "==>S: S2 (operator tie)"

    # decision 12: working memory at 12, found after expanding the tree
    select(page, 12)
    wm = memory_at(trace, 12)
    count = text_of(wm.find("S1", "count")[0][3])
    op = text_of(next(w for w in wm.find("S1", "operator") if not w[4])[3])
    tree = page.locator("#wm-tree")
    assert f"^count {count}" in tree.inner_text()
    op_node = page.locator(f"#wm-tree .wm-node[data-id='{op}']")
    assert "^name" not in op_node.inner_text()
    op_node.locator(":scope > .wm-head").click()
    assert "^name count" in op_node.inner_text()
    assert f"({len(wm)} WMEs at decision 12)" in page.locator("#wm-size").inner_text()

    # the firings of 12, with their bindings, as the trace recorded them
    fired = [f for _, recs in trace.cycles(12, 12) for r in recs for f in r.get("firings") or ()]
    shown = page.locator("#firings .firing:not(.retraction)")
    assert shown.count() == len(fired)
    for i, f in enumerate(fired):
        assert shown.nth(i).get_attribute("data-rule") == f["rule"]
        text = shown.nth(i).locator(".bindings").inner_text()
        for var, value in f["bindings"].items():
            assert f"{var} = {text_of(value)}" in text

    # the impasse at 7: summary, goal stack with the substate, its WMEs
    select(page, 7)
    assert page.locator("#decision-summary .big").inner_text() == "==>S: S2 (operator tie)"
    goals = page.locator("#goals").inner_text()
    assert "impasse: operator tie" in goals and "S2 (tie/operator)" in goals
    page.fill("#wm-root", "S2")
    page.press("#wm-root", "Enter")
    assert "^impasse tie" in page.locator("#wm-tree").inner_text()

    # schema events and the MMD frame when present
    select(page, 10)
    assert page.locator("#schema-events .schema-event").inner_text().startswith("reach activated")
    assert page.locator("#mmd-frame img").evaluate("img => img.complete && img.naturalWidth") == 1

    # keyboard: the next decision
    page.locator("#timeline").focus()
    page.keyboard.press("ArrowDown")
    page.wait_for_selector("body[data-selected='11']")

    shot = tmp_path / "viewer.png"
    page.screenshot(path=str(shot))
    assert_not_blank(shot)
    assert page.errors == []  # type: ignore[attr-defined]
    assert all(u.startswith(("file:", "data:")) for u in page.requests)  # type: ignore[attr-defined]


def test_ten_thousand_decisions_stay_responsive(page, counter_trace, tmp_path) -> None:
    trace = Trace(counter_trace(10_000, tie_every=50, schema_every=100))
    html = Path(write_html(trace, str(tmp_path / "big.html")))
    start = time.perf_counter()
    open_page(page, html)
    load_s = time.perf_counter() - start
    in_dom = page.locator("#timeline .row").count()
    page.fill("#goto", "7000")
    page.press("#goto", "Enter")
    page.wait_for_selector("body[data-selected='7000']")
    start = time.perf_counter()
    select(page, 7005)
    click_s = time.perf_counter() - start
    count = text_of(memory_at(trace, 7005).find("S1", "count")[0][3])
    assert f"^count {count}" in page.locator("#wm-tree").inner_text()
    print(f"\n10k-decision page: {html.stat().st_size / 1e6:.1f} MB, load {load_s:.2f} s, "
          f"click {click_s * 1000:.0f} ms ({page.get_attribute('body', 'data-render-ms')} ms "
          f"rendering), {in_dom} timeline rows in the DOM")
    assert in_dom < 200  # virtualised: not one node per decision
    assert load_s < 20 and click_s < 3
    assert page.errors == []  # type: ignore[attr-defined]


def assert_not_blank(path: Path) -> None:
    import cv2
    import numpy as np

    image = cv2.imread(str(path))
    assert image is not None and image.shape[0] > 500 and image.shape[1] > 1000
    colours = np.unique(image.reshape(-1, 3)[::97], axis=0)
    assert float(image.std()) > 20 and len(colours) > 50


@pytest.fixture(scope="module")
def run_page(tmp_path_factory) -> tuple[Trace, Path]:
    from .test_html import run_trace

    folder = tmp_path_factory.mktemp("run")
    trace = Trace(run_trace(folder))
    return trace, Path(write_html(trace, str(folder / "view.html")))


def go(page, d: int) -> None:
    """Select decision ``d`` through the "go to" box (its row may be out of view)."""
    page.fill("#goto", str(d))
    page.press("#goto", "Enter")
    page.wait_for_selector(f"body[data-selected='{d}']", timeout=10_000)


def test_the_run_panels_follow_the_timeline(page, run_page) -> None:
    trace, html = run_page
    records = list(trace.records())
    open_page(page, html)
    assert page.locator("#run-panels").is_visible() and page.locator("#look-panel").is_visible()

    # before the ball is seen: the Scene Background alone
    spawn = next(r for r in records if r["kind"] == "schema" and r["event"] == "spawned")
    early = next(r for r in records if r["kind"] == "frame" and r["frame"] == 5)
    go(page, early["d"])
    graph = page.locator("#network-graph")
    assert graph.locator(".node").count() == 1
    assert graph.locator(".node").get_attribute("data-name") == "background"
    assert page.locator("#mmd-summary").get_attribute("data-frame") == "5"
    shown = page.locator("#mmd-summary [data-key='pixel error'] b").inner_text()
    assert shown == f"{early['mmd']['pixel_error']:.2f}"

    # after the spawn: the ball's schema, spawned bottom-up, fed regions by the background
    last = [r for r in records if r["kind"] == "decision"][-1]["d"]
    go(page, last)
    ball = graph.locator(".node[data-name='ball']")
    assert ball.count() == 1 and "bottom-up" in (ball.get_attribute("class") or "")
    status = [r["data"]["status"] for r in records if r["kind"] == "schema"
              and r["event"] == "status" and r["schema"] == "ball"]
    assert ball.get_attribute("data-status") == (status[-1] if status else "waiting")
    edge = graph.locator(".edge")
    assert (edge.get_attribute("data-from"), edge.get_attribute("data-to"),
            edge.get_attribute("data-port")) == ("background", "ball", "regions")
    assert spawn["data"]["type"] == "foreground-object"
    frames = [r for r in records if r["kind"] == "frame"]
    regions = page.locator("#mmd-regions tr.expected td")
    assert regions.nth(4).inner_text() == "ball" and frames[-1]["regions"][0]["owner"] == "ball"

    # the learned look: one picture per surface, loaded from the page itself
    look = next(r for r in records if r["kind"] == "appearance")
    figs = page.locator("#look-grid figure")
    assert figs.count() == len(look["surfaces"])
    floor = page.locator("#look-grid figure[data-surface='floor']")
    assert f"{round(100 * look['surfaces'][0]['coverage'])}% seen" in floor.inner_text()
    assert floor.locator("img").evaluate("img => img.complete && img.naturalWidth") > 0

    # the chart takes you to a frame
    box = page.locator("#mmd-chart svg").bounding_box()
    page.mouse.click(box["x"] + 2, box["y"] + box["height"] / 2)
    page.wait_for_selector("#mmd-summary[data-frame='0']")
    assert page.locator("#look-grid .empty").inner_text() == "nothing learned yet"

    shot = html.parent / "run.png"
    page.screenshot(path=str(shot))
    assert_not_blank(shot)
    assert page.errors == []  # type: ignore[attr-defined]
    assert all(u.startswith(("file:", "data:")) for u in page.requests)  # type: ignore[attr-defined]
