"""The run's records in ``trace.jsonl``, beside the engine's own.

:class:`TraceOutput` is a listener twice: on the schema network's events
(each written as a ``schema`` record the moment it happens, between the
engine's records of the decision it happened in) and on the frame records
(a ``frame`` record, a ``network`` record when the network changed, and an
``appearance`` record when the learned look changed; ``docs/runner.md``).
At the end it writes the ``summary`` record and the engine's footer, and
moves the file into place.

The learned look is written at its first learning, then when it has changed
and :data:`APPEARANCE_EVERY` frames have passed, the wait doubling after each
record up to :data:`APPEARANCE_EVERY_MAX` frames: a long run's trace holds a
few dozen of them (``docs/appearance.md``).
"""

from __future__ import annotations

import base64
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import cv2

from adapt.engine.trace import TraceWriter
from adapt.files import temporary_file
from adapt.runner.report import mmd_json, objects_json
from adapt.schemas import SchemaEvent

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.interface import RuleEngine
    from adapt.mirror import AppearanceModel
    from adapt.runner.record import FrameRecord
    from adapt.schemas.percepts import BackgroundPercept

__all__ = ["TraceOutput", "AppearanceTrace", "APPEARANCE_EVERY", "APPEARANCE_EVERY_MAX",
           "PREVIEW_SIDE"]

#: Frames between two records of the learned look, at first (then doubling).
APPEARANCE_EVERY = 30
#: The longest wait between two records of the learned look, frames.
APPEARANCE_EVERY_MAX = 1800
#: Largest side of a texture preview in the trace, pixels.
PREVIEW_SIDE = 160


class AppearanceTrace:
    """When to write the learned look, and its record (see the module docstring)."""

    def __init__(self, model: "AppearanceModel") -> None:
        self.model = model
        self._passes = 0
        self._frame = -APPEARANCE_EVERY
        self._wait = APPEARANCE_EVERY

    def record(self, percept: "BackgroundPercept") -> dict[str, Any] | None:
        """The look's record for this frame's percept, when it is due; else None."""
        model = self.model
        if percept.learn_passes == self._passes or not model.learned:
            return None
        if self._passes and percept.frame - self._frame < self._wait:
            return None
        if self._passes:
            self._wait = min(2 * self._wait, APPEARANCE_EVERY_MAX)
        self._passes = percept.learn_passes
        self._frame = percept.frame
        surfaces = []
        for name, t in model.textures().items():
            ok, png = cv2.imencode(".png", t.preview(PREVIEW_SIDE))
            surfaces.append({
                "name": name, "coverage": round(t.coverage, 4),
                "size": [int(t.mask.shape[1]), int(t.mask.shape[0])],
                "pixels_per_metre": round(t.pixels_per_metre[0], 1),
                "extent": [round(v, 4) for v in t.extent], "updates": t.updates,
                "image": ("data:image/png;base64," + base64.b64encode(png.tobytes()).decode("ascii"))
                if ok else None})
        return {"frame": percept.frame, "stage": percept.stage.value,
                "passes": percept.learn_passes, "ms": round(percept.learn_ms, 2),
                "surfaces": surfaces}


class TraceOutput:
    """``trace.jsonl`` (see the module docstring), written to a temporary file beside it
    until :meth:`close`."""

    def __init__(self, path: Path, *, level: int, files: list[str], seed: int,
                 appearance: "AppearanceModel", header: dict[str, Any] | None = None) -> None:
        self.path = path
        path.parent.mkdir(parents=True, exist_ok=True)
        self.tmp = temporary_file(path)
        #: The engine's trace writer (the agent writes its records through it); ``header``:
        #: the engine's own header fields (:meth:`RuleEngine.trace_header`).
        self.writer = TraceWriter(self.tmp, level=level, files=files, seed=seed, header=header)
        self.looks = AppearanceTrace(appearance)

    def event(self, event: SchemaEvent) -> None:
        """A schema event, as it happens."""
        self.writer.event("schema", event.as_json())

    def frame(self, record: "FrameRecord") -> None:
        """The frame's records."""
        out: dict[str, Any] = {"d": record.decisions, "frame": record.index,
                               "t": round(record.time, 6), "schemas": list(record.schemas),
                               "unexpected_regions": record.unexpected_regions,
                               "objects": objects_json(record)}
        bg = record.background
        if bg is not None:
            out["mmd"] = mmd_json(bg)
            out["regions"] = [r.as_json() for r in bg.regions]
        self.writer.event("frame", out)
        if record.subscene is not None:
            self.writer.event("network", {"d": record.decisions, "frame": record.index,
                                          **record.subscene})
        look = None if bg is None else self.looks.record(bg)
        if look is not None:
            self.writer.event("appearance", {"d": record.decisions, **look})
        self.writer.flush()

    def close(self, agent: "RuleEngine", summary: dict[str, Any], wall: float,
              error: str | None) -> Path:
        """The summary and the footer, and the file in place."""
        # the summary before the footer: readers take the footer as the trace's last record
        self.writer.event("summary", {"d": agent.decisions, **summary})
        # the footer says why the run stopped (summary["stopped"]), not why the agent's last
        # slice of decisions did (always "max-decisions": the frame's decisions done)
        self.writer.footer({**agent.report().to_dict(), "stop_reason": summary["stopped"]},
                           wall, error)
        self.writer.close()
        os.replace(self.tmp, self.path)
        return self.path

    def abandon(self) -> None:
        """Close and remove the temporary file of a trace that is not kept (a run that never
        ran, or one whose trace is already in place)."""
        self.writer.close()
        self.tmp.unlink(missing_ok=True)
