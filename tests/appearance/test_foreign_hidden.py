"""The ball's path through the first look is background to learn, not an object.

Throw 23 of ``bench/foreign.py`` (at 320x240): a camera on the robot, a green ball rolling
from the first frame over green and cyan floor tiles, across the view and behind an
obstacle.  The first look left its path unlearned (the frames never settled there) and the
render drew the scenario's gravel in it: a ghost the shape of the ball's path.  The ball's
schema was spawned on it and held it in its box, where nothing was ever learned again; when
the ball came out from behind the obstacle a second schema was spawned for it, as an object
the scenario does not know.  Texels the first look left unlearned because something moved
over them are now *hidden* (:meth:`~adapt.mirror.appearance.AppearanceModel.hidden`): once
their pixels held still
they are learned whatever box covers them, and a region on them that holds still is
``unseen``, never spawned for.
"""

from __future__ import annotations

import pytest

from .bench_throws import replay, sightings

pytest.importorskip("pybullet")


def test_the_path_a_ball_rolled_through_the_first_look_is_no_object() -> None:
    sc, rows = replay(23, 4.0)
    # before: "ball" and "foreground-object-1" (the ball itself, taken for another object)
    assert set().union(*(r["names"] for r in rows)) == {"ball"}
    seen, on = sightings(sc, rows)
    # the ball out from behind the obstacle (frame 99 of 120 when written) is followed: 10
    # sightings within 0.4 radii; off only once, at the first look (before: twice, 5.8 and
    # 8 radii, and 6 sightings on)
    assert len(on) >= 8 and len(seen) - len(on) <= 1, seen
