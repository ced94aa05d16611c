"""The floor the robot stood on while the look was first learned is no object.

Throw 13 of ``bench/foreign.py --small``: a camera inside the arena, the robot starting
near the south wall.  The first look cannot see the floor under the robot; once the
robot drives off to meet the ball, that floor differs from the look's guess.  The rules
spawned a schema for it as an object the scenario does not know (9 of the 10 such
spurious schemas on fixed cameras in 10 throws were this), and a ball schema that missed
the ball for a frame near it could take it for the ball and hold it.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from adapt.runner import Runner
from adapt.schemas.foreground import ForegroundObject

from .bench_throws import QUIET, replay, sightings, throw

pytest.importorskip("pybullet")



def _robot_drove_off(sc: Any, rows: list[dict[str, Any]]) -> bool:
    """Whether the true robot went farther than its diameter from where it started."""
    start = sc.scene.robot.position
    return max(math.dist(r["robot"], start) for r in rows
               if r["robot"] is not None) > 2 * sc.scene.robot.radius


def test_the_floor_under_the_robots_start_is_never_spawned_for() -> None:
    sc, rows = replay(13, 3.0)
    assert _robot_drove_off(sc, rows)
    assert {n for r in rows for n in r["names"]} == {"ball"}
    radius = sc.model("ball").ball.radius
    # on the floor (it is thrown from 0.29 m up: the fit's ground plane does not hold in the air)
    seen = [r for r in rows if r["observed"] is not None and r["height"] < radius + 0.01]
    assert len(seen) >= 30
    assert all(math.dist(r["observed"], r["truth"]) < 2 * radius for r in seen)


def test_the_robots_rim_left_in_the_look_is_never_spawned_for() -> None:
    # throw 6: a camera outside the arena, the robot standing near it.  The real robot shows
    # a few pixels past the imagined one's outline (its pose a little off, its shape
    # another), inside the margin kept around the imagined bodies at the first look; the
    # refinements learned those pixels as floor while it stood (the render's guess there
    # differs from the body's dark edge by less than the threshold).  When it drove off, the
    # dark rim it left in the look was no "unseen" floor (its texels had been learned), and
    # was spawned for as an object the scenario does not know (at 1.5 s, at 320x240 and
    # at 640x480).  A region mostly on the pixels the imagined bodies covered at the first
    # look, held still, is the look's ignorance there, learned or not.
    sc, rows = replay(6, 2.2)
    assert _robot_drove_off(sc, rows)
    assert {n for r in rows for n in r["names"]} == {"ball"}


def test_the_ball_is_told_from_the_looks_error_on_its_path_by_its_colour() -> None:
    # throw 45: the ball rolls from the first frame, slowly, so the first look leaves its
    # path unlearned (those pixels changed), and the render shows the scenario's guess of
    # the floor there.  The ball's schema was spawned on a region holding the ball and that
    # path; the path, ball-sized and shaped, was the nearer blob, and the schema followed
    # it while the ball rolled on, to be spawned for as an object the scenario does not
    # know at 0.77 s.  Of the blobs of the ball's size and outline, one of its colour is taken
    # first.
    sc, rows = replay(45, 1.2)
    assert {n for r in rows for n in r["names"]} == {"ball"}
    radius = sc.model("ball").ball.radius
    seen = [r for r in rows if r["observed"] is not None]
    assert len(seen) >= 15
    assert all(math.dist(r["observed"], r["truth"]) < 2 * radius for r in seen)


def test_a_lost_ball_is_not_found_again_on_floor_the_robot_uncovered() -> None:
    # held-out throw 112 at 640x480 (a camera inside the arena): the ball passes behind
    # obstacle0 at 1.1 s and is lost.  The robot, driving off, uncovers floor the first look
    # never saw (the render shows the scenario's guess there); a crescent of it, the ball's
    # size and outline but not its colour, was taken for the lost ball 1.5 m from where its
    # path went, 17 cm from the robot, whose agent said "caught" at 1.4 s and stopped.  An
    # object lost is found again only by a blob of its colour.
    sc, rows = replay(112, 1.6, small=False)
    start = sc.scene.robot.position
    assert max(math.dist(r["robot"], start) for r in rows) > sc.scene.robot.radius  # it drove
    seen, on = sightings(sc, rows)
    assert seen[:2] == on[:2] and len(on) >= 2  # seen before it is lost: the track exists
    assert seen == on, [(i, rows[i]["observed"], rows[i]["truth"]) for i in seen if i not in on]


def test_a_region_the_ball_left_is_no_longer_its() -> None:
    # throw 34: the ball's schema was spawned on a region holding the ball and the spot it
    # had rolled over while the look was first learned (the look's error there).  The
    # region stayed claimed by the ball's schema after the ball had rolled on, so it was
    # never repaired, and at 2.4 s, after the ball was missed for a few frames, the schema
    # took fragments of it for the ball, 1.5 m away.  Once the schema has found its object,
    # a region is its only where its object's box is.
    sc = throw(34, 1.6)
    stale: list[tuple[int, tuple[int, int, int, int]]] = []
    seen = []

    class Look:
        def frame(self, record: Any) -> None:
            # from the frame after it first found the ball (the regions of a frame are told
            # before the schemas look at it)
            if "ball" not in net or not isinstance(net["ball"], ForegroundObject) \
                    or net["ball"].sightings < 2:
                return
            seen.append(record.index)
            box = net["ball"].monitored_box()
            bg = record.background
            for r in () if bg is None else bg.regions:
                if r.owner == "ball" and (box is None or not _overlap(r.bbox, box)):
                    stale.append((record.index, r.bbox))

    runner = Runner(sc, out=None, seed=34, outputs=QUIET, listeners=(Look(),))
    net = runner.network
    runner.run()
    assert len(seen) > 20
    assert not stale, stale[:5]


def _overlap(a: tuple[int, int, int, int], b: tuple[int, int, int, int]) -> bool:
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]
