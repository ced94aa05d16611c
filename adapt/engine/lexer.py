"""Tokens of Soar's rule language, split the way Soar 9.6's lexer splits them.

A *constituent string* is a run of letters, digits and ``$%&*+-/:<=>?_@``.
It becomes, in this order of preference: one of the special lexemes
(``-->``, ``+``, ``-``, ``<``, ``>``, ``<=``, ``>=``, ``<>``, ``<=>``, ``=``,
``<<``, ``>>``), a variable (``<x>``), an integer (``[+-]?digits``), a float
(``[+-]?digits.digits`` with an optional exponent -- only after a decimal
point, so ``1e5`` is a string while ``1.5e3`` is ``1500.0``), an
identifier-shaped token (a letter followed by digits, ``p1`` -> ``P1``,
``q01`` -> ``Q1``), or a symbolic constant.  A number stopped by ``.`` goes on
as a float (``1.2.3`` is ``1.2`` then ``.3``, as in Soar).

Other characters: ``( ) { } ^ , . ! ~`` are tokens of their own, ``|...|``
is a quoted string and ``"..."`` a documentation string (``\\`` escapes the
next character in both), ``#`` starts a comment that runs to the end of the
line, and ``;`` separates like white space (so ``;#`` starts a comment).
Anything else is an error.

Examples
--------
>>> [(t.kind, t.value) for t in tokenize("^a.b 1.5e3 1e5 p1 |x y| <v> <=> -->")]
... # doctest: +NORMALIZE_WHITESPACE
[('^', '^'), ('symbol', 'a'), ('.', '.'), ('symbol', 'b'), ('float', Float(1500.0)),
 ('symbol', '1e5'), ('idshaped', 'P1'), ('quoted', 'x y'), ('variable', '<v>'),
 ('relation', '<=>'), ('-->', '-->'), ('eof', None)]
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Iterator, Union

from adapt.engine.symbols import Float
from adapt.errors import RuleSyntaxError

__all__ = ["Token", "tokenize", "iter_tokens", "CONSTANT_KINDS"]

_CONSTITUENT = frozenset(
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789$%&*+-/:<=>?_@"
)
_SINGLE = {"(": "(", ")": ")", "{": "{", "}": "}", "^": "^", ",": ",", "!": "!", "~": "~"}
_RELATIONS = frozenset({"<", ">", "<=", ">=", "<>", "<=>", "="})
_INT = re.compile(r"[+-]?[0-9]+\Z")
_FLOAT = re.compile(r"([+-]?(?:[0-9]+\.[0-9]*|\.[0-9]+))(?:[eE]([+-]?[0-9]*))?\Z")
_IDSHAPED = re.compile(r"([A-Za-z])([0-9]+)\Z")
_INT64 = 2**63

#: Token kinds that stand for a constant.
CONSTANT_KINDS = frozenset({"symbol", "int", "float", "idshaped", "quoted"})

TokenValue = Union[str, int, Float, None]


@dataclass(frozen=True, slots=True)
class Token:
    """One lexeme.

    ``kind`` is one of ``( ) { } ^ , . ! ~ + - --> relation << >> variable int
    float idshaped symbol quoted doc eof``; ``text`` is the source text and
    ``value`` the symbol it stands for (for constants and variables).
    """

    kind: str
    text: str
    value: TokenValue
    line: int
    col: int
    offset: int


class _Lexer:
    def __init__(self, text: str, file: str) -> None:
        self.text = text
        self.file = file
        self.pos = 0
        self.line = 1
        self.line_start = 0
        self.tokens: list[Token] = []

    def error(self, message: str, line: int, col: int) -> RuleSyntaxError:
        lines = self.text.splitlines()
        source = lines[line - 1] if 0 < line <= len(lines) else None
        return RuleSyntaxError(message, file=self.file, line=line, col=col, source_line=source)

    def run(self) -> list[Token]:
        return list(self.iter_tokens())

    def iter_tokens(self) -> Iterator[Token]:
        text, n = self.text, len(self.text)
        while self.pos < n:
            if self.tokens:
                yield from self.tokens
                self.tokens.clear()
            ch = text[self.pos]
            if ch == "\n":
                self.pos += 1
                self.line += 1
                self.line_start = self.pos
            elif ch in " \t\r\f\v;":
                self.pos += 1
            elif ch == "#":
                end = text.find("\n", self.pos)
                self.pos = n if end < 0 else end
            elif ch in _SINGLE:
                self.emit(_SINGLE[ch], ch, ch, self.pos)
                self.pos += 1
            elif ch == "|" or ch == '"':
                self.quoted(ch)
            elif ch == ".":
                self.period()
            elif ch in _CONSTITUENT:
                self.constituent()
            else:
                raise self.error(
                    f"unexpected character {ch!r} in rule text", self.line, self.pos - self.line_start + 1
                )
        self.emit("eof", "", None, self.pos)
        yield from self.tokens
        self.tokens.clear()

    def emit(self, kind: str, text: str, value: TokenValue, start: int) -> None:
        col = start - self.line_start + 1
        self.tokens.append(Token(kind, text, value, self.line, col, start))

    def quoted(self, quote: str) -> None:
        text, start = self.text, self.pos
        line, col = self.line, self.pos - self.line_start + 1
        out: list[str] = []
        i = start + 1
        while True:
            if i >= len(text):
                what = "quoted string '|'" if quote == "|" else "documentation string '\"'"
                raise self.error(f"unterminated {what}: no closing {quote}", line, col)
            c = text[i]
            if c == "\\" and i + 1 < len(text):
                i += 1
                c = text[i]
            elif c == quote:
                break
            if c == "\n":
                self.line += 1
                self.line_start = i + 1
            out.append(c)
            i += 1
        kind = "quoted" if quote == "|" else "doc"
        self.tokens.append(Token(kind, text[start : i + 1], "".join(out), line, col, start))
        self.pos = i + 1

    def read_constituents(self, i: int) -> int:
        text, n = self.text, len(self.text)
        while i < n and text[i] in _CONSTITUENT:
            i += 1
        return i

    def rest_of_float(self, i: int) -> int:
        """``i`` is at ``.``: read the point, digits and an optional exponent."""
        text, n = self.text, len(self.text)
        i += 1
        while i < n and text[i].isdigit() and text[i].isascii():
            i += 1
        if i < n and text[i] in "eE":
            i += 1
            if i < n and text[i] in "+-":
                i += 1
            while i < n and text[i].isdigit() and text[i].isascii():
                i += 1
        return i

    def period(self) -> None:
        start = self.pos
        nxt = self.text[start + 1 : start + 2]
        if nxt.isdigit() and nxt.isascii():
            end = self.rest_of_float(start)
            self.classify(start, end)
        else:
            self.emit(".", ".", ".", start)
            self.pos = start + 1

    def constituent(self) -> None:
        start = self.pos
        end = self.read_constituents(start)
        word = self.text[start:end]
        if (
            end < len(self.text)
            and self.text[end] == "."
            and word[0] in "+-0123456789"
            and all(c.isdigit() for c in word[1:])
        ):
            end = self.rest_of_float(end)
        self.classify(start, end)

    def classify(self, start: int, end: int) -> None:
        word = self.text[start:end]
        self.pos = end
        if word == "-->":
            self.emit("-->", word, word, start)
        elif word == "+" or word == "-":
            self.emit(word, word, word, start)
        elif word in _RELATIONS:
            self.emit("relation", word, word, start)
        elif word == "<<" or word == ">>":
            self.emit(word, word, word, start)
        elif len(word) >= 3 and word[0] == "<" and word[-1] == ">":
            self.emit("variable", word, word, start)
        elif _INT.match(word):
            value = int(word)
            if not -_INT64 <= value < _INT64:
                raise self.error(
                    f"integer {word} does not fit in 64 bits", self.line, start - self.line_start + 1
                )
            self.emit("int", word, value, start)
        elif (m := _FLOAT.match(word)) is not None:
            exponent = m.group(2)
            number = m.group(1) + (f"e{exponent}" if exponent and exponent not in "+-" else "")
            value_f = float(number)
            if value_f in (float("inf"), float("-inf")):
                raise self.error(
                    f"float {word} is out of range", self.line, start - self.line_start + 1
                )
            self.emit("float", word, Float(value_f), start)
        elif (m := _IDSHAPED.match(word)) is not None:
            self.emit("idshaped", word, f"{m.group(1).upper()}{int(m.group(2))}", start)
        else:
            self.emit("symbol", word, word, start)


def tokenize(text: str, file: str = "<string>") -> list[Token]:
    """Split rule text into tokens, ending with an ``eof`` token.

    Raises
    ------
    RuleSyntaxError
        For a character Soar's lexer does not accept, an unterminated
        ``|...|`` or ``"..."``, or a number out of range.

    Examples
    --------
    >>> [t.value for t in tokenize("1.2.3 -5 +.5 5a e5")]
    [Float(1.2), Float(0.3), -5, Float(0.5), '5a', 'E5', None]
    """
    return _Lexer(text, file).run()


def iter_tokens(text: str, file: str = "<string>") -> Iterator[Token]:
    """Tokens one at a time, so that an error late in the text is raised only
    when the reader gets there (see :func:`tokenize`)."""
    return _Lexer(text, file).iter_tokens()
