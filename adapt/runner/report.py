"""``report.json``, written as the run goes: the JSON edge of the frame records.

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
``summary``.  :func:`frame_json` turns a typed frame record (and its score
against the truth) into a frame of the report; :class:`ReportOutput` is the
listener that streams them.  Typed values become JSON here and nowhere
earlier.

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
from typing import TYPE_CHECKING, Any, Sequence

from adapt.files import temporary_file
from adapt.runner.baseline import report_key
from adapt.runner.evaluation import reported

if TYPE_CHECKING:  # pragma: no cover
    from adapt.runner.evaluation import Evaluation, FrameScore
    from adapt.runner.record import FrameRecord
    from adapt.schemas.percepts import BackgroundPercept

__all__ = ["ReportWriter", "ReportOutput", "frame_json", "objects_json", "mmd_json", "REPORT_KEYS",
           "FRAME_KEYS", "to_json"]

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


def _xy(p: Sequence[float] | None) -> list[float] | None:
    q = reported(p)
    return None if q is None else [q[0], q[1]]


def mmd_json(bg: "BackgroundPercept") -> dict[str, Any]:
    """A frame's ``mmd``: the Scene Background's alignment and its cost."""
    return {"aligned": bg.aligned, "trusted": bg.trusted,
            "pixel_error": None if math.isnan(bg.pixel_error) else round(bg.pixel_error, 4),
            "inliers": 0 if bg.mmd is None else bg.mmd.n_inliers,
            "regions": len(bg.regions), "ms": round(bg.ms, 2)}


def objects_json(record: "FrameRecord") -> dict[str, dict[str, list[float] | None]]:
    """The frame's ``objects``: each object's observed and imagined floor position."""
    return {t.name: {"observed": _xy(t.observed), "imagined": _xy(t.imagined)}
            for t in record.tracked}


def frame_json(record: "FrameRecord", score: "FrameScore | None" = None,
               target: str | None = None) -> dict[str, Any]:
    """One frame of ``report.json`` (``docs/runner.md``): the record, and its score against
    the truth when there is one; ``target`` is the object the baselines' robots chase."""
    objects = objects_json(record)
    preds: dict[str, Any] = {}
    for t in record.tracked:
        p = record.percept_of(t.name)
        pred = None if p is None else p.prediction
        preds[t.name] = [] if pred is None else [h.as_json() for h in pred.horizons]
    out: dict[str, Any] = {
        "index": record.index, "t": round(record.time, 6), "schemas": list(record.schemas),
        "unexpected_regions": record.unexpected_regions, "objects": objects,
        "predictions": preds,
        "contacts": {p.object: p.prediction.contacts_json() for p in record.objects
                     if p.prediction is not None},
    }
    for name, state in record.baselines.items():
        out[report_key(name)] = {obj: [{"horizon": b.horizon, "position": _xy(b.position)}
                                       for b in found]
                                 for obj, found in state.predictions.items()}
    out["parameters"] = {p.object: {k: e.as_json() for k, e in p.estimates.items()}
                         for p in record.objects if p.estimates}
    if record.background is not None:
        out["mmd"] = mmd_json(record.background)
    if record.robot is not None:
        robot: dict[str, Any] = {"odometry": _xy(record.robot.position),
                                 "heading": round(record.robot.heading, 4)}
        for name, state in record.baselines.items():
            where = None if target is None else state.robots.get(target)
            if where is not None:
                robot[report_key(name)] = _xy(where)
        out["robot"] = robot
    out["uncorrected"] = {n: _xy(p) for n, p in record.uncorrected.items()}
    if score is not None:
        out.update(score.as_json())
    return out


class ReportOutput:
    """The report as a listener on the frame records (see the module docstring)."""

    def __init__(self, path: str | os.PathLike[str], head: dict[str, Any],
                 evaluation: "Evaluation", target: str | None) -> None:
        self.writer = ReportWriter(path, head)
        self.evaluation = evaluation
        self.target = target

    def frame(self, record: "FrameRecord") -> None:
        """Append the frame (with its score, which the evaluation made first)."""
        self.writer.frame(frame_json(record, self.evaluation.score(record.index), self.target))

    def close(self, summary: dict[str, Any]) -> Path:
        """Finish ``report.json`` with ``summary``."""
        return self.writer.close(summary)
