"""The grid of a sweep: ``--seeds`` and ``--set`` read into values.

``--seeds`` is a comma-separated list of seeds and inclusive ranges
(``1-200``, ``1,5,9``, ``1-10,50-60``).  Each ``--set KEY=VALUES`` is one
axis of the grid: a scenario key path (as for
:func:`adapt.scenario.load_scenario`'s overrides) and a comma-separated list
of items, each a YAML value or an inclusive range ``lo:hi:step`` of numbers
(``0.5:0.9:0.1`` is 0.5, 0.6, 0.7, 0.8, 0.9; stepped in decimal, so no
``0.30000000000000004``).  Commas inside brackets or quotes belong to the
value: ``reality.camera_offset_deg=[1,0,0],[2,0,0]`` is two values.  The
sweep is the product of the seeds and every axis.

A syntax error is a :class:`~adapt.errors.SweepSpecError` at the column of
the argument; whether a value suits the scenario is the scenario reader's to
say (see :mod:`adapt.sweep.plan`).

Examples
--------
>>> parse_seeds("1-3,7")
(1, 2, 3, 7)
>>> a = parse_axis("world.objects.ball.restitution=0.5:0.7:0.1,0.95")
>>> a.path, [i.text for i in a.items]
('world.objects.ball.restitution', ['0.5', '0.6', '0.7', '0.95'])
>>> [i.text for i in parse_axis("reality.camera_offset_deg=[1, 0, 0],[2,0,0]").items]
['[1, 0, 0]', '[2,0,0]']
>>> parse_seeds("5-2")
Traceback (most recent call last):
...
adapt.errors.SweepSpecError: --seeds:1:1: the range 5-2 runs backwards; expected LOW-HIGH with LOW <= HIGH
    5-2
    ^
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Any

from adapt.errors import SweepSpecError
from adapt.scenario.nodes import yaml_value

__all__ = ["Item", "Axis", "parse_seeds", "parse_axis", "canonical", "MAX_RANGE"]

#: The most values one ``lo:hi:step`` range may give (a larger one is a typo, most likely).
MAX_RANGE = 100_000

_SEED_ITEM = re.compile(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?$")
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_RANGE = re.compile(rf"\s*({_NUMBER})\s*:\s*({_NUMBER})\s*:\s*({_NUMBER})\s*$")


@dataclass(frozen=True, slots=True)
class Item:
    """One value of an axis.

    Attributes
    ----------
    text : str
        The value as YAML text (what the override gives the scenario reader).
    value : object
        The value read from ``text`` (a number, string, list, ...), as JSON
        would hold it: what ``runs.jsonl`` and ``sweep.json`` show.
    col : int
        1-based column in the ``--set`` argument of the item it came from
        (every value of a range points at the range).
    from_range : bool
        True when the value was stepped from ``lo:hi:step``.
    """

    text: str
    value: Any
    col: int
    from_range: bool = False


@dataclass(frozen=True, slots=True)
class Axis:
    """One ``--set KEY=VALUES``: a key path and its values, in the order given."""

    path: str
    items: tuple[Item, ...]
    text: str

    @property
    def values(self) -> list[Any]:
        """The values, as JSON would hold them."""
        return [i.value for i in self.items]

    @property
    def numeric(self) -> bool:
        """True when every value is a number (plots draw it on a number line)."""
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in self.values)


def _fail(flag: str, text: str, col: int, message: str) -> SweepSpecError:
    return SweepSpecError(message, file=flag, line=1, col=col, source_line=text)


def parse_seeds(text: str) -> tuple[int, ...]:
    """Read ``--seeds``: seeds and inclusive ranges ``LOW-HIGH``, comma-separated.

    Examples
    --------
    >>> parse_seeds("0-2, 10")
    (0, 1, 2, 10)
    >>> parse_seeds("1,x")
    Traceback (most recent call last):
    ...
    adapt.errors.SweepSpecError: --seeds:1:3: expected a seed (an integer >= 0) or a range LOW-HIGH, got 'x'
        1,x
          ^
    """
    seeds: list[int] = []
    seen: dict[int, int] = {}
    pos = 0
    for part in text.split(","):
        col = pos + len(part) - len(part.lstrip()) + 1
        pos += len(part) + 1
        m = _SEED_ITEM.match(part)
        if not part.strip() or m is None:
            raise _fail("--seeds", text, col, "expected a seed (an integer >= 0) or a range "
                        f"LOW-HIGH, got {part.strip()!r}")
        low = int(m.group(1))
        high = low if m.group(2) is None else int(m.group(2))
        if high < low:
            raise _fail("--seeds", text, col, f"the range {part.strip()} runs backwards; "
                        "expected LOW-HIGH with LOW <= HIGH")
        if high - low >= MAX_RANGE:
            raise _fail("--seeds", text, col, f"the range {part.strip()} has {high - low + 1} "
                        f"seeds; at most {MAX_RANGE} in one range")
        for s in range(low, high + 1):
            if s in seen:
                raise _fail("--seeds", text, col, f"seed {s} is given twice (first at column "
                            f"{seen[s]})")
            seen[s] = col
            seeds.append(s)
    return tuple(seeds)


def _split(text: str, start: int) -> list[tuple[str, int]]:
    """Comma-separated items of ``text`` outside brackets, braces and quotes, with their
    1-based columns (``start`` is the column of ``text[0]``)."""
    items: list[tuple[str, int]] = []
    depth = 0
    quote = ""
    begin = 0
    for i, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "'\"":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            items.append((text[begin:i], start + begin))
            begin = i + 1
    items.append((text[begin:], start + begin))
    return items


def canonical(text: str) -> Any:
    """A YAML value text read as JSON would hold it (a date or other type becomes its text).

    Examples
    --------
    >>> canonical("0.70"), canonical("[1, 2]"), canonical("brick"), canonical("1e-3")
    (0.7, [1, 2], 'brick', 0.001)
    """
    try:
        value = yaml_value(text)
    except ValueError:
        return text
    return _jsonable(value, text)


def _jsonable(value: Any, text: str) -> Any:
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else text
    if isinstance(value, list):
        return [_jsonable(v, text) for v in value]
    if isinstance(value, dict):
        return {str(k): _jsonable(v, text) for k, v in value.items()}
    return str(value)


def _stepped(m: re.Match[str], flag: str, text: str, col: int) -> list[str]:
    try:
        lo, hi, step = (Decimal(m.group(i)) for i in (1, 2, 3))
    except InvalidOperation:  # pragma: no cover - the pattern admits only numbers
        raise _fail(flag, text, col, "expected numbers in lo:hi:step") from None
    if step == 0:
        raise _fail(flag, text, col, "the step of lo:hi:step is 0; expected a non-zero step")
    if (hi - lo) * step < 0:
        raise _fail(flag, text, col, f"the range {m.group(0).strip()} never reaches {m.group(2)}"
                    " from " + m.group(1) + "; the step goes the other way")
    count = int((hi - lo) / step) + 1
    if count > MAX_RANGE:
        raise _fail(flag, text, col, f"the range {m.group(0).strip()} has {count} values; at "
                    f"most {MAX_RANGE}")
    return [str(lo + i * step) for i in range(count)]


def parse_axis(text: str) -> Axis:
    """Read one ``--set KEY=VALUES`` (see the module docstring).

    Examples
    --------
    >>> [i.value for i in parse_axis("run.fps=10:30:10").items]
    [10, 20, 30]
    >>> parse_axis("world.dt=0.01,,0.02")
    Traceback (most recent call last):
    ...
    adapt.errors.SweepSpecError: --set:1:15: an empty value; expected VALUE,VALUE,... or lo:hi:step
        world.dt=0.01,,0.02
                      ^
    """
    key, eq, rest = text.partition("=")
    if not eq or not key.strip():
        raise _fail("--set", text, len(text) + 1 if not eq else 1,
                    "expected KEY=VALUES (for example world.objects.ball.restitution=0.6,0.8 "
                    "or reality.camera_offset_deg=0:2:0.5)")
    path = key.strip()
    items: list[Item] = []
    seen: dict[str, int] = {}
    for part, col in _split(rest, len(key) + 2):
        if not part.strip():
            raise _fail("--set", text, col, "an empty value; expected VALUE,VALUE,... or "
                        "lo:hi:step")
        lead = len(part) - len(part.lstrip())
        m = _RANGE.match(part)
        texts = _stepped(m, "--set", text, col + lead) if m else [part.strip()]
        for t in texts:
            value = canonical(t)
            ident = repr(value)
            if ident in seen:
                raise _fail("--set", text, col + lead, f"the value {t} is given twice for "
                            f"{path} (first at column {seen[ident]})")
            seen[ident] = col + lead
            items.append(Item(t, value, col + lead, m is not None))
    return Axis(path, tuple(items), text)
