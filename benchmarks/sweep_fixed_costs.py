"""A short sweep's fixed costs against its work, for each execution, side by side in one run.

11 speeds (20:25:0.5 Hz) of the paper 22 Hz scene with the map internal called directly for
``--t-end`` s each (0.05 s: runs of about 0.25 s on an idle core), as

* a plain loop of ``run_point`` in one process (what a script would do);
* ``rotor-host sweep --execution inline`` (the command's own process);
* ``--execution pool`` with 1 and 2 workers (forked warm after a first run in the command);
* ``--execution cluster`` with 1 and 2 workers (a Dask LocalCluster started for the sweep);
* ``auto`` with 2 workers (what a user gets).

Each row is a fresh process (wall time: what a user waits for), the fixed costs and the work as
the command reports them in its summary JSON (``fixed_costs_s``, ``work_s``), the runs' mean wall
time, and the loop's whole time and work over the row's. ``uptime``'s load and how many cores
two CPU-bound processes get now (``parallel_capacity``) are printed: the 2-worker ratios cannot
exceed the latter.

    .venv/bin/python benchmarks/sweep_fixed_costs.py [--t-end 0.05] [--repeat 1]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_cosim import cpu
from bench_fixed_costs import parallel_capacity, table

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
SPEEDS = "20:25:0.5"  # 11 speeds

# the plain loop, timed in its process: its imports and first run apart from the rest
LOOP = """
import json, sys, time
t0 = time.perf_counter()
from pathlib import Path
from bearing_fmu.io.cliargs import float_range
from rotor_host.analyses.sweep import point_scene, points, run_point
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.overrides import SceneOverrides, load_with_overrides
imports = time.perf_counter() - t0
scene = load_with_overrides(sys.argv[1], SceneOverrides(internal="map", via="direct", t_end_s=float(sys.argv[2])))
disks = sorted({d.node + 1 for d in Rotor.from_toml(scene.rotor_path).disks})
t1 = time.perf_counter()
walls = []
for p in points(scene, float_range("Hz", 0.0)(sys.argv[4])):
    row = run_point(point_scene(scene, p, disks), p, sys.argv[3], scene.t_end_s / 2, disks)
    assert row["status"] == "ok", row
    walls.append(row["wall_s"])
print(json.dumps({"imports": imports, "work": time.perf_counter() - t1, "walls": walls}))
"""

ROWS = [("plain loop", None, None), ("inline", "inline", 1), ("pool, 1 worker", "pool", 1),
        ("pool, 2 workers", "pool", 2), ("cluster, 1 worker", "cluster", 1), ("cluster, 2 workers", "cluster", 2),
        ("auto, 2 workers", "auto", 2)]


def one(how: str | None, workers: int | None, t_end: float, tmp: Path) -> dict:
    """Whole wall [s], fixed costs (parts) [s], work [s] and the runs' walls of one row."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg",
           "ROTOR_HOST_SCHEDULER_FILE": str(tmp / "no-cluster.json")}
    env.pop("DASK_SCHEDULER_ADDRESS", None)
    out = tmp / f"{how}-{workers}-{time.time_ns()}"
    if how is None:
        argv = ["-c", LOOP, str(SCENE), str(t_end), str(out), SPEEDS]
        out.mkdir()
    else:
        argv = ["-m", "rotor_host.cli", "sweep", str(SCENE), "--internal", "map", "--via", "direct", "--t-end",
                str(t_end), "--speeds-hz", SPEEDS, "--execution", how, "--workers", str(workers), "--out", str(out),
                "--quiet"]
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, *argv], cwd=ROOT, env=env, capture_output=True, text=True, timeout=900)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError(f"{how}: exit {r.returncode}\n{r.stderr[-2000:]}")
    if how is None:
        got = json.loads(r.stdout.strip().splitlines()[-1])
        return {"wall": wall, "fixed": {"imports": got["imports"]}, "work": got["work"], "walls": got["walls"]}
    s = json.loads((out / "sweep_paper_22hz_map.json").read_text())
    fixed = {k: v for k, v in s["fixed_costs_s"].items() if k != "total"}
    return {"wall": wall, "fixed": fixed, "work": s["work_s"], "walls": [r["wall_s"] for r in s["rows"]],
            "execution": s["execution"]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--t-end", type=float, default=0.05, help="each run's simulated time [s] (default 0.05)")
    ap.add_argument("--repeat", type=int, default=1, help="rows measured this many times, the least kept")
    args = ap.parse_args()
    load = os.getloadavg()
    print(f"# A short sweep's fixed costs, {time.strftime('%Y-%m-%d %H:%M')} on {cpu()} ({os.cpu_count()} cores), "
          f"load {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}\n")
    cores = [parallel_capacity()]
    res: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        one("inline", 1, args.t_end, Path(tmp))  # numba's cache and the OS's file cache warm: not counted
        for _ in range(args.repeat):
            for name, how, n in ROWS:
                r = one(how, n, args.t_end, Path(tmp))
                if name not in res or r["wall"] < res[name]["wall"]:
                    res[name] = r
    cores.append(parallel_capacity())
    loop = res["plain loop"]
    rows = []
    for name, _, _ in ROWS:
        r = res[name]
        rows.append([name + (f" ({r['execution']})" if name.startswith("auto") else ""), f"{r['wall']:.2f}",
                     f"{sum(r['fixed'].values()):.2f}",
                     ", ".join(f"{k} {v:.2f}" for k, v in r["fixed"].items() if v >= 0.005),
                     f"{r['work']:.2f}", f"{sum(r['walls']) / len(r['walls']):.3f}",
                     f"{loop['wall'] / r['wall']:.2f}", f"{loop['work'] / r['work']:.2f}"])
    print(table(["execution", "whole process [s]", "fixed costs [s]", "of which [s]", "work [s]",
                 "per run [s]", "loop / this (whole)", "loop / this (work)"], rows))
    load = os.getloadavg()
    print(f"\n(11 speeds {SPEEDS} Hz, map internal direct, t_end {args.t_end:g} s each; least of {args.repeat}; "
          "'whole process' includes the interpreter's start and the summary's writing; the loop's fixed cost is "
          "its imports (its first run's kernel loading is in its work). Two CPU-bound processes got "
          + " and ".join(f"{c:.2f}" for c in cores) + " cores' worth before and after the rows. "
          f"Load at the end {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}.)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
