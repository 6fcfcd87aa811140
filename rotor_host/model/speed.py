"""Shaft speed over time: constant, or a run-up / coast-down profile.

A profile is piecewise linear in time through points (t_k, f_k) [s, Hz] and constant before the
first and after the last point, so a linear ramp f0 -> f1 over [t0, t1] is two points and a
measured speed table is many. What the rotor needs from it, all exact for a piecewise-linear
speed:

* ``omega(t)`` [rad/s]: the bearings' input and the gyroscopic term Omega G;
* ``alpha(t)`` [rad/s^2]: the angular acceleration, whose unbalance force is m r alpha along
  the tangent (ahead of the mass);
* ``angle(t)`` [rad]: the integrated shaft angle, which places the unbalance mass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class SpeedProfile:
    """Piecewise-linear shaft speed through (times_s[k], speeds_hz[k]); constant outside."""

    times_s: tuple[float, ...]
    speeds_hz: tuple[float, ...]

    def __post_init__(self):
        t, f = np.asarray(self.times_s, float), np.asarray(self.speeds_hz, float)
        if t.ndim != 1 or t.size < 1 or t.size != f.size:
            raise ValueError(f"speed profile: times_s and speeds_hz must be lists of equal length >= 1, got "
                             f"{t.size} and {f.size}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
            raise ValueError("speed profile: times and speeds must be finite numbers")
        if np.any(np.diff(t) <= 0.0):
            raise ValueError(f"speed profile: times_s must increase strictly, got {list(t)}")
        if np.any(f <= 0.0):
            raise ValueError(f"speed profile: speeds_hz must be > 0 (a hydrodynamic bearing carries no load at "
                             f"rest), got {list(f)}")

    @classmethod
    def constant(cls, speed_hz: float) -> "SpeedProfile":
        return cls((0.0,), (float(speed_hz),))

    @classmethod
    def ramp(cls, f0_hz: float, f1_hz: float, t1_s: float, t0_s: float = 0.0) -> "SpeedProfile":
        return cls((t0_s, t1_s), (f0_hz, f1_hz))

    @property
    def is_constant(self) -> bool:
        return len(set(self.speeds_hz)) == 1

    def hz(self, t):
        """Shaft speed [Hz] at t [s]: a float, or an array for an array of times."""
        v = np.interp(t, self.times_s, self.speeds_hz)
        return float(v) if np.ndim(v) == 0 else v

    def omega(self, t: float) -> float:
        """Shaft speed [rad/s] at t."""
        return TWO_PI * self.hz(t)

    def alpha(self, t: float) -> float:
        """Angular acceleration [rad/s^2] at t (the right-hand slope at a profile point)."""
        ts, fs = self.times_s, self.speeds_hz
        if len(ts) < 2 or t < ts[0] or t >= ts[-1]:
            return 0.0
        k = int(np.searchsorted(ts, t, side="right")) - 1
        return TWO_PI * (fs[k + 1] - fs[k]) / (ts[k + 1] - ts[k])

    def angle(self, t: float) -> float:
        """Shaft angle [rad] turned from t = 0 to t: the exact integral of omega."""
        return self._integral(t) - self._integral(0.0)

    def _integral(self, t: float) -> float:
        """Integral of omega from the first profile time to t (negative before it)."""
        ts, fs = self.times_s, self.speeds_hz
        if t <= ts[0]:
            return TWO_PI * fs[0] * (t - ts[0])
        total = 0.0
        for k in range(len(ts) - 1):
            a, b = ts[k], min(ts[k + 1], t)
            if b <= a:
                break
            fb = fs[k] + (fs[k + 1] - fs[k]) * (b - a) / (ts[k + 1] - ts[k])
            total += 0.5 * (fs[k] + fb) * (b - a)
            if t <= ts[k + 1]:
                return TWO_PI * total
        return TWO_PI * (total + fs[-1] * (t - ts[-1]))

    def describe(self) -> str:
        if self.is_constant:
            return f"{self.speeds_hz[0]:g} Hz"
        return " -> ".join(f"{f:g} Hz at {t:g} s" for t, f in zip(self.times_s, self.speeds_hz))
