"""``runs.jsonl``: the sweep's record of finished runs, one JSON object a line.

It is the one thing a sweep must not lose, so it is only ever appended to:
each record is written as one line and flushed as soon as its run is back,
and the file is opened once per sweep with its folder locked
(:func:`adapt.files.lock_folder`: ``.adapt.lock`` beside it, the lock a run
takes too), so two sweeps -- or a sweep and a run -- cannot write into one
folder at once.  A last line cut short (the machine died while writing it) is dropped
when the file is opened again; any other line that is not a run record is
an error naming its line, never silently skipped.

The latest record of a key is the one that counts (a failed run retried with
``--retry-failed`` gets a second record).

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> with RunLog(d / "runs.jsonl") as log:
...     log.append({"key": "seed1-a", "status": "ok"})
>>> with d.joinpath("runs.jsonl").open("a") as f:
...     _ = f.write('{"key": "seed2-a", "sta')       # a line cut short
>>> with RunLog(d / "runs.jsonl") as log:
...     [r["key"] for r in log.records], log.dropped
(['seed1-a'], 1)
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import IO, Any

from adapt.errors import SweepError
from adapt.files import FolderLock, lock_folder

__all__ = ["RunLog", "latest"]


class RunLog:
    """The append-only record file (see the module docstring); a context manager.

    Attributes
    ----------
    records : list of dict
        Every record read when it was opened, then every record appended.
    dropped : int
        1 when a last line cut short was dropped on opening, else 0.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.records: list[dict[str, Any]] = []
        self.dropped = 0
        self._file: IO[str] | None = None
        self._lock: FolderLock | None = None

    def __enter__(self) -> "RunLog":
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def open(self) -> None:
        """Lock the folder, read the records, drop a cut-short last line, open for appending."""
        self._lock = lock_folder(self.path.parent, "--out", ("figures",))
        try:
            cut, newline = self._read()
            self._file = open(self.path, "a+", encoding="utf-8")
            if cut is not None:
                self._file.truncate(cut)
                self._file.seek(0, os.SEEK_END)
            if newline:
                self._file.write("\n")
                self._file.flush()
        except BaseException:
            self.close()
            raise

    def _read(self) -> tuple[int | None, bool]:
        """Read the records; return the length to cut the file to (or None) and whether
        the last record lacks its newline."""
        if not self.path.exists():
            return None, False
        data = self.path.read_bytes()
        pos = 0
        for number, raw in enumerate(data.split(b"\n"), start=1):
            end = pos + len(raw)
            last = end >= len(data)
            if raw.strip():
                try:
                    record = json.loads(raw)
                    if not isinstance(record, dict) or not isinstance(record.get("key"), str):
                        raise ValueError("not a run record")
                except ValueError as exc:
                    if last:  # cut short while it was being written
                        self.dropped = 1
                        return pos, False
                    raise SweepError(f"{self.path}:{number}: not a run record ({exc}); "
                                     "remove or repair that line to go on") from None
                self.records.append(record)
                if last:  # a complete record without its newline
                    return None, True
            pos = end + 1
        return None, False

    def append(self, record: dict[str, Any]) -> None:
        """Write ``record`` as one line and flush it to the operating system."""
        if self._file is None:
            raise SweepError(f"{self.path} is not open")
        record = _finite(record)
        self._file.write(json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n")
        self._file.flush()
        self.records.append(record)

    def close(self) -> None:
        """Close the file (everything is on disk already) and release the lock."""
        if self._file is not None:
            self._file.close()
            self._file = None
        if self._lock is not None:
            self._lock.release()
            self._lock = None


def latest(records: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """The latest record of every key.

    >>> latest([{"key": "a", "status": "failed"}, {"key": "a", "status": "ok"}])["a"]["status"]
    'ok'
    """
    out: dict[str, dict[str, Any]] = {}
    for r in records:
        out[r["key"]] = r
    return out


def _finite(value: Any) -> Any:
    """``value`` with every NaN or infinity replaced by None (JSON has neither)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value

