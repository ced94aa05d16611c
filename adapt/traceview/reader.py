"""Streaming reader of adapt traces (``docs/trace-format.md``).

A :class:`Trace` reads and checks the header when it is opened, then yields
the records after it one at a time, so a trace of any length is read in
constant memory: no line is read past :data:`MAX_LINE` bytes.  A truncated
last line (a run that was killed mid-write) is skipped with a
:class:`TraceWarning` that says so; a file that is not a trace (a device or a
pipe, a line longer than :data:`MAX_LINE`, two traces one after the other),
or a trace of another format version, raises :class:`adapt.errors.TraceError`.

Records are grouped into *decision cycles* the way Soar counts them: cycle
``D`` is the input and proposal phases whose ``d`` is ``D - 1``, then decision
phase ``D`` (its ``phase`` and ``decision`` records) and the apply and output
phases after it.  :func:`cycle_of` gives a record's cycle.

Examples
--------
>>> import json, os, tempfile
>>> path = os.path.join(tempfile.mkdtemp(), "t.jsonl")
>>> lines = [{"kind": "header", "format": "adapt-trace", "version": 1, "files": [],
...           "level": 1},
...          {"kind": "decision", "d": 1, "level": 0, "selected": None, "impasse": None}]
>>> with open(path, "w") as f:
...     _ = f.write("".join(json.dumps(r) + "\\n" for r in lines) + '{"kind": "foot')
>>> trace = Trace(path)
>>> trace.header.level, trace.header.version
(1, 1)
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     [r["kind"] for r in trace.records()]
['decision']
>>> print(caught[0].message)  # doctest: +ELLIPSIS
/...t.jsonl:3: the last line is truncated (an interrupted run?); read the 1 complete records before it
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from adapt.errors import TraceError
from adapt.files import is_special
from adapt.traceview.records import RecordError, check_header, check_record

__all__ = [
    "FORMAT",
    "VERSION",
    "TraceWarning",
    "TraceHeader",
    "Trace",
    "cycle_of",
    "load_line",
    "LineError",
    "PRE_DECISION_PHASES",
    "MAX_LINE",
]

#: The ``format`` value of every adapt trace header.
FORMAT = "adapt-trace"
#: The format version this reader understands.
VERSION = 1
#: Phases that run before the decision phase of their cycle (their ``d`` is one less).
PRE_DECISION_PHASES = frozenset({"input", "proposal"})
#: The longest line (one record) read, in bytes: 32 MiB.  A longer one is refused after
#: reading that much, never held whole.
MAX_LINE = 32 * 1024 * 1024

Record = dict[str, Any]


class TraceWarning(UserWarning):
    """A trace was read, but not all of it (a truncated last line)."""


@dataclass(frozen=True)
class TraceHeader:
    """The first record of a trace.

    Attributes
    ----------
    version : int
        The format version (always :data:`VERSION` once read).
    level : int
        The trace level 1..5 the run was written at.
    files : tuple of str
        The rule files the agent loaded, as the run named them.
    seed : int or None
        The run's random seed.
    adapt : str
        The adapt version that wrote the trace.
    created : str
        When the run started (ISO 8601), or ``""``.
    raw : dict
        The whole record, for fields added by later writers.
    """

    version: int
    level: int
    files: tuple[str, ...]
    seed: int | None = None
    adapt: str = ""
    created: str = ""
    raw: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)


class LineError(ValueError):
    """A line that is not one JSON value this reader accepts."""


def _constant(name: str) -> Any:
    raise LineError(f"{name} is not a JSON number")


def _finite(text: str) -> float:
    value = float(text)
    if value in (float("inf"), float("-inf")):
        raise LineError(f"{text} is too large for a number")
    return value


_DECODER = json.JSONDecoder(parse_constant=_constant, parse_float=_finite)


def load_line(line: bytes, *, paths: str | None = None) -> Any:
    r"""One JSON value of a trace line, strictly.

    Raises :class:`LineError` (a :class:`ValueError`) for a line that is not
    UTF-8 JSON, that holds ``NaN``, ``Infinity`` or a number too large for a
    float, that nests too deeply, or whose strings hold a lone surrogate
    (``"\ud800"``: not text, and not writable as UTF-8).  The one exception
    is the list of file names under the key ``paths`` (the header's
    ``"files"``): Python writes a file name's bytes that are not UTF-8 as the
    surrogates U+DC80..U+DCFF, and those are kept.

    >>> load_line(b'{"kind": "x", "v": 1.5}')
    {'kind': 'x', 'v': 1.5}
    >>> load_line(b'{"kind": "x", "v": "\\ud800"}')
    Traceback (most recent call last):
    ...
    adapt.traceview.reader.LineError: a string holds a lone surrogate, \ud800, which is not text
    >>> load_line(b'{"files": ["\\udcff.soar"]}', paths="files")
    {'files': ['\udcff.soar']}
    """
    try:
        value = _DECODER.decode(line.decode("utf-8"))
    except RecursionError:
        raise LineError("the JSON nests too deeply") from None
    except UnicodeDecodeError:
        raise LineError("the line is not UTF-8") from None
    if b"\\u" in line and (b"\\ud" in line or b"\\uD" in line):
        checked = value
        if paths is not None and isinstance(value, dict) and isinstance(value.get(paths), list):
            names = value[paths]
            checked = {k: v for k, v in value.items() if k != paths}
            for name in names:
                if isinstance(name, str):
                    try:
                        name.encode("utf-8", "surrogateescape")
                    except UnicodeEncodeError:
                        _lone_surrogate(name)
        try:
            json.dumps(checked, ensure_ascii=False).encode("utf-8")
        except UnicodeEncodeError as exc:
            _lone_surrogate(exc.object[exc.start:exc.end])
    return value


def _lone_surrogate(text: str) -> None:
    for char in text:
        if 0xD800 <= ord(char) <= 0xDFFF:
            code = char.encode("unicode_escape", "backslashreplace").decode("ascii")
            raise LineError(f"a string holds a lone surrogate, {code}, which is not text")
    raise LineError("a string holds a lone surrogate, which is not text")


def cycle_of(record: Record) -> int | None:
    """The decision cycle a record belongs to (``None`` for header and footer).

    >>> cycle_of({"kind": "phase", "d": 4, "phase": "proposal"})
    5
    >>> cycle_of({"kind": "phase", "d": 5, "phase": "apply"}), cycle_of({"kind": "decision", "d": 5})
    (5, 5)
    """
    d = record.get("d")
    if not isinstance(d, int):
        return None
    if record.get("kind") == "phase" and record.get("phase") in PRE_DECISION_PHASES:
        return d + 1
    return d


def _parse_header(path: str, line: bytes) -> TraceHeader:
    try:
        record = load_line(line, paths="files")
    except ValueError:
        record = None
    if not isinstance(record, dict) or record.get("kind") != "header" or (
        record.get("format") != FORMAT
    ):
        raise TraceError(
            f"{path}: not an adapt trace (the first line is not a header record with "
            f'"format": "{FORMAT}"; traces are written by `adapt rules run --trace`)'
        )
    version = record.get("version")
    if version != VERSION:
        raise TraceError(
            f"{path}: trace format version {version!r}; this adapt reads version {VERSION}"
        )
    level = record.get("level", 5)
    if not isinstance(level, int) or not 1 <= level <= 5:
        raise TraceError(f"{path}: header has trace level {level!r}; expected 1..5")
    files = record.get("files") or []
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        raise TraceError(f"{path}: header field \"files\" is not a list of paths")
    try:
        check_header(record)
    except RecordError as exc:
        raise TraceError(f"{path}:1: header: {exc}") from None
    seed = record.get("seed")
    return TraceHeader(
        version=version,
        level=level,
        files=tuple(files),
        seed=seed if isinstance(seed, int) else None,
        adapt=str(record.get("adapt", "")),
        created=str(record.get("created", "")),
        raw=record,
    )


class Trace:
    """A trace file, opened for streaming.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.jsonl`` trace.

    Raises
    ------
    adapt.errors.TraceError
        If the file is missing, empty, not a trace, or of another format version.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = os.fspath(path)
        if is_special(self.path):
            raise TraceError(f"{self.path}: not a regular file (a device, a pipe or a socket); "
                             "expected a trace file")
        try:
            with open(self.path, "rb") as f:
                first = self._line(f, 1)
        except FileNotFoundError:
            raise TraceError(f"{self.path}: no such trace file") from None
        except IsADirectoryError:
            raise TraceError(f"{self.path}: is a directory, not a trace file") from None
        except OSError as exc:
            raise TraceError(f"{self.path}: cannot read: {exc.strerror}") from None
        if not first.strip():
            raise TraceError(f"{self.path}: empty file, not an adapt trace")
        self.header = _parse_header(self.path, first)
        #: Messages about incomplete reading, once a pass has found them.
        self.notices: list[str] = []

    def _line(self, f: Any, lineno: int) -> bytes:
        """The next line of ``f``, at most :data:`MAX_LINE` bytes of it (``b""`` at the end)."""
        line: bytes = f.readline(MAX_LINE + 1)
        if len(line) > MAX_LINE and not line.endswith(b"\n"):
            raise TraceError(f"{self.path}:{lineno}: the line is longer than "
                             f"{MAX_LINE // (1024 * 1024)} MiB; not a trace record (a trace's "
                             "lines are records of a few kilobytes)")
        return line

    def _notice(self, message: str) -> None:
        if message not in self.notices:
            self.notices.append(message)
            warnings.warn(message, TraceWarning, stacklevel=3)

    def records(self) -> Iterator[Record]:
        """Every record after the header, in file order (the footer included).

        Each call reads the file again from the start.  A truncated last line
        ends the iteration with a :class:`TraceWarning`; any other line that is
        not a JSON object with a ``"kind"``, or a record that breaks the trace
        schema (:mod:`adapt.traceview.records`), raises :class:`TraceError`
        naming the line and the field.
        """
        with open(self.path, "rb") as f:
            self._line(f, 1)
            lineno = 1
            while line := self._line(f, lineno + 1):
                lineno += 1
                try:
                    record = load_line(line)
                except ValueError as exc:
                    if not line.endswith(b"\n"):
                        self._notice(
                            f"{self.path}:{lineno}: the last line is truncated (an interrupted "
                            f"run?); read the {lineno - 2} complete records before it"
                        )
                        return
                    if not line.strip():
                        continue
                    why = f" ({exc})" if isinstance(exc, LineError) else ""
                    raise TraceError(f"{self.path}:{lineno}: not a JSON record{why}") from None
                if not isinstance(record, dict) or not isinstance(record.get("kind"), str):
                    raise TraceError(f"{self.path}:{lineno}: not a trace record (no \"kind\")")
                if record["kind"] == "header":
                    raise TraceError(f"{self.path}:{lineno}: a second header record: this file "
                                     "holds two traces one after the other (joined with cat?); "
                                     "expected one trace per file")
                try:
                    check_record(record)
                except RecordError as exc:
                    raise TraceError(f"{self.path}:{lineno}: {record['kind']} record: {exc}") from None
                yield record

    def cycles(
        self, first: int | None = None, last: int | None = None
    ) -> Iterator[tuple[int, list[Record]]]:
        """The records of each decision cycle, ``(D, records)``, from ``first`` to ``last``.

        Stops reading once past ``last``.  Records without a cycle (the
        footer) are not yielded.
        """
        current: int | None = None
        group: list[Record] = []
        for record in self.records():
            cycle = cycle_of(record)
            if cycle is None:
                continue
            if cycle != current:
                if current is not None and group:
                    yield current, group
                group = []
                current = cycle
                if last is not None and cycle > last:
                    return
            if first is None or cycle >= first:
                group.append(record)
        if current is not None and group:
            yield current, group

    def footer(self) -> Record | None:
        """The footer record, or ``None`` (a run that did not end normally).

        Reads only the end of the file.
        """
        with open(self.path, "rb") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - 65536))
            tail = f.read(65536).splitlines()
        for line in reversed(tail):
            try:
                record = load_line(line)
            except ValueError:
                continue
            if isinstance(record, dict) and record.get("kind") == "footer":
                try:
                    check_record(record)
                except RecordError as exc:
                    raise TraceError(f"{self.path}: the footer record: {exc}") from None
                return record
            if isinstance(record, dict):
                return None
        return None

    def initial_wmes(self) -> list[list[Any]]:
        """The WMEs that existed before the first phase (header ``"wmes"``, optional)."""
        wmes = self.header.raw.get("wmes") or []
        return [list(w) for w in wmes if isinstance(w, list) and len(w) == 5]

    def require_level(self, level: int, what: str) -> None:
        """Raise :class:`TraceError` unless the trace was written at ``level`` or more."""
        if self.header.level < level:
            raise TraceError(
                f"{self.path}: {what} needs a trace written at level {level} or more; "
                f"this one is level {self.header.level} (run with --trace-level {level})"
            )
