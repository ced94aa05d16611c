"""Surfaces: the static planes of a scene and their coordinate conventions."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.errors import ImaginationError
from adapt.geometry import Camera
from adapt.imagination import (
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_WALL,
    Floor,
    Obstacle,
    SceneSpec,
    Wall,
    scene_surfaces,
)
from adapt.scenario import Scenario

CAM = Camera.look_at(fx=500, fy=480, cx=300.5, cy=210.0, width=640, height=480,
                     position=(0.4, -1.5, 1.1), look_at=(0.0, 2.0, 0.3), roll_deg=5.0)


def test_every_static_surface_is_described(bundled: Scenario) -> None:
    surfaces = scene_surfaces(bundled.scene)
    names = [s.name for s in surfaces]
    assert names[:5] == ["floor", "north", "east", "south", "west"]
    assert names[5:10] == ["crate/side0", "crate/side1", "crate/side2", "crate/side3", "crate/top"]
    assert len(surfaces) == 1 + 4 + (4 + 1) + (3 + 1) + (4 + 1)
    for s in surfaces:
        u, v = np.array(s.u), np.array(s.v)
        assert np.dot(u, u) == pytest.approx(1) and np.dot(v, v) == pytest.approx(1)
        assert np.dot(u, v) == pytest.approx(0, abs=1e-12)
        assert s.polygon is not None and len(s.polygon) >= 3
        assert 0.6 <= s.shade <= 1.0
    by = {s.name: s for s in surfaces}
    assert by["floor"].label == LABEL_FLOOR and by["floor"].normal == (0.0, 0.0, 1.0)
    assert by["north"].label == LABEL_WALL and by["north"].two_sided
    assert by["wedge/top"].label == LABEL_OBSTACLE + 1 and by["wedge/top"].origin[2] == 0.3
    # The room's walls run clockwise seen from above, so their fronts face inwards.
    for wall in ("north", "east", "south", "west"):
        inwards = np.array([0.0, 1.0, 0.5]) - np.array(by[wall].origin)
        assert np.dot(by[wall].normal, inwards) > 0
        assert by[wall].seen_from((0.0, 1.0, 0.5)) and by[wall].seen_from((0.0, 9.0, 0.5))


def test_obstacle_sides_face_outwards_and_the_top_up() -> None:
    ob = Obstacle("o", ((0, 0), (0, 1), (1, 1), (1, 0)), height=0.4)  # given clockwise
    surfaces = scene_surfaces(SceneSpec(obstacles=(ob,)))[1:]
    centre = np.array([0.5, 0.5, 0.2])
    for s in surfaces[:-1]:
        middle = np.array(s.point(s.polygon[1][0] / 2, 0.2))  # type: ignore[index]
        assert np.dot(np.array(s.normal), middle - centre) > 0
        assert s.seen_from(middle + np.array(s.normal)) and not s.seen_from(centre)
    top = surfaces[-1]
    assert top.normal == (0.0, 0.0, 1.0) and top.seen_from((0.5, 0.5, 1.0))
    assert not top.seen_from((0.5, 0.5, 0.3))


def test_the_homography_maps_face_points_to_their_projection(bundled: Scenario) -> None:
    rng = np.random.default_rng(3)
    for s in scene_surfaces(bundled.scene):
        e = s.extent
        assert e is not None
        st = np.stack([rng.uniform(e[0], e[2], 20), rng.uniform(e[1], e[3], 20)], axis=1)
        world = s.to_world(st)
        assert np.allclose(s.to_face(world), st)
        h = s.homography(CAM) @ np.vstack([st.T, np.ones(20)])
        front = h[2] > 0
        assert np.allclose((h[:2] / h[2]).T[front], CAM.project(world)[front], atol=1e-6)


def test_surface_image_pixel_centres_follow_the_convention() -> None:
    wall = scene_surfaces(SceneSpec(walls=(Wall("w", (1, 2), (1, 5), height=1.5),)))[1]
    a = wall.image_to_face((300, 150))  # 100 px per metre
    assert (a @ [0, 0, 1]).tolist() == pytest.approx([0.005, 1.495, 1.0])  # top-left: top of wall
    assert (a @ [299, 149, 1]).tolist() == pytest.approx([2.995, 0.005, 1.0])
    assert wall.point(0.0, 1.5) == (1.0, 2.0, 1.5)
    # Image -> camera: a pixel of the surface image lands on its projected world point.
    h = wall.image_homography(CAM, (300, 150))
    p = h @ [120, 40, 1]
    s, t, _ = a @ [120, 40, 1]
    assert (p[:2] / p[2]).tolist() == pytest.approx(CAM.project([wall.point(s, t)])[0].tolist())
    with pytest.raises(ImaginationError, match="^size: "):
        wall.image_to_face((0, 10))


def test_unbounded_floor_and_name_collisions() -> None:
    floor = scene_surfaces(SceneSpec(floor=Floor()))[0]
    assert floor.polygon is None and floor.extent is None
    with pytest.raises(ImaginationError, match="^extent: surface 'floor' is unbounded"):
        floor.image_to_face((10, 10))
    assert floor.image_to_face((10, 10), (0, 0, 1, 1))[0, 0] == pytest.approx(0.1)
    clash = SceneSpec(walls=(Wall("box/top", (0, 0), (1, 0)),),
                      obstacles=(Obstacle("box", ((2, 2), (3, 2), (3, 3))),))
    with pytest.raises(ImaginationError, match="'box/top' is used twice"):
        scene_surfaces(clash)
