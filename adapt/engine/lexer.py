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
from typing import Iterator, Union

from adapt.engine.symbols import Float
from adapt.errors import RuleSyntaxError

__all__ = ["Token", "tokenize", "iter_tokens", "token_batches", "CONSTANT_KINDS"]

_RELATIONS = frozenset({"<", ">", "<=", ">=", "<>", "<=>", "="})
_INT = re.compile(r"[+-]?[0-9]+\Z")
_FLOAT = re.compile(r"([+-]?(?:[0-9]+\.[0-9]*|\.[0-9]+))(?:[eE]([+-]?[0-9]*))?\Z")
_IDSHAPED = re.compile(r"([A-Za-z])([0-9]+)\Z")
_INT64 = 2**63

#: One lexeme (or blank) at a position, tried in order.  A number followed by
#: ``.`` goes on as a float (``1.2.3`` is ``1.2`` then ``.3``; ``+.`` is a
#: word, as Soar reads it), then constituent runs, single-character tokens,
#: blanks and comments (``;`` separates like white space), newlines, quotes,
#: and a lone ``.``.
_SCAN = re.compile(r"""
    (?P<word>(?:[+-][0-9]*|[0-9]+)\.[0-9]*(?:[eE][+-]?[0-9]*)?
            |\.[0-9]+(?:[eE][+-]?[0-9]*)?
            |[A-Za-z0-9$%&*+\-/:<=>?_@]+)
    |(?P<single>[(){}^,!~])
    |(?P<blank>(?:[ \t\r\f\v;]|\#[^\n]*)+)
    |(?P<newline>\n)
    |(?P<quote>[|"])
    |(?P<period>\.)
""", re.VERBOSE)
#: Kinds and values of the words met so far (rule bases repeat their words).
_KINDS: dict[str, tuple[str, TokenValue]] = {}
_KINDS_MAX = 100_000

#: Token kinds that stand for a constant.
CONSTANT_KINDS = frozenset({"symbol", "int", "float", "idshaped", "quoted"})

TokenValue = Union[str, int, Float, None]


class Token:
    """One lexeme.

    ``kind`` is one of ``( ) { } ^ , . ! ~ + - --> relation << >> variable int
    float idshaped symbol quoted doc eof``; ``text`` is the source text and
    ``value`` the symbol it stands for (for constants and variables).  Tokens
    are never changed once made (a plain slotted class rather than a frozen
    record: the parser makes hundreds of thousands of them for a large rule
    base, and compiled, this class is built without a Python-level call).
    """

    __slots__ = ("kind", "text", "value", "line", "col", "offset")

    def __init__(self, kind: str, text: str, value: TokenValue, line: int, col: int,
                 offset: int) -> None:
        self.kind = kind
        self.text = text
        self.value = value
        self.line = line
        self.col = col
        self.offset = offset

    def __repr__(self) -> str:
        return (f"Token({self.kind!r}, {self.text!r}, {self.value!r}, line={self.line}, "
                f"col={self.col})")


class _Lexer:
    def __init__(self, text: str, file: str, start: int = 0) -> None:
        self.text = text
        self.file = file
        self.pos = start
        self.line = text.count("\n", 0, start) + 1 if start else 1
        self.line_start = text.rfind("\n", 0, start) + 1 if start else 0
        self.tokens: list[Token] = []

    def error(self, message: str, line: int, col: int) -> RuleSyntaxError:
        lines = self.text.splitlines()
        source = lines[line - 1] if 0 < line <= len(lines) else None
        return RuleSyntaxError(message, file=self.file, line=line, col=col, source_line=source)

    def run(self) -> list[Token]:
        return list(self.iter_tokens())

    def iter_tokens(self) -> Iterator[Token]:
        for batch in self.batches(1):
            yield from batch

    def batches(self, size: int) -> Iterator[list[Token]]:
        """The tokens in lists of about ``size`` (the last one ends with ``eof``).

        A lexical error is raised only after the tokens before it have been
        handed out, when the reader asks for more.
        """
        try:
            while self.pos < len(self.text):
                if len(self.tokens) >= size:
                    yield self.tokens
                    self.tokens = []
                self.scan()
        except RuleSyntaxError:
            if self.tokens:
                yield self.tokens
                self.tokens = []
            raise
        self.emit("eof", "", None, self.pos)
        yield self.tokens
        self.tokens = []

    def scan(self) -> None:
        """Read the lexeme (or blank) at :attr:`pos`."""
        text = self.text
        m = _SCAN.match(text, self.pos)
        if m is None:  # a character no lexeme starts with
            raise self.error(f"unexpected character {text[self.pos]!r} in rule text",
                             self.line, self.pos - self.line_start + 1)
        group = m.lastgroup
        start, end = m.span()
        if group == "word":
            self.classify(start, end)
        elif group == "blank":
            self.pos = end
        elif group == "single":
            ch = text[start]
            self.tokens.append(Token(ch, ch, ch, self.line, start - self.line_start + 1, start))
            self.pos = end
        elif group == "newline":
            self.pos = end
            self.line += 1
            self.line_start = end
        elif group == "quote":
            self.quoted(text[start])
        else:  # "period": a '.' that does not start a float
            self.emit(".", ".", ".", start)
            self.pos = end

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

    def classify(self, start: int, end: int) -> None:
        word = self.text[start:end]
        self.pos = end
        known = _KINDS.get(word)
        if known is None:
            known = self.kind_of(word, start)
            if len(_KINDS) < _KINDS_MAX:
                _KINDS[word] = known
        kind, value = known
        self.tokens.append(Token(kind, word, value, self.line, start - self.line_start + 1, start))

    def kind_of(self, word: str, start: int) -> tuple[str, TokenValue]:
        """The kind and value of a constituent word (see the module docstring)."""
        if word == "-->":
            return "-->", word
        if word == "+" or word == "-":
            return word, word
        if word in _RELATIONS:
            return "relation", word
        if word == "<<" or word == ">>":
            return word, word
        if len(word) >= 3 and word[0] == "<" and word[-1] == ">":
            return "variable", word
        if _INT.match(word):
            value = int(word)
            if not -_INT64 <= value < _INT64:
                raise self.error(
                    f"integer {word} does not fit in 64 bits", self.line, start - self.line_start + 1
                )
            return "int", value
        m = _FLOAT.match(word)
        if m is not None:
            exponent = m.group(2)
            number = m.group(1) + (f"e{exponent}" if exponent and exponent not in "+-" else "")
            value_f = float(number)
            if value_f in (float("inf"), float("-inf")):
                raise self.error(
                    f"float {word} is out of range", self.line, start - self.line_start + 1
                )
            return "float", Float(value_f)
        m = _IDSHAPED.match(word)
        if m is not None:
            return "idshaped", f"{m.group(1).upper()}{int(m.group(2))}"
        return "symbol", word


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


def token_batches(text: str, file: str = "<string>", size: int = 2048,
                  start: int = 0) -> Iterator[list[Token]]:
    """Tokens in lists of about ``size``: :func:`iter_tokens` for a reader that
    takes many at a time (an error is raised when the batch holding it is read).
    ``start``: the offset in ``text`` to begin at (lines and columns still
    count from the start of ``text``)."""
    return _Lexer(text, file, start).batches(size)
