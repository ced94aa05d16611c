"""``adapt check`` and ``adapt run`` agree on every number a scenario may give (issue 21).

For every numeric key of ``docs/scenario.md`` (each has its bound in
:data:`adapt.scenario.bounds.BOUNDS`, and a docs test keeps the two in step),
each awkward value -- 0, -1, 1e-300, 1e300, NaN, infinity and the key's bounds
and one step either side of them -- is given with ``--set`` to a small scenario
(the main bouncing-ball scenario at 80x60 pixels with one obstacle, its
perception rules and a second ball at the start; the video scenario for a
video's keys).  ``check`` and ``run
--max-frames 2`` must both accept it or both refuse it, neither may exit 70
(an internal error), and a value outside its bound is refused by both.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from adapt.scenario.bounds import BOUNDS, Bound

from .harness import ROOT, Outcome, check_contract, drive

SPECIAL = [0, -1, 1e-300, 1e300, math.nan, math.inf]

#: Vectors a base scenario does not give, with values the reader takes.
VECTORS: dict[str, list[Any]] = {
    "reality.camera_offset": [0.0, 0.0, 0.0],
    "reality.camera_offset_deg": [0.0, 0.0, 0.0],
    "reality.appearance.texture_phase": [0.0, 0.0],
    "reality.appearance.tint": [1.0, 1.0, 1.0],
    "reality.objects[i].position": [-0.8, 0.6],
    "reality.objects[i].velocity": [0.0, 0.0],
    "world.robot.size": [0.5, 0.4],
    "camera.distortion": [0.0, 0.0, 0.0, 0.0],
}
VECTOR_KEYS = {"camera.position", "camera.look_at", "world.floor.extent", "world.walls[i].from",
               "world.walls[i].to", "world.objects[i].position", "world.objects[i].velocity",
               "world.robot.size", "world.robot.position", "reality.appearance.color_shift",
               *VECTORS}


def values(bound: Bound) -> list[Any]:
    """The special values, and each finite bound with one step either side."""
    out: list[Any] = list(SPECIAL)
    for b in (bound.low, bound.high):
        if b is None:
            continue
        if bound.integer:
            out += [int(b) - 1, int(b), int(b) + 1]
        else:
            step = max(abs(b), 1e-3) * 1e-3
            out += [b - step, b, b + step]
    return list(dict.fromkeys(out))


def text(value: Any) -> str:
    if isinstance(value, float) and math.isnan(value):
        return ".nan"
    if isinstance(value, float) and math.isinf(value):
        return ".inf" if value > 0 else "-.inf"
    return repr(value)


@pytest.fixture(scope="module")
def bases(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The bouncing-ball scenario at 80x60 pixels with a second ball present from the start,
    and the video scenario."""
    folder = tmp_path_factory.mktemp("bounds")
    doc = yaml.safe_load((ROOT / "scenarios" / "bouncing-ball.yaml").read_text(encoding="utf-8"))
    doc["camera"].update(fx=65.625, fy=65.625, cx=39.5, cy=29.5, width=80, height=60)
    doc["schemas"]["scene-background"]["mmd_pixels"] = 4800
    doc["world"]["objects"].append({"name": "marble", "radius": 0.05, "position": [1.5, 0.5],
                                    "velocity": [0.3, 0.0], "color": [20, 200, 20]})
    doc["world"]["obstacles"] = doc["world"]["obstacles"][:1]  # fewer nodes to read: faster
    doc["rules"] = [str(ROOT / "rules" / "mirror" / "perception.soar")]
    ball = folder / "ball.yaml"
    ball.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return {"ball": ball, "video": ROOT / "scenarios" / "video-sequence.yaml"}


def concrete(key: str) -> str:
    """The key path in the base scenario: the second ball for the world's objects' own keys."""
    if key.startswith("world.objects[i].") and ".ranges." not in key:
        return key.replace("[i]", "[1]")
    return key.replace("[i]", "[0]")


def base_value(doc: dict[str, Any], path: str) -> Any:
    target: Any = doc
    for step in re.findall(r"[^.\[\]]+|\[\d+\]", path):
        index = int(step[1:-1]) if step.startswith("[") else step
        try:
            target = target[index]
        except (KeyError, IndexError, TypeError):
            return None
    return target


def override(doc: dict[str, Any], key: str, value: Any) -> str:
    path = concrete(key)
    if key == "world.obstacles[i].polygon":
        return f"{path}[0][0]={text(value)}"
    if key in VECTOR_KEYS:
        vector = list(base_value(doc, path) or VECTORS[key])
        vector[0] = value
        return f"{path}=[{', '.join(text(v) for v in vector)}]"
    if key == "predict.horizons":
        return f"{path}=[{text(value)}]"
    return f"{path}={text(value)}"


def outcome(argv: list[str]) -> Outcome:
    result = drive(argv)
    check_contract(result)
    return result


@pytest.mark.parametrize("key", sorted(BOUNDS))
def test_check_and_run_agree_at_the_bounds(key: str, bases: dict[str, Path],
                                           tmp_path: Path) -> None:
    base = bases["video" if key == "reality.fps" else "ball"]
    doc = yaml.safe_load(base.read_text(encoding="utf-8"))
    bound = BOUNDS[key]
    for i, value in enumerate(values(bound)):
        given = override(doc, key, value)
        check = outcome(["check", str(base), "--set", given])
        run = outcome(["run", str(base), "--set", given, "--out", str(tmp_path / f"r{i}"),
                       "--max-frames", "2", "--no-video", "--no-figures", "--quiet"])
        said = f"--set {given}: check {check.status} {check.err[-600:]!r}; run {run.status} " \
               f"{run.err[-600:]!r}"
        assert check.status == run.status, said
        inside = isinstance(value, int) or math.isfinite(value)
        if not (inside and bound.contains(value)):
            assert check.status == 1, said
