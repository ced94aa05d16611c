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
>>> p = Parameter("gain", float, 0.5, "fraction of the camera correction applied per frame",
...               low=0.0, high=1.0, low_open=True)
>>> p.check(0.25), p.check(1)
(0.25, 1.0)
>>> p.check(2)
Traceback (most recent call last):
...
adapt.schemas.spec.ParameterError: expected at most 1, got 2
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

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


class ParameterError(ValueError):
    """A parameter value does not fit its declaration (the caller adds where)."""


@dataclass(frozen=True, slots=True)
class Parameter:
    """One parameter of a schema type.

    ``kind`` is ``float``, ``int``, ``bool`` or ``str``; ``low``/``high``
    bound numbers (``low_open``/``high_open`` exclude the bound itself);
    ``choices`` restricts strings.
    """

    name: str
    kind: type
    default: Any
    doc: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] = ()

    def check(self, value: Any) -> Any:
        """The value converted to ``kind``, or :class:`ParameterError` saying what was expected."""
        if self.kind is bool:
            if isinstance(value, bool):
                return value
            if value in ("yes", "no", "true", "false"):
                return value in ("yes", "true")
            raise ParameterError(f"expected true or false, got {value!r}")
        if self.kind is str:
            if not isinstance(value, str) or not value:
                raise ParameterError(f"expected a string, got {value!r}")
            if self.choices and value not in self.choices:
                raise ParameterError("expected one of " + ", ".join(self.choices) + f", got {value!r}")
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParameterError(f"expected a number, got {value!r}")
        if self.kind is int:
            if isinstance(value, float) and not value.is_integer():
                raise ParameterError(f"expected an integer, got {value!r}")
            v: float = int(value)
        else:
            v = float(value)
            if not math.isfinite(v):
                raise ParameterError(f"expected a finite number, got {value!r}")
        if self.low is not None and (v < self.low or (self.low_open and v == self.low)):
            raise ParameterError(f"expected {'more than' if self.low_open else 'at least'} "
                                 f"{self.low:g}, got {value!r}")
        if self.high is not None and (v > self.high or (self.high_open and v == self.high)):
            raise ParameterError(f"expected {'less than' if self.high_open else 'at most'} "
                                 f"{self.high:g}, got {value!r}")
        return v

    def describe(self) -> str:
        """``name (type, unit, range): doc``, for ``adapt schemas list``."""
        bits = [self.kind.__name__]
        if self.unit:
            bits.append(self.unit)
        if self.low is not None or self.high is not None:
            lo = "" if self.low is None else f"{self.low:g}"
            hi = "" if self.high is None else f"{self.high:g}"
            bits.append(f"{'(' if self.low_open else '['}{lo}..{hi}{')' if self.high_open else ']'}")
        if self.choices:
            bits.append("|".join(self.choices))
        return f"{self.name} ({', '.join(bits)}; default {self.default!r}): {self.doc}"

    def as_json(self) -> dict[str, Any]:
        """The declaration as JSON."""
        return {"name": self.name, "type": self.kind.__name__, "default": self.default,
                "unit": self.unit, "low": self.low, "high": self.high,
                "choices": list(self.choices), "doc": self.doc}


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
