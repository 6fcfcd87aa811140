"""Plots of scene runs (in the manner of the paper's Figs 4-8) and error-vs-run-time tables.

Runs are the arrays a scene writes (``SceneRun.arrays`` or the saved .npz): t, nodes,
y, z (n_out, n_nodes) [m], Fy, Fz (n_out, n_bearings) [N], eccentricity, bearing_nodes, CR.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plotting import pyplot, save_figure
from .tables import markdown_table  # noqa: F401  (re-exported: compare, dt_study and sweep take it from here)


def _col(arrays, node: int) -> int:
    nodes = list(np.asarray(arrays["nodes"]).tolist())
    if node not in nodes:
        raise KeyError(f"node {node} was not recorded; recorded nodes: {nodes}")
    return nodes.index(node)


def disk_node_of(arrays) -> int | None:
    """The node (1-based) the disk-orbit panel shows: the rotor's first disk when recorded
    (runs keep ``disk_nodes``), else the recorded non-bearing node that moves most, else None."""
    nodes = [int(n) for n in np.asarray(arrays["nodes"]).ravel()]
    for n in np.asarray(arrays.get("disk_nodes", [])).ravel():
        if int(n) in nodes:
            return int(n)
    bearings = {int(n) for n in np.asarray(arrays["bearing_nodes"]).ravel()}
    others = [n for n in nodes if n not in bearings]
    if not others or not len(arrays["t"]):
        return None
    size = [float(np.ptp(arrays["y"][:, nodes.index(n)]) + np.ptp(arrays["z"][:, nodes.index(n)])) for n in others]
    return others[int(np.argmax(size))]


def plot_runs(runs: dict, path, *, bearing: int = 0, disk_node: int | None = None, title: str = "",
              history: bool = False) -> Path:
    """One figure like the paper's: (a) Fy vs t, (b) Fz vs t of the bearing, (c) bearing orbit
    (with the clearance circle when it comes near it), (d) disk orbit (``disk_node``, default
    the rotor's first disk: ``disk_node_of``); with ``history`` also (e) y and (f) z of the
    bearing vs t (Fig. 5e-f) and, when the first run has a film temperature (a supply
    temperature: ``scenes.thermal``), (g) T_eff and (h) P_loss of every bearing vs t. ``runs``
    maps a label (e.g. "Reynolds") to run arrays; the panels say which bearing they show.

    The axes are scaled to the first run (the reference), so a variant whose orbit runs away
    (the linear model through the wall) cannot shrink the others to a line; such a variant is
    marked "(off scale)" in the legend. A small bearing orbit fills its panel (in units of CR)
    instead of sitting as a dot in the full clearance circle."""
    plt = pyplot()
    if disk_node is None and runs:
        disk_node = disk_node_of(next(iter(runs.values())))
    first = next(iter(runs.values())) if runs else None
    thermal = history and first is not None and bool(np.size(first.get("T_eff", ())))
    nrow = 4 if thermal else 3 if history else 2
    fig, axes = plt.subplots(nrow, 2, figsize=(11, 3.6 * nrow))
    ax = axes.ravel()
    styles = ["-", "--", ":", "-."]
    lims = _reference_limits(first, bearing, disk_node, history) if first is not None else {}
    for i, (label, a) in enumerate(runs.items()):
        if i > 0 and _off_scale(a, bearing, lims):
            label = f"{label} (off scale)"
        ls = styles[i % len(styles)]
        t = np.asarray(a["t"])
        bnode = int(np.asarray(a["bearing_nodes"])[bearing])
        cb = _col(a, bnode)
        CR = float(np.asarray(a["CR"])[bearing])
        ax[0].plot(t, np.asarray(a["Fy"])[:, bearing], ls, lw=1, label=label)
        ax[1].plot(t, np.asarray(a["Fz"])[:, bearing], ls, lw=1, label=label)
        ax[2].plot(np.asarray(a["y"])[:, cb] / CR, np.asarray(a["z"])[:, cb] / CR, ls, lw=0.8, label=label)
        if disk_node is not None and disk_node in list(np.asarray(a["nodes"])):
            cd = _col(a, disk_node)
            ax[3].plot(np.asarray(a["y"])[:, cd] * 1e6, np.asarray(a["z"])[:, cd] * 1e6, ls, lw=0.8, label=label)
        if history:
            ax[4].plot(t, np.asarray(a["y"])[:, cb] * 1e6, ls, lw=0.8, label=label)
            ax[5].plot(t, np.asarray(a["z"])[:, cb] * 1e6, ls, lw=0.8, label=label)
        if thermal and np.size(a.get("T_eff", ())):
            for k, node in enumerate(np.asarray(a["bearing_nodes"]).ravel()):
                who = f"{label}, bearing {k + 1} (node {int(node)})"
                lk = styles[(i + k) % len(styles)]  # bearings of equal load lie on each other: told apart by style
                ax[6].plot(t, np.asarray(a["T_eff"])[:, k] - 273.15, lk, lw=0.9, label=who)
                ax[7].plot(t, np.asarray(a["P_loss"])[:, k], lk, lw=0.9, label=who)
    if lims.get("clearance", True):
        th = np.linspace(0, 2 * np.pi, 361)
        ax[2].plot(np.cos(th), np.sin(th), "k-", lw=1.2, label="clearance")
    for k, lim in lims.items():
        if k == "clearance":
            continue
        if k in (2, 3):
            ax[k].set_xlim(*lim[0])
            ax[k].set_ylim(*lim[1])
        else:
            ax[k].set_ylim(*lim)
    ax[2].set_aspect("equal")
    ax[3].set_aspect("equal", adjustable="box" if 3 in lims else "datalim")
    which = _bearing_words(first, bearing) if first is not None else ""
    labels = [("t [s]", "Fy [N]", f"(a) horizontal film force, {which}"),
              ("t [s]", "Fz [N]", f"(b) vertical film force, {which}"),
              ("y / CR", "z / CR", f"(c) orbit of {which}" + ("" if lims.get("clearance", True) else
                                                           "\n(zoomed: the clearance circle is |y, z| / CR = 1)")),
              ("y [um]", "z [um]", f"(d) disk orbit (node {disk_node})" if disk_node else "(d) no disk recorded"),
              ("t [s]", "y [um]", f"(e) horizontal displacement, {which}"),
              ("t [s]", "z [um]", f"(f) vertical displacement, {which}"),
              ("t [s]", "T_eff [C]", "(g) effective film temperature"),
              ("t [s]", "P_loss [W]", "(h) friction power of the film")]
    for a_, (xl, yl, tl) in zip(ax, labels):
        a_.set_xlabel(xl)
        a_.set_ylabel(yl)
        a_.set_title(tl, fontsize=10)
        a_.grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    if thermal:
        ax[6].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=9)
    return save_figure(fig, path)


def _bearing_words(a, bearing: int) -> str:
    """Which bearing a panel shows: 'bearing 1 (node 3) of 2'."""
    nodes = np.asarray(a["bearing_nodes"]).ravel()
    return f"bearing {bearing + 1} (node {int(nodes[bearing])})" + (f" of {nodes.size}" if nodes.size > 1 else "")


def _span(v, margin: float = 0.15):
    v = np.asarray(v, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return None
    lo, hi = float(v.min()), float(v.max())
    pad = margin * (hi - lo) or max(abs(hi), 1e-12) * margin
    return lo - pad, hi + pad


def _reference_limits(a, bearing: int, disk_node, history: bool) -> dict:
    """Axis limits per panel from the reference run: {panel: (lo, hi)} or, for the orbits,
    {panel: ((xlo, xhi), (ylo, yhi))}. The bearing orbit always shows the clearance circle."""
    bnode = int(np.asarray(a["bearing_nodes"])[bearing])
    cb = _col(a, bnode)
    CR = float(np.asarray(a["CR"])[bearing])
    y, z = np.asarray(a["y"])[:, cb], np.asarray(a["z"])[:, cb]
    lims = {0: _span(np.asarray(a["Fy"])[:, bearing]), 1: _span(np.asarray(a["Fz"])[:, bearing])}
    e_max = float(np.nanmax(np.hypot(y, z))) / CR if len(y) else 0.0
    if e_max >= NEAR_WALL or not len(y):  # near the wall: show the clearance circle (and beyond)
        r = max(1.1, 1.1 * e_max)
        lims[2] = ((-r, r), (-r, r))
    else:  # a small orbit: fill the panel with it, equal scales
        (ylo, yhi), (zlo, zhi) = _span(y / CR), _span(z / CR)
        half = 0.5 * max(yhi - ylo, zhi - zlo, 1e-3)
        yc, zc = 0.5 * (ylo + yhi), 0.5 * (zlo + zhi)
        lims[2] = ((yc - half, yc + half), (zc - half, zc + half))
        lims["clearance"] = False
    if disk_node is not None and disk_node in list(np.asarray(a["nodes"])):
        cd = _col(a, disk_node)
        yd, zd = _span(np.asarray(a["y"])[:, cd] * 1e6), _span(np.asarray(a["z"])[:, cd] * 1e6)
        if yd and zd:
            lims[3] = (yd, zd)
    if history:
        lims[4], lims[5] = _span(y * 1e6), _span(z * 1e6)
    return {k: v for k, v in lims.items() if v is not None}


NEAR_WALL = 0.7  # a bearing orbit reaching this eccentricity ratio is drawn with the clearance circle


def _off_scale(a, bearing: int, lims: dict) -> bool:
    """True when the run's bearing force or orbit leaves the reference's axes by far (2x)."""
    bnode = int(np.asarray(a["bearing_nodes"])[bearing])
    cb = _col(a, bnode)
    CR = float(np.asarray(a["CR"])[bearing])
    checks = [(0, np.asarray(a["Fy"])[:, bearing]), (1, np.asarray(a["Fz"])[:, bearing])]
    for k, v in checks:
        if k in lims and v.size:
            lo, hi = lims[k]
            if np.nanmax(np.abs(v)) > 2 * max(abs(lo), abs(hi)):
                return True
    if 2 in lims and len(a["t"]):
        r = max(abs(x) for pair in lims[2] for x in pair)
        return bool(np.nanmax(np.hypot(np.asarray(a["y"])[:, cb], np.asarray(a["z"])[:, cb])) / CR > 2 * r)
    return False


def errors_against(ref: dict, run: dict, *, bearing_cols: bool = True) -> dict:
    """Force NRMSE [%] and orbit RMS / max error [% of CR] of ``run`` against ``ref`` on the
    bearing journals, over the time both cover (a failed run is compared up to where it got).

    NRMSE = RMS(F - F_ref) / RMS(F_ref - mean F_ref) over both components and bearings: the
    error relative to the dynamic part of the force (the static part would hide it).
    """
    n = min(len(ref["t"]), len(run["t"]))
    if n < 2:
        return {"force_nrmse_pct": float("nan"), "orbit_rms_pct_cr": float("nan"), "orbit_max_pct_cr": float("nan")}
    if not np.allclose(np.asarray(ref["t"])[:n], np.asarray(run["t"])[:n], rtol=0, atol=1e-9):
        raise ValueError("runs are not on the same time grid; compare runs with the same dt and record step")
    fr = np.stack([np.asarray(ref["Fy"])[:n], np.asarray(ref["Fz"])[:n]])
    fx = np.stack([np.asarray(run["Fy"])[:n], np.asarray(run["Fz"])[:n]])
    dyn = fr - fr.mean(axis=1, keepdims=True)
    nrmse = np.sqrt(np.mean((fx - fr) ** 2)) / max(np.sqrt(np.mean(dyn**2)), 1e-300)
    cols_r = [_col(ref, int(b)) for b in np.asarray(ref["bearing_nodes"])]
    cols_x = [_col(run, int(b)) for b in np.asarray(run["bearing_nodes"])]
    CR = np.asarray(ref["CR"])
    dy = (np.asarray(run["y"])[:n, cols_x] - np.asarray(ref["y"])[:n, cols_r]) / CR
    dz = (np.asarray(run["z"])[:n, cols_x] - np.asarray(ref["z"])[:n, cols_r]) / CR
    d = np.hypot(dy, dz)
    return {"force_nrmse_pct": 100 * float(nrmse), "orbit_rms_pct_cr": 100 * float(np.sqrt(np.mean(d**2))),
            "orbit_max_pct_cr": 100 * float(d.max())}


def _runup_summary(scene, run, out: Path, inputs: str) -> None:
    """A run-up's waterfall and its summary lines: the 1x peak, a critical speed only where the run
    crosses one (``crossings.scene_criticals``), and the whirl onset."""
    from .computed_for import wrapped
    from .linear.crossings import scene_criticals
    from .waterfall import (check_run_up, default_nodes, peak_line, plot_waterfall, spectra, speed_range, summary,
                            whirl_line)

    try:
        check_run_up(run.arrays)
        nodes = default_nodes(run.arrays)
        specs = [spectra(run.arrays, n) for n in nodes]  # a run too short for a spectrum: ValueError
        lo, hi = speed_range(run.arrays)
        crit = scene_criticals(scene, lo, hi)
        png = plot_waterfall(run.arrays, out / f"{run.npz.stem}_waterfall.png", nodes=nodes,
                             criticals_hz=crit.speeds_hz,
                             title=f"{scene.description or scene.name}: {scene.speed_profile.describe()}\n"
                                   + wrapped(inputs))
    except ValueError as exc:  # say why, keep the run
        print(f"no waterfall: {exc}")
        return
    if crit.note:
        print(crit.note)
    for n, sp in zip(nodes, specs):
        s = summary(sp, crit.criticals)
        print(f"node {n}: {peak_line(s, lo, hi, crit.note)}; {whirl_line(s)}")
    print(f"wrote {png}")


def run_and_report(scene, out, *, progress: bool = True, plots: bool = True) -> int:
    """``rotor-host run``: run the scene into the folder ``out``, print what happened, draw the
    run (and, for a run-up, its waterfall); 0 when the run finished ok, else 1."""
    from bearing_fmu.io.outputs import ensure_writable

    from ..scenes.run import run_scene
    from ..scenes.thermal import thermal_lines
    from .computed_for import scene_line, wrapped

    out = ensure_writable(out)  # refused before any work
    inputs = scene_line(scene)
    run = run_scene(scene, out, progress=progress)
    m = run.meta
    via = f"{scene.via}, native" if scene.via == "fmu" and scene.fmu_kind == "native" else scene.via
    print(f"computed for: {inputs}")
    print(f"{scene.name} [{scene.internal} via {via}]: {m['status']}, {m['steps']} steps to "
          f"t = {m['t_reached_s']:.4g} s in {m['wall_time_s']:.1f} s "
          f"(setup {m['setup_time_s']:.1f} s), {m['newton_mean_evaluations_per_step']:.2f} force "
          f"evaluations per step, {m['step_cuts']} step cuts")
    print(f"max eccentricity ratio per bearing: {', '.join(f'{e:.3f}' for e in m['max_eccentricity'])}"
          + ("  (the orbit crossed the clearance circle)" if m["crossed_clearance"] else ""))
    if any(p is not None for p in m.get("peak_pressure_Pa", [])):  # at each journal's closest approach
        print("peak film pressure per bearing (Reynolds, at its largest eccentricity): " + ", ".join(
            "-" if p is None else f"{p / 1e6:.4g} MPa at {d:.1f} deg (t = {t:.4g} s)"
            for p, d, t in zip(m["peak_pressure_Pa"], m["peak_pressure_deg"], m["peak_pressure_t_s"])))
    for line in thermal_lines(run.arrays):  # a supply temperature: how hot, how much power
        print(line)
    if m["status"] != "ok":
        print(f"stopped: {m['message']}")
    if scene.speed_profile is not None and plots and run.arrays["t"].size > 1:
        _runup_summary(scene, run, out, inputs)
    if plots and run.arrays["t"].size > 1:
        title = "\n".join(x for x in (scene.description or scene.name, wrapped(inputs)) if x)
        png = plot_runs({scene.internal: run.arrays}, out / f"{run.npz.stem}.png", title=title, history=True)
        print(f"wrote {run.npz}, {run.json}, {png}")
    else:
        print(f"wrote {run.npz}, {run.json}")
    return 0 if m["status"] == "ok" else 1
