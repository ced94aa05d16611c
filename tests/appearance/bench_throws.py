"""The throws of ``bench/foreign.py --small`` as scenarios, for tests that replay one."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from adapt.scenario import OutputSettings, Scenario, loads_scenario

ROOT = Path(__file__).resolve().parents[2]
#: No outputs written: a test reads the run's frames through a listener.
QUIET = OutputSettings(report=False, trace=False, video=False, figures=False)


def scenario_text(seed: int, duration: float) -> str:
    """Throw ``seed``'s scenario YAML at 320x240, ``duration`` seconds long."""
    spec = importlib.util.spec_from_file_location("_bench_foreign", ROOT / "bench" / "foreign.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return str(module.scenario_text(seed, True, duration)[0])


def throw(seed: int, duration: float, *overrides: str) -> Scenario:
    """Throw ``seed``'s scenario, read as ``bench/foreign.py`` reads it (with ``--set``
    style ``overrides``, ``KEY=VALUE``)."""
    return loads_scenario(scenario_text(seed, duration), file=f"foreign-{seed}.yaml",
                          base=ROOT / "scenarios", overrides=list(overrides))
