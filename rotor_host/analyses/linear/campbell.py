"""Figures of a stability analysis (``rotor_host.analyses.linear.stability``): the Campbell diagram with the
1x and 0.5x lines, the critical speeds and the threshold; the log decrement against speed; the
least stable mode's shape. How an engineer reads them: docs/campbell.md.

Each figure takes the ``StabilityResult`` of ``rotor_host.analyses.linear.stability`` (``res``); this
module does not import that one, which calls it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...model.rotor import Rotor
from .modal import AF_CRITICALLY_DAMPED, LOG_DEC_HEAVY
from ..plotting import pyplot, save_figure

_FWD = dict(marker="^", color="tab:red", label="forward whirl")
_BWD = dict(marker="v", color="tab:blue", label="backward whirl")


def _mode_scatter(ax, res, value, top: float = math.inf):
    """Scatter value(point, i) against speed for the lowest n_modes modes, forward and
    backward marked; heavily damped modes (AF = pi / log dec < 2.5: no resonance) hollow;
    unstable modes (log dec < 0) ringed in black; the modes above the ranked band (``band_hz``:
    not ranked for the least stable mode nor the threshold) small and grey, named in the legend
    when one lies below ``top`` (the axis' end)."""
    heavy_seen = False
    beyond = [(p.speed_hz, value(p, i), p.forward(i)) for p in res.ok_points
              for i in range(min(res.n_modes, p.freq_hz.size)) if p.freq_hz[i] > p.band_hz]
    for style, fwd in ((_FWD, True), (_BWD, False)):
        xs, ys, unstable, heavy = [], [], [], []
        for p in res.ok_points:
            for i in range(min(res.n_modes, p.freq_hz.size)):
                if p.forward(i) == fwd and not p.freq_hz[i] > p.band_hz:
                    xs.append(p.speed_hz)
                    ys.append(value(p, i))
                    unstable.append(p.log_dec[i] < 0.0)
                    heavy.append(p.log_dec[i] > LOG_DEC_HEAVY)
        if xs:
            xs, ys, u, h = np.array(xs), np.array(ys), np.array(unstable), np.array(heavy)
            ax.scatter(xs[~h], ys[~h], s=14, marker=style["marker"], color=style["color"], label=style["label"],
                       zorder=3)
            ax.scatter(xs[h], ys[h], s=14, marker=style["marker"], facecolors="none", edgecolors=style["color"],
                       linewidths=0.8, zorder=3)
            heavy_seen = heavy_seen or bool(h.any())
            if u.any():
                ax.scatter(xs[u], ys[u], s=60, marker="o", facecolors="none", edgecolors="black", linewidths=1.0,
                           zorder=4)
    for fwd, marker in ((True, "^"), (False, "v")):
        pts = [(x, y) for x, y, f in beyond if f == fwd]
        if pts:
            ax.scatter(*zip(*pts), s=8, marker=marker, color="0.65", zorder=2)
    if any(y <= top for _, y, _ in beyond):
        ax.scatter([], [], s=8, marker="^", color="0.65",
                   label=f"grey: above the ranked band ({res.band_hz:.4g} Hz =\n{res.rank_up_to:g} x the top speed): "
                         "not ranked")
    ax.scatter([], [], s=60, marker="o", facecolors="none", edgecolors="black", label="unstable (log dec < 0)")
    if heavy_seen:
        ax.scatter([], [], s=14, marker="^", facecolors="none", edgecolors="grey",
                   label=f"hollow: heavily damped, log dec > {LOG_DEC_HEAVY:.2f}\n(AF < {AF_CRITICALLY_DAMPED:g}: no "
                         "resonance peak)")


def plot_campbell(res, path, title: str = "") -> Path:
    """Damped natural frequencies against speed, forward and backward whirl marked, the 1x and
    0.5x lines, the critical speeds (1x crossings) and the threshold."""

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10.5, 5.5))
    pts = res.ok_points
    s = np.array([p.speed_hz for p in res.points])
    top = 1.25 * s.max()
    _mode_scatter(ax, res, lambda p, i: p.freq_hz[i], top)
    ax.plot([0, s.max()], [0, s.max()], "k-", lw=0.8, label="1x", zorder=5)
    ax.plot([0, s.max()], [0, 0.5 * s.max()], "k--", lw=0.8, label="0.5x", zorder=5)
    if res.criticals:
        ax.plot([c["speed_hz"] for c in res.criticals], [c["speed_hz"] for c in res.criticals], "s", ms=7,
                mfc="none", mec="tab:green", mew=1.5, label="critical speed (1x crossing)")
    if res.threshold is not None:
        t = res.threshold
        ax.axvline(t.speed_hz, color="tab:purple", lw=1.0, ls=":")
        ax.plot([t.speed_hz], [t.whirl_hz], "*", color="tab:purple", ms=13,
                label=f"threshold {t.speed_hz:.2f} Hz, whirl {t.whirl_hz:.2f} Hz")
    ranks = min([min(res.n_modes, p.freq_hz.size) for p in pts] or [0])
    above = [k + 1 for k in range(ranks) if all(p.freq_hz[k] > top for p in pts)]  # whole branches off the plot
    ax.set_xlim(0, s.max() * 1.02)
    ax.set_ylim(0, top)
    ax.set_xlabel("shaft speed [Hz]")
    ax.set_ylabel("damped natural frequency [Hz]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)  # outside: hides no mode
    ax.set_title((title or f"Campbell diagram: {res.rotor} [{res.internal}]") + _inputs(res)
                 + (f"\n(modes {above[0]}-{above[-1]} of the {res.n_modes} lowest lie above {top:.0f} Hz: frequencies in "
                    "the json)" if above else ""),
                 fontsize=10)
    return _save(fig, plt, path)


def plot_log_dec(res, path, title: str = "") -> Path:
    """Log decrement of the lowest modes against speed, the least stable one as a line, zero
    (the stability limit) and the threshold."""

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10.5, 4.5))
    _mode_scatter(ax, res, lambda p, i: p.log_dec[i])
    pts = res.ok_points
    ax.plot([p.speed_hz for p in pts], [p.least_log_dec if p.least is not None else np.nan for p in pts], "k-",
            lw=1.0, label=f"least stable mode up to {res.band_hz:.4g} Hz\n({res.rank_up_to:g} x the top speed)")
    ax.axhline(0.0, color="grey", lw=0.8)
    if res.threshold is not None:
        ax.axvline(res.threshold.speed_hz, color="tab:purple", lw=1.0, ls=":",
                   label=f"threshold {res.threshold.speed_hz:.2f} Hz")
    lds = [p.log_dec[i] for p in pts for i in range(min(res.n_modes, p.freq_hz.size))]
    if lds:
        lo, hi = min(min(lds), 0.0), max(lds)
        cap = 5.0  # heavily damped (nearly overdamped) modes would squash the ones that matter
        hi = min(hi, cap)
        pad = 0.05 * (hi - lo or 1.0)
        ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("shaft speed [Hz]")
    ax.set_ylabel("logarithmic decrement")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.set_title((title or f"Log decrement: {res.rotor} [{res.internal}]") + _inputs(res), fontsize=10)
    return _save(fig, plt, path)


def plot_mode_shape(res, rotor: Rotor, path, title: str = "") -> Path | None:
    """The least stable mode at the threshold (or at the top speed): (a) the amplitude of y
    and z along the shaft, bearings and disks marked; (b) the orbits (ellipses, normalised to
    the largest) at the bearings and disks, with the direction of travel."""

    if res.threshold is not None:
        p = res.threshold.point
        where = f"at the threshold {p.speed_hz:.2f} Hz"
    elif res.ok_points:
        p = res.ok_points[-1]
        where = f"at the top speed {p.speed_hz:g} Hz (no threshold in the range)"
    else:
        return None
    i = p.least
    if i is None:  # no mode in the ranking band at the top speed: nothing to call least stable
        return None
    Y, Z = p.shapes[0::4, i], p.shapes[1::4, i]
    big = max(np.abs(Y).max(), np.abs(Z).max())
    Y, Z = Y / big, Z / big  # the largest translation 1 (the shape's largest entry may be a tilt)
    shape = p.shapes[:, i]
    x = rotor.node_x * 1e3
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1.5, 1]})
    a1.plot(x, np.abs(Y), "o-", ms=3, label="|y|")
    a1.plot(x, np.abs(Z), "s-", ms=3, label="|z|")
    for n in rotor.bearing_nodes:
        a1.axvline(x[n], color="grey", ls="--", lw=0.8)
    for d in rotor.disks:
        a1.axvline(x[d.node], color="tab:green", ls=":", lw=1.0)
    a1.set_xlabel("axial position [mm] (dashed: bearings, dotted: disks)")
    a1.set_ylabel("amplitude (largest translation 1)")
    a1.set_ylim(0.0, 1.08)  # from zero: a rigid-body mode is a flat line, not a bending one
    a1.grid(alpha=0.3)
    a1.legend(fontsize=8)
    ph = np.linspace(0.0, 2.0 * math.pi, 121)
    marked = [(n, f"bearing node {n + 1}") for n in rotor.bearing_nodes] + \
             [(d.node, f"disk node {d.node + 1}") for d in rotor.disks]
    for n, label in marked:
        y = np.real(Y[n] * np.exp(1j * ph))
        z = np.real(Z[n] * np.exp(1j * ph))
        (line,) = a2.plot(y, z, lw=1.2, label=f"{label} ({rotor.whirl(shape, n):+.2f})")
        a2.annotate("", xy=(y[12], z[12]), xytext=(y[6], z[6]),
                    arrowprops=dict(arrowstyle="->", color=line.get_color()))
    a2.set_aspect("equal")
    a2.set_xlabel("y")
    a2.set_ylabel("z")
    a2.grid(alpha=0.3)
    a2.legend(fontsize=7, title="whirl (+1 fwd, -1 bwd)", title_fontsize=7, loc="upper left",
              bbox_to_anchor=(1.02, 1.0), borderaxespad=0)  # beside the orbits: it covered the disk's
    fig.suptitle(title or f"{res.rotor} [{res.internal}]: least stable mode {where}: {p.freq_hz[i]:.2f} Hz, "
                 f"log dec {p.log_dec[i]:.3g}" + _inputs(res), fontsize=10)
    return _save(fig, plt, path)


def _inputs(res) -> str:
    """The result's inputs line (``analyses.computed_for``) as further title lines; '' without it."""
    from ..computed_for import wrapped

    line = getattr(res, "inputs", "")
    return "\n" + wrapped(line, 110) if line else ""


def _save(fig, plt, path) -> Path:
    return save_figure(fig, path)


