"""The sweep's figures, drawn with matplotlib (Agg, no window) into ``figures/``.

``rates.png``
    Each yes/no metric's rate (the mirror's ``caught`` beside the
    baseline's, and ``reachable``) against each swept parameter, pooled over
    the other parameters, with 95 % Wilson intervals as error bars; over all
    runs when nothing but the seed is swept.  Not drawn when the runs have
    no yes/no metric (a scenario without an interception goal).
``errors.png``
    First row: the distribution over runs of each error metric (box: the
    quartiles; whiskers: the 10th and 90th percentiles; line: the median),
    the mirror's beside the baseline's where the baseline has one.  One
    more row per swept parameter: the median and the quartiles of each error
    against the parameter.

A numeric parameter is drawn on a number line; any other (a list, a name)
as categories in the order given; a ``--set`` with one value is a setting,
not a swept parameter, and gets no panel.  Every file is written atomically.
"""

from __future__ import annotations

import io
import json
import textwrap
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from adapt.files import write_atomic
from adapt.sweep.aggregate import metric_names
from adapt.sweep.grid import Axis
from adapt.sweep.metrics import BASELINE, TIMING, is_flag, label, peer_of

__all__ = ["write_plots", "MAX_ERROR_PANELS"]

#: The most error metrics ``errors.png`` draws (the first ones in table order).
MAX_ERROR_PANELS = 6

DPI = 110
MIRROR = "#1f6fb4"
BASE = "#d9822b"
OTHER = "#7a7a7a"


def write_plots(records: Sequence[Mapping[str, Any]], axes: Sequence[Axis],
                folder: str | Path, title: str = "") -> dict[str, Path]:
    """Draw the figures of the finished runs among ``records``; return what was written."""
    ok = [r for r in records if r.get("status") == "ok"]
    out: dict[str, Path] = {}
    if not ok:
        return out
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    axes = [a for a in axes if len(a.items) > 1]  # a single value is a setting, not a sweep
    names = metric_names(ok)
    flags = [n for n in names if is_flag(n)]
    if flags:
        out["rates"] = _rates(ok, axes, flags, folder / "rates.png", title)
    errors = [n for n in names if not is_flag(n) and not n.startswith(BASELINE)
              and n not in TIMING and n != "frames"][:MAX_ERROR_PANELS]
    if errors:
        out["errors"] = _errors(ok, axes, errors, folder / "errors.png", title)
    return out


def _figure(rows: int, cols: int, title: str) -> tuple[Any, Any]:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3.6 * cols, 2.9 * rows + (0.4 if title else 0.0)), dpi=DPI,
                 facecolor="white", layout="constrained")
    FigureCanvasAgg(fig)
    if title:
        fig.suptitle(title, fontsize=11)
    grid = fig.subplots(rows, cols, squeeze=False)
    return fig, grid


def _save(fig: Any, path: Path) -> Path:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, facecolor="white")
    return write_atomic(path, buf.getvalue())


def _positions(axis: Axis | None) -> tuple[list[float], list[str] | None]:
    """x positions of an axis's values, and tick labels when they are categories."""
    if axis is None:
        return [0.0], ["all runs"]
    if axis.numeric:
        return [float(v) for v in axis.values], None
    return [float(i) for i in range(len(axis.items))], [_short(v) for v in axis.values]


def _short(v: Any) -> str:
    text = v if isinstance(v, str) else json.dumps(v)
    return text if len(text) <= 18 else text[:16] + "…"


def _same(a: Any, b: Any) -> bool:
    return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def _groups(ok: Sequence[Mapping[str, Any]], axis: Axis | None
            ) -> list[list[Mapping[str, Any]]]:
    if axis is None:
        return [list(ok)]
    return [[r for r in ok if _same((r.get("set") or {}).get(axis.path), v)]
            for v in axis.values]


def _style(name: str) -> tuple[str, str, str]:
    """Colour, marker and legend text of a metric."""
    if name.startswith(BASELINE):
        return BASE, "s", "baseline (constant-velocity Kalman)"
    if peer_of(name) is not None:
        return MIRROR, "o", "mirror"
    return OTHER, "^", label(name)


def _rates(ok: Sequence[Mapping[str, Any]], axes: Sequence[Axis], flags: Sequence[str],
           path: Path, title: str) -> Path:
    from adapt.sweep.stats import wilson

    panels: list[Axis | None] = list(axes) or [None]
    fig, grid = _figure(1, len(panels), title)
    for ax, axis in zip(grid[0], panels):
        xs, ticks = _positions(axis)
        span = (max(xs) - min(xs)) if len(xs) > 1 else 1.0
        groups = _groups(ok, axis)
        for j, name in enumerate(flags):
            colour, marker, text = _style(name)
            if name == "caught":
                text = "mirror (caught)"
            elif name == "baseline_caught":
                text = "baseline (caught)"
            shift = (j - (len(flags) - 1) / 2) * 0.02 * span
            px, py, lo, hi = [], [], [], []
            for x, rs in zip(xs, groups):
                got = [bool(r["metrics"][name]) for r in rs if name in r.get("metrics", {})]
                if not got:
                    continue
                k, n = sum(got), len(got)
                a, b = wilson(k, n)
                px.append(x + shift)
                py.append(k / n)
                lo.append(max(0.0, k / n - a))
                hi.append(max(0.0, b - k / n))
            if px:
                ax.errorbar(px, py, yerr=[lo, hi], color=colour, marker=marker, capsize=3,
                            linestyle="-" if axis is not None and len(px) > 1 else "none",
                            label=text)
        ax.set_ylim(-0.03, 1.03)
        ax.set_ylabel("rate (95 % Wilson interval)")
        ax.set_xlabel("" if axis is None else axis.path)
        if ticks is not None:
            ax.set_xticks(xs, ticks, rotation=20 if axis is not None else 0)
            ax.set_xlim(-0.5, len(xs) - 0.5)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    return _save(fig, path)


def _errors(ok: Sequence[Mapping[str, Any]], axes: Sequence[Axis], names: Sequence[str],
            path: Path, title: str) -> Path:
    fig, grid = _figure(1 + len(axes), len(names), title)
    for col, name in enumerate(names):
        peer = peer_of(name)
        series = [name] + ([peer] if peer is not None and _has(ok, peer) else [])
        ax = grid[0][col]
        data = [[float(r["metrics"][s]) for r in ok if s in r["metrics"]] for s in series]
        labels = ["mirror" if peer_of(s) else "baseline" if s.startswith(BASELINE) else "runs"
                  for s in series]
        if len(series) == 1:
            labels = ["all runs"]
        for i, (vals, s) in enumerate(zip(data, series)):
            if vals:
                _box(ax, i, vals, _style(s)[0] if len(series) > 1 else OTHER)
        ax.set_xticks(range(len(series)), [f"{t}\n(n={len(v)})" for t, v in zip(labels, data)])
        ax.set_xlim(-0.6, len(series) - 0.4)
        ax.set_title(label(name), fontsize=9)
        ax.grid(alpha=0.3, axis="y")
        ax.ticklabel_format(axis="y", useOffset=False)
        for row, axis in enumerate(axes, start=1):
            _against(grid[row][col], ok, axis, series, name, legend=row == 1)
    note = ("Box: quartiles and median over runs; whiskers: 10th and 90th percentiles."
            + (" Below: median and quartiles at each value of a swept parameter." if axes else ""))
    lines = textwrap.wrap(note, width=int(60 * len(names)))
    fig.text(0.5, 0.0, "\n".join(lines), ha="center", va="bottom", fontsize=8, color="#444444")
    bottom = (0.08 + 0.15 * len(lines)) / fig.get_figheight()
    fig.get_layout_engine().set(rect=(0, bottom, 1, 1 - bottom))
    return _save(fig, path)


def _has(ok: Sequence[Mapping[str, Any]], name: str | None) -> bool:
    return name is not None and any(name in r.get("metrics", {}) for r in ok)


def _box(ax: Any, x: float, values: Sequence[float], colour: str) -> None:
    p10, p25, p50, p75, p90 = np.percentile(values, [10, 25, 50, 75, 90])
    ax.bxp([{"med": p50, "q1": p25, "q3": p75, "whislo": p10, "whishi": p90, "fliers": []}],
           positions=[x], widths=0.5, showfliers=False, patch_artist=True,
           boxprops={"facecolor": colour, "alpha": 0.35, "edgecolor": colour},
           medianprops={"color": colour, "linewidth": 2},
           whiskerprops={"color": colour}, capprops={"color": colour})


def _against(ax: Any, ok: Sequence[Mapping[str, Any]], axis: Axis, series: Sequence[str],
             name: str, legend: bool) -> None:
    xs, ticks = _positions(axis)
    groups = _groups(ok, axis)
    span = (max(xs) - min(xs)) if len(xs) > 1 else 1.0
    for j, s in enumerate(series):
        colour, marker, text = _style(s)
        if len(series) == 1:
            colour, text = OTHER, "median, quartiles"
        shift = (j - (len(series) - 1) / 2) * 0.02 * span
        px, py, lo, hi = [], [], [], []
        for x, rs in zip(xs, groups):
            vals = [float(r["metrics"][s]) for r in rs if s in r.get("metrics", {})]
            if not vals:
                continue
            q1, med, q3 = np.percentile(vals, [25, 50, 75])
            px.append(x + shift)
            py.append(med)
            lo.append(med - q1)
            hi.append(q3 - med)
        if px:
            ax.errorbar(px, py, yerr=[lo, hi], color=colour, marker=marker, capsize=3,
                        linestyle="-" if len(px) > 1 else "none", label=text)
    ax.set_xlabel(axis.path)
    ax.set_ylabel(label(name), fontsize=8)
    ax.ticklabel_format(axis="y", useOffset=False)
    if ticks is not None:
        ax.set_xticks(xs, ticks, rotation=20)
        ax.set_xlim(-0.5, len(xs) - 0.5)
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=7, loc="best")
