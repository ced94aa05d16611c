"""A typed, documented parameter: of a schema type, of a reality kind.

A :class:`Parameter` has a type, a default, a unit, bounds and a line of
documentation; :meth:`Parameter.check` converts a value read from YAML or
from the rules' commands, or says what was expected.  Schema types
(:mod:`adapt.schemas.spec`) and reality kinds from plugins
(:mod:`adapt.scenario.kinds`) declare theirs with it.

Examples
--------
>>> p = Parameter("gain", float, 0.5, "fraction of the camera correction applied per frame",
...               low=0.0, high=1.0, low_open=True)
>>> p.check(0.25), p.check(1)
(0.25, 1.0)
>>> p.check(2)
Traceback (most recent call last):
...
adapt.parameters.ParameterError: expected at most 1, got 2
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["Parameter", "ParameterError", "REQUIRED"]


class _Required:
    """The default of a parameter that must be given."""

    def __repr__(self) -> str:
        return "required"


#: The default of a parameter that has none: the value must be given.
REQUIRED: Any = _Required()


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
