"""The rule engine a run uses: made in one place, used through the engine interface.

:func:`make_agent` builds the agent of a run on the engine the scenario names
(``engine:``, :class:`~adapt.engine.interface.EngineName`: adapt's own, the
default, or the Soar kernel), with the scenario's rule files loaded and its
random stream seeded (Soar's ``srand`` on the Soar engine).  The runner uses it
only through :class:`~adapt.engine.interface.RuleEngine` -- the one protocol
of an engine, re-exported here -- : the input and output callbacks, the
rules' writes, running decision cycles, the trace it writes into the run's
``trace.jsonl`` (:meth:`~adapt.engine.interface.RuleEngine.attach_trace`).

A rule file with an error is reported where the scenario names it
(:func:`scenario_rule_error`), by the check (:mod:`adapt.runner.check`) and
here alike.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from adapt.engine.interface import RuleEngine
from adapt.engines import make_agent as make_engine
from adapt.errors import RuleError

if TYPE_CHECKING:  # pragma: no cover
    from adapt.scenario import RuleFile, Scenario

__all__ = ["RuleEngine", "make_agent", "scenario_rule_error", "AGENT_HISTORY"]

#: Operator selections, impasses and writes the agent keeps in memory.
AGENT_HISTORY = 1000


def scenario_rule_error(exc: RuleError, rule_file: "RuleFile") -> RuleError:
    """``exc`` (an error in a rule file) saying where the scenario names the file."""
    return type(exc)(f"{exc.message} (a rule file of the scenario, {rule_file.source.location}: "
                     f"{rule_file.source.path})", file=exc.file, line=exc.line, col=exc.col,
                     source_line=exc.source_line)


def make_agent(scenario: "Scenario", *, seed: int, history: int = AGENT_HISTORY) -> RuleEngine:
    """The agent of a run on the scenario's engine, with its rule files loaded.

    Raises
    ------
    RuleError
        A rule file with an error, at its position and where the scenario names it.
    AdaptError
        The Soar engine without soar-sml installed (the message names the extra).
    """
    agent = make_engine(scenario.engine, seed=seed, history=history)
    try:
        for rf in scenario.rules:
            try:
                agent.load_file(rf.path)
            except RuleError as exc:
                raise scenario_rule_error(exc, rf) from None
    except BaseException:
        agent.close()
        raise
    return agent
