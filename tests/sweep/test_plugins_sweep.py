"""A sweep of a scenario with plugins: every worker process imports them when it reads the
scenario, so its runs use the plugin's reality kind and schema type."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("distributed")

from adapt.sweep.plan import make_plan  # noqa: E402
from adapt.sweep.session import run_sweep  # noqa: E402

PLUGIN = '''
import numpy as np
import adapt


class Flat:
    def __init__(self, size, fps, n, level):
        self.size, self.fps, self.length, self.level = size, fps, n, level

    def __iter__(self):
        w, h = self.size
        for i in range(self.length):
            yield adapt.Frame(i, i / self.fps, np.full((h, w, 3), self.level, np.uint8))

    def close(self):
        pass


adapt.REALITIES.register(adapt.RealityType(
    "sweep-flat", "flat frames", parameters=(
        adapt.Parameter("level", int, 80, "grey level", low=0, high=255),),
    open=lambda r, sc, streams: Flat((sc.camera.width, sc.camera.height), 10.0, 6,
                                     r.get("level"))))
'''

SCENARIO = """plugins: [flat.py]
camera: {fx: 130, fy: 130, cx: 79.5, cy: 59.5, width: 160, height: 120,
         position: [0.0, -1.0, 1.5], look_at: [0.0, 1.2, 0.0]}
world: {}
reality: {kind: sweep-flat, level: 60}
outputs: {video: false, figures: false, trace: false}
"""


def test_a_sweep_runs_a_plugin_reality_on_two_workers(two_workers: Any, tmp_path: Path) -> None:
    folder = tmp_path / "scenario"
    folder.mkdir()
    (folder / "flat.py").write_text(PLUGIN)
    (folder / "s.yaml").write_text(SCENARIO)
    plan = make_plan(folder / "s.yaml", seeds="1-4", sets=["reality.level=40,200"], max_frames=3)
    out = run_sweep(plan, tmp_path / "out", client=two_workers.client, plots=False)
    assert (out.ok, out.failed) == (8, 0)
    recs = [json.loads(t) for t in (tmp_path / "out" / "runs.jsonl").read_text().splitlines()]
    assert all(r["summary"]["frames"] == 3 for r in recs)
    assert len({r["worker"]["pid"] for r in recs}) == 2  # both workers imported the plugin
