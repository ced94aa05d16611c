"""Input and output links: the hooks for perceptual and motor schemas.

During the **input phase** every input callback receives an
:class:`InputWriter`; what it adds and removes under the input-link is
buffered and committed at the end of the phase.  Writing at any other time
raises :class:`adapt.errors.EngineError`.

After each **output phase** every output callback receives an
:class:`OutputView` of the output-link: its current WMEs, and the WMEs added
and removed under it since the previous output phase (callbacks are called
only when something changed).

Examples
--------
>>> from adapt.engine import Agent
>>> agent = Agent()
>>> def sense(writer):
...     if writer.decision == 0:
...         writer.add(writer.input_link, "light", "red")
>>> agent.on_input(sense)
>>> _ = agent.load_text('sp {see (state <s> ^io.input-link.light red) --> '
...                     '(write |red seen|) (halt)}')
>>> agent.run(5).output
'red seen'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

from adapt.engine.memory import WmeKey
from adapt.engine.symbols import Identifier, Symbol, to_symbol
from adapt.engine.wme import WME
from adapt.errors import EngineError

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.kernel import Kernel

__all__ = ["InputWriter", "OutputView", "IoLinks"]


class InputWriter:
    """Adds and removes WMEs under the input-link during the input phase.

    Attributes
    ----------
    input_link : Identifier
        The ``^input-link`` identifier (``I2``).
    decision : int
        Decisions run so far.
    """

    def __init__(self, links: IoLinks) -> None:
        self._links = links
        self.input_link: Identifier = links.kernel.input_link
        self.decision = 0

    def _check(self) -> None:
        if not self._links.in_input:
            raise EngineError("the input-link can be written only during the input phase "
                              "(from an on_input callback)")

    def new_id(self, letter: str = "I") -> Identifier:
        """A new identifier for structure under the input-link."""
        self._check()
        k = self._links.kernel
        return k.ids.new(letter)

    def add(self, id: object, attr: object, value: object) -> None:
        """Add ``(id ^attr value)``; ``value`` may be a new identifier.

        Raises
        ------
        EngineError
            Outside the input phase, or when ``id`` is not an identifier or
            ``attr`` / ``value`` is not a symbol (a string, int, float or
            identifier; ``bool`` and ``None`` are not).
        """
        self._check()
        self._links.kernel.wm.add(_identifier(id), _symbol(attr, "attribute"),
                                  _symbol(value, "value"))

    def remove(self, id: object, attr: object, value: object) -> None:
        """Remove ``(id ^attr value)`` (a no-op if it is not there)."""
        self._check()
        self._links.kernel.wm.remove(_identifier(id), _symbol(attr, "attribute"),
                                     _symbol(value, "value"))

    def set(self, id: object, attr: object, value: object) -> None:
        """Make ``value`` the only value of ``(id ^attr)``.

        Nothing changes when it already is (the WME keeps its timetag, so no
        rule re-fires); otherwise the other values are removed and ``value``
        added.  Removing an identifier value lets its structure be garbage
        collected.

        Examples
        --------
        >>> from adapt.engine import Agent
        >>> agent = Agent()
        >>> def sense(w):
        ...     w.set(w.input_link, "x", w.decision)
        >>> agent.on_input(sense)
        >>> _ = agent.run(3)
        >>> [w.value for w in agent.wm if w.attr == "x"]
        [2]
        """
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        v = _symbol(value, "value")
        wm = self._links.kernel.wm
        for key in [k for k in wm.pending_adds if k[0] is ident and k[1] == a and not k[3]]:
            if key[2] != v:
                wm.remove(*key)
        current = wm.values(ident, a)
        for old in current:
            if old != v:
                wm.remove(ident, a, old)
        if v not in current:
            wm.add(ident, a, v)

    def clear(self, id: object, attr: object) -> None:
        """Remove every value of ``(id ^attr)``."""
        self._check()
        ident = _identifier(id)
        a = _symbol(attr, "attribute")
        wm = self._links.kernel.wm
        for key in [k for k in wm.pending_adds if k[0] is ident and k[1] == a and not k[3]]:
            wm.remove(*key)
        for old in wm.values(ident, a):
            wm.remove(ident, a, old)

    def values(self, id: object, attr: object) -> list[Symbol]:
        """The current (committed) values of ``(id ^attr *)``."""
        return self._links.kernel.wm.values(_identifier(id), _symbol(attr, "attribute"))


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


@dataclass(frozen=True)
class OutputView:
    """The output-link after an output phase.

    Attributes
    ----------
    output_link : Identifier
    wmes : tuple of WME
        Every WME reachable from the output-link.
    added, removed : tuple of WME
        Changes since the previous output phase.
    decision : int
    """

    output_link: Identifier
    wmes: tuple[WME, ...]
    added: tuple[WME, ...]
    removed: tuple[WME, ...]
    decision: int

    def commands(self) -> list[tuple[Symbol, Identifier | Symbol]]:
        """``(attr, value)`` of each WME directly on the output-link."""
        return [(w.attr, w.value) for w in self.wmes if w.id is self.output_link]

    def values(self, id: Symbol, attr: Symbol) -> list[Symbol]:
        """The values of ``(id ^attr *)`` under the output-link."""
        return [w.value for w in self.wmes if w.id is id and w.attr == attr]


class IoLinks:
    """The agent's input and output callbacks."""

    def __init__(self, kernel: Kernel, decisions: Callable[[], int]) -> None:
        self.kernel = kernel
        self.in_input = False
        self.input_callbacks: list[Callable[[InputWriter], None]] = []
        self.output_callbacks: list[Callable[[OutputView], None]] = []
        self._decisions = decisions
        self._writer = InputWriter(self)
        self._last: dict[WmeKey, WME] = {}

    def run_input(self) -> None:
        """Call the input callbacks with a writer that works only now."""
        if not self.input_callbacks:
            return
        self._writer.decision = self._decisions()
        self.in_input = True
        try:
            for callback in self.input_callbacks:
                callback(self._writer)
        finally:
            self.in_input = False

    def output_wmes(self) -> list[WME]:
        """Every WME reachable from the output-link."""
        wm = self.kernel.wm
        out: list[WME] = []
        seen = {self.kernel.output_link}
        stack = [self.kernel.output_link]
        while stack:
            for w in wm.of(stack.pop()):
                out.append(w)
                if type(w.value) is Identifier and w.value not in seen:
                    seen.add(w.value)
                    stack.append(w.value)
        return out

    def run_output(self) -> None:
        """Call the output callbacks if the output-link changed."""
        if not self.output_callbacks:
            return
        wmes = self.output_wmes()
        now = {w.key: w for w in wmes}
        added = tuple(w for key, w in now.items() if key not in self._last)
        removed = tuple(w for key, w in self._last.items() if key not in now)
        self._last = now
        if not added and not removed:
            return
        view = OutputView(self.kernel.output_link, tuple(wmes), added, removed,
                          self._decisions())
        for callback in self.output_callbacks:
            callback(view)
