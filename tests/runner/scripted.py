"""The bookkeeping of a scripted stand-in for the schema network, shared by the rules tests
(``test_perception_rules.py``, ``test_search_rules.py``): each writes its own input-link
and carries out the commands its way; this writes a structure's attributes as the network
does and answers each output-link command once, ``^status complete`` in the next input
phase."""

from __future__ import annotations

from typing import Any

from adapt.engine import OutputView
from adapt.engine.interface import InputLink

#: A command's attributes the rules tests read.
COMMAND_ATTRIBUTES = ("name", "type", "region", "object")


class ScriptedNetwork:
    """What every scripted network keeps: :attr:`done`, the commands carried out (verb and
    attributes, in order), and the commands to answer."""

    def __init__(self) -> None:
        self.done: list[tuple[str, dict[str, Any]]] = []
        self._pending: list[Any] = []
        self._answered: set[Any] = set()

    def acknowledge(self, w: InputLink) -> None:
        """Answer the commands carried out in the last output phase."""
        for cid in self._pending:
            w.add(cid, "status", "complete")
        self._pending.clear()

    def commands(self, view: OutputView) -> list[tuple[str, dict[str, Any]]]:
        """The commands on the output-link not carried out yet, with their attributes
        (numbers as numbers, symbols as strings); each is recorded in :attr:`done` and
        answered in the next input phase."""
        new = []
        for verb, cid in view.commands():
            if cid in self._answered or view.values(cid, "status"):  # type: ignore[arg-type]
                continue
            self._answered.add(cid)
            attrs = {str(a): v for a in COMMAND_ATTRIBUTES
                     for v in view.values(cid, a)}  # type: ignore[arg-type]
            attrs = {k: (v if isinstance(v, (int, float)) else str(v)) for k, v in attrs.items()}
            self.done.append((str(verb), attrs))
            self._pending.append(cid)
            new.append((str(verb), attrs))
        return new


def add_all(w: InputLink, parent: Any, attrs: dict[str, Any]) -> None:
    """Write ``attrs`` on ``parent`` as the network does (a bool as ``yes`` or ``no``)."""
    for key, value in attrs.items():
        w.add(parent, key, ("yes" if value else "no") if isinstance(value, bool) else value)
