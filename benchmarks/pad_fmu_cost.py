"""The five tilting pads through the Python FMU beside the same internal in-process, in one run (issue 33
item 6): the paper rotor on two five-pad bearings at 44 Hz (rotor_host/bundled/scenes/paper_5pad_lbp_44hz.toml,
the Reynolds pads at their default grid, --t-end s) and its map variant (paper_5pad_lbp_44hz_map.toml, the
pads from the bundled pads' map), each via = "direct" and via = "fmu" (rotor_host/coupling/cosim.py: the
static equilibrium in Initialization Mode, each Newton iterate a restored FMU state, a doStep, the
outputs). Per row the CPU time of the integration's process share (process time: the clock says little
on a shared machine) per step, best of --repeat runs after one warm-up run each, and the largest
distance between the two routes' orbits (they run the same solver calls: 0 expected).

    .venv/bin/python benchmarks/pad_fmu_cost.py [--t-end 0.01] [--repeat 2]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

SCENES = ROOT / "rotor_host" / "bundled" / "scenes"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--t-end", type=float, default=0.01, help="simulated time per run [s] (default 0.01)")
    ap.add_argument("--repeat", type=int, default=2, help="timed runs per row, the best kept (default 2)")
    args = ap.parse_args(argv)
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; {args.t_end:g} s simulated per run")
    with tempfile.TemporaryDirectory(prefix="pad_fmu_cost_") as tmp:
        for name in ("paper_5pad_lbp_44hz", "paper_5pad_lbp_44hz_map"):
            scene = load_scene(SCENES / f"{name}.toml")
            orbits, cost = {}, {}
            for via in ("direct", "fmu"):
                run = scene.with_internal("tilting_pad", t_end_s=args.t_end, via=via)
                best = None
                for k in range(args.repeat + 1):  # the first loads the kernels and builds the FMU
                    t0 = time.process_time()
                    res = run_scene(run, out_dir=tmp, stem=f"{name}_{via}", work_dir=Path(tmp) / "fmu")
                    cpu = time.process_time() - t0
                    if not res.ok:
                        raise SystemExit(f"{name} via {via}: {res.meta['message']}")
                    share = cpu - res.meta["setup_time_s"] - res.meta["kernels_time_s"]
                    if k and (best is None or share < best):
                        best = share
                steps = res.meta["steps"]
                cost[via] = best / steps
                orbits[via] = np.array([res.arrays["y"], res.arrays["z"]])
                print(f"{name} via {via}: {1e3 * cost[via]:.2f} ms of CPU per step ({steps} steps, "
                      f"{res.meta['newton_mean_evaluations_per_step']:.2f} evaluations a step)")
            diff = np.max(np.abs(orbits["fmu"] - orbits["direct"]))
            print(f"{name}: FMU / direct {cost['fmu'] / cost['direct']:.2f}x; largest orbit difference "
                  f"{diff:.3g} m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
