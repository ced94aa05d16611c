"""The working-memory element (WME): ``(id ^attr value)`` with a timetag.

A WME is an immutable record.  ``acceptable`` is true for the WMEs that stand
for acceptable preferences (``(S1 ^operator O1 +)``); those are matched only by
conditions that carry ``+`` on the value, and plain conditions match only WMEs
without it.  Two WMEs with the same ``(id, attr, value, acceptable)`` never
exist at once in one working memory; :attr:`WME.key` is that identity.

Examples
--------
>>> from adapt.engine.symbols import Identifier
>>> s1 = Identifier("S", 1)
>>> w = WME(s1, "type", "state", False, 3)
>>> w
(3: S1 ^type state)
>>> w.key == (s1, "type", "state", False)
True
"""

from __future__ import annotations

from typing import NamedTuple

from adapt.engine.symbols import Symbol, format_symbol

__all__ = ["WME"]


class WME(NamedTuple):
    """One working-memory element."""

    id: Symbol
    attr: Symbol
    value: Symbol
    acceptable: bool
    timetag: int

    @property
    def key(self) -> tuple[Symbol, Symbol, Symbol, bool]:
        """``(id, attr, value, acceptable)``: what makes two WMEs the same."""
        return (self.id, self.attr, self.value, self.acceptable)

    def __repr__(self) -> str:
        plus = " +" if self.acceptable else ""
        return (
            f"({self.timetag}: {format_symbol(self.id)} ^{format_symbol(self.attr)} "
            f"{format_symbol(self.value)}{plus})"
        )
