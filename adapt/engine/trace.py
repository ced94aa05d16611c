"""The trace writer: JSON Lines records of ``docs/trace-format.md``.

A :class:`TraceWriter` is attached to an agent (``Agent(trace=...)``); the
agent tells it when phases begin and end, what fired, retracted and changed
in working memory, and what each decision did.  It writes one ``header``,
one ``phase`` record per phase (trace level >= 2), one ``decision`` record
per decision phase, and a ``footer``; the file is flushed after every
decision, so an interrupted run loses nothing already written.

When an agent has no trace the kernel's hooks are not installed at all, so
tracing costs nothing.

Examples
--------
>>> import io, json
>>> buf = io.StringIO()
>>> tw = TraceWriter(buf, level=2, files=["a.soar"], seed=1)
>>> tw.begin_phase(0, "proposal"); tw.write_text("hi"); tw.end_phase()
>>> tw.footer({"halted": True, "stop_reason": "halt", "decisions": 0,
...            "production_firings": 1, "wm_size_final": 5}, 0.001)
>>> [json.loads(line)["kind"] for line in buf.getvalue().splitlines()]
['header', 'phase', 'footer']
>>> json.loads(buf.getvalue().splitlines()[1])["writes"]
'hi'
"""

from __future__ import annotations

import datetime
import json
import os
from typing import IO, Any, Iterable, Mapping

from adapt.engine.symbols import Float, Identifier, Symbol
from adapt.engine.wme import WME

__all__ = ["TraceWriter", "symbol_json", "FORMAT", "VERSION"]

FORMAT = "adapt-trace"
VERSION = 1

#: Record kinds the writer produces itself (see :meth:`TraceWriter.event`).
_OWN_KINDS = frozenset({"header", "phase", "decision", "footer"})


def symbol_json(value: Symbol | None) -> Any:
    """A symbol as the trace writes it (identifiers as ``{"id": "S1"}``).

    Examples
    --------
    >>> symbol_json(Identifier("S", 1)), symbol_json(Float(3.0)), symbol_json(3)
    ({'id': 'S1'}, 3.0, 3)
    """
    if type(value) is Identifier:
        return {"id": value.name}
    if type(value) is Float:
        return float(value)
    return value


def _wme_json(w: WME) -> list[Any]:
    return [w.timetag, symbol_json(w.id), symbol_json(w.attr), symbol_json(w.value),
            w.acceptable]


class TraceWriter:
    """Writes trace records to a text stream (or a path, opened for writing).

    Parameters
    ----------
    sink : str, path-like or text stream
    level : int
        1..5, see ``docs/trace-format.md``.
    files : list of str
        The rule files of the run (for the header).
    seed : int
    header : mapping, optional
        More header fields (the Soar engine's ``engine`` and ``absent``).
    """

    def __init__(self, sink: Any, *, level: int = 5, files: Iterable[str] = (),
                 seed: int | None = 1, version: str = "0.1.0",
                 header: Mapping[str, Any] | None = None) -> None:
        if not 1 <= level <= 5:
            raise ValueError(f"trace level must be 1..5, not {level}")
        if isinstance(sink, (str, os.PathLike)):
            self._out: IO[str] = open(sink, "w", encoding="utf-8")  # noqa: SIM115 (closed by close())
            self._owned = True
        else:
            self._out = sink
            self._owned = False
        self.level = level
        self._phase: dict[str, Any] | None = None
        self._carry: list[WME] = []
        self.closed = False
        created = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        record = {"kind": "header", "format": FORMAT, "version": VERSION, "adapt": version,
                  "files": list(files), "seed": seed, "level": level, "created": created}
        for key, value in (header or {}).items():
            record.setdefault(key, value)
        self._record(record)
        self._out.flush()

    def _record(self, record: dict[str, Any]) -> None:
        self._out.write(json.dumps(record, separators=(",", ":")) + "\n")

    # -- phases ---------------------------------------------------------------
    def begin_phase(self, d: int, phase: str) -> None:
        """A phase starts (``d`` = decisions started so far)."""
        if self.level < 2:  # level 1 writes no phase records
            self._phase = None
            return
        rec: dict[str, Any] = {"kind": "phase", "d": d, "phase": phase}
        if self.level >= 4:
            rec["adds"] = [_wme_json(w) for w in self._carry]
            rec["removes"] = []
        self._carry = []
        if self.level >= 3:
            rec["firings"] = []
            rec["retractions"] = []
        rec["writes"] = ""
        rec["messages"] = []
        self._phase = rec

    def end_phase(self) -> None:
        """The phase ended: write its record (level >= 2)."""
        rec = self._phase
        self._phase = None
        if rec is None or self.level < 2:
            return
        if not rec["writes"]:
            del rec["writes"]
        self._record(rec)

    def existing_wmes(self, wmes: Iterable[WME]) -> None:
        """WMEs already in working memory when the trace starts: written as
        adds of the first phase record, so working memory can be rebuilt."""
        self._carry = sorted(wmes, key=lambda w: w.timetag)

    def write_text(self, text: str) -> None:
        """Text written by ``(write ...)`` in the current phase."""
        if self._phase is not None:
            self._phase["writes"] += text

    def message(self, text: str) -> None:
        """A kernel message in the current phase."""
        if self._phase is not None:
            self._phase["messages"].append(text)

    def wm_changes(self, added: list[WME], removed: list[WME]) -> None:
        """WMEs added and removed (level >= 4)."""
        rec = self._phase
        if rec is None or self.level < 4:
            return
        rec["adds"].extend(_wme_json(w) for w in added)
        rec["removes"].extend(w.timetag for w in removed)

    def firing(self, rule: str, level: int, support: str | None,
               bindings: dict[Any, Symbol] | None, wmes: Iterable[WME]) -> None:
        """A production fired (level >= 3); a ``support`` or ``bindings`` of
        None (not known: the Soar kernel does not report bindings) is left out."""
        rec = self._phase
        if rec is None or self.level < 3:
            return
        firing: dict[str, Any] = {"rule": rule, "level": level}
        if support is not None:
            firing["support"] = support
        if bindings is not None:
            firing["bindings"] = {str(k): symbol_json(v) for k, v in bindings.items()}
        firing["wmes"] = [w.timetag for w in wmes]
        rec["firings"].append(firing)

    def retraction(self, rule: str, level: int, wmes: Iterable[WME]) -> None:
        """An instantiation was retracted (level >= 3)."""
        rec = self._phase
        if rec is None or self.level < 3:
            return
        rec["retractions"].append({"rule": rule, "level": level,
                                   "wmes": [w.timetag for w in wmes]})

    # -- decisions --------------------------------------------------------------
    def decision(self, record: dict[str, Any]) -> None:
        """A decision record (written after its phase record), then flush."""
        if self.level < 5:
            record.pop("candidates", None)
        pending = self._phase
        if pending is not None:
            self.end_phase()
        self._record({"kind": "decision", **record})
        self._out.flush()

    def event(self, kind: str, data: dict[str, Any]) -> None:
        """A record of another layer (``"schema"``, ``"frame"``, ...), written at once.

        The trace format's own kinds cannot be written this way; readers skip
        kinds they do not know.

        Examples
        --------
        >>> import io, json
        >>> buf = io.StringIO()
        >>> tw = TraceWriter(buf, level=1)
        >>> tw.event("schema", {"d": 3, "event": "instantiated", "schema": "ball"})
        >>> json.loads(buf.getvalue().splitlines()[-1])["event"]
        'instantiated'
        """
        if kind in _OWN_KINDS:
            raise ValueError(f"{kind!r} records are written by the trace writer itself")
        self._record({"kind": kind, **data})

    def flush(self) -> None:
        """Flush the stream."""
        self._out.flush()

    def footer(self, report: dict[str, Any], elapsed_s: float,
               error: str | None = None) -> None:
        """The last record; ``error`` names a Python exception that ended the run."""
        if self._phase is not None:
            self.end_phase()
        rec = {"kind": "footer", "halted": report["halted"],
               "stop_reason": report["stop_reason"], "decisions": report["decisions"],
               "production_firings": report["production_firings"],
               "wm_size_final": report["wm_size_final"], "elapsed_s": round(elapsed_s, 6)}
        if error is not None:
            rec["error"] = error
        self._record(rec)
        self._out.flush()

    def close(self) -> None:
        """Close the stream if this writer opened it."""
        if self.closed:
            return
        self.closed = True
        if self._owned:
            self._out.close()
        else:
            self._out.flush()
