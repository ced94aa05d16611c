"""The Soar kernel's process: the only module that imports ``soar_sml``.

:class:`adapt.soar.SoarAgent` runs this file as a script (``python -I
worker.py FD_IN FD_OUT``: it imports only the standard library and
``soar_sml``) and talks to it over two pipes (:mod:`multiprocessing.connection`:
length-prefixed pickles of plain tuples).  The worker makes one kernel in its
own thread (``Kernel.CreateKernelInCurrentThread``, no listener port) and one
agent, and answers requests one at a time:

* ``("config", commands)``: runs each command (``decide set-random-seed``,
  ``trace ...``); replies ``("ready", info, xml)`` with the WMEs that exist
  (the top state's structure) as ``<wme>`` elements;
* ``("source", line, trace commands)``: ``source "path"``, then the trace
  commands again (an agent's own ``watch 0`` must not hide what the report
  needs); replies ``("sourced", ok, text, added names, xml)``;
* ``("command", line)``: replies ``("result", ok, text)``;
* ``("run", n, input, output, tracing)``: streams ``("xml", [raw, ...])``,
  ``("input", d)`` (then waits for ``("ops", ops)`` or ``("abort",)``; an op the
  kernel refuses stops the run with ``("input-error", why)``),
  ``("ids", {number: kernel name})``, ``("output", d, wmes)``; ends with
  ``("done", info)``.  The run-event callbacks a run does not need (input,
  output-link change tracking, the end of each cycle) are not registered:
  each costs every decision;
* ``("quit",)``: exits.

The XML trace (``smlEVENT_XML_TRACE_OUTPUT``) is passed on as the raw strings
the kernel sends (with the ``Error`` lines of the printed trace, which the XML
trace lacks, as ``<error>`` elements) -- :mod:`adapt.soar.recorder` reads
them -- in batches: at
most :data:`FLUSH_S` seconds old, and always before an input request and at
the end of a run.  ``SIGUSR1`` asks a running agent to stop
(``StopSelf``); ``SIGINT`` is ignored (the parent handles Ctrl-C).  When the
parent goes away the worker exits.

Input operations (``ops``) name identifiers by kernel name (a string: the
input-link, an output-link command, structure made earlier) or by a number
the parent gave a new identifier; the worker keeps the SML objects of the
WMEs it made so that it can remove them.
"""

from __future__ import annotations

import html
import os
import re
import signal
import sys
import time
from collections import deque
from multiprocessing.connection import Connection
from typing import Any

#: Seconds the worker may hold XML trace strings before sending them.
FLUSH_S = 0.02

_STATS = {
    "decisions": re.compile(r"^(\d+) decisions", re.MULTILINE),
    "elaboration_cycles": re.compile(r"^(\d+) elaboration cycles", re.MULTILINE),
    "production_firings": re.compile(r"^(\d+) production firings", re.MULTILINE),
    "wm_size": re.compile(r"^WM size: (\d+) current", re.MULTILINE),
}


_ERROR = re.compile(r"Error:(?:(?!Error:)[^\n])*")
_WRITE = re.compile(r'<rhs_write string="([^"]*)"')


def _escape(text: str) -> str:
    return (text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
            .replace(">", "&gt;"))


def _stats(text: str) -> dict[str, int]:
    out = {}
    for key, pattern in _STATS.items():
        m = pattern.search(text)
        if m is not None:
            out[key] = int(m.group(1))
    return out


class Worker:
    """One kernel and one agent, driven by the parent's requests."""

    def __init__(self, conn_in: Connection, conn_out: Connection) -> None:
        import soar_sml

        self.sml = soar_sml
        self.rx = conn_in
        self.tx = conn_out
        self.kernel = soar_sml.Kernel.CreateKernelInCurrentThread(True, soar_sml.Kernel.kSuppressListener)
        if self.kernel is None or self.kernel.HadError():
            raise RuntimeError("could not create the Soar kernel: "
                               + (self.kernel.GetLastErrorDescription() if self.kernel else "None"))
        self.agent = self.kernel.CreateAgent("adapt")
        if self.agent is None:
            raise RuntimeError("could not create a Soar agent: " + self.kernel.GetLastErrorDescription())
        self.xml: list[str] = []
        self.errors: list[str] = []
        self.writes: deque[str] = deque(maxlen=256)  # the latest (write) texts
        self.last_flush = time.perf_counter()
        self.stop_requested = False
        self.running = False
        self.want_input = False
        self.want_output = False
        #: SML identifiers the parent may name: kernel name (or new-id number) -> Identifier
        self.ids: dict[Any, Any] = {}
        #: SML WMEs this process made: (id key, attr, value key, value is an id) -> WMElement
        self.wmes: dict[tuple[Any, str, Any, bool], Any] = {}
        #: new identifiers whose kernel name is not known yet: number -> client name
        self.unnamed: dict[int, str] = {}
        self.output: dict[int, tuple[Any, ...]] = {}
        agent = self.agent
        agent.RegisterForXMLEvent(soar_sml.smlEVENT_XML_TRACE_OUTPUT, self.on_xml, None)
        agent.RegisterForPrintEvent(soar_sml.smlEVENT_PRINT, self.on_print, None)
        agent.SetOutputLinkChangeTracking(False)
        #: the callbacks registered only while a run needs them (each costs every decision)
        self.registered: dict[str, list[int]] = {}
        signal.signal(signal.SIGUSR1, self.on_stop)

    # -- sending ---------------------------------------------------------------------

    def send(self, message: tuple[Any, ...]) -> None:
        try:
            self.tx.send(message)
        except OSError:  # the parent is gone
            os._exit(3)

    def flush(self) -> None:
        if self.xml:
            self.send(("xml", self.xml))
            self.xml = []
        self.last_flush = time.perf_counter()

    # -- kernel callbacks ----------------------------------------------------------------

    def on_xml(self, _event: int, _data: object, _agent: object, xml: Any) -> None:
        raw = xml.GenerateXMLString(True)
        self.xml.append(raw)
        if "rhs_write" in raw:
            self.writes.extend(html.unescape(w) for w in _WRITE.findall(raw))
        self.attach_errors()
        if time.perf_counter() - self.last_flush > FLUSH_S:
            self.flush()
        if self.stop_requested and self.running:
            self.agent.StopSelf()

    def on_print(self, _event: int, _data: object, _agent: object, text: str) -> None:
        """The printed trace: only its errors are kept, those the XML trace lacks (an RHS
        function's ``Error: ...``, printed wherever the line then stands), as ``<error>``
        elements after the cycle's XML."""
        if "Error:" in text:
            self.errors.extend(_ERROR.findall(text))

    def attach_errors(self) -> None:
        """Put the printed errors after the XML of their decision cycle (the kernel flushes
        the printed trace after the XML at the end of a cycle, but before it when a run
        stops: both reach here before the next cycle's XML).  A line that is the text of
        one of the latest ``(write)`` calls (the printed trace holds the writes too) is no
        error."""
        if not self.errors:
            return
        for line in self.errors:
            if not any(line in w for w in self.writes):
                self.xml.append(f'<trace><error string="{_escape(line)}"></error></trace>')
        self.errors = []

    def on_stop(self, _signum: int, _frame: object) -> None:
        self.stop_requested = True
        if self.running:
            self.agent.StopSelf()

    def on_input(self, _event: int, _data: object, agent: Any, _phase: object) -> None:
        if not self.want_input:
            return
        self.flush()
        self.send(("input", agent.GetDecisionCycleCounter()))
        try:
            request = self.rx.recv()
        except (EOFError, OSError):
            os._exit(3)
        if request[0] != "ops":  # ("abort",): an input callback of the parent failed
            self.stop_requested = True
            agent.StopSelf()
            return
        error = self.apply(request[1])
        agent.Commit()
        if error is not None:  # no reply otherwise: the parent does not wait for one
            self.stop_requested = True
            agent.StopSelf()
            self.send(("input-error", error))

    def after_input(self, _event: int, _data: object, agent: Any, _phase: object) -> None:
        if not self.unnamed:
            return
        names = {n: agent.ConvertIdentifier(client) for n, client in self.unnamed.items()}
        self.unnamed = {}
        for n, kernel_name in names.items():
            self.ids[kernel_name] = self.ids.pop(n)
        if names:  # the parent names these identifiers by their kernel names from now on
            self.wmes = {(names.get(i, i), a, names.get(v, v) if is_id else v, is_id): w
                         for (i, a, v, is_id), w in self.wmes.items()}
        self.flush()
        self.send(("ids", names))

    def after_cycle(self, _event: int, _data: object, agent: Any, _phase: object) -> None:
        self.attach_errors()
        if self.want_output and agent.GetNumberOutputLinkChanges() > 0:
            agent.ClearOutputLinkChanges()
            self.send_output(agent)
        if self.stop_requested and self.running:
            agent.StopSelf()

    # -- the input-link --------------------------------------------------------------------

    def apply(self, ops: list[tuple[Any, ...]]) -> str | None:
        """Carry out the parent's input operations in order; the first failure is returned."""
        agent = self.agent
        for op in ops:
            kind, ident, attr = op[0], op[1], op[2]
            parent = self.ids.get(ident)
            if parent is None:
                return f"identifier {ident} is not on the input-link (or was removed from it)"
            if kind == "add":
                value, vtype = op[3], op[4]
                key = (ident, attr, value, vtype in ("new", "id"))
                if key in self.wmes:
                    continue
                if vtype == "new":
                    wme = agent.CreateIdWME(parent, attr)  # an Identifier: the WME and its value
                    self.ids[value] = wme
                    self.unnamed[value] = wme.GetValueAsString()
                elif vtype == "id":
                    target = self.ids.get(value)
                    if target is None:
                        return f"identifier {value} is not on the input-link (or was removed from it)"
                    wme = agent.CreateSharedIdWME(parent, attr, target)
                elif vtype == "int":
                    wme = agent.CreateIntWME(parent, attr, value)
                elif vtype == "float":
                    wme = agent.CreateFloatWME(parent, attr, value)
                else:
                    wme = agent.CreateStringWME(parent, attr, value)
                if wme is None:
                    return f"SML refused to add ({ident} ^{attr} {value})"
                self.wmes[key] = wme
            else:  # remove
                is_id = op[4] in ("new", "id")
                wme = self.wmes.pop((ident, attr, op[3], is_id), None)
                if wme is not None:
                    agent.DestroyWME(wme)
                    if is_id:
                        self.forget(op[3])
        return None

    def forget(self, ident: Any) -> None:
        """After an identifier's last link is removed: drop its WMEs (SML deleted them)."""
        if any(k[3] and k[2] == ident for k in self.wmes):
            return  # still linked elsewhere
        stack = [ident]
        while stack:
            current = stack.pop()
            for key in [k for k in self.wmes if k[0] == current]:
                del self.wmes[key]
                if key[3] and not any(k[3] and k[2] == key[2] for k in self.wmes):
                    stack.append(key[2])
            self.ids.pop(current, None)

    # -- the output-link ---------------------------------------------------------------

    def send_output(self, agent: Any) -> None:
        """Send every WME under the output-link: ``(timetag, id, attr, value, type)``."""
        link = agent.GetOutputLink()
        if link is None:
            return
        out: list[tuple[Any, ...]] = []
        seen = {link.GetValueAsString()}
        self.ids[link.GetValueAsString()] = link
        stack = [link]
        while stack:
            ident = stack.pop()
            for i in range(ident.GetNumberChildren()):
                w = ident.GetChild(i)
                vtype = w.GetValueType()
                value = w.GetValueAsString()
                out.append((w.GetTimeTag(), w.GetIdentifierName(), w.GetAttribute(), value, vtype))
                if w.IsIdentifier() and value not in seen:
                    seen.add(value)
                    child = w.ConvertToIdentifier()
                    self.ids.setdefault(value, child)
                    stack.append(child)
        self.flush()
        self.send(("output", agent.GetDecisionCycleCounter(), out))

    # -- requests ------------------------------------------------------------------------

    def command(self, line: str) -> tuple[bool, str]:
        text = self.agent.ExecuteCommandLine(line)
        return bool(self.agent.GetLastCommandLineResult()), text

    def state_xml(self) -> str:
        """The WMEs that exist (the top state's structure) as the kernel's XML: ``<wme>``
        elements of ``print --internal``, read without running ``init-soar`` (which would
        change what the kernel names its chunks)."""
        response = self.sml.ClientAnalyzedXML()
        self.agent.ExecuteCommandLineXML("print --internal --depth 1000 S1", response)
        return str(response.GenerateXMLString(True))

    def productions(self) -> list[str]:
        _ok, text = self.command("print --all")
        return [line.split()[0] for line in text.splitlines() if line.strip()]

    def serve(self) -> None:
        while True:
            try:
                request = self.rx.recv()
            except (EOFError, OSError):
                return
            kind = request[0]
            if kind == "quit":
                return
            if kind == "config":
                for line in request[1]:
                    self.command(line)
                link = self.agent.GetInputLink()
                self.ids = {link.GetValueAsString(): link}
                info = {"kernel": self.kernel.GetSoarKernelVersion(), "pid": os.getpid()}
                self.xml = []
                self.send(("ready", info, self.state_xml()))
            elif kind == "source":
                before = set(self.productions())
                ok, text = self.command(request[1])
                for line in request[2]:
                    self.command(line)
                added = [p for p in reversed(self.productions()) if p not in before]
                xml, self.xml = self.xml, []
                self.send(("sourced", ok, text, added, xml))
            elif kind == "command":
                ok, text = self.command(request[1])
                self.send(("result", ok, text))
            elif kind == "run":
                self.run(request[1], request[2], request[3], request[4])
            else:
                self.send(("error", f"unknown request {kind!r}"))

    def need(self, what: str, wanted: bool) -> None:
        """Register the callbacks of ``what`` (``input``, ``output``, ``cycle``) when a run
        needs them, unregister them when it does not."""
        sml, agent = self.sml, self.agent
        if wanted == (what in self.registered):
            return
        if not wanted:
            for ident in self.registered.pop(what):
                agent.UnregisterForRunEvent(ident)
            if what == "output":
                agent.SetOutputLinkChangeTracking(False)
            return
        if what == "input":
            self.registered[what] = [
                agent.RegisterForRunEvent(sml.smlEVENT_BEFORE_INPUT_PHASE, self.on_input, None),
                agent.RegisterForRunEvent(sml.smlEVENT_AFTER_INPUT_PHASE, self.after_input, None)]
        else:  # output, and the end of each cycle (printed errors after the cycle's XML)
            self.registered[what] = [
                agent.RegisterForRunEvent(sml.smlEVENT_AFTER_DECISION_CYCLE, self.after_cycle, None)]
            if what == "output":
                agent.SetOutputLinkChangeTracking(True)

    def run(self, n: int | None, want_input: bool, want_output: bool, tracing: bool) -> None:
        agent = self.agent
        self.want_input, self.want_output = want_input, want_output
        self.need("input", want_input)
        self.need("output", want_output)
        self.need("cycle", tracing and not want_output)
        self.stop_requested = False
        self.running = True
        before = agent.GetDecisionCycleCounter()
        started = time.perf_counter()
        try:
            if n is None:
                agent.RunSelfForever()
            else:
                agent.RunSelf(n)
        finally:
            self.running = False
        seconds = time.perf_counter() - started
        self.attach_errors()
        if want_output and agent.GetNumberOutputLinkChanges() > 0:
            agent.ClearOutputLinkChanges()
            self.send_output(agent)
        self.flush()
        decisions = agent.GetDecisionCycleCounter()
        info = {"decisions": decisions, "ran": decisions - before,
                "halted": agent.GetRunState() == self.sml.sml_RUNSTATE_HALTED,
                "stopped": self.stop_requested, "seconds": seconds}
        info.update(_stats(self.command("stats")[1]))
        self.send(("done", info))


def _die_with_parent() -> None:
    """On Linux, have the kernel's process killed when adapt's process ends."""
    try:
        import ctypes

        libc = ctypes.CDLL(None)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def main(argv: list[str]) -> int:
    """``python -I worker.py FD_IN FD_OUT``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        _die_with_parent()
    rx = Connection(int(argv[1]), writable=False)
    tx = Connection(int(argv[2]), readable=False)
    try:
        worker = Worker(rx, tx)
    except Exception as exc:  # noqa: BLE001 - reported to the parent, which words the error
        tx.send(("failed", f"{type(exc).__name__}: {exc}"))
        return 1
    worker.serve()
    return 0


if __name__ == "__main__":
    code = main(sys.argv)
    sys.stdout.flush()
    os._exit(code)  # the native kernel sometimes misbehaves at interpreter exit
