"""The engine's vocabulary: phases, support, impasses, stop reasons.

Every name the decision cycle, the kernel and the reports share is a typed
value here: an :class:`~enum.Enum` where the engine branches on it in its
hot paths (compared by identity), a :data:`~typing.Literal` where it is
only reported.  The string values are the words of Soar and of
``docs/trace-format.md``; a ``str`` enum member equals its word and is
written as it in JSON.

Examples
--------
>>> Phase.DECISION.value, Phase.DECISION == "decision", Phase.DECISION.next
('decision', True, <Phase.APPLY: 'apply'>)
>>> Support.O == "o", [s.value for s in Support]
(True, ['o', 'i', 'none'])
>>> import json; json.dumps({"support": Support.I})
'{"support": "i"}'
"""

from __future__ import annotations

from enum import Enum
from typing import Literal

__all__ = ["Phase", "PHASES", "Support", "ImpasseType", "ImpasseAttribute", "StopReason",
           "IMPASSE_TYPES", "NO_CHANGE"]


class Phase(str, Enum):
    """The five phases of a decision cycle, in order."""

    INPUT = "input"
    PROPOSAL = "proposal"
    DECISION = "decision"
    APPLY = "apply"
    OUTPUT = "output"

    @property
    def next(self) -> Phase:
        """The phase that follows this one (output is followed by input)."""
        return _NEXT[self]


#: The phases in cycle order.
PHASES: tuple[Phase, ...] = tuple(Phase)
_NEXT = {p: PHASES[(i + 1) % len(PHASES)] for i, p in enumerate(PHASES)}


class Support(str, Enum):
    """The support of an instantiation's preferences.

    ``NONE`` is a production whose actions are only function calls: it makes
    no preference and is scheduled like i-support.
    """

    O = "o"
    I = "i"  # noqa: E741  (Soar's name)
    NONE = "none"


#: An impasse type, as the substate's ``^impasse`` names it.
ImpasseType = Literal["tie", "conflict", "constraint-failure", "no-change"]
#: The impasse types.
IMPASSE_TYPES: tuple[ImpasseType, ...] = ("tie", "conflict", "constraint-failure", "no-change")
#: The no-change impasse type.
NO_CHANGE: ImpasseType = "no-change"
#: What an impasse is about (``^attribute``).
ImpasseAttribute = Literal["operator", "state"]
#: Why a run stopped.
StopReason = Literal["halt", "max-decisions", "max-goal-depth", "interrupted"]
