"""Symbols as a trace writes them, turned into text or engine symbols.

In a trace an identifier is ``{"id": "S1"}``, a string is a symbolic
constant, and JSON integers and floats are Soar's integer and float
constants (see ``docs/trace-format.md``).

Examples
--------
>>> text_of({"id": "S1"}), text_of("count"), text_of(3), text_of(2.5)
('S1', 'count', '3', '2.500000')
>>> text_of("two words"), text_of("")
('|two words|', '||')
>>> table = IdentifierTable()
>>> a, b = table.decode({"id": "O7"}), table.decode({"id": "O7"})
>>> a is b, a.letter, a.number
(True, 'O', 7)
"""

from __future__ import annotations

import re
from typing import Any

from adapt.engine.symbols import Float, Identifier, Symbol, format_symbol

__all__ = ["text_of", "id_name", "IdentifierTable", "wme_text"]

_PLAIN = re.compile(r"^[A-Za-z0-9\-_*+/<>=&$%!?:.@~]+$")
_ID_NAME = re.compile(r"^([A-Za-z]+)(\d+)$")


def id_name(value: Any) -> str | None:
    """The identifier's name if ``value`` is a trace identifier, else ``None``."""
    if isinstance(value, dict):
        name = value.get("id")
        return name if isinstance(name, str) else None
    return None


def text_of(value: Any) -> str:
    """The text of a trace symbol as Soar prints it (``|..|`` around odd strings)."""
    name = id_name(value)
    if name is not None:
        return name
    if isinstance(value, bool) or value is None:
        return "nil" if value is None else str(value).lower()
    if isinstance(value, float):
        return format_symbol(Float(value))
    if isinstance(value, str):
        return value if _PLAIN.match(value) else "|" + value.replace("|", "\\|") + "|"
    return str(value)


def wme_text(timetag: int | None, ident: Any, attr: Any, value: Any, acceptable: bool) -> str:
    """``(231: S1 ^count 3)`` (without the timetag when it is ``None``).

    >>> wme_text(231, {"id": "S1"}, "operator", {"id": "O7"}, True)
    '(231: S1 ^operator O7 +)'
    """
    head = f"{timetag}: " if timetag is not None else ""
    plus = " +" if acceptable else ""
    return f"({head}{text_of(ident)} ^{text_of(attr)} {text_of(value)}{plus})"


class IdentifierTable:
    """Turns trace symbols into engine symbols, one :class:`Identifier` per name.

    Engine identifiers compare by identity, so a reader that wants to match
    conditions against rebuilt working memory must intern them.
    """

    __slots__ = ("_ids",)

    def __init__(self) -> None:
        self._ids: dict[str, Identifier] = {}

    def identifier(self, name: str) -> Identifier:
        """The one identifier object called ``name``."""
        ident = self._ids.get(name)
        if ident is None:
            match = _ID_NAME.match(name)
            if match:
                ident = Identifier(match.group(1).upper(), int(match.group(2)))
            else:
                ident = Identifier(name[:1].upper() or "I", 0)
            ident.name = name
            self._ids[name] = ident
        return ident

    def decode(self, value: Any) -> Symbol:
        """An engine symbol for a trace symbol (floats become :class:`Float`)."""
        name = id_name(value)
        if name is not None:
            return self.identifier(name)
        if isinstance(value, float):
            return Float(value)
        if isinstance(value, (str, int)) and not isinstance(value, bool):
            return value
        return text_of(value)
