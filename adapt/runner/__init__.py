"""The scenario runner: frames -> schemas -> rules -> motor schemas -> imagination.

* :mod:`~adapt.runner.runner` - :class:`Runner`, the frame loop;
* :mod:`~adapt.runner.report` - ``report.json``, streamed;
* :mod:`~adapt.runner.evaluation` - errors against ground truth (the only reader of truth);
* :mod:`~adapt.runner.panels` - the frames of ``mmd.mp4``;
* :mod:`~adapt.runner.figures` - the figures (matplotlib).
"""

from __future__ import annotations

from adapt.runner.runner import STAGES, Progress, Runner, RunResult

__all__ = ["Runner", "RunResult", "Progress", "STAGES"]
