"""``rotor-host sweep``: plan the runs, run them where the work is best run (``local.choose``: this
process, a pool of warm processes, a Dask cluster), write the summary (also of the runs that
finished when the sweep is interrupted), and print the fixed costs apart from the work."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

from bearing_fmu.io.interrupts import as_interrupted, note_kept
from bearing_fmu.io.fixed_costs import FixedCosts
from bearing_fmu.io.outputs import claim, ensure_writable

from bearing_fmu.parallel.cluster import dask_client, scheduler_named
from .execute import drop_stale_locks, finished_on_disk, sweep, warm_worker
from .local import choose, pool_start_method, run_inline, run_pool
from .plan import Point, check_fixed_speed, point_scene, points, run_base, settle_time, swept_values
from .summary import run_label, summary_diagram, write_summary

def command(*, scene, speeds_hz=None, unbalance_g=None, settle_s: float | None = None, scheduler: str | None = None,
            workers: int | None = None, execution: str = "auto", out="out/sweep", quiet: bool = False) -> int:
    """``rotor-host sweep``: the scene (a ``Scene``, overrides applied) at each speed of ``speeds_hz``
    or each unbalance mass of ``unbalance_g`` (lists of numbers or ranges' values), in this process,
    a pool of warm processes or on Dask (``local.choose``); the fixed costs printed apart from the work."""
    costs = FixedCosts()
    with costs.timed("imports"):
        from ...model.rotor import Rotor
        from ...scenes.bearings import scene_fmu
        from ...scenes.sanity import check_scene_physics

    if scheduler and workers:
        raise ValueError("--workers: sets the size of the local cluster; with --scheduler the cluster's own "
                         "workers run the sweep (give one of the two)")
    scheduler = scheduler_named(scheduler) if scheduler else None
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
    how = choose(execution, len(pts), workers=workers, scheduler=scheduler)
    build = None
    if scene.via == "fmu":  # one build for all runs, here, while a cluster starts (0.5 s each)
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(1, thread_name_prefix="build-fmu")
        build = pool.submit(_timed, scene_fmu, scene, None)  # the user's FMU cache: built once for every command
        pool.shutdown(wait=False)
    base = f"sweep_{run_base(scene)}" + ("_unbalance" if unbalance else "")
    t0 = time.perf_counter()
    with claim(out, base) as name:
        stem = name.path("")
        kw = dict(settle_s=settle_s, bearing_nodes=bearing_nodes, disk_nodes=disk_nodes, unbalance=unbalance)
        info = {"cluster": how.where, "execution": how.kind, "workers": how.workers}
        finished: dict[Point, dict] = {}
        diagram = dict(settle_s=settle_s, unbalance=unbalance)
        drawing = False
        try:
            rows = _execute(how, scene, build, pts, out, settle_s, disk_nodes, costs, info, finished, quiet)
            info.update(wall_s=time.perf_counter() - t0, run_s=sum(r.get("wall_s") or 0 for r in rows))
            t_summary = time.perf_counter()
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
          f"({info['run_s']:.1f} s of runs; {how.where}: {how.reason})")
    print(costs.line(info["work_s"], f"{len(rows)} runs") + f"; summary {time.perf_counter() - t_summary:.2f} s")
    for r in rows:
        if r["status"] != "ok":
            print(f"  {run_label(r, unbalance)}: {r['status']}: {r['message'][:300]}")
    # where the runs' files are: the folder asked for, or its rescue folder (a full disk)
    where = sorted({str(Path(f).parent) for r in rows for f in r.get("files") or []}) or [str(out)]
    print(f"wrote {', '.join(str(f) for f in files)} and each run's .npz/.json in {' and '.join(where)}")
    return 0 if n_ok else 1


def _timed(func, *args):
    """``func(*args)`` and its seconds (a build in a thread, while the workers start)."""
    t0 = time.perf_counter()
    return func(*args), time.perf_counter() - t0


def _execute(how, scene, build, pts: list[Point], out: Path, settle_s: float, disk_nodes: list[int],
             costs: FixedCosts, info: dict, finished: dict, quiet: bool) -> list[dict]:
    """The runs as ``how`` says, their rows in the order of ``pts``; each fixed cost in ``costs``
    (the FMU build, this process's kernels, the pool's or cluster's start, the workers' warm-up),
    the work's wall time in ``info["work_s"]``, the figures in ``info["fixed_costs_s"]``."""
    def fmu_built(scene):
        if build is None:
            return scene
        t0 = time.perf_counter()
        fmu, build_s = build.result()  # a build that failed (a missing file) raises here, by name
        costs.add("FMU build", build_s if how.kind != "cluster" else time.perf_counter() - t0)
        return replace(scene, fmu=fmu)

    try:
        if how.kind == "cluster":
            t0 = time.perf_counter()
            with dask_client(how.scheduler, how.workers) as client:
                costs.add("cluster connect" if how.scheduler else f"cluster start ({how.workers} workers)",
                          time.perf_counter() - t0)
                info["workers"] = len(client.nthreads())
                scene = fmu_built(scene)
                t_work = time.perf_counter()
                rows = sweep(client, scene, pts, out, settle_s, disk_nodes, progress=not quiet, rows=finished,
                             info=info, announce=True)
                costs.add("workers' kernels (side by side)", info.get("warm_wall_s"))
                work = time.perf_counter() - t_work - (info.get("warm_wall_s") or 0.0)
                t_close = time.perf_counter()
            costs.add("cluster close", time.perf_counter() - t_close)
        else:
            scene = fmu_built(scene)
            costs.add("kernels" + (" and FMUs" if scene.via == "fmu" else ""), warm_worker(scene))
            t_work = time.perf_counter()
            if how.kind == "inline":
                rows = run_inline(scene, pts, out, settle_s, disk_nodes, progress=not quiet, rows=finished)
            else:
                rows = run_pool(scene, pts, out, settle_s, disk_nodes, how.workers, progress=not quiet, rows=finished,
                                info=info)
                costs.add(f"pool start ({how.workers} workers, {pool_start_method()})", info.get("pool_s"))
            work = time.perf_counter() - t_work - (info.get("pool_s") or 0.0)
    finally:
        info["fixed_costs_s"] = costs.as_dict()
    info["work_s"] = work
    return rows


__all__ = ["command"]
