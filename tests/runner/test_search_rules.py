"""The search rules of ``rules/mirror/intercept.soar`` against a scripted input-link: a
camera on the robot that sees nothing of the goal's object looks round for it (bench
throws 5 and 35 of ``bench/foreign.py``: the ball rolled out of view while the first look
was learned, and no schema ever followed it)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from adapt.engine import Agent, OutputView
from adapt.engine.interface import InputLink

from .scripted import ScriptedNetwork, add_all

RULES = Path(__file__).resolve().parents[2] / "rules" / "mirror"


class Network(ScriptedNetwork):
    """Writes a goal (intercept the ball), a robot, the Scene Background and :attr:`schemas`
    in each input phase and carries out ``^instantiate`` and ``^remove``."""

    def __init__(self, mounted: bool = True, appearance: str = "learned") -> None:
        super().__init__()
        self.mounted = mounted
        self.appearance = appearance
        self.schemas: dict[str, dict[str, Any]] = {}

    def write(self, w: InputLink) -> None:
        self.acknowledge(w)
        for attr in ("schema", "goal", "robot"):
            w.clear(w.input_link, attr)
        goal = w.new_id("G")
        w.add(w.input_link, "goal", goal)
        w.add(goal, "name", "intercept")
        w.add(goal, "object", "ball")
        robot = w.new_id("R")
        w.add(w.input_link, "robot", robot)
        w.add(robot, "x", 0.0)
        bg = w.new_id("B")
        w.add(w.input_link, "schema", bg)
        add_all(w, bg, {"name": "background", "type": "scene-background", "kind": "perceptual",
                        "pixel-error": 0.2, "camera-moving": False, "mounted": self.mounted,
                        "appearance": self.appearance})
        for name, attrs in self.schemas.items():
            s = w.new_id("S")
            w.add(w.input_link, "schema", s)
            add_all(w, s, {"name": name, **attrs})

    def read(self, view: OutputView) -> None:
        for verb, attrs in self.commands(view):
            if verb == "remove":
                self.schemas.pop(attrs["name"], None)
            elif verb == "instantiate":
                kind = "perceptual" if attrs["type"] == "foreground-object" else "motor"
                self.schemas[attrs["name"]] = {"type": attrs["type"], "kind": kind,
                                               "object": attrs.get("object", "ball"),
                                               "status": "idle"}


def agent(net: Network) -> Agent:
    a = Agent()
    a.load_file(RULES / "perception.soar")
    a.load_file(RULES / "intercept.soar")
    a.on_input(net.write)
    a.on_output(net.read)
    return a


def test_a_camera_on_the_robot_that_sees_nothing_of_the_goals_object_looks_round() -> None:
    net = Network()
    a = agent(net)
    a.run(6)
    assert net.done == [("instantiate", {"name": "search", "type": "search",
                                         "object": "ball"})], net.done
    # the ball is seen: a schema follows it, the search ends (and the intercept begins)
    net.schemas["ball"] = {"type": "foreground-object", "kind": "perceptual",
                           "object": "ball", "status": "running"}
    a.run(6)
    assert ("remove", {"name": "search"}) in net.done, net.done
    assert "search" not in net.schemas
    # lost once it is imagined: the intercept schema faces the imagined body, no search
    net.schemas["ball"].update({"status": "lost", "imagined-x": 0.5})
    a.run(8)
    assert sum(1 for v, c in net.done if v == "instantiate" and c["type"] == "search") == 1
    # lost before the imagination had it (seen once): nothing to face, look round again
    del net.schemas["ball"]["imagined-x"]
    a.run(8)
    assert sum(1 for v, c in net.done if v == "instantiate" and c["type"] == "search") == 2
    assert "search" in net.schemas


@pytest.mark.parametrize("mounted, appearance", [(False, "learned"), (True, "structure")])
def test_no_search_from_a_fixed_camera_or_before_the_first_look(mounted: bool,
                                                                appearance: str) -> None:
    # a fixed camera sees what it sees whichever way the robot turns; a camera still
    # learning its first look must hold still
    net = Network(mounted=mounted, appearance=appearance)
    agent(net).run(8)
    assert not [c for v, c in net.done if c.get("type") == "search"], net.done


@pytest.mark.parametrize("status, imagined", [("running", False), ("waiting", False),
                                              ("lost", True)])
def test_no_search_for_an_object_a_schema_already_follows(status: str, imagined: bool) -> None:
    net = Network()
    net.schemas["ball"] = {"type": "foreground-object", "kind": "perceptual", "object": "ball",
                           "status": status}
    if imagined:
        net.schemas["ball"]["imagined-x"] = 0.5
    agent(net).run(8)
    assert not [c for v, c in net.done if c.get("type") == "search"], net.done
