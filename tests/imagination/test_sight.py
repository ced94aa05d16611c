"""Lines of sight in 3D (closed-form cases): the camera's height and the walls' and obstacles'
heights decide what is hidden."""

from __future__ import annotations

import pytest

from adapt.imagination.scene import Obstacle, SceneSpec, Wall
from adapt.imagination.sight import blocked_by, hidden_by, prism_span, segment_crossing

ROOM = SceneSpec(walls=(Wall("north", (-2.5, 3.0), (2.5, 3.0), height=1.0),
                        Wall("east", (2.5, 3.0), (2.5, -1.0), height=1.0)))


@pytest.mark.parametrize(("point", "wall"), [
    ((0.5, 3.5), "north"),      # straight through the north wall
    ((3.0, 1.0), "east"),
    ((2.4, 2.9), None),          # inside the corner
    ((-3.0, 2.9), None),         # past the north wall's end, not through it
    ((0.0, 3.0), None),          # on the wall: touching is not crossing
])
def test_from_below_the_walls_top_the_wall_hides_what_is_behind_it(
        point: tuple[float, float], wall: str | None) -> None:
    found = hidden_by(ROOM, (0.0, 0.0, 0.5), point, 0.1)
    assert (found.name if found is not None else None) == wall


def test_the_line_clears_a_wall_exactly_when_it_crosses_above_its_top() -> None:
    # eye 2 m high at y = 0, the wall 1 m high at y = 3: a point at y = 4 is seen when the
    # line crosses y = 3 above z = 1: 2 + (3 / 4) (z - 2) > 1, i.e. z > 2/3
    scene = SceneSpec(walls=(Wall("w", (-5.0, 3.0), (5.0, 3.0), height=1.0),))
    assert blocked_by(scene, (0, 0, 2.0), (0, 4, 0.66)) is not None
    assert blocked_by(scene, (0, 0, 2.0), (0, 4, 0.67)) is None


def test_a_camera_outside_above_a_low_wall_sees_the_floor_inside() -> None:
    # the set-up: 2.3 m high, 0.5 m behind a 12 cm front wall of a 3 m arena
    arena = SceneSpec(walls=(
        Wall("south", (1.5, -1.5), (-1.5, -1.5), height=0.12),
        Wall("north", (-1.5, 1.5), (1.5, 1.5), height=0.5),
        Wall("east", (1.5, 1.5), (1.5, -1.5), height=0.5),
        Wall("west", (-1.5, -1.5), (-1.5, 1.5), height=0.5)))
    eye = (0.0, -2.0, 2.3)
    for x in (-1.3, 0.0, 1.3):
        for y in (-1.35, 0.0, 1.35):
            assert hidden_by(arena, eye, (x, y), 0.1) is None, (x, y)
    # the same camera 5 cm high (floor level behind the wall) sees none of it
    assert hidden_by(arena, (0.0, -2.0, 0.05), (0.0, 0.0), 0.1).name == "south"  # type: ignore[union-attr]
    # a ball outside the north wall, 0.5 m high, is hidden from the high camera
    assert hidden_by(arena, eye, (0.0, 1.8), 0.1).name == "north"  # type: ignore[union-attr]


def test_a_ball_whose_top_shows_over_a_wall_is_not_hidden() -> None:
    # the wall is 0.15 m high; the ball (radius 0.1) has its centre below the wall's line of
    # sight and its top above it, seen from a camera at the wall's height
    scene = SceneSpec(walls=(Wall("w", (-5.0, 1.0), (5.0, 1.0), height=0.15),))
    assert blocked_by(scene, (0, 0, 0.15), (0, 2, 0.1)) is not None
    assert blocked_by(scene, (0, 0, 0.15), (0, 2, 0.2)) is None
    assert hidden_by(scene, (0, 0, 0.15), (0, 2), 0.1) is None


CRATE = Obstacle("crate", polygon=((1.0, -0.5), (2.0, -0.5), (2.0, 0.5), (1.0, 0.5)), height=0.4)


def test_an_obstacle_hides_what_is_behind_it_up_to_its_height() -> None:
    scene = SceneSpec(obstacles=(CRATE,))
    eye = (0.0, 0.0, 0.5)
    # the line to (3, 0, 0.1) enters the crate at x = 1 with z = 0.5 - 0.4 / 3 = 0.367 < 0.4
    assert blocked_by(scene, eye, (3.0, 0.0, 0.1)).name == "crate"  # type: ignore[union-attr]
    # from 2 m high it passes above the crate: at x = 2, z = 2 - (2/3) 1.9 = 0.733 > 0.4
    assert blocked_by(scene, (0.0, 0.0, 2.0), (3.0, 0.0, 0.1)) is None
    # beside the crate
    assert blocked_by(scene, eye, (3.0, 2.0, 0.1)) is None
    # grazing its corner is not passing through it
    assert blocked_by(scene, (0.0, 0.5, 0.1), (2.0, -1.5, 0.1)) is None  # through (1, -0.5)


def test_segment_helpers_closed_form() -> None:
    assert segment_crossing((0, 0), (4, 0), (1, -1), (1, 1)) == pytest.approx(0.25)
    assert segment_crossing((0, 0), (4, 0), (5, -1), (5, 1)) is None
    assert prism_span((0, 0), (4, 0), CRATE.polygon) == pytest.approx((0.25, 0.5))
    assert prism_span((1.5, 0), (4, 0), CRATE.polygon) == pytest.approx((0.0, 0.2))
    assert prism_span((0, 2), (4, 2), CRATE.polygon) is None
