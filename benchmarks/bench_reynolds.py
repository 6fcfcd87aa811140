"""Error-vs-run-time of the finite-volume Reynolds solver (bearing_fmu.physics.solver.reynolds).

Prints markdown tables:
  1. for several grids: median time per force call (Reynolds and Gumbel cavitation), per
     force_and_jacobian call, active-set iterations, and the force error against the finest
     grid at eccentricity 0.3 / 0.6 / 0.9 (Reynolds cavitation);
  2. the convergence study of the default grid: default vs 2x and 4x refined (both
     directions), with the observed order p = log2(|F1 - F2| / |F2 - F4|).

Bearing: the paper's (D = 31 mm, L = 20 mm, CR = 90 um, mu = 0.05 Pa s), omega = 2 pi 50 rad/s,
journal displaced at 0.4 rad from straight down; "+sq" adds a squeeze velocity
(radial 0.3 CR omega (1 - eps), tangential a fifth of that).

    .venv/bin/python benchmarks/bench_reynolds.py [--quick]
"""

from __future__ import annotations

import argparse
import math
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.physics.params import PAPER_BEARING as P  # noqa: E402
from bearing_fmu.physics.solver.reynolds import DEFAULT_N_THETA, DEFAULT_N_X, Reynolds  # noqa: E402

OMEGA = 2 * math.pi * 50.0
EPS = (0.3, 0.6, 0.9)
ANGLE = 0.4


def state(eps, squeeze=False):
    ur = np.array([math.sin(ANGLE), -math.cos(ANGLE)])
    ut = np.array([math.cos(ANGLE), math.sin(ANGLE)])
    vr = 0.3 * P.CR * OMEGA * (1 - eps) if squeeze else 0.0
    v = vr * ur + 0.2 * vr * ut
    q = eps * P.CR * ur
    return float(q[0]), float(q[1]), float(v[0]), float(v[1]), OMEGA


def median_time(fn, args, repeat):
    fn(*args)
    ts = np.empty(repeat)
    for k in range(repeat):
        t0 = time.perf_counter()
        fn(*args)
        ts[k] = time.perf_counter() - t0
    return float(np.median(ts))


def cpu_name():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name"):
                return line.split(":", 1)[1].strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return platform.processor() or "unknown"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer repeats and a coarser reference")
    args = ap.parse_args()
    repeat = 50 if args.quick else 300
    ref_grid = (512, 64) if args.quick else (1024, 128)
    grids = [(32, 4), (48, 8), (64, 8), (65, 16), (96, 12), (DEFAULT_N_THETA, DEFAULT_N_X), (192, 24), (256, 32)]

    print(f"# Reynolds solver benchmark  ({time.strftime('%Y-%m-%d')}, {cpu_name()}, "
          f"python {platform.python_version()}, numpy {np.__version__})\n")
    t0 = time.perf_counter()
    ref = Reynolds(P, *ref_grid)
    F_ref = {eps: np.array(ref.force(*state(eps))) for eps in EPS}
    print(f"reference grid {ref_grid[0]} x {ref_grid[1]} (n_theta x n_x), "
          f"{time.perf_counter() - t0:.1f} s for {len(EPS)} states\n")

    print("| n_theta x n_x | unknowns (half) | reynolds [ms] | gumbel [ms] | jacobian [ms] | iterations |"
          " err eps 0.3 | err eps 0.6 | err eps 0.9 |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for nt, nx in grids:
        rr = Reynolds(P, nt, nx)
        rg = Reynolds(P, nt, nx, cavitation="gumbel")
        t_r = max(median_time(rr.force, state(e), repeat) for e in EPS)
        t_g = max(median_time(rg.force, state(e), repeat) for e in EPS)
        t_j = max(median_time(rr.force_and_jacobian, state(e), repeat) for e in EPS)
        its = max(rr.diagnostics(*state(e))["iterations"] for e in EPS)
        errs = [np.linalg.norm(np.array(rr.force(*state(e))) - F_ref[e]) / np.linalg.norm(F_ref[e]) for e in EPS]
        mark = " (default)" if (nt, nx) == (DEFAULT_N_THETA, DEFAULT_N_X) else ""
        print(f"| {nt} x {nx}{mark} | {nt * nx // 2} | {1e3 * t_r:.3f} | {1e3 * t_g:.3f} | {1e3 * t_j:.3f} | "
              f"{its} | " + " | ".join(f"{100 * e:.3f} %" for e in errs) + " |")
    print("\ntimes: median of", repeat, "calls, worst of the three eccentricities; errors |F - F_ref| / |F_ref|.\n")

    print(f"## Convergence of the default grid {DEFAULT_N_THETA} x {DEFAULT_N_X} (Reynolds cavitation)\n")
    print("| state | |F| [N] | err default vs 4x | err 2x vs 4x | observed order |")
    print("| --- | ---: | ---: | ---: | ---: |")
    solvers = {f: Reynolds(P, DEFAULT_N_THETA * f, DEFAULT_N_X * f) for f in (1, 2, 4)}
    for eps in EPS:
        for sq in (False, True):
            s = state(eps, sq)
            F = {f: np.array(r.force(*s)) for f, r in solvers.items()}
            n4 = np.linalg.norm(F[4])
            d12, d24 = np.linalg.norm(F[1] - F[2]), np.linalg.norm(F[2] - F[4])
            order = math.log2(d12 / d24) if d24 > 0 else float("inf")
            print(f"| eps {eps}{' +sq' if sq else ''} | {n4:.4g} | {100 * np.linalg.norm(F[1] - F[4]) / n4:.3f} % | "
                  f"{100 * d24 / n4:.3f} % | {order:.2f} |")


if __name__ == "__main__":
    main()
