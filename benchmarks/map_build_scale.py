"""How ``bearing-fmu map`` scales on a Dask cluster (issue 35 item 5; docs/forcemap.md, "Building on a
cluster"): the same build on a local cluster of 1 and of 2 worker processes, side by side and
alternating (the machine is shared: its load is printed), and what a projection to many cores needs:
the scheduler's cost per task, the bytes a row task moves, the cost of one Reynolds solve and of
writing a row into the partial file.

    PYTHONPATH=. python benchmarks/map_build_scale.py [--resolution 96x96 --phases 4 --repeats 2]
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import pickle
import tempfile
import time
from functools import partial as bind
from pathlib import Path

import numpy as np


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def noop(x):
    return x


def cpu_s() -> float:
    """This process's CPU time [s] (run on every worker: the work each did, whatever the load)."""
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def worker_cpu(address: str) -> dict:
    from dask.distributed import Client

    with Client(address) as c:
        return c.run(cpu_s)


def main() -> None:
    from dask.distributed import Client, LocalCluster

    from bearing_fmu.internals.map.build import build_map
    from bearing_fmu.internals.map.store import settings_for
    from bearing_fmu.internals.map.tables import table_row
    from bearing_fmu.physics.params import PAPER_BEARING as P

    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--resolution", default="96x96", help="N_EPSxN_BETA of the full bore's map (default: the default)")
    ap.add_argument("--phases", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--tasks", type=int, default=2000, help="no-op tasks to time the scheduler with")
    a = ap.parse_args()
    n_eps, n_beta = (int(v) for v in a.resolution.split("x"))
    settings = settings_for(P, resolution=(n_eps, n_beta), phases=a.phases)
    solves = 2 * n_eps * n_beta * a.phases
    print(f"map {n_eps} x {n_beta}, {a.phases} phases, Reynolds {settings.n_theta} x {settings.n_x}: {solves} solves, "
          f"{n_eps} row tasks; load {load()}")
    out = {"settings": str(settings), "runs": []}
    tmp = Path(tempfile.mkdtemp(prefix="map-scale-"))
    clusters = {n: LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                silence_logs=logging.CRITICAL) for n in (1, 2)}
    try:
        for n, c in clusters.items():  # every worker loads the kernels (numba's cache) before the timing
            build_map(P, settings_for(P, resolution=(4 * n, 8), grid=(settings.n_theta, settings.n_x), phases=1),
                      tmp / f"warm{n}.partial", scheduler=c.scheduler_address)
        times = {1: [], 2: []}
        for r in range(a.repeats):
            for n in (1, 2) if r % 2 == 0 else (2, 1):  # alternating: a change of load hits both
                before, cpu0 = load(), worker_cpu(clusters[n].scheduler_address)
                t0 = time.perf_counter()
                build_map(P, settings, tmp / f"m{n}.partial", scheduler=clusters[n].scheduler_address)
                dt = time.perf_counter() - t0
                cpu1 = worker_cpu(clusters[n].scheduler_address)
                cpu = [cpu1[w] - cpu0[w] for w in cpu1 if w in cpu0]
                times[n].append(dt)
                out["runs"].append({"workers": n, "s": round(dt, 2), "worker_cpu_s": [round(c, 2) for c in cpu],
                                    "load_before": before, "load_after": load()})
                # the CPU time says what the cores did; on a machine this loaded the clock says little
                print(f"  {n} worker(s): {dt:.1f} s, worker CPU {' + '.join(f'{c:.1f}' for c in cpu)} s (load "
                      f"{before} -> {load()})")
        t1, t2 = min(times[1]), min(times[2])
        print(f"best of {a.repeats}: 1 worker {t1:.1f} s, 2 workers {t2:.1f} s: {t1 / t2:.2f}x; one solve "
              f"{t1 / solves * 1e3:.3f} ms (incl. the flows' and the task's share)")
        out.update(best_1_s=round(t1, 2), best_2_s=round(t2, 2), speedup=round(t1 / t2, 3),
                   ms_per_solve=round(t1 / solves * 1e3, 4))
        with Client(clusters[2].scheduler_address) as client:  # the scheduler's cost per task
            client.gather(client.map(noop, range(200), pure=False))
            t0 = time.perf_counter()
            client.gather(client.map(noop, range(a.tasks), pure=False))
            per = (time.perf_counter() - t0) / a.tasks
        print(f"scheduler: {per * 1e3:.3f} ms per task ({a.tasks} no-op tasks, submit to result, 2 workers)")
        out["ms_per_task"] = round(per * 1e3, 4)
    finally:
        for c in clusters.values():
            c.close()
    # bytes: the shared task (once per worker), one row's input and result, its line in the partial file
    from bearing_fmu.internals.map.tables import TableAxes  # noqa: F401 - the axes as the build has them
    beta = -np.pi + 2 * np.pi * np.arange(n_beta) / n_beta
    task = bind(table_row, P, settings.n_theta, settings.n_x, settings.cavitation, betas=beta, wall_exponent=0.0,
                n_phase=a.phases, flows=True)
    row = task(0.5)
    line = json.dumps({"row": 1, "values": [np.asarray(v).tolist() for v in row]})
    t0 = time.perf_counter()
    for _ in range(50):
        json.dumps({"row": 1, "values": [np.asarray(v).tolist() for v in row]})
    write_s = (time.perf_counter() - t0) / 50
    sizes = {"task_bytes": len(pickle.dumps(task)), "row_input_bytes": len(pickle.dumps(0.5)),
             "row_result_bytes": len(pickle.dumps(row)), "partial_line_bytes": len(line),
             "partial_line_us_per_value": round(write_s / (4 * n_beta) * 1e6, 3)}
    print(f"bytes: shared task {sizes['task_bytes']} (once per worker), row input {sizes['row_input_bytes']}, row "
          f"result {sizes['row_result_bytes']} ({4 * n_beta} numbers), its partial line {sizes['partial_line_bytes']} "
          f"(encoded at {sizes['partial_line_us_per_value']} us per number)")
    out.update(sizes, load_end=load(), cpus=os.cpu_count())
    print(json.dumps(out))


if __name__ == "__main__":
    main()
