"""A grey ball on grey gravel is followed whole, and none of its pieces is an object.

Throw 50 of ``bench/foreign.py``: a camera on the robot, a smooth light-grey ball rolling
on a gravel floor whose mean grey is the ball's.  Its per-pixel difference from the
learned look showed only where a grain was lighter or darker than the ball: its top, and
scattered pieces of its lower half.  The ball's schema, spawned on its top, refused every
piece as not ball-shaped and never sighted it; the rules spawned schemas for the pieces
as objects the scenario does not know (both spurious schemas of the 50 throws at
640x480).  When the per-pixel difference shows no sighting, the object's search now also
counts where the frame is flat over the look's texture
(:func:`~adapt.vision.texture.flat_over_texture`).
"""

from __future__ import annotations

import pytest

from .bench_throws import replay, sightings

pytest.importorskip("pybullet")


def test_a_ball_the_colour_of_the_gravel_is_followed_and_its_pieces_are_not_objects() -> None:
    sc, rows = replay(50, 2.0)
    assert set().union(*(r["names"] for r in rows)) == {"ball"}
    seen, on = sightings(sc, rows)
    # before: no sighting at all in the 6 s; when written, 12 in 2 s, one of them 3.1 radii
    # off.  How many follow depends on the machine: the camera on the robot falls out of step
    # as the robot turns to face the ball (frame 7), and the ball with it: on a second machine
    # 5 on (frames 5, 16, 17, 48, 50), the same one off
    assert len(on) >= 4 and len(seen) - len(on) <= 1, seen
