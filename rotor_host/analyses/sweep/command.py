"""``rotor-host sweep``: plan the runs, run them on a Dask cluster, write the summary (also of
the runs that finished when the sweep is interrupted)."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

from bearing_fmu.io.exits import as_interrupted, note_kept
from bearing_fmu.io.outputs import claim, ensure_writable

from ..dask_cluster import dask_client
from .execute import drop_stale_locks, finished_on_disk, sweep
from .plan import Point, check_fixed_speed, point_scene, points, run_base, settle_time, swept_values
from .summary import run_label, summary_diagram, write_summary

def command(*, scene, speeds_hz=None, unbalance_g=None, settle_s: float | None = None, scheduler: str | None = None,
            workers: int | None = None, out="out/sweep", quiet: bool = False) -> int:
    """``rotor-host sweep``: the scene (a ``Scene``, overrides applied) at each speed of ``speeds_hz``
    or each unbalance mass of ``unbalance_g`` (lists of numbers or ranges' values), on Dask."""
    from ...model.rotor import Rotor
    from ...scenes.run import scene_fmu
    from ...scenes.sanity import check_scene_physics

    if scheduler and workers:
        raise ValueError("--workers: sets the size of the local cluster; with --scheduler the cluster's own "
                         "workers run the sweep (give one of the two)")
    settle_s = settle_time(settle_s, scene)
    out = ensure_writable(Path(out).resolve())
    unbalance = unbalance_g is not None
    pts = (points(scene, unbalance_g=swept_values(unbalance_g, "--unbalance-g")) if unbalance
           else points(scene, swept_values(speeds_hz, "--speeds-hz")))
    check_fixed_speed(scene, [p.speed_hz for p in pts])
    rotor = Rotor.from_toml(scene.rotor_path)
    # the step against the fastest run's period, the speed and unbalance against the rotor: before any run
    for p in {max(pts, key=lambda p: p.speed_hz), max(pts, key=lambda p: p.unbalance_g or 0.0)}:
        check_scene_physics(point_scene(scene, p, []), rotor)
    bearing_nodes = [n + 1 for n in rotor.bearing_nodes]
    disk_nodes = sorted({d.node + 1 for d in rotor.disks})
    build = None
    if scene.via == "fmu":  # one build for all runs, here, while the cluster starts (0.5 s each)
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(1, thread_name_prefix="build-fmu")
        build = pool.submit(scene_fmu, scene, None)  # the user's FMU cache: built once for every command
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
            drop_stale_locks(out, pts)
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
            print(f"  {run_label(r, unbalance)}: {r['status']}: {r['message'][:300]}")
    print(f"wrote {', '.join(str(f) for f in files)} and each run's .npz/.json in {out}")
    return 0 if n_ok else 1


__all__ = ["command"]
