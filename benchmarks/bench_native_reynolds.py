"""The native FMU's Reynolds solver (bearing_fmu/fmu/native/c/reynolds_solver.c) against the
numba kernels it ports (bearing_fmu/physics/solver/reynolds_kernels.py, geometry_kernels.py): the
1000-state comparison of issue 24 and the time per call.

1. Differences: 1000 random states per grid (32 x 4, 64 x 8, 128 x 16) and cavitation model
   (eccentricity 0.05-0.97, any attitude, velocities up to omega CR, omega 20-600 rad/s; the
   states of tests/test_native_reynolds.py), force and Jacobian through the Python internal
   (``Reynolds.force_and_jacobian``) and the C solver, the largest relative difference of each
   (against the largest entry of the force, of dF/dq, of dF/dv); the other bores at 128 x 16.
2. Time per call, each in one compiled loop over the same states (the floor: no Python between
   calls): the numba kernel called from an njit loop, the C solver from a C loop
   (rs_call_many). Two sequences: the 1000 random states (far apart: mostly cold starts) and a
   transient (a whirl orbit, 1000 calls: warm starts). Best of --repeat.

    .venv/bin/python benchmarks/bench_native_reynolds.py [--repeat 5] [--states 1000]
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_cosim import cpu  # noqa: E402
from test_native_reynolds import BORES, PAPER, random_states  # noqa: E402

from bearing_fmu.fmu.native.solver_lib import NativeReynolds, solver_library  # noqa: E402
from bearing_fmu.physics.params import BearingParams  # noqa: E402
from bearing_fmu.physics.solver.reynolds import WARM_MAX_DLOG, Reynolds  # noqa: E402
from bearing_fmu.physics.solver.reynolds_kernels import reynolds_kernel  # noqa: E402
from rotor_host.analyses.report import markdown_table  # noqa: E402

GRIDS = ((32, 4), (64, 8), (128, 16))


@njit(cache=False)
def _numba_loop(states, out, mode, CR, mu, R, dth, dx, m, sin_c, cos_c, sin_f, cos_f, ds, dc, tdiag, rs, qw,
                at, ax, b, db, dat, dax, diag, cxo, cto, act, Lb, Y, S, zb, z2, p, pf, rhs, tmp, mu_y, mu_z,
                F, dFq, dFv, Ft, info, max_iter, grow, warm, warm_cap, max_turn, max_dlog, hs, order, nvalid, wring):
    for k in range(states.shape[0]):
        x = states[k]
        info[:] = 0.0
        reynolds_kernel(mode, True, x[0], x[1], x[2], x[3], x[4], CR, mu, R, dth, dx, m, sin_c, cos_c, sin_f,
                        cos_f, ds, dc, tdiag, rs, qw, at, ax, b, db, dat, dax, diag, cxo, cto, act, Lb, Y, S, zb, z2,
                        p, pf, rhs, tmp, mu_y, mu_z, F, dFq, dFv, Ft, info, max_iter, grow, warm, warm_cap,
                        max_turn, max_dlog, hs, order, nvalid, wring)
        out[k, 0:2] = F
        out[k, 2:6] = dFq.ravel()
        out[k, 6:10] = dFv.ravel()


def numba_many(rey: Reynolds, states: np.ndarray) -> np.ndarray:
    """The full bore's numba kernel at every state in one njit loop (the arrays of ``rey``)."""
    s, pr = rey, rey.params
    out = np.zeros((states.shape[0], 10))
    _numba_loop(states, out, s._mode, pr.CR, pr.mu, pr.R, s._dth, s._dx, s._m, s._sin_c, s._cos_c, s._sin_f,
                s._cos_f, s._ds, s._dc, s._tdiag, s._rs, s._qw, s._at, s._ax, s._b, s._db, s._dat, s._dax, s._diag,
                s._cxo, s._cto, s._act, s._Lb, s._Y, s._S, s._zb, s._z2, s._p, s._pf, s._rhs, s._tmp, s._mu_y,
                s._mu_z, s._F, s._dFq, s._dFv, s._Ft, s._info, s._max_iter, s._grow, s.warm_start, s._warm_cap,
                s._max_turn, WARM_MAX_DLOG, s._hs, s._order, s._nvalid, s._wring)
    return out


def transient(params: BearingParams, n: int) -> np.ndarray:
    """A forward whirl at 0.3 x the 22 Hz speed with a slowly breathing radius, 2e-4 s apart,
    each step evaluated twice (a Newton iterate 1e-3 beside it)."""
    omega, CR = 2 * math.pi * 22.0, params.CR
    whirl, out = 0.3 * omega, []
    for k in range(n // 2):
        t = k * 2e-4
        r = CR * (0.5 + 0.3 * math.sin(40.0 * t))
        y, z = r * math.cos(whirl * t), r * math.sin(whirl * t)
        out += [(y, z, -whirl * z, whirl * y, omega), (y * 1.001, z, -whirl * z, whirl * y, omega)]
    return np.array(out)


def rel(a: np.ndarray, b: np.ndarray) -> float:
    """|a - b| over the largest |b|; |a| where b is 0 (a film cavitated whole: F = 0, J = 0)."""
    scale = np.max(np.abs(b))
    return float(np.max(np.abs(a - b)) / scale) if scale > 0 else float(np.max(np.abs(a)))


def differences(lib, n: int) -> list[dict]:
    rows = []
    cases = [("full", g, cav) for g in GRIDS for cav in ("reynolds", "gumbel")]
    cases += [(name, (128, 16), cav) for name in BORES if name != "full" for cav in ("reynolds", "gumbel")]
    for bore, grid, cav in cases:
        params = BearingParams(**PAPER, geometry=BORES[bore])
        py = Reynolds(params, *grid, cavitation=cav)
        c = NativeReynolds(lib, params, *grid, cavitation=cav)
        worst = np.zeros(3)
        for s in random_states(params, n, 3):
            a, b = py.force_and_jacobian(*s), c.force_and_jacobian(*s)
            worst = np.maximum(worst, [rel(b[0], a[0]), rel(b[1], a[1]), rel(b[2], a[2])])
        rows.append({"bore": bore, "grid": f"{grid[0]} x {grid[1]}", "cav": cav, "F": worst[0], "K": worst[1],
                     "C": worst[2], "passes": f"{py.counts()['passes']} / {c.counts()['passes']}"})
    return rows


def best_time(fn, repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def timings(lib, n: int, repeat: int) -> list[dict]:
    rows = []
    params = BearingParams(**PAPER)
    for grid in GRIDS:
        for cav in ("reynolds", "gumbel"):
            for label, states in (("random", np.array(random_states(params, n, 3))),
                                  ("transient", transient(params, n))):
                py = Reynolds(params, *grid, cavitation=cav)
                c = NativeReynolds(lib, params, *grid, cavitation=cav)

                def run_numba():
                    py.forget()
                    return numba_many(py, states)

                def run_c():
                    c.forget()
                    return c.call_many(states)

                diff = rel(run_c(), run_numba())  # also compiles the njit loop before timing
                tn, tc = best_time(run_numba, repeat), best_time(run_c, repeat)
                rows.append({"grid": f"{grid[0]} x {grid[1]}", "cav": cav, "seq": label,
                             "numba": 1e6 * tn / len(states), "c": 1e6 * tc / len(states), "ratio": tc / tn,
                             "diff": diff})
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5, help="runs of each timed loop, the fastest counts")
    ap.add_argument("--states", type=int, default=1000, help="random states per grid and cavitation model")
    args = ap.parse_args()
    print(f"bench_native_reynolds: {cpu()}, {platform.machine()}, Python {platform.python_version()}")
    with tempfile.TemporaryDirectory() as tmp:
        lib = solver_library(Path(tmp))
        rows = differences(lib, args.states)
        print(f"\nC solver vs Python internal, {args.states} random states each: largest relative difference")
        print(markdown_table(rows, [("bore", "bore", ""), ("grid", "grid", ""), ("cav", "cavitation", ""),
                                    ("F", "force", ".2g"), ("K", "dF/dq", ".2g"), ("C", "dF/dv", ".2g"),
                                    ("passes", "passes Python / C", "")]))
        rows = timings(lib, args.states, args.repeat)
    print(f"\nForce and Jacobian per call, one compiled loop each, best of {args.repeat} [us]:")
    print(markdown_table(rows, [("grid", "grid", ""), ("cav", "cavitation", ""), ("seq", "states", ""),
                                ("numba", "numba kernel", ".1f"), ("c", "C solver", ".1f"),
                                ("ratio", "C / numba", ".2f"), ("diff", "largest difference", ".2g")]))


if __name__ == "__main__":
    main()
