"""Sweeps: one scene run at many shaft speeds (or unbalance masses) in parallel on Dask.

``rotor-host sweep SCENE --speeds-hz 10:60:2.5`` runs the scene once per speed (or, with
``--unbalance-g 0 4 8.5 17``, once per mass of the scene's first ``[[unbalance]]``) as tasks
of a ``dask.distributed`` cluster: a ``LocalCluster`` on this machine by default (one worker
process per core, one thread each: the runs hold the GIL), or an existing cluster whose
scheduler ``--scheduler`` names. Each task is ``run.run_scene`` in a worker process; it
writes its own ``<scene>_<internal>_<speed>hz.npz/.json`` into the output folder and returns
one summary row (small, so nothing large crosses the network). The client collects the rows
as the runs finish (progress bar), and writes

* ``sweep_<scene>_<internal>.md/.json``: per run the speed (and unbalance), the status, per
  bearing the largest and smallest eccentricity ratio after the transient, per disk the
  largest and smallest distance from its static position, and the run time;
* ``sweep_<scene>_<internal>.png``: the bifurcation diagram, those values against speed (or
  unbalance) with the samples taken once per shaft revolution (docs/sweep.md: how to read it).

"After the transient" is the part of each run from ``--settle-s`` to its end (default: the
second half). A run that fails (no static equilibrium, a journal at the wall: status
``failed``) or raises in its worker (status ``error``) is a row of the summary with its
reason; the sweep goes on. Ctrl-C / SIGTERM cancel the runs not yet finished, write the
summary of those that did (status ``interrupted``) and exit 130 / 143.

Workers: each worker process imports the code and loads the compiled kernels once (numba's
on-disk cache beside the package, or the FMU code cache: the first run on each worker pays
it, later runs on it do not). Workers of a remote cluster need this package installed and
the scene's files and the output folder at the same paths (a shared file system).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from bearing_fmu.io.exits import as_interrupted, note_kept
from bearing_fmu.io.outputs import claim, ensure_writable, note_rescued, take_rescued, write_json, write_text

from ..scenes.thermal import settled_thermal
from .dask_cluster import check_scheduler, dask_client
from .plotting import pyplot, save_figure

MAX_RUNS = 1000  # a range that expands to more is a typo (a step in the wrong unit)


# ------------------------------------------------------------------ the values swept

def _flat(groups, option: str) -> list[float]:
    """The values of several command-line items (each a list: ``cliargs.float_range``), sorted,
    each once, at most MAX_RUNS of them."""
    values = sorted({v for g in groups for v in g})
    if len(values) > MAX_RUNS:
        raise ValueError(f"{option}: {len(values)} runs; a sweep takes at most {MAX_RUNS} (a step in the wrong unit?)")
    return values


@dataclass(frozen=True)
class Point:
    """One run of a sweep: the shaft speed [Hz], the first unbalance's mass [g] (None: the
    scene's own) and the stem of its result files."""

    speed_hz: float
    unbalance_g: float | None
    stem: str

    @property
    def label(self) -> str:
        return f"{self.speed_hz:g} Hz" if self.unbalance_g is None else f"{self.unbalance_g:g} g"


def run_base(scene) -> str:
    """``<scene file stem>_<internal>``: the start of every file name of a sweep of ``scene``."""
    return f"{Path(scene.source).stem if scene.source else scene.name}_{scene.internal}"


def points(scene, speeds_hz=None, unbalance_g=None) -> list[Point]:
    """The runs of a speed sweep (``speeds_hz``) or an unbalance sweep (``unbalance_g``: masses
    [g] on the scene's first [[unbalance]], at the scene's speed). Each run is at one constant
    speed: a scene with a [speed_profile] (a run-up) is refused."""
    base = run_base(scene)
    if getattr(scene, "speed_profile", None) is not None:
        option = "--unbalance-g" if unbalance_g is not None else "--speeds-hz"
        raise ValueError(f"{option}: the scene {scene.source} has a [speed_profile] (a run-up or coast-down); a sweep "
                         "runs each speed constant, from the static equilibrium: use a scene with speed_hz alone")
    if unbalance_g is not None:
        if not scene.unbalances:
            raise ValueError(f"--unbalance-g: the scene {scene.source} has no [[unbalance]] entry to vary; "
                             "add one (node, mass_kg, radius_mm) or sweep --speeds-hz")
        return [Point(scene.speed_hz, m, f"{base}_{m:.12g}g") for m in unbalance_g]
    return [Point(f, None, f"{base}_{f:.12g}hz") for f in speeds_hz]  # distinct: float_range rounds to 12 digits


def point_scene(scene, point: Point, disk_nodes: list[int]):
    """The scene of one run: its speed or first unbalance mass, and the disks recorded."""
    unb = list(scene.unbalances)
    if point.unbalance_g is not None:
        unb[0] = replace(unb[0], mass_kg=point.unbalance_g / 1e3)
    nodes = sorted(set(scene.record_nodes) | {n - 1 for n in disk_nodes})
    return replace(scene, speed_hz=point.speed_hz, unbalances=unb, record_nodes=nodes)


# ------------------------------------------------------------- what a run leaves

def settled_metrics(arrays: dict, settle_s: float, speed_hz: float, disk_nodes: list[int],
                    max_samples: int = 400) -> dict:
    """What the bifurcation diagram shows of one run, over t >= settle_s (the settled part):

    * per bearing: largest and smallest eccentricity ratio, and the eccentricity once per
      shaft revolution (linearly interpolated at settle_s + k / speed);
    * per disk (1-based node, recorded): largest and smallest distance of the disk centre
      from its static equilibrium position [um], and the same once per revolution;
    * with a supply temperature, per bearing its mean T_eff [K] and P_loss [W] (``settled_thermal``).

    Empty lists when fewer than two recorded steps lie in the window (a run that stopped
    before it), and no disk entry without a static position to measure from: nothing that
    cannot be computed is reported, so no NaN."""
    t = np.asarray(arrays["t"], float)
    win = t >= settle_s - 1e-12
    out = {"settled_samples": int(win.sum()), "bearings": [], "disks": []}
    if out["settled_samples"] < 2:
        return out
    tw = t[win]
    revs = settle_s + np.arange(max_samples) / speed_hz
    revs = revs[revs <= tw[-1] + 1e-12]
    nodes = [int(n) for n in np.asarray(arrays["nodes"])]
    ecc = np.asarray(arrays["eccentricity"], float)[win]
    for k, node in enumerate(np.asarray(arrays["bearing_nodes"]).tolist()):
        e = ecc[:, k]
        out["bearings"].append({"node": int(node), "ecc_max": float(e.max()), "ecc_min": float(e.min()),
                                "once_per_rev": np.interp(revs, tw, e).tolist()})
    for b, th in zip(out["bearings"], settled_thermal(arrays, win)):
        b.update(th)
    q0 = np.asarray(arrays["q0"], float)
    for node in disk_nodes:
        c = nodes.index(node)
        if not np.all(np.isfinite(q0[2 * c:2 * c + 2])):
            continue  # no static position to measure from (no equilibrium)
        r = 1e6 * np.hypot(np.asarray(arrays["y"])[win, c] - q0[2 * c], np.asarray(arrays["z"])[win, c] - q0[2 * c + 1])
        out["disks"].append({"node": node, "amp_max_um": float(r.max()), "amp_min_um": float(r.min()),
                             "once_per_rev_um": np.interp(revs, tw, r).tolist()})
    return out


def _status(meta: dict) -> str:
    status = meta["status"]
    if meta["crossed_clearance"]:  # the linear model's orbit may leave the clearance circle
        status = "crossed clearance" if status == "ok" else f"{status}, crossed clearance"
    return status


def warm_worker(scene, work_dir: str) -> float:
    """In a worker, before its first run: import the run's code and load the compiled kernels the
    scene's runs call (``scenes.run.load_kernels``); through FMUs, instantiate the scene's bearing
    FMUs once (their code and kernels load then), in ``work_dir``. Once per worker process, so no
    run's times count it. Seconds taken; never raises (a run that cannot load its code says so)."""
    t0 = time.perf_counter()
    try:
        from ..model.rotor import Rotor
        from ..scenes.run import bearing_loads, build_bearings, load_kernels
        from ..scenes.scene import G

        load_kernels(scene)
        if scene.via == "fmu":
            rotor = Rotor.from_toml(scene.rotor_path)
            f_static = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
            with build_bearings(scene, rotor, bearing_loads(rotor, f_static), Path(work_dir)):
                pass
    except Exception:  # noqa: BLE001 - only a head start: the first run loads what is missing, or fails by name
        pass
    return time.perf_counter() - t0


def run_point(scene, point: Point, out_dir: str, settle_s: float, disk_nodes: list[int]) -> dict:
    """One run of the sweep, in a worker: run the scene, write its files, return its row.
    An exception is a row with status ``error`` (named in one line), not a lost task."""
    t0 = time.perf_counter()
    row = {"speed_hz": point.speed_hz, "unbalance_g": point.unbalance_g, "stem": point.stem, "pid": os.getpid()}
    take_rescued()  # this worker's earlier runs' rescues were reported with their rows
    try:
        from ..scenes.run import run_scene

        run = run_scene(scene, out_dir, stem=point.stem, work_dir=Path(out_dir) / "fmu")
    except Exception as exc:  # noqa: BLE001 - reported in the summary, the sweep goes on
        return {**row, **error_fields(exc), "wall_s": time.perf_counter() - t0, "bearings": [], "disks": [],
                "rescued": [asdict(r) for r in take_rescued()]}
    row["rescued"] = [asdict(r) for r in take_rescued()]  # the client counts them (exit code 1)
    files = [str(run.npz), str(run.json)] if run.npz else []
    return {**row, **_run_fields(run.meta, run.arrays, files, point, settle_s, disk_nodes)}


def _run_fields(m: dict, arrays, files: list[str], point: Point, settle_s: float, disk_nodes: list[int]) -> dict:
    """A finished run's part of its row: from its metadata and arrays (in the worker, or from its
    files when the client was interrupted before it received the row)."""
    fields = dict(status=_status(m), message=m["message"], t_reached_s=m["t_reached_s"], wall_s=m["wall_time_s"],
                  integration_s=m["integration_time_s"], setup_s=m["setup_time_s"] + m["equilibrium_time_s"],
                  evals_per_step=m["newton_mean_evaluations_per_step"], step_cuts=m["step_cuts"],
                  static_eccentricity=m["equilibrium_eccentricity"], files=files)
    fields.update(settled_metrics(arrays, settle_s, point.speed_hz, disk_nodes))
    return fields


def finished_on_disk(out: Path, point: Point, settle_s: float, disk_nodes: list[int]) -> dict | None:
    """The row of a run that finished and was written (its json neither running nor interrupted)
    though the client had not received it yet, rebuilt from its files; else None."""
    import json

    js, npz = out / f"{point.stem}.json", out / f"{point.stem}.npz"
    try:
        m = json.loads(js.read_text())
        if m.get("status") in ("running", "interrupted") or not npz.is_file():
            return None
        with np.load(npz) as data:
            arrays = {k: data[k] for k in data.files}
        row = {"speed_hz": point.speed_hz, "unbalance_g": point.unbalance_g, "stem": point.stem, "pid": m.get("pid"),
               "rescued": []}
        return {**row, **_run_fields(m, arrays, [str(npz), str(js)], point, settle_s, disk_nodes)}
    except (OSError, ValueError, KeyError):  # not there, or being written: not kept
        return None


def error_fields(exc: BaseException) -> dict:
    """Status and one-line message of a run that raised (in its worker, or a worker that died)."""
    text = " ".join(str(exc).split()) or "(no message)"
    return {"status": "error", "message": f"{type(exc).__name__}: {text}"}


# ------------------------------------------------------------------ running on Dask

def sweep(client, scene, pts: list[Point], out_dir: Path, settle_s: float, disk_nodes: list[int], *,
          progress: bool = True, log=print, rows: dict | None = None, info: dict | None = None) -> list[dict]:
    """Run every point as a task on ``client``; return the rows in the order the points are
    given. Each worker first loads the code and kernels the runs call (``warm_worker``; the
    slowest worker's seconds go to ``info["warm_s"]``). ``rows`` (point -> row) fills as the runs
    finish, for a caller whose interrupt may come after this returns (in closing the cluster).
    On an interrupt the tasks not finished are cancelled; the rows that are there are attached
    to the exception (``exc.sweep_rows``) and it is raised again."""
    import threading

    from dask.distributed import as_completed
    from tqdm import tqdm

    # the diagram's matplotlib imported while the workers run (0.6 s the command would wait for after them)
    threading.Thread(target=pyplot, daemon=True, name="import-matplotlib").start()
    # all workers at once, before any run; a worker lost meanwhile is the business of the runs' rows
    warm = [s for s in client.run(warm_worker, scene, str(Path(out_dir) / "fmu"), on_error="return").values()
            if isinstance(s, float)]
    if info is not None and warm:
        info["warm_s"] = max(warm)
    futures = {client.submit(run_point, point_scene(scene, p, disk_nodes), p, str(out_dir), settle_s, disk_nodes,
                             key=f"sweep-{p.stem}-{os.getpid()}-{time.time_ns()}", pure=False, priority=-i): p
               for i, p in enumerate(pts)}
    rows = {} if rows is None else rows
    bar = tqdm(total=len(pts), unit="run", desc=f"sweep {scene.name} [{scene.internal}]", disable=not progress)
    try:
        for fut in as_completed(futures):
            p = futures[fut]
            rows[p] = _collect(fut, p)
            bar.update(1)
            bar.set_postfix_str(f"{p.label}: {rows[p]['status']}")
            if rows[p]["status"] != "ok":
                (bar.write if progress else log)(f"  {p.label}: {rows[p]['status']}: {rows[p]['message'][:300]}")
    except KeyboardInterrupt as exc:
        for fut, p in futures.items():  # finished but not yet collected: they count
            if p not in rows and fut.status == "finished":
                rows[p] = _collect(fut, p)
        client.cancel(list(futures))  # queued runs never start; running ones end with their workers
        exc.sweep_rows = [rows[p] for p in pts if p in rows]
        raise
    finally:
        bar.close()
    return [rows[p] for p in pts]


def _collect(fut, point: Point) -> dict:
    """The row of a finished task; the files its worker had to rescue count as this command's."""
    row = _result(fut, point)
    for r in row.get("rescued", []):
        note_rescued(**r)
    return row


def _result(fut, point: Point) -> dict:
    """The row of a finished task; a task whose worker raised or died is an ``error`` row."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - a worker that died (KilledWorker), a pickling error...
        return {"speed_hz": point.speed_hz, "unbalance_g": point.unbalance_g, "stem": point.stem,
                **error_fields(exc), "bearings": [], "disks": []}


# ------------------------------------------------------------------------ the summary

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
    from .report import markdown_table

    what = (f"unbalance on node {scene.unbalances[0].node + 1} at {scene.unbalances[0].radius_m * 1e3:g} mm, "
            f"{scene.speed_hz:g} Hz" if unbalance else "shaft speed")
    title = sweep_title(scene, rows, unbalance)
    lines = [f"# {title}", "",
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
        lines += [f"- {_label(r, unbalance)}: {r['status']}: {r['message']}" for r in bad]
    out = [write_text(f"{path_stem}.md", "\n".join(lines) + "\n")]
    out.append(write_json(f"{path_stem}.json", {
        "scene": str(scene.source), "internal": scene.internal, "via": scene.via, "dt_s": scene.dt_s,
        "t_end_s": scene.t_end_s, "settle_s": settle_s, "swept": "unbalance_g" if unbalance else "speed_hz",
        "status": "interrupted" if note else "ok", "note": note, **info, "rows": rows}, indent=1))
    png = summary_diagram(path_stem, scene, rows, settle_s=settle_s, unbalance=unbalance) if plot else None
    return out + ([png] if png else [])


def summary_diagram(path_stem: Path, scene, rows: list[dict], *, settle_s: float, unbalance: bool) -> Path | None:
    """The bifurcation diagram ``<stem>.png`` of the summary, when a run has something to draw,
    titled from the sweep (the swept quantity and range, not the scene's own speed)."""
    if not any(r["status"] == "ok" and r.get("bearings") for r in rows):
        return None
    return plot_bifurcation(rows, f"{path_stem}.png", unbalance=unbalance,
                            title=f"{sweep_title(scene, rows, unbalance)}\n{scene.internal} via {scene.via}, after "
                                  f"the transient: t >= {settle_s:g} s of {scene.t_end_s:g} s per run")


def _label(r: dict, unbalance: bool) -> str:
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
    n_b = max((len(r["bearings"]) for r in good), default=0)
    for k in range(n_b):
        xs = [r[key] for r in good]
        _ranges(ax_b, xs, [r["bearings"][k]["ecc_max"] for r in good], [r["bearings"][k]["ecc_min"] for r in good],
                [r["bearings"][k]["once_per_rev"] for r in good], colors[k % len(colors)],
                f"bearing {k + 1} (node {good[0]['bearings'][k]['node']})", filled=k == 0)
        stat = [(r[key], r["static_eccentricity"][k]) for r in good if r.get("static_eccentricity")]
        if stat:
            ax_b.plot(*zip(*stat), "--", color=colors[k % len(colors)], lw=0.8, alpha=0.7,
                      label="static equilibrium" if k == 0 else None)
    ax_b.set_ylabel("bearing eccentricity ratio")
    ax_b.set_ylim(0, 1.0)
    if has_disk:
        ax_d = axes[1, 0]
        n_d = max(len(r["disks"]) for r in good)
        for k in range(n_d):
            g = [r for r in good if len(r["disks"]) > k]
            _ranges(ax_d, [r[key] for r in g], [r["disks"][k]["amp_max_um"] for r in g],
                    [r["disks"][k]["amp_min_um"] for r in g], [r["disks"][k]["once_per_rev_um"] for r in g],
                    colors[(n_b + k) % len(colors)], f"disk (node {g[0]['disks'][k]['node']})", filled=True)
        ax_d.set_ylabel("disk amplitude from static position [um]")
        _amplitude_scale(ax_d, [v for r in good for d in r["disks"] for v in (d["amp_max_um"], d["amp_min_um"])])
    failed = [r for r in rows if r not in good]
    for ax in axes[:, 0]:
        for i, r in enumerate(failed):
            ax.plot(r[key], 0, "x", color="red", ms=9, mew=2, clip_on=False, transform=ax.get_xaxis_transform(),
                    label="failed or stopped (see the summary)" if i == 0 else None)
        ax.grid(alpha=0.3, which="both")
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


def _ranges(ax, xs, hi, lo, samples, color, label, filled) -> None:
    """Per x: a vertical bar lo..hi with end markers, and the once-per-revolution samples."""
    face = color if filled else "none"
    ax.vlines(xs, lo, hi, color=color, lw=1.0, alpha=0.6)
    ax.plot(xs, hi, "^", color=color, mfc=face, ms=6, ls="none", label=f"{label}: max")
    ax.plot(xs, lo, "v", color=color, mfc=face, ms=6, ls="none", label=f"{label}: min")
    px = [x for x, s in zip(xs, samples) for _ in s]
    py = [v for s in samples for v in s]
    if px:
        ax.plot(px, py, ".", color="0.35", ms=2, ls="none", alpha=0.6,
                label="once per revolution" if filled else None)


# ------------------------------------------------------------------------ command line


FIXED_SPEED_RTOL = 1e-9  # what the fixed-speed internals take as their speed (Taylor: OMEGA_RTOL)


def check_fixed_speed(scene, speeds_hz) -> None:
    """An internal that answers only at the speed its data was made for (capability
    ``fixed_speed``: a fitted surrogate) refuses any other: refuse a speed sweep with it before
    any run, naming what does sweep speeds."""
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.registry import Context

    from ..model.rotor import Rotor

    spec = registry.get(scene.internal)
    if not spec.can.fixed_speed:
        return
    params = Rotor.from_toml(scene.rotor_path).bearings[0]
    f0 = registry.create(spec.name, params, scene.internal_options(), Context(omega=scene.omega),
                         where=str(scene.source)).omega / (2 * math.pi)
    other = [f for f in speeds_hz if abs(f - f0) > FIXED_SPEED_RTOL * f0]
    if other:
        sweepers = ", ".join(n for n in registry.having(any_state=True))
        raise ValueError(f"--speeds-hz: the {spec.name} internal answers only at the speed its data was made for "
                         f"({f0:g} Hz), not at {', '.join(f'{f:g}' for f in other[:4])}"
                         f"{' ...' if len(other) > 4 else ''} Hz; sweep speeds with an internal valid at any speed "
                         f"({sweepers}), or sweep --unbalance-g at {f0:g} Hz")


def _settle(settle_s: float | None, scene) -> float:
    settle = scene.t_end_s / 2 if settle_s is None else settle_s
    if settle >= scene.t_end_s:
        raise ValueError(f"--settle-s {settle:g}: must be less than the run's end time t_end = {scene.t_end_s:g} s "
                         "(the summary needs a settled part to measure)")
    return settle


def _drop_stale_locks(out: Path, pts: list[Point]) -> None:
    """Remove the name locks (``outputs.claim``) that stopped workers left behind: their
    process is gone, so they hold nothing (a later run would take them over anyway)."""
    from bearing_fmu.io.outputs import pid_alive

    for p in pts:
        lock = out / f"{p.stem}.lock"
        try:
            if not pid_alive(int(lock.read_text().strip())):
                lock.unlink()
        except (OSError, ValueError):
            pass


def command(*, scene, speeds_hz=None, unbalance_g=None, settle_s: float | None = None, scheduler: str | None = None,
            workers: int | None = None, out="out/sweep", quiet: bool = False) -> int:
    """``rotor-host sweep``: the scene (a ``Scene``, overrides applied) at each speed of ``speeds_hz``
    or each unbalance mass of ``unbalance_g`` (lists of numbers or ranges' values), on Dask."""
    from ..model.rotor import Rotor
    from ..scenes.run import scene_fmu

    if scheduler and workers:
        raise ValueError("--workers: sets the size of the local cluster; with --scheduler the cluster's own "
                         "workers run the sweep (give one of the two)")
    settle_s = _settle(settle_s, scene)
    out = ensure_writable(Path(out).resolve())
    unbalance = unbalance_g is not None
    pts = (points(scene, unbalance_g=_flat(unbalance_g, "--unbalance-g")) if unbalance
           else points(scene, _flat(speeds_hz, "--speeds-hz")))
    check_fixed_speed(scene, [p.speed_hz for p in pts])
    rotor = Rotor.from_toml(scene.rotor_path)
    bearing_nodes = [n + 1 for n in rotor.bearing_nodes]
    disk_nodes = sorted({d.node + 1 for d in rotor.disks})
    build = None
    if scene.via == "fmu":  # one build for all runs, here, while the cluster starts (0.5 s each)
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(1, thread_name_prefix="build-fmu")
        build = pool.submit(scene_fmu, scene, out / "fmu")
        pool.shutdown(wait=False)
    base = f"sweep_{run_base(scene)}" + ("_unbalance" if unbalance else "")
    t0 = time.perf_counter()
    with claim(out, base) as name:
        stem = name.path("")
        kw = dict(settle_s=settle_s, bearing_nodes=bearing_nodes, disk_nodes=disk_nodes, unbalance=unbalance)
        info = {"cluster": scheduler or "local cluster", "workers": None}
        finished: dict[Point, dict] = {}
        diagram = dict(settle_s=settle_s, unbalance=unbalance)
        drawing = False
        try:
            with dask_client(scheduler, workers) as client:
                info["workers"] = len(client.nthreads())
                if build is not None:  # a build that failed (a missing file) raises here, by name
                    scene = replace(scene, fmu=build.result())
                rows = sweep(client, scene, pts, out, settle_s, disk_nodes, progress=not quiet, rows=finished,
                             info=info)
            info.update(wall_s=time.perf_counter() - t0, run_s=sum(r.get("wall_s") or 0 for r in rows))
            files = write_summary(stem, scene, rows, info=info, **kw, plot=False)
            drawing = True
            files += [f for f in [summary_diagram(stem, scene, rows, **diagram)] if f]
        except KeyboardInterrupt as exc:  # in the runs, closing the cluster (workers stopped) or writing: keep them
            for p in pts:  # runs written but not yet received (the interrupt came first): from their files
                if p not in finished:
                    row = finished_on_disk(out, p, settle_s, disk_nodes)
                    if row is not None:
                        finished[p] = row
            done = exc.sweep_rows = [finished[p] for p in pts if p in finished]
            _drop_stale_locks(out, pts)
            if done:
                info.update(wall_s=time.perf_counter() - t0, run_s=sum(r.get("wall_s") or 0 for r in done))
                what = (f"all {len(pts)} runs had finished" if len(done) == len(pts)
                        else f"the {len(done)} of {len(pts)} runs that finished")
                sig = as_interrupted(exc).signal_name
                files = write_summary(stem, scene, done, info=info, **kw, plot=False,
                                      note=f"interrupted by {sig}{' while drawing the diagram' if drawing else ''}: "
                                           f"{what}")
                try:  # unless the interrupt came while drawing it; a second interrupt skips it, the table is kept
                    files += [f for f in [None if drawing else summary_diagram(stem, scene, done, **diagram)] if f]
                except KeyboardInterrupt:
                    pass
                note_kept(exc, f"{', '.join(str(f) for f in files)} ({len(done)} of {len(pts)} runs finished, "
                               f"each with its .npz/.json)")
            raise
    n_ok = sum(r["status"] == "ok" for r in rows)
    print(f"{n_ok} of {len(rows)} runs ok in {info['wall_s']:.1f} s on {info['workers']} worker(s) "
          f"({info['run_s']:.1f} s of runs)")
    for r in rows:
        if r["status"] != "ok":
            print(f"  {_label(r, unbalance)}: {r['status']}: {r['message'][:300]}")
    print(f"wrote {', '.join(str(f) for f in files)} and each run's .npz/.json in {out}")
    return 0 if n_ok else 1


__all__ = ["Point", "run_base", "points", "point_scene", "settled_metrics", "warm_worker",
           "run_point", "check_fixed_speed", "check_scheduler", "dask_client", "sweep", "sweep_title", "write_summary",
           "summary_diagram", "plot_bifurcation", "command"]
