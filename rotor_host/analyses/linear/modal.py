"""Which modes a report speaks of: the frequency band in which the least stable mode is ranked,
the critical speeds (where the 1x line crosses a damped natural frequency that can ring), and
whether a run's 1x peak lies at one of them. Plain numbers in, plain numbers and sentences out;
``stability`` (the damped modes over speed), ``campbell`` (its figures) and ``waterfall`` /
``crossings`` (a run-up's peak) use them. How an engineer reads them: docs/campbell.md.

The rules, each a constant here and written into every report that applies it:

* **Ranking band.** The least stable mode is looked for among the modes whose damped frequency
  lies at or below ``RANK_UP_TO`` (2) times the top speed of the range: every whirl and whip
  (below 1x), every mode an unbalance (1x) or a twice-per-revolution force (2x, misalignment,
  a cracked shaft) can drive anywhere in the range. A mode far above, such as a 3 kHz bending
  mode of a shaft without damping (log decrement 0 at every speed), would otherwise be named
  "least stable" at every speed and hide the modes that matter; the modes beyond the band are
  still reported, in one line (their least log decrement), so an instability there is not lost.
* **Critical speeds.** A 1x crossing counts as a critical speed when the mode's amplification
  factor AF = pi / delta is at least ``AF_CRITICALLY_DAMPED`` (2.5): API 617 and API 684 call
  a mode with AF < 2.5 critically damped, one that gives no resonance peak and needs no
  separation margin (log decrement above pi / 2.5 = 1.26; the oil-film modes near standstill
  reach 10). Such
  crossings are listed apart, as "1x crossings of heavily damped modes", not as critical speeds.
"""

from __future__ import annotations

import math

import numpy as np

RANK_UP_TO = 2.0  # the ranking band: modes up to this multiple of the range's top speed
AF_CRITICALLY_DAMPED = 2.5  # API 684: amplification factor below which a mode is critically damped
LOG_DEC_HEAVY = math.pi / AF_CRITICALLY_DAMPED  # 1.257: log decrement above which a mode gives no peak
ROUND_OFF_LOG_DEC = 1e-4  # |log dec| below this: undamped to round-off (no shaft damping)
PEAK_TOLERANCE = 0.10  # a 1x peak within 10 % of a critical speed (plus a window's speed change) is at it


def band_hz(top_speed_hz: float, multiple: float = RANK_UP_TO) -> float:
    """The upper end [Hz] of the ranking band: ``multiple`` times the top speed."""
    if not (math.isfinite(multiple) and multiple > 0.0):
        raise ValueError(f"rank up to {multiple!r} x the top speed: expected a finite number > 0")
    return float(multiple) * float(top_speed_hz)


def band_rule(multiple: float, band: float) -> str:
    """The ranking rule in words, as every report writes it."""
    why = ("every whirl, and every mode a 1x or 2x force can drive in the range" if multiple >= 2.0 else
           "every whirl, and every mode the 1x can drive in the range" if multiple >= 1.0 else
           "below the 1x line at the top speed")
    return f"least stable mode ranked among the modes up to {multiple:g} x the top speed ({band:.4g} Hz): {why}"


def least_in_band(freq_hz: np.ndarray, log_dec: np.ndarray, band: float) -> int | None:
    """Index of the smallest log decrement among the modes with damped frequency <= ``band``
    [Hz]; None when no mode lies in the band."""
    inside = np.flatnonzero(np.asarray(freq_hz) <= band)
    if inside.size == 0:
        return None
    return int(inside[np.argmin(np.asarray(log_dec)[inside])])


def amplification_factor(log_dec: float) -> float:
    """AF = pi / delta, the peak response over the static one of a lightly damped mode (inf at
    delta <= 0)."""
    return math.pi / log_dec if log_dec > 0.0 else math.inf


def critical_speeds(points, n_modes: int | None = None) -> list[dict]:
    """Speeds where the 1x line crosses the k-th lowest damped natural frequency (k < n_modes;
    None: every rank), linearly interpolated between consecutive speeds with an equilibrium:
    [{speed_hz, mode (1-based rank), log_dec, whirl, amplification_factor, heavily_damped}], by
    speed. The k-th lowest frequency is continuous in speed even where two modes veer, so a
    crossing is found whichever mode carries it. ``heavily_damped``: AF < 2.5, no critical speed
    (see the module docstring); so is a rank that jumps where an overdamped oil-film mode turns
    oscillatory near standstill (its log decrement ~10 enters the interpolation)."""
    out = []
    for a, b in zip(points, points[1:]):
        if not (a.ok and b.ok):
            continue
        ranks = min(a.freq_hz.size, b.freq_hz.size)
        for k in range(ranks if n_modes is None else min(n_modes, ranks)):
            ga, gb = a.freq_hz[k] - a.speed_hz, b.freq_hz[k] - b.speed_hz
            if ga > 0.0 >= gb or ga < 0.0 <= gb:
                w = ga / (ga - gb)
                near = a if w < 0.5 else b
                ld = float((1 - w) * a.log_dec[k] + w * b.log_dec[k])
                out.append({"speed_hz": float(a.speed_hz + w * (b.speed_hz - a.speed_hz)), "mode": k + 1,
                            "log_dec": ld, "whirl": float(near.whirl[k]),
                            "amplification_factor": min(amplification_factor(ld), 1e9),
                            "heavily_damped": bool(max(ld, a.log_dec[k], b.log_dec[k]) > LOG_DEC_HEAVY)})
    return sorted(out, key=lambda d: d["speed_hz"])


def split_crossings(crossings: list[dict]) -> tuple[list[dict], list[dict]]:
    """(critical speeds, 1x crossings of heavily damped modes)."""
    return ([c for c in crossings if not c["heavily_damped"]], [c for c in crossings if c["heavily_damped"]])


def no_critical_line(lo_hz: float, hi_hz: float, damped: list[dict] = ()) -> str:
    """The line a report prints when no critical speed lies in lo-hi Hz."""
    also = ""
    if damped:
        also = (f" (the 1x line crosses {len(damped)} heavily damped mode(s), log dec >= "
                f"{min(c['log_dec'] for c in damped):.3g}, AF < {AF_CRITICALLY_DAMPED:g}: no resonance)")
    return f"no critical speed in {lo_hz:g}-{hi_hz:g} Hz: the 1x line crosses no lightly damped natural frequency{also}"


def least_beyond(points, band: float) -> tuple[float, float, float] | None:
    """(log dec, frequency [Hz], speed [Hz]) of the least stable mode above ``band`` over the
    points (SpeedPoints with an equilibrium), None when no mode lies above it."""
    out = None
    for p in points:
        above = np.flatnonzero(p.freq_hz > band)
        if above.size:
            i = int(above[np.argmin(p.log_dec[above])])
            if out is None or p.log_dec[i] < out[0]:
                out = (float(p.log_dec[i]), float(p.freq_hz[i]), float(p.speed_hz))
    return out


def beyond_band_line(least: tuple[float, float, float] | None, band: float) -> str:
    """One line on the modes above the ranking band: ``least`` is (log dec, frequency [Hz],
    speed [Hz]) of the least stable of them over the sweep, None when there are none."""
    if least is None:
        return f"no mode above {band:.4g} Hz among those computed"
    ld, f, s = least
    if abs(ld) < ROUND_OFF_LOG_DEC:
        what = "undamped to round-off (e.g. a shaft without damping, damping_beta_s = 0)"
    elif ld < 0.0:
        what = "UNSTABLE: a mode beyond the band grows; widen the band to rank it"
    else:
        what = "stable"
    return f"modes above {band:.4g} Hz (not ranked): least log dec {ld:.3g} ({f:.4g} Hz at {s:g} Hz), {what}"


def peak_tolerance_hz(critical_hz: float, window_speed_change_hz: float) -> float:
    """How far a 1x peak may lie from the critical speed it belongs to: ``PEAK_TOLERANCE`` of
    the critical speed (a run-up peaks a little above it, the response lagging the sweeping
    force; a coast-down below) plus the speed change over one spectrum window."""
    return PEAK_TOLERANCE * abs(critical_hz) + abs(window_speed_change_hz)


def critical_near(peak_hz: float, criticals: list[dict], window_speed_change_hz: float = 0.0) -> dict | None:
    """The critical speed nearest the 1x peak at ``peak_hz`` among those within their
    ``peak_tolerance_hz``, else None."""
    near = [c for c in criticals
            if abs(c["speed_hz"] - peak_hz) <= peak_tolerance_hz(c["speed_hz"], window_speed_change_hz)]
    return min(near, key=lambda d: abs(d["speed_hz"] - peak_hz)) if near else None


__all__ = ["RANK_UP_TO", "AF_CRITICALLY_DAMPED", "LOG_DEC_HEAVY", "band_hz", "band_rule", "least_in_band",
           "amplification_factor", "critical_speeds", "split_crossings", "least_beyond", "no_critical_line",
           "beyond_band_line",
           "critical_near", "peak_tolerance_hz"]
