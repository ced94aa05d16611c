"""``report.json``, written as the run goes.

The report of a run of hours cannot wait in memory: :class:`ReportWriter`
streams each frame's record into a temporary file beside ``report.json`` and,
when the run ends (normally, interrupted, or failed), closes the ``frames``
list, adds the ``summary`` and renames the file into place.  So the report is
always complete, valid JSON, and the previous ``report.json`` (if any)
survives until the new one is whole.

The keys are a contract (``docs/runner.md``): ``scenario``, ``seed``, ``fps``,
``frames`` (each with ``index``, ``t``, ``schemas``, ``unexpected_regions``,
``objects`` -> ``observed``/``imagined``, ``predictions``; and ``truth``,
``camera_pose_error``, ``errors`` when the reality has ground truth), and
``summary``.

Examples
--------
>>> import json, tempfile, pathlib
>>> out = pathlib.Path(tempfile.mkdtemp()) / "report.json"
>>> w = ReportWriter(out, {"scenario": "s.yaml", "seed": 1, "fps": 30.0})
>>> w.frame({"index": 0, "t": 0.0})
>>> _ = w.close({"frames": 1, "interrupted": False})
>>> data = json.loads(out.read_text())
>>> data["frames"][0]["index"], data["summary"]["frames"]
(0, 1)
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

from adapt.files import temporary_file

__all__ = ["ReportWriter", "REPORT_KEYS", "FRAME_KEYS", "to_json"]

#: Top-level keys of ``report.json``, in order.
REPORT_KEYS = ("scenario", "seed", "fps", "frames", "summary")
#: Keys every frame record has.
FRAME_KEYS = ("index", "t", "schemas", "unexpected_regions", "objects", "predictions")


def to_json(value: Any) -> Any:
    """``value`` with non-finite floats as ``null`` (JSON has no NaN)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: to_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json(v) for v in value]
    return value


class ReportWriter:
    """Streams a report (see the module docstring)."""

    def __init__(self, path: str | os.PathLike[str], head: dict[str, Any]) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._tmp = temporary_file(self.path)
        self._out = open(self._tmp, "w", encoding="utf-8")  # noqa: SIM115 (closed by close())
        text = json.dumps(to_json(head))
        self._out.write(text[:-1] + (', ' if head else '') + '"frames": [')
        self._first = True
        self.frames = 0
        self.closed = False

    def frame(self, record: dict[str, Any]) -> None:
        """Append one frame's record."""
        self._out.write(("\n  " if self._first else ",\n  ")
                        + json.dumps(to_json(record), separators=(",", ":")))
        self._first = False
        self.frames += 1

    def close(self, summary: dict[str, Any]) -> Path:
        """Finish the file with ``summary`` and move it into place."""
        if self.closed:
            return self.path
        self.closed = True
        self._out.write('\n],\n"summary": ' + json.dumps(to_json(summary), indent=1) + "}\n")
        self._out.close()
        os.replace(self._tmp, self.path)
        return self.path

    def discard(self) -> None:
        """Drop the partial report (the previous file stays)."""
        if not self.closed:
            self.closed = True
            self._out.close()
            self._tmp.unlink(missing_ok=True)
