"""The schema network: the paper's minimal subscene as a networkx DiGraph.

Nodes are schema instances (by name, the instance in the node's ``schema``
attribute); an edge ``a -> b`` with a ``ports`` attribute says that ``a``
provides what ``b`` consumes on those ports.  Perceptual schemas perceive in
the graph's topological order, so a provider has looked at the frame before
its consumers do.

**Ports carry percepts.**  A provider publishes a frozen record on each port
it provides (:meth:`SchemaNetwork.publish`; :mod:`adapt.schemas.percepts`),
and a consumer reads its providers' records on a port through the graph's
in-edges with that port (:meth:`SchemaNetwork.percepts`), never through
another schema's members.  What a schema tells the network about itself is
the base class's: the image box it explains (:meth:`Schema.monitored_box
<adapt.schemas.base.Schema.monitored_box>`), the difference regions it claims
(:meth:`~adapt.schemas.base.Schema.claimed_regions`; a region has at most one
owner) and the world object it monitors
(:meth:`~adapt.schemas.base.Schema.monitored_object`; an object has at most
one).  Outside the schemas (the runner's outputs) the percepts are read with
:meth:`SchemaNetwork.published`.

The network is driven by the rules, never by Python code straight from the
goals (paper section 3.1: put in place partly top-down by the problem
solver, partly bottom-up by perception):

* **input phase** (:meth:`SchemaNetwork.write_input`): the frame, the goals,
  the robot's odometry and every schema's own structure are written on the
  input-link, and each command the network has handled gets ``^status``;
* **output phase** (:meth:`SchemaNetwork.on_output`): new commands on the
  output-link are carried out: ``^instantiate`` (a schema of a type, with
  parameters; *spawned* bottom-up when it names a difference ``^region``),
  ``^remove``, and ``^command`` (addressed to a motor schema).

Every change is an event (:class:`SchemaEvent`) for the trace; the network
as a whole is :meth:`SchemaNetwork.subscene`.  The layout of both links is
documented in ``docs/schemas.md``.
"""

from __future__ import annotations

import difflib
from time import perf_counter
from typing import TYPE_CHECKING, Any, Callable, Iterator, Mapping, Sequence, TypeVar

import networkx as nx
import numpy as np

from adapt.engine.interface import InputLink, OutputView
from adapt.engine.symbols import Identifier
from adapt.errors import SchemaError
from adapt.scenario import RealityKind
from adapt.schemas.base import BBox, Origin, Schema, Status
from adapt.schemas.events import EventKind, SchemaEvent
from adapt.schemas.links import Command, Structure, read_commands
from adapt.schemas.registry import REGISTRY, Registry
from adapt.schemas.spec import ParameterError, SchemaKind, SchemaSpec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.frames import Actuator, Frame
    from adapt.imagination.scene import RobotSpec
    from adapt.mirror import Mirror
    from adapt.scenario import Goal, ObjectModel, PredictSettings, SchemaSettings

__all__ = ["SchemaNetwork", "SchemaEvent", "EventKind", "check_settings"]

#: A percept type, for the typed accessors.
P = TypeVar("P")


def check_settings(settings: Sequence["SchemaSettings"], registry: Registry = REGISTRY
                   ) -> dict[str, dict[str, Any]]:
    """Check a scenario's ``schemas`` section against the registry.

    Returns the checked parameters per type; raises a positioned
    :class:`~adapt.errors.ScenarioError` for an unknown type, an unknown
    parameter or a bad value.
    """
    out: dict[str, dict[str, Any]] = {}
    for s in settings:
        try:
            spec = registry.get(s.type)
        except SchemaError as exc:
            raise s.source.error(str(exc)) from None
        checked: dict[str, Any] = {}
        names = [p.name for p in spec.parameters]
        for key, value in s.parameters.items():
            src = s.parameter_sources.get(key, s.source)
            if key not in names:
                close = difflib.get_close_matches(key, names, n=1, cutoff=0.6)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise src.error(f"unknown parameter of {spec.name}{hint}; expected one of "
                                + ", ".join(names))
            try:
                checked[key] = spec.parameter(key).check(value)
            except ParameterError as exc:
                raise src.error(str(exc)) from None
        out[s.type] = checked
    return out


class SchemaNetwork:
    """The instantiated schemas and their port connections (see the module docstring).

    Parameters
    ----------
    mirror : Mirror
        The imagination the schemas keep in step with reality.
    registry : Registry
        Schema types by name.
    settings : sequence of SchemaSettings
        The scenario's ``schemas`` section (checked here).
    models : mapping of str to ObjectModel
        The declared objects, by name.
    goals : sequence of Goal
        Written on the input-link.
    actuator : Actuator or None
        The real robot, for motor schemas.
    predict : PredictSettings, optional
        Horizons, cadence and ensemble size of object schemas' predictions.
    rng : Generator, optional
        The prediction ensembles' random stream.
    frame_interval : float
        Seconds between frames.
    reality : RealityKind
        The kind of the reality the frames come from (set by the runner from
        the scenario).  Schemas may adapt to it (the Scene Background learns
        the surfaces' look of any but a synthetic reality by default); it never carries the
        reality's truth.
    """

    def __init__(self, mirror: "Mirror", *, registry: Registry = REGISTRY,
                 settings: Sequence["SchemaSettings"] = (),
                 models: Mapping[str, "ObjectModel"] | None = None,
                 goals: Sequence["Goal"] = (), actuator: "Actuator | None" = None,
                 predict: "PredictSettings | None" = None,
                 rng: np.random.Generator | None = None, frame_interval: float = 1.0 / 30.0,
                 reality: RealityKind = RealityKind.SYNTHETIC) -> None:
        from adapt.scenario import PredictSettings

        self.mirror = mirror
        self.predict = predict if predict is not None else PredictSettings()
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.frame_interval = frame_interval
        self.reality = reality
        self.registry = registry
        self.settings = check_settings(settings, registry)
        self.models = dict(models or {})
        self.goals = tuple(goals)
        self.actuator = actuator
        self.graph: nx.DiGraph = nx.DiGraph()
        self.frame_index = -1
        self.time = 0.0
        self.decision = 0
        self.listeners: list[Callable[[SchemaEvent], None]] = []
        self.changed = False
        #: Seconds spent in each schema type's perceive/act so far.
        self.seconds: dict[str, float] = {}
        self._order: list[Schema] | None = None
        self._counter: dict[str, int] = {}
        #: The frame perceived last, and the perceptual schemas spawned since (each looks
        #: at it too: :meth:`perceive_spawned`).
        self._frame: "Frame | None" = None
        self._spawned: list[str] = []
        self._root: Structure | None = None
        self._seen_commands: set[Identifier] = set()
        self._statuses: dict[Identifier, tuple[str, str]] = {}
        self._last_status: dict[str, Status] = {}
        self._percepts: dict[tuple[str, str], object] = {}

    # -- membership ---------------------------------------------------------------------

    def __contains__(self, name: object) -> bool:
        return name in self.graph

    def __getitem__(self, name: str) -> Schema:
        try:
            return self.graph.nodes[name]["schema"]  # type: ignore[no-any-return]
        except KeyError:
            raise SchemaError(f"no schema called {name!r}") from None

    def __len__(self) -> int:
        return self.graph.number_of_nodes()

    def __iter__(self) -> Iterator[Schema]:
        return iter(self.ordered())

    def ordered(self) -> list[Schema]:
        """Every schema, providers before consumers (then in creation order)."""
        if self._order is None:
            names = list(self.graph.nodes)
            rank = {n: i for i, n in enumerate(names)}
            try:
                gens = list(nx.topological_generations(self.graph))
                order = [n for g in gens for n in sorted(g, key=rank.__getitem__)]
            except nx.NetworkXUnfeasible:  # a cycle: keep creation order
                order = names
            self._order = [self.graph.nodes[n]["schema"] for n in order]
        return self._order

    @property
    def names(self) -> list[str]:
        """Schema names, in order."""
        return [s.name for s in self.ordered()]

    # -- percepts -----------------------------------------------------------------------------

    def publish(self, schema: Schema, percept: object, port: str | None = None) -> None:
        """``schema`` publishes ``percept`` on ``port`` (None: on every port it provides);
        it replaces what the schema published there before."""
        ports = [p.name for p in schema.spec.provides] if port is None else [port]
        for name in ports:
            if not any(p.name == name for p in schema.spec.provides):
                raise SchemaError(f"{schema.spec.name} does not provide a port {name!r}")
            self._percepts[(schema.name, name)] = percept

    def percepts(self, schema: Schema, port: str, kind: type[P]) -> list[P]:
        """The percepts of type ``kind`` that ``schema``'s providers published on ``port``
        (through its in-edges with that port), providers in the network's order."""
        name = schema.name
        if name not in self.graph:
            return []
        out: list[P] = []
        for provider in self.ordered():
            data = self.graph.get_edge_data(provider.name, name)
            if data is not None and port in data["ports"]:
                found = self._percepts.get((provider.name, port))
                if isinstance(found, kind):
                    out.append(found)
        return out

    def percept(self, schema: Schema, port: str, kind: type[P]) -> P | None:
        """The first of :meth:`percepts`, or None."""
        found = self.percepts(schema, port, kind)
        return found[0] if found else None

    def published(self, kind: type[P]) -> list[P]:
        """Every percept of type ``kind`` the schemas have published (once each, schemas
        in the network's order): how what perceives is read from outside the network."""
        out: list[P] = []
        for schema in self.ordered():
            for port in schema.spec.provides:
                found = self._percepts.get((schema.name, port.name))
                if isinstance(found, kind) and not any(found is o for o in out):
                    out.append(found)
        return out

    def claims(self) -> dict[int, str]:
        """The difference regions claimed (region id -> schema): each region by at most one
        schema, the first in the network's order to claim it."""
        out: dict[int, str] = {}
        for schema in self.ordered():
            for region in schema.claimed_regions():
                out.setdefault(region, schema.name)
        return out

    def monitor_of(self, obj: str) -> str | None:
        """The schema that monitors the world object ``obj``, or None."""
        for schema in self.ordered():
            if schema.monitored_object() == obj:
                return schema.name
        return None

    # -- the robot, for motor schemas ------------------------------------------------------

    @property
    def robot(self) -> "RobotSpec | None":
        """The robot's model (speed and acceleration limits, size), or None without a robot."""
        return self.mirror.scene.robot

    def robot_pose(self) -> tuple[tuple[float, float], float] | None:
        """The imagined robot's pose (odometry): ``((x, y), heading)``, or None."""
        return self.mirror.robot_pose()

    def command_robot(self, velocity: tuple[float, float], turn: float = 0.0) -> None:
        """Command the robot's velocity (m/s, floor frame) and turn rate (rad/s): the imagined
        robot (odometry) and the real one (the reality's :class:`~adapt.frames.Actuator`,
        when it has one) alike."""
        self.mirror.command_robot(velocity, turn)
        if self.actuator is not None:
            self.actuator.command_robot(velocity, turn)

    # -- changing the network ---------------------------------------------------------------

    def instantiate(self, type_name: str, name: str | None = None,
                    parameters: Mapping[str, Any] | None = None,
                    origin: Origin = Origin.TOP_DOWN) -> Schema:
        """Create a schema of ``type_name`` and join it to the network.

        Parameters are the type's defaults, then the scenario's
        ``schemas.<type>`` values, then ``parameters``.

        Raises
        ------
        SchemaError
            For an unknown type or parameter, a bad value, a name in use, a
            second instance of a singleton type, a ``region`` another schema
            owns (a region has one owner), or a schema that cannot start (a
            drive schema without a robot).
        """
        spec = self.registry.get(type_name)
        if name is None:
            n = self._counter.get(spec.name, 0) + 1
            self._counter[spec.name] = n
            name = spec.name if spec.singleton else f"{spec.name}-{n}"
            while name in self.graph:
                n += 1
                self._counter[spec.name] = n
                name = f"{spec.name}-{n}"
        if not name or name in self.graph:
            raise SchemaError(f"a schema called {name!r} already exists" if name
                              else "a schema needs a name")
        if spec.singleton and any(s.spec is spec for s in self.ordered()):
            raise SchemaError(f"there can be only one {spec.name} schema")
        values = spec.defaults()
        values.update(self.settings.get(spec.name, {}))
        for key, value in (parameters or {}).items():
            try:
                p = spec.parameter(key)
            except KeyError:
                names = [q.name for q in spec.parameters]
                raise SchemaError(f"unknown parameter {key!r} of {spec.name}; expected one of "
                                  + (", ".join(names) if names else "none")) from None
            try:
                values[key] = p.check(value)
            except ParameterError as exc:
                raise SchemaError(f"{spec.name} parameter {key}: {exc}") from None
        self._check_owner(values.get("region"))
        try:
            schema = spec.factory(name, values, self)
        except ValueError as exc:
            raise SchemaError(f"cannot start {spec.name} {name!r}: {exc}") from None
        schema.origin = origin
        self.graph.add_node(name, schema=schema, type=spec.name, kind=spec.kind.value)
        self._connect(schema)
        self._order = None
        self.changed = True
        self._last_status[name] = schema.status
        schema.joined()
        if origin is Origin.BOTTOM_UP and spec.kind is SchemaKind.PERCEPTUAL:
            self._spawned.append(name)
        kind = EventKind.SPAWNED if origin is Origin.BOTTOM_UP else EventKind.INSTANTIATED
        self._emit(SchemaEvent(kind, name, self.frame_index, self.decision,
                               {"type": spec.name, "origin": origin.value,
                                "parameters": {k: v for k, v in values.items()
                                               if k in (parameters or {})}}))
        return schema

    def _check_owner(self, region: object) -> None:
        """A region has one owner: refuse a schema for a difference region (its ``region``
        parameter) that another schema claims or was made for."""
        if isinstance(region, bool) or not isinstance(region, int) or region <= 0:
            return
        owner = self.claims().get(region) or next(
            (s.name for s in self.ordered() if s.parameters.get("region") == region), None)
        if owner is not None:
            raise SchemaError(f"region {region} already has an owner, schema {owner!r}; a "
                              "region has one owner")

    def _connect(self, schema: Schema) -> None:
        spec = schema.spec
        for other in list(self.graph.nodes):
            if other == schema.name:
                continue
            o: SchemaSpec = self.graph.nodes[other]["schema"].spec
            out = tuple(p.name for p in spec.provides if any(c.name == p.name for c in o.consumes))
            if out:
                self.graph.add_edge(schema.name, other, ports=out)
            into = tuple(c.name for c in spec.consumes if any(p.name == c.name for p in o.provides))
            if into:
                self.graph.add_edge(other, schema.name, ports=into)

    def remove(self, name: str) -> None:
        """Remove a schema (it releases its bodies and hooks; its percepts and claims go)."""
        schema = self[name]
        schema.stop()
        self.graph.remove_node(name)
        for key in [k for k in self._percepts if k[0] == name]:
            del self._percepts[key]
        self._last_status.pop(name, None)
        self._order = None
        self.changed = True
        self._emit(SchemaEvent(EventKind.REMOVED, name, self.frame_index, self.decision,
                               {"type": schema.spec.name}))

    # -- events ---------------------------------------------------------------------------------

    def _emit(self, event: SchemaEvent) -> None:
        for listener in self.listeners:
            listener(event)

    def note(self, schema: Schema, kind: EventKind, data: dict[str, Any]) -> None:
        """A schema reports an event (for example ``created``: a body in the imagination)."""
        self._emit(SchemaEvent(kind, schema.name, self.frame_index, self.decision, data))

    # -- the frame loop ---------------------------------------------------------------------------

    def perceive(self, frame: "Frame") -> None:
        """Every perceptual schema looks at ``frame``, providers first."""
        self.frame_index = frame.index
        self.time = frame.time
        self._frame = frame
        self._spawned = []
        for schema in self.ordered():
            if schema.kind is SchemaKind.PERCEPTUAL:
                self._look(schema, frame)
        self._status_events()

    def perceive_spawned(self) -> None:
        """Every perceptual schema spawned bottom-up since :meth:`perceive` looks at that
        frame too -- the frame whose difference region it was spawned for -- providers
        first, so that what it finds there is this frame's, not the next's (a spawned
        schema used to wait a frame: one frame of every object unfollowed).  Its percept
        reaches the rules at the next input phase, as every percept does."""
        spawned, self._spawned = self._spawned, []
        frame = self._frame
        if frame is None or not spawned:
            return
        for schema in self.ordered():
            if schema.name in spawned:  # perceptual all (instantiate keeps only those)
                self._look(schema, frame)
        self._status_events()

    def _look(self, schema: Schema, frame: "Frame") -> None:
        """``schema`` perceives ``frame``, its seconds counted for its type."""
        started = perf_counter()
        schema.perceive(frame)
        self._spend(schema, started)

    def _spend(self, schema: Schema, started: float) -> None:
        """Count the seconds since ``started`` (``perf_counter``) for ``schema``'s type."""
        key = schema.spec.name
        self.seconds[key] = self.seconds.get(key, 0.0) + perf_counter() - started

    def act(self, time: float) -> None:
        """Every motor schema acts."""
        for schema in self.ordered():
            if schema.kind is SchemaKind.MOTOR:
                started = perf_counter()
                schema.act(time)
                self._spend(schema, started)
        self._status_events()

    def _status_events(self) -> None:
        for schema in self.ordered():
            before = self._last_status.get(schema.name)
            if before is not schema.status:
                self._last_status[schema.name] = schema.status
                self._emit(SchemaEvent(EventKind.STATUS, schema.name, self.frame_index,
                                       self.decision,
                                       {"status": schema.status.value,
                                        "message": schema.message}))

    def monitored_boxes(self, exclude: str | None = None) -> list[tuple[str, BBox]]:
        """``(schema, box)`` of every part of the image a schema explains."""
        out = []
        for schema in self.ordered():
            if schema.name == exclude:
                continue
            box = schema.monitored_box()
            if box is not None:
                out.append((schema.name, box))
        return out

    # -- the input-link ------------------------------------------------------------------------------

    def write_input(self, writer: InputLink) -> None:
        """The input-phase callback: write the frame, goals, robot, schemas and command statuses."""
        self.decision = writer.decision
        if self._root is None:
            self._root = Structure(writer.input_link, writer)
        root = self._root
        root.bind(writer)
        frame = root.child("frame", 0)
        frame.set("index", max(self.frame_index, 0))
        frame.set("time", round(self.time, 4))
        for i, goal in enumerate(self.goals):
            g = root.child("goal", i)
            g.set("name", goal.name)
            for key, value in goal.attributes:
                g.set(key, value)
        pose = self.mirror.robot_pose()
        if pose is not None:
            (x, y), heading = pose
            r = root.child("robot", 0)
            r.set("x", round(x, 4))
            r.set("y", round(y, 4))
            r.set("heading", round(heading, 4))
            robot = self.mirror.scene.robot
            assert robot is not None
            r.set("max-speed", robot.max_speed)
            r.set("max-accel", robot.max_accel)
        for schema in self.ordered():
            node = root.child("schema", schema.name)
            node.set("name", schema.name)
            node.set("type", schema.spec.name)
            node.set("kind", schema.kind.value)
            node.set("status", schema.status.value)
            node.set("origin", schema.origin.value)
            schema.write(node)
        root.keep_children("schema", self.names)
        for cid, (status, message) in self._statuses.items():
            writer.set(cid, "status", status)
            if message:
                writer.set(cid, "message", message)
        self._statuses.clear()

    # -- the output-link ------------------------------------------------------------------------------

    def on_output(self, view: OutputView) -> None:
        """The output-phase callback: carry out the new commands."""
        self.decision = view.decision
        for cmd in read_commands(view, self._seen_commands):
            error = self._carry_out(cmd)
            self._statuses[cmd.id] = ("error", error) if error else ("complete", "")
            if error:
                self._emit(SchemaEvent(EventKind.REJECTED,
                                       str(cmd.get("name", cmd.get("schema", ""))),
                                       self.frame_index, self.decision,
                                       {"command": cmd.verb, "error": error,
                                        "attributes": {k: _json(v) for k, v in cmd.as_dict().items()}}))
        live = {w.value for w in view.wmes if w.id is view.output_link}
        self._seen_commands &= live  # type: ignore[operator]

    def _carry_out(self, cmd: Command) -> str:
        attrs = cmd.as_dict()
        try:
            if cmd.verb == "instantiate":
                type_name = attrs.pop("type", None)
                if not isinstance(type_name, str):
                    return "^instantiate needs ^type (one of " + ", ".join(self.registry.names()) + ")"
                name = attrs.pop("name", None)
                if name is not None and not isinstance(name, str):
                    name = str(name)
                origin = Origin.BOTTOM_UP if attrs.get("region") else Origin.TOP_DOWN
                self.instantiate(type_name, name, attrs, origin)
                return ""
            if cmd.verb == "remove":
                name = attrs.get("name")
                if not isinstance(name, str) or name not in self:
                    return f"^remove needs the ^name of a schema; no schema called {name!r}"
                self.remove(name)
                return ""
            if cmd.verb == "command":
                name = attrs.pop("schema", None)
                if not isinstance(name, str) or name not in self:
                    return f"^command needs the ^schema it is for; no schema called {name!r}"
                schema = self[name]
                error = schema.command(attrs)
                self._status_events()
                return error or ""
        except SchemaError as exc:
            return str(exc)
        return f"unknown command ^{cmd.verb}; expected ^instantiate, ^remove or ^command"

    # -- the whole --------------------------------------------------------------------------------

    def subscene(self) -> dict[str, Any]:
        """The network as JSON: nodes (schema summaries) and port edges."""
        return {"nodes": [s.summary() for s in self.ordered()],
                "edges": [{"from": a, "to": b, "port": port}
                          for a, b, d in self.graph.edges(data=True) for port in d["ports"]]}


def _json(value: Any) -> Any:
    if isinstance(value, Identifier):
        return str(value)
    return value
