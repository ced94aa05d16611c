"""A constant-velocity Kalman filter on the floor plane.

It is the foreground object schema's position and velocity filter, and the
baseline the mirror is measured against: a tracker that assumes the object
keeps its velocity cannot foresee a bounce.  The state is ``(x, y, vx, vy)``;
measurements are positions; the process noise is white acceleration of
spectral density ``q`` (m²/s³), the measurement noise ``r`` metres (standard
deviation).

Examples
--------
>>> kf = ConstantVelocityKF(q=1.0, r=0.01)
>>> for k in range(30):
...     kf.step(k / 30.0, (0.5 * k / 30.0, 1.0))
>>> [round(v, 2) for v in kf.velocity], [round(v, 3) for v in kf.predict_position(1.0)]
([0.5, 0.0], [0.983, 1.0])
"""

from __future__ import annotations

import math
from collections import deque
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["ConstantVelocityKF"]


class ConstantVelocityKF:
    """See the module docstring.

    Parameters
    ----------
    q : float
        White-acceleration spectral density, m²/s³.
    r : float
        Measurement noise, metres (standard deviation).
    gate : float or None
        Mahalanobis distance beyond which a measurement restarts the filter
        from the last two measurements instead of being blended in (a bounce
        or a re-acquired object); None: never.
    window : int
        0: the measurement noise is ``r``.  Else it is estimated from the
        scatter of the last ``window`` measurements, never below ``r``
        (see :attr:`noise`): measurements scattered more widely than ``r``
        widen the gate and the blend instead of restarting the filter on each.

    Examples
    --------
    Sightings scattered 3 cm about a straight roll: with the noise fixed at
    5 mm, 42 of the 60 restart the filter (each with a velocity from two of
    them, a metre a second off); with the noise estimated from their scatter
    (2.5 cm), none does.

    >>> rng = np.random.default_rng(0)
    >>> fixed = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0)
    >>> adaptive = ConstantVelocityKF(q=0.3, r=0.005, gate=6.0, window=15)
    >>> for k in range(60):
    ...     z = (k / 30.0 + rng.normal(0, 0.03), 1.0 + rng.normal(0, 0.03))
    ...     fixed.step(k / 30.0, z)
    ...     adaptive.step(k / 30.0, z)
    >>> fixed.restarts, adaptive.restarts, round(adaptive.noise, 3)
    (42, 0, 0.025)
    """

    def __init__(self, q: float = 4.0, r: float = 0.01, gate: float | None = None,
                 window: int = 0) -> None:
        if not (q > 0 and r > 0):
            raise ValueError("q and r must be positive")
        if window < 0:
            raise ValueError("window must be 0 or positive")
        self.q = float(q)
        self.r = float(r)
        self.gate = gate
        self.window = int(window)
        #: the last three measurements, and the last ``window`` scatters (see :attr:`noise`)
        self._seen: deque[tuple[float, NDArray[np.float64]]] = deque(maxlen=3)
        self._scatter: deque[float] = deque(maxlen=max(self.window, 1))
        self._noise = self.r
        self.x: NDArray[np.float64] = np.zeros(4)
        self.P: NDArray[np.float64] = np.eye(4)
        self.time: float | None = None
        self.updates = 0
        self.restarts = 0
        self._last: tuple[float, NDArray[np.float64]] | None = None

    @property
    def initialised(self) -> bool:
        """True after the first measurement."""
        return self.time is not None

    @property
    def position(self) -> tuple[float, float]:
        """Filtered ``(x, y)``."""
        return (float(self.x[0]), float(self.x[1]))

    @property
    def velocity(self) -> tuple[float, float]:
        """Filtered ``(vx, vy)``."""
        return (float(self.x[2]), float(self.x[3]))

    @property
    def noise(self) -> float:
        """The measurement noise in use, m: ``r``, or with a ``window`` the larger of ``r``
        and the scatter of the last ``window`` measurements about straight lines through
        their neighbours -- each measurement less the interpolation between the one before
        and the one after, scaled to one measurement's variance; their median squared
        length over ``2 ln 2`` (a squared length is exponential, of mean twice the variance
        per axis).  A turn moves one or two of them, a constant velocity none: it measures
        the sightings, not the filter's model or its state."""
        return self._noise

    def _learn_noise(self, time: float, z: NDArray[np.float64]) -> None:
        if not self.window:
            return
        seen = self._seen
        seen.append((time, z))
        if len(seen) < 3:
            return
        (t0, z0), (t1, z1), (t2, z2) = seen[-3], seen[-2], seen[-1]
        if not t0 < t1 < t2:
            return
        w = (t1 - t0) / (t2 - t0)  # z1 ~ (1 - w) z0 + w z2
        e = z1 - (1.0 - w) * z0 - w * z2
        self._scatter.append(float(e @ e) / (1.0 + (1.0 - w) ** 2 + w**2))
        spread = float(np.median(self._scatter)) / (2.0 * math.log(2.0))
        self._noise = math.sqrt(max(self.r**2, spread))

    def _predict(self, dt: float) -> None:
        if dt <= 0:
            return
        f = np.eye(4)
        f[0, 2] = f[1, 3] = dt
        q = self.q
        g = np.array([[dt**3 / 3, 0, dt**2 / 2, 0], [0, dt**3 / 3, 0, dt**2 / 2],
                      [dt**2 / 2, 0, dt, 0], [0, dt**2 / 2, 0, dt]]) * q
        self.x = f @ self.x
        self.P = f @ self.P @ f.T + g

    def step(self, time: float, z: Sequence[float] | None) -> None:
        """Advance to ``time`` and blend in the measurement ``z`` (None: predict only)."""
        if self.time is None:
            if z is None:
                return
            self.x = np.array([float(z[0]), float(z[1]), 0.0, 0.0])
            self.P = np.diag([self.r**2, self.r**2, 4.0, 4.0])
            self.time = float(time)
            self.updates = 1
            self._last = (float(time), np.array(z[:2], float))
            self._learn_noise(float(time), self._last[1])
            return
        self._predict(float(time) - self.time)
        self.time = float(time)
        if z is None:
            return
        zz = np.array([float(z[0]), float(z[1])])
        h = np.zeros((2, 4))
        h[0, 0] = h[1, 1] = 1.0
        self._learn_noise(float(time), zz)
        r = self._noise
        s = h @ self.P @ h.T + np.eye(2) * r**2
        y = zz - h @ self.x
        if self.gate is not None and self._last is not None:
            d = float(np.sqrt(y @ np.linalg.solve(s, y)))
            if d > self.gate:
                t0, z0 = self._last
                dt = float(time) - t0
                v = (zz - z0) / dt if dt > 0 else np.zeros(2)
                self.x = np.array([zz[0], zz[1], v[0], v[1]])
                self.P = np.diag([r**2, r**2, 2 * (r / max(dt, 1e-3))**2,
                                  2 * (r / max(dt, 1e-3))**2])
                self.restarts += 1
                self.updates += 1
                self._last = (float(time), zz)
                return
        k = self.P @ h.T @ np.linalg.inv(s)
        self.x = self.x + k @ y
        self.P = (np.eye(4) - k @ h) @ self.P
        self.updates += 1
        self._last = (float(time), zz)

    @property
    def position_sigma(self) -> float:
        """RMS standard deviation of the position estimate, m."""
        return math.sqrt(max(0.0, (self.P[0, 0] + self.P[1, 1]) / 2.0))

    @property
    def velocity_sigma(self) -> float:
        """RMS standard deviation of the velocity estimate, m/s."""
        return math.sqrt(max(0.0, (self.P[2, 2] + self.P[3, 3]) / 2.0))

    def reset(self, time: float, position: Sequence[float], velocity: Sequence[float],
              position_std: float, velocity_std: float) -> None:
        """Start again from a known state (after a bounce measured by other means)."""
        self.x = np.array([float(position[0]), float(position[1]),
                           float(velocity[0]), float(velocity[1])])
        self.P = np.diag([position_std**2, position_std**2, velocity_std**2, velocity_std**2])
        self.time = float(time)
        self.restarts += 1
        self._last = (float(time), np.array(position[:2], float))

    def predict_position(self, horizon: float) -> tuple[float, float]:
        """Where the filter expects the object ``horizon`` seconds after its time."""
        return (float(self.x[0] + self.x[2] * horizon), float(self.x[1] + self.x[3] * horizon))

    def copy(self) -> "ConstantVelocityKF":
        """An independent copy."""
        out = ConstantVelocityKF(self.q, self.r, self.gate, self.window)
        out.x, out.P, out.time = self.x.copy(), self.P.copy(), self.time
        out.updates, out.restarts, out._last = self.updates, self.restarts, self._last
        out._seen.extend(self._seen)
        out._scatter.extend(self._scatter)
        out._noise = self._noise
        return out
