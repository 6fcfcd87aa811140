"""Force map: resolution study and speed, side by side in one run.

For each table resolution (n_eps x n_beta) and number of averaged attitudes, build the paper
bearing's map from the Reynolds solver at its default grid and measure, at the same random
states (eccentricity up to 0.95 and 0.98, speeds of both signs, velocities up to 1.5 omega CR):

* the error against Reynolds at the same grid, |F_map - F_rey| / max(|F_rey|, S |omega|);
* the solver's own scatter at each state: the spread of its force when its grid turns under
  the journal by a fraction of a cell (same eps, beta, r): the floor no table can go below.

Then the cost per call: force + Jacobian in a numba loop and from Python, against Reynolds.

    .venv/bin/python benchmarks/forcemap_study.py [--quick]
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np
from numba import njit

from bearing_fmu.forcemap import ForceMap, reduced, scale, state_for, tabulate
from bearing_fmu.params import PAPER_BEARING as P
from bearing_fmu.reynolds import Reynolds

OMEGA = 2 * math.pi * 22.0


def states(n, eps_max, seed):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        eps, phi = rng.uniform(0, eps_max), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        out.append((eps * P.CR * math.cos(phi), eps * P.CR * math.sin(phi), v[0], v[1], om))
    return out


def errors(fmap, rey, xs):
    e = []
    for x in xs:
        Fr, Fm = np.array(rey.force(*x)), np.array(fmap.force(*x))
        e.append(np.linalg.norm(Fm - Fr) / max(np.linalg.norm(Fr), scale(P) * abs(x[4])))
    return np.array(e)


def scatter(rey, xs, n_turn=5):
    """Spread of the solver's G at each state's (eps, beta) over attitudes within one cell."""
    out = []
    cell = 2 * math.pi / rey.n_theta
    for x in xs:
        eps, phi, a, c = reduced(*x[:4], x[4], P.CR)
        beta = math.atan2(c, a)
        G = []
        for k in range(n_turn):
            ph = phi + k / n_turn * cell
            y, z, vy, vz = state_for(eps, beta, P, phi=ph)
            F = np.array(rey.force(y, z, vy, vz, 1.0))
            u = np.array([math.cos(ph), math.sin(ph)])
            G.append([F @ u, F @ np.array([-u[1], u[0]])])
        G = np.array(G)
        out.append(np.ptp(G, axis=0).max() / max(np.linalg.norm(G.mean(axis=0)), scale(P) * 1.0))
    return np.array(out)


def q(e):
    return f"{np.median(e):.1e} / {np.percentile(e, 95):.1e} / {e.max():.1e}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer states and resolutions")
    args = ap.parse_args()
    n = 100 if args.quick else 400
    rey = Reynolds(P)
    sets = {0.95: states(n, 0.95, 1), 0.98: states(n, 0.98, 2)}
    print(f"# force map study, {time.strftime('%Y-%m-%d')}, {platform.processor() or platform.machine()}, "
          f"Reynolds {rey.n_theta} x {rey.n_x}, {n} random states per set\n")
    floor = {k: scatter(rey, v[: n // 4]) for k, v in sets.items()}
    print("solver's own scatter (grid turned within one cell), median / 95th pct / max:")
    for k, v in floor.items():
        print(f"  eps <= {k}: {q(v)}")
    print()
    print("| table | attitudes | build [s] | file [kB] | eps <= 0.95: median / p95 / max | eps <= 0.98: median / p95 / max |")
    print("|---|---|---|---|---|---|")
    grid = [(24, 48, 1), (32, 64, 1), (48, 96, 1), (48, 96, 4), (64, 128, 4)]
    if args.quick:
        grid = [(24, 48, 1), (48, 96, 4)]
    import tempfile

    from bearing_fmu.forcemap import save_map

    for ne, nb, nph in grid:
        t0 = time.perf_counter()
        table = tabulate(P, n_eps=ne, n_beta=nb, n_phase=nph, workers=2)
        built = time.perf_counter() - t0
        with tempfile.TemporaryDirectory() as d:
            size = save_map(table, f"{d}/m.json").stat().st_size / 1e3
        fmap = ForceMap(P, table)
        e = {k: errors(fmap, rey, v) for k, v in sets.items()}
        print(f"| {ne} x {nb} | {nph} | {built:.1f} | {size:.0f} | {q(e[0.95])} | {q(e[0.98])} |")

    # speed: force + Jacobian per call
    fmap = ForceMap(P, tabulate(P, n_eps=48, n_beta=96, n_phase=1, workers=2))
    xs = np.array(states(2000, 0.95, 3))
    F, J = np.zeros(2), np.zeros((2, 4))
    args_k = fmap._args

    @njit
    def loop(xs, F, J):
        acc = 0.0
        for i in range(xs.shape[0]):
            fmap_kernel(*args_k, xs[i, 0], xs[i, 1], xs[i, 2], xs[i, 3], xs[i, 4], True, F, J)
            acc += F[0]
        return acc

    fmap_kernel = fmap._kernel
    loop(xs, F, J)
    t0 = time.perf_counter()
    for _ in range(20):
        loop(xs, F, J)
    t_numba = (time.perf_counter() - t0) / (20 * len(xs))
    t0 = time.perf_counter()
    for x in xs:
        fmap.force_and_jacobian(*x)
    t_py = (time.perf_counter() - t0) / len(xs)
    t0 = time.perf_counter()
    for x in xs[:300]:
        rey.force_and_jacobian(*x)
    t_rey = (time.perf_counter() - t0) / 300
    print(f"\nforce + Jacobian per call: map {t_numba * 1e6:.2f} us in a numba loop, {t_py * 1e6:.2f} us from "
          f"Python; Reynolds {rey.n_theta} x {rey.n_x} {t_rey * 1e6:.0f} us from Python "
          f"({t_rey / t_py:.0f}x the map from Python)")


if __name__ == "__main__":
    main()
