"""Force map of a grooved or partial-arc bore (3-D, ``internals/map/groovemap.py``): the reduction
checked on the solver, the supply-pressure test, and the resolution study, in one run.

* Reduction: states with equal (eps, phi, beta) but r from 0.01 to 2500 1/s and speeds of both
  signs give the same G = F / (S r) from Reynolds (and phi + the bore's symmetry period too).
* Supply pressure: F(p_s) - F(0) at one position for motions scaled by 0.5, 1, 2: a constant
  under superposition (a p_s part independent of r); with cavitation it is not.
* Resolution: maps of the two-groove paper bearing (or --bearing) at several (n_eps, n_phi,
  n_beta, attitudes), against Reynolds at the same grid at random states (eps <= 0.95, any
  attitude, speeds of both signs 0.2-3 x 22 Hz, velocities up to 1.5 omega CR):
  |F_map - F_rey| / max(|F_rey|, S |omega|), median / p95 / max; the interpolation error alone
  (against the averaged function the table samples) and the solver's own roughness in phi (its
  G over +-1 cell of attitude minus the quadratic through it).

    .venv/bin/python benchmarks/groovemap_study.py [--bearing FILE] [--quick] [--out DIR]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.internals.map.tables import reduced, scale, state_for
from bearing_fmu.internals.map.groovemap import (GroovedForceMap, grooved_row, save_grooved_map, symmetry_period,
                                             tabulate_grooved)
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

OMEGA = 2 * math.pi * 22.0
TABLES = [(48, 8, 48, 2), (48, 12, 48, 2), (48, 16, 48, 2), (48, 24, 48, 2), (48, 32, 48, 2),
          (32, 24, 32, 2), (64, 24, 64, 2), (48, 24, 48, 1), (48, 24, 48, 4), (64, 24, 64, 1), (64, 32, 64, 1)]
QUICK = [(24, 8, 24, 1), (32, 12, 32, 2)]


def states(P, n, seed, eps_hi=0.95):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        eps, phi = rng.uniform(0.0, eps_hi), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        out.append((eps * P.CR * math.cos(phi), eps * P.CR * math.sin(phi), v[0], v[1], om))
    return out


def rel(P, F, Fref, omega):
    return np.linalg.norm(np.subtract(F, Fref)) / max(np.linalg.norm(Fref), scale(P) * abs(omega))


def G_of(P, rey, eps, phi, beta, r, omega):
    y, z, vy, vz = state_for(eps, beta, P, phi, omega, r)
    F = np.array(rey.force(y, z, vy, vz, omega))
    u, w = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
    return np.array([F @ u, F @ w]) / (scale(P) * r)


def reduction_check(P, rey):
    period = symmetry_period(P.geometry)
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(20):
        eps, phi, beta = rng.uniform(0, 0.95), rng.uniform(-math.pi, math.pi), rng.uniform(-math.pi, math.pi)
        ref = G_of(P, rey, eps, phi, beta, 1.0, 1.0)
        for r, om in ((0.01, 3.0), (100.0, 138.0), (2500.0, -50.0), (7.0, -900.0)):
            worst = max(worst, np.abs(G_of(P, rey, eps, phi, beta, r, om) - ref).max() / np.abs(ref).max())
        if period < 2 * math.pi:
            worst = max(worst, np.abs(G_of(P, rey, eps, phi + period, beta, 3.0, 9.0) - ref).max() / np.abs(ref).max())
    print(f"reduction: 20 (eps, phi, beta) x 4 states with r 0.01 .. 2500 1/s, omega of both signs"
          f"{' and phi + the symmetry period' if period < 2 * math.pi else ''}: largest relative difference in G "
          f"{worst:.1e}")


def supply_check(P):
    if not P.geometry.grooves:
        return
    fed = dataclasses.replace(P, geometry=dataclasses.replace(P.geometry, supply_pressure=100e3))
    r0, r1 = Reynolds(P), Reynolds(fed)
    print("supply pressure 100 kPa: F(p_s) - F(0) [N] for the motion scaled by lambda (constant if superposable)")
    for eps in (0.1, 0.5, 0.8):
        y, z, vy, vz = state_for(eps, 0.0, P, -0.5 * math.pi, OMEGA, OMEGA * eps)
        row = []
        for lam in (0.5, 1.0, 2.0):
            d = np.subtract(r1.force(y, z, lam * vy, lam * vz, lam * OMEGA), r0.force(y, z, lam * vy, lam * vz,
                                                                                   lam * OMEGA))
            row.append(f"lambda {lam:g}: ({d[0]:.3g}, {d[1]:.3g})")
        print(f"  eps {eps:g} (22 Hz, journal below the centre, beta 0): " + "; ".join(row))


def sampled(P, rey, x, n_phase):
    eps, phi, a, c = reduced(*x[:4], x[4], P.CR)
    G = grooved_row(P, rey.n_theta, rey.n_x, rey.cavitation, eps, [phi], [math.atan2(c, a)], n_phase, rey, False)[0][0, 0]
    u = np.array([math.cos(phi), math.sin(phi)])
    return scale(P) * math.hypot(a, c) * (G[0] * u + G[1] * np.array([-u[1], u[0]]))


def roughness(P, rey, xs, n_turn=9):
    """The solver's cell-scale roughness in phi at each state's (eps, beta): G at n_turn attitudes
    over +-1 cell, minus its least-squares quadratic in phi (the smooth dependence on the grooves'
    position), largest residual relative to max(|G|, 1). No table finer than a cell follows it."""
    out = []
    cell = 2 * math.pi / rey.n_theta
    d = np.linspace(-cell, cell, n_turn)
    for x in xs:
        eps, phi, a, c = reduced(*x[:4], x[4], P.CR)
        G = np.array([G_of(P, rey, eps, phi + k, math.atan2(c, a), 1.0, 1.0) for k in d])
        fit = np.polynomial.polynomial.polyvander(d / cell, 2)
        res = G - fit @ np.linalg.lstsq(fit, G, rcond=None)[0]
        out.append(np.abs(res).max() / max(np.linalg.norm(G.mean(axis=0)), 1.0))
    return np.array(out)


def cost(P, fmap, rey, xs):
    """Force + Jacobian per call from Python [us]: the map against Reynolds, side by side."""
    out = []
    for f, n in ((fmap.force_and_jacobian, 20), (rey.force_and_jacobian, 1)):
        t0 = time.perf_counter()
        for _ in range(n):
            for x in xs:
                f(*x)
        out.append((time.perf_counter() - t0) / (n * len(xs)) * 1e6)
    print(f"cost per call, force + Jacobian from Python: map {out[0]:.1f} us, Reynolds {rey.n_theta} x {rey.n_x} "
          f"{out[1]:.0f} us ({out[1] / out[0]:.0f}x)")


def q(e):
    return f"{np.median(e):.1e} / {np.percentile(e, 95):.1e} / {np.max(e):.1e}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bearing", default="rotor_host/bundled/bearing_paper_2groove.toml")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--states", type=int, default=300)
    ap.add_argument("--out", default=None, help="keep the maps in this folder")
    ap.add_argument("--tables", default=None, help="n_eps,n_phi,n_beta,phases;... instead of the ladder")
    ap.add_argument("--cost", default=None, metavar="MAP", help="only the cost per call of this map file")
    args = ap.parse_args()
    P = BearingParams.from_toml(args.bearing)
    rey = Reynolds(P)
    if args.cost:
        from bearing_fmu.internals.map.mapfile import open_map

        fmap = open_map(args.cost, P)
        xs = states(P, 200, 2)
        fmap.force_and_jacobian(*xs[0])
        return cost(P, fmap, rey, xs)
    print(f"{args.bearing}: {P.geometry.describe()}, L/D {P.L / P.D:.4g}, Reynolds {rey.n_theta} x {rey.n_x}; "
          f"{time.strftime('%Y-%m-%d %H:%M')}")
    reduction_check(P, rey)
    supply_check(P)
    xs = states(P, 40 if args.quick else args.states, 1)
    Fr = [rey.force(*x) for x in xs]
    sc = roughness(P, rey, xs[:100])
    print(f"solver roughness in phi (G over +-1 cell minus its quadratic), 100 states: {q(sc)}")
    tables = QUICK if args.quick else TABLES
    if args.tables:
        tables = [tuple(int(v) for v in t.split(",")) for t in args.tables.split(";")]
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp())
    out.mkdir(parents=True, exist_ok=True)
    print("| n_eps x n_phi x n_beta | attitudes | build [s] (2 workers) | file [kB] | against Reynolds: median / p95 / max "
          "| interpolation alone (60 states) |")
    print("|---|---|---|---|---|---|")
    for ne, nphi, nb, nph in tables:
        t0 = time.perf_counter()
        table = tabulate_grooved(P, n_eps=ne, n_phi=nphi, n_beta=nb, n_phase=nph, workers=2)
        built = time.perf_counter() - t0
        path = save_grooved_map(table, out / f"map_{ne}x{nphi}x{nb}_{nph}.json")
        fmap = GroovedForceMap(P, table)
        e = np.array([rel(P, fmap.force(*x), f, x[4]) for x, f in zip(xs, Fr)])
        ei = np.array([rel(P, fmap.force(*x), sampled(P, rey, x, nph), x[4]) for x in xs[:60]])
        print(f"| {ne} x {nphi} x {nb} | {nph} | {built:.0f} | {path.stat().st_size / 1e3:.0f} | {q(e)} | {q(ei)} |",
              flush=True)


if __name__ == "__main__":
    main()
