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


def _num(v: float) -> str:
    """A bound as messages show it: whole numbers in full (``4915200``), others by ``:g``."""
    return str(int(v)) if float(v).is_integer() else f"{v:g}"


@dataclass(frozen=True, slots=True)
class Parameter:
    """One parameter of a schema type.

    ``kind`` is ``float``, ``int``, ``bool`` or ``str``; ``low``/``high``
    bound numbers (adapt's own parameters have both: a value beyond them could only fail
    later; ``low_open``/``high_open`` exclude the bound itself); ``choices`` restricts
    strings.
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
        if isinstance(value, float) and not math.isfinite(value):
            raise ParameterError(f"expected a finite number, got {value!r}")
        if self.kind is int and isinstance(value, float) and not value.is_integer():
            raise ParameterError(f"expected an integer, got {value!r}")
        shown = f"{value:g}" if isinstance(value, float) or abs(value) < 10**16 else \
            f"a {len(str(abs(value)))}-digit number"
        if self.low is not None and (value < self.low or (self.low_open and value == self.low)):
            raise ParameterError(f"expected {'more than' if self.low_open else 'at least'} "
                                 f"{_num(self.low)}, got {shown}")
        if self.high is not None and (value > self.high or (self.high_open and value == self.high)):
            raise ParameterError(f"expected {'less than' if self.high_open else 'at most'} "
                                 f"{_num(self.high)}, got {shown}")
        try:
            return int(value) if self.kind is int else float(value)
        except OverflowError:  # an integer of hundreds of digits where no bound applies
            raise ParameterError(f"expected a number, got {shown}") from None

    @property
    def range_text(self) -> str:
        """The type and bounds as ``docs/schemas.md`` writes them (``float in (0, 1]``), or
        "" for a parameter that is not a number.

        Examples
        --------
        >>> Parameter("gain", float, 0.5, "", low=0.0, high=1.0, low_open=True).range_text
        'float in (0, 1]'
        """
        if self.kind not in (int, float) or self.low is None or self.high is None:
            return ""
        lo, hi = _num(self.low), _num(self.high)
        return (f"{self.kind.__name__} in {'(' if self.low_open else '['}{lo}, "
                f"{hi}{')' if self.high_open else ']'}")

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
