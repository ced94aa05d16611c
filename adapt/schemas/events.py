"""What happens to the schema network, as events for the trace and the runner.

Examples
--------
>>> e = SchemaEvent(EventKind.SPAWNED, "foreground-object-1", 12, 37, {"type": "foreground-object"})
>>> e.as_json()["event"]
'spawned'
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any

__all__ = ["EventKind", "SchemaEvent"]


class EventKind(enum.Enum):
    """What happened to the network (the trace's ``schema`` record's ``event``)."""

    INSTANTIATED = "instantiated"  #: a schema put in place top-down
    SPAWNED = "spawned"            #: bottom-up, for a difference region
    REMOVED = "removed"
    STATUS = "status"              #: a schema's status changed
    CREATED = "created"            #: a schema created a body in the imagination
    BOUNCE = "bounce"              #: an object schema recognised a bounce
    REJECTED = "rejected"          #: a command the network could not carry out


@dataclass(frozen=True, slots=True)
class SchemaEvent:
    """Something that happened to the network (``kind``: see :class:`EventKind`)."""

    kind: EventKind
    schema: str
    frame: int
    decision: int
    data: dict[str, Any] = field(default_factory=dict)

    def as_json(self) -> dict[str, Any]:
        """The trace's ``schema`` record (without ``kind``)."""
        return {"d": self.decision, "frame": self.frame, "event": self.kind.value,
                "schema": self.schema, "data": self.data}
