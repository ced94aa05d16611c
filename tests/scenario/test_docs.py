"""docs/scenario.md and the reader stay in step: every documented table lists exactly the
keys the reader accepts, and the documented defaults are the records' defaults."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from adapt.imagination.scene import Ball, Floor, Obstacle, RobotSpec, Wall
from adapt.scenario import TOP_KEYS, OutputSettings, PredictSettings, RealAppearance, RunSettings
from adapt.scenario import bullet as BU
from adapt.scenario import device as D
from adapt.scenario import reality as R
from adapt.scenario import run as RUN
from adapt.scenario import world as W
from adapt.scenario.bounds import BOUNDS, BULLET_BOUNDS, bullet_bound

DOC = Path(__file__).resolve().parents[2] / "docs" / "scenario.md"

#: heading -> (keys the reader accepts, record whose field defaults the doc must show,
#:             key -> field name where they differ)
TABLES = {
    "Top level": (TOP_KEYS, None, {}),
    "`camera`": (W.CAMERA_KEYS, None, {}),
    "`world`": (W.WORLD_KEYS, None, {}),
    "`world.floor`": (W.FLOOR_KEYS, Floor, {}),
    "`world.walls[i]`": (W.WALL_KEYS, Wall, {}),
    "`world.obstacles[i]`": (W.OBSTACLE_KEYS, Obstacle, {}),
    "`world.objects[i]` (balls)": (W.OBJECT_KEYS, Ball, {}),
    "`world.robot`": (W.ROBOT_KEYS, RobotSpec, {}),
    "`reality` with `kind: synthetic` (the default)": (R.SYNTHETIC_KEYS, None, {}),
    "`reality.appearance`": (R.APPEARANCE_KEYS, RealAppearance, {}),
    "`reality.robot`": (R.REALITY_ROBOT_KEYS, None, {}),
    "`reality.objects[i]`": (R.TRUE_OBJECT_KEYS, None, {}),
    "`reality.objects[i].throw`": (R.THROW_KEYS, None, {}),
    "`reality` with `kind: video`": (R.VIDEO_KEYS, None, {}),
    "`reality` with `kind: camera`": (D.CAMERA_REALITY_KEYS, None, {}),
    "`reality` with `kind: bullet`": (BU.BULLET_KEYS, None, {}),
    "`reality.floor`, `reality.walls` and `reality.obstacles` (bullet)":
        (BU.BULLET_SURFACE_KEYS, None, {}),
    "`reality.objects[i]` (bullet)": (BU.BULLET_OBJECT_KEYS, None, {}),
    "`reality.objects[i].throw` (bullet)": (BU.BULLET_THROW_KEYS, None, {}),
    "`reality.look` (bullet)": (BU.LOOK_KEYS, None, {}),
    "`reality.robot` (bullet)": (BU.BULLET_ROBOT_KEYS, None, {}),
    "`run`": (RUN.RUN_KEYS, RunSettings, {}),
    "`predict`": (RUN.PREDICT_KEYS, PredictSettings, {}),
    "`outputs`": (RUN.OUTPUT_KEYS, OutputSettings, {}),
}


def tables() -> dict[str, list[tuple[str, str]]]:
    """heading -> [(key, default cell)] of the first table under it."""
    out: dict[str, list[tuple[str, str]]] = {}
    heading = None
    for line in DOC.read_text(encoding="utf-8").splitlines():
        m = re.match(r"#+ (.*)", line)
        if m:
            heading = m.group(1).strip()
            continue
        if heading and line.startswith("| `"):
            cells = [c.strip() for c in line.strip("|").split("|")]
            keys = re.findall(r"`([^`]+)`", cells[0])
            default = cells[2] if len(cells) > 2 else ""
            for key in keys:
                out.setdefault(heading, []).append((key, default))
    return out


@pytest.mark.parametrize("heading", sorted(TABLES))
def test_every_documented_table_lists_the_readers_keys(heading: str) -> None:
    found = tables()
    assert heading in found, f"docs/scenario.md has no table under {heading!r}"
    documented = [k for k, _ in found[heading]]
    keys, _, _ = TABLES[heading]
    assert sorted(set(documented)) == sorted(keys), heading


@pytest.mark.parametrize("heading", sorted(h for h, v in TABLES.items() if v[1] is not None))
def test_documented_defaults_are_the_records_defaults(heading: str) -> None:
    keys, record, rename = TABLES[heading]
    fields = record.__dataclass_fields__  # type: ignore[union-attr]
    checked = 0
    for key, cell in tables()[heading]:
        name = rename.get(key, key)
        if name not in fields or fields[name].default is fields[name].default_factory:
            continue
        default = fields[name].default
        text = cell.strip("`")
        try:
            value = yaml.safe_load(text.replace("`", ""))
        except yaml.YAMLError:
            continue
        if isinstance(default, tuple):
            default = list(default)
        if isinstance(value, (int, float)) and isinstance(default, (int, float)) \
                and not isinstance(default, bool):
            assert abs(float(value) - float(default)) < 1e-9, (heading, key, cell, default)
            checked += 1
        elif isinstance(value, (bool, list)) and isinstance(default, (bool, list)):
            assert value == default, (heading, key, cell, default)
            checked += 1
        elif isinstance(value, str) and isinstance(default, str) and value in (default, f"'{default}'"):
            checked += 1
    assert checked >= 1, f"no default of {heading} could be compared"


#: heading -> the key paths its table's keys are under
PREFIXES = {"Top level": ("",), "`reality` with `kind: synthetic` (the default)": ("reality",),
            "`reality` with `kind: video`": ("reality",),
            "`reality` with `kind: camera`": ("reality",),
            "`world.objects[i]` (balls)": ("world.objects[i]",),
            "`reality` with `kind: bullet`": ("reality",),
            "`reality.floor`, `reality.walls` and `reality.obstacles` (bullet)":
                ("reality.floor", "reality.walls", "reality.obstacles"),
            "`reality.objects[i]` (bullet)": ("reality.objects[i]",),
            "`reality.objects[i].throw` (bullet)": ("reality.objects[i].throw",),
            "`reality.look` (bullet)": ("reality.look",),
            "`reality.robot` (bullet)": ("reality.robot",)}


def typed_rows(bullet: bool = False) -> dict[str, str]:
    """Every documented key path -> its type cell: of the tables of a ``kind: bullet``
    reality, or (``bullet=False``) of the others (a key both document, ``reality.dt`` say,
    may be bounded otherwise in each)."""
    out: dict[str, str] = {}
    heading = None
    for line in DOC.read_text(encoding="utf-8").splitlines():
        m = re.match(r"#+ (.*)", line)
        if m:
            heading = m.group(1).strip()
            continue
        if heading in TABLES and line.startswith("| `") and ("bullet" in heading) == bullet:
            cells = [c.strip() for c in line.strip("|").split("|")]
            for prefix in PREFIXES.get(heading, (heading.strip("`"),)):
                for key in re.findall(r"`([^`]+)`", cells[0]):
                    out[f"{prefix}.{key}" if prefix else key] = cells[1]
    return out


def test_every_bound_is_documented_in_its_keys_row() -> None:
    """The type column states each number's bound as adapt/scenario/bounds.py declares it
    (in the tables of a ``kind: bullet`` reality, as it bounds them)."""
    rows, bullet_rows = typed_rows(), typed_rows(bullet=True)
    for key, bound in BOUNDS.items():
        if ".ranges." in key:  # documented in the ranges row: each end within the key's bounds
            assert key.replace(".ranges.", ".") in BOUNDS
            continue
        assert key in rows or key in bullet_rows, f"{key} has a bound but no row in docs/scenario.md"
        if key in rows:
            assert bound.text in rows[key], (key, rows[key], bound.text)
    for key, cell in bullet_rows.items():
        if key in BOUNDS or key in BULLET_BOUNDS:
            assert bullet_bound(key).text in cell, (key, cell, bullet_bound(key).text)


def test_every_documented_number_has_a_bound() -> None:
    for bullet in (False, True):
        for key, cell in typed_rows(bullet).items():
            if re.search(r"\bnumber|\binteger|\[x, y", cell):
                assert key in BOUNDS or (bullet and key in BULLET_BOUNDS), (key, cell)


def test_the_engine_key_is_documented_with_its_choices_and_default() -> None:
    from adapt.engine.interface import ENGINE_NAMES
    from adapt.scenario import Scenario

    row = dict(tables()["Top level"])["engine"]
    line = next(x for x in DOC.read_text(encoding="utf-8").splitlines()
                if x.startswith("| `engine` |"))
    kinds = line.split("|")[2]
    assert sorted(re.findall(r"`([^`]+)`", kinds)) == sorted(ENGINE_NAMES)
    assert row.strip("`") == Scenario.__dataclass_fields__["engine"].default.value
