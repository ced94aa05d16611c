"""Per-run metrics: a few flat numbers and flags read from a run's summary.

The summary of :class:`adapt.runner.Runner` is the contract; a key it does
not have is a metric the run does not have (left out, never an error), so
the same sweep code serves scenarios with and without an interception goal.

metric                                   read from the summary
---------------------------------------  ---------------------------------------------------
``caught`` (flag)                        ``intercept.caught``
``catch_t``                              ``intercept.t`` (seconds; only when caught)
``reachable`` (flag)                     ``intercept.reachable``
``baseline_caught`` (flag)               ``baseline.caught``
``baseline_catch_t``                     ``baseline.t``
``tracking_error_m``                     ``tracking_error_m[obj].median`` (1)
``imagination_error_m``                  ``imagination_error_m[obj].median`` (1)
``camera_position_error_m``              ``camera_position_error_m.median``
``camera_rotation_error_deg``            ``camera_rotation_error_deg.median``
``prediction_error_m@H``                 ``prediction_error_m[H].mirror.median``
``baseline_prediction_error_m@H``        ``prediction_error_m[H].baseline.median``
``bounce_prediction_error_m@H``          ``prediction_error_m[H].mirror.bounce_median``
``baseline_bounce_prediction_error_m@H`` ``prediction_error_m[H].baseline.bounce_median``
``frames``                               ``frames``
``frames_per_s`` (timing)                ``frames_per_s``
``wall_s`` (timing)                      ``wall_s``

(1) of the interception's object when the summary names one
(``intercept.object``), otherwise of the object with the largest median: a
run is as well tracked as its worst-tracked object.  ``H`` is a prediction
horizon in seconds as the summary writes it (``0.5``).

A metric ``baseline_<name>`` is the baseline's peer of ``<name>`` (a
constant-velocity Kalman filter driving a simulated robot, run on the same
sightings): the aggregate compares them run by run and the plots draw them
side by side.  Timing metrics differ from machine to machine; every other
metric of a run depends only on its seed and its overrides.

Examples
--------
>>> s = {"frames": 90, "frames_per_s": 20.0, "wall_s": 4.5,
...      "intercept": {"object": "ball", "caught": True, "t": 2.1, "reachable": True},
...      "baseline": {"caught": False, "t": None},
...      "tracking_error_m": {"ball": {"median": 0.02}, "other": {"median": 0.05}},
...      "prediction_error_m": {"0.5": {"mirror": {"median": 0.04, "bounce_median": None},
...                                     "baseline": {"median": 0.09}}}}
>>> m = metrics_of(s)
>>> m["caught"], m["baseline_caught"], m["catch_t"], "baseline_catch_t" in m
(True, False, 2.1, False)
>>> m["tracking_error_m"], m["prediction_error_m@0.5"], m["baseline_prediction_error_m@0.5"]
(0.02, 0.04, 0.09)
>>> metrics_of({"frames": 3})
{'frames': 3}
"""

from __future__ import annotations

import math
from typing import Any, Mapping

__all__ = ["metrics_of", "peer_of", "is_flag", "TIMING", "BASELINE", "order_key", "label"]

#: Metrics that measure the machine rather than the run.
TIMING = frozenset({"frames_per_s", "wall_s"})

#: The prefix of a baseline's metric.
BASELINE = "baseline_"

_FLAGS = ("caught", "reachable", "baseline_caught")

#: The order of metrics in tables (a horizon's metrics follow their family).
_ORDER = ("caught", "baseline_caught", "reachable", "catch_t", "baseline_catch_t",
          "tracking_error_m", "imagination_error_m", "prediction_error_m",
          "baseline_prediction_error_m", "bounce_prediction_error_m",
          "baseline_bounce_prediction_error_m", "camera_position_error_m",
          "camera_rotation_error_deg", "frames", "frames_per_s", "wall_s")

_LABELS = {
    "caught": "caught", "reachable": "reachable", "catch_t": "time to catch (s)",
    "tracking_error_m": "tracking error (m)", "imagination_error_m": "imagination error (m)",
    "camera_position_error_m": "camera position error (m)",
    "camera_rotation_error_deg": "camera rotation error (deg)",
    "prediction_error_m": "prediction error (m)",
    "bounce_prediction_error_m": "prediction error after a bounce (m)",
    "frames": "frames", "frames_per_s": "frames/s", "wall_s": "wall time (s)",
}


def _number(v: Any) -> float | None:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    return float(v) if math.isfinite(v) else None


def _get(summary: Mapping[str, Any], *path: str) -> Any:
    node: Any = summary
    for p in path:
        if not isinstance(node, Mapping) or p not in node:
            return None
        node = node[p]
    return node


def _per_object(summary: Mapping[str, Any], key: str, target: Any) -> float | None:
    table = summary.get(key)
    if not isinstance(table, Mapping):
        return None
    medians: dict[str, float] = {}
    for name in table:
        v = _number(_get(table, name, "median"))
        if v is not None:
            medians[str(name)] = v
    if not medians:
        return None
    if isinstance(target, str) and target in medians:
        return medians[target]
    return max(medians.values())


def metrics_of(summary: Mapping[str, Any]) -> dict[str, Any]:
    """The run's metrics (see the module docstring); a missing key gives no metric."""
    out: dict[str, Any] = {}

    def flag(name: str, value: Any) -> None:
        if isinstance(value, bool):
            out[name] = value

    def number(name: str, value: Any) -> None:
        v = _number(value)
        if v is not None:
            out[name] = v

    flag("caught", _get(summary, "intercept", "caught"))
    number("catch_t", _get(summary, "intercept", "t"))
    flag("reachable", _get(summary, "intercept", "reachable"))
    flag("baseline_caught", _get(summary, "baseline", "caught"))
    number("baseline_catch_t", _get(summary, "baseline", "t"))
    target = _get(summary, "intercept", "object")
    number("tracking_error_m", _per_object(summary, "tracking_error_m", target))
    number("imagination_error_m", _per_object(summary, "imagination_error_m", target))
    number("camera_position_error_m", _get(summary, "camera_position_error_m", "median"))
    number("camera_rotation_error_deg", _get(summary, "camera_rotation_error_deg", "median"))
    horizons = summary.get("prediction_error_m")
    if isinstance(horizons, Mapping):
        for h, sources in horizons.items():
            if not isinstance(sources, Mapping):
                continue
            for src, prefix in (("mirror", ""), ("baseline", BASELINE)):
                number(f"{prefix}prediction_error_m@{h}", _get(sources, src, "median"))
                number(f"{prefix}bounce_prediction_error_m@{h}",
                       _get(sources, src, "bounce_median"))
    frames = summary.get("frames")
    if isinstance(frames, int) and not isinstance(frames, bool):
        out["frames"] = frames
    number("frames_per_s", summary.get("frames_per_s"))
    number("wall_s", summary.get("wall_s"))
    return out


def is_flag(name: str) -> bool:
    """True for a yes/no metric (aggregated as a rate).

    >>> is_flag("caught"), is_flag("catch_t")
    (True, False)
    """
    return name in _FLAGS


def peer_of(name: str) -> str | None:
    """The baseline's metric that ``name`` is compared with, or None.

    >>> peer_of("caught"), peer_of("prediction_error_m@0.5"), peer_of("baseline_caught")
    ('baseline_caught', 'baseline_prediction_error_m@0.5', None)
    >>> peer_of("tracking_error_m") is None
    True
    """
    if name.startswith(BASELINE):
        return None
    family = name.split("@")[0]
    if family in ("caught", "catch_t", "prediction_error_m", "bounce_prediction_error_m"):
        return BASELINE + name
    return None


def order_key(name: str) -> tuple[int, float, str]:
    """Sort key that lists metrics in the module docstring's order (horizons ascending).

    >>> sorted(["wall_s", "prediction_error_m@1", "caught", "prediction_error_m@0.5"],
    ...        key=order_key)
    ['caught', 'prediction_error_m@0.5', 'prediction_error_m@1', 'wall_s']
    """
    family, _, h = name.partition("@")
    rank = _ORDER.index(family) if family in _ORDER else len(_ORDER)
    try:
        horizon = float(h) if h else 0.0
    except ValueError:
        horizon = 0.0
    return rank, horizon, name


def label(name: str) -> str:
    """A human label for plots: ``prediction error (m), 0.5 s ahead``.

    >>> label("baseline_prediction_error_m@0.5")
    'prediction error (m), 0.5 s ahead'
    """
    family, _, h = name.partition("@")
    if family.startswith(BASELINE):
        family = family[len(BASELINE):]
    text = _LABELS.get(family, family)
    return f"{text}, {h} s ahead" if h else text
