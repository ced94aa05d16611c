"""The run's own statistics and its summary (``report.json``'s ``summary``).

:class:`RunStats` counts what the loop does -- seconds per stage, the network's
events, the rules' last writes, the Scene Background's milliseconds per
frame -- in memory that stays flat however long the run; :meth:`RunStats.summary`
joins them with what the object schemas published (their parameter estimates
and how fast their predictions ran) into the summary's keys
(``docs/runner.md``); the evaluation adds its own.

Examples
--------
>>> s = RunStats()
>>> s.add("perception", 0.02); s.add("decisions", 0.01); s.write("hello\\n")
>>> out = s.summary(frames=2, fps=30.0, wall=0.5, interrupted=False, error=None, stopped="end-of-frames", decisions=6,
...                 halted=False, schemas=[], schema_s={}, objects=[])
>>> out["stage_ms"]["perception"], out["simulated_s"], out["writes"]
(10.0, 0.0667, 'hello\\n')
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from adapt.schemas import SchemaEvent
from adapt.schemas.percepts import ObjectPercept

__all__ = ["RunStats", "STAGES"]

#: The stages timed per frame, in loop order.
STAGES = ("reality", "perception", "decisions", "action", "physics", "outputs")

#: The Scene Background's milliseconds kept (the newest) for the median.
MMD_KEPT = 4096
#: The rules' writes kept (the newest) for the summary's ``writes``.
WRITES_KEPT = 200


class RunStats:
    """What the loop counts (see the module docstring)."""

    def __init__(self) -> None:
        self.stage_s = {s: 0.0 for s in STAGES}
        self.events: dict[str, int] = {}
        self.writes: list[str] = []
        self.mmd_ms: list[float] = []

    def add(self, stage: str, seconds: float) -> None:
        """``seconds`` more in ``stage``."""
        self.stage_s[stage] += seconds

    def event(self, event: SchemaEvent) -> None:
        """Count a network event."""
        key = event.kind.value
        self.events[key] = self.events.get(key, 0) + 1

    def write(self, text: str) -> None:
        """Keep a ``(write ...)`` of the rules."""
        self.writes.append(text)
        if len(self.writes) > WRITES_KEPT:
            del self.writes[:WRITES_KEPT // 2]

    def mmd(self, ms: float) -> None:
        """The Scene Background's milliseconds for a frame."""
        self.mmd_ms.append(ms)
        if len(self.mmd_ms) > MMD_KEPT:
            del self.mmd_ms[: len(self.mmd_ms) - MMD_KEPT // 2]

    def summary(self, *, frames: int, fps: float, wall: float, interrupted: bool,
                error: str | None, stopped: str, decisions: int, halted: bool, schemas: Sequence[str],
                schema_s: Mapping[str, float], objects: Sequence[ObjectPercept]) -> dict[str, Any]:
        """The summary's keys but the evaluation's."""
        n = max(frames, 1)
        total = sum(self.stage_s.values())
        return {
            "frames": frames,
            "simulated_s": round(frames / fps, 4),
            "wall_s": round(wall, 3),
            "frames_per_s": round(frames / wall, 2) if wall > 0 else None,
            "interrupted": interrupted,
            "error": error,
            "stopped": stopped,
            "decisions": decisions,
            "halted": halted,
            "schemas": list(schemas),
            "events": dict(sorted(self.events.items())),
            "stage_ms": {k: round(1000.0 * v / n, 3) for k, v in self.stage_s.items()},
            "stage_share": {k: round(v / total, 4) if total > 0 else 0.0
                            for k, v in self.stage_s.items()},
            "schema_ms": {k: round(1000.0 * v / n, 3) for k, v in sorted(schema_s.items())},
            "mmd_ms_median": round(float(np.median(self.mmd_ms)), 3) if self.mmd_ms else None,
            "rollouts": _rollouts(objects),
            "parameters": {p.object: {k: e.as_json() for k, e in p.estimates.items()}
                           for p in objects if p.estimates},
            "writes": "".join(self.writes[-20:]),
        }


def _rollouts(objects: Sequence[ObjectPercept]) -> dict[str, Any]:
    """How fast the object schemas' predictions ran: seconds of imagination rolled out
    per wall-clock second (times real time)."""
    sim = sum(p.rollouts[0] for p in objects)
    wall = sum(p.rollouts[1] for p in objects)
    return {"simulated_s": round(sim, 3), "wall_s": round(wall, 4),
            "times_real_time": round(sim / wall, 1) if wall > 0 else None}
