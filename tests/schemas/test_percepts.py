"""BackgroundPercept's robot mask: the imagined robot's pixels, grown by a margin, but not
those that show something of another colour than the robot's in the real frame."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.geometry import Camera
from adapt.imagination.surface import LABEL_ROBOT
from adapt.schemas.percepts import ROBOT_COLOUR_PIXELS, BackgroundPercept

CAM = Camera(100, 100, 40, 30, 80, 60, np.eye(3), np.zeros(3))


def scene(shift: int) -> tuple[BackgroundPercept, np.ndarray]:
    """A dark robot drawn at columns 30-49 of an 80x60 frame, the real one ``shift`` px to
    the left, and a cyan ball resting against its right side."""
    labels = np.zeros((60, 80), np.uint16)
    labels[20:45, 30:50] = LABEL_ROBOT
    real = np.full((60, 80, 3), 150, np.uint8)  # the floor
    real[20:45, 30 - shift:50 - shift] = (35, 35, 40)  # the real robot
    real[28:38, 50 - shift:58 - shift] = (200, 190, 20)  # the ball beside it (BGR)
    p = BackgroundPercept(0, 0.0, CAM, CAM, drawn={"robot": LABEL_ROBOT}, warped_labels=labels)
    return p, real


@pytest.mark.parametrize("shift", [0, 2, 4])
def test_what_shows_past_the_robot_in_another_colour_is_not_the_robots(shift: int) -> None:
    p, real = scene(shift)
    grown = p.robot_mask(margin=3)
    mask = p.robot_mask(margin=3, real=real)
    assert grown is not None and mask is not None
    ball = np.all(real == (200, 190, 20), axis=-1)
    robot = np.all(real == (35, 35, 40), axis=-1)
    assert (grown & ball).any()  # the margin covers part of the ball ...
    assert not (mask & ball).any()  # ... which the robot's colour gives back
    assert np.array_equal(mask & robot, grown & robot)  # the robot's own pixels stay masked
    floor = ~(ball | robot)
    assert not (mask & floor).any()  # nor is the floor past the real robot's edge its image


def test_a_box_with_too_little_of_the_robot_inside_its_outline_leaves_the_mask_whole() -> None:
    p, real = scene(2)
    box = (47, 20, 12, 25)  # the robot's right edge: 3 columns drawn, none 3 px inside
    grown = p.robot_mask(margin=3, box=box)
    assert grown is not None and grown.any()
    assert np.array_equal(p.robot_mask(margin=3, box=box, real=real), grown)
    core = p.robot_mask(box=(30, 20, 20, 25))
    assert core is not None and int(core.sum()) >= ROBOT_COLOUR_PIXELS


def test_a_box_of_the_frame_gets_the_same_mask_as_the_whole_frame_there() -> None:
    p, real = scene(3)
    whole = p.robot_mask(margin=3, real=real)
    assert whole is not None
    box = (25, 15, 40, 35)
    part = p.robot_mask(margin=3, box=box, real=real)
    assert part is not None and np.array_equal(part, whole[15:50, 25:65])
