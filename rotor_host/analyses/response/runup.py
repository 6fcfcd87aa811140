"""``rotor-host linear-vs-runup``: the linear unbalance response against the same unbalance in a
run-up through the nonlinear bearing force, at a small and a large unbalance.

For a run-up scene (a ``[speed_profile]`` and its ``[[unbalance]]``) and each scale factor F of
its unbalance masses:

* **linear**: the steady 1x response of the rotor linearised at each speed (``unbalance``), the
  forward circle's radius |X_y + i X_z| / 2 (``forward_m``) at each recorded node: what the 1x
  line of a waterfall shows for a steady whirl (``waterfall.Spectra``: a circular whirl of
  radius A shows A at its frequency). It scales with F exactly.
* **nonlinear**: the scene run with the masses times F (``scenes.run.run_scene``: the bearing
  force itself, FMUs or in-process, whatever the scene says), its 1x forward component tracked
  per window (order tracking, ``tracked_1x``): with phi(t) = 2 pi int speed dt the shaft angle,
  X_f = sum w (s - mean s) e^{-i phi} / sum w over a Hann window w of the whirl s = y + i z, the
  forward 1x radius |X_f| at the window's mean speed. Not the waterfall's FFT bin: a run-up's
  1x frequency sweeps through the window and falls between bins, which loses up to 15 % of the
  amplitude (the Hann window's scalloping); the tracked phase follows it exactly.

Where the journal stays near its equilibrium the two agree up to the run-up's own transient:
a ramp through a resonance of half-power bandwidth dN in less than a few of its time constants
peaks later and lower than the steady response (the sweep-rate effect, linear too). Where they
part with the scale, the nonlinearity does: a large orbit in the film stiffens it (the peak
moves up and flattens), and above the stability threshold the run-up's whirl (subsynchronous,
not in the 1x line) is what the linear answer cannot give. The report writes both peaks per
scale and node and their ratio (run-up over linear): where it does not change with the scale the
linear answer holds (the difference is the sweep rate's); where it does, the film's
nonlinearity is at work.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

DEFAULT_SCALES = (0.1, 1.0)
LINEAR_POINTS = 501  # speeds of the linear response over the run's range (0.1 Hz on 10-60 Hz)


def _unbalances(scene, scale: float):
    from .synchronous import Unbalance

    return [Unbalance(u.node + 1, u.mass_kg * 1e3 * scale, u.radius_m * 1e3, math.degrees(u.phase_rad))
            for u in scene.unbalances]


def _peak(speeds, amp) -> tuple[float | None, float | None]:
    a = np.asarray(amp, float)
    if not np.isfinite(a).any():
        return None, None
    k = int(np.nanargmax(a))
    return float(speeds[k]), float(a[k])


def tracked_1x(arrays: dict, node: int, window_s: float) -> tuple[np.ndarray, np.ndarray]:
    """(window mean speeds [Hz], forward 1x radius [m]) of recorded ``node`` (1-based) by order
    tracking (module docstring); half-overlapping Hann windows of ``window_s``."""
    nodes = [int(n) for n in np.asarray(arrays["nodes"]).ravel()]
    if node not in nodes:
        raise ValueError(f"node {node} was not recorded; recorded nodes: {', '.join(map(str, nodes))}")
    c = nodes.index(node)
    t = np.asarray(arrays["t"], float)
    speed = np.asarray(arrays["speed_hz"], float)
    phi = np.concatenate([[0.0], np.cumsum(np.pi * (speed[1:] + speed[:-1]) * np.diff(t))])  # 2 pi int f dt
    s = np.asarray(arrays["y"], float)[:, c] + 1j * np.asarray(arrays["z"], float)[:, c]
    n = int(round(window_s / float(np.median(np.diff(t)))))
    if n < 16 or n > t.size:
        raise ValueError(f"window {window_s:g} s holds {n} recorded samples of the run's {t.size}")
    w = np.hanning(n)
    sp, amp = [], []
    for i in range(0, t.size - n + 1, n // 2):
        seg = s[i:i + n] - s[i:i + n].mean()
        amp.append(abs(np.sum(w * seg * np.exp(-1j * phi[i:i + n])) / w.sum()))
        sp.append(float(np.mean(speed[i:i + n])))
    return np.array(sp), np.array(amp)


def compare(scene, scales=DEFAULT_SCALES, out=None, *, window_s=None, progress: bool = False, log=None) -> dict:
    """The linear response and the run-ups of ``scene`` at each scale (module docstring): a dict
    with per scale the run's status, and per node the curves and the two peaks."""
    from ...scenes.run import run_scene
    from ..linear.stability import Stability
    from ..linear.inputs import check_speeds
    from ..waterfall import DEFAULT_WINDOW_S
    from ...model.rotor import Rotor
    from .unbalance import response_from

    if scene.speed_profile is None or scene.speed_profile.is_constant:
        raise ValueError(f"{scene.source}: a run-up scene is needed: one with a [speed_profile] whose speed changes")
    if not scene.unbalances:
        raise ValueError(f"{scene.source}: the scene has no [[unbalance]] to scale")
    t = np.linspace(0.0, scene.t_end_s, 1001)
    hz = np.asarray(scene.speed.hz(t), float)
    lo, hi = float(np.min(hz)), float(np.max(hz))
    rotor = Rotor.from_toml(scene.rotor_path)
    nodes = sorted({n + 1 for n in rotor.bearing_nodes} | {n + 1 for n in scene.record_nodes})
    analysis = Stability(rotor, scene.internal, scene.internal_options(), scene.static_loads,
                         where=str(scene.source), T_supply_K=scene.supply_temperature_K)
    sweep = analysis.sweep(check_speeds(np.linspace(max(lo, 1e-3), hi, LINEAR_POINTS)), log=log)
    out_dir = None if out is None else Path(out)
    result = {"scene": str(scene.source), "internal": scene.internal, "via": scene.via, "speeds_hz": [lo, hi],
              "threshold_hz": None if sweep.threshold is None else sweep.threshold.speed_hz, "scales": []}
    for F in scales:
        unb = _unbalances(scene, float(F))
        lin = response_from(analysis, sweep, scene.rotor_path, unb, probes=nodes)
        sc = replace(scene, unbalances=[replace(u, mass_kg=u.mass_kg * float(F)) for u in scene.unbalances])
        stem = f"{Path(scene.source).stem if scene.source else scene.name}_x{F:g}"
        run = run_scene(sc, out_dir, progress=progress, stem=stem)
        entry = {"scale": float(F), "unbalances": [u.as_dict() for u in unb], "run_status": run.meta["status"],
                 "run_message": run.meta.get("message", ""), "linear_speeds_hz": lin.speeds_hz,
                 "linear_unstable": lin.unstable, "nodes": {}}
        for n in nodes:
            f_lin = lin.node(n)["forward_m"]
            row = {"linear_forward_m": [None if not np.isfinite(v) else float(v) for v in f_lin]}
            s_lin, a_lin = _peak(lin.speeds_hz, np.where(lin.unstable, np.nan, f_lin))
            row.update(linear_peak_hz=s_lin, linear_peak_m=a_lin)
            try:
                speeds, one = tracked_1x(run.arrays, n, window_s or DEFAULT_WINDOW_S)
            except (ValueError, KeyError) as exc:  # not recorded, or a run too short for a window
                row["runup_note"] = str(exc)
                speeds = None
            if speeds is not None:
                s_run, a_run = _peak(speeds, one)
                at = float(np.interp(s_lin, speeds, one)) if s_lin is not None else None
                row.update(runup_speeds_hz=speeds.tolist(), runup_1x_m=one.tolist(), runup_peak_hz=s_run,
                           runup_peak_m=a_run, runup_at_linear_peak_m=at,
                           peak_ratio=None if a_run is None or not a_lin else a_run / a_lin)
            entry["nodes"][str(n)] = row
        result["scales"].append(entry)
    return result


def plot(result: dict, node: int, path, title: str = "") -> Path:
    from ..plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 6))
    colors = ("tab:blue", "tab:red", "tab:green", "tab:purple")
    for k, e in enumerate(result["scales"]):
        row, c = e["nodes"][str(node)], colors[k % len(colors)]
        s = np.asarray(e["linear_speeds_hz"])
        f = np.array([np.nan if v is None else v for v in row["linear_forward_m"]]) * 1e6
        u = np.asarray(e["linear_unstable"])
        ax.plot(s[~u], f[~u], "-", color=c, label=f"linear, x{e['scale']:g} unbalance")
        if u.any():
            ax.plot(s[u], f[u], ":", color=c, label="linear above the threshold (not reached)")
        if "runup_1x_m" in row:
            ax.plot(row["runup_speeds_hz"], np.asarray(row["runup_1x_m"]) * 1e6, "o", ms=3, color=c, alpha=0.7,
                    label=f"run-up 1x, x{e['scale']:g} ({e['run_status']})")
    if result["threshold_hz"] is not None:
        ax.axvline(result["threshold_hz"], color="k", ls="--", lw=0.8, label="stability threshold (linear)")
    ax.set_yscale("log")
    ax.set_xlabel("shaft speed [Hz]")
    ax.set_ylabel("1x forward whirl radius [um]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Linear unbalance response against the run-up at node {node}\n{title}", fontsize=9)
    return save_figure(fig, path)


def markdown(result: dict, figures=()) -> str:
    from ..tables import markdown_table

    def num(v, scale=1.0, fmt=".4g"):
        return "-" if v is None else format(v * scale, fmt)

    rows = []
    for e in result["scales"]:
        for n, r in e["nodes"].items():
            rows.append({"scale": f"x{e['scale']:g}", "node": n, "linear peak Hz": num(r["linear_peak_hz"]),
                         "linear um": num(r["linear_peak_m"], 1e6), "run-up peak Hz": num(r.get("runup_peak_hz")),
                         "run-up um": num(r.get("runup_peak_m"), 1e6),
                         "run-up / linear peak": num(r.get("peak_ratio"), 1.0, ".3f"),
                         "run": e["run_status"]})
    lines = [f"# Linear response against the run-up: {result['scene']}", "",
             f"internal {result['internal']} (run via {result['via']}); speeds {result['speeds_hz'][0]:g}-"
             f"{result['speeds_hz'][1]:g} Hz; linear stability threshold "
             + ("none in the range" if result["threshold_hz"] is None else f"{result['threshold_hz']:.2f} Hz"), "",
             "Linear: the steady 1x forward whirl radius; run-up: its 1x forward radius by order tracking per "
             "window (docs/response.md).", "", markdown_table(rows, [(c, c, "") for c in rows[0]]) if rows else "", ""]
    if figures:
        lines += [f"![{f.stem}]({f.name})" for f in figures] + [""]
    return "\n".join(lines)


def command(*, scene, scale=DEFAULT_SCALES, window_s=None, out="out", quiet: bool = False, no_plots: bool = False) -> int:
    """``rotor-host linear-vs-runup``: writes linear_vs_runup.json/.md, one figure per node and the runs."""
    from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

    out = ensure_writable(out)
    res = compare(scene, scale, out, window_s=window_s, progress=not quiet, log=lambda m: print(f"  {m}"))
    nodes = sorted({int(n) for e in res["scales"] for n in e["nodes"]})
    figs = [] if no_plots else [plot(res, n, out / f"linear_vs_runup_node{n}.png",
                                     f"{Path(res['scene']).name}; internal {res['internal']}") for n in nodes]
    files = [write_json(out / "linear_vs_runup.json", res), write_text(out / "linear_vs_runup.md", markdown(res, figs)),
             *figs]
    for e in res["scales"]:
        for n, r in e["nodes"].items():
            print(f"x{e['scale']:g} node {n}: linear peak {num_hz(r['linear_peak_hz'])} {num_um(r['linear_peak_m'])}, "
                  f"run-up 1x peak {num_hz(r.get('runup_peak_hz'))} {num_um(r.get('runup_peak_m'))} "
                  f"[{e['run_status']}]")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


def num_hz(v) -> str:
    return "-" if v is None else f"{v:.2f} Hz"


def num_um(v) -> str:
    return "-" if v is None else f"{v * 1e6:.4g} um"


__all__ = ["tracked_1x", "compare", "plot", "markdown", "command", "DEFAULT_SCALES"]
