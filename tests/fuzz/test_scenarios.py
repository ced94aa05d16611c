"""The scenario commands on generated YAML: ``check``, ``render``, ``imagine``, ``run``, ``sync``.

Each scenario is the small fuzz scenario (the room at 80x60 pixels, three
frames) with a few values replaced by awkward ones -- zero, negative, tiny and
huge numbers, NaN and infinities, strings, lists, mappings, nulls, huge
cameras, a ball inside a wall -- keys removed or misspelt, or its text broken:
tabs, unbalanced brackets, a byte-order mark, tags, recursive anchors and an
alias bomb ("billion laughs").
"""

from __future__ import annotations

import copy
import math
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .harness import Pool, examples, run_checked, small_scenario

VALUES = [0, -1, 1, 0.5, 1e-9, 1e-300, 1e9, 1e300, -1e300, math.nan, math.inf, -math.inf, 33000,
          2**63, "x", "", "1e-3", "0x10", [], {}, None, True, [1, 2], [1e300, 0.0], [0, 0, 0],
          [[0, 0], [0, 0], [0, 0]], {"a": 1}, "builtin:nosuch", "../../etc/passwd", "é"]
TEXT_BREAKS = ["\t", "[", "]", "{", "}", ": ", "- ", "&a ", "*a", "!!python/object:os.system ",
               "!!binary ", "'", '"', "#", "\ufeff", "---\n", "...\n", "%YAML 1.1\n", "? "]
BOMB = ("lol: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"l{i}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
    f"*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}]\n"
    for i in range(8)))


def _paths(value: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    found = [prefix] if prefix else []
    if isinstance(value, dict):
        for k, v in value.items():
            found += _paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            found += _paths(v, prefix + (i,))
    return found


@st.composite
def scenarios(draw: st.DrawFn) -> str:
    doc = copy.deepcopy(small_scenario(rules="../inputs/perception.soar"))
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(_paths(doc)))
        target = doc
        for key in path[:-1]:
            target = target[key]
        operation = draw(st.integers(0, 9))
        if operation <= 6:
            target[path[-1]] = draw(st.sampled_from(VALUES))
        elif operation == 7:
            del target[path[-1]]
        elif operation == 8 and isinstance(target, dict):
            target[str(path[-1]) + draw(st.sampled_from(["e", "_", "s", "X"]))] = target.pop(path[-1])
        else:
            doc["world"]["objects"][0]["position"] = [-2.45, 0.9]  # inside the west wall
    text = yaml.safe_dump(doc, sort_keys=False, allow_unicode=True)
    for _ in range(draw(st.integers(0, 2))):
        at = draw(st.integers(0, len(text)))
        text = text[:at] + draw(st.sampled_from(TEXT_BREAKS)) + text[at:]
    if draw(st.integers(0, 19)) == 0:
        text = BOMB + text
    return text


COMMANDS = [
    ["check"],
    ["render", "--out", "{out}/f.png", "--t", "0.2", "--labels", "{out}/l.png"],
    ["imagine", "--horizon", "0.5", "--json"],
    ["run", "--out", "{out}/run", "--no-video", "--no-figures", "--max-frames", "2"],
    ["sync", "--real", "{real}", "--max-iter", "2", "--out", "{out}/sync"],
]


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
def test_generated_scenarios_keep_the_contract(pool: Pool, command: list[str]) -> None:
    @settings(max_examples=examples(25), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(scenarios())
    def check(text: str) -> None:
        folder = pool.outputs()
        scenario = folder / "s.yaml"
        scenario.write_text(text, encoding="utf-8")
        args = [a.replace("{out}", str(folder)).replace("{real}", pool.path("real.png"))
                for a in command[1:]]
        run_checked(pool, [command[0], str(scenario), *args])

    check()


@pytest.mark.parametrize("text", [
    "a: &a [*a]\n",  # a recursive anchor
    BOMB,
    "world: {dt: 1.0e-9}\n",
    "\ufeffseed: 1\n",
    "camera: !!python/object/apply:os.system ['true']\n",
    "- just\n- a list\n",
    "",
], ids=["recursive-anchor", "billion-laughs", "dt", "bom", "python-tag", "list", "empty"])
def test_reported_scenario_texts(pool: Pool, text: str) -> None:
    folder = pool.outputs()
    scenario = folder / "s.yaml"
    scenario.write_text(text, encoding="utf-8")
    for command in (["check"], ["render", "--out", str(folder / "f.png")]):
        outcome = run_checked(pool, [command[0], str(scenario), *command[1:]])
        assert outcome.status == 1, outcome


def _set(doc: dict[str, Any], path: str, value: Any) -> None:
    keys = [int(k) if k.isdigit() else k for k in path.split(".")]
    target: Any = doc
    for key in keys[:-1]:
        target = target[key]
    target[keys[-1]] = value


@pytest.mark.parametrize("path, value, status", [
    ("camera.width", 33000, 1),
    ("world.walls.0.height", 1.0e300, 1),
    ("world.objects.0.mass", 1.0e300, 1),
    ("world.dt", 1.0e-9, 1),
    ("world.objects.0.velocity", [80.0, 0.0], 0),  # fast, but sub-stepped: no tunnelling
    ("world.objects.0.position", [-2.45, 0.9], 1),  # inside the west wall
    ("world.obstacles.0.height", "1e-3", 0),  # YAML 1.2 float
    ("camera.position", [0.0, -0.6, -0.2], 1),  # below the floor
    ("sede", 3, 1),  # a top-level typo
], ids=lambda v: str(v)[:24])
def test_the_reported_scenario_values(pool: Pool, path: str, value: Any, status: int) -> None:
    """The findings of issue 11 that others fixed, checked through every scenario command."""
    doc = small_scenario(rules="../inputs/perception.soar")
    _set(doc, path, value)
    folder = pool.outputs()
    scenario = folder / "s.yaml"
    scenario.write_text(yaml.safe_dump(doc, sort_keys=False).replace("'1e-3'", "1e-3"))
    for command in COMMANDS[:3]:
        args = [a.replace("{out}", str(folder)) for a in command[1:]]
        outcome = run_checked(pool, [command[0], str(scenario), *args])
        assert outcome.status == status, outcome
