"""Right-hand-side functions: the built-ins of Soar and users' Python functions.

A :class:`FunctionTable` maps names to :class:`RhsFunction` records.  The parser
checks every call against a table (unknown names and wrong argument counts
are load-time errors, and so are value functions used as stand-alone actions
and vice versa, as in Soar); the decision cycle evaluates values with
:func:`evaluate`.

The built-ins follow Soar 9.6 (each checked against the real kernel, 9.6.5):

===========================  ==================================================
``(+ a ...)`` ``(* a ...)``  sum / product; int if every argument is an int,
                             else float; ``(+)`` is 0, ``(*)`` is 1; ints wrap
                             at 64 bits as in Soar
``(- a ...)``                ``(- a)`` negates, else subtracts the rest from a
``(/ a ...)``                always a float; ``(/ a)`` is ``1 / a``
``(div a b)`` ``(mod a b)``  ints only; quotient truncated toward zero and the
                             matching remainder (``(mod -7 3)`` is ``-1``)
``(abs a)``                  absolute value, keeps the type
``(int a)`` ``(float a)``    conversion; floats truncate toward zero; strings
                             are read like C's ``strtol`` / ``strtod`` (the
                             longest numeric prefix, 0 when there is none)
``(concat a ...)``           the arguments' text, floats as ``%f``, no spaces
``(make-constant-symbol a ...)``  a new string: the concatenated prefix (default
                             ``constant``) and a number from one shared counter
``(ifeq a b c d)``           ``c`` if ``a`` and ``b`` are the same symbol, else ``d``
``(crlf)``                   ``"\\n"`` (a value: ``(write (crlf))``)
``(write a ...)``            prints the arguments' text, no spaces (stand-alone)
``(halt)``                   halts the agent (stand-alone)
``(interrupt)``              stops the run without halting (stand-alone)
===========================  ==================================================

Run-time errors (a non-number passed to ``+``, division by zero, a non-integer
passed to ``div``, an identifier passed to ``int`` ...) are what Soar does:
the message (Soar's wording) goes to :meth:`RhsContext.error` and the
function has no value (``None``), so the action that used it is skipped.

Examples
--------
>>> from adapt.engine.production import FunctionCall, Variable
>>> from adapt.engine.symbols import Float
>>> class Ctx:  # the parts of an RhsContext these calls use
...     def write(self, text): print(text, end="")
...     def halt(self): print("<halt>")
...     def interrupt(self): print("<interrupt>")
...     def error(self, message): print("Error:", message)
...     def make_constant_symbol(self, prefix): return prefix + "1"
>>> table = default_functions()
>>> call = FunctionCall("/", (Variable("<x>"), 4))
>>> evaluate(call, {Variable("<x>"): 3}, table, Ctx())
Float(0.75)
>>> evaluate(FunctionCall("write", ("x=", FunctionCall("+", (1, Float(2.5))))), {}, table, Ctx())
x=3.500000
>>> evaluate(FunctionCall("div", (7, 0)), {}, table, Ctx()) is None
Error: attempt to divide ('div') by zero.
True
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Callable, Mapping, Protocol, Sequence

from adapt.engine.commands import ON_SOAR
from adapt.engine.production import FunctionCall, RhsValue, Variable
from adapt.engine.soar_functions import REFUSED_FUNCTIONS, SOAR_FUNCTIONS
from adapt.engine.soar_random import SoarRandom
from adapt.engine.symbols import Float, Identifier, Symbol, format_symbol, to_symbol
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = [
    "RhsContext",
    "RhsFunction",
    "FunctionTable",
    "default_functions",
    "evaluate",
]


class RhsContext(Protocol):
    """What a right-hand-side function may do to the agent that fires it.

    ``copies`` and ``copied_ids``: the WMEs and identifiers ``deep-copy`` made
    during the current action; the firing asserts the WMEs with its own
    support, the identifiers at the level of the identifier the copy is
    attached to (the kernel empties both).
    """

    copies: list[tuple[Identifier, Symbol, Symbol]]
    copied_ids: list[Identifier]

    def write(self, text: str) -> None:
        """Append ``text`` to the agent's output (``write``, no separators added)."""

    def halt(self) -> None:
        """Halt the agent once the current elaboration cycle completes."""

    def interrupt(self) -> None:
        """Stop the run before the next decision phase, without halting."""

    def error(self, message: str) -> None:
        """Report a run-time error of a function (Soar prints ``Error: message``)."""

    def make_constant_symbol(self, prefix: str) -> str:
        """A string ``prefix`` + n from the agent's one shared counter, unused so far."""

    def decision_count(self) -> int:
        """The number of decisions so far (``dc``)."""

    def soar_random(self) -> SoarRandom:
        """The agent's random numbers (``rand-int``, ``rand-float``)."""

    def wmes_of(self, ident: Identifier) -> Sequence[WME]:
        """The WMEs of ``ident`` in working memory (acceptable preferences excluded)."""

    def deep_copy(self, ident: Identifier) -> Identifier:
        """A new identifier whose structure copies ``ident``'s; the copied WMEs are
        made by the firing that calls it (``deep-copy``)."""

    def count(self, name: str) -> None:
        """Add one to the agent's counter ``name`` (``count``)."""

    def traces(self, level: int) -> bool:
        """Whether the agent traces ``level`` (``trace``)."""


#: A built-in's implementation: evaluated arguments and the context.
Implementation = Callable[[Sequence[Symbol], RhsContext], "Symbol | None"]


@dataclass(frozen=True, slots=True)
class RhsFunction:
    """One right-hand-side function.

    ``as_value`` / ``as_action``: whether it may be used as a value
    (``(<s> ^x (+ 1 2))``) and as a stand-alone action (``(write hi)``).
    ``max_args`` ``None`` means any number.
    """

    name: str
    implementation: Implementation
    min_args: int = 0
    max_args: int | None = None
    as_value: bool = True
    as_action: bool = True

    def arity_text(self) -> str:
        """The expected argument count, in words."""
        if self.max_args == self.min_args:
            return f"{self.min_args}"
        if self.max_args is None:
            return f"at least {self.min_args}"
        return f"{self.min_args} to {self.max_args}"


class FunctionTable:
    """Right-hand-side functions by name.

    Examples
    --------
    >>> table = default_functions()
    >>> table.register("twice", lambda x: 2 * x, min_args=1, max_args=1)
    >>> table.check_call("twice", 2, as_action=False)
    "wrong number of arguments to function 'twice' (expected 1, got 2)"
    >>> table.check_call("nope", 0, as_action=True)
    "unknown RHS function 'nope'"
    >>> print(table.check_call("twice", 1, as_action=False))
    None
    """

    def __init__(self, functions: Mapping[str, RhsFunction] | None = None) -> None:
        self._functions: dict[str, RhsFunction] = dict(functions or {})

    def __contains__(self, name: object) -> bool:
        return name in self._functions

    def names(self) -> list[str]:
        """Every function name, sorted."""
        return sorted(self._functions)

    def get(self, name: str) -> RhsFunction | None:
        """The function called ``name``, or ``None``."""
        return self._functions.get(name)

    def copy(self) -> FunctionTable:
        """An independent table with the same functions."""
        return FunctionTable(self._functions)

    def add(self, function: RhsFunction) -> None:
        """Add a function record (a name may be defined once).

        Raises
        ------
        EngineError
            If the name is already defined.
        """
        if function.name in self._functions:
            raise EngineError(f"RHS function {function.name!r} is already defined")
        self._functions[function.name] = function

    def register(
        self,
        name: str,
        fn: Callable[..., object],
        *,
        min_args: int = 0,
        max_args: int | None = None,
    ) -> None:
        """Make the Python function ``fn`` callable from rules as ``(name ...)``.

        ``fn`` is called with the evaluated argument symbols (``str``, ``int``,
        :class:`~adapt.engine.symbols.Float`, or identifiers).  Its result goes
        through :func:`~adapt.engine.symbols.to_symbol`; ``None`` means "no
        value" (an action that uses it is skipped, as in Soar).  A user function
        may be used both as a value and as a stand-alone action.

        Raises
        ------
        EngineError
            For an empty name, a name already defined, or bad argument counts.
            At run time, when ``fn`` raises or returns something that is not a
            symbol.
        """
        if not isinstance(name, str) or not name or any(c.isspace() or c in "()|^{}" for c in name):
            raise EngineError(f"{name!r} is not a usable RHS function name")
        if min_args < 0 or (max_args is not None and max_args < min_args):
            raise EngineError(f"bad argument counts for RHS function {name!r}: {min_args}..{max_args}")

        def call(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
            try:
                result = fn(*args)
            except Exception as exc:  # a user's function failing is a run-time error
                raise EngineError(f"RHS function {name!r} raised {type(exc).__name__}: {exc}") from exc
            if result is None:
                return None
            try:
                return to_symbol(result)
            except TypeError:
                raise EngineError(
                    f"RHS function {name!r} returned {result!r}, which is not a symbol "
                    "(expected a string, int or float)"
                ) from None

        self.add(RhsFunction(name, call, min_args, max_args))

    def check_call(self, name: str, nargs: int, *, as_action: bool) -> str | None:
        """Why ``(name arg1 ... argN)`` cannot be used this way, or ``None`` if it can."""
        fn = self._functions.get(name)
        if fn is None:
            why = REFUSED_FUNCTIONS.get(name)
            if why is not None:
                hint = "" if name in ("exec", "accept") else f"; {ON_SOAR}"
                return f"RHS function {name!r} is one adapt does not run: {why}{hint}"
            return f"unknown RHS function {name!r}"
        if as_action and not fn.as_action:
            return f"function {name!r} cannot be used as a stand-alone action"
        if not as_action and not fn.as_value:
            return f"function {name!r} can only be used as a stand-alone action"
        if nargs < fn.min_args or (fn.max_args is not None and nargs > fn.max_args):
            return (
                f"wrong number of arguments to function {name!r} "
                f"(expected {fn.arity_text()}, got {nargs})"
            )
        return None

    def call(self, name: str, args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
        """Call ``name`` with evaluated arguments; ``None`` when it has no value.

        Raises
        ------
        EngineError
            For an unknown function (the parser rules this out for loaded rules).
        """
        fn = self._functions.get(name)
        if fn is None:
            raise EngineError(f"unknown RHS function {name!r}")
        return fn.implementation(args, context)


def evaluate(
    value: RhsValue,
    bindings: Mapping[Variable, Symbol],
    table: FunctionTable,
    context: RhsContext,
) -> Symbol | None:
    """The symbol an RHS value stands for in one firing.

    Variables must be in ``bindings`` (the cycle adds new identifiers for RHS
    variables not bound on the left-hand side before evaluating).  ``None``
    means a function call had no value (a run-time error reported through
    ``context.error``, or a function with no result such as ``write``); the
    action that needed the value is skipped.

    Raises
    ------
    EngineError
        For a variable missing from ``bindings``.
    """
    if isinstance(value, Variable):
        try:
            return bindings[value]
        except KeyError:
            raise EngineError(f"variable {value.name} has no binding in this firing") from None
    if isinstance(value, FunctionCall):
        args: list[Symbol] = []
        for arg in value.args:
            v = evaluate(arg, bindings, table, context)
            if v is None:
                return None
            args.append(v)
        return table.call(value.name, args, context)
    return value


# ----------------------------------------------------------------- built-ins

_INT64 = 2**63


def _wrap(n: int) -> int:
    """Two's-complement 64-bit wrap, as Soar's ``int64_t`` arithmetic."""
    return ((n + _INT64) % (2 * _INT64)) - _INT64


def _numbers(name: str, args: Sequence[Symbol], context: RhsContext) -> list[int | float] | None:
    """The arguments as numbers, or None (and an error) when one is not a number."""
    out: list[int | float] = []
    for a in args:
        if not isinstance(a, (int, float)):
            context.error(f"non-number ({format_symbol(a)}) passed to {name} function")
            return None
        out.append(a)
    return out


def _ints(values: list[int | float]) -> list[int] | None:
    """``values`` when every one is an int."""
    out: list[int] = []
    for v in values:
        if not isinstance(v, int):
            return None
        out.append(v)
    return out


def _plus(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    if len(args) == 2:  # the common case
        a, b = args
        if type(a) is int and type(b) is int:
            n = a + b
            return n if -_INT64 <= n < _INT64 else _wrap(n)
    values = _numbers("+", args, context)
    if values is None:
        return None
    ints = _ints(values)
    if ints is not None:
        return _wrap(sum(ints))
    return Float(sum(float(v) for v in values))


def _times(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    values = _numbers("*", args, context)
    if values is None:
        return None
    ints = _ints(values)
    if ints is not None:
        product = 1
        for i in ints:
            product = _wrap(product * i)
        return product
    result = 1.0
    for v in values:
        result *= float(v)
    return Float(result)


def _minus(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    if len(args) == 2:  # the common case
        a, b = args
        if type(a) is int and type(b) is int:
            n = a - b
            return n if -_INT64 <= n < _INT64 else _wrap(n)
    values = _numbers("-", args, context)
    if values is None:
        return None
    ints = _ints(values)
    if len(values) == 1:
        return _wrap(-ints[0]) if ints is not None else Float(-float(values[0]))
    if ints is not None:
        result = ints[0]
        for i in ints[1:]:
            result = _wrap(result - i)
        return result
    f = float(values[0])
    for v in values[1:]:
        f -= float(v)
    return Float(f)


def _divide(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    numbers = _numbers("/", args, context)
    if numbers is None:
        return None
    values = [float(a) for a in numbers]
    if len(values) == 1:
        values.insert(0, 1.0)
    result = values[0]
    for v in values[1:]:
        if v == 0.0:
            context.error("attempt to divide ('/') by zero.")
            return None
        result /= v
    return Float(result)


def _int_pair(name: str, args: Sequence[Symbol], context: RhsContext) -> tuple[int, int] | None:
    ints: list[int] = []
    for a in args:
        if not isinstance(a, int):
            context.error(f"non-integer ({format_symbol(a)}) passed to {name} function")
            return None
        ints.append(a)
    a, b = ints
    if b == 0:
        context.error(f"attempt to divide ('{name}') by zero.")
        return None
    return a, b


def _trunc_div(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


def _div(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    pair = _int_pair("div", args, context)
    return None if pair is None else _wrap(_trunc_div(*pair))


def _mod(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    pair = _int_pair("mod", args, context)
    if pair is None:
        return None
    a, b = pair
    return _wrap(a - b * _trunc_div(a, b))


def _abs(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is int:
        return _wrap(abs(a))
    if isinstance(a, float):
        return Float(abs(a) if float(a) != 0.0 else a)  # Soar keeps -0.0
    context.error(f"'abs' function called with non-numeric argument {format_symbol(a)}")
    return None


_STRTOL = re.compile(r"\s*([+-]?[0-9]+)")
_STRTOD = re.compile(r"\s*([+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)")


def _clamp64(n: int) -> int:
    return max(-_INT64, min(_INT64 - 1, n))


def _int(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if type(a) is int:
        return a
    if isinstance(a, float):
        f = float(a)
        if math.isnan(f):
            return 0
        return _clamp64(int(f)) if math.isfinite(f) else _clamp64(int(math.copysign(_INT64, f)))
    if isinstance(a, Identifier):
        context.error(f"identifier ({a.name}) passed to 'int' RHS function.")
        return None
    m = _STRTOL.match(str(a))
    return _clamp64(int(m.group(1))) if m else 0


def _float(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a = args[0]
    if isinstance(a, float):
        return Float(a)
    if type(a) is int:
        return Float(float(a))
    if isinstance(a, Identifier):
        context.error(f"identifier ({a.name}) passed to 'float' RHS function.")
        return None
    m = _STRTOD.match(str(a))
    if not m:
        return Float(0.0)
    f = float(m.group(1))
    if math.isinf(f):
        context.error(f"bad float ({a}) given to 'float' RHS function")
        return None
    return Float(f)


def _text(args: Sequence[Symbol]) -> str:
    return "".join(format_symbol(a) for a in args)


def _write(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    context.write(_text(args))
    return None


def _crlf(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return "\n"


def _halt(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    context.halt()
    return None


def _interrupt(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    context.interrupt()
    return None


def _concat(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return _text(args)


def _make_constant_symbol(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    return context.make_constant_symbol(_text(args) if args else "constant")


def _same(a: Symbol, b: Symbol) -> bool:
    if isinstance(a, Identifier) or isinstance(b, Identifier):
        return a is b
    return type(a) is type(b) and a == b


def _ifeq(args: Sequence[Symbol], context: RhsContext) -> Symbol | None:
    a, b, then, other = args
    return then if _same(a, b) else other


_BUILTINS: tuple[RhsFunction, ...] = (
    RhsFunction("+", _plus, as_action=False),
    RhsFunction("*", _times, as_action=False),
    RhsFunction("-", _minus, 1, None, as_action=False),
    RhsFunction("/", _divide, 1, None, as_action=False),
    RhsFunction("div", _div, 2, 2, as_action=False),
    RhsFunction("mod", _mod, 2, 2, as_action=False),
    RhsFunction("abs", _abs, 1, 1, as_action=False),
    RhsFunction("int", _int, 1, 1, as_action=False),
    RhsFunction("float", _float, 1, 1, as_action=False),
    RhsFunction("concat", _concat, as_action=False),
    RhsFunction("make-constant-symbol", _make_constant_symbol, as_action=False),
    RhsFunction("ifeq", _ifeq, 4, 4, as_action=False),
    RhsFunction("crlf", _crlf, 0, 0, as_action=False),
    RhsFunction("write", _write, as_value=False),
    RhsFunction("halt", _halt, 0, 0, as_value=False),
    RhsFunction("interrupt", _interrupt, 0, 0, as_value=False),
)


def default_functions() -> FunctionTable:
    """A new table holding only the built-ins (register your own on it): the
    functions above and the rest of Soar 9.6's defaults
    (:mod:`adapt.engine.soar_functions`).

    Examples
    --------
    >>> names = default_functions().names()
    >>> len(names), names[:8]
    (55, ['*', '+', '-', '/', 'abs', 'atan2', 'capitalize-symbol', 'compute-dice-probability'])
    """
    table = {f.name: f for f in _BUILTINS}
    for name, impl, least, most, as_value, as_action in SOAR_FUNCTIONS:
        table[name] = RhsFunction(name, impl, least, most, as_value, as_action)
    return FunctionTable(table)
