"""How a sweep runs: each run a task of a Dask cluster (``run_point`` in a worker: the scene run,
its files written, one summary row returned, ``settled_metrics`` of its settled part), the
workers warmed first, the rows collected as they finish, an interrupt's finished runs kept (also
from their files, ``finished_on_disk``)."""

from __future__ import annotations

import os
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from bearing_fmu.io.outputs import note_rescued, take_rescued

from ...scenes.thermal import settled_thermal
from ..plotting import pyplot
from .plan import Point, point_scene

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


def warm_worker(scene) -> float:
    """In a worker, before its first run: import the run's code and load the compiled kernels the
    scene's runs call (``scenes.run.load_kernels``); through FMUs, instantiate the scene's bearing
    FMUs once (their code and kernels load then; built in the user's FMU cache). Once per worker process, so no
    run's times count it. Seconds taken; never raises (a run that cannot load its code says so)."""
    t0 = time.perf_counter()
    try:
        from ...model.rotor import Rotor
        from ...scenes.bearings import build_bearings
        from ...scenes.run import bearing_loads, load_kernels
        from ...scenes.scene import G

        load_kernels(scene)
        if scene.via == "fmu":
            rotor = Rotor.from_toml(scene.rotor_path)
            f_static = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
            with build_bearings(scene, rotor, bearing_loads(rotor, f_static), None):
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
        from ...scenes.run import run_scene

        run = run_scene(scene, out_dir, stem=point.stem)
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
          progress: bool = True, log=print, rows: dict | None = None, info: dict | None = None,
          announce: bool = False) -> list[dict]:
    """Run every point as a task on ``client``; return the rows in the order the points are
    given. Each worker first loads the code and kernels the runs call (``warm_worker``; the
    slowest worker's seconds go to ``info["warm_s"]``). ``rows`` (point -> row) fills as the runs
    finish, for a caller whose interrupt may come after this returns (in closing the cluster).
    On an interrupt the tasks not finished are cancelled; the rows that are there are attached
    to the exception (``exc.sweep_rows``) and it is raised again."""
    import threading

    from dask.distributed import as_completed

    # the diagram's matplotlib imported while the workers run (0.6 s the command would wait for after them)
    threading.Thread(target=pyplot, daemon=True, name="import-matplotlib").start()
    # all workers at once, before any run; a worker lost meanwhile is the business of the runs' rows
    t0 = time.perf_counter()
    if announce:  # once, whatever the number of workers (a cold numba cache: each compiles the kernels once)
        print(f"loading the code and compiled kernels in the {len(client.nthreads())} workers side by side, "
              "once per worker", file=sys.stderr, flush=True)
    warm = [s for s in client.run(warm_worker, scene, on_error="return").values()
            if isinstance(s, float)]
    if info is not None and warm:
        info["warm_s"] = max(warm)
        info["warm_wall_s"] = time.perf_counter() - t0
    futures = {client.submit(run_point, point_scene(scene, p, disk_nodes), p, str(out_dir), settle_s, disk_nodes,
                             key=f"sweep-{p.stem}-{os.getpid()}-{time.time_ns()}", pure=False, priority=-i): p
               for i, p in enumerate(pts)}

    def interrupted(rows: dict) -> None:
        for fut, p in futures.items():  # finished but not yet collected: they count
            if p not in rows and fut.status == "finished":
                rows[p] = _collect_row(row_of(fut, p))
        client.cancel(list(futures))  # queued runs never start; running ones end with their workers

    finished = ((futures[fut], row_of(fut, futures[fut])) for fut in as_completed(futures))
    return gather(finished, scene, pts, progress=progress, log=log, rows=rows, on_interrupt=interrupted)


def gather(finished, scene, pts: list[Point], *, progress: bool = True, log=print, rows: dict | None = None,
           on_interrupt=None) -> list[dict]:
    """Collect the rows as the runs finish, whatever runs them: ``finished`` yields (point, row)
    pairs; a progress bar, a line per run that did not end ``ok``. On an interrupt,
    ``on_interrupt(rows)`` adds what finished meanwhile and stops the rest; the rows that are
    there are attached to the exception (``exc.sweep_rows``) and it is raised again."""
    from tqdm import tqdm

    rows = {} if rows is None else rows
    bar = tqdm(total=len(pts), unit="run", desc=f"sweep {scene.name} [{scene.internal}]", disable=not progress)
    try:
        for p, row in finished:
            rows[p] = _collect_row(row)
            bar.update(1)
            bar.set_postfix_str(f"{p.label}: {rows[p]['status']}")
            if rows[p]["status"] != "ok":
                (bar.write if progress else log)(f"  {p.label}: {rows[p]['status']}: {rows[p]['message'][:300]}")
    except KeyboardInterrupt as exc:
        if on_interrupt is not None:
            on_interrupt(rows)
        exc.sweep_rows = [rows[p] for p in pts if p in rows]
        raise
    finally:
        bar.close()
    return [rows[p] for p in pts]


def _collect_row(row: dict) -> dict:
    """A finished run's row; the files its worker had to rescue count as this command's."""
    for r in row.get("rescued", []):
        note_rescued(**r)
    return row


def row_of(fut, point: Point) -> dict:
    """The row of a finished task (a Dask or a ``concurrent.futures`` future); a task whose
    worker raised or died is an ``error`` row."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - a worker that died (KilledWorker), a pickling error...
        return {"speed_hz": point.speed_hz, "unbalance_g": point.unbalance_g, "stem": point.stem,
                **error_fields(exc), "bearings": [], "disks": []}


def drop_stale_locks(out: Path, pts: list[Point]) -> None:
    """Remove the name locks (``outputs.claim``) that stopped workers left behind: their
    process is gone, so they hold nothing (a later run would take them over anyway). This
    process's own are freed at the command's end (``outputs.release_held``)."""
    from bearing_fmu.io.outputs import pid_alive

    for p in pts:
        lock = out / f"{p.stem}.lock"
        try:
            if not pid_alive(int(lock.read_text().strip())):
                lock.unlink()
        except (OSError, ValueError):
            pass


__all__ = ["settled_metrics", "warm_worker", "run_point", "finished_on_disk", "error_fields", "sweep", "gather",
           "row_of", "drop_stale_locks"]
