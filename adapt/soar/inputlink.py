"""The input-link writer of the Soar engine: :class:`~adapt.engine.interface.InputLink`
calls turned into SML input WMEs.

Input callbacks run in the parent process; what they write is kept as a
list of operations and sent to the kernel's process when the callbacks
return, which carries them out with SML (``CreateIdWME``, ``CreateSharedIdWME``,
``CreateStringWME`` / ``CreateIntWME`` / ``CreateFloatWME``, ``DestroyWME``)
in the same input phase.  The writer keeps its own view of the WMEs it made,
so that :meth:`SoarInputWriter.set` and :meth:`~SoarInputWriter.values`
behave as the own engine's: writing a value again changes nothing (the WME
keeps its timetag), and removing an identifier value drops the structure
under it.

A new identifier (:meth:`SoarInputWriter.new_id`) gets its kernel name
(``F1``) once it is linked (``add(parent, attr, new)``) and the input phase
is over; SML names it by the first letter of the attribute that links it,
as ``Structure.under`` does.  Writing is possible only during the input
phase, as with the own engine.
"""

from __future__ import annotations

from typing import Any

from adapt.engine.symbols import Float, Identifier, Symbol, to_symbol
from adapt.errors import EngineError

__all__ = ["SoarInputWriter", "Op"]

#: One operation for the kernel's process: ``("add", id, attr, value, type)`` or
#: ``("remove", id, attr, value, type)``; ids are kernel names or new-id numbers.
Op = tuple[str, Any, str, Any, str]


def _symbol(value: object, what: str) -> Symbol:
    try:
        return to_symbol(value)
    except TypeError:
        raise EngineError(f"input-link {what} {value!r} is not a Soar symbol "
                          "(expected a string, int, float or identifier)") from None


def _identifier(value: object) -> Identifier:
    if not isinstance(value, Identifier):
        raise EngineError(f"input-link WMEs need an identifier as their id, got {value!r}")
    return value


class SoarInputWriter:
    """Adds and removes WMEs under the input-link during the input phase.

    Attributes
    ----------
    input_link : Identifier
        The ``^input-link`` identifier (``I2``).
    decision : int
        Decisions run so far.
    """

    def __init__(self, input_link: Identifier) -> None:
        self.input_link = input_link
        self.decision = 0
        self.open = False
        self.ops: list[Op] = []
        #: the WMEs this writer made: (id, attr) -> values, in order
        self._values: dict[tuple[Identifier, Symbol], list[Symbol]] = {}
        #: the same, as they stood when the last input phase ended
        self._committed: dict[tuple[Identifier, Symbol], list[Symbol]] = {}
        self._touched: set[tuple[Identifier, Symbol]] = set()
        #: new identifiers: object -> the number the kernel's process knows it by
        self._new: dict[Identifier, int] = {}
        self._serial = 0

    # -- the phase ------------------------------------------------------------------------

    def begin(self, decision: int) -> None:
        """The input phase starts."""
        self.decision = decision
        self.open = True
        self.ops = []

    def end(self) -> list[Op]:
        """The input phase's callbacks returned: the operations to carry out."""
        self.open = False
        for key in self._touched:
            values = self._values.get(key)
            if values:
                self._committed[key] = list(values)
            else:
                self._committed.pop(key, None)
        self._touched.clear()
        ops, self.ops = self.ops, []
        return ops

    def named(self, number: int) -> Identifier | None:
        """The new identifier the kernel's process knows as ``number`` (then forgotten)."""
        for ident, n in self._new.items():
            if n == number:
                del self._new[ident]
                return ident
        return None

    def _check(self) -> None:
        if not self.open:
            raise EngineError("the input-link can be written only during the input phase "
                              "(from an on_input callback)")

    def _ref(self, ident: Identifier) -> Any:
        number = self._new.get(ident)
        return ident.name if number is None else number

    # -- InputLink ------------------------------------------------------------------------

    def new_id(self, letter: str = "I") -> Identifier:
        """A new identifier for structure under the input-link (named when linked)."""
        self._check()
        self._serial += 1
        first = letter[:1].upper() if letter[:1].isalpha() else "I"
        ident = Identifier(first, 0)
        ident.name = f"{first}?{self._serial}"
        self._new[ident] = self._serial
        return ident

    def add(self, id: object, attr: object, value: object) -> None:
        """Add ``(id ^attr value)``; ``value`` may be a new identifier.

        Raises
        ------
        EngineError
            Outside the input phase, or when ``id`` is not an identifier or
            ``attr`` / ``value`` is not a symbol.
        """
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        v = _symbol(value, "value")
        key = (ident, a)
        values = self._values.setdefault(key, [])
        if v in values and _same_type(values, v):
            return
        values.append(v)
        self._touched.add(key)
        self.ops.append(("add", self._ref(ident), str(a), self._value_ref(v), self._type(v)))

    def remove(self, id: object, attr: object, value: object) -> None:
        """Remove ``(id ^attr value)`` (a no-op if this writer did not make it)."""
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        v = _symbol(value, "value")
        key = (ident, a)
        values = self._values.get(key)
        if not values:
            return
        for i, old in enumerate(values):
            if old == v and type(old) is type(v):
                del values[i]
                break
        else:
            return
        self._touched.add(key)
        self.ops.append(("remove", self._ref(ident), str(a), self._value_ref(v), self._type(v)))
        if type(v) is Identifier:
            self._drop(v)

    def set(self, id: object, attr: object, value: object) -> None:
        """Make ``value`` the only value of ``(id ^attr)`` (nothing changes when it already is)."""
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        v = _symbol(value, "value")
        current = list(self._values.get((ident, a), ()))
        keep = False
        for old in current:
            if old == v and type(old) is type(v):
                keep = True
            else:
                self.remove(ident, a, old)
        if not keep:
            self.add(ident, a, v)

    def clear(self, id: object, attr: object) -> None:
        """Remove every value of ``(id ^attr)``."""
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        for old in list(self._values.get((ident, a), ())):
            self.remove(ident, a, old)

    def values(self, id: object, attr: object) -> list[Symbol]:
        """The values of ``(id ^attr *)`` this writer made, as the last input phase left them."""
        return list(self._committed.get((_identifier(id), _symbol(attr, "attribute")), ()))

    # -- helpers ------------------------------------------------------------------------------

    def _value_ref(self, v: Symbol) -> Any:
        if type(v) is Identifier:
            return self._ref(v)
        if type(v) is Float:
            return float(v)
        return v

    def _type(self, v: Symbol) -> str:
        if type(v) is Identifier:
            return "new" if v in self._new and not self._linked(v) else "id"
        if type(v) is Float:
            return "float"
        if type(v) is int:
            return "int"
        return "string"

    def _linked(self, ident: Identifier) -> bool:
        """Whether a pending or earlier add already links ``ident`` (then it is shared)."""
        count = sum(1 for values in self._values.values() for x in values if x is ident)
        return count > 1

    def _drop(self, ident: Identifier) -> None:
        """Forget the structure under an identifier that is no longer linked."""
        if any(x is ident for values in self._values.values() for x in values):
            return
        stack = [ident]
        while stack:
            current = stack.pop()
            for key in [k for k in self._values if k[0] is current]:
                for x in self._values.pop(key):
                    if type(x) is Identifier and not any(
                            y is x for values in self._values.values() for y in values):
                        stack.append(x)
                self._touched.add(key)
            self._new.pop(current, None)


def _same_type(values: list[Symbol], v: Symbol) -> bool:
    return any(x == v and type(x) is type(v) for x in values)
