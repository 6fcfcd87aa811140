"""The lobed bore's force map (the sum of its lobes' partial-arc maps, internals/map/lobemap.py) against
the lobed bore's Reynolds solver: force at random states, the cost of one call side by side, and the
closed loop (a scene with the map against the same scene on Reynolds called directly).

    .venv/bin/python benchmarks/lobemap_study.py BEARING MAP [--states 300] [--scene SCENE [--speed-hz F]
        [--mass-kg M] [--t-end S]]

The force error is |F_map - F_Reynolds| / max(|F_Reynolds|, S |omega|), S = mu R L (R / CR)^2, as
groovemap_study.py measures it; the states: the journal anywhere within 0.95 CR of the bearing's centre,
speeds of both signs (0.2-3 x 22 Hz), velocities up to 1.5 CR omega.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.internals.map.mapfile import load_any_map, map_internal
from bearing_fmu.internals.map.tables import scale
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

OMEGA = 2.0 * math.pi * 22.0


def states(P, n, seed, e_hi=0.95):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        e, phi = P.CR * e_hi * math.sqrt(rng.uniform()), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        out.append((e * math.cos(phi), e * math.sin(phi), v[0], v[1], om))
    return out


def accuracy(P, fmap, rey, xs):
    err = []
    for x in xs:
        F, Fr = np.array(fmap.force(*x)), np.array(rey.force(*x))
        err.append(np.linalg.norm(F - Fr) / max(np.linalg.norm(Fr), scale(P) * abs(x[4])))
    return np.array(err)


def cost(fmap, rey, xs, repeat=3):
    """[s] per force_and_jacobian call of each, side by side (best of ``repeat``)."""
    t_map, t_rey = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for x in xs:
            fmap.force_and_jacobian(*x)
        t_map.append((time.perf_counter() - t0) / len(xs))
        t0 = time.perf_counter()
        for x in xs:
            rey.force_and_jacobian(*x)
        t_rey.append((time.perf_counter() - t0) / len(xs))
    return min(t_map), min(t_rey)


def closed_loop(scene_path, map_path, grid, speed_hz=None, mass_kg=None, t_end=None):
    from rotor_host.analyses.report import errors_against
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(scene_path)
    kw = {k: v for k, v in (("speed_hz", speed_hz), ("t_end_s", t_end)) if v is not None}
    if mass_kg is not None:
        from dataclasses import replace

        scene = replace(scene, unbalances=[replace(u, mass_kg=mass_kg) for u in scene.unbalances])
    out = Path(tempfile.mkdtemp())

    def run(internal, opts, stem):
        t0 = time.perf_counter()
        r = run_scene(scene.with_internal(internal, via="direct", options=opts, **kw), out, stem=stem)
        return r, time.perf_counter() - t0

    rey, t_rey = run("reynolds", {"reynolds": {"n_theta": grid[0], "n_x": grid[1]}}, "reynolds")
    fmap, t_map = run("map", {"map": {"map": Path(map_path).resolve()}}, "map")
    return errors_against(rey.arrays, fmap.arrays), t_rey, t_map, rey.meta["status"], fmap.meta["status"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bearing")
    ap.add_argument("map")
    ap.add_argument("--states", type=int, default=300)
    ap.add_argument("--grid", default="128x16", help="the lobed bore's Reynolds grid N_THETAxN_X")
    ap.add_argument("--scene")
    ap.add_argument("--speed-hz", type=float)
    ap.add_argument("--mass-kg", type=float)
    ap.add_argument("--t-end", type=float)
    args = ap.parse_args()
    grid = tuple(int(v) for v in args.grid.split("x"))
    P = BearingParams.from_toml(args.bearing)
    table = load_any_map(args.map)
    fmap = map_internal(P, table, args.map)
    rey = Reynolds(P, *grid)
    xs = states(P, args.states, 1)
    e = accuracy(P, fmap, rey, xs)
    t_map, t_rey = cost(fmap, rey, xs[:100])
    print(f"{fmap!r}\nagainst Reynolds {grid[0]} x {grid[1]} at {len(xs)} states: median {np.median(e):.2g}, p95 "
          f"{np.quantile(e, 0.95):.2g}, max {e.max():.2g}; force + Jacobian {t_map * 1e6:.0f} us (map) vs "
          f"{t_rey * 1e6:.0f} us (Reynolds): {t_rey / t_map:.1f}x", flush=True)
    if args.scene:
        err, t_r, t_m, s_r, s_m = closed_loop(args.scene, args.map, grid, args.speed_hz, args.mass_kg, args.t_end)
        print(f"{Path(args.scene).stem} (speed {args.speed_hz or 'scene'}, mass {args.mass_kg or 'scene'}): Reynolds "
              f"{s_r} in {t_r:.1f} s, map {s_m} in {t_m:.1f} s ({t_r / t_m:.1f}x); orbit RMS "
              f"{err['orbit_rms_pct_cr']:.4f} % CR, max {err['orbit_max_pct_cr']:.4f} % CR, force NRMSE "
              f"{err['force_nrmse_pct']:.4f} %")


if __name__ == "__main__":
    main()
