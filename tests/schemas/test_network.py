"""The schema network: instantiation, parameters, ports and order, commands from the rules,
statuses on the input-link, events."""

from __future__ import annotations

import math
from types import MappingProxyType

import pytest

from adapt.engine import Agent
from adapt.errors import ScenarioError, SchemaError
from adapt.geometry import Camera
from adapt.imagination import Ball, RobotSpec, SceneSpec
from adapt.mirror import Mirror
from adapt.scenario import SchemaSettings, Source
from adapt.schemas import REGISTRY, EventKind, Origin, SchemaNetwork, Status, check_settings

CAM = Camera.look_at(fx=200, fy=200, cx=80, cy=60, width=160, height=120,
                     position=(0, -2, 1), look_at=(0, 1, 0))


def network(robot: bool = True) -> SchemaNetwork:
    scene = SceneSpec(robot=RobotSpec(position=(0.0, -1.0), max_speed=1.0, max_accel=2.0)
                      if robot else None)
    return SchemaNetwork(Mirror(scene, CAM))


def test_instantiation_connects_ports_and_orders_providers_first() -> None:
    net = network()
    events = []
    net.listeners.append(events.append)
    drive = net.instantiate("drive")
    fo = net.instantiate("foreground-object", origin=Origin.BOTTOM_UP)
    bg = net.instantiate("scene-background")
    # the provider comes first, then the consumers in creation order
    assert net.names == [bg.name, drive.name, fo.name] == ["scene-background", "drive-1",
                                                           "foreground-object-1"]
    edges = {(a, b, port) for a, b, d in net.graph.edges(data=True) for port in d["ports"]}
    assert edges == {(bg.name, drive.name, "camera"), (bg.name, fo.name, "regions")}
    assert [e.kind.value for e in events] == ["instantiated", "spawned", "instantiated"]
    assert fo.origin is Origin.BOTTOM_UP and drive.status is Status.IDLE
    sub = net.subscene()
    assert {n["name"] for n in sub["nodes"]} == {bg.name, drive.name, fo.name}
    net.remove(fo.name)
    assert fo.name not in net and events[-1].kind is EventKind.REMOVED


@pytest.mark.parametrize("call, message", [
    (lambda n: n.instantiate("scene-backgrund"), "did you mean 'scene-background'"),
    (lambda n: n.instantiate("drive", parameters={"speeed": 1}), "unknown parameter 'speeed'"),
    (lambda n: n.instantiate("drive", parameters={"speed": 2}), "at most 1"),
    (lambda n: n.instantiate("foreground-object", parameters={"object": "nothing"}),
     "no object called 'nothing'"),
])
def test_bad_instantiations(call, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SchemaError, match=message):
        call(network())


def test_singletons_names_and_robots() -> None:
    net = network()
    net.instantiate("scene-background")
    with pytest.raises(SchemaError, match="only one"):
        net.instantiate("scene-background")
    net.instantiate("drive", "go")
    with pytest.raises(SchemaError, match="already exists"):
        net.instantiate("drive", "go")
    with pytest.raises(SchemaError, match="no robot"):
        network(robot=False).instantiate("drive")


def test_scenario_settings_are_checked_with_positions() -> None:
    src = Source("s.yaml", 7, 3, "schemas.drive", "  drive: {speed: 3}")
    good = SchemaSettings("drive", MappingProxyType({"speed": 0.5}), src,
                          MappingProxyType({"speed": src}))
    assert check_settings([good]) == {"drive": {"speed": 0.5}}
    bad = SchemaSettings("drive", MappingProxyType({"speed": 3}), src,
                         MappingProxyType({"speed": Source("s.yaml", 7, 19, "schemas.drive.speed")}))
    with pytest.raises(ScenarioError) as info:
        check_settings([bad])
    assert str(info.value).startswith("s.yaml:7:19: schemas.drive.speed: expected at most 1")
    unknown = SchemaSettings("driv", MappingProxyType({}), src)
    with pytest.raises(ScenarioError, match="did you mean 'drive'"):
        check_settings([unknown])
    # the scenario's values sit between the defaults and the rules' own
    net = SchemaNetwork(Mirror(SceneSpec(robot=RobotSpec(max_speed=1, max_accel=1)), CAM),
                        settings=[good])
    assert net.instantiate("drive").parameters["speed"] == 0.5
    assert net.instantiate("drive", parameters={"speed": 0.25}).parameters["speed"] == 0.25


RULES = """
sp {propose*make (state <s> ^superstate nil ^io.input-link <in> ^io.output-link <out>)
   -(<in> ^schema.type drive) -(<out> ^instantiate)
-->  (<s> ^operator <o> + =) (<o> ^name make)}
sp {apply*make (state <s> ^operator.name make ^io.output-link <out>)
-->  (<out> ^instantiate <c>) (<c> ^type drive ^name mover ^speed 0.5)
     (<out> ^instantiate <d>) (<d> ^type nonsense)}
sp {propose*go (state <s> ^superstate nil ^io.input-link.schema <m> ^io.output-link <out>)
   (<m> ^name mover ^status idle) -(<out> ^command)
-->  (<s> ^operator <o> + =) (<o> ^name go)}
sp {apply*go (state <s> ^operator.name go ^io.output-link <out>)
-->  (<out> ^command <c>) (<c> ^schema mover ^x 0.5 ^y -1.0)}
sp {seen (state <s> ^io.output-link.<v> <c>) (<c> ^status <st>)
-->  (write <v> | | <st> (crlf))}
sp {wait (state <s> ^superstate nil -^operator.name wait) --> (<s> ^operator <o> + <) (<o> ^name wait)}
"""


def test_rules_drive_the_network_through_the_links() -> None:
    net = network()
    agent = Agent(seed=1)
    agent.load_text(RULES)
    agent.on_input(net.write_input)
    agent.on_output(net.on_output)
    out = []
    agent.on_write(out.append)
    for frame in range(8):
        agent.run(2, footer=False)
        net.act(frame / 30)
    text = "".join(out)
    assert "instantiate complete" in text and "instantiate error" in text
    assert "command complete" in text
    mover = net["mover"]
    assert mover.parameters["speed"] == 0.5 and mover.status is Status.EXECUTING
    assert mover.target == (0.5, -1.0)
    # the error says what was wrong
    msgs = [w.value for w in agent.wm if w.attr == "message"]
    assert any("unknown schema type 'nonsense'" in str(m) for m in msgs)
    # the input-link shows the schema and the robot
    schema_ids = [w.value for w in agent.wm if w.attr == "schema" and w.id == agent.input_link]
    assert len(schema_ids) == 1
    assert any(w.attr == "robot" for w in agent.wm if w.id == agent.input_link)


def test_the_drive_schema_reaches_its_target_and_refuses_obstacles() -> None:
    from adapt.imagination import Obstacle

    scene = SceneSpec(robot=RobotSpec(position=(0.0, 0.0), max_speed=1.0, max_accel=2.0),
                      obstacles=(Obstacle("box", ((2, 2), (3, 2), (3, 3), (2, 3)), 0.5),))
    mirror = Mirror(scene, CAM)
    net = SchemaNetwork(mirror)
    d = net.instantiate("drive")
    assert d.command({"x": 1.0, "y": 0.5}) is None
    t = 0.0
    while d.status is Status.EXECUTING and t < 5:
        net.act(t)
        t += 1 / 30
        mirror.step_to(t)
    assert d.status is Status.COMPLETE
    x, y = mirror.world.position(scene.robot.name)  # type: ignore[union-attr]
    assert abs(x - 1.0) < 0.06 and abs(y - 0.5) < 0.06
    assert d.command({"x": 2.5, "y": 2.5}) is None and d.status is Status.FAILED
    assert "inside obstacle 'box'" in d.message
    assert "needs ^x and ^y" in str(d.command({"x": 1}))
    assert d.command({"stop": "yes"}) is None and d.status is Status.IDLE


def test_the_registry_lists_every_builtin_type() -> None:
    from adapt.plugins import BUILTIN

    builtin = [s for s in REGISTRY if REGISTRY.origin(s.name) == BUILTIN]  # not a plugin's
    assert [s.name for s in builtin] == ["drive", "foreground-object", "intercept",
                                         "scene-background", "search"]
    for spec in builtin:
        data = spec.as_json()
        assert data["name"] == spec.name and data["parameters"]


def test_the_drive_schema_goes_round_an_obstacle_in_its_way() -> None:
    from adapt.imagination import Obstacle

    box = Obstacle("box", ((-0.6, 1.0), (0.6, 1.0), (0.6, 1.6), (-0.6, 1.6)), 0.5)
    scene = SceneSpec(robot=RobotSpec(position=(0.0, 0.0), max_speed=1.0, max_accel=2.0),
                      obstacles=(box,))
    mirror = Mirror(scene, CAM)
    net = SchemaNetwork(mirror)
    d = net.instantiate("drive")
    assert d.command({"x": 0.0, "y": 2.6}) is None
    assert len(d.footprint.route((0.0, 0.0), (0.0, 2.6)) or []) == 3  # round one side
    t, closest = 0.0, 9.0
    while d.status is Status.EXECUTING and t < 12:
        net.act(t)
        t += 1 / 30
        mirror.step_to(t)
        x, y = mirror.world.position(scene.robot.name)  # type: ignore[union-attr]
        closest = min(closest, max(abs(x) - 0.6, abs(y - 1.3) - 0.3))
    assert d.status is Status.COMPLETE, (t, mirror.world.position("robot"))
    assert closest >= d.footprint.radius - 0.02  # never pressed against the box


def test_an_object_is_never_created_where_another_body_is() -> None:
    from adapt.imagination import Ball

    net = network()
    net.mirror.add_ball(Ball("ball", radius=0.1), (0.0, 1.0), (0.0, 0.0))
    fo = net.instantiate("foreground-object", origin=Origin.BOTTOM_UP)
    assert fo.overlaps((0.15, 1.0), 0.1) == "ball"          # a fragment of the ball
    assert fo.overlaps((0.0, -0.8), 0.1) == "robot"         # the robot's own body
    assert fo.overlaps((1.0, 1.0), 0.1) is None
    fo.ball = Ball(fo.body, radius=0.1)
    fo.kf.step(0.0, (0.1, 1.0))
    fo._create_body(None)  # type: ignore[arg-type]
    assert not fo.in_imagination
    fo.kf = type(fo.kf)(q=0.3, r=0.005)
    fo.kf.step(0.0, (1.0, 1.0))
    fo._create_body(None)  # type: ignore[arg-type]
    assert fo.in_imagination


def test_a_consumer_reads_its_providers_percepts_through_its_edges() -> None:
    from dataclasses import dataclass

    from adapt.schemas import Port, Schema, SchemaKind, SchemaSpec
    from adapt.schemas.percepts import BackgroundPercept

    @dataclass(frozen=True)
    class Note:
        text: str

    def spec(name: str, provides: tuple[str, ...] = (), consumes: tuple[str, ...] = ()) -> SchemaSpec:
        return SchemaSpec(name, SchemaKind.PERCEPTUAL, "a test type",
                          factory=lambda n, p, net: Schema(n, specs[name], p, net),
                          provides=tuple(Port(x) for x in provides),
                          consumes=tuple(Port(x) for x in consumes), singleton=False)

    specs = {"writer": spec("writer", provides=("note",)),
             "reader": spec("reader", consumes=("note",)),
             "bystander": spec("bystander", consumes=("other",))}
    registry = REGISTRY.copy()
    for s in specs.values():
        registry.register(s)
    net = SchemaNetwork(Mirror(SceneSpec(), CAM), registry=registry)
    writer, reader = net.instantiate("writer"), net.instantiate("reader")
    bystander = net.instantiate("bystander")
    assert net.percepts(reader, "note", Note) == []
    net.publish(writer, Note("hello"))
    assert net.percepts(reader, "note", Note) == [Note("hello")]
    assert net.percept(reader, "note", BackgroundPercept) is None     # typed: another kind
    assert net.percepts(bystander, "note", Note) == []                 # no edge, no percept
    assert net.published(Note) == [Note("hello")]
    with pytest.raises(SchemaError, match="does not provide a port 'other'"):
        net.publish(writer, Note("x"), port="other")
    net.remove(writer.name)
    assert net.percepts(reader, "note", Note) == [] and net.published(Note) == []


def test_a_region_has_one_owner_and_an_object_one_monitor() -> None:
    from adapt.imagination import Ball
    from adapt.scenario import ObjectModel

    net = SchemaNetwork(Mirror(SceneSpec(), CAM), models={"ball": ObjectModel(Ball("ball"))})
    net.instantiate("foreground-object", parameters={"object": "ball"})
    assert net.monitor_of("ball") == "foreground-object-1"
    with pytest.raises(SchemaError, match="object 'ball' is already monitored"):
        net.instantiate("foreground-object", parameters={"object": "ball"})
    # spawned for a region no provider reports: it claims nothing
    fo = net.instantiate("foreground-object", parameters={"region": 7}, origin=Origin.BOTTOM_UP)
    assert fo.claimed_regions() == () and net.claims() == {}
    # a second schema for the same region is refused: a region has one owner
    with pytest.raises(SchemaError, match=f"region 7 already has an owner, schema '{fo.name}'"):
        net.instantiate("foreground-object", parameters={"region": 7}, origin=Origin.BOTTOM_UP)
    net.remove(fo.name)
    assert net.instantiate("foreground-object", parameters={"region": 7}).parameters["region"] == 7


def test_removing_an_unknown_objects_schema_takes_its_body_and_a_declared_ones_stays() -> None:
    from adapt.scenario import ObjectModel

    net = SchemaNetwork(Mirror(SceneSpec(), CAM), models={"ball": ObjectModel(Ball("ball"))})
    known = net.instantiate("foreground-object", parameters={"object": "ball"})
    unknown = net.instantiate("foreground-object", parameters={"region": 3},
                              origin=Origin.BOTTOM_UP)
    for name, x in (("ball", -0.5), (unknown.name, 0.5)):
        net.mirror.add_ball(Ball(name, radius=0.1), (x, 0.5), (0.0, 0.0))
    net.remove(unknown.name)
    net.remove(known.name)
    assert not net.mirror.has_body(unknown.name)   # nothing else would pull it
    assert net.mirror.has_body("ball")             # the world declares it


def test_a_schema_spawned_in_a_frame_looks_at_that_frame_once() -> None:
    # spawned for a region of frame k (during the decisions that follow its perception), a
    # perceptual schema looks at frame k too, not first at k + 1; one put in place top-down,
    # and one spawned before the frame was perceived, do not look twice
    import numpy as np

    from adapt.frames import Frame
    from adapt.schemas import Schema, SchemaKind, SchemaSpec

    seen: dict[str, list[int]] = {}

    class Looker(Schema):
        def perceive(self, frame: Frame) -> None:
            seen.setdefault(self.name, []).append(frame.index)

    spec = SchemaSpec("looker", SchemaKind.PERCEPTUAL, "a test type",
                      factory=lambda n, p, net: Looker(n, spec, p, net), singleton=False)
    registry = REGISTRY.copy()
    registry.register(spec)
    net = SchemaNetwork(Mirror(SceneSpec(), CAM), registry=registry)
    frames = [Frame(k, k / 30, np.zeros((120, 160, 3), np.uint8)) for k in range(3)]
    early = net.instantiate("looker", origin=Origin.BOTTOM_UP)  # before any frame
    net.perceive(frames[0])
    net.perceive_spawned()
    top = net.instantiate("looker")                              # top-down, in frame 0
    spawned = net.instantiate("looker", origin=Origin.BOTTOM_UP)  # bottom-up, in frame 0
    net.perceive_spawned()
    net.perceive_spawned()                                       # once only
    net.perceive(frames[1])
    net.perceive_spawned()
    assert seen[early.name] == [0, 1]
    assert seen[top.name] == [1]
    assert seen[spawned.name] == [0, 1]


@pytest.mark.parametrize("heading_deg, middle_side", [(0.0, 1.0), (180.0, -1.0)])
def test_the_search_schema_waits_then_turns_towards_the_middle_and_stops_on_removal(
        heading_deg: float, middle_side: float) -> None:
    import math

    from adapt.imagination import Floor

    # the robot in the floor's south-west part: the middle is to its left facing +x, to its
    # right facing -x
    scene = SceneSpec(floor=Floor(extent=(-2.0, -2.0, 2.0, 2.0)),
                      robot=RobotSpec(position=(-1.0, -1.0), heading_deg=heading_deg,
                                      max_speed=1.0, max_accel=2.0))
    mirror = Mirror(scene, CAM)
    net = SchemaNetwork(mirror)
    s = net.instantiate("search", parameters={"object": "ball", "turn_rate": 1.0, "delay": 0.5})
    t = 0.0
    headings = []
    while t < 2.0:
        net.act(t)
        t += 1 / 30
        mirror.step_to(t)
        pose = mirror.robot_pose()
        assert pose is not None and math.dist(pose[0], (-1.0, -1.0)) < 1e-6  # in place
        headings.append(pose[1])
        if t < 0.45:
            assert s.status is Status.IDLE
    assert s.status is Status.EXECUTING and s.direction == middle_side
    turned = (headings[-1] - headings[0] + math.pi) % (2 * math.pi) - math.pi
    assert turned * middle_side == pytest.approx(1.5, abs=0.1)  # 1 rad/s for 1.5 s
    assert s.turned == pytest.approx(1.5, abs=0.1)
    net.remove(s.name)
    mirror.step_to(t + 0.5)
    assert mirror.world.robot_command == (0.0, 0.0, 0.0)
    with pytest.raises(SchemaError, match="no robot"):
        network(robot=False).instantiate("search")


def test_the_search_schema_holds_still_while_a_region_looks_like_its_object() -> None:
    from adapt.schemas.percepts import BackgroundPercept, RegionReport

    scene = SceneSpec(robot=RobotSpec(position=(0.0, -1.0), max_speed=1.0, max_accel=2.0))
    mirror = Mirror(scene, CAM)
    net = SchemaNetwork(mirror)
    bg = net.instantiate("scene-background", parameters={"appearance": "off"})
    s = net.instantiate("search", parameters={"object": "ball", "delay": 0.0})
    region = RegionReport(7, (10, 10, 8, 8), (14.0, 14.0), 50, 4, False, None, (0.0, 1.0), 0.2,
                          looks_like="ball")
    for regions, turning in (((), True), ((region,), False), ((), True)):
        net.publish(bg, BackgroundPercept(frame=0, time=0.0, camera_before=CAM,
                                          camera_after=CAM, regions=regions))
        net.act(0.0)
        assert s.holding is (not turning)
        assert (mirror.world.robot_command[2] != 0.0) is turning


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_the_search_schema_turns_towards_a_region_like_its_object_cut_by_the_frames_side(
        side: float) -> None:
    import math

    from adapt.schemas.percepts import BackgroundPercept, RegionReport

    # robot camera 17 of bench/foreign.py: the ball came into view at the frame's side and
    # the robot held still with it cut there, where the rules spawn no schema for it
    scene = SceneSpec(robot=RobotSpec(position=(0.0, -1.0), max_speed=1.0, max_accel=2.0))
    mirror = Mirror(scene, CAM)
    net = SchemaNetwork(mirror)
    bg = net.instantiate("scene-background", parameters={"appearance": "off"})
    s = net.instantiate("search", parameters={"object": "ball", "delay": 0.0, "turn_rate": 1.0})
    # a region half a radian to the robot's left is counter-clockwise (+1), to its right not
    (x, y), heading = mirror.robot_pose()  # type: ignore[misc]
    floor = (x + math.cos(heading + side * 0.5), y + math.sin(heading + side * 0.5))
    left = side > 0
    bbox = (0, 10, 8, 8) if left else (CAM.width - 8, 10, 8, 8)
    cut = RegionReport(7, bbox, (4.0, 14.0), 50, 4, False, None, floor, 0.2, at_edge=True,
                       looks_like="ball")
    inside = RegionReport(8, (40, 10, 8, 8), (44.0, 14.0), 50, 4, False, None, floor, 0.2,
                          looks_like="ball")
    for regions, holding, turn in (((cut,), False, side), ((cut, inside), True, 0.0)):
        net.publish(bg, BackgroundPercept(frame=0, time=0.0, camera_before=CAM,
                                          camera_after=CAM, regions=regions))
        net.act(0.0)
        assert s.holding is holding
        assert mirror.world.robot_command[2] == pytest.approx(turn)


def test_a_doubted_imagined_body_is_never_caught() -> None:
    # bench/foreign.py's throw 50 (a camera on the robot): the ball lost, its imagined body in
    # view for frames and not found there, the robot drove to it and the agent said "caught"
    # 1 m from the ball; the intercept schema's ^caught takes the imagined body only while
    # the ball's schema does not doubt it
    from adapt.schemas.intercept import Intercept
    from adapt.schemas.percepts import ObjectPercept, Sighting

    net = network()
    ic = net.instantiate("intercept", parameters={"object": "ball"})
    assert isinstance(ic, Intercept)
    ball = Ball("ball", radius=0.1)

    def sees(**kw: object) -> None:
        ic.watched = lambda: ObjectPercept(frame=0, time=0.0, object="ball", ball=ball,  # type: ignore[method-assign]
                                           **kw)  # type: ignore[arg-type]

    sees(imagined=(0.0, -0.7))  # at the robot's feet, below its camera: caught
    assert ic.object_distance() == pytest.approx(0.3)
    sees(imagined=(0.0, -0.7), doubted=True)  # the imagination's error: no distance, no catch
    assert ic.object_distance() is None
    seen = Sighting(0, 0.0, (0, 0, 1, 1), (0.0, 0.0), 1, (0.0, -0.75))
    sees(imagined=(0.0, -0.7), doubted=True, sighting=seen, position=(0.0, -0.75))
    assert ic.object_distance() == pytest.approx(0.25)  # seen: the sighting, doubted or not


def test_the_robot_turns_to_face_its_object_and_holds_still_once_it_does() -> None:
    # bench/foreign.py's throw 23 (a camera on the robot): the gaze's turn rate decayed with
    # the heading error and never reached zero, so the camera was "moving" (its history
    # restarted, no lost object found again) for two seconds while it faced the ball; now it
    # starts past GAZE_START_STOP[0] degrees and stops within GAZE_START_STOP[1]
    from adapt.schemas.intercept import GAZE_GAIN, GAZE_START_STOP, Intercept
    from adapt.schemas.percepts import ObjectPercept

    net = network()  # the robot at (0, -1), heading +x
    ic = net.instantiate("intercept", parameters={"object": "ball", "turn_rate": 1.5})
    assert isinstance(ic, Intercept)
    ball = Ball("ball", radius=0.1)

    def bearing(deg: float) -> float:
        """The gaze's command for an object ``deg`` degrees to the robot's left, 2 m away."""
        at = (2.0 * math.cos(math.radians(deg)), -1.0 + 2.0 * math.sin(math.radians(deg)))
        ic.watched = lambda: ObjectPercept(frame=0, time=0.0, object="ball", ball=ball,  # type: ignore[method-assign]
                                           imagined=at)
        ic._gaze()
        return net.mirror.world.robot_command[2]

    start, stop = GAZE_START_STOP
    assert bearing(0.8 * start) == 0.0  # facing it well enough: no turn
    assert bearing(1.5 * start) == pytest.approx(GAZE_GAIN * math.radians(1.5 * start), rel=1e-3)
    # once turning it turns on down to the stop, then holds still
    assert bearing(0.8 * start) == pytest.approx(GAZE_GAIN * math.radians(0.8 * start), rel=1e-3)
    assert bearing(2.0 * stop) > 0.0
    assert bearing(0.5 * stop) == 0.0
    assert bearing(0.8 * start) == 0.0
    assert bearing(-30.0) == pytest.approx(-1.5)  # to the right, at most turn_rate
