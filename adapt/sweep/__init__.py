"""Sweeps: one scenario over many seeds and a grid of parameters, on Dask.

``adapt sweep SCENARIO.yaml --seeds 1-200 --set KEY=V1,V2 ...`` runs the
product of the seeds and the ``--set`` values, one run per task, on an
embedded local Dask cluster or on any Dask scheduler, and writes into its
folder ``runs.jsonl`` (one record per run, appended as each run finishes),
``sweep.json`` (rates with Wilson intervals, medians and percentiles per
grid cell), ``runs.csv`` and ``figures/``.  See ``docs/sweeps.md``.

The parts, in the order a sweep uses them:

* :mod:`~adapt.sweep.grid` - ``--seeds`` and ``--set`` read into values;
* :mod:`~adapt.sweep.plan` - the grid's runs, every cell checked by the
  scenario reader before anything runs;
* :mod:`~adapt.sweep.task` - one run in a worker, returning its record;
* :mod:`~adapt.sweep.metrics` - a run's metrics read from its summary;
* :mod:`~adapt.sweep.cluster` - the embedded cluster or a scheduler (Dask
  is imported only there and in :mod:`~adapt.sweep.session`);
* :mod:`~adapt.sweep.store` - ``runs.jsonl``, append-only and locked;
* :mod:`~adapt.sweep.session` - the sweep itself: skip what is done, run
  the rest, record each run once, survive dead workers and Ctrl-C;
* :mod:`~adapt.sweep.stats`, :mod:`~adapt.sweep.aggregate`,
  :mod:`~adapt.sweep.plots` - ``sweep.json``, ``runs.csv`` and the figures.

This package may import the runner, the scenario reader (and, to check a
grid before running it, the schema registry and the rule parser); nothing
but the command line imports it.

Examples
--------
>>> from adapt.sweep import parse_seeds, parse_axis
>>> len(parse_seeds("1-200")), parse_axis("run.fps=15,30").values
(200, [15, 30])
"""

from __future__ import annotations

from adapt.sweep.grid import Axis, Item, parse_axis, parse_seeds
from adapt.sweep.metrics import metrics_of
from adapt.sweep.plan import Plan, make_plan
from adapt.sweep.session import Outcome, Progress, run_sweep
from adapt.sweep.task import RunSpec, run_task

__all__ = ["Axis", "Item", "parse_axis", "parse_seeds", "metrics_of", "Plan", "make_plan",
           "Outcome", "Progress", "run_sweep", "RunSpec", "run_task"]
