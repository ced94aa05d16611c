"""Everything a run reads: the scenario's files and the files its rules ``source``.

:meth:`adapt.scenario.Scenario.inputs` lists what the scenario names; a rule
file may ``source`` others, which only the rule loader finds.  A run's output
guard (:func:`adapt.files.check_outputs`) and a sweep's take both.

Examples
--------
>>> from pathlib import Path
>>> from adapt.scenario import load_scenario
>>> root = Path(__file__).resolve().parents[2]
>>> ins = run_inputs(load_scenario(root / "scenarios" / "bouncing-ball.yaml"))
>>> [i.what for i in ins][:2]
['the scenario', "the scenario's rules[0] (a rule file)"]
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from adapt.errors import RuleError
from adapt.files import Input, Inputs

if TYPE_CHECKING:
    from adapt.scenario import RuleFile, Scenario

__all__ = ["run_inputs", "sourced_inputs"]


def sourced_inputs(rule: "RuleFile", files: Sequence[str]) -> list[Input]:
    """The files a scenario's rule file read besides itself (``files``: the loader's list,
    the rule file first), as inputs named after its key."""
    top = Path(rule.path).resolve()
    return [Input(f"a file sourced by the scenario's {rule.source.path or 'rules'} "
                  f"({rule.path})", Path(f)) for f in files if Path(f).resolve() != top]


def run_inputs(scenario: "Scenario") -> Inputs:
    """The scenario's inputs and every file its rule files ``source``.

    A rule file that does not load adds nothing: its error is reported, at its
    position, when the agent loads it.
    """
    from adapt.engine.functions import default_functions
    from adapt.engine.parse import load_rule_file

    inputs = scenario.inputs()
    table = default_functions()
    for rule in scenario.rules:
        try:
            loaded = load_rule_file(rule.path, functions=table)
        except RuleError:
            continue
        inputs.extend(sourced_inputs(rule, loaded.files))
    return inputs
