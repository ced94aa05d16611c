"""The rule-engine interface: what the runner, the schemas and the command line use.

adapt runs rules on one of two engines behind the same interface:

* ``adapt`` -- its own engine, :class:`adapt.engine.Agent` (the default):
  readable Python, structured traces with bindings and candidates, checked
  decision by decision against Soar;
* ``soar`` -- the real Soar kernel (PyPI ``soar-sml``, the extra
  ``adapt[soar]``), :class:`adapt.soar.SoarAgent`: Soar's speed, and what
  the own engine refuses (chunking, reinforcement learning, semantic and
  episodic memory).

Both load the same rule files, run the same decision cycle (``run(n)`` stops
before the apply phase of the ``n``-th decision; ``(halt)``, ``(interrupt)``
and the goal-depth limit stop a run), call the same input and output
callbacks -- an :class:`InputLink` in each input phase, an
:class:`~adapt.engine.io.OutputView` after each output phase that changed
the output-link -- give the same :class:`~adapt.engine.report.RunReport`,
and write the same trace records (``docs/trace-format.md``).  What each
engine is, and when to choose which, is ``docs/engines.md``.

This module holds the one protocol of an engine (:class:`RuleEngine`, used
by the runner, the schema network, the command line and the tests), what its
callbacks get (:class:`InputLink`, :class:`~adapt.engine.io.OutputView`) and
the engine names; like the rest of :mod:`adapt.engine` it imports only the
standard library and :mod:`adapt.errors`.  :func:`adapt.engines.make_agent`
builds either engine.

Examples
--------
>>> from adapt.engine import Agent
>>> isinstance(Agent(), RuleEngine)
True
>>> EngineName("soar") is EngineName.SOAR, [e.value for e in EngineName]
(True, ['adapt', 'soar'])
"""

from __future__ import annotations

import os
from enum import Enum
from typing import Any, Callable, Protocol, Sequence, runtime_checkable

from adapt.engine.io import OutputView
from adapt.engine.report import RunReport
from adapt.engine.symbols import Identifier, Symbol
from adapt.engine.trace import TraceWriter
from adapt.engine.vocabulary import StopReason

__all__ = ["EngineName", "InputLink", "LoadedRules", "OutputView", "RuleEngine", "ENGINE_NAMES"]


class EngineName(str, Enum):
    """The rule engines: adapt's own and the Soar kernel."""

    ADAPT = "adapt"
    SOAR = "soar"


#: The engine names, as ``--engine`` and ``engine:`` take them.
ENGINE_NAMES: tuple[str, ...] = tuple(e.value for e in EngineName)


@runtime_checkable
class InputLink(Protocol):
    """What an input callback gets in each input phase: adds and removes
    WMEs under the input-link (committed at the end of the phase).

    :class:`adapt.engine.InputWriter` is the own engine's; the Soar engine's
    maps each call to SML input WMEs.
    """

    input_link: Identifier
    decision: int

    def new_id(self, letter: str = "I") -> Identifier:
        """A new identifier for structure under the input-link."""
        ...

    def add(self, id: object, attr: object, value: object) -> None:
        """Add ``(id ^attr value)``."""
        ...

    def remove(self, id: object, attr: object, value: object) -> None:
        """Remove ``(id ^attr value)`` (a no-op if it is not there)."""
        ...

    def set(self, id: object, attr: object, value: object) -> None:
        """Make ``value`` the only value of ``(id ^attr)``."""
        ...

    def clear(self, id: object, attr: object) -> None:
        """Remove every value of ``(id ^attr)``."""
        ...

    def values(self, id: object, attr: object) -> list[Symbol]:
        """The current values of ``(id ^attr *)``."""
        ...


class LoadedRules(Protocol):
    """What loading a rule file gives: at least the productions it added."""

    @property
    def productions(self) -> Sequence[Any]:
        """The productions the file (and the files it sources) added."""
        ...


@runtime_checkable
class RuleEngine(Protocol):
    """An agent of either engine (see the module docstring).

    Attributes
    ----------
    halted : bool
        ``(halt)`` was executed.
    decisions : int
        Decision phases run so far.
    stop_reason : str or None
        Why the last run stopped; a caller that stops the run itself may set
        it (``"interrupted"``).
    operator_count : int
        Operator selections so far.
    warnings : list of str
        Warnings of the rule files loaded.
    files : list of str
        The rule files loaded (for trace headers).
    """

    halted: bool
    stop_reason: StopReason | None
    warnings: list[str]
    files: list[str]

    @property
    def decisions(self) -> int:
        """Decision phases run so far."""
        ...

    @property
    def operator_count(self) -> int:
        """Operator selections so far."""
        ...

    def load_file(self, path: str | os.PathLike[str]) -> LoadedRules:
        """Load an agent file (and the files it sources)."""
        ...

    def load_text(self, text: str, file: str = "<string>") -> LoadedRules:
        """Load agent text; errors name ``file``."""
        ...

    def run(self, max_decisions: int | None = None, *, footer: bool = True) -> RunReport:
        """Run until halt, interrupt, the goal-depth limit or ``max_decisions``.

        ``footer=False``: this call writes no trace footer, even when it
        raises; a caller running the agent in slices (the runner's frame
        loop) ends the trace itself (:meth:`write_footer`).
        """
        ...

    def report(self) -> RunReport:
        """The report so far."""
        ...

    def write_footer(self, elapsed_s: float, error: str | None = None) -> None:
        """Write the trace's footer (for runs made of ``run(..., footer=False)`` slices)."""
        ...

    def close(self) -> None:
        """Release what the agent holds (its trace file; the Soar kernel)."""
        ...

    def trace_header(self) -> dict[str, Any]:
        """The header fields this engine's traces carry besides the common ones (the
        Soar engine's ``engine``, ``kernel``, ``absent``; none for the own engine)."""
        ...

    def attach_trace(self, writer: TraceWriter) -> None:
        """Write this agent's trace records through ``writer`` (at ``writer.level``), from
        its first run on: for a caller that writes its own records in the same file
        (the runner) and made ``writer`` with :meth:`trace_header`."""
        ...

    def on_input(self, callback: Callable[[InputLink], None]) -> None:
        """Call ``callback(writer)`` in every input phase."""
        ...

    def on_output(self, callback: Callable[[OutputView], None]) -> None:
        """Call ``callback(view)`` after each output phase that changed the output-link."""
        ...

    def on_write(self, callback: Callable[[str], None]) -> None:
        """Call ``callback(text)`` with the text of every ``(write ...)``."""
        ...

    @property
    def goals(self) -> list[Identifier]:
        """The goal stack's state identifiers, top first."""
        ...

    def print_state(self, ident: object = None, depth: int = 1) -> str:
        """Working memory under ``ident`` (the top state by default), as Soar prints it."""
        ...
