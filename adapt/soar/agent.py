"""The Soar engine: :class:`SoarAgent`, the real Soar kernel behind adapt's engine interface.

A :class:`SoarAgent` is used as :class:`adapt.engine.Agent` is
(:class:`adapt.engine.interface.RuleEngine`): it loads the same rule files
(with Soar's own ``source``, so every command Soar knows works: ``chunk
always``, ``rl``, ``smem``, ``epmem`` ...), runs decision cycles, calls the
same input and output callbacks, and gives the same
:class:`~adapt.engine.report.RunReport` and trace records.  The kernel runs
in a child process (:mod:`adapt.soar.process`); the report and the trace are
built here, from what the kernel reports (:mod:`adapt.soar.recorder`), so a
crash of the kernel ends the run with :class:`~adapt.soar.process.KernelCrash`
and leaves both complete up to the last decisions the kernel reported.

How the interface maps to the kernel:

* **seed**: ``decide set-random-seed N`` (Soar's ``srand``) before any rule
  is loaded; :meth:`SoarAgent.reseed` later;
* **run(n)**: ``RunSelf(n)`` -- Soar stops before the apply phase of the
  ``n``-th decision, as the own engine does (``run(0)`` runs one decision,
  as Soar's ``run 0``); the stop reason is read from the kernel: halted,
  ``(interrupt)``, the goal-depth warning, the decision bound;
* **input**: before each input phase the input callbacks get a
  :class:`~adapt.soar.inputlink.SoarInputWriter`; what they write becomes SML
  input WMEs in that input phase;
* **output**: after each decision cycle in which the output-link changed
  (SML's output-link change tracking), the output callbacks get an
  :class:`~adapt.engine.io.OutputView` of it;
* **write**: ``(write)`` text reaches ``on_write`` listeners and the report
  from the kernel's trace, at the end of each decision cycle;
* **Ctrl-C**: the kernel is asked to stop after its current phase
  (``StopSelf``); the run ends as "interrupted" with what ran reported.

Examples
--------
>>> agent = SoarAgent(seed=1)                               # doctest: +SKIP
>>> _ = agent.load_file("rules/examples/water-jug.soar")    # doctest: +SKIP
>>> agent.run().halted                                      # doctest: +SKIP
True
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import tempfile
import threading
import time
from typing import Any, Callable, Iterator

from adapt.engine.io import OutputView
from adapt.engine.report import RunReport
from adapt.engine.symbols import Identifier
from adapt.engine.trace import TraceWriter
from adapt.engine.vocabulary import StopReason
from adapt.engine.wme import WME
from adapt.errors import EngineError, RuleError
from adapt.soar.inputlink import SoarInputWriter
from adapt.soar.process import KernelCrash, KernelProcess
from adapt.soar.recorder import KernelRecorder, Symbols, trace_header

__all__ = ["SoarAgent", "SoarRules", "trace_commands"]

_LOCATION = re.compile(r"^\t(.+):(\d+)\s*$", re.MULTILINE)
_NOISE = re.compile(r"^(?:[*#]+|Total: .*|Error while sourcing file|Production addition failed\.|"
                    r"\t.*)$")


def trace_commands(trace_level: int | None) -> list[str]:
    """The kernel's trace settings for an adapt trace level (``None``: no trace).

    Without a trace the kernel traces decisions only: the report's operator
    selections and impasses come from them, and ``(write)`` text and
    messages are always sent.  Levels 1-2 add the phases; levels 3-5 trace
    everything adapt writes (firings with the timetags they matched, the
    preferences they made, WME changes).

    >>> trace_commands(None), trace_commands(2), trace_commands(5)
    (['trace 1'], ['trace 2'], ['trace 5', 'trace --timetags'])
    """
    if trace_level is None:
        return ["trace 1"]
    if trace_level <= 2:
        return ["trace 2"]
    return ["trace 5", "trace --timetags"]


class SoarRules:
    """What loading a file into the kernel gave: the names of the productions it
    added, the files, and the kernel's warnings."""

    def __init__(self, productions: tuple[str, ...], files: tuple[str, ...],
                 warnings: tuple[str, ...]) -> None:
        self.productions = productions
        self.files = files
        self.warnings = warnings


def _quote(path: str) -> str:
    return '"' + path.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _shown(path: str, top: str, given: str) -> str:
    """A path as the user should see it: as given for the top file, relative when below here."""
    if os.path.abspath(path) == top:
        return given
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return path
    return path if rel.startswith("..") else rel


def _line_of(text: str, line: int) -> str | None:
    lines = text.splitlines()
    return lines[line - 1] if 1 <= line <= len(lines) else None


def _source_line(path: str, line: int) -> str | None:
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            for k, text in enumerate(f, 1):
                if k == line:
                    return text
    except OSError:
        return None
    return None


class SoarAgent:
    """An agent in the real Soar kernel (see the module docstring).

    Parameters
    ----------
    seed : int
        Soar's random seed (``srand``): indifferent selection, ``rand-int``,
        ``rand-float``.
    trace : path, text stream, TraceWriter or None
        Where to write a JSON Lines trace (``docs/trace-format.md``).
    trace_level : int
        1..5.
    history : int or None
        Keep only the most recent operator selections, impasses, writes and
        messages in memory (``None``: everything), as :class:`adapt.engine.Agent`.

    Raises
    ------
    AdaptError
        When soar-sml is not installed (the message says which extra to
        install) or the kernel cannot start.
    """

    def __init__(self, *, seed: int = 1, trace: Any = None, trace_level: int = 5,
                 history: int | None = None) -> None:
        if trace is not None and not 1 <= trace_level <= 5:
            raise EngineError(f"trace level must be 1..5, not {trace_level}")
        if history is not None and history < 1:
            raise EngineError(f"history must be >= 1 or None, not {history}")
        self.seed = seed
        self.history = history
        self.halted = False
        self.stop_reason: StopReason | None = None
        self.warnings: list[str] = []
        self.files: list[str] = []
        self.tracer: TraceWriter | None = None
        self._trace_arg = trace
        self._trace_level = trace_level
        self._trace_commands = trace_commands(trace_level if trace is not None else None)
        self.symbols = Symbols()
        self.recorder = KernelRecorder(self.symbols, history=history, track_wmes=True)
        self.process = KernelProcess()
        self.kernel_version = ""
        self._stats: dict[str, int] = {}
        self._inputs: list[Callable[[Any], None]] = []
        self._outputs: list[Callable[[OutputView], None]] = []
        self._last_output: dict[tuple[Any, ...], WME] = {}
        self._interrupted = 0
        self._failure: str | None = None  # an input operation the kernel refused
        reply = self.process.request(("config", [f"decide set-random-seed {seed}",
                                                 *self._trace_commands]))
        self.kernel_version = f"Soar {reply[1]['kernel']}"
        self.recorder.existing(reply[2])
        self.recorder.track_wmes = trace is not None and trace_level >= 3
        top = next((w.id for w in self.recorder.wm.values() if w.attr == "superstate"
                    and w.value == "nil"), None)
        self.top_state: Identifier = top if isinstance(top, Identifier) else self.symbols.identifier("S1")
        self.input_link = self._link("input-link", "I2")
        self.output_link = self._link("output-link", "I3")
        self.writer = SoarInputWriter(self.input_link)

    def _link(self, attr: str, default: str) -> Identifier:
        wm = self.recorder.wm.values()
        io = next((w.value for w in wm if w.id is self.top_state and w.attr == "io"), None)
        found = next((w.value for w in wm if w.id is io and w.attr == attr), None)
        return found if isinstance(found, Identifier) else self.symbols.identifier(default)

    # -- what the interface asks -----------------------------------------------------------

    @property
    def decisions(self) -> int:
        """Decision phases run so far (while a run is being read: as far as it has been read)."""
        return self.recorder.d

    @property
    def operator_count(self) -> int:
        """Operator selections so far."""
        return self.recorder.operator_count

    @property
    def impasse_count(self) -> int:
        """Impasses so far."""
        return self.recorder.impasse_count

    @property
    def messages(self) -> list[str]:
        """Kernel messages and warnings so far."""
        return list(self.recorder.messages)

    def load_file(self, path: str | os.PathLike[str]) -> SoarRules:
        """Load an agent file with Soar's ``source`` (every command Soar knows works).

        Raises
        ------
        RuleError
            When the file cannot be read, or the kernel rejects a rule or a
            command: the kernel's message, with the file and line it names.
        """
        given = os.fspath(path)
        top = os.path.abspath(given)
        if not os.path.isfile(top):
            why = "is a directory" if os.path.isdir(top) else "No such file or directory"
            raise RuleError(f"cannot read rule file: {why}", file=given)
        return self._source(top, given)

    def _source(self, top: str, given: str) -> SoarRules:
        reply = self.process.request(("source", f"source {_quote(top)}", self._trace_commands))
        _kind, ok, text, added, xml = reply
        for x in xml:
            self.recorder.feed(x)
        if not ok:
            raise self._load_error(text, top, given)
        warnings = tuple(f"{given}: warning: {line.strip().lstrip('*#').strip().removeprefix('Warning:').strip()}"
                         for line in text.splitlines() if "Warning:" in line)
        self.warnings.extend(warnings)
        self.files.append(given)
        return SoarRules(tuple(added), (given,), warnings)

    def load_text(self, text: str, file: str = "<string>") -> SoarRules:
        """Load agent text (productions and commands), as :meth:`load_file` loads a file;
        errors name ``file``.  (The kernel reads it from a temporary file: a
        ``source`` in it is relative to that file's folder.)"""
        with tempfile.TemporaryDirectory(prefix="adapt-soar-") as folder:
            path = os.path.join(folder, "agent.soar")
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            try:
                rules = self._source(path, file)
            except RuleError as exc:
                if os.path.abspath(exc.file) != path and exc.file != file:
                    raise
                raise RuleError(exc.message, file=file, line=exc.line, col=exc.col,
                                source_line=_line_of(text, exc.line)) from None
        self.files.pop()
        return SoarRules(rules.productions, (), rules.warnings)

    def _load_error(self, text: str, top: str, given: str) -> RuleError:
        where = _LOCATION.search(text)
        lines = text.splitlines()
        start = next((i for i, line in enumerate(lines) if "Error" in line or "error" in line), 0)
        message = " ".join(line.strip().lstrip("*#").strip() for line in lines[start:]
                           if line.strip() and not _NOISE.match(line.strip("\n")))
        message = f"the Soar kernel rejected it: {(message or text.strip()).removeprefix('Error: ')}"
        if where is None:
            return RuleError(message, file=given)
        path, line = where.group(1), int(where.group(2))
        return RuleError(message, file=_shown(path, top, given), line=line,
                         source_line=_source_line(path, line))

    def reseed(self, seed: int) -> None:
        """Seed Soar's random numbers (``srand``)."""
        self.seed = seed
        self.command(f"decide set-random-seed {seed}")

    def command(self, line: str) -> str:
        """Run one Soar command in the kernel (``rl``, ``smem --query``, ``print``, ...);
        its text.

        Raises
        ------
        EngineError
            When the kernel says the command failed.
        """
        _kind, ok, text = self.process.request(("command", line))
        if not ok:
            raise EngineError(f"the Soar kernel refused {line!r}: {text.strip()}")
        return str(text)

    @property
    def goals(self) -> list[Identifier]:
        """The goal stack's state identifiers, top first (the kernel's ``print --stack``)."""
        text = self.command("print --stack --states")
        return [self.symbols.identifier(m) for m in re.findall(r"==>S: (\S+)", text)]

    def print_state(self, ident: object = None, depth: int = 1) -> str:
        """Working memory under ``ident`` (the top state by default), as Soar's ``print --depth``."""
        root = self.top_state if ident is None else ident
        if not isinstance(root, Identifier):
            raise EngineError(f"print_state needs an identifier, not {ident!r}")
        return self.command(f"print --depth {int(depth)} {root.name}").rstrip("\n")

    def on_input(self, callback: Callable[[Any], None]) -> None:
        """Call ``callback(writer)`` in every input phase (a :class:`SoarInputWriter`)."""
        self._inputs.append(callback)

    def on_output(self, callback: Callable[[OutputView], None]) -> None:
        """Call ``callback(view)`` after each decision cycle that changed the output-link."""
        self._outputs.append(callback)

    def on_write(self, callback: Callable[[str], None]) -> None:
        """Call ``callback(text)`` with the text of every ``(write ...)``."""
        self.recorder.on_write.append(callback)

    # -- running ------------------------------------------------------------------------

    def run(self, max_decisions: int | None = None, *, footer: bool = True) -> RunReport:
        """Run until halt, an interrupt, the goal-depth limit, or ``max_decisions``
        decisions (stopping before the apply phase of the last one); may be
        called again to continue.

        Raises
        ------
        KernelCrash
            The kernel's process died; the report and the trace (with its
            footer) hold what ran.
        """
        if max_decisions is not None and max_decisions < 0:
            raise EngineError("max_decisions must be >= 0")
        if self.process.dead is not None:
            raise KernelCrash(self.process.dead)
        self._open_trace()
        started = time.perf_counter()
        if not self.halted:
            self.stop_reason = None
        error: str | None = None
        try:
            if not self.halted:
                self._run(max_decisions)
        except BaseException as exc:
            error = f"{type(exc).__name__}: {exc}"
            if self.stop_reason is None:
                self.stop_reason = "interrupted"
            raise
        finally:
            if self.halted:
                self.stop_reason = "halt"
            if self.tracer is not None and footer:
                self.tracer.footer(self.report().to_dict(), time.perf_counter() - started, error)
        return self.report()

    def _run(self, n: int | None) -> None:
        self.recorder.goal_depth_exceeded = False
        self._interrupted = 0
        self.process.send(("run", None if n is None else max(n, 1), bool(self._inputs),
                           bool(self._outputs), self.tracer is not None))
        with self._ctrl_c():
            try:
                info = self._pump(stopping=False)
            except BaseException:
                self._stop()
                raise
        self._finish(info, n)
        if self._interrupted:
            raise KeyboardInterrupt
        if self._failure is not None:
            failure, self._failure = self._failure, None
            self.stop_reason = "interrupted"
            raise EngineError(failure)

    @contextlib.contextmanager
    def _ctrl_c(self) -> Iterator[None]:
        """While the kernel runs, Ctrl-C asks it to stop (a second one ends its process);
        the run ends, everything it reported is read, then KeyboardInterrupt is raised."""
        if threading.current_thread() is not threading.main_thread():
            yield
            return

        def interrupt(_signum: int, _frame: object) -> None:
            self._interrupted += 1
            if self._interrupted == 1:
                self.process.stop()
            else:
                self.process.kill()

        previous = signal.signal(signal.SIGINT, interrupt)
        try:
            yield
        finally:
            signal.signal(signal.SIGINT, previous)

    def _finish(self, info: dict[str, Any], n: int | None) -> None:
        """What the kernel said when its run ended: decisions, halt, counters, stop reason."""
        self.recorder.d = int(info["decisions"])
        self.halted = bool(info["halted"])
        self._stats = {k: int(v) for k, v in info.items() if k in
                       ("production_firings", "elaboration_cycles", "wm_size")}
        if self.halted:
            self.stop_reason = "halt"
        elif info["stopped"]:
            self.stop_reason = "interrupted"
        elif n is not None and int(info["ran"]) >= max(n, 1):
            self.stop_reason = "max-decisions"
        elif self.recorder.goal_depth_exceeded:
            self.stop_reason = "max-goal-depth"
        else:
            self.stop_reason = "interrupted"

    def _pump(self, stopping: bool) -> dict[str, Any]:
        """Handle the kernel's messages until the run is done."""
        process, recorder = self.process, self.recorder
        while True:
            message = process.recv()
            kind = message[0]
            if kind == "xml":
                for xml in message[1]:
                    recorder.feed(xml)
            elif kind == "input":
                if stopping or self._interrupted:
                    process.send(("abort",))
                else:
                    self._input(int(message[1]))
            elif kind == "ids":
                for number, name in message[1].items():
                    ident = self.writer.named(number)
                    if ident is not None:
                        self.symbols.bind(ident, name)
            elif kind == "output":
                self._output(int(message[1]), message[2], call=not (stopping or self._interrupted))
            elif kind == "input-error":  # the kernel stops its run: read to its end, then raise
                self._failure = f"input-link: {message[1]}"
                stopping = True
            elif kind == "done":
                return dict(message[1])
            elif kind == "error":
                raise EngineError(f"the Soar engine failed: {message[1]}")

    def _stop(self) -> None:
        """After an error here (a callback raised): stop the kernel's run and read what it did."""
        if self.process.dead is not None:
            return
        self.process.stop()
        try:
            info = self._pump(stopping=True)
        except EngineError:
            return
        self._finish(info, None)
        self.stop_reason = "interrupted"

    def _input(self, decision: int) -> None:
        writer = self.writer
        writer.begin(decision)
        self.recorder.d = decision
        try:
            for callback in self._inputs:
                callback(writer)
        except BaseException:
            writer.end()
            self.process.send(("abort",))
            raise
        self.process.send(("ops", writer.end()))

    def _output(self, decision: int, wmes: list[tuple[Any, ...]], call: bool) -> None:
        s = self.symbols
        now: dict[tuple[Any, ...], WME] = {}
        for timetag, ident, attr, value, vtype in wmes:
            w = WME(s.identifier(ident), attr, s.value(value, vtype), False, int(timetag))
            now[(w.id, w.attr, w.value, type(w.value))] = w
        added = tuple(w for key, w in now.items() if key not in self._last_output)
        removed = tuple(w for key, w in self._last_output.items() if key not in now)
        self._last_output = now
        if not call or (not added and not removed):
            return
        view = OutputView(self.output_link, tuple(now.values()), added, removed, decision)
        for callback in self._outputs:
            callback(view)

    def report(self) -> RunReport:
        """The report so far (after a kernel crash, the counters of the last run that ended)."""
        r = self.recorder
        return RunReport(
            halted=self.halted, stop_reason=self.stop_reason or "interrupted",
            decisions=self.decisions, output=r.output(),
            operators=[list(o) for o in r.operators], impasses=[list(i) for i in r.impasses],
            production_firings=self._stats.get("production_firings", 0),
            elaboration_cycles=self._stats.get("elaboration_cycles", 0),
            wm_size_final=self._stats.get("wm_size", 0), messages=list(r.messages))

    def attach_trace(self, writer: TraceWriter) -> None:
        """Write the trace through ``writer`` (at its level) from the first run on; the
        kernel traces what that level needs from now.

        Raises
        ------
        EngineError
            When the agent already has a trace.
        """
        if self.tracer is not None or self._trace_arg is not None:
            raise EngineError("the agent already writes a trace")
        self._trace_arg = writer
        self._trace_level = writer.level
        self._trace_commands = trace_commands(writer.level)
        for line in self._trace_commands:
            self.command(line)
        self.recorder.track_wmes = writer.level >= 3

    def write_footer(self, elapsed_s: float, error: str | None = None) -> None:
        """Write the trace's footer (for runs made of ``run(..., footer=False)`` slices)."""
        if self.tracer is not None:
            self.tracer.footer(self.report().to_dict(), elapsed_s, error)

    def close(self) -> None:
        """Close the trace file (if the agent opened it) and end the kernel's process."""
        if self.tracer is not None:
            self.tracer.close()
        self.process.close()

    def trace_header(self) -> dict[str, Any]:
        """The header fields of this engine's traces (``engine``, ``kernel``, ``absent``)."""
        return trace_header(self.kernel_version)

    def _open_trace(self) -> None:
        if self.tracer is not None or self._trace_arg is None:
            return
        arg = self._trace_arg
        self.tracer = arg if isinstance(arg, TraceWriter) else TraceWriter(
            arg, level=self._trace_level, files=self.files, seed=self.seed,
            header=self.trace_header())
        self.recorder.attach(self.tracer)

    def __repr__(self) -> str:
        return (f"SoarAgent(decisions={self.decisions}, halted={self.halted}, "
                f"kernel={self.kernel_version!r})")
