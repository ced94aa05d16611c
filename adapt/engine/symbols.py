"""The vocabulary of working memory: identifiers and constants.

A WME's fields hold *symbols*:

* :class:`Identifier` -- a letter and a number (``S1``, ``O3``, ``I2``), created
  only by the agent (one object per identifier, compared by identity);
* symbolic constants -- Python ``str``;
* integer constants -- Python ``int`` (never ``bool``);
* floating-point constants -- :class:`Float`, a ``float`` that is never equal to
  an ``int`` (in Soar ``2`` and ``2.0`` are different values) and hashes apart
  from it.

Every float that enters working memory must be a :class:`Float`; use
:func:`to_symbol` to turn a Python value into a symbol.

Examples
--------
>>> Float(2.0) == 2, Float(2.0) == Float(2.0), len({2, Float(2.0)})
(False, True, 2)
>>> format_symbol(Float(1.5)), format_symbol(7), format_symbol("hi")
('1.500000', '7', 'hi')
"""

from __future__ import annotations

from typing import Union

from adapt.engine.floats import Float

__all__ = [
    "Identifier",
    "Float",
    "Symbol",
    "Constant",
    "is_number",
    "to_symbol",
    "format_symbol",
    "symbol_sort_key",
    "level_of",
    "is_goal",
    "IdentifierFactory",
]


class Identifier:
    """A working-memory identifier such as ``S1``.

    Identifiers compare and hash by identity: an agent creates exactly one
    object per identifier, through its :class:`IdentifierFactory`.

    ``level`` is the goal level the identifier belongs to (0: the top state;
    a substate's local structure has the substate's level until a result
    promotes it).  It lives on the identifier, as in Soar, so it goes away
    with the identifier: nothing has to forget it when working memory drops
    the identifier.

    ``goal`` is true while the identifier is a state of the goal stack (the
    top state or a substate): what a condition written ``(state <s> ...)``
    requires of ``<s>`` (Soar's ``isa_goal``).  The kernel sets it when it
    creates a state and clears it when it removes one.
    """

    __slots__ = ("letter", "number", "name", "level", "goal")

    def __init__(self, letter: str, number: int, level: int = 0, goal: bool = False) -> None:
        self.letter = letter
        self.number = number
        self.name = f"{letter}{number}"
        self.level = level
        self.goal = goal

    def __repr__(self) -> str:
        return self.name

    def __str__(self) -> str:
        return self.name

    def sort_key(self) -> tuple[str, int]:
        """``(letter, number)``, the order Soar prints identifiers in."""
        return (self.letter, self.number)


#: A constant symbol.
Constant = Union[str, int, Float]
#: Anything a WME field can hold.
Symbol = Union[Identifier, str, int, Float]


def is_number(value: object) -> bool:
    """True for int and float constants (not ``bool``, not strings)."""
    t = type(value)
    return t is int or t is Float or t is float


def to_symbol(value: object) -> Symbol:
    """Turn a Python value into a symbol (``float`` -> :class:`Float`).

    Raises
    ------
    TypeError
        For values that are not ``str``, ``int``, ``float`` or
        :class:`Identifier` (``bool`` and ``None`` included).

    Examples
    --------
    >>> to_symbol(0.5), to_symbol(3), to_symbol("a")
    (Float(0.5), 3, 'a')
    """
    t = type(value)
    if t is str or t is int or t is Float or t is Identifier:
        return value  # type: ignore[return-value]
    if t is float:
        return Float(value)  # type: ignore[arg-type]
    if isinstance(value, bool) or value is None:
        raise TypeError(f"{value!r} is not a Soar symbol (expected a string, int or float)")
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        return Float(value)
    if isinstance(value, str):
        return str(value)
    raise TypeError(f"{value!r} is not a Soar symbol (expected a string, int or float)")


def format_symbol(value: Symbol) -> str:
    """Text of a symbol as Soar's ``write`` prints it (floats as ``%f``)."""
    if type(value) is Float or type(value) is float:
        return "%f" % value
    return str(value)


def is_goal(value: object) -> bool:
    """Whether ``value`` is a state of the goal stack (:attr:`Identifier.goal`):
    what ``(state <s> ...)`` tests.

    Examples
    --------
    >>> is_goal(Identifier("S", 1, goal=True)), is_goal(Identifier("F", 1)), is_goal("S1")
    (True, False, False)
    """
    return type(value) is Identifier and value.goal


def level_of(value: object) -> int:
    """The goal level of an identifier (:attr:`Identifier.level`); 0 for anything else."""
    return value.level if isinstance(value, Identifier) else 0


def symbol_sort_key(value: Symbol) -> tuple[int, object, object]:
    """A total order over symbols, for deterministic printing."""
    if isinstance(value, Identifier):
        return (3, value.letter, value.number)
    if isinstance(value, str):
        return (2, value, 0)
    return (1, float(value), 0 if type(value) is int else 1)


class IdentifierFactory:
    """Creates identifiers with one counter per letter, as Soar does.

    Examples
    --------
    >>> ids = IdentifierFactory()
    >>> ids.state(), ids.new("O"), ids.new("o"), ids.new("<"), ids.new("small"), ids.state()
    (S1, O1, O2, I1, I2, S2)
    """

    __slots__ = ("_counters", "_letters")

    def __init__(self) -> None:
        self._counters: dict[str, int] = {}
        #: hint -> letter (rules use a handful of hints, one per new variable)
        self._letters: dict[str, str] = {}

    def new(self, hint: str, level: int = 0) -> Identifier:
        """A fresh identifier at goal level ``level`` whose letter is the first
        letter of ``hint`` (upper-cased), or ``I`` when ``hint`` does not start
        with a letter -- or starts with S, which only states have (Soar's
        ``prohibit_S``: a rule's ``<small>`` makes ``I4``, not ``S4``)."""
        letter = self._letters.get(hint)
        if letter is None:
            letter = hint[:1].upper() if hint[:1].isalpha() else "I"
            if letter == "S":
                letter = "I"
            self._letters[hint] = letter
        n = self._counters.get(letter, 0) + 1
        self._counters[letter] = n
        return Identifier(letter, n, level)

    def state(self, level: int = 0) -> Identifier:
        """A fresh state identifier (``S``, a goal: :attr:`Identifier.goal`)."""
        n = self._counters.get("S", 0) + 1
        self._counters["S"] = n
        return Identifier("S", n, level, goal=True)
