"""The schema base class: what the network calls, and what a schema tells it.

A schema instance is a node of the schema network (the minimal subscene).
When it has been made and joined to its providers and consumers, the network
calls :meth:`Schema.joined` (its first look at its providers' percepts).
Then, each frame and in this order:

1. :meth:`Schema.perceive` on every perceptual schema, in the order of the
   network's port edges (providers before consumers): the schema looks at
   its part of the image and of the imagination, reads its providers'
   percepts (``self.network.percepts(self, port, kind)``) and publishes its
   own (``self.network.publish(self, percept)``; :mod:`adapt.schemas.percepts`);
2. :meth:`Schema.write` during the agent's input phase: the schema writes
   what it perceives (or, for a motor schema, its status) under its own
   identifier on the input-link;
3. :meth:`Schema.command` after an output phase, for each new command the
   rules addressed to it;
4. :meth:`Schema.act` on every motor schema: it drives the reality and the
   imagination;
5. :meth:`Schema.before_step` before every physics step of the imagination
   (a correction force acts on every step, not once a frame).

A schema owns a part of the image (:meth:`Schema.monitored_box`: the
difference it explains, labelled *expected* from then on; and the difference
regions it claims, :meth:`Schema.claimed_regions`), a part of the
imagination (the bodies it created) and, for an object schema, a world
object (:meth:`Schema.monitored_object`).  These three are all a schema tells
the network about itself beyond its percepts.
"""

from __future__ import annotations

import enum
from typing import TYPE_CHECKING, Any, Mapping

from adapt.schemas.links import Structure
from adapt.schemas.spec import SchemaKind, SchemaSpec

if TYPE_CHECKING:  # pragma: no cover
    from adapt.frames import Frame
    from adapt.schemas.network import SchemaNetwork

__all__ = ["Schema", "Status", "Origin", "BBox"]

BBox = tuple[int, int, int, int]


class Status(enum.Enum):
    """A schema's status as the input-link reports it."""

    RUNNING = "running"        # a perceptual schema at work
    WAITING = "waiting"        # a perceptual schema that has not found its object yet
    LOST = "lost"              # a perceptual schema whose object is not seen
    IDLE = "idle"              # a motor schema without a command
    EXECUTING = "executing"    # a motor schema carrying out a command
    COMPLETE = "complete"      # its command is done
    FAILED = "failed"          # its command cannot be done


class Origin(enum.Enum):
    """Why a schema exists."""

    TOP_DOWN = "top-down"     # instantiated by the rules from the goals
    BOTTOM_UP = "bottom-up"   # spawned by the rules for an unexpected difference


class Schema:
    """Base class of every schema.

    Parameters
    ----------
    name : str
        Unique in the network (the rules' ``^name``).
    spec : SchemaSpec
        Its type.
    parameters : mapping
        Checked values of every declared parameter.
    network : SchemaNetwork
        The network it belongs to (its view of the mirror, the frame, the
        other schemas).
    """

    def __init__(self, name: str, spec: SchemaSpec, parameters: Mapping[str, Any],
                 network: "SchemaNetwork") -> None:
        self.name = name
        self.spec = spec
        self.parameters = dict(parameters)
        self.network = network
        self.status = Status.RUNNING if spec.kind is SchemaKind.PERCEPTUAL else Status.IDLE
        self.origin = Origin.TOP_DOWN
        self.created_frame = network.frame_index
        self.message = ""

    @property
    def kind(self) -> SchemaKind:
        """Perceptual or motor."""
        return self.spec.kind

    # -- the frame loop -------------------------------------------------------

    def joined(self) -> None:
        """Called once the network has joined the schema to its providers and consumers
        (before its first frame): the first look at its providers' percepts."""

    def perceive(self, frame: "Frame") -> None:
        """Look at the new frame (perceptual schemas)."""

    def write(self, node: Structure) -> None:
        """Write what this schema perceives, or its status, under ``node``.

        The base writes nothing beyond what the network writes for every
        schema (``^name``, ``^type``, ``^kind``, ``^status``, ``^origin``).
        """

    def command(self, attributes: Mapping[str, Any]) -> str | None:
        """A command from the output-link; returns an error message or None."""
        return "this schema takes no commands"

    def act(self, time: float) -> None:
        """Act on the reality and the imagination (motor schemas)."""

    def before_step(self, time: float) -> None:
        """Called before every physics step of the imagination."""

    def monitored_box(self) -> BBox | None:
        """The real-image box ``(x, y, w, h)`` this schema explains, or None."""
        return None

    def claimed_regions(self) -> tuple[int, ...]:
        """The tracked difference regions this schema explains (their ids): it owns each
        one its providers' regions do not already give to another schema."""
        return ()

    def monitored_object(self) -> str | None:
        """The world object this schema monitors (at most one schema monitors an object)."""
        return None

    def stop(self) -> None:
        """The schema is being removed: release what it holds in the imagination."""

    def summary(self) -> dict[str, Any]:
        """A JSON summary for the trace and the report."""
        return {"name": self.name, "type": self.spec.name, "kind": self.kind.value,
                "status": self.status.value, "origin": self.origin.value}

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r} {self.status.value}>"
