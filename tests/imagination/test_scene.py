"""Bad input to the scene records is a clear error naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.errors import ImaginationError
from adapt.geometry import Camera
from adapt.imagination import Ball, Obstacle, RobotSpec, SceneSpec, Wall


def test_polygon_is_stored_counter_clockwise() -> None:
    ob = Obstacle("o", polygon=((0, 0), (0, 1), (1, 1), (1, 0)))
    assert ob.area == pytest.approx(1.0)


@pytest.mark.parametrize(
    "polygon, message",
    [
        (((0, 0), (1, 0)), "at least 3 points"),
        (((0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2)), "expected a convex polygon"),
        (((0, 0), (1, 0), (2, 0)), "non-zero area"),
        (((0, 0), (1, 0), (1, 0), (0, 1)), "repeated point"),
    ],
)
def test_bad_polygons(polygon: tuple[tuple[float, float], ...], message: str) -> None:
    with pytest.raises(ImaginationError, match=message):
        Obstacle("o", polygon=polygon)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"radius": -0.1}, "radius"),
        ({"radius": 0.0}, "radius"),
        ({"mass": -1.0}, "mass"),
        ({"restitution": 1.5}, "restitution"),
        ({"rolling_resistance": -0.1}, "rolling_resistance"),
        ({"position": (1.0,)}, "position"),
        ({"velocity": (float("nan"), 0.0)}, "velocity"),
        ({"color": (0, 0, 300)}, "color"),
        ({"texture": "builtin:marble"}, "texture"),
    ],
)
def test_bad_ball_fields(kwargs: dict[str, object], field: str) -> None:
    with pytest.raises(ImaginationError, match=f"^{field}: (expected|unknown)"):
        Ball("b", **kwargs)  # type: ignore[arg-type]


def test_bad_walls_robot_and_names() -> None:
    with pytest.raises(ImaginationError, match="^height"):
        Wall("w", (0, 0), (1, 0), height=-1)
    with pytest.raises(ImaginationError, match="^to"):
        Wall("w", (0, 0), (0, 0))
    with pytest.raises(ImaginationError, match="^shape"):
        RobotSpec(shape="triangle")
    with pytest.raises(ImaginationError, match="used twice"):
        SceneSpec(balls=(Ball("x"),), walls=(Wall("x", (0, 0), (1, 0)),))


@pytest.mark.parametrize(
    "look_at, message",
    [((0, 0, 5), "straight up"), ((0, 0, -1), "straight down"), ((0, 0, 1), "equals its position")],
)
def test_impossible_cameras(look_at: tuple[float, float, float], message: str) -> None:
    with pytest.raises(ImaginationError, match=message):
        Camera.look_at(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
                       position=(0, 0, 1), look_at=look_at)


def test_camera_projection_is_k_r_x_minus_c() -> None:
    cam = Camera.look_at(fx=525, fy=530, cx=319.5, cy=239.5, width=640, height=480,
                         position=(0.3, -1.0, 0.7), look_at=(0.5, 3.0, 0.2), roll_deg=4.0)
    x = np.array([[0.9, 2.0, 0.4], [-1.0, 3.0, 1.2]])
    h = (cam.K @ cam.rotation @ (x - cam.position).T).T
    assert np.allclose(cam.project(x), h[:, :2] / h[:, 2:], atol=1e-9)


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: Wall("w", (0, 0), (1, 0), height=1e300), "height"),
        (lambda: Wall("w", (0, 0), (1e300, 0)), "to"),
        (lambda: Ball("b", mass=1e300), "mass"),
        (lambda: Ball("b", mass=1e-300), "mass"),
        (lambda: Ball("b", radius=1e-9), "radius"),
        (lambda: Ball("b", velocity=(3e3, 0.0)), "velocity"),
        (lambda: Ball("b", friction=1e300), "friction"),
        (lambda: Obstacle("o", ((0, 0), (1, 0), (0, 1)), tile=1e-300), "tile"),
        (lambda: RobotSpec(max_speed=1e300), "max_speed"),
        (lambda: SceneSpec(gravity=1e300), "gravity"),
        (lambda: SceneSpec(dt=1e-9), "dt"),
        (lambda: Obstacle("o", [(np.cos(a), np.sin(a)) for a in np.linspace(0, 6.2, 300)]),
         "polygon"),
    ],
)
def test_absurd_magnitudes_are_refused_naming_the_field(make: object, field: str) -> None:
    with pytest.raises(ImaginationError, match=f"^{field}: expected"):
        make()  # type: ignore[operator]


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"width": 33000}, "width"),
        ({"height": 0}, "height"),
        ({"width": 640.5}, "width"),
        ({"width": 8000, "height": 8000}, "width"),
        ({"fx": 1e300}, "fx"),
        ({"fx": float("nan")}, "fx"),
        ({"cx": float("inf")}, "cx"),
        ({"position": (1e300, 0, 1)}, "position"),
        ({"look_at": (0, 0, float("nan"))}, "look_at"),
    ],
)
def test_absurd_cameras_are_refused_naming_the_field(kwargs: dict[str, object], field: str) -> None:
    args: dict[str, object] = dict(fx=500, fy=500, cx=320, cy=240, width=640, height=480,
                                   position=(0, 0, 1), look_at=(0, 1, 1))
    args.update(kwargs)
    with pytest.raises(ImaginationError, match=f"^{field}: "):
        Camera.look_at(**args)  # type: ignore[arg-type]


def test_a_camera_keeps_read_only_copies_of_its_arrays() -> None:
    r, c = np.eye(3), np.array([0.0, -1.0, 1.0])
    cam = Camera(500, 500, 320, 240, 640, 480, r, c)
    r[0, 0], c[0] = -1.0, 9.0
    assert cam.rotation[0, 0] == 1.0 and cam.position[0] == 0.0
    with pytest.raises(ValueError):
        cam.rotation[0, 0] = 2.0
    with pytest.raises(ValueError):
        cam.position[0] = 2.0
    turned = cam.with_rotation(r @ np.diag([1.0, -1.0, 1.0]) @ np.diag([1.0, 1.0, 1.0]))
    assert not turned.rotation.flags.writeable
    with pytest.raises(ImaginationError, match="^rotation: expected a proper rotation"):
        Camera(500, 500, 320, 240, 640, 480, 2 * np.eye(3), c)
