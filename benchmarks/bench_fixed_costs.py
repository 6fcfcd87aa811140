"""Fixed costs against work, side by side: command-line start-up, the first step of a run, and a
sweep on 1 and 2 Dask workers against a plain loop.

Each figure is the wall time of a fresh process (what a user waits for), run against this
checkout and, with ``--before PATH``, against another checkout of the package (e.g. a worktree
of ``main`` before a change) in the same run, so the two columns share the machine's load.

* start-up: ``rotor-host --help``, ``bearing-fmu --help`` and every subcommand's ``--help``
  (``python -m <cli>``), the least of ``--repeat`` runs;
* first step: the paper 22 Hz scene with the map internal for ``--t-end-first`` s, twice in one
  process (direct, through the pythonfmu FMU, through the native FMU): the first run's reported
  integration time against the second's; their difference is fixed cost counted as work (the
  compiled kernels loaded at the first step), which should be ~0;
* sweep: 20 speeds (12.5:60:2.5 Hz) of the same scene with the map internal (the scene's own
  route: ``--via``) for ``--t-end`` s each, as a plain loop of ``run_scene`` in one process and as
  ``rotor-host sweep`` on a local cluster of 1 and 2 workers (whole process: imports, cluster,
  runs, summary). The target: 2 workers >= 1.7 x faster than one, both no slower than the loop.

    .venv/bin/python benchmarks/bench_fixed_costs.py [--before ../main] [--t-end 0.1] [--only startup,first,sweep]

Needs 2 idle cores for the sweep's ratio to mean anything (``uptime`` is printed).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_cosim import cpu  # the machine's CPU name, as the other benchmarks print it

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
SPEEDS = "12.5:60:2.5"  # 20 speeds, both ends included

HELPS = [("rotor_host.cli", []), ("bearing_fmu.cli", [])] + [
    ("rotor_host.cli", [c]) for c in ("run", "compare", "paper", "fit", "dt-study", "waterfall", "limit-cycle",
                                      "stability", "sweep")] + [
    ("bearing_fmu.cli", [c]) for c in ("demo", "fit", "build", "map")]

# Run in a fresh process against one checkout: the scene twice, the first and second run's times.
FIRST = """
import json, sys
from rotor_host.scenes.overrides import SceneOverrides, load_with_overrides
from rotor_host.scenes.run import run_scene
route, t_end = sys.argv[1], float(sys.argv[2])
ov = SceneOverrides(internal="map", via="direct" if route == "direct" else "fmu", native=route == "native",
                    t_end_s=t_end)
out = []
for _ in range(2):
    m = run_scene(load_with_overrides(sys.argv[3], ov), None).meta
    out.append({k: m.get(k, 0.0) for k in ("integration_time_s", "setup_time_s", "equilibrium_time_s",
                                           "kernels_time_s", "wall_time_s")} | {"steps": m["steps"]})
print(json.dumps(out))
"""

# A plain loop: the sweep's runs one after the other in this process (what a script would do).
LOOP = """
import sys
from pathlib import Path
from bearing_fmu.io.cliargs import float_range
from rotor_host.analyses.sweep import point_scene, points, run_point
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.overrides import SceneOverrides, load_with_overrides
scene = load_with_overrides(sys.argv[1], SceneOverrides(internal="map", via=sys.argv[4] or None,
                                                        t_end_s=float(sys.argv[2])))
disks = sorted({d.node + 1 for d in Rotor.from_toml(scene.rotor_path).disks})
out = Path(sys.argv[3])
for p in points(scene, float_range("Hz", 0.0)(sys.argv[5])):
    row = run_point(point_scene(scene, p, disks), p, str(out), scene.t_end_s / 2, disks)
    assert row["status"] == "ok", row
"""


CPU_S = [0.0]  # CPU seconds (user + system) of the last run's process and the processes it waited for


def run(tree: Path, argv: list[str], timeout: float = 900.0) -> tuple[float, str]:
    """Wall time [s] and stdout of ``python argv`` with ``tree`` first on the path (its CPU
    seconds, workers included, in ``CPU_S[0]``)."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, *argv], cwd=tree, env=env, capture_output=True, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU_S[0] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(argv[:4])} in {tree}: exit {r.returncode}\n{r.stderr[-2000:]}")
    return wall, r.stdout


def table(head: list[str], rows: list[list]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    return "\n".join(lines + ["| " + " | ".join(str(c) for c in r) + " |" for r in rows])


def startup(trees: dict[str, Path], repeat: int) -> str:
    rows = []
    for module, sub in HELPS:
        prog = {"rotor_host.cli": "rotor-host", "bearing_fmu.cli": "bearing-fmu"}[module]
        row = [f"`{prog} {' '.join(sub + ['--help'])}`"]
        for tree in trees.values():
            row.append(f"{min(run(tree, ['-m', module, *sub, '--help'])[0] for _ in range(repeat)):.2f}")
        rows.append(row)
    bare = min(run(ROOT, ["-c", "pass"])[0] for _ in range(repeat))
    numpy = min(run(ROOT, ["-c", "import numpy"])[0] for _ in range(repeat))
    return (table(["command", *(f"{k} [s]" for k in trees)], rows)
            + f"\n\n(least of {repeat}; a bare `python -c pass` {bare:.2f} s, `import numpy` {numpy:.2f} s)")


def first_step(trees: dict[str, Path], t_end: float) -> str:
    rows = []
    for route in ("direct", "fmu", "native"):
        row = [route]
        for tree in trees.values():
            _, out = run(tree, ["-c", FIRST, route, str(t_end), str(SCENE)])
            a, b = json.loads(out.strip().splitlines()[-1])
            row += [f"{a['integration_time_s']:.3f} / {b['integration_time_s']:.3f}",
                    f"{a['integration_time_s'] - b['integration_time_s']:+.3f}",
                    f"{a['kernels_time_s']:.3f}"]
        rows.append(row)
    head = ["route"]
    for k in trees:
        head += [f"{k}: integration 1st / 2nd run [s]", f"{k}: fixed cost in it [s]", f"{k}: kernels before [s]"]
    return (table(head, rows) + f"\n\n(the map scene for {t_end:g} s = {round(t_end / 1e-4)} steps, twice in one "
            "fresh process; 'kernels before': the time the run spent loading compiled kernels before its clock)")


SPIN = "s = 0\nfor i in range(8_000_000):\n    s += i\n"  # ~1-2 s of one core's pure Python


def parallel_capacity() -> float:
    """How many cores two CPU-bound processes get here now: 2.0 on two idle cores, 1.0 when the
    machine's other work leaves room for one (then no second worker can make a sweep faster)."""
    alone, _ = run(ROOT, ["-c", SPIN])
    t0 = time.perf_counter()
    procs = [subprocess.Popen([sys.executable, "-c", SPIN]) for _ in range(2)]
    for p in procs:
        p.wait()
    return 2.0 * alone / (time.perf_counter() - t0)


def sweeps(trees: dict[str, Path], t_end: float, via: str) -> str:
    rows = []
    cores = [parallel_capacity()]
    for name, tree in trees.items():
        with tempfile.TemporaryDirectory() as tmp:
            loop, _ = run(tree, ["-c", LOOP, str(SCENE), str(t_end), str(Path(tmp) / "loop"), via, SPEEDS])
            cpu_s = {0: CPU_S[0]}
            walls = {}
            for n in (1, 2):
                cmd = ["-m", "rotor_host.cli", "sweep", str(SCENE), "--internal", "map", "--speeds-hz", SPEEDS,
                       "--t-end", str(t_end), "--workers", str(n), "--out", str(Path(tmp) / f"w{n}"), "--quiet"]
                if via:
                    cmd += ["--via", via]
                walls[n], _ = run(tree, cmd)
                cpu_s[n] = CPU_S[0]
        rows.append([name, f"{loop:.1f}", f"{walls[1]:.1f}", f"{walls[2]:.1f}", f"{walls[1] / walls[2]:.2f}",
                     f"{loop / walls[1]:.2f}", f"{loop / walls[2]:.2f}",
                     " / ".join(f"{cpu_s[n]:.1f}" for n in (0, 1, 2))])
        cores.append(parallel_capacity())
    return (table(["code", "plain loop [s]", "1 worker [s]", "2 workers [s]", "1 / 2 workers", "loop / 1 worker",
                   "loop / 2 workers", "CPU loop / 1 / 2 workers [s]"], rows)
            + f"\n\n(20 speeds {SPEEDS} Hz, map internal{', via ' + via if via else ' (the scene route: fmu)'}, "
              f"t_end {t_end:g} s each; whole processes, their CPU seconds with the workers'; target 1 / 2 "
              "workers >= 1.7, loop / n >= 1)\n\n(two CPU-bound processes at once got "
              + ", ".join(f"{c:.2f}" for c in cores) + " cores' worth, before, between and after the rows: "
              "2.0 on two idle cores; the 1 / 2 workers ratio cannot exceed it)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", type=Path, help="another checkout of the package, measured in the same run")
    ap.add_argument("--t-end", type=float, default=0.1, help="each sweep run's simulated time [s] (default 0.1)")
    ap.add_argument("--t-end-first", type=float, default=0.05, help="the first-step runs' simulated time [s]")
    ap.add_argument("--via", choices=("fmu", "direct"), default="", help="the sweep's route (default: the scene's)")
    ap.add_argument("--repeat", type=int, default=5, help="start-up: least of this many runs (default 5)")
    ap.add_argument("--only", default="startup,first,sweep", help="comma-separated parts to run")
    args = ap.parse_args()
    trees = {"after": ROOT} if args.before is None else {"before": args.before.resolve(), "after": ROOT}
    parts = set(args.only.split(","))
    load = os.getloadavg()
    print(f"# Fixed costs, {time.strftime('%Y-%m-%d %H:%M')} on {cpu()} ({os.cpu_count()} cores), load "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; " + ", ".join(f"{k}: {v}" for k, v in trees.items()) + "\n")
    if "startup" in parts:
        print("## Command-line start-up (wall of a fresh process)\n\n" + startup(trees, args.repeat) + "\n")
    if "first" in parts:
        print("## The first step: fixed cost counted as integration\n\n" + first_step(trees, args.t_end_first) + "\n")
    if "sweep" in parts:
        print("## A sweep on 1 and 2 workers against a plain loop\n\n" + sweeps(trees, args.t_end, args.via) + "\n")
    load = os.getloadavg()
    print(f"(load at the end {load[0]:.2f} {load[1]:.2f} {load[2]:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
