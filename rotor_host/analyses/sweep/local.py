"""Where a sweep runs, chosen by the work: in this process, in a pool of warm worker processes,
or on a Dask cluster, and the first two of these (the Dask one is ``execute.sweep``).

A local Dask cluster costs 2-4 s to start (a scheduler, a nanny and a worker process per core,
each importing dask.distributed and then the code, and loading the kernels) and a few ms per
task; a pool of processes forked from this one, once it has loaded the code and the kernels,
starts warm in a few hundredths of a second and runs the same ``run_point`` on the same
arguments, so on one machine the cluster costs more than it saves (benchmarks/sweep_fixed_costs.py).
``choose`` therefore picks (``--execution auto``, the default):

* a cluster that is already running: ``--scheduler``, or one left running for later commands
  (``bearing_fmu.parallel.cluster.running_scheduler``: nothing to start, its workers stay warm between commands);
* this process (``inline``) when one worker would run everything (``--workers 1``, one run):
  a second process would only add its start;
* else a pool of ``--workers`` processes (default: the cores), forked once this process is warm
  (where the platform forks; elsewhere started and warmed side by side).

``--execution cluster`` still starts a LocalCluster (a run lost with a crashed worker is run
again on another; a pool reports it as an ``error`` row). The rows are the same whichever runs them.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading
import time
from dataclasses import dataclass

from ..plotting import pyplot
from .execute import gather, row_of, run_point, warm_worker
from .plan import Point, point_scene

EXECUTIONS = ("auto", "inline", "pool", "cluster")


@dataclass(frozen=True)
class Execution:
    """How a sweep runs: ``kind`` inline | pool | cluster, its ``workers`` (None: a cluster's
    own), the ``scheduler`` of a running cluster (None: a LocalCluster started for the sweep)
    and why it was chosen (one line)."""

    kind: str
    workers: int | None
    scheduler: str | None = None
    reason: str = ""

    @property
    def where(self) -> str:
        """What ran the runs, for the summary."""
        if self.kind == "inline":
            return "the command's own process"
        if self.kind == "pool":
            return f"a pool of {self.workers} {pool_start_method()}ed processes"
        return self.scheduler or "local cluster"


def choose(execution: str, n_runs: int, *, workers: int | None, scheduler: str | None, log=print) -> Execution:
    """The execution of ``n_runs`` runs (module docstring): ``execution`` is the command line's
    ``--execution``; ``workers`` its ``--workers``, ``scheduler`` its ``--scheduler`` (an address)."""
    from bearing_fmu.parallel.cluster import running_scheduler

    if execution not in EXECUTIONS:
        raise ValueError(f"--execution {execution}: one of {', '.join(EXECUTIONS)}")
    if scheduler:
        if execution in ("inline", "pool"):
            raise ValueError(f"--execution {execution}: runs on this machine; --scheduler names a cluster (give one)")
        return Execution("cluster", None, scheduler, "--scheduler")
    n = max(1, min(workers or os.cpu_count() or 1, n_runs))
    if execution == "cluster":
        return Execution("cluster", workers or os.cpu_count() or 1, None, "--execution cluster")
    if execution == "auto" and not workers:
        address = running_scheduler(log)
        if address:
            return Execution("cluster", None, address, "a cluster left running")
    if execution == "inline" or (execution == "auto" and n == 1):
        return Execution("inline", 1, None, "one worker" if execution == "auto" else "--execution inline")
    return Execution("pool", n, None, "--execution pool" if execution == "pool" else
                     "a local cluster would cost more than it saves")


def pool_start_method() -> str:
    """fork where a forked child is safe (Linux): it starts with this process's code and kernels
    loaded; elsewhere spawn (each worker imports and loads them, side by side)."""
    return "fork" if sys.platform.startswith("linux") else "spawn"


def run_inline(scene, pts: list[Point], out_dir, settle_s: float, disk_nodes: list[int], *, progress: bool = True,
               log=print, rows: dict | None = None) -> list[dict]:
    """The runs one after the other in this process (warm: ``warm_worker`` before)."""
    finished = ((p, run_point(point_scene(scene, p, disk_nodes), p, str(out_dir), settle_s, disk_nodes)) for p in pts)
    return gather(finished, scene, pts, progress=progress, log=log, rows=rows)


def run_pool(scene, pts: list[Point], out_dir, settle_s: float, disk_nodes: list[int], workers: int, *,
             progress: bool = True, log=print, rows: dict | None = None, info: dict | None = None) -> list[dict]:
    """The runs on a pool of ``workers`` processes. Forking (Linux), this process runs the first
    point itself, then forks the pool for the rest: a real run warms everything a run calls
    (the kernels ``warm_worker`` loads, and the equilibrium's and the recorder's code paths,
    0.5-4 s more in a fresh worker; on a cold numba cache it compiles them once, not once per
    worker), and every worker starts with it. Spawning, the workers warm side by side.
    ``info`` gets the pool's start [s] (``pool_s``). On an interrupt the queued runs are
    cancelled and the workers stopped at once (a stopped run leaves its last checkpoint)."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    method = pool_start_method()
    first, rest = (pts[:1], pts[1:]) if method == "fork" and len(pts) > 1 else ([], pts)
    state: dict = {}

    def finished():
        for p in first:
            yield p, run_point(point_scene(scene, p, disk_nodes), p, str(out_dir), settle_s, disk_nodes)
        t0 = time.perf_counter()
        # the workers ignore SIGINT (inherited): Ctrl-C reaches the terminal's whole process group and
        # only this process acts on it (as for the Dask workers: bearing_fmu.parallel.cluster.dask_client)
        main = threading.current_thread() is threading.main_thread()
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            pool = state["pool"] = ProcessPoolExecutor(
                min(workers, len(rest)), mp_context=multiprocessing.get_context(method), initializer=_worker_start,
                initargs=(scene if method == "spawn" else None,))
            # a forking pool forks all its workers at the first submit: here
            futures = state["futures"] = {
                pool.submit(run_point, point_scene(scene, p, disk_nodes), p, str(out_dir), settle_s, disk_nodes): p
                for p in rest}
        finally:
            if main:
                signal.signal(signal.SIGINT, old)
        if info is not None:
            info["pool_s"] = time.perf_counter() - t0
        threading.Thread(target=pyplot, daemon=True, name="import-matplotlib").start()  # after the fork
        for fut in as_completed(futures):
            yield futures[fut], row_of(fut, futures[fut])

    def interrupted(rows: dict) -> None:
        for fut, p in state.get("futures", {}).items():  # finished but not yet collected: they count
            if p not in rows and fut.done() and not fut.cancelled():
                rows[p] = row_of(fut, p)
        _stop(state.get("pool"))

    try:
        out = gather(finished(), scene, pts, progress=progress, log=log, rows=rows, on_interrupt=interrupted)
    except BaseException:
        _stop(state.get("pool"))
        raise
    state["pool"].shutdown(wait=True)  # every run has ended: the idle workers exit at once
    return out


def _worker_start(scene) -> None:
    """In each pool worker, first: SIGTERM ends it (not the parent's interrupt handler, which a
    fork inherits); spawned, load the code and kernels (``warm_worker``)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if scene is not None:
        warm_worker(scene)


def _stop(pool) -> None:
    """Cancel the queued runs and terminate the pool's workers now: a run in progress would hold
    its worker (and the interpreter's exit, which joins the pool) until it ends."""
    if pool is None:
        return
    pool.shutdown(wait=False, cancel_futures=True)
    for child in multiprocessing.active_children():  # this process's children: the pool's workers
        child.terminate()
    for child in multiprocessing.active_children():
        child.join(timeout=2)


__all__ = ["EXECUTIONS", "Execution", "choose", "pool_start_method", "run_inline", "run_pool"]
