"""Force map: resolution study and speed, side by side in one run.

For each table (n_eps x n_beta, attitudes averaged per point, eps_max, wall exponent k),
build the paper bearing's map from the Reynolds solver at its default grid and measure, at the
same random states (speeds of both signs from 0.2 to 3 times 22 Hz, velocities up to
1.5 omega CR, any attitude; eccentricity uniform up to 0.95, up to 0.98, and in 0.98-0.99, where
the 44 Hz whirl runs):

* the error against Reynolds at the same grid, |F_map - F_rey| / max(|F_rey|, S |omega|):
  what a user sees;
* the interpolation error alone: the same measure against the function the table samples
  (the solver's force averaged over the table's attitudes within one cell, at the state's
  eps and beta), so the solver's grid scatter is left out;
* the solver's own scatter at each state: the spread of its force when its grid turns under
  the journal by a fraction of a cell (same eps, beta, r): the floor no table can go below
  against the solver.

Then Lund's coefficients from the shipped map against ``linearize`` on Reynolds at the paper
scenes' equilibria, and the cost per call: force + Jacobian in a numba loop and from Python,
against Reynolds.

    .venv/bin/python benchmarks/forcemap_study.py [--quick] [--map rotor_host/bundled/maps/paper_bearing.json]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's packages, not the installed ones

from bearing_fmu.internals.map.forcemap import ForceMap
from bearing_fmu.internals.map.tablefile import save_map
from bearing_fmu.internals.map.tables import DEFAULT_EPS_MAX, DEFAULT_N_BETA, DEFAULT_N_EPS, DEFAULT_N_PHASE, DEFAULT_WALL_EXPONENT, reduced, table_row, scale, state_for, tabulate
from bearing_fmu.physics.params import PAPER_BEARING as P
from bearing_fmu.physics.solver.reynolds import Reynolds

OMEGA = 2 * math.pi * 22.0
BANDS = ((0.0, 0.95), (0.0, 0.98), (0.98, 0.99))  # eccentricity ranges of the random state sets
TARGETS = {BANDS[0]: 1e-3, BANDS[1]: 5e-3}  # issue 15: force within 0.1 % (eps <= 0.95), 0.5 % (eps <= 0.98)
DEFAULT = (DEFAULT_N_EPS, DEFAULT_N_BETA, DEFAULT_N_PHASE, DEFAULT_EPS_MAX, DEFAULT_WALL_EXPONENT)
PREVIOUS = (48, 96, 4, 0.99, 2.0)  # the default before this study
# (n_eps, n_beta, attitudes, eps_max, k): the resolution ladder at k = 2 around the previous
# default with its attitudes, eps_max and k varied alone; then the ladder at k = 0 up to the
# default and the default's attitudes, eps_max and k varied alone
TABLES = [(24, 48, 4, 0.99, 2.0), (32, 64, 4, 0.99, 2.0), PREVIOUS, (64, 128, 4, 0.99, 2.0),
          (96, 192, 4, 0.99, 2.0), (48, 192, 4, 0.99, 2.0), (96, 96, 4, 0.99, 2.0),
          (48, 96, 1, 0.99, 2.0), (48, 96, 2, 0.99, 2.0), (48, 96, 8, 0.99, 2.0),
          (48, 96, 4, 0.98, 2.0), (48, 96, 4, 0.995, 2.0),
          (48, 96, 4, 0.99, 0.0), (48, 96, 4, 0.99, 1.0), (48, 96, 4, 0.99, 3.0),
          (64, 96, 4, 0.99, 0.0), (80, 96, 4, 0.99, 0.0), DEFAULT, (96, 192, 4, 0.99, 0.0),
          (96, 96, 1, 0.99, 0.0), (96, 96, 8, 0.99, 0.0), (96, 96, 4, 0.98, 0.0), (96, 96, 4, 0.995, 0.0),
          (96, 96, 4, 0.99, 1.0)]
QUICK = [(24, 48, 1, 0.99, 2.0), PREVIOUS, DEFAULT]
# Lund coefficients: (speed [Hz], load on one bearing [N]) of the paper scenes' equilibria (half the
# rotor weight 16.7 N plus the static load on the bearing node) and the harsh 0.95 scene
EQUILIBRIA = [(10.0, 16.7), (22.0, 16.7), (44.0, 16.7), (10.0, 516.7), (20.0, 816.7), (10.0, 896.7)]


def states(n, eps_lo, eps_hi, seed):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        eps, phi = rng.uniform(eps_lo, eps_hi), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        out.append((eps * P.CR * math.cos(phi), eps * P.CR * math.sin(phi), v[0], v[1], om))
    return out


def rel(F, Fref, omega):
    return np.linalg.norm(np.subtract(F, Fref)) / max(np.linalg.norm(Fref), scale(P) * abs(omega))


def errors(fmap, rey, xs):
    """Map against Reynolds at each state; nan where the map refuses it (beyond its eps_max)."""
    e = []
    for x in xs:
        if math.hypot(x[0], x[1]) / P.CR >= fmap.table.eps_max:
            e.append(np.nan)
            continue
        e.append(rel(fmap.force(*x), rey.force(*x), x[4]))
    return np.array(e)


def sampled_force(rey, x, n_phase):
    """The force at state x from the function the table samples: G at the state's (eps, beta)
    averaged over the table's attitudes (``tables.table_row`` with k = 0), turned to the state."""
    eps, phi, a, c = reduced(*x[:4], x[4], P.CR)
    G = table_row(P, rey.n_theta, rey.n_x, rey.cavitation, eps, [math.atan2(c, a)], 0.0, n_phase, rey)[0]
    u = np.array([math.cos(phi), math.sin(phi)])
    return scale(P) * math.hypot(a, c) * (G[0] * u + G[1] * np.array([-u[1], u[0]]))


def interpolation_errors(fmap, rey, xs):
    return np.array([rel(fmap.force(*x), sampled_force(rey, x, fmap.table.provenance["n_phase"]), x[4])
                     for x in xs if math.hypot(x[0], x[1]) / P.CR < fmap.table.eps_max])


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
    if np.all(np.isnan(e)):
        return "refused"
    return f"{np.nanmedian(e):.1e} / {np.nanpercentile(e, 95):.1e} / {np.nanmax(e):.1e}"


def resolution_table(rey, sets, grid):
    bands = " | ".join(f"{lo:g} < eps <= {hi:g}" if lo else f"eps <= {hi:g}" for lo, hi in BANDS)
    print(f"| table | attitudes | eps_max | k | build [s] | file [kB] | {bands} | % of states over target: "
          f"eps <= 0.95 (0.1 %) / eps <= 0.98 (0.5 %) | interpolation alone, eps <= 0.98 |")
    print("|---|---|---|---|---|---|" + "---|" * len(BANDS) + "---|---|")
    for ne, nb, nph, em, k in grid:
        t0 = time.perf_counter()
        table = tabulate(P, n_eps=ne, n_beta=nb, n_phase=nph, eps_max=em, wall_exponent=k, workers=2)
        built = time.perf_counter() - t0
        with tempfile.TemporaryDirectory() as d:
            size = save_map(table, f"{d}/m.json").stat().st_size / 1e3
        fmap = ForceMap(P, table)
        e = {b: errors(fmap, rey, sets[b]) for b in BANDS}
        cols = " | ".join(q(e[b]) for b in BANDS)
        over = " / ".join(f"{100 * np.mean(e[b] > tol):.1f}" for b, tol in TARGETS.items())
        interp = q(interpolation_errors(fmap, rey, sets[BANDS[1]][: len(sets[BANDS[1]]) // 2]))
        mark = {DEFAULT: " (default)", PREVIOUS: " (previous default)"}.get((ne, nb, nph, em, k), "")
        print(f"| {ne} x {nb}{mark} | {nph} | {em:g} | {k:g} | {built:.1f} | {size:.0f} | {cols} | {over} | {interp} |",
              flush=True)


def _turned(M, R):
    return R.T @ M @ R


def lund(fmap, rey, n_turn=8):
    """Lund coefficients from the map's analytic Jacobian against ``linearize`` on Reynolds (the
    solver's own Jacobian) at each equilibrium of the solver; beside it the solver's own scatter
    (the same state and load turned with the grid by a fraction of a cell, coefficients turned
    back: the largest difference over ``n_turn`` turns) and the map against the solver's
    coefficients averaged over those turns. Differences: max |dK| / max |K| (the same for C)."""
    from bearing_fmu.physics.statics import equilibrium, linearize

    print("| speed [Hz] | load [N] | eps | equilibrium shift [% CR] | map vs Reynolds: K / C | "
          "Reynolds turned within a cell vs itself: K / C | map vs Reynolds averaged over the turns: K / C |")
    print("|---|---|---|---|---|---|---|")
    cell = 2 * math.pi / rey.n_theta
    for hz, w in EQUILIBRIA:
        om = 2 * math.pi * hz
        qr = np.array(equilibrium(rey, (0.0, -w), om))
        qm = equilibrium(fmap, (0.0, -w), om)
        Kr, Cr = linearize(rey, *qr, om)
        Km, Cm = linearize(fmap, *qr, om)
        nk, nc = np.abs(Kr).max(), np.abs(Cr).max()
        turns = []
        for k in range(n_turn):
            a = (k + 0.5) / n_turn * cell
            R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
            K, C = linearize(rey, *(R @ qr), om)
            turns.append((_turned(K, R), _turned(C, R)))
        Ka, Ca = (np.mean([t[i] for t in turns], axis=0) for i in range(2))
        sk = max(np.abs(K - Kr).max() for K, _ in turns) / nk
        sc = max(np.abs(C - Cr).max() for _, C in turns) / nc
        print(f"| {hz:g} | {w:g} | {math.hypot(*qr) / P.CR:.4f} | {100 * math.hypot(*np.subtract(qm, qr)) / P.CR:.4f} "
              f"| {np.abs(Km - Kr).max() / nk:.1e} / {np.abs(Cm - Cr).max() / nc:.1e} | {sk:.1e} / {sc:.1e} "
              f"| {np.abs(Km - Ka).max() / nk:.1e} / {np.abs(Cm - Ca).max() / nc:.1e} |", flush=True)


def best_of(fn, repeat=5):
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        n = fn()
        out.append((time.perf_counter() - t0) / n)
    return min(out)


def speed(fmap, rey):
    """Per-call cost, best of 5 (the machine is shared): force + Jacobian in a numba loop, force +
    Jacobian and force alone from Python, Reynolds force + Jacobian from Python."""
    xs = np.array(states(2000, 0.0, 0.95, 3))
    F, J = np.zeros(2), np.zeros((2, 4))
    kernel, args_k = fmap._kernel, fmap._args

    @njit
    def loop(xs, F, J):
        acc = 0.0
        for i in range(xs.shape[0]):
            kernel(*args_k, xs[i, 0], xs[i, 1], xs[i, 2], xs[i, 3], xs[i, 4], True, F, J)
            acc += F[0]
        return acc

    loop(xs, F, J)  # compile

    def numba_loop():
        for _ in range(20):
            loop(xs, F, J)
        return 20 * len(xs)

    def python(method):
        def run():
            for x in xs:
                method(*x)
            return len(xs)
        return run

    def reynolds():
        for x in xs[:300]:
            rey.force_and_jacobian(*x)
        return 300

    t_numba = best_of(numba_loop)
    t_py = best_of(python(fmap.force_and_jacobian))
    t_force = best_of(python(fmap.force))
    t_rey = best_of(reynolds, 2)
    print(f"force + Jacobian per call (best of 5): map {t_numba * 1e6:.2f} us in a numba loop, {t_py * 1e6:.2f} us "
          f"from Python (force alone {t_force * 1e6:.2f} us); Reynolds {rey.n_theta} x {rey.n_x} "
          f"{t_rey * 1e6:.0f} us from Python ({t_rey / t_py:.0f}x the map from Python)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer states and tables")
    ap.add_argument("--map", default="rotor_host/bundled/maps/paper_bearing.json",
                    help="the map for the Lund coefficients and the speed (default: the shipped one)")
    ap.add_argument("--speed-only", nargs="*", metavar="MAP",
                    help="only the cost per call, of these map files (default: --map)")
    args = ap.parse_args()
    n = 100 if args.quick else 400
    rey = Reynolds(P)
    if args.speed_only is not None:
        for path in args.speed_only or [args.map]:
            fmap = ForceMap.from_file(path, P)
            print(f"{fmap!r}: ", end="")
            speed(fmap, rey)
        return
    sets = {b: states(n, *b, seed=i + 1) for i, b in enumerate(BANDS)}
    print(f"# force map study, {time.strftime('%Y-%m-%d')}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}; Reynolds {rey.n_theta} x {rey.n_x}, "
          f"{n} random states per set\n")
    print("solver's own scatter (grid turned within one cell), median / 95th pct / max:")
    for b, xs in sets.items():
        print(f"  {b[0]:g} < eps <= {b[1]:g}: {q(scatter(rey, xs[: n // 4]))}", flush=True)
    print("\nmap against Reynolds at the same grid, median / 95th pct / max of "
          "|F_map - F_rey| / max(|F_rey|, S |omega|):\n")
    resolution_table(rey, sets, QUICK if args.quick else TABLES)
    fmap = ForceMap.from_file(args.map, P) if not args.quick else ForceMap(P, tabulate(P, workers=2))
    print(f"\nLund coefficients, {fmap!r} against linearize on Reynolds at its equilibrium:\n")
    lund(fmap, rey)
    print()
    speed(fmap, rey)


if __name__ == "__main__":
    main()
