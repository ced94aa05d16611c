"""Right-hand-side functions.

Every expected value and error message below was checked against the real
Soar kernel (soar-sml 9.6.5, kernel 9.6.50) by running ``(write ...)`` and
``(<s> ^result ...)`` with the same call; "None" means Soar printed the error
and skipped the action.
"""

from __future__ import annotations

import pytest

from adapt.engine.functions import FunctionTable, default_functions, evaluate
from adapt.engine.parse import parse_rules
from adapt.engine.production import FunctionCall, Variable
from adapt.engine.symbols import Float, Identifier, Symbol, format_symbol
from adapt.errors import EngineError


class Context:
    """A recording RhsContext."""

    def __init__(self) -> None:
        self.output: list[str] = []
        self.errors: list[str] = []
        self.halted = False
        self.interrupted = False
        self.counter = 0

    def write(self, text: str) -> None:
        self.output.append(text)

    def halt(self) -> None:
        self.halted = True

    def interrupt(self) -> None:
        self.interrupted = True

    def error(self, message: str) -> None:
        self.errors.append(message)

    def make_constant_symbol(self, prefix: str) -> str:
        self.counter += 1
        return f"{prefix}{self.counter}"


S1 = Identifier("S", 1)


def value_of(call: str, ctx: Context | None = None) -> Symbol | None:
    """Parse ``call`` as an RHS value (with <s> bound to S1) and evaluate it."""
    rule = parse_rules(f"sp {{t (state <s>) --> (<s> ^result {call})}}").productions[0]
    return evaluate(rule.actions[0].value, {Variable("<s>"): S1}, default_functions(),
                    ctx or Context())


# (call, value as Soar writes it, Python type) -- checked against Soar 9.6.5
VALUES = [
    ("(+ 1 2)", "3", int),
    ("(+ 1 2.0)", "3.000000", Float),
    ("(+)", "0", int),
    ("(+ 0.1 0.2)", "0.300000", Float),
    ("(* 2 3)", "6", int),
    ("(* 2 2.5)", "5.000000", Float),
    ("(*)", "1", int),
    ("(* 4611686018427387904 4)", "0", int),
    ("(- 5)", "-5", int),
    ("(- 2.5)", "-2.500000", Float),
    ("(- 5 1 1)", "3", int),
    ("(- 1 1.0)", "0.000000", Float),
    ("(- 0)", "0", int),
    ("(/ 6 3)", "2.000000", Float),
    ("(/ 7 2)", "3.500000", Float),
    ("(/ 5)", "0.200000", Float),
    ("(div -7 2)", "-3", int),
    ("(div 7 -2)", "-3", int),
    ("(div -7 -2)", "3", int),
    ("(mod -7 3)", "-1", int),
    ("(mod 7 -3)", "1", int),
    ("(mod -7 -3)", "-1", int),
    ("(abs -3)", "3", int),
    ("(abs -2.5)", "2.500000", Float),
    ("(abs -0.0)", "-0.000000", Float),
    ("(int 3.7)", "3", int),
    ("(int -3.7)", "-3", int),
    ("(int -0.5)", "0", int),
    ("(int 3)", "3", int),
    ("(int |12|)", "12", int),
    ("(int abc)", "0", int),
    ("(int 1e5)", "1", int),
    ("(int 2.5e3)", "2500", int),
    ("(int .5)", "0", int),
    ("(int |3.9|)", "3", int),
    ("(int |-7|)", "-7", int),
    ("(int |+7|)", "7", int),
    ("(int | 7|)", "7", int),
    ("(int 99999999999)", "99999999999", int),
    ("(int 3e9999)", "3", int),
    ("(float 3)", "3.000000", Float),
    ("(float 2.5)", "2.500000", Float),
    ("(float |2.5|)", "2.500000", Float),
    ("(float abc)", "0.000000", Float),
    ("(float |1e5|)", "100000.000000", Float),
    ("(float 1.)", "1.000000", Float),
    ("(float 0.1)", "0.100000", Float),
    ("(concat a 1.5 b 2)", "a1.500000b2", str),
    ("(concat <s> 1)", "S11", str),
    ("(concat)", "", str),
    ("(crlf)", "\n", str),
    ("(ifeq 1 1 yes no)", "yes", str),
    ("(ifeq 1 1.0 yes no)", "no", str),
    ("(ifeq <s> <s> y n)", "y", str),
    ("(ifeq 1 1 <s> b)", "S1", Identifier),
    ("(make-constant-symbol)", "constant1", str),
    ("(make-constant-symbol item)", "item1", str),
    ("(make-constant-symbol a b)", "ab1", str),
    ("(make-constant-symbol |a b|)", "a b1", str),
    ("(make-constant-symbol 5)", "51", str),
    ("(make-constant-symbol <s>)", "S11", str),
]


@pytest.mark.parametrize("call, text, kind", VALUES, ids=[v[0] for v in VALUES])
def test_builtin_values(call: str, text: str, kind: type) -> None:
    ctx = Context()
    result = value_of(call, ctx)
    assert result is not None and type(result) is kind
    assert format_symbol(result) == text
    assert ctx.errors == []


# (call, Soar's error message) -- checked against Soar 9.6.5; the action is skipped
ERRORS = [
    ("(/ 1 0)", "attempt to divide ('/') by zero."),
    ("(/ 1 0.0)", "attempt to divide ('/') by zero."),
    ("(/ 0.0 0)", "attempt to divide ('/') by zero."),
    ("(div 7 0)", "attempt to divide ('div') by zero."),
    ("(mod 7 0)", "attempt to divide ('mod') by zero."),
    ("(+ a 1)", "non-number (a) passed to + function"),
    ("(- a)", "non-number (a) passed to - function"),
    ("(* a 2)", "non-number (a) passed to * function"),
    ("(/ a)", "non-number (a) passed to / function"),
    ("(div 7.5 2)", "non-integer (7.500000) passed to div function"),
    ("(mod 7 2.0)", "non-integer (2.000000) passed to mod function"),
    ("(div a 2)", "non-integer (a) passed to div function"),
    ("(abs x)", "'abs' function called with non-numeric argument x"),
    ("(int <s>)", "identifier (S1) passed to 'int' RHS function."),
    ("(float <s>)", "identifier (S1) passed to 'float' RHS function."),
    ("(float |1e400|)", "bad float (1e400) given to 'float' RHS function"),
    ("(+ 1 (/ 1 0))", "attempt to divide ('/') by zero."),
]


@pytest.mark.parametrize("call, message", ERRORS, ids=[e[0] for e in ERRORS])
def test_builtin_runtime_errors(call: str, message: str) -> None:
    ctx = Context()
    assert value_of(call, ctx) is None
    assert ctx.errors == [message]


def test_write_crlf_halt_interrupt() -> None:
    rule = parse_rules(
        "sp {t (state <s> ^x <x>) --> (write |x = | <x> | | 1.5 (crlf)) (halt) (interrupt)}"
    ).productions[0]
    ctx = Context()
    table = default_functions()
    for action in rule.actions:
        assert evaluate(action.call, {Variable("<s>"): S1, Variable("<x>"): 7}, table, ctx) is None
    # Soar 9.6.5: write adds no spaces and prints floats as %f
    assert ctx.output == ["x = 7 1.500000\n"]
    assert ctx.halted and ctx.interrupted


def test_make_constant_symbol_uses_the_context_counter() -> None:
    ctx = Context()
    # Soar 9.6.5: one shared counter -> constant1 item2 constant3 item4
    assert [value_of(c, ctx) for c in ("(make-constant-symbol)", "(make-constant-symbol item)",
                                       "(make-constant-symbol)", "(make-constant-symbol item)")
            ] == ["constant1", "item2", "constant3", "item4"]


def test_user_functions() -> None:
    table = default_functions()
    table.register("half", lambda x: x / 2, min_args=1, max_args=1)
    table.register("name", lambda *a: None)
    table.register("bad", lambda: [1])
    table.register("boom", lambda: 1 / 0)
    ctx = Context()
    assert evaluate(FunctionCall("half", (3,)), {}, table, ctx) == Float(1.5)
    assert type(evaluate(FunctionCall("half", (3,)), {}, table, ctx)) is Float
    assert evaluate(FunctionCall("name", ("a", "b")), {}, table, ctx) is None
    with pytest.raises(EngineError, match=r"RHS function 'bad' returned \[1\], which is not a symbol"):
        evaluate(FunctionCall("bad", ()), {}, table, ctx)
    with pytest.raises(EngineError, match="RHS function 'boom' raised ZeroDivisionError"):
        evaluate(FunctionCall("boom", ()), {}, table, ctx)


def test_register_rejects_bad_definitions() -> None:
    table = default_functions()
    with pytest.raises(EngineError, match="already defined"):
        table.register("write", print)
    with pytest.raises(EngineError, match="not a usable RHS function name"):
        table.register("two words", print)
    with pytest.raises(EngineError, match="bad argument counts"):
        table.register("f", print, min_args=2, max_args=1)


def test_tables_are_independent() -> None:
    a = default_functions()
    a.register("extra", lambda: 1)
    assert "extra" in a and "extra" not in default_functions()
    b: FunctionTable = a.copy()
    b.register("more", lambda: 2)
    assert "more" not in a


def test_unbound_variable_is_an_engine_error() -> None:
    with pytest.raises(EngineError, match=r"variable <x> has no binding"):
        evaluate(Variable("<x>"), {}, default_functions(), Context())


def test_unknown_function_at_run_time_is_an_engine_error() -> None:
    with pytest.raises(EngineError, match="unknown RHS function 'nope'"):
        evaluate(FunctionCall("nope", ()), {}, default_functions(), Context())
