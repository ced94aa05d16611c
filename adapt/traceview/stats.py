"""Summary figures of a run, computed in one streaming pass over its trace.

Examples
--------
>>> series = SizeSeries(capacity=4)
>>> for d in range(10):
...     series.add(d, 100 + d)
>>> series.points
((0, 100), (4, 104), (8, 108))
>>> sparkline([1, 2, 3, 8])
'▁▂▃█'
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any

from adapt.traceview.reader import Trace
from adapt.traceview.show import impasse_text

__all__ = ["SizeSeries", "TraceStats", "compute_stats", "format_stats", "sparkline"]

_BLOCKS = "▁▂▃▄▅▆▇█"


def sparkline(values: list[int] | list[float]) -> str:
    """One character per value, ``▁`` (lowest) to ``█`` (highest)."""
    if not values:
        return ""
    lo, hi = min(values), max(values)
    span = hi - lo
    return "".join(_BLOCKS[0 if span == 0 else round((v - lo) / span * 7)] for v in values)


class SizeSeries:
    """``(decision, size)`` samples of a long run in bounded memory.

    Keeps every ``step``-th decision; when ``capacity`` samples are held, every
    other one is dropped and ``step`` doubles.
    """

    __slots__ = ("capacity", "step", "_points")

    def __init__(self, capacity: int = 256) -> None:
        self.capacity = capacity
        self.step = 1
        self._points: list[tuple[int, int]] = []

    def add(self, decision: int, size: int) -> None:
        """Record the size at the end of a decision cycle."""
        if decision % self.step:
            return
        self._points.append((decision, size))
        if len(self._points) >= self.capacity:
            self.step *= 2
            self._points = [p for p in self._points if p[0] % self.step == 0]

    @property
    def points(self) -> tuple[tuple[int, int], ...]:
        """The samples kept, in decision order."""
        return tuple(self._points)


@dataclass(frozen=True)
class TraceStats:
    """What :func:`compute_stats` finds.  ``wm_*`` are ``None`` below level 4."""

    path: str
    level: int
    files: tuple[str, ...]
    seed: int | None
    #: Decision phases run: the footer's count when it has one, else the decision records.
    decisions: int
    cycles: int
    firings: dict[str, int]
    retractions: int
    impasses: dict[str, int]
    max_goal_depth: int
    wm_final: int | None
    wm_min: int | None
    wm_max: int | None
    wm_mean: float | None
    wm_series: tuple[tuple[int, int], ...]
    phase_time_s: dict[str, float]
    phase_counts: dict[str, int]
    schema_events: int
    stop_reason: str | None
    elapsed_s: float | None
    error: str | None = None
    notices: tuple[str, ...] = field(default=())

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (``adapt trace stats --json``)."""
        return {
            "trace": self.path,
            "level": self.level,
            "files": list(self.files),
            "seed": self.seed,
            "decisions": self.decisions,
            "cycles": self.cycles,
            "production_firings": sum(self.firings.values()),
            "firings_per_rule": self.firings,
            "retractions": self.retractions,
            "impasses": self.impasses,
            "max_goal_depth": self.max_goal_depth,
            "wm_size": None if self.wm_final is None else {
                "final": self.wm_final, "min": self.wm_min, "max": self.wm_max,
                "mean": self.wm_mean, "series": [list(p) for p in self.wm_series],
            },
            "phases": {p: {"count": n, "time_s": self.phase_time_s.get(p)}
                       for p, n in self.phase_counts.items()},
            "schema_events": self.schema_events,
            "stop_reason": self.stop_reason,
            "error": self.error,
            "elapsed_s": self.elapsed_s,
            "notices": list(self.notices),
        }


def compute_stats(trace: Trace, series_points: int = 256) -> TraceStats:
    """Read the whole trace once and summarise it (memory bounded by live WM)."""
    firings: Counter[str] = Counter()
    impasses: Counter[str] = Counter()
    phase_time: dict[str, float] = {}
    phase_counts: Counter[str] = Counter()
    track_wm = trace.header.level >= 4
    live: set[int] = {w[0] for w in trace.initial_wmes()} if track_wm else set()
    series = SizeSeries(series_points)
    wm_min: int | None = None
    wm_max = 0
    wm_total = 0
    wm_samples = 0
    decisions = retractions = schema_events = max_depth = cycles = 0
    footer: dict[str, Any] | None = None

    def sample(cycle: int) -> None:
        nonlocal wm_min, wm_max, wm_total, wm_samples
        size = len(live)
        series.add(cycle, size)
        wm_min = size if wm_min is None else min(wm_min, size)
        wm_max = max(wm_max, size)
        wm_total += size
        wm_samples += 1

    for cycle, records in trace.cycles():
        cycles += 1
        for record in records:
            kind = record["kind"]
            if kind == "phase":
                name = str(record.get("phase"))
                phase_counts[name] += 1
                if isinstance(record.get("time_s"), (int, float)):
                    phase_time[name] = phase_time.get(name, 0.0) + float(record["time_s"])
                for f in record.get("firings") or ():
                    firings[str(f.get("rule"))] += 1
                retractions += len(record.get("retractions") or ())
                if track_wm:
                    # adds first: a WME can be added and removed in one phase
                    live.update(a[0] for a in record.get("adds") or ())
                    live.difference_update(record.get("removes") or ())
            elif kind == "decision":
                decisions += 1
                level = int(record.get("level") or 0)
                max_depth = max(max_depth, level + 1)
                if record.get("impasse"):
                    impasses[impasse_text(record["impasse"])] += 1
                    max_depth = max(max_depth, level + 2)
            elif kind == "schema":
                schema_events += 1
        if track_wm:
            sample(cycle)
    footer = trace.footer()
    # The footer counts the decision phases the agent started, as the run's own summary
    # and the HTML page say; a run interrupted inside a decision phase may not have
    # written that last decision's record.
    counted = footer.get("decisions") if footer is not None else None
    if isinstance(counted, int) and counted > decisions:
        decisions = counted
    return TraceStats(
        path=trace.path,
        level=trace.header.level,
        files=trace.header.files,
        seed=trace.header.seed,
        decisions=decisions,
        cycles=cycles,
        firings=dict(sorted(firings.items(), key=lambda kv: (-kv[1], kv[0]))),
        retractions=retractions,
        impasses=dict(sorted(impasses.items(), key=lambda kv: (-kv[1], kv[0]))),
        max_goal_depth=max_depth,
        wm_final=len(live) if track_wm else None,
        wm_min=wm_min if track_wm else None,
        wm_max=wm_max if track_wm else None,
        wm_mean=round(wm_total / wm_samples, 2) if track_wm and wm_samples else None,
        wm_series=series.points,
        phase_time_s={k: round(v, 6) for k, v in phase_time.items()},
        phase_counts=dict(phase_counts),
        schema_events=schema_events,
        stop_reason=None if footer is None else footer.get("stop_reason"),
        elapsed_s=None if footer is None else footer.get("elapsed_s"),
        error=None if footer is None else footer.get("error"),
        notices=tuple(trace.notices),
    )


def format_stats(stats: TraceStats) -> str:
    """The human-readable report of ``adapt trace stats``."""
    lines = [f"trace: {stats.path} (level {stats.level}, seed {stats.seed})"]
    if stats.files:
        lines.append("rule files: " + ", ".join(stats.files))
    stop = stats.stop_reason or "no footer: the run did not end normally"
    if stats.error:
        stop += f": {stats.error.splitlines()[0]}"
    lines.append(f"decisions: {stats.decisions} (stopped: {stop})")
    if stats.elapsed_s is not None:
        lines.append(f"run time: {stats.elapsed_s:g} s")
    if stats.level >= 3:
        total = sum(stats.firings.values())
        lines.append(f"production firings: {total} ({stats.retractions} retractions)")
        width = max((len(r) for r in stats.firings), default=0)
        lines.extend(f"  {rule:<{width}}  {n:>8}" for rule, n in stats.firings.items())
    total_imp = sum(stats.impasses.values())
    detail = ", ".join(f"{k} {n}" for k, n in stats.impasses.items())
    lines.append(f"impasses: {total_imp}" + (f" ({detail})" if detail else ""))
    lines.append(f"deepest goal stack: {stats.max_goal_depth}")
    if stats.wm_final is not None:
        lines.append(
            f"working memory: final {stats.wm_final}, min {stats.wm_min}, "
            f"max {stats.wm_max}, mean {stats.wm_mean}"
        )
        if stats.wm_series:
            first, last = stats.wm_series[0][0], stats.wm_series[-1][0]
            sizes = [s for _, s in stats.wm_series]
            if len(sizes) > 64:
                sizes = [sizes[round(i * (len(sizes) - 1) / 63)] for i in range(64)]
            lines.append(f"  size over decisions {first}..{last}: {sparkline(sizes)}")
    if stats.phase_time_s:
        lines.append("time per phase:")
        lines.extend(f"  {p:<9} {t:.6f} s" for p, t in stats.phase_time_s.items())
    if stats.schema_events:
        lines.append(f"schema events: {stats.schema_events}")
    return "\n".join(lines)
