"""Lines of sight over the floor plan (closed-form cases)."""

from __future__ import annotations

import pytest

from adapt.imagination.scene import SceneSpec, Wall
from adapt.imagination.sight import behind_wall

ROOM = SceneSpec(walls=(Wall("north", (-2.5, 3.0), (2.5, 3.0)),
                        Wall("east", (2.5, 3.0), (2.5, -1.0))))


@pytest.mark.parametrize(("point", "wall"), [
    ((0.5, 3.5), "north"),      # straight through the north wall
    ((3.0, 1.0), "east"),
    ((2.4, 2.9), None),          # inside the corner
    ((-3.0, 2.9), None),         # past the north wall's end, not through it
    ((0.0, 3.0), None),          # on the wall: touching is not crossing
])
def test_the_wall_between_the_eye_and_the_point(point: tuple[float, float],
                                                wall: str | None) -> None:
    found = behind_wall(ROOM, (0.0, 0.0), point)
    assert (found.name if found is not None else None) == wall


def test_seen_from_outside_the_room_the_room_is_behind_the_wall() -> None:
    assert behind_wall(ROOM, (0.0, 4.0), (0.0, 2.0)).name == "north"  # type: ignore[union-attr]
