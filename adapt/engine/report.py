"""The report of a run: what happened, in the shapes real Soar's reports use.

Examples
--------
>>> r = RunReport(halted=True, stop_reason="halt", decisions=2, output="hi\\n",
...               operators=[[1, 0, "go"]], impasses=[], production_firings=3,
...               elaboration_cycles=4, wm_size_final=9, messages=["This Agent halted."])
>>> r.to_dict()["operators"], r.to_dict()["stop_reason"]
([[1, 0, 'go']], 'halt')
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["RunReport", "REPORT_KEYS"]

#: The keys of :meth:`RunReport.to_dict`, in order.
REPORT_KEYS = ("halted", "stop_reason", "decisions", "output", "operators", "impasses",
               "production_firings", "elaboration_cycles", "wm_size_final", "messages")


@dataclass(frozen=True)
class RunReport:
    """What an agent did since it was created, at the end of a ``run``.

    Attributes
    ----------
    halted : bool
        ``(halt)`` was executed.
    stop_reason : str
        ``"halt"``, ``"max-decisions"``, ``"max-goal-depth"`` or ``"interrupted"``.
    decisions : int
        Decision phases run (Soar's decision counter).
    output : str
        Everything ``write`` printed.
    operators : list of [decision, level, name]
        Every operator selection; level 0 is the top state; ``name`` is the
        operator's ``^name`` (``None`` when it has none, as Soar reports it).
    impasses : list of [decision, level, type, attribute]
        Every new substate: its level, impasse type (``tie``, ``conflict``,
        ``constraint-failure``, ``no-change``) and attribute (``operator`` or
        ``state``).
    production_firings, elaboration_cycles : int
    wm_size_final : int
        WMEs in working memory at the end (Soar also counts its epmem/smem/RL
        structures, which adapt does not build).
    messages : list of str
        Kernel messages and warnings.
    """

    halted: bool
    stop_reason: str
    decisions: int
    output: str
    operators: list[list[Any]] = field(default_factory=list)
    impasses: list[list[Any]] = field(default_factory=list)
    production_firings: int = 0
    elaboration_cycles: int = 0
    wm_size_final: int = 0
    messages: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The report as plain JSON-ready data, with the keys of :data:`REPORT_KEYS`."""
        return {
            "halted": self.halted,
            "stop_reason": self.stop_reason,
            "decisions": self.decisions,
            "output": self.output,
            "operators": [list(o) for o in self.operators],
            "impasses": [list(i) for i in self.impasses],
            "production_firings": self.production_firings,
            "elaboration_cycles": self.elaboration_cycles,
            "wm_size_final": self.wm_size_final,
            "messages": list(self.messages),
        }
