"""The public face of the engine: :class:`Agent`.

An agent owns a kernel (working memory, matcher, goal stack), loads Soar
rules, runs decision cycles, and reports what happened in a
:class:`~adapt.engine.report.RunReport`.

Examples
--------
>>> agent = Agent(seed=1)
>>> _ = agent.load_text('''
... sp {init (state <s> ^superstate nil) --> (<s> ^count 0)}
... sp {propose*count (state <s> ^count {<c> < 3})
...    --> (<s> ^operator <o> +) (<o> ^name count ^value <c>)}
... sp {apply*count (state <s> ^operator <o> ^count <c>) (<o> ^name count ^value <c>)
...    --> (<s> ^count <c> -) (<s> ^count (+ <c> 1))}
... sp {done (state <s> ^count 3) --> (write |three|) (halt)}
... ''')
>>> report = agent.run()
>>> report.halted, report.decisions, report.output, report.operators
(True, 3, 'three', [[1, 0, 'count'], [2, 0, 'count'], [3, 0, 'count']])
>>> print(agent.print_state(depth=1))
(S1 ^count 3 ^epmem E1 ^io I1 ^reward-link R1 ^smem L1 ^superstate nil ^type state)
"""

from __future__ import annotations

import gc
import os
import time
from collections import deque
from typing import Any, Callable, Iterator, MutableSequence

from adapt.engine import cycle
from adapt.engine.commands import Chunking, Setting
from adapt.engine.events import Event, EventBus
from adapt.engine.functions import FunctionTable, default_functions
from adapt.engine.goals import Goal
from adapt.engine.io import InputWriter, IoLinks, OutputView
from adapt.engine.kernel import Kernel
from adapt.engine.matcher import Matcher
from adapt.engine.parse import RuleFile, load_rule_file, parse_rules
from adapt.engine.report import RunReport
from adapt.engine.soar_random import SoarRandom
from adapt.engine.symbols import Identifier, Symbol
from adapt.engine.trace import TraceWriter
from adapt.engine.tracing import TraceRecorder
from adapt.engine.vocabulary import Phase, StopReason
from adapt.engine.wme import WME
from adapt.errors import EngineError

__all__ = ["Agent", "DEFAULT_GC_THRESHOLD"]

#: Generation-0 threshold of CPython's cyclic garbage collector while
#: :meth:`Agent.run` runs (see ``gc_threshold`` and ``docs/performance.md``).
DEFAULT_GC_THRESHOLD = 10_000


def _make_matcher(name: str) -> Matcher:
    if name == "naive":
        from adapt.engine.naive import NaiveMatcher

        return NaiveMatcher()
    if name == "rete":
        from adapt.engine.rete import Rete

        return Rete()
    raise EngineError(f"unknown matcher {name!r} (expected 'rete' or 'naive')")


#: The generation-1 and generation-2 thresholds of the policy (see ``gc_threshold``):
#: with CPython's 10 and 10, a run that starts with the collector's counters
#: near their limits still gets a full collection of the whole heap early on.
_GC_OLDER = (50, 100)


def _raise_gc_threshold(threshold: int | None) -> tuple[int, ...] | None:
    """Raise the collector's thresholds to ``(threshold, 50, 100)`` (each
    only if higher); returns the thresholds to restore, or None when nothing
    was changed."""
    if threshold is None or not gc.isenabled():
        return None
    saved = gc.get_threshold()
    if saved[0] == 0:  # automatic collection is off
        return None
    wanted = (max(saved[0], threshold), max(saved[1], _GC_OLDER[0]),
              max(saved[2], _GC_OLDER[1]))
    if wanted == saved:
        return None
    gc.set_threshold(*wanted)
    return saved


class _Context:
    """What right-hand-side functions may do to the agent (``RhsContext``)."""

    __slots__ = ("agent", "_constants", "copies", "copied_ids")

    def __init__(self, agent: Agent) -> None:
        self.agent = agent
        self._constants = 0
        self.copies: list[tuple[Identifier, Symbol, Symbol]] = []
        self.copied_ids: list[Identifier] = []

    def write(self, text: str) -> None:
        self.agent._write(text)

    def halt(self) -> None:
        self.agent.halted = True

    def interrupt(self) -> None:
        self.agent.interrupt_pending = True

    def error(self, message: str) -> None:
        self.agent.message(f"Error: {message}")

    def make_constant_symbol(self, prefix: str) -> str:
        while True:
            self._constants += 1
            name = f"{prefix}{self._constants}"
            if name not in self.agent._symbols_in_use():
                return name

    def decision_count(self) -> int:
        return self.agent.decisions

    def soar_random(self) -> SoarRandom:
        return self.agent.rng

    def wmes_of(self, ident: Identifier) -> list[WME]:
        return [w for w in self.agent.kernel.wm.of(ident) if not w[3]]

    def count(self, name: str) -> None:
        counters = self.agent.counters
        counters[name] = counters.get(name, 0) + 1

    def traces(self, level: int) -> bool:
        return level == 1  # Soar's default trace: decisions only

    def deep_copy(self, ident: Identifier) -> Identifier:
        """Soar's ``deep-copy``: identifiers made depth first, each identifier's
        WMEs visited as Soar keeps them (the newest attribute first, the newest
        WME first), the WMEs queued in :attr:`copies` for the firing."""
        ids = self.agent.kernel.ids
        root = ids.new("D")
        made: dict[Identifier, Identifier] = {}
        copies = self.copies
        self.copied_ids.append(root)

        def visit(source: Identifier, target: Identifier) -> None:
            if source in made:
                return
            made[source] = target
            for w in _soar_slot_order(self.wmes_of(source)):
                new: list[Symbol] = []
                for field in (w[1], w[2]):
                    if type(field) is Identifier:
                        copy = made.get(field)
                        if copy is None:
                            copy = ids.new(field.letter)
                            self.copied_ids.append(copy)
                        visit(field, copy)
                        new.append(copy)
                    else:
                        new.append(field)
                copies.append((target, new[0], new[1]))

        visit(ident, root)
        return root


def _soar_slot_order(wmes: list[WME]) -> list[WME]:
    """WMEs in the order Soar walks an identifier's slots: the slot created
    last first, in a slot the newest WME first."""
    first_seen: dict[Symbol, int] = {}
    for w in wmes:
        first_seen.setdefault(w[1], w[4])
    return sorted(wmes, key=lambda w: (-first_seen[w[1]], -w[4]))


class Agent:
    """A Soar-compatible rule engine agent.

    Parameters
    ----------
    seed : int
        Seed of the generator used for indifferent operator selection.
    matcher : {"rete", "naive"}
    trace : path, text stream, TraceWriter or None
        Where to write a JSON Lines trace (``docs/trace-format.md``).
    trace_level : int
        1..5.
    max_elaborations : int
        Elaboration cycles per proposal or apply phase (Soar: 100).
    max_goal_depth : int
        Deepest substate level before the run stops (Soar: 100).
    gc_threshold : int or None
        The garbage-collection policy of :meth:`run`.  While it runs, the
        thresholds of Python's cyclic garbage collector are raised (never
        lowered) to ``(gc_threshold, 50, 100)`` -- CPython's defaults are
        ``(700, 10, 10)`` -- and the caller's thresholds are restored when it
        returns.  The engine keeps many long-lived container objects (WMEs,
        tokens, instantiations, the network); with the default thresholds
        the collector runs a full collection, which scans all of them, every
        few hundred thousand allocations, and a large run becomes
        superlinear.  ``None`` (or 0) leaves the collector alone; nothing is
        changed either when the caller has disabled it (``gc.disable()``).
        Cyclic garbage then waits longer to be freed: at most about
        ``gc_threshold`` container objects' worth.
    history : int or None
        Keep only the most recent ``history`` operator selections, impasses,
        ``write`` texts and messages in memory (and so in :meth:`report`);
        ``None`` keeps everything.  An agent that runs for hours (a robot)
        needs a bound so that its memory stays flat; the counts
        :attr:`operator_count` and :attr:`impasse_count` are kept either way.

    Examples
    --------
    >>> import gc
    >>> before = gc.get_threshold()
    >>> _ = Agent().run(max_decisions=2)      # raised during the run only
    >>> gc.get_threshold() == before
    True
    >>> Agent(gc_threshold=None).gc_threshold is None
    True
    """

    def __init__(self, *, seed: int = 1, matcher: str = "rete", trace: Any = None,
                 trace_level: int = 5, max_elaborations: int = 100,
                 max_goal_depth: int = 100,
                 gc_threshold: int | None = DEFAULT_GC_THRESHOLD,
                 history: int | None = None) -> None:
        if gc_threshold is not None and gc_threshold < 0:
            raise EngineError(f"gc_threshold must be >= 0 or None, not {gc_threshold}")
        if history is not None and history < 1:
            raise EngineError(f"history must be >= 1 or None, not {history}")
        self.history = history
        self.gc_threshold = gc_threshold or None
        self.seed = seed
        #: Soar's random numbers, seeded as Soar's ``srand`` seeds them
        self.rng = SoarRandom(seed)
        #: the counters of ``(count ...)``
        self.counters: dict[str, int] = {}
        self.functions: FunctionTable = default_functions()
        self.max_elaborations = max_elaborations
        self.max_goal_depth = max_goal_depth
        #: whether ``(write ...)`` output is kept (Soar's ``output agent-writes``)
        self.agent_writes = True
        self.warnings: list[str] = []
        self.messages: MutableSequence[str] = self._log()
        self.files: list[str] = []
        self.halted = False
        #: ``(interrupt)`` fired: the run stops before the next decision phase
        self.interrupt_pending = False
        self.stop_reason: StopReason | None = None
        self.decisions = 0
        self.elaboration_cycles = 0
        self.operators: MutableSequence[list[Any]] = self._log()
        self.impasses: MutableSequence[list[Any]] = self._log()
        self.operator_count = 0
        self.impasse_count = 0
        self.next_phase = Phase.INPUT
        self._output: MutableSequence[str] = self._log()
        #: the agent's events: the trace and other layers listen here
        self.events = EventBus()
        self._context = _Context(self)
        self.kernel = Kernel(_make_matcher(matcher), self.functions, self._context, self.events)
        self.io = IoLinks(self.kernel, lambda: self.decisions)
        self.kernel.commit()
        self._trace_arg = trace
        self._trace_level = trace_level
        self.tracer: TraceWriter | None = None
        if trace is not None and not 1 <= trace_level <= 5:
            raise EngineError(f"trace level must be 1..5, not {trace_level}")

    def _log(self) -> MutableSequence[Any]:
        return [] if self.history is None else deque(maxlen=self.history)

    # -- rules --------------------------------------------------------------
    def load_text(self, text: str, file: str = "<string>", *,
                  chunking: Chunking = "refuse") -> RuleFile:
        """Load agent text: productions (one with an existing name replaces it)
        and agent-file commands (see :mod:`adapt.engine.commands`; ``source``
        reads files relative to the current directory).

        Raises
        ------
        RuleError
            At the first error; nothing from ``text`` is loaded then.
        """
        saved_gc = _raise_gc_threshold(self.gc_threshold)
        try:
            return self._load(parse_rules(text, file=file, functions=self.functions,
                                          chunking=chunking))
        finally:
            if saved_gc is not None:
                gc.set_threshold(*saved_gc)

    def load_file(self, path: str | os.PathLike[str], *,
                  chunking: Chunking = "refuse") -> RuleFile:
        """Load an agent file and the files it sources (see :meth:`load_text`).

        ``chunking="off"``: an agent written for chunking runs with learning
        off (its chunking commands are accepted and do nothing).  Loading
        follows the garbage-collection policy of :meth:`run` (see
        ``gc_threshold``): a large rule base is many long-lived objects.
        """
        saved_gc = _raise_gc_threshold(self.gc_threshold)
        try:
            rules = load_rule_file(path, functions=self.functions, chunking=chunking)
            self.files.extend(rules.files)
            return self._load(rules)
        finally:
            if saved_gc is not None:
                gc.set_threshold(*saved_gc)

    def _load(self, rules: RuleFile) -> RuleFile:
        self.warnings.extend(rules.warnings)
        settings = list(rules.settings)
        k = 0
        for i, p in enumerate(rules.productions):
            while k < len(settings) and settings[k][0] <= i:
                self._apply(settings[k][1])
                k += 1
            if p.name in self.kernel.rules:
                where = f"{p.location}: " if p.location is not None else ""
                self.warnings.append(f"{where}production {p.name} replaces an earlier one")
            self.kernel.add_production(p)
        for _, setting in settings[k:]:
            self._apply(setting)
        self.kernel.commit()
        return rules

    def _apply(self, setting: Setting) -> None:
        """Do what an accepted agent-file command asks (see :mod:`adapt.engine.commands`)."""
        kind, value = setting.kind, setting.value
        if kind == "seed":
            assert isinstance(value, int)
            self.reseed(value)
        elif kind == "multi-attributes":
            assert isinstance(value, int) and setting.name is not None
            self.kernel.multi_attributes[setting.name] = value
            self.kernel.matcher.constants.add(setting.name)
        elif kind == "symbols":
            self.kernel.matcher.constants.add(str(value))
        elif kind == "max-elaborations":
            assert isinstance(value, int)
            self.max_elaborations = value
        elif kind == "max-goal-depth":
            assert isinstance(value, int)
            self.max_goal_depth = value
        elif kind == "agent-writes":
            self.agent_writes = bool(value)
        elif kind == "echo":
            self.message(str(value))

    def reseed(self, seed: int) -> None:
        """Seed the agent's random numbers (Soar's ``srand``)."""
        self.seed = seed
        self.rng.seed(seed)

    def register_function(self, name: str, fn: Callable[..., object], *, min_args: int = 0,
                          max_args: int | None = None) -> None:
        """Make a Python function callable from rules as ``(name ...)``.

        Register functions before loading rules that call them.
        """
        self.functions.register(name, fn, min_args=min_args, max_args=max_args)

    # -- running ----------------------------------------------------------------
    def run(self, max_decisions: int | None = None, *, footer: bool = True) -> RunReport:
        """Run until halt, an interrupt, the goal-depth limit, or ``max_decisions``
        decisions (stopping before the apply phase of the last one).

        May be called again to continue; the report covers the whole life of
        the agent.  A Python exception from a user RHS function ends the run
        (the trace gets its footer, unless ``footer=False``) and propagates.

        ``footer=False`` writes no trace footer at the end of this call, even
        when it raises: a caller that runs the agent in many slices (a frame
        loop) writes one footer at the very end with :meth:`write_footer`.
        """
        if max_decisions is not None and max_decisions < 0:
            raise EngineError("max_decisions must be >= 0")
        self._open_trace()
        started = time.perf_counter()
        if not self.halted:
            self.stop_reason = None
        error: str | None = None
        saved_gc = _raise_gc_threshold(self.gc_threshold)
        try:
            if not self.halted:
                cycle.run(self, max_decisions)
        except BaseException as exc:
            error = f"{type(exc).__name__}: {exc}"
            if self.stop_reason is None:
                self.stop_reason = "interrupted"
            raise
        finally:
            if saved_gc is not None:
                gc.set_threshold(*saved_gc)
            if self.halted:
                self.stop_reason = "halt"
            if self.tracer is not None and footer:
                self.tracer.footer(self.report().to_dict(), time.perf_counter() - started,
                                   error)
        return self.report()

    def trace_header(self) -> dict[str, Any]:
        """The header fields of this engine's traces besides the common ones: none (a
        trace without ``engine`` is the own engine's)."""
        return {}

    def attach_trace(self, writer: TraceWriter) -> None:
        """Write the trace through ``writer`` (at its level) from the first run on.

        Raises
        ------
        EngineError
            When the agent already has a trace.
        """
        if self.tracer is not None or self._trace_arg is not None:
            raise EngineError("the agent already writes a trace")
        self._trace_arg = writer
        self._trace_level = writer.level

    def write_footer(self, elapsed_s: float, error: str | None = None) -> None:
        """Write the trace's footer (for runs made of ``run(..., footer=False)`` slices)."""
        if self.tracer is not None:
            self.tracer.footer(self.report().to_dict(), elapsed_s, error)

    def step(self) -> RunReport:
        """Run one decision cycle (``run(1)``)."""
        return self.run(1)

    def report(self) -> RunReport:
        """The report so far."""
        return RunReport(
            halted=self.halted, stop_reason=self.stop_reason or "interrupted",
            decisions=self.decisions, output="".join(self._output),
            operators=[list(o) for o in self.operators],
            impasses=[list(i) for i in self.impasses],
            production_firings=self.kernel.firings,
            elaboration_cycles=self.elaboration_cycles,
            wm_size_final=len(self.kernel.wm), messages=list(self.messages))

    def close(self) -> None:
        """Close the trace file (if the agent opened one)."""
        if self.tracer is not None:
            self.tracer.close()

    # -- working memory ----------------------------------------------------------
    @property
    def wm(self) -> Iterator[WME]:
        """Iterate over working memory."""
        return iter(self.kernel.wm)

    @property
    def top_state(self) -> Identifier:
        """``S1``."""
        return self.kernel.top.id

    @property
    def input_link(self) -> Identifier:
        """The ``^input-link`` identifier."""
        return self.kernel.input_link

    @property
    def output_link(self) -> Identifier:
        """The ``^output-link`` identifier."""
        return self.kernel.output_link

    @property
    def goals(self) -> list[Identifier]:
        """The goal stack's state identifiers, top first."""
        out: list[Identifier] = []
        goal: Goal | None = self.kernel.top
        while goal is not None:
            out.append(goal.id)
            goal = goal.lower
        return out

    def print_state(self, ident: object = None, depth: int = 1) -> str:
        """Like Soar's ``print --depth N S1`` (``ident``: an identifier, the top state by default).

        Raises
        ------
        EngineError
            When ``ident`` is not an identifier of this agent.
        """
        root = self.top_state if ident is None else ident
        if not isinstance(root, Identifier):
            raise EngineError(f"print_state needs an identifier, not {ident!r}")
        return self.kernel.wm.tree(root, depth)

    def on_input(self, callback: Callable[[InputWriter], None]) -> None:
        """Call ``callback(writer)`` in every input phase."""
        self.io.input_callbacks.append(callback)

    def on_output(self, callback: Callable[[OutputView], None]) -> None:
        """Call ``callback(view)`` after each output phase that changed the output-link."""
        self.io.output_callbacks.append(callback)

    def on_write(self, callback: Callable[[str], None]) -> None:
        """Call ``callback(text)`` with the text of every ``(write ...)`` as it happens."""
        self.events.subscribe(Event.WRITE, callback)

    # -- what rules and the cycle report ------------------------------------------
    def message(self, text: str) -> None:
        """Record a kernel message."""
        self.messages.append(text)
        self.events.emit(Event.MESSAGE, text)

    def _write(self, text: str) -> None:
        if not self.agent_writes:
            return
        self._output.append(text)
        self.events.emit(Event.WRITE, text)

    @property
    def halted_message_pending(self) -> bool:
        """True when the agent halted and "This Agent halted." is not yet the last message."""
        return self.halted and (not self.messages or self.messages[-1] != "This Agent halted.")

    def _symbols_in_use(self) -> set[Symbol]:
        used: set[Symbol] = set()
        for w in self.kernel.wm:
            used.update((w.attr, w.value))
        return used

    # -- tracing -------------------------------------------------------------------
    def _open_trace(self) -> None:
        if self.tracer is not None or self._trace_arg is None:
            return
        arg = self._trace_arg
        self.tracer = arg if isinstance(arg, TraceWriter) else TraceWriter(
            arg, level=self._trace_level, files=self.files, seed=self.seed)
        TraceRecorder(self.tracer, self.kernel, self.events)

    def __repr__(self) -> str:
        return (f"Agent(decisions={self.decisions}, wmes={len(self.kernel.wm)}, "
                f"rules={len(self.kernel.rules)}, halted={self.halted})")

