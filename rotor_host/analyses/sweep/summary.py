"""What a sweep reports: the summary table (markdown and json) with its title naming what was
swept over which range, and the bifurcation diagram (docs/sweep.md: how to read it)."""

from __future__ import annotations

import math
from pathlib import Path

from bearing_fmu.io.outputs import write_json, write_text

from ..plotting import pyplot, save_figure

def _flat_row(r: dict) -> dict:
    """A row with its per-bearing and per-disk values as columns (for the markdown table)."""
    out = dict(r)
    for k, b in enumerate(r.get("bearings", [])):
        out[f"b{k}_max"], out[f"b{k}_min"] = b["ecc_max"], b["ecc_min"]
        out[f"b{k}_T"], out[f"b{k}_P"] = b.get("T_eff_K", math.nan) - 273.15, b.get("P_loss_W")
    for k, d in enumerate(r.get("disks", [])):
        out[f"d{k}_max"], out[f"d{k}_min"] = d["amp_max_um"], d["amp_min_um"]
    return out


def summary_columns(bearing_nodes: list[int], disk_nodes: list[int], unbalance: bool, thermal=False) -> list[tuple]:
    cols = [("speed_hz", "speed [Hz]", "g")]
    if unbalance:
        cols.append(("unbalance_g", "unbalance [g]", "g"))
    cols.append(("status", "status", ""))
    for k, n in enumerate(bearing_nodes):
        cols += [(f"b{k}_max", f"bearing {k + 1} (node {n}) ecc. max", ".3f"), (f"b{k}_min", "min", ".3f")]
        cols += [(f"b{k}_T", "T_eff [C]", ".2f"), (f"b{k}_P", "P_loss [W]", ".3g")] if thermal else []
    for k, n in enumerate(disk_nodes):
        cols += [(f"d{k}_max", f"disk (node {n}) amplitude max [um]", ".1f"), (f"d{k}_min", "min [um]", ".1f")]
    cols += [("wall_s", "run time [s]", ".1f"), ("integration_s", "integration [s]", ".1f")]
    return cols


def sweep_title(scene, rows: list[dict], unbalance: bool) -> str:
    """What was swept, over which range, with what held fixed: the summary's and the diagram's
    title (not the scene's description, which names the scene's own speed)."""
    key, unit = ("unbalance_g", "g") if unbalance else ("speed_hz", "Hz")
    values = [r[key] for r in rows if r.get(key) is not None]
    span = (f"{min(values):g}-{max(values):g} {unit}" if len(set(values)) > 1 else
            f"{values[0]:g} {unit}" if values else "no runs")
    unb = scene.unbalances[0] if scene.unbalances else None
    where = "" if unb is None else f" on node {unb.node + 1} at {unb.radius_m * 1e3:g} mm"
    if unbalance:
        return f"Sweep of {scene.name}: unbalance {span}{where} ({len(rows)} runs) at {scene.speed_hz:g} Hz"
    held = "no unbalance" if unb is None else f"unbalance {unb.mass_kg * 1e3:g} g{where}" + (
        f" (+{len(scene.unbalances) - 1} more)" if len(scene.unbalances) > 1 else "")
    return f"Sweep of {scene.name}: shaft speed {span} ({len(rows)} runs), {held}"


def write_summary(path_stem: Path, scene, rows: list[dict], *, settle_s: float, bearing_nodes, disk_nodes,
                  unbalance: bool, info: dict, note: str = "", plot: bool = True) -> list[Path]:
    """``<stem>.md``, ``.json`` and (with a run to draw) the bifurcation diagram ``.png``."""
    from ..report import markdown_table

    what = (f"unbalance on node {scene.unbalances[0].node + 1} at {scene.unbalances[0].radius_m * 1e3:g} mm, "
            f"{scene.speed_hz:g} Hz" if unbalance else "shaft speed")
    from ..computed_for import scene_line

    title = sweep_title(scene, rows, unbalance)
    inputs = scene_line(scene)
    lines = [f"# {title}", "", f"Computed for: {inputs}", "",
             f"scene {scene.source}, {scene.internal} via {scene.via}, dt = {scene.dt_s:g} s, "
             f"{scene.t_end_s:g} s per run, swept: {what}. After the transient = t >= {settle_s:g} s. "
             f"Eccentricity = journal displacement / radial clearance; disk amplitude = distance of the disk "
             f"centre from its static equilibrium position. {len(rows)} runs on {info['workers']} worker(s) "
             f"({info['cluster']}): {info['wall_s']:.1f} s wall time, {info['run_s']:.1f} s of runs"
             + (f" (the workers loaded the code and kernels in {info['warm_s']:.1f} s before the first)"
                if info.get("warm_s") is not None else "") + ".", ""]
    if note:
        lines += [f"**{note}**", ""]
    oil = any("T_eff_K" in b for r in rows for b in r.get("bearings", []))  # a supply temperature
    lines.append(markdown_table([_flat_row(r) for r in rows], summary_columns(bearing_nodes, disk_nodes, unbalance, oil)))
    bad = [r for r in rows if r["status"] != "ok"]
    if bad:
        lines += ["", "Runs that did not finish cleanly:", ""]
        lines += [f"- {run_label(r, unbalance)}: {r['status']}: {r['message']}" for r in bad]
    out = [write_text(f"{path_stem}.md", "\n".join(lines) + "\n")]
    out.append(write_json(f"{path_stem}.json", {
        "scene": str(scene.source), "inputs": inputs, "internal": scene.internal, "via": scene.via, "dt_s": scene.dt_s,
        "t_end_s": scene.t_end_s, "settle_s": settle_s, "swept": "unbalance_g" if unbalance else "speed_hz",
        "status": "interrupted" if note else "ok", "note": note, **info, "rows": rows}, indent=1))
    png = summary_diagram(path_stem, scene, rows, settle_s=settle_s, unbalance=unbalance) if plot else None
    return out + ([png] if png else [])


def summary_diagram(path_stem: Path, scene, rows: list[dict], *, settle_s: float, unbalance: bool) -> Path | None:
    """The bifurcation diagram ``<stem>.png`` of the summary, when a run has something to draw,
    titled from the sweep (the swept quantity and range, not the scene's own speed)."""
    from ..computed_for import scene_line, wrapped

    if not any(r["status"] == "ok" and r.get("bearings") for r in rows):
        return None
    return plot_bifurcation(rows, f"{path_stem}.png", unbalance=unbalance,
                            title=f"{sweep_title(scene, rows, unbalance)}\n{scene.internal} via {scene.via}, after "
                                  f"the transient: t >= {settle_s:g} s of {scene.t_end_s:g} s per run\n"
                                  + wrapped(scene_line(scene), 130))


def run_label(r: dict, unbalance: bool) -> str:
    """The swept value of a row, with its unit."""
    return f"{r['unbalance_g']:g} g" if unbalance else f"{r['speed_hz']:g} Hz"


def plot_bifurcation(rows: list[dict], path, *, unbalance: bool = False, title: str = "") -> Path:
    """Bearing eccentricity (top) and disk amplitude (bottom) against the swept value: per run
    the range from the smallest to the largest value after the transient (bar with end
    markers), the once-per-revolution samples (dots: one point for an orbit synchronous with
    the shaft, a spread for a whirl), the static equilibrium (dashed) and failed runs (x on the axis)."""

    plt = pyplot()
    key = "unbalance_g" if unbalance else "speed_hz"
    good = [r for r in rows if r["status"] == "ok" and r.get("bearings")]
    has_disk = any(r.get("disks") for r in good)
    fig, axes = plt.subplots(2 if has_disk else 1, 1, figsize=(11, 7.5 if has_disk else 4.5), sharex=True,
                             squeeze=False)
    ax_b = axes[0, 0]
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    n_b = min((len(r["bearings"]) for r in good), default=0)
    for j, group in enumerate(_same_bearings(good, n_b)):
        k = group[0]
        xs = [r[key] for r in good]
        nodes = ", ".join(str(good[0]["bearings"][g]["node"]) for g in group)
        label = (f"bearing {k + 1} (node {nodes})" if len(group) == 1 else
                 f"bearings {', '.join(str(g + 1) for g in group)} (nodes {nodes}): the same")
        _ranges(ax_b, xs, [r["bearings"][k]["ecc_max"] for r in good], [r["bearings"][k]["ecc_min"] for r in good],
                [r["bearings"][k]["once_per_rev"] for r in good], colors[j % len(colors)], label)
        stat = [(r[key], r["static_eccentricity"][k]) for r in good if r.get("static_eccentricity")]
        if stat:
            ax_b.plot(*zip(*stat), "--", color=colors[j % len(colors)], lw=0.8, alpha=0.7)
    ax_b.set_ylabel("bearing eccentricity ratio")
    ax_b.set_ylim(0, 1.0)
    if has_disk:
        ax_d = axes[1, 0]
        n_d = max(len(r["disks"]) for r in good)
        for k in range(n_d):
            g = [r for r in good if len(r["disks"]) > k]
            _ranges(ax_d, [r[key] for r in g], [r["disks"][k]["amp_max_um"] for r in g],
                    [r["disks"][k]["amp_min_um"] for r in g], [r["disks"][k]["once_per_rev_um"] for r in g],
                    colors[(n_b + k) % len(colors)], f"disk (node {g[0]['disks'][k]['node']})")
        ax_d.set_ylabel("disk amplitude from static position [um]")
        _amplitude_scale(ax_d, [v for r in good for d in r["disks"] for v in (d["amp_max_um"], d["amp_min_um"])])
    failed = [r for r in rows if r not in good]
    for ax in axes[:, 0]:
        for i, r in enumerate(failed):
            ax.plot(r[key], 0, "x", color="red", ms=9, mew=2, clip_on=False, transform=ax.get_xaxis_transform(),
                    label="failed or stopped (see the summary)" if i == 0 else None)
        ax.grid(alpha=0.3, which="both")
        # what the marks mean, once (the colours name the bearings and disks)
        ax.plot([], [], "^", color="0.3", mfc="none", ls="none", label="max after the transient")
        ax.plot([], [], "v", color="0.3", mfc="none", ls="none", label="min")
        ax.plot([], [], ".", color="0.35", ls="none", label="once per revolution")
        if ax is ax_b and any(r.get("static_eccentricity") for r in good):
            ax.plot([], [], "--", color="0.3", lw=0.8, label="static equilibrium")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    axes[-1, 0].set_xlabel("unbalance mass [g]" if unbalance else "shaft speed [Hz]")
    if title:
        fig.suptitle(title, fontsize=10)
    return save_figure(fig, path)


def _amplitude_scale(ax, values) -> None:
    """A log scale when the amplitudes span more than 30x (a resonance or a whirl next to small
    synchronous orbits), else linear from 0; also linear when one is round-off (< 1 nm: a run
    without unbalance stays at rest), which a log axis would stretch over ten decades."""
    if values and min(values) >= 1e-3 and max(values) > 30 * min(values):
        ax.set_yscale("log")
    else:
        ax.set_ylim(bottom=0)


def _same_bearings(good: list[dict], n_b: int, tol: float = 1e-3) -> list[list[int]]:
    """The bearings grouped where their eccentricities agree within ``tol`` in every run (a symmetric
    rotor's: their marks would lie on each other), each group drawn and named once."""
    def values(k):
        return [v for r in good for v in (r["bearings"][k]["ecc_max"], r["bearings"][k]["ecc_min"])]

    groups: list[list[int]] = []
    for k in range(n_b):
        home = next((g for g in groups if all(abs(a - b) <= tol for a, b in zip(values(g[0]), values(k)))), None)
        if home is None:
            groups.append([k])
        else:
            home.append(k)
    return groups


def _ranges(ax, xs, hi, lo, samples, color, label) -> None:
    """Per x: a vertical bar lo..hi with end markers (``label`` on the bar), and the
    once-per-revolution samples."""
    ax.vlines(xs, lo, hi, color=color, lw=1.0, alpha=0.6, label=label)
    ax.plot(xs, hi, "^", color=color, ms=6, ls="none")
    ax.plot(xs, lo, "v", color=color, ms=6, ls="none")
    px = [x for x, s in zip(xs, samples) for _ in s]
    py = [v for s in samples for v in s]
    if px:
        ax.plot(px, py, ".", color="0.35", ms=2, ls="none", alpha=0.6)


__all__ = ["summary_columns", "sweep_title", "write_summary", "summary_diagram", "run_label", "plot_bifurcation"]
