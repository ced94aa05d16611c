"""Statistics of a sweep's runs: rates with Wilson intervals, distribution summaries.

* A **rate** (how often the robot caught the ball) is ``k`` of ``n`` with the
  **Wilson score interval** at 95 % (``z = 1.959964``): unlike the normal
  approximation it stays inside [0, 1] and is honest for 0 or ``n``
  successes and for small ``n`` (Wilson 1927; Brown, Cai and DasGupta 2001).
* A **distribution** (an error over runs) is summarised by its count, mean,
  minimum, maximum, the 10th, 25th, 50th, 75th and 90th percentiles (linear
  interpolation, NumPy's default), and a distribution-free 95 % interval for
  the median from order statistics (the binomial method; none below 6
  values, where no such interval reaches 95 %).

Examples
--------
>>> r = rate(8, 10)
>>> r["rate"], r["low"], r["high"]
(0.8, 0.4902, 0.9433)
>>> rate(0, 0)["rate"] is None
True
>>> d = describe([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7])
>>> d["median"], d["p25"], d["n"], (d["median_low"], d["median_high"])
(0.4, 0.25, 7, (0.1, 0.7))
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

__all__ = ["rate", "describe", "wilson", "median_interval", "Z95", "DIGITS"]

#: The normal quantile of a two-sided 95 % interval.
Z95 = 1.959963984540054

#: Decimal places kept in ``sweep.json``.
DIGITS = 4


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of ``k`` successes in ``n`` trials.

    Examples
    --------
    >>> [round(v, 4) for v in wilson(0, 20)]
    [0.0, 0.1611]
    >>> [round(v, 4) for v in wilson(20, 20)]
    [0.8389, 1.0]
    """
    if n <= 0:
        raise ValueError("wilson: n must be positive")
    if not 0 <= k <= n:
        raise ValueError(f"wilson: k must be in 0..{n}, got {k}")
    p = k / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z / (1 + z2 / n) * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def rate(k: int, n: int) -> dict[str, Any]:
    """``{"k", "n", "rate", "low", "high"}`` with the 95 % Wilson interval (None when n = 0)."""
    if n == 0:
        return {"k": 0, "n": 0, "rate": None, "low": None, "high": None}
    low, high = wilson(k, n)
    return {"k": k, "n": n, "rate": round(k / n, DIGITS), "low": round(low, DIGITS),
            "high": round(high, DIGITS)}


def median_interval(values: Sequence[float], level: float = 0.95) -> tuple[float, float] | None:
    """A distribution-free interval for the median: order statistics ``(x_j, x_k)`` of the
    sorted values, the narrowest symmetric pair with binomial coverage >= ``level``.

    Examples
    --------
    >>> median_interval([5.0, 1.0, 4.0, 2.0, 3.0]) is None  # 5 values cannot reach 95 %
    True
    >>> median_interval(list(range(1, 21)))
    (6, 15)
    """
    xs = sorted(values)
    n = len(xs)
    if n == 0:
        return None
    pmf = [math.comb(n, i) / 2.0 ** n for i in range(n + 1)]
    # coverage of (x_(j), x_(n+1-j)) (1-based) is P(j <= B <= n - j), B ~ Bin(n, 1/2)
    best = None
    for j in range(1, n // 2 + 1):
        cover = sum(pmf[j:n - j + 1])
        if cover >= level:
            best = j
        else:
            break
    if best is None:
        return None
    return xs[best - 1], xs[n - best]


def describe(values: Sequence[float]) -> dict[str, Any]:
    """Count, mean, min, max, percentiles and the median's 95 % interval (see the module
    docstring); only ``{"n": 0}`` for no values."""
    if not values:
        return {"n": 0}
    a = np.asarray(values, dtype=float)
    p10, p25, p50, p75, p90 = (float(v) for v in np.percentile(a, [10, 25, 50, 75, 90]))
    ci = median_interval(list(a))

    def r(v: float) -> float:
        return round(float(v), DIGITS)

    return {"n": int(a.size), "median": r(p50),
            "median_low": None if ci is None else r(ci[0]),
            "median_high": None if ci is None else r(ci[1]),
            "mean": r(float(a.mean())), "min": r(float(a.min())), "max": r(float(a.max())),
            "p10": r(p10), "p25": r(p25), "p75": r(p75), "p90": r(p90)}
