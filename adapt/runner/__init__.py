"""The scenario runner: frames -> schemas -> rules -> motor schemas -> imagination.

* :mod:`~adapt.runner.runner` - :class:`Runner`, the frame loop;
* :mod:`~adapt.runner.record` - :class:`FrameRecord`, one typed record a frame, and the
  listener protocol;
* :mod:`~adapt.runner.check` - the scenario check and a run's length (``adapt check``,
  the runner and sweeps);
* :mod:`~adapt.runner.agent` - the rule engine a run uses, made in one place;
* :mod:`~adapt.runner.baseline` - the baselines (a keyed collection; the Kalman one);
* :mod:`~adapt.runner.twin` - the uncorrected imagination beside the mirror;
* :mod:`~adapt.runner.evaluation` - errors against ground truth (the only reader of truth);
* :mod:`~adapt.runner.summary` - the run's own statistics and its summary;
* the outputs, listeners on the frame records: :mod:`~adapt.runner.report`
  (``report.json``), :mod:`~adapt.runner.trace` (``trace.jsonl``),
  :mod:`~adapt.runner.panels` (``mmd.mp4``), :mod:`~adapt.runner.figures` (the figures).
"""

from __future__ import annotations

from adapt.runner.check import RunLength, ScenarioCheck, check_scenario, run_length
from adapt.runner.record import FrameListener, FrameRecord
from adapt.runner.runner import STAGES, Progress, Runner, RunResult

__all__ = ["Runner", "RunResult", "Progress", "STAGES", "FrameRecord", "FrameListener",
           "check_scenario", "ScenarioCheck", "run_length", "RunLength"]
