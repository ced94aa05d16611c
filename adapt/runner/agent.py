"""The rule engine a run uses: made in one place, used through a small interface.

:func:`make_agent` builds the agent of a run: adapt's own engine
(:class:`adapt.engine.Agent`) with the scenario's rule files loaded, the
trace writer attached and its random stream seeded.  The runner uses it only
through :class:`RuleEngine` (the input and output callbacks, the rules'
writes, running decision cycles, the trace's footer), so another engine
behind the same interface (the real Soar kernel, say) is a change here and
nowhere else.

A rule file with an error is reported where the scenario names it
(:func:`scenario_rule_error`), by the check (:mod:`adapt.runner.check`) and
here alike.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Protocol

from adapt.engine import Agent, InputWriter, OutputView
from adapt.errors import RuleError

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine import RunReport
    from adapt.engine.trace import TraceWriter
    from adapt.engine.vocabulary import StopReason
    from adapt.scenario import RuleFile, Scenario

__all__ = ["RuleEngine", "make_agent", "scenario_rule_error", "AGENT_HISTORY"]

#: Operator selections, impasses and writes the agent keeps in memory.
AGENT_HISTORY = 1000


class RuleEngine(Protocol):
    """What the runner needs of a rule engine."""

    #: Decision cycles run so far.
    decisions: int
    #: The rules halted the agent.
    halted: bool
    #: Why the last run stopped (``"interrupted"`` is set by the runner on Ctrl-C).
    stop_reason: "StopReason | None"

    def on_input(self, callback: Callable[[InputWriter], None]) -> None:
        """Call ``callback`` in every input phase."""
        ...

    def on_output(self, callback: Callable[[OutputView], None]) -> None:
        """Call ``callback`` after every output phase."""
        ...

    def on_write(self, callback: Callable[[str], None]) -> None:
        """Call ``callback`` with the text of every ``(write ...)``."""
        ...

    def run(self, max_decisions: int | None = None, *, footer: bool = True) -> "RunReport":
        """Run up to ``max_decisions`` decision cycles."""
        ...

    def write_footer(self, elapsed_s: float, error: str | None = None) -> None:
        """End the trace."""
        ...

    def report(self) -> "RunReport":
        """What the agent has done so far."""
        ...


def scenario_rule_error(exc: RuleError, rule_file: "RuleFile") -> RuleError:
    """``exc`` (an error in a rule file) saying where the scenario names the file."""
    return type(exc)(f"{exc.message} (a rule file of the scenario, {rule_file.source.location}: "
                     f"{rule_file.source.path})", file=exc.file, line=exc.line, col=exc.col,
                     source_line=exc.source_line)


def make_agent(scenario: "Scenario", *, seed: int, trace: "TraceWriter | None" = None,
               trace_level: int = 4, history: int = AGENT_HISTORY) -> RuleEngine:
    """The agent of a run, with the scenario's rule files loaded.

    Raises
    ------
    RuleError
        A rule file with an error, at its position and where the scenario names it.
    """
    agent = Agent(seed=seed, trace=trace, trace_level=trace_level, history=history)
    for rf in scenario.rules:
        try:
            agent.load_file(rf.path)
        except RuleError as exc:
            raise scenario_rule_error(exc, rf) from None
    return agent
