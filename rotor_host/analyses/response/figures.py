"""Figures of an unbalance response (``unbalance.ResponseResult``): per probe node the Bode plot
(0-peak amplitude and phase of y and z against speed, the orbit's major semi-axis) and the
polar plot (the complex amplitude X_y, X_z traced over speed). Speeds above the stability
threshold are drawn dashed and shaded; peaks are marked with their AF; the operating range
is shaded. How to read them: docs/response.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..computed_for import wrapped
from ..plotting import pyplot, save_figure

_COLOR = {"y": "tab:blue", "z": "tab:red"}


def _segments(speeds, values, unstable):
    """(x, y, unstable) runs of consecutive points of the same stability, overlapping by one
    point so the curve stays whole."""
    out, start = [], 0
    for i in range(1, len(speeds) + 1):
        if i == len(speeds) or unstable[i] != unstable[start]:
            hi = min(i + 1, len(speeds))
            out.append((speeds[start:hi], values[start:hi], unstable[start]))
            start = i
    return out


def _shade(ax, res):
    s = np.asarray(res.speeds_hz)
    u = np.asarray(res.unstable)
    if u.any():
        start = res.threshold_hz if res.threshold_hz is not None else s[u].min()
        ax.axvspan(start, s[-1], color="0.85", zorder=0,
                   label="above the stability threshold (unstable: steady response not reached)")
    if res.operating_hz is not None:
        ax.axvspan(*res.operating_hz, color="tab:green", alpha=0.12, zorder=0, label="operating range")


def plot_bode(res, node: int, path, inputs: str = "") -> Path:
    """Amplitude [um 0-pk] and phase [deg] of y and z at 1-based ``node`` against speed."""
    plt = pyplot()
    s, X, u = res.curve()
    c = res.node(node, X)
    fig, (ax, axp) = plt.subplots(2, 1, figsize=(10, 7), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    for d in ("y", "z"):
        for k, (xs, a, unst) in enumerate(_segments(s, c[f"{d}_amplitude_m"] * 1e6, u)):
            ax.plot(xs, a, "--" if unst else "-", color=_COLOR[d], label=None if k else f"{d} (0-peak)")
        for xs, ph, unst in _segments(s, c[f"{d}_phase_deg"], u):
            axp.plot(xs, ph, ".", ms=3, color=_COLOR[d], alpha=0.5 if unst else 1.0)
    ax.plot(s, c["major_m"] * 1e6, color="0.3", lw=0.8, label="orbit major semi-axis")
    for k, p in enumerate(q for q in res.peaks if q["node"] == node):  # refined peaks; labels stacked
        af = p["amplification_factor"]
        ax.plot(p["speed_hz"], p["amplitude_m"] * 1e6, "o", color=_COLOR[p["direction"]], mfc="none")
        ax.annotate(f"{p['direction']} {p['speed_hz']:.2f} Hz, AF {'?' if af is None else f'{af:.3g}'}",
                    (p["speed_hz"], p["amplitude_m"] * 1e6), textcoords="offset points", xytext=(10, -4 - 14 * k),
                    fontsize=8, color=_COLOR[p["direction"]])
    _shade(ax, res)
    ax.set_ylabel("amplitude [um, 0-peak]")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    unb = "; ".join(u.label() for u in res.unbalances)
    ax.set_title(f"Unbalance response at node {node} ({unb})\n{wrapped(inputs)}", fontsize=9)
    axp.set_ylabel("phase [deg] (y = A cos(Omega t + phase))")
    axp.set_xlabel("shaft speed [Hz]")
    axp.set_ylim(-185, 185)
    axp.set_yticks(range(-180, 181, 90))
    axp.grid(True, alpha=0.3)
    _shade(axp, res)
    return save_figure(fig, path)


def plot_polar(res, node: int, path, inputs: str = "") -> Path:
    """X_y and X_z [um] in the complex plane over speed (Re along the abscissa), speeds labelled."""
    plt = pyplot()
    i_y, i_z = res.rotor.dof(node - 1, "y"), res.rotor.dof(node - 1, "z")
    s, X, u = res.curve()
    grid = set(res.speeds_hz)
    fig, ax = plt.subplots(figsize=(7, 7))
    both = np.concatenate([X[:, i_y], X[:, i_z]]) * 1e6
    both = both[np.isfinite(both)]
    gap = 0.04 * (float(np.ptp(np.concatenate([both.real, both.imag]))) if both.size else 1.0)
    placed: list[complex] = []  # labels closer than ``gap`` to one placed would overlap it: left out
    for d, dof in (("y", i_y), ("z", i_z)):
        x = X[:, dof] * 1e6
        for k, (idx, _, unst) in enumerate(_segments(np.arange(s.size), s, u)):
            ax.plot(x[idx].real, x[idx].imag, "--" if unst else "-", color=_COLOR[d],
                    label=None if k else f"X_{d}")
        on_grid = [j for j in range(s.size) if s[j] in grid]
        for j in on_grid[::max(1, len(on_grid) // 8)]:
            if np.isfinite(x[j]) and all(abs(x[j] - q) > gap for q in placed):
                placed.append(complex(x[j]))
                ax.plot(x[j].real, x[j].imag, ".", color=_COLOR[d], ms=4)
                ax.annotate(f"{s[j]:g}", (x[j].real, x[j].imag), fontsize=7, color=_COLOR[d],
                            xytext=(3, 3), textcoords="offset points")
    ax.plot([0], [0], "k+")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Re X [um] (y = Re(X e^{i Omega t}))")
    ax.set_ylabel("Im X [um]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, title="dashed: above the threshold" if u.any() else None, title_fontsize=8)
    ax.set_title(f"Polar plot at node {node}, speeds [Hz] marked\n{wrapped(inputs, 90)}", fontsize=8)
    return save_figure(fig, path)


__all__ = ["plot_bode", "plot_polar"]
