"""``sweep.json`` and ``runs.csv``: the runs of a plan, aggregated per grid cell.

Only finished runs (``status: "ok"``) give metrics; a failed or lost run is
counted as such and is never a "not caught".  Per cell, per swept value
(pooled over the other axes) and over the whole sweep:

``rates``
    each yes/no metric (``caught``, ``baseline_caught``, ``reachable``) as
    ``{"k", "n", "rate", "low", "high"}``, the interval being the 95 % Wilson
    score interval (:mod:`adapt.sweep.stats`);
``values``
    each numeric metric as ``{"n", "median", "median_low", "median_high",
    "mean", "min", "max", "p10", "p25", "p75", "p90"}`` (``catch_t`` over the
    runs that caught);
``paired``
    each metric beside its baseline's, run by run on the runs that have both:
    for a flag, how many runs only one of them caught; for a number, the
    median of (mirror - baseline) and how often the mirror's is lower, as a
    rate.

Examples
--------
>>> from adapt.sweep.grid import parse_axis
>>> ax = parse_axis("world.dt=0.01,0.02")
>>> recs = [{"key": f"k{i}", "seed": i, "set": {"world.dt": 0.01 * (1 + i % 2)},
...          "status": "ok", "metrics": {"caught": i % 3 != 0, "baseline_caught": False}}
...         for i in range(6)]
>>> s = summarise(recs, [ax])
>>> s["overall"]["rates"]["caught"]["k"], s["overall"]["paired"]["caught"]["mirror_only"]
(4, 4)
>>> [v["value"] for v in s["by_parameter"]["world.dt"]]
[0.01, 0.02]
"""

from __future__ import annotations

import csv
import io
import json
from collections import Counter
from typing import Any, Iterable, Mapping, Sequence

from adapt.sweep.grid import Axis
from adapt.sweep.metrics import TIMING, is_flag, order_key, peer_of
from adapt.sweep.stats import DIGITS, describe, rate

__all__ = ["cell_stats", "summarise", "csv_text", "metric_names", "deterministic", "is_timing",
           "cell_id", "INTERVALS"]

#: What the intervals in ``sweep.json`` are.
INTERVALS = {"rates": "Wilson score interval, 95 %",
             "medians": "distribution-free order-statistic interval, 95 % (none below 6 runs)"}


def metric_names(records: Iterable[Mapping[str, Any]]) -> list[str]:
    """Every metric any of ``records`` has, in table order."""
    names: set[str] = set()
    for r in records:
        names.update((r.get("metrics") or {}).keys())
    return sorted(names, key=order_key)


def cell_stats(records: Sequence[Mapping[str, Any]], planned: int | None = None
               ) -> dict[str, Any]:
    """Counts, rates, values and paired comparisons of some runs (see the module docstring)."""
    status = Counter(r.get("status") for r in records)
    ok = [r for r in records if r.get("status") == "ok"]
    names = metric_names(ok)
    out: dict[str, Any] = {"ok": status.get("ok", 0), "failed": status.get("failed", 0),
                           "lost": status.get("lost", 0)}
    if planned is not None:
        out = {"planned": planned, **out, "remaining": planned - len(records)}
    rates: dict[str, Any] = {}
    values: dict[str, Any] = {}
    for name in names:
        got = [r["metrics"][name] for r in ok if name in r["metrics"]]
        if is_flag(name):
            rates[name] = rate(sum(bool(v) for v in got), len(got))
        else:
            values[name] = describe([float(v) for v in got])
    paired: dict[str, Any] = {}
    for name in names:
        peer = peer_of(name)
        if peer is None or peer not in names:
            continue
        pairs = [(r["metrics"][name], r["metrics"][peer]) for r in ok
                 if name in r["metrics"] and peer in r["metrics"]]
        if is_flag(name):
            c = Counter((bool(a), bool(b)) for a, b in pairs)
            paired[name] = {"n": len(pairs), "both": c[(True, True)],
                            "mirror_only": c[(True, False)], "baseline_only": c[(False, True)],
                            "neither": c[(False, False)]}
        elif pairs:
            diffs = [float(a) - float(b) for a, b in pairs]
            d = describe(diffs)
            paired[name] = {"n": len(pairs), "median_difference": d["median"],
                            "median_difference_low": d["median_low"],
                            "median_difference_high": d["median_high"],
                            "mirror_lower": rate(sum(x < 0 for x in diffs), len(diffs))}
    out.update(rates=rates, values=values, paired=paired)
    return out


def summarise(records: Sequence[Mapping[str, Any]], axes: Sequence[Axis],
              planned: Mapping[str, int] | None = None) -> dict[str, Any]:
    """``overall``, ``cells`` and ``by_parameter`` statistics of ``records`` (the latest
    record of each run of the grid).

    ``planned`` maps a cell's :func:`cell_id` to its number of runs, in the grid's order; without it counts of planned and remaining runs are left out.
    """
    by_cell: dict[str, list[Mapping[str, Any]]] = {}
    for r in records:
        by_cell.setdefault(cell_id(r.get("set") or {}), []).append(r)
    cells = []
    order = list(planned) if planned is not None else list(by_cell)
    for cid in order:
        rs = by_cell.get(cid, [])
        stats = cell_stats(rs, None if planned is None else planned[cid])
        cells.append({"set": json.loads(cid), **stats})
    total = None if planned is None else sum(planned.values())
    by_parameter: dict[str, list[dict[str, Any]]] = {}
    for axis in axes:
        rows = []
        for value in axis.values:
            rs = [r for r in records if _same((r.get("set") or {}).get(axis.path), value)]
            n = None
            if planned is not None:
                n = sum(k for cid, k in planned.items()
                        if _same(json.loads(cid).get(axis.path), value))
            rows.append({"value": value, **cell_stats(rs, n)})
        by_parameter[axis.path] = rows
    errors = Counter(str(r.get("error")) for r in records if r.get("status") != "ok")
    return {"overall": cell_stats(records, total), "cells": cells,
            "by_parameter": by_parameter,
            "errors": [{"error": e, "runs": k} for e, k in errors.most_common(20)]}


def cell_id(cell: Mapping[str, Any]) -> str:
    """A cell's overrides as canonical JSON (keys sorted): the cell's identity."""
    return json.dumps(dict(cell), sort_keys=True, separators=(",", ":"))


def _same(a: Any, b: Any) -> bool:
    return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def csv_text(records: Sequence[Mapping[str, Any]], axes: Sequence[Axis]) -> str:
    """``runs.csv``: one row per run (key, seed, each swept key, status, error, the task's wall
    and CPU time, each metric); flags as ``true``/``false``, lists as JSON, missing values empty.

    >>> print(csv_text([{"key": "k", "seed": 1, "set": {}, "status": "ok",
    ...                  "metrics": {"caught": True, "wall_s": 2.0}}], []), end="")
    key,seed,status,error,task_s,cpu_s,caught,wall_s
    k,1,ok,,,,true,2.0
    """
    names = metric_names(records)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["key", "seed", *[a.path for a in axes], "status", "error", "task_s", "cpu_s",
                *names])
    for r in records:
        cell = r.get("set") or {}
        m = r.get("metrics") or {}
        w.writerow([r["key"], r.get("seed"), *[_cell(cell.get(a.path)) for a in axes],
                    r.get("status"), r.get("error") or "", _cell(r.get("task_s")),
                    _cell(r.get("cpu_s")), *[_cell(m.get(n)) for n in names]])
    return buf.getvalue()


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(round(v, DIGITS + 2))
    if isinstance(v, (int, str)):
        return str(v)
    return json.dumps(v)


def deterministic(record: Mapping[str, Any]) -> dict[str, Any]:
    """The part of a record that depends only on the run's seed and overrides (its key,
    status, error, metrics and summary without timings); for comparing sweeps.

    Timings are found by name at any depth of the summary (:func:`is_timing`).

    >>> deterministic({"key": "k", "status": "ok", "error": None, "worker": {"pid": 1},
    ...                "metrics": {"frames": 3, "wall_s": 1.0},
    ...                "summary": {"wall_s": 1.0, "rollouts": {"simulated_s": 2.0, "wall_s": 0.1}}})
    {'key': 'k', 'status': 'ok', 'error': None, 'metrics': {'frames': 3}, 'summary': {'rollouts': {'simulated_s': 2.0}}}
    """
    return {"key": record["key"], "status": record.get("status"), "error": record.get("error"),
            "metrics": {k: v for k, v in (record.get("metrics") or {}).items()
                        if k not in TIMING},
            "summary": _untimed(record.get("summary") or {})}


def is_timing(key: str) -> bool:
    """True for a summary key that measures the machine, not the run: ``wall_s``,
    ``frames_per_s``, ``times_real_time``, ``stage_share`` and every ``..._ms`` or
    ``..._ms_...`` key (``stage_ms``, ``schema_ms``, ``mmd_ms_median``).

    >>> [k for k in ("wall_s", "simulated_s", "stage_ms", "mmd_ms_median", "frames") if is_timing(k)]
    ['wall_s', 'stage_ms', 'mmd_ms_median']
    """
    return key in _TIMING_KEYS or key.endswith("_ms") or "_ms_" in key


def _untimed(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {k: _untimed(v) for k, v in value.items() if not is_timing(str(k))}
    return value


_TIMING_KEYS = frozenset({"wall_s", "frames_per_s", "times_real_time", "stage_share"})
