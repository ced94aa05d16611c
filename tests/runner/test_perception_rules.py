"""The mirror's perception rules (``rules/mirror/perception.soar``) against a scripted
input-link: a small stand-in for the schema network writes schemas and regions as the
network does (``docs/schemas.md``) and carries out the commands the rules give.

The case is the ghost of issue 20: the goal's object was spawned on a region that never
showed it (the learned look's error where the ball stood while the look was learned), and
the real ball, moving, was taken for an object the scenario does not know.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import pytest

from adapt.engine import Agent, OutputView
from adapt.engine.interface import InputLink

from .scripted import ScriptedNetwork, add_all

RULES = Path(__file__).resolve().parents[2] / "rules" / "mirror" / "perception.soar"

#: A region's attributes as the Scene Background writes them (the ones the rules read).
GHOST = {"id": 1, "expected": True, "monitored-by": "ball", "age": 20, "size": 0.4,
         "still": False, "unseen": False, "at-edge": False}
BALL = {"id": 2, "expected": True, "monitored-by": "foreground-object-1", "age": 8,
        "size": 0.22, "still": False, "unseen": False, "at-edge": False, "looks-like": "ball"}


class Network(ScriptedNetwork):
    """Writes the input-link from :attr:`schemas` and :attr:`regions` in each input phase
    and carries out ``^remove`` and ``^instantiate`` (a region's new owner)."""

    def __init__(self, schemas: dict[str, dict[str, Any]], regions: list[dict[str, Any]],
                 camera_moving: bool = False):
        super().__init__()
        self.schemas = schemas
        self.regions = regions
        self.camera_moving = camera_moving

    def write(self, w: InputLink) -> None:
        self.acknowledge(w)
        w.clear(w.input_link, "schema")
        w.clear(w.input_link, "goal")
        goal = w.new_id("G")
        w.add(w.input_link, "goal", goal)
        w.add(goal, "name", "watch")
        w.add(goal, "object", "ball")
        bg = w.new_id("B")
        w.add(w.input_link, "schema", bg)
        add_all(w, bg, {"name": "background", "type": "scene-background", "kind": "perceptual",
                        "pixel-error": 0.2, "camera-moving": self.camera_moving})
        for region in self.regions:
            r = w.new_id("R")
            w.add(bg, "region", r)
            add_all(w, r, region)
        for name, attrs in self.schemas.items():
            s = w.new_id("S")
            w.add(w.input_link, "schema", s)
            add_all(w, s, {"name": name, **attrs})

    def read(self, view: OutputView) -> None:
        for verb, attrs in self.commands(view):
            if verb == "remove":
                self.schemas.pop(str(attrs["name"]), None)
                for region in self.regions:   # nobody monitors its region now
                    if region["monitored-by"] == attrs["name"]:
                        region.update({"expected": False, "monitored-by": "nil"})
            elif verb == "instantiate":
                name = str(attrs.get("name", f"foreground-object-{len(self.done)}"))
                self.schemas[name] = {"type": attrs["type"], "kind": "perceptual", "status": "waiting",
                                      "object": attrs.get("object", name), "frames-seen": 0,
                                      "declared": "object" in attrs, "seen": False}
                for region in self.regions:
                    if region["id"] == attrs.get("region"):
                        region.update({"expected": True, "monitored-by": name})


def run(net: Network, decisions: int = 12) -> list[tuple[str, dict[str, Any]]]:
    agent = Agent()
    agent.load_file(RULES)
    agent.on_input(net.write)
    agent.on_output(net.read)
    agent.run(decisions)
    return net.done


def stale_and_other() -> dict[str, dict[str, Any]]:
    return {"ball": {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                     "declared": True, "seen": False, "frames-seen": 0, "moved": False},
            "foreground-object-1": {"type": "foreground-object", "kind": "perceptual",
                                    "object": "foreground-object-1", "declared": False,
                                    "seen": True, "frames-seen": 9, "moved": True}}


@pytest.mark.parametrize("ghost_first", [True, False])
def test_the_goals_object_on_a_ghost_is_recognised_in_the_unknown_object_that_looks_like_it(
        ghost_first: bool) -> None:
    regions = [dict(GHOST), dict(BALL)]
    net = Network(stale_and_other(), regions if ghost_first else regions[::-1])
    done = run(net)
    removed = sorted(a["name"] for verb, a in done if verb == "remove")
    assert removed == ["ball", "foreground-object-1"], done
    # then the region that looks like the ball is spawned for it, before the ghost
    spawned = [a for verb, a in done if verb == "instantiate"]
    assert spawned[0] == {"type": "foreground-object", "region": 2, "object": "ball",
                          "name": "ball"}, done
    assert next(r for r in net.regions if r["id"] == 1)["monitored-by"] != "ball"


def test_nothing_is_recognised_once_the_goals_object_was_seen_or_the_other_looks_unlike_it(
) -> None:
    seen = stale_and_other()
    seen["ball"].update({"frames-seen": 3, "moved": True})  # it followed its object
    assert not [v for v, _ in run(Network(seen, [dict(GHOST), dict(BALL)]))
                if v == "remove"]
    unlike = dict(BALL)
    del unlike["looks-like"]
    assert not [v for v, _ in run(Network(stale_and_other(), [dict(GHOST), unlike]))
                if v == "remove"]


def run_twice(schemas: Callable[[], dict[str, dict[str, Any]]],
              regions: Callable[[], list[dict[str, Any]]]) -> Network:
    """One agent run, then the same input-link put back as it was and run again."""
    net = Network(schemas(), regions())
    agent = Agent()
    agent.load_file(RULES)
    agent.on_input(net.write)
    agent.on_output(net.read)
    agent.run(12)
    net.schemas, net.regions = schemas(), regions()
    agent.run(12)
    return net


def test_an_object_is_recognised_once() -> None:
    # the ball was spawned on its region; then the ghost's deadlock is put back as it was
    net = run_twice(stale_and_other, lambda: [dict(GHOST), dict(BALL)])
    assert sum(1 for v, _ in net.done if v == "remove") == 2, net.done


def lost() -> dict[str, dict[str, Any]]:
    return {"ball": {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                     "declared": True, "seen": False, "frames-seen": 40, "status": "lost"}}


def test_a_lost_goals_object_is_found_again_in_a_region_that_looks_like_it() -> None:
    moved = dict(BALL, **{"expected": False, "monitored-by": "nil", "age": 4})
    unlike = {k: v for k, v in moved.items() if k != "looks-like"}
    done = run(Network(lost(), [moved]))
    assert [v for v, _ in done][:2] == ["remove", "instantiate"], done
    assert done[1][1] == {"type": "foreground-object", "region": 2, "object": "ball",
                          "name": "ball"}
    # a region that does not look like it is something else: an object of its own
    done = run(Network(lost(), [unlike]))
    assert [(v, "object" in a) for v, a in done] == [("instantiate", False)], done


def never_seen() -> dict[str, dict[str, Any]]:
    return {"ball": {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                     "declared": True, "seen": False, "frames-seen": 0, "frames-missed": 5,
                     "status": "waiting", "region": 1}}


def test_the_goals_object_never_seen_is_spawned_for_a_region_that_looks_like_it() -> None:
    # held-out throw 110 of bench/foreign.py: the ball's schema was spawned on a region that
    # never showed it, and the ball, moving in view, was spawned for as an object the
    # scenario does not know, to be recognised as the ball a frame later -- a schema that
    # never was.  The never-seen schema gives way, and the region is spawned for the ball.
    moving = dict(BALL, **{"expected": False, "monitored-by": "nil", "age": 4})
    net = Network(never_seen(), [dict(GHOST, still=True), moving])  # (the look's error)
    done = run(net)
    assert [v for v, _ in done][:2] == ["remove", "instantiate"], done
    assert done[0][1] == {"name": "ball"}
    assert done[1][1] == {"type": "foreground-object", "region": 2, "object": "ball",
                          "name": "ball"}
    assert not [a for v, a in done if v == "instantiate" and "object" not in a], done


def test_the_goals_object_never_seen_gives_way_once_and_not_to_everything() -> None:
    moving = dict(BALL, **{"expected": False, "monitored-by": "nil", "age": 4})
    # once: the region spawned for it, never seen either, keeps it against the next one
    net = run_twice(never_seen, lambda: [dict(GHOST), dict(moving)])
    assert sum(1 for v, _ in net.done if v == "remove") == 1, net.done
    # a schema that has not looked for three frames yet keeps it
    young = never_seen()
    young["ball"]["frames-missed"] = 2
    assert not [v for v, _ in run(Network(young, [dict(GHOST), dict(moving)])) if v == "remove"]
    # a schema that has seen its object keeps it
    seen = never_seen()
    seen["ball"].update({"frames-seen": 5, "status": "running"})
    assert not [v for v, _ in run(Network(seen, [dict(GHOST), dict(moving)])) if v == "remove"]
    # nor for a region that does not look like it, holds still, or from a moving camera
    unlike = {k: v for k, v in moving.items() if k != "looks-like"}
    for regions, camera_moving in (([dict(GHOST), unlike], False),
                                   ([dict(GHOST), dict(moving, still=True)], False),
                                   ([dict(GHOST), dict(moving)], True)):
        done = run(Network(never_seen(), regions, camera_moving=camera_moving))
        assert not [v for v, _ in done if v == "remove"], (regions, camera_moving, done)


@pytest.mark.parametrize("lost_ball", [False, True])
def test_a_region_on_surfaces_the_look_never_learned_is_never_spawned_for(lost_ball: bool) -> None:
    # the floor the robot stood on while the look was first learned, uncovered since: the
    # look's ignorance, not an object arriving (nor the lost ball found again), however
    # much it looks like the ball
    schemas = lost() if lost_ball else {}
    region = dict(BALL, **{"expected": False, "monitored-by": "nil", "age": 4})
    assert [v for v, _ in run(Network(dict(schemas), [region]))][-1:] == ["instantiate"]
    region["unseen"] = True
    assert run(Network(dict(schemas), [region])) == []


@pytest.mark.parametrize("moving", [False, True])
def test_a_camera_the_robot_drives_spawns_only_for_a_declared_object_nothing_follows(
        moving: bool) -> None:
    # while the robot's odometry moves its camera, the difference holds the camera's own
    # motion's errors (parallax, blur, a texture aliased anew): on bench/foreign.py's robot
    # cameras these were all but 2 of the 89 spurious schemas in 50 throws
    tracked = {"ball": {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                        "declared": True, "seen": True, "frames-seen": 40, "status": "running"}}
    unknown = {k: v for k, v in BALL.items() if k != "looks-like"}
    unknown.update({"expected": False, "monitored-by": "nil", "age": 4})
    done = run(Network(dict(tracked), [dict(unknown)], camera_moving=moving))
    assert [v for v, _ in done] == ([] if moving else ["instantiate"]), done
    # the goal's object itself is found from a moving camera: no schema follows it yet ...
    like = dict(unknown, **{"looks-like": "ball"})
    done = run(Network({}, [dict(like)], camera_moving=moving))
    assert done == [("instantiate", {"type": "foreground-object", "region": 2,
                                     "object": "ball", "name": "ball"})], done
    # ... but a region that looks like an object a schema follows, or lost, is that object
    # for its schema to find, or the floor's texture seen anew in its colour (robot camera 32
    # of bench/foreign.py: its lost ball's schema was moved onto such patches of a white
    # floor, and 5 objects the scenario does not know were spawned for the others): it is
    # spawned for, or the lost object found again in it, only from a camera that holds still
    done = run(Network(dict(tracked), [dict(like)], camera_moving=moving))
    assert [v for v, _ in done] == ([] if moving else ["instantiate"]), done
    done = run(Network(lost(), [dict(like)], camera_moving=moving))
    assert [v for v, _ in done][:2] == ([] if moving else ["remove", "instantiate"]), done


def test_the_goals_object_on_a_ghost_of_its_own_shape_is_recognised_once_the_other_moves() -> None:
    # held-out throw 124 of bench/foreign.py: the first look, learned from two frames, took
    # in the ball where it stood (green on grass: too few pixels changed to say something
    # moved); the ball's schema was spawned on that ghost, which shows a ball and is "seen"
    # every frame, while the real ball, rolling, was taken for an object the scenario does
    # not know
    ghost = stale_and_other()
    ghost["ball"].update({"seen": True, "frames-seen": 40})
    done = run(Network(ghost, [dict(GHOST), dict(BALL)]))
    assert sorted(a["name"] for v, a in done if v == "remove") == ["ball", "foreground-object-1"]
    assert [a for v, a in done if v == "instantiate"][0]["region"] == 2, done
    # not while the other has not moved either, nor once the goal's object has moved
    for schema, moved in (("foreground-object-1", False), ("ball", True)):
        held = stale_and_other()
        held["ball"].update({"seen": True, "frames-seen": 40})
        held[schema]["moved"] = moved
        assert not [v for v, _ in run(Network(held, [dict(GHOST), dict(BALL)])) if v == "remove"]


def test_a_still_region_is_spawned_for_only_as_the_goals_object_nothing_follows() -> None:
    # robot camera 17 of bench/foreign.py: the ball came to rest out of sight and was found
    # by looking round; its region held still, as the learned look's error does, so nothing
    # was spawned for it and the robot held still before it for the rest of the throw
    resting = dict(BALL, **{"expected": False, "monitored-by": "nil", "age": 6, "still": True})
    done = run(Network({}, [dict(resting)]))
    assert done == [("instantiate", {"type": "foreground-object", "region": 2,
                                     "object": "ball", "name": "ball"})], done
    # a still region that does not look like the goal's object is the look's error (a ghost
    # shows what lay under the object), one on surfaces never learned its ignorance; from a
    # camera the robot moves, or one that is not in step, nothing is still
    unlike = {k: v for k, v in resting.items() if k != "looks-like"}
    assert run(Network({}, [unlike])) == []
    assert run(Network({}, [dict(resting, unseen=True)])) == []
    assert run(Network({}, [dict(resting)], camera_moving=True)) == []
    # once a schema follows the goal's object (or has lost it), a still region is not it
    tracked = {"ball": {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                        "declared": True, "seen": True, "frames-seen": 40, "status": "running"}}
    assert run(Network(tracked, [dict(resting)])) == []
    assert run(Network(lost(), [dict(resting)])) == []
