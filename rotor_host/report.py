"""Plots of scene runs (in the manner of the paper's Figs 4-8) and error-vs-run-time tables.

Runs are the arrays a scene writes (``SceneRun.arrays`` or the saved .npz): t, nodes,
y, z (n_out, n_nodes) [m], Fy, Fz (n_out, n_bearings) [N], eccentricity, bearing_nodes, CR.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _col(arrays, node: int) -> int:
    nodes = list(np.asarray(arrays["nodes"]).tolist())
    if node not in nodes:
        raise KeyError(f"node {node} was not recorded; recorded nodes: {nodes}")
    return nodes.index(node)


def plot_runs(runs: dict, path, *, bearing: int = 0, disk_node: int | None = 6, title: str = "",
              history: bool = False) -> Path:
    """One figure like the paper's: (a) Fy vs t, (b) Fz vs t of the bearing, (c) bearing orbit
    with the clearance circle, (d) disk orbit; with ``history`` also (e) y and (f) z of the
    bearing vs t (Fig. 5e-f). ``runs`` maps a label (e.g. "Reynolds") to run arrays."""
    plt = _plt()
    nrow = 3 if history else 2
    fig, axes = plt.subplots(nrow, 2, figsize=(11, 3.6 * nrow))
    ax = axes.ravel()
    styles = ["-", "--", ":", "-."]
    for i, (label, a) in enumerate(runs.items()):
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
    th = np.linspace(0, 2 * np.pi, 361)
    ax[2].plot(np.cos(th), np.sin(th), "k-", lw=1.2, label="clearance")
    ax[2].set_aspect("equal")
    ax[3].set_aspect("equal", adjustable="datalim")
    labels = [("t [s]", "Fy [N]", "(a) horizontal film force"), ("t [s]", "Fz [N]", "(b) vertical film force"),
              ("y / CR", "z / CR", "(c) bearing orbit"), ("y [um]", "z [um]", f"(d) disk orbit (node {disk_node})"),
              ("t [s]", "y [um]", "(e) horizontal bearing displacement"),
              ("t [s]", "z [um]", "(f) vertical bearing displacement")]
    for a_, (xl, yl, tl) in zip(ax, labels):
        a_.set_xlabel(xl)
        a_.set_ylabel(yl)
        a_.set_title(tl, fontsize=10)
        a_.grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


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


def markdown_table(rows: list[dict], columns: list[tuple[str, str, str]]) -> str:
    """rows of dicts -> a markdown table; columns = (key, header, format)."""
    head = "| " + " | ".join(h for _, h, _ in columns) + " |"
    sep = "|" + "|".join("---" for _ in columns) + "|"
    lines = [head, sep]
    for r in rows:
        cells = []
        for key, _, fmt in columns:
            v = r.get(key)
            if v is None or (isinstance(v, float) and not np.isfinite(v)):
                cells.append("-")
            else:
                cells.append(format(v, fmt) if fmt else str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
