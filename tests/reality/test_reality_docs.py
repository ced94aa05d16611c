"""docs/reality.md names every key the reader accepts in the reality section."""

from __future__ import annotations

import re

import pytest

from adapt.scenario.bullet import (
    BULLET_KEYS,
    BULLET_OBJECT_KEYS,
    BULLET_ROBOT_KEYS,
    BULLET_SURFACE_KEYS,
    BULLET_THROW_KEYS,
    LOOK_KEYS,
)
from adapt.scenario.device import CAMERA_REALITY_KEYS
from adapt.scenario.reality import (
    APPEARANCE_KEYS,
    REALITY_ROBOT_KEYS,
    SYNTHETIC_KEYS,
    THROW_KEYS,
    TRUE_OBJECT_KEYS,
    VIDEO_KEYS,
)

from .conftest import ROOT

DOC = (ROOT / "docs" / "reality.md").read_text(encoding="utf-8")


def table_keys(heading: str) -> set[str]:
    """The backquoted names in the first column of the table under ``heading``."""
    part = DOC.split(heading, 1)[1]
    rows = re.findall(r"^\| ([^|]+) \|", part.split("\n\n|", 1)[-1].split("\n\n", 1)[0], re.M)
    return {k for row in rows for k in re.findall(r"`([a-z_]+)`", row)}


@pytest.mark.parametrize("heading, keys", [
    ("### Keys of `reality` (synthetic)", SYNTHETIC_KEYS),
    ("### `reality.objects[i]`", TRUE_OBJECT_KEYS),
    ("### `reality.objects[i].throw`", THROW_KEYS),
    ("### `reality.appearance`", APPEARANCE_KEYS),
    ("### `reality.robot`", REALITY_ROBOT_KEYS),
    ("## The video source", VIDEO_KEYS),
    ("## The camera source", CAMERA_REALITY_KEYS),
    ("### Keys of `reality` (bullet)", BULLET_KEYS),
    ("### `reality.floor`, `reality.walls`, `reality.obstacles` (bullet)", BULLET_SURFACE_KEYS),
    ("### `reality.objects[i]` (bullet)", BULLET_OBJECT_KEYS),
    ("### `reality.objects[i].throw` (bullet)", BULLET_THROW_KEYS),
    ("### `reality.look` (bullet)", LOOK_KEYS),
    ("### `reality.robot` (bullet)", BULLET_ROBOT_KEYS),
])
def test_every_key_is_documented_and_nothing_else(heading: str, keys: tuple[str, ...]) -> None:
    assert table_keys(heading) == set(keys)
