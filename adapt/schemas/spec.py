"""What a schema type declares: its kind, ports and parameters.

A :class:`SchemaSpec` is a frozen record registered by name (see
:mod:`adapt.schemas.registry`).  Its **ports** say what an instance provides
to other schemas and what it consumes from them; the network joins a
provider to every consumer of the same port with an edge of the
minimal subscene's graph.  Its **parameters** are typed, with a default, a
unit, bounds and a line of documentation; values come from the scenario's
``schemas`` section and from the rules' ``^instantiate`` commands, and are
checked here.

Examples
--------
>>> from adapt.schemas import REGISTRY
>>> spec = REGISTRY.get("intercept")
>>> spec.kind, spec.provides, [port.name for port in spec.consumes]
(<SchemaKind.MOTOR: 'motor'>, (), ['object', 'camera'])
>>> spec.parameter("object").describe()
"object (str; default 'ball'): the world object to intercept"

A parameter (:class:`~adapt.parameters.Parameter`) checks its values itself.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

from adapt.parameters import Parameter, ParameterError

if TYPE_CHECKING:  # pragma: no cover
    from adapt.schemas.base import Schema

__all__ = ["SchemaKind", "Port", "Parameter", "SchemaSpec", "ParameterError"]


class SchemaKind(enum.Enum):
    """Perceptual schemas watch the image and model part of the world; motor
    schemas act."""

    PERCEPTUAL = "perceptual"
    MOTOR = "motor"


@dataclass(frozen=True, slots=True)
class Port:
    """A named kind of data a schema provides or consumes (``regions``,
    ``camera``, ``object``, ...), with a line saying what it carries."""

    name: str
    doc: str = ""


@dataclass(frozen=True, slots=True, eq=False)
class SchemaSpec:
    """A schema type.

    Attributes
    ----------
    name : str
        The type's name, as rules and scenarios write it (``scene-background``).
    kind : SchemaKind
    doc : str
        What it does, in one paragraph.
    provides, consumes : tuple of Port
    parameters : tuple of Parameter
    factory : callable
        ``factory(name, parameters, network) -> Schema``.
    singleton : bool
        At most one instance at a time (the scene background).
    """

    name: str
    kind: SchemaKind
    doc: str
    factory: Callable[..., "Schema"] = field(repr=False)
    provides: tuple[Port, ...] = ()
    consumes: tuple[Port, ...] = ()
    parameters: tuple[Parameter, ...] = ()
    singleton: bool = False

    def parameter(self, name: str) -> Parameter:
        """The declaration of parameter ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def defaults(self) -> dict[str, Any]:
        """Every parameter at its default."""
        return {p.name: p.default for p in self.parameters}

    def as_json(self) -> dict[str, Any]:
        """The type as JSON (``adapt schemas list --json``)."""
        return {"name": self.name, "kind": self.kind.value, "doc": self.doc,
                "singleton": self.singleton,
                "provides": [{"name": p.name, "doc": p.doc} for p in self.provides],
                "consumes": [{"name": p.name, "doc": p.doc} for p in self.consumes],
                "parameters": [p.as_json() for p in self.parameters]}
