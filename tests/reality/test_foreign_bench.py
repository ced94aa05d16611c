"""``bench/foreign.py``'s randomized realities are valid scenarios and vary as it says
(no PyBullet needed: only the scenarios are read)."""

from __future__ import annotations

import importlib.util
import math
from collections import Counter
from pathlib import Path
from types import ModuleType

import numpy as np

from adapt.scenario import BulletReality, Mount, loads_scenario

ROOT = Path(__file__).resolve().parents[2]


def _bench() -> ModuleType:
    path = ROOT / "bench" / "foreign.py"
    spec = importlib.util.spec_from_file_location("_bench_foreign", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_throw_is_a_valid_scenario_and_they_vary() -> None:
    bench = _bench()
    kinds: Counter[str] = Counter()
    moving, heights, in_view = 0, set(), 0
    for seed in range(1, 31):
        text, chosen = bench.scenario_text(seed, small=seed % 2 == 0)
        sc = loads_scenario(text, file=f"foreign-{seed}.yaml", base=ROOT / "scenarios")
        assert isinstance(sc.reality, BulletReality)
        kinds[chosen["camera"]] += 1
        assert (sc.mount.kind is Mount.ROBOT) == (chosen["camera"] == "robot")
        south = next(w for w in sc.scene.walls if w.name == "south")
        if chosen["camera"] == "outside":
            assert south.height <= 0.15 and sc.camera.position[1] < south.start[1]
            assert sc.camera.position[2] >= 2.0
        heights.add(round(south.height, 2))
        throw = sc.reality.object("ball").throw
        assert throw is not None
        moving += throw.time.low == 0.0
        r = sc.model("ball").ball.radius
        u, v = sc.camera.project(np.array([[throw.x.low, throw.y.low, r]]))[0]
        in_view += 0 <= u < sc.camera.width and 0 <= v < sc.camera.height
        assert sc.camera.width == (320 if seed % 2 == 0 else 640)
    assert set(kinds) == {"outside", "inside", "robot"} and min(kinds.values()) >= 9
    assert 5 <= moving <= 25 and len(heights) > 10
    assert in_view >= 25   # the throw is placed where the camera sees it


def test_the_same_seed_gives_the_same_throw() -> None:
    bench = _bench()
    assert bench.scenario_text(7)[0] == bench.scenario_text(7)[0]
    assert bench.scenario_text(7)[0] != bench.scenario_text(8)[0]


def test_the_figures_of_a_throw() -> None:
    bench = _bench()
    sc = loads_scenario(bench.scenario_text(3)[0], base=ROOT / "scenarios")
    r = sc.model("ball").ball.radius
    frames = [{"t": k / 30, "visible": k < 8, "truth": [0.1 * k, 0.0],
               "velocity": [1.0, 0.0] if k < 5 else [-0.8, 0.0],
               "observed": None if k in (2, 3) else [0.1 * k + (3 * r if k == 4 else 0.0), 0.0],
               "confident": k >= 6, "names": ["ball", "foreground-object-1"] if k == 7 else ["ball"],
               "aligned": k >= 2, "learned": k >= 5}
              for k in range(10)]
    summary = {"stage_ms": {"reality": 100.0, "perception": 20.0, "decisions": 5.0}}
    out = bench._figures(summary, frames, sc)
    # visible 0-7; tracked: not 2, 3 (unseen) nor 4 (3 radii off)
    assert out["coverage"] == 5 / 8 and out["seen_share"] == 6 / 8
    assert out["spurious"] == 1 and out["spurious_names"] == ["foreground-object-1"]
    # the first contact at frame 5; confident from frame 6 of 6..9
    assert out["confident_after_contact"] == 1.0
    assert math.isclose(out["loop_ms"], 25.0) and out["reality_ms"] == 100.0
    assert out["aligned_share"] == 0.8 and out["learned_share"] == 0.5
