"""Exit statuses of the ``adapt`` command line, one table for every subcommand.

Tools and test harnesses read these (``docs/cli.md`` lists them):

======  ==========================  ==================================================
status  name                        meaning
======  ==========================  ==================================================
0       ``OK``                      done; for ``rules run``: the agent halted
1       ``ERROR``                   bad input or a failure (``adapt: error: ...``)
2       ``USAGE``                   a bad command line (argparse's own status)
3       ``DECISION_LIMIT``          ``rules run``: stopped at ``--max-decisions``
4       ``GOAL_DEPTH``              ``rules run``: the goal stack grew too deep
5       ``RULE_INTERRUPT``          ``rules run``: a rule called ``(interrupt)``
6       ``RULE_ERROR``              ``rules run``: a run-time error in a rule's actions
7       ``NO_ALIGNMENT``            ``mmd`` / ``sync``: the images could not be aligned
8       ``NOT_CONVERGED``           ``sync``: ``--max-iter`` renders without reaching ``--tolerance``
9       ``RUNS_FAILED``             ``sweep``: finished, but some runs failed or were lost
70      ``INTERNAL``                a bug in adapt (``adapt: internal error: ...``; please report it)
130     ``INTERRUPTED``             stopped by Ctrl-C (SIGINT); what ran is reported
======  ==========================  ==================================================
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["Exit", "COMMAND_STATUSES"]


class Exit(IntEnum):
    """The exit statuses (see the module docstring)."""

    OK = 0
    ERROR = 1
    USAGE = 2
    DECISION_LIMIT = 3
    GOAL_DEPTH = 4
    RULE_INTERRUPT = 5
    RULE_ERROR = 6
    NO_ALIGNMENT = 7
    NOT_CONVERGED = 8
    RUNS_FAILED = 9
    INTERNAL = 70
    INTERRUPTED = 130


_COMMON = (Exit.OK, Exit.ERROR, Exit.USAGE, Exit.INTERRUPTED)

#: The statuses each subcommand exits with (besides :attr:`Exit.INTERNAL`, a bug).
#: ``docs/cli.md`` lists the same table; ``tests/docs`` checks that they agree.
COMMAND_STATUSES: dict[str, tuple[Exit, ...]] = {
    "run": _COMMON,
    "check": _COMMON,
    "schemas list": _COMMON,
    "plugins list": _COMMON,
    "rules run": _COMMON + (Exit.DECISION_LIMIT, Exit.GOAL_DEPTH, Exit.RULE_INTERRUPT,
                            Exit.RULE_ERROR),
    "rules check": _COMMON,
    "rules info": (Exit.OK, Exit.USAGE, Exit.INTERRUPTED),
    "render": _COMMON,
    "imagine": _COMMON,
    "mmd": _COMMON + (Exit.NO_ALIGNMENT,),
    "sync": _COMMON + (Exit.NO_ALIGNMENT, Exit.NOT_CONVERGED),
    "trace show": _COMMON,
    "trace wm": _COMMON,
    "trace why": _COMMON,
    "trace stats": _COMMON,
    "trace diff": _COMMON,
    "trace html": _COMMON,
    "sweep": _COMMON + (Exit.RUNS_FAILED,),
}
