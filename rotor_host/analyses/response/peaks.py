"""Resonance peaks of an unbalance response, their half-power amplification factor and the
separation margins of API 617 / API RP 684.

**Peak.** A grid point whose amplitude exceeds both neighbours'; its speed and amplitude are
then refined between those neighbours by Brent's bounded search on the response itself
(each evaluation is a new solve at that speed, with the bearings' coefficients there), to
``PEAK_XTOL`` of the speed.

**Half-power amplification factor** (API RP 684, the "half-power bandwidth method"; API 617,
7th ed., 2.6.2.10)::

    AF = N_c1 / (N_2 - N_1)

N_c1 the peak speed, N_1 < N_c1 < N_2 the speeds where the amplitude falls to the peak's
1 / sqrt(2) (each found by Brent's root search on the response between the grid points that
bracket it). For a lightly damped single mode AF = 1 / (2 zeta) = pi / delta. When the curve does
not fall to the half-power level on either side, before the range ends or before it climbs above
the peak (a shoulder of a higher resonance), the AF is unknown (None) and the peak is not
classed as a critical speed or not.

**Required separation margin** (API 617, 7th ed., 2.6.2.10; API RP 684 repeats it), in percent
of the minimum operating speed for a peak below it, of the maximum continuous speed for one
above it:

* AF < 2.5: the mode is critically damped, no margin is required (not a critical speed);
* 2.5 <= AF <= 3.55: 5 % below, 15 % above;
* AF > 3.55: ``16 - 6 / (AF - 3)`` below, ``26 - 6 / (AF - 3)`` above (the same numbers at
  3.55, tending to 16 % and 26 % for an undamped resonance).

**Separation margin** of a peak at N_c: ``100 (N_min - N_c) / N_min`` below the operating range,
``100 (N_c - N_max) / N_max`` above it; inside the range it is negative (the larger of the two
expressions, the side the peak is nearer), and the requirement of that side applies.
"""

from __future__ import annotations

import math

import numpy as np

AF_CRITICAL = 2.5  # API 617 / 684: below this a resonance is critically damped, not a critical speed
AF_LOW_BAND = 3.55  # up to this the fixed margins 5 % (below) and 15 % (above) apply
PEAK_XTOL = 1e-6  # refinement tolerance, relative to the speed
HALF_POWER = 1.0 / math.sqrt(2.0)


def grid_peaks(amplitude) -> list[int]:
    """Indices of the interior grid points whose amplitude is above the left neighbour's and not
    below the right one's (a flat top counts once); NaN points (no equilibrium) break the curve."""
    a = np.asarray(amplitude, float)
    out = []
    for i in range(1, a.size - 1):
        if np.isfinite(a[i - 1:i + 2]).all() and a[i] > a[i - 1] and a[i] >= a[i + 1]:
            out.append(i)
    return out


def refine_peak(amp, lo: float, hi: float) -> tuple[float, float]:
    """(speed, amplitude) of the maximum of ``amp(speed)`` in [lo, hi] by Brent's bounded search."""
    from scipy.optimize import minimize_scalar

    r = minimize_scalar(lambda s: -amp(s), bounds=(lo, hi), method="bounded",
                        options={"xatol": PEAK_XTOL * max(abs(lo), abs(hi))})
    return float(r.x), float(-r.fun)


def half_power_speeds(amp, speeds, amplitude, peak_hz: float, peak: float) -> tuple[float | None, float | None]:
    """(N_1, N_2): where ``amp`` falls to ``peak`` / sqrt 2 below and above the peak at ``peak_hz``,
    each by a root search between the peak (or the last grid point above the level) and the first
    grid point below the level; None on a side where the grid curve does not fall to it before
    the range ends, a NaN breaks it or it rises above the peak (a shoulder of a higher peak, not a
    resonance of its own)."""
    from scipy.optimize import brentq

    s, a = np.asarray(speeds, float), np.asarray(amplitude, float)
    level = HALF_POWER * peak

    def cross(order) -> float | None:
        inner = peak_hz  # amp(inner) >= level
        for k in order:
            if not np.isfinite(a[k]) or a[k] > peak:  # a break, or a higher peak before half power
                return None
            if a[k] < level:
                lo, hi = sorted((s[k], inner))
                return float(brentq(lambda x: amp(x) - level, lo, hi, xtol=PEAK_XTOL * hi))
            inner = s[k]
        return None

    return cross(np.flatnonzero(s < peak_hz)[::-1]), cross(np.flatnonzero(s > peak_hz))


def amplification_factor(n_peak: float, n1: float | None, n2: float | None) -> float | None:
    """API RP 684's half-power AF = N_c1 / (N_2 - N_1); None when a half-power speed is unknown."""
    if n1 is None or n2 is None or not n2 > n1:
        return None
    return n_peak / (n2 - n1)


def required_margin_pct(af: float | None, side: str) -> float | None:
    """API 617's required separation margin [%] for a peak of amplification factor ``af`` on
    ``side`` ("below" the minimum operating speed or "above" the maximum continuous one); 0 for
    AF < 2.5; None when the AF is unknown."""
    if af is None:
        return None
    if side not in ("below", "above"):
        raise ValueError(f"side {side!r}: expected 'below' or 'above'")
    if af < AF_CRITICAL:
        return 0.0
    if af <= AF_LOW_BAND:
        return 5.0 if side == "below" else 15.0
    return (16.0 if side == "below" else 26.0) - 6.0 / (af - 3.0)


def separation_margin(n_c: float, operating_hz: tuple[float, float]) -> tuple[float, str]:
    """(margin [%], side) of a peak at ``n_c`` from the operating range (min, max) [Hz]: side
    "below" or "above", the margin negative when the peak lies inside the range."""
    lo, hi = operating_hz
    below, above = 100.0 * (lo - n_c) / lo, 100.0 * (n_c - hi) / hi
    return (below, "below") if below >= above else (above, "above")


def peak_record(node: int, direction: str, speed_hz: float, amplitude_m: float, n1, n2, operating_hz,
                unstable: bool, refined: bool) -> dict:
    """The json entry of one peak (keys of the issue's ``peaks`` and what the report needs)."""
    af = amplification_factor(speed_hz, n1, n2)
    rec = {"node": node, "direction": direction, "speed_hz": speed_hz, "amplitude_m": amplitude_m,
           "amplification_factor": af, "half_power_hz": [n1, n2], "critical": None if af is None else af >= AF_CRITICAL,
           "separation_margin_pct": None, "required_margin_pct": None, "side": None, "meets_margin": None,
           "unstable": unstable, "refined": refined}
    if operating_hz is not None:
        sm, side = separation_margin(speed_hz, operating_hz)
        req = required_margin_pct(af, side)
        rec.update(separation_margin_pct=sm, side=side if sm >= 0.0 else f"inside (nearer the {side} end)",
                   required_margin_pct=req, meets_margin=None if req is None else bool(sm >= req))
    return rec


def peak_words(p: dict) -> str:
    """One line on a peak for the report and the console."""
    af = p["amplification_factor"]
    unknown = "unknown (no half-power point on one side: the range ends or a higher peak comes first)"
    head = (f"node {p['node']} {p['direction']}: {p['speed_hz']:.3f} Hz, {p['amplitude_m'] * 1e6:.4g} um 0-pk, "
            f"AF {unknown if af is None else f'{af:.3g}'}")
    if p["unstable"]:
        head += ", ABOVE THE STABILITY THRESHOLD (the steady response is not what the machine does)"
    if af is not None and af < AF_CRITICAL:
        return head + f": critically damped (AF < {AF_CRITICAL:g}), not a critical speed, no margin required"
    if p["separation_margin_pct"] is None:
        return head + ("" if af is None else ": a critical speed") + " (no operating range given: no margin)"
    req = p["required_margin_pct"]
    verdict = "" if req is None else (f", required {req:.3g} % ({'met' if p['meets_margin'] else 'NOT MET'})")
    return head + f", separation margin {p['separation_margin_pct']:.3g} % {p['side']}{verdict}"


__all__ = ["AF_CRITICAL", "AF_LOW_BAND", "grid_peaks", "refine_peak", "half_power_speeds", "amplification_factor",
           "required_margin_pct", "separation_margin", "peak_record", "peak_words"]
