"""The input-link and output-link as the schemas see them.

:class:`Structure` is a piece of working memory under one identifier that a
schema rewrites every input phase.  Writing the same value again changes
nothing (the WME keeps its timetag, so no rule re-fires); a changed value
replaces the old one; a child structure (``^region R7``) is created once
and kept while it is written, and removed (with everything under it) when
:meth:`Structure.keep_children` no longer lists it.

:func:`read_commands` turns the WMEs the rules put on the output-link into
:class:`Command` records, each read once.

The layout both build is the contract rules are written against; it is
documented attribute by attribute in ``docs/schemas.md``.

Examples
--------
>>> from adapt.engine import Agent
>>> agent = Agent()
>>> root = None
>>> def sense(w):
...     global root
...     if root is None:
...         root = Structure.under(w, w.input_link, "thing")
...     root.bind(w)
...     root.set("x", w.decision * 1.5)
...     root.child("part", 1).set("size", 2)
>>> agent.on_input(sense)
>>> _ = agent.run(2)
>>> print(agent.print_state(agent.input_link, depth=3))
(I2 ^thing T1)
  (T1 ^part P1 ^x 1.500000)
    (P1 ^size 2)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Hashable

from adapt.engine.interface import InputLink, OutputView
from adapt.engine.symbols import Identifier, Symbol

__all__ = ["Structure", "Command", "read_commands", "COMMANDS"]

#: The output-link commands the network reads: ``^instantiate``, ``^remove``, ``^command``.
COMMANDS = ("instantiate", "remove", "command")


class Structure:
    """A working-memory structure rewritten each input phase (see the module docstring)."""

    def __init__(self, ident: Identifier, writer: InputLink | None = None) -> None:
        self.id = ident
        self._writer = writer
        self._children: dict[tuple[str, Hashable], Structure] = {}
        self._values: dict[str, Symbol | None] = {}

    @classmethod
    def under(cls, writer: InputLink, parent: Identifier, attr: str) -> "Structure":
        """A new structure ``(parent ^attr <new id>)``."""
        ident = writer.new_id(attr[0].upper())
        writer.add(parent, attr, ident)
        return cls(ident, writer)

    def bind(self, writer: InputLink) -> None:
        """Use ``writer`` (valid during this input phase) for the following writes."""
        self._writer = writer
        for child in self._children.values():
            child.bind(writer)

    @property
    def writer(self) -> InputLink:
        """The input phase's writer."""
        if self._writer is None:
            raise RuntimeError("Structure used before bind()")
        return self._writer

    def set(self, attr: str, value: Any) -> None:
        """Make ``value`` the only value of ``^attr`` (None removes the attribute).

        Floats are kept as they are given; round them first for readable
        traces (the schemas round metres to 0.1 mm and pixels to 0.01 px).
        """
        if value is None:
            if self._values.get(attr) is not None:
                self.writer.clear(self.id, attr)
            self._values[attr] = None
            return
        if isinstance(value, bool):
            value = "yes" if value else "no"
        old = self._values.get(attr)
        if old is not None and type(old) is type(value) and old == value:
            return
        self.writer.set(self.id, attr, value)
        self._values[attr] = value

    def child(self, attr: str, key: Hashable) -> "Structure":
        """The sub-structure ``(self ^attr C)`` known by ``key``; created on first use."""
        k = (attr, key)
        found = self._children.get(k)
        if found is None:
            found = Structure.under(self.writer, self.id, attr)
            self._children[k] = found
        return found

    def keep_children(self, attr: str, keys: set[Hashable] | list[Hashable]) -> None:  # type: ignore[valid-type]
        """Remove the ``^attr`` children whose key is not in ``keys``."""
        keep = set(keys)
        for (a, key) in list(self._children):
            if a == attr and key not in keep:
                child = self._children.pop((a, key))
                self.writer.remove(self.id, a, child.id)


@dataclass(frozen=True, slots=True)
class Command:
    """A command the rules put on the output-link.

    ``verb`` is the output-link attribute (``instantiate``, ``remove``,
    ``command``, or any other, which the network reports as unknown);
    ``attributes`` the command's own WMEs (the first value of each
    attribute); ``id`` the command's identifier, where the network writes
    ``^status``.
    """

    verb: str
    id: Identifier
    attributes: tuple[tuple[str, Any], ...]
    decision: int

    def get(self, key: str, default: Any = None) -> Any:
        """The value of attribute ``key``."""
        for k, v in self.attributes:
            if k == key:
                return v
        return default

    def as_dict(self) -> dict[str, Any]:
        """The attributes as a dict (``status`` and ``message`` left out)."""
        return {k: v for k, v in self.attributes if k not in ("status", "message")}


def _plain(value: Symbol) -> Any:
    if type(value) is Identifier:
        return value
    if isinstance(value, float):
        return float(value)
    return value


def read_commands(view: OutputView, seen: set[Identifier]) -> list[Command]:
    """The new commands on the output-link (identifiers in ``seen`` are skipped
    and the new ones added to it), in the order the rules made them."""
    out: list[Command] = []
    fresh = [w for w in view.added if w.id is view.output_link and type(w.value) is Identifier
             and w.value not in seen]
    fresh.sort(key=lambda w: w.timetag)
    for w in fresh:
        cid: Identifier = w.value  # type: ignore[assignment]
        seen.add(cid)
        attrs: dict[str, Any] = {}
        for c in view.wmes:
            if c.id is cid and not c.acceptable and str(c.attr) not in attrs:
                attrs[str(c.attr)] = _plain(c.value)
        out.append(Command(str(w.attr), cid, tuple(attrs.items()), view.decision))
    return out
