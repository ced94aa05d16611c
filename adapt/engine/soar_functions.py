"""The rest of Soar 9.6's default right-hand-side functions.

Soar registers these by default (``rhs_functions.cpp``,
``rhs_functions_math.cpp``); each follows the kernel's code -- results,
types, formatting and error messages -- and was checked against the real
kernel (PyPI ``soar-sml`` 9.6.5) by the agents ``rhs_more_*.soar`` of
``tests/engine/agents``.

======================================  =============================================
``(string x)``                          the text of ``x``; floats ``%.17f``
``(capitalize-symbol s)`` ``(trim s)``  first letter upper-cased; blanks (space, tab,
                                        newline) trimmed; strings only
``(strlen x)``                          length of the text of ``x`` (floats ``%f``)
``(dc)``                                the decision count
``(timestamp)``                         local time ``YYYY-MM-DD HH:MM:SS.mmm``
``(min a ...)`` ``(max a ...)``         int if every argument is an int, else float
``(sin a)`` ``(cos a)`` ``(sqrt a)``    float
``(atan2 y x)``                         float
``(round-off n m)``                     ``n`` rounded to the nearest ``m`` (ints:
                                        ``m * ((n +- m/2) / m)``, floats in tenths)
``(round-off-heading n m)``             the same, then into ``(-180, 180]``
``(compute-heading x1 y1 x2 y2)``       int degrees, Soar's heading convention
``(compute-range x1 y1 x2 y2)``         int: the distance, truncated
``(compute-dice-probability d s c p)``  float: chance that ``c`` of ``d`` dice with
                                        ``s`` sides show a face (``p``: eq ne lt gt le ge)
``(rand-int [n])``                      Soar's generator: ``[0, n]``, or a 32-bit
                                        number without (or with a non-positive) ``n``
``(rand-float [n])``                    ``[0, n]`` or ``[0, 1]``
``(size id)``                           the number of WMEs of ``id``
``(sum id)`` ``(product id)``           over the int values of ``id``'s WMEs
``(set-count id attr [a2 [a3]])``       the values of ``(id ^attr)`` (or the path
``set-sum set-multiply set-min``        ``^attr.a2.a3``): their count, or the sum ...
``set-max set-range set-mean``          of the numeric ones as a float (``NaN`` when
``set-stdev``                           there is none)
``(deep-copy id)``                      a copy of the structure under ``id``: a new
                                        identifier ``D<n>``, new identifiers for the
                                        copied ones, the WMEs made by the firing
``(count x ...)``                       adds one to the agent's counter ``x``
``(wait ms)``                           sleeps (default 1 ms)
``(trace level x ...)``                 writes when the agent traces ``level`` (1 by
                                        default: ``(trace 0 ...)`` and ``(trace 1 ...)``)
``(log channel x ...)``                 writes when the channel is on (none is)
``(dont-learn s)`` ``(force-learn s)``  nothing: learning is off
``(succeeded)`` ``(failed)``            ``(halt)``, as Soar 9.6.5 reads them (with
                                        its warning at load)
======================================  =============================================

Soar's ``@`` and ``link-stm-to-ltm`` (semantic memory), ``accept`` (reads the
terminal), ``from-st-xml``, ``exec`` and ``cmd`` (call out of the agent) are
refused at load time with the reason.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Callable, Sequence

from adapt.engine.symbols import Float, Identifier, Symbol, format_symbol

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.functions import RhsContext

__all__ = ["SOAR_FUNCTIONS", "REFUSED_FUNCTIONS", "LOAD_WARNINGS", "soar_string",
           "SoarFunction"]

#: ``(name, implementation, min_args, max_args, as_value, as_action)``
SoarFunction = tuple[str, Callable[[Sequence[Symbol], "RhsContext"], "Symbol | None"], int,
                     "int | None", bool, bool]

#: Soar functions adapt does not run, with why (a load-time error).
REFUSED_FUNCTIONS: dict[str, str] = {
    "@": "semantic memory is not implemented",
    "link-stm-to-ltm": "semantic memory is not implemented",
    "accept": "it reads a line from the terminal, which an agent in adapt never does",
    "from-st-xml": "reading XML into working memory is not implemented",
    "exec": "it calls a function registered with Soar's client library; register a Python "
            "function with Agent.register_function instead",
    "cmd": "it runs a Soar command, which adapt never does from a rule",
}

#: Warnings Soar prints when a rule calls these (the function is then read as another).
LOAD_WARNINGS: dict[str, str] = {
    "succeeded": "WARNING: Replacing function named succeeded with halt since this is a "
                 "unit test",
    "failed": "WARNING: Replacing function named failed with halt since this is a unit test",
}


def _number(a: Symbol) -> float | None:
    if type(a) is int or type(a) is Float:
        return float(a)
    return None


def soar_string(value: Symbol) -> str:
    """The text ``(string x)`` gives: floats with 17 decimals (``%.17f``).

    >>> soar_string(Float(0.1)), soar_string(3), soar_string("a")
    ('0.10000000000000001', '3', 'a')
    """
    if type(value) is Float:
        return "%.17f" % value
    return format_symbol(value)


# -- strings -------------------------------------------------------------------------------

def _string(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return soar_string(args[0])


def _capitalize(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is not str:
        context.error(f"non-symbol ({format_symbol(a)}) passed to capitalize-symbol function.")
        return None
    return a[:1].upper() + a[1:]


def _trim(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is not str:
        context.error(f"non-symbol ({format_symbol(a)}) passed to 'trim' function.")
        return None
    return a.strip(" \t\n")


def _strlen(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return len(format_symbol(args[0]).encode("utf-8"))


def _dc(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return context.decision_count()


def _timestamp(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    now = time.time()
    t = time.localtime(now)
    return (f"{t.tm_year:04d}-{t.tm_mon:02d}-{t.tm_mday:02d} {t.tm_hour:02d}:{t.tm_min:02d}:"
            f"{t.tm_sec:02d}.{int((now % 1) * 1000):03d}")


# -- arithmetic -------------------------------------------------------------------------------

def _extreme(name: str, pick_max: bool) -> Callable[[Sequence[Symbol], RhsContext],
                                                   "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        for a in args:
            if _number(a) is None:
                context.error(f"non-number ({format_symbol(a)}) passed to {name} function")
                return None
        if not args:
            return 0
        if all(type(a) is int for a in args):
            ints = [a for a in args if type(a) is int]
            return max(ints) if pick_max else min(ints)
        floats = [float(a) for a in args if type(a) is int or type(a) is Float]
        return Float(max(floats) if pick_max else min(floats))
    return fn


def _unary_float(name: str, f: Callable[[float], float]) -> Callable[
        [Sequence[Symbol], RhsContext], "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        x = _number(args[0])
        if x is None:
            context.error(f"'{name}' function called with non-numeric argument "
                          f"{format_symbol(args[0])}")
            return None
        try:
            return Float(f(x))
        except ValueError:  # sqrt of a negative number: C gives NaN
            return Float(math.nan)
    return fn


def _atan2(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    y, x = _number(args[0]), _number(args[1])
    for a, v in zip(args, (y, x)):
        if v is None:
            context.error(f"non-number ({format_symbol(a)}) passed to atan2")
            return None
    return Float(math.atan2(y, x))  # type: ignore[arg-type]


def _c_div(a: int, b: int) -> int:
    """C's integer division (truncates toward zero)."""
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


def _round_int(n: int, m: int) -> int:
    if m == 0:
        raise ZeroDivisionError
    half = _c_div(m, 2)
    return m * _c_div(n - half if n < 0 else n + half, m)


def _round_float(n: float, m: float) -> float:
    n10 = math.trunc(n * 10.0)
    m10 = math.trunc(m * 10.0)
    half = math.trunc(m10 / 2.0)
    q = math.trunc((n10 - half) / m10) if n10 < 0 else math.trunc((n10 + half) / m10)
    return (m10 * q) / 10.0


def _heading_int(n: int) -> int:
    while n <= -180:
        n += 360
    while n > 180:
        n -= 360
    return n


def _heading_float(n: float) -> float:
    while n <= -180.0:
        n += 360.0
    while n > 180.0:
        n -= 360.0
    return n


def _round_off(name: str, heading: bool) -> Callable[[Sequence[Symbol], RhsContext],
                                                    "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        a, b = args
        n = _number(a)
        m = _number(b)
        if n is None:
            n = 0.0
        try:
            if type(b) is Float:
                value = _round_float(n, float(b))
                return Float(_heading_float(value) if heading else value)
            value_i = _round_int(int(n), int(m) if m is not None else 0)
        except ZeroDivisionError:
            context.error(f"attempt to divide by zero in '{name}'.")
            return None
        return _heading_int(value_i) if heading else value_i
    return fn


_PI = 3.141592653589


def _four_numbers(name: str, args: Sequence[Symbol],
                  context: RhsContext) -> list[float] | None:
    values = [_number(a) for a in args]
    for a, v in zip(args, values):
        if v is None:
            context.error(f"non-number ({format_symbol(a)}) passed to - {name}")
            return None
    return values  # type: ignore[return-value]


def _compute_range(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    v = _four_numbers("compute-range", args, context)
    if v is None:
        return None
    return int(math.sqrt((v[0] - v[2]) ** 2 + (v[1] - v[3]) ** 2))


def _compute_heading(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    v = _four_numbers("compute-heading", args, context)
    if v is None:
        return None
    x1, y1, x2, y2 = (float(math.trunc(x)) for x in v)  # C casts floats to int64 first
    dx, dy = x2 - x1, y2 - y1
    mag = math.sqrt(dx * dx + dy * dy)
    if mag < 0.01:
        dx, dy = 1.0, 0.0
    else:
        dx, dy = dx / mag, dy / mag
    heading = math.atan2(dy, dx) - _PI / 2
    if heading < 0.0:
        heading += 2 * _PI
    heading = 2 * _PI - heading
    if heading > _PI:
        heading -= 2 * _PI
    degrees = math.trunc((heading * 180) / _PI)
    rounded = _round_int(degrees, 1)
    bounded = int(math.fmod(rounded, 360))
    if bounded > 180:
        bounded -= 360
    if bounded <= -180:
        bounded += 360
    return bounded


def _binomial(n: int, m: int) -> int:
    return math.comb(n, m) if 0 <= m <= n else 0


def _dice_exact(dice: int, sides: int, count: int) -> float:
    if dice < 0 or count < 0 or sides < 1:
        return 0.0
    if dice == 0:
        return 1.0 if count == 0 else 0.0
    if count > dice:
        return 0.0
    result = float(_binomial(dice, count))
    result *= 1.0 / math.pow(sides, count)
    result *= math.pow(sides - 1, dice - count) / math.pow(sides, dice - count)
    return result


def _dice_at_least(dice: int, sides: int, count: int) -> float:
    if dice < 0 or count < 0 or sides < 1:
        return 0.0
    return sum(_dice_exact(dice, sides, count + i) for i in range(dice - count + 1))


def _zero(x: float) -> float:
    return 0.0 if abs(x) <= 0.00001 else x


def _dice(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    numbers: list[int] = []
    for a, role in zip(args[:3], ("dice", "sides", "count")):
        v = _number(a)
        if v is None:
            context.error(f"non-number ({format_symbol(a)}) passed as '{role}' to - "
                          "compute-dice-probability")
            return None
        numbers.append(a if type(a) is int else math.trunc(v))
    dice, sides, count = numbers
    pred = args[3]
    if type(pred) is not str:
        context.error(f"non-string ({format_symbol(pred)}) passed as 'pred' to - "
                      "compute-dice-probability")
        return None
    exact = _dice_exact(dice, sides, count)
    if pred == "eq":
        ret = 0.0 if count < 0 or count > dice else _zero(exact)
    elif pred == "ne":
        ret = 1.0 if count < 0 or count > dice else _zero(1 - exact)
    elif pred == "lt":
        ret = (0.0 if count <= 0 else 1.0 if count > dice
               else _zero(1 - _dice_at_least(dice, sides, count)))
    elif pred == "gt":
        ret = (1.0 if count < 0 else 0.0 if count >= dice
               else _zero(_dice_at_least(dice, sides, count) - exact))
    elif pred == "le":
        ret = (0.0 if count < 0 else 1.0 if count >= dice
               else _zero((1 - _dice_at_least(dice, sides, count)) + exact))
    elif pred == "ge":
        ret = (1.0 if count <= 0 else 0.0 if count > dice
               else _zero(_dice_at_least(dice, sides, count)))
    else:
        context.error(f"invalid string ({pred}) passed as 'pred' to - compute-dice-probability")
        return None
    return Float(ret)


def _rand_int(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    n = 0
    if args:
        a = args[0]
        if type(a) is int:
            n = a
        elif type(a) is Float:
            n = math.trunc(a)
        else:
            context.error(f"non-number ({format_symbol(a)}) passed to - rand-int")
            return None
    rng = context.soar_random()
    if n > 0:
        return rng.rand_int(n & 0xFFFFFFFF)
    return rng.rand_uint32()


def _rand_float(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    n = 0.0
    if args:
        v = _number(args[0])
        if v is None:
            context.error(f"non-number ({format_symbol(args[0])}) passed to - rand-float")
            return None
        n = v
    rng = context.soar_random()
    return Float(rng.rand() * n if n > 0 else rng.rand())


# -- working memory -----------------------------------------------------------------------------

def _size(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is not Identifier:
        context.error(f"non-symbol ({format_symbol(a)}) passed to size function")
        return None
    return len(context.wmes_of(a))


def _fold(name: str, product: bool) -> Callable[[Sequence[Symbol], RhsContext],
                                                "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        a = args[0]
        if type(a) is not Identifier:
            context.error(f"non-symbol ({format_symbol(a)}) passed to {name} function")
            return None
        total = 1 if product else 0
        for w in context.wmes_of(a):
            v = w[2]
            if type(v) is not int:
                context.error(f"non-integer ({format_symbol(v)}) in a WME of {a} passed to "
                              f"{name} function")
                return None
            total = total * v if product else total + v
        return ((total + 2**31) % 2**32) - 2**31  # Soar sums in a C int
    return fn


def _set_values(args: Sequence[Symbol], context: RhsContext) -> list[Symbol] | str:
    """The values the set functions reduce, or Soar's error string."""
    ident = args[0]
    if type(ident) is not Identifier:
        return "|ERROR: First parameter needs to be an identifier.|"
    if len(args) < 2:
        return "|ERROR: Missing set attribute parameter.|"
    level: list[Symbol] = [ident]
    for attr in args[1:4]:
        nxt: list[Symbol] = []
        for ident2 in level:
            if type(ident2) is Identifier:
                nxt.extend(w[2] for w in context.wmes_of(ident2) if w[1] == attr)
        level = nxt
    return level


def _set(kind: str) -> Callable[[Sequence[Symbol], RhsContext], "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        values = _set_values(args, context)
        if isinstance(values, str):
            return values
        if kind == "count":
            return len(values)
        numbers = [float(v) for v in values if type(v) is int or type(v) is Float]
        if not numbers:
            return "NaN"
        if kind == "sum":
            return Float(sum(numbers))
        if kind == "multiply":
            out = 1.0
            for x in numbers:
                out *= x
            return Float(out)
        if kind == "min":
            return Float(min(numbers))
        if kind == "max":
            return Float(max(numbers))
        if kind == "range":
            return Float(max(numbers) - min(numbers))
        mean = sum(numbers) / len(numbers)
        if kind == "mean":
            return Float(mean)
        return Float(math.sqrt(sum((x - mean) ** 2 for x in numbers) / len(numbers)))
    return fn


def _deep_copy(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is not Identifier:
        return "*symbol not id*"
    return context.deep_copy(a)


# -- actions -------------------------------------------------------------------------------------

def _count(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    for a in args:
        context.count(format_symbol(a))
    return None


def _wait(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    first = args[0] if args else None
    ms = first if type(first) is int else 1
    time.sleep(max(0, ms) / 1000.0)
    return None


def _trace(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    level = args[0]
    if type(level) is not int or not 0 <= level <= 5:
        context.error("First argument of agent's (trace) rhs-function must be an integer trace "
                      f"level between 0 and 5.  {format_symbol(level)} is invalid.")
        return None
    if context.traces(level):
        context.write("".join(format_symbol(a) for a in args[1:]))
    return None


def _log(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    channel = args[0]
    if type(channel) is not int or not 1 <= channel <= 99:
        context.error("First argument of agent's (log) rhs-function must be an integer channel "
                      f"number between 1 and 99.  {format_symbol(channel)} is invalid.")
    return None


def _learning(name: str) -> Callable[[Sequence[Symbol], RhsContext], "Symbol | None"]:
    def fn(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        if type(args[0]) is not Identifier:
            context.error(f"non-identifier ({format_symbol(args[0])}) passed to {name} "
                          "function.")
        return None
    return fn


def _halt(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    context.halt()
    return None


SOAR_FUNCTIONS: tuple[SoarFunction, ...] = (
    ("string", _string, 1, 1, True, False),
    ("capitalize-symbol", _capitalize, 1, 1, True, False),
    ("trim", _trim, 1, 1, True, False),
    ("strlen", _strlen, 1, 1, True, False),
    ("dc", _dc, 0, 0, True, False),
    ("timestamp", _timestamp, 0, 0, True, False),
    ("min", _extreme("min", False), 0, None, True, False),
    ("max", _extreme("max", True), 0, None, True, False),
    ("sin", _unary_float("sin", math.sin), 1, 1, True, False),
    ("cos", _unary_float("cos", math.cos), 1, 1, True, False),
    ("sqrt", _unary_float("sqrt", math.sqrt), 1, 1, True, False),
    ("atan2", _atan2, 2, 2, True, False),
    ("round-off", _round_off("round_off", False), 2, 2, True, False),
    ("round-off-heading", _round_off("round-off-heading", True), 2, 2, True, False),
    ("compute-heading", _compute_heading, 4, 4, True, False),
    ("compute-range", _compute_range, 4, 4, True, False),
    ("compute-dice-probability", _dice, 4, 4, True, False),
    ("rand-int", _rand_int, 0, None, True, False),
    ("rand-float", _rand_float, 0, None, True, False),
    ("size", _size, 1, 1, True, False),
    ("sum", _fold("sum", False), 1, 1, True, False),
    ("product", _fold("product", True), 1, 1, True, False),
    ("set-count", _set("count"), 0, None, True, False),
    ("set-sum", _set("sum"), 0, None, True, False),
    ("set-multiply", _set("multiply"), 0, None, True, False),
    ("set-min", _set("min"), 0, None, True, False),
    ("set-max", _set("max"), 0, None, True, False),
    ("set-range", _set("range"), 0, None, True, False),
    ("set-mean", _set("mean"), 0, None, True, False),
    ("set-stdev", _set("stdev"), 0, None, True, False),
    ("deep-copy", _deep_copy, 1, 1, True, False),
    ("count", _count, 0, None, False, True),
    ("wait", _wait, 0, None, False, True),
    ("trace", _trace, 1, None, False, True),
    ("log", _log, 1, None, False, True),
    ("dont-learn", _learning("dont-learn"), 1, 1, False, True),
    ("force-learn", _learning("force-learn"), 1, 1, False, True),
    ("succeeded", _halt, 0, 0, False, True),
    ("failed", _halt, 0, 0, False, True),
)
