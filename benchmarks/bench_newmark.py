"""Newmark integrator: steps per second and Newton iterations per step on a 44-DOF rotor.

    .venv/bin/python benchmarks/bench_newmark.py [--t-end 0.2] [--dt 1e-4] [--no-profile]

Rotor: the paper rotor (rotor_host/bundled/rotor_paper.toml through rotor_host.model.rotor.Rotor) when it can be
built, otherwise a 44-DOF Euler-Bernoulli beam chain of similar size (11 nodes, disk at node 6).
Bearings at nodes 3 and 9 (1-based), DOFs y, z. Cases, dt = 1e-4 s over 0.2 s at 22 Hz with
the paper's unbalance (8.5 g at 37 mm on the disk) and weight:

  linear-in-K   bearing springs and dampers inside K and C, no nodal force (the floor)
  linear-nodal  the same bearings as a LinearForce (protocol, exact tangent)
  cubic-nodal   f = -(Kb q + k3 q^3) - Cb v per bearing DOF, exact tangent (a cheap
                nonlinear force; k3 chosen so that k3 q^2 ~ Kb at q ~ 10 um)
  cubic-fd      the cubic force without derivatives, finite-difference tangent

Prints a markdown table, the per-iteration cost of the Woodbury correction against refactoring
the dense 44 x 44 tangent, and a cProfile of the cubic-nodal case (top per-step costs).
"""

from __future__ import annotations

import argparse
import cProfile
import math
import pstats
import sys
import time
import timeit
from pathlib import Path

import numpy as np
import scipy.linalg as sla

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from rotor_host.integrate import banded  # noqa: E402
from rotor_host.integrate import forces  # noqa: E402
from rotor_host.integrate import newmark as nm  # noqa: E402
from rotor_host.integrate import newmark_kernels as kernels  # noqa: E402

HZ = 22.0
UNBALANCE = (8.5e-3, 37e-3)  # kg, m (paper, section 3)
KB = np.array([[3.0e5, 1.0e5], [-2.0e5, 6.0e5]])  # N/m, a plausible Lund stiffness block
CB = np.array([[1.0e3, 1.0e2], [1.0e2, 2.0e3]])  # N s/m
K3 = 3.0e15  # N/m^3


def beam_chain():
    """44-DOF stand-in: 10 Euler-Bernoulli elements of the paper's lengths and diameters,
    disk lumped at node 6, steel, C = 1.5e-5 K."""
    E, rho = 200e9, 7850.0
    elems = [(40, 12), (10, 31), (10, 31), (266.5, 12), (23.5, 23.5), (23.5, 23.5), (266.5, 12), (10, 31),
             (10, 31), (40, 12)]
    n = 44
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    G = np.zeros((n, n))
    for e, (L_mm, d_mm) in enumerate(elems):
        L, d = L_mm * 1e-3, d_mm * 1e-3
        A, I = math.pi * d * d / 4, math.pi * d ** 4 / 64
        k = E * I / L ** 3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                        [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
        m = rho * A * L / 420 * np.array([[156, 22 * L, 54, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                                          [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
        for plane, rot, sign in ((0, 3, 1.0), (1, 2, -1.0)):  # (y, tz) and (z, -ty)
            idx = [4 * e + plane, 4 * e + rot, 4 * (e + 1) + plane, 4 * (e + 1) + rot]
            S = np.diag([1.0, sign, 1.0, sign])
            K[np.ix_(idx, idx)] += S @ k @ S
            M[np.ix_(idx, idx)] += S @ m @ S
    md, Id, Ip = 2.3, 1.7e-3, 2.6e-3
    j = 4 * 5
    M[j, j] += md
    M[j + 1, j + 1] += md
    M[j + 2, j + 2] += Id
    M[j + 3, j + 3] += Id
    G[j + 2, j + 3], G[j + 3, j + 2] = Ip, -Ip
    return M, K, 1.5e-5 * K, G, "44-DOF Euler-Bernoulli chain (stand-in)"


def load_rotor():
    try:
        from rotor_host.model.rotor import Rotor
        r = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml")
        M, K, C, G = (np.asarray(a, dtype=float) for a in (r.M, r.K, r.C, r.G))
        if M.shape != (44, 44):
            raise ValueError(f"paper rotor has {M.shape[0]} DOFs")
        return M, K, C, G, "paper rotor (rotor_host/bundled/rotor_paper.toml)"
    except Exception as e:  # noqa: BLE001 - any failure: fall back, say why
        print(f"(paper rotor unavailable: {type(e).__name__}: {e}; using the stand-in chain)")
        return beam_chain()


class CubicBearings:
    """f = -(Kb q + k3 q^3) - Cb v on (y, z) of each bearing, exact derivatives or none."""

    def __init__(self, dofs, exact=True):
        self.dofs = np.asarray(dofs)
        nb = len(dofs) // 2
        self.Kb = sla.block_diag(*[KB] * nb)
        self.Cb = sla.block_diag(*[CB] * nb)
        self.exact = exact
        self._dv = -self.Cb

    def begin_step(self, t, dt):
        pass

    def evaluate(self, q, v):
        f = -(self.Kb @ q) - K3 * q ** 3 - self.Cb @ v
        if not self.exact:
            return f, None, None
        dq = -self.Kb - np.diag(3.0 * K3 * q * q)
        return f, dq, self._dv

    def accept_step(self):
        pass

    def reject_step(self):
        pass


def build_cases(M, K, C, G):
    n = M.shape[0]
    bdofs = [4 * 2, 4 * 2 + 1, 4 * 8, 4 * 8 + 1]  # nodes 3 and 9 (1-based), y and z
    omega = 2 * math.pi * HZ
    w = np.zeros(n)
    w[1::4] = 1.0
    f_w = -9.81 * (M @ w)
    amp = UNBALANCE[0] * UNBALANCE[1] * omega ** 2
    iy, iz = 4 * 5, 4 * 5 + 1

    def f_ext(t, _f=np.empty(n)):
        _f[:] = f_w
        _f[iy] += amp * math.cos(omega * t)
        _f[iz] += amp * math.sin(omega * t)
        return _f

    Kin, Cin = K.copy(), C.copy()
    for i in (0, 2):
        idx = bdofs[i:i + 2]
        Kin[np.ix_(idx, idx)] += KB
        Cin[np.ix_(idx, idx)] += CB
    lin = forces.LinearForce(bdofs, sla.block_diag(KB, KB), sla.block_diag(CB, CB))
    return {
        "linear-in-K": dict(M=M, K=Kin, C=Cin, G=G, omega=omega, f_ext=f_ext, nodal_force=None),
        "linear-nodal": dict(M=M, K=K, C=C, G=G, omega=omega, f_ext=f_ext, nodal_force=lin),
        "cubic-nodal": dict(M=M, K=K, C=C, G=G, omega=omega, f_ext=f_ext, nodal_force=CubicBearings(bdofs)),
        "cubic-fd": dict(M=M, K=K, C=C, G=G, omega=omega, f_ext=f_ext,
                         nodal_force=CubicBearings(bdofs, exact=False), config=nm.NewmarkConfig(tangent="fd")),
    }, bdofs


def run_case(kw, t_end, dt, repeats):
    """Best wall time of `repeats` runs (the machine may be shared), after a warm-up."""
    n = kw["M"].shape[0]
    integ = nm.Newmark(**kw)
    integ.run(np.zeros(n), np.zeros(n), 0.0, 10 * dt, dt)  # warm-up (numba, caches)
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = integ.run(np.zeros(n), np.zeros(n), 0.0, t_end, dt)
        best = min(best, time.perf_counter() - t0)
    return res, best


def woodbury_vs_refactor(M, K, C, G, bdofs, dt):
    """Per-iteration linear algebra: the compiled Woodbury correction (against the banded LU
    of S0) vs lu_factor + lu_solve."""
    n, m = M.shape[0], len(bdofs)
    omega = 2 * math.pi * HZ
    D = C + omega * G
    cfg = nm.NewmarkConfig()
    dofs = np.asarray(bdofs, dtype=np.int64)
    w = banded.bandwidth(M, K, C, G)
    ops = kernels.StepOps(dt, banded.to_band(M, w), banded.to_band(D, w), banded.to_band(K, w), dofs, cfg)
    S0, LU, c1 = banded.from_band(ops.SB[0]), ops.SB[1], ops.c1
    rng = np.random.default_rng(0)
    R = rng.standard_normal(n)
    Jq = -np.diag(rng.uniform(1e5, 1e6, m))
    Jv = -np.diag(rng.uniform(1e2, 1e3, m))
    x, A, y, Jt, dq = np.zeros(n), np.zeros((m, m)), np.zeros(m), np.zeros((m, m)), np.zeros(n)
    args = (R, Jq, Jv, c1, 1.0, LU, ops.W, dofs, x, A, y, Jt, dq)
    kernels._correction(*args)

    def refactor():
        S = S0.copy()
        S[np.ix_(dofs, dofs)] -= Jq + c1 * Jv
        return sla.lu_solve(sla.lu_factor(S, check_finite=False), -R, check_finite=False)

    np.testing.assert_allclose(dq, refactor(), rtol=1e-8, atol=1e-14 * np.max(np.abs(dq)))
    N = 20000
    t_w = min(timeit.repeat(lambda: kernels._correction(*args), number=N, repeat=3)) / N
    t_r = min(timeit.repeat(refactor, number=N // 10, repeat=3)) / (N // 10)
    lu = sla.lu_factor(S0)
    t_s = min(timeit.repeat(lambda: sla.lu_solve(lu, R, check_finite=False), number=N, repeat=3)) / N
    return t_w, t_r, t_s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.2)
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-profile", action="store_true")
    args = ap.parse_args(argv)

    M, K, C, G, label = load_rotor()
    cases, bdofs = build_cases(M, K, C, G)
    n_steps = int(round(args.t_end / args.dt))
    print(f"\n{label}: {M.shape[0]} DOFs, bearings at DOFs {bdofs}, {HZ} Hz, dt = {args.dt:g} s, "
          f"{args.t_end:g} s = {n_steps} steps\n")
    print("Newton iterations = force evaluations per step (1 = the linearised predictor was accepted);"
          " best of", args.repeats, "runs.\n")
    print("| case | steps/s | us/step | iterations/step (mean, max) | total evaluations | cuts |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    results = {}
    for name, kw in cases.items():
        res, wall = run_case(kw, args.t_end, args.dt, args.repeats)
        results[name] = res
        print(f"| {name} | {n_steps / wall:,.0f} | {wall / n_steps * 1e6:.1f} | "
              f"{res.mean_iterations:.2f}, {res.iterations.max()} | {res.n_evaluations} | {res.n_cuts} |")
    d = np.max(np.abs(results["linear-nodal"].q - results["linear-in-K"].q))
    print(f"\nlinear-nodal vs linear-in-K: max |dq| = {d:.2e} m (same equations)")
    jb = np.asarray(bdofs)
    amp = np.max(np.abs(results["cubic-nodal"].q[:, jb]))
    print(f"cubic-nodal: max bearing displacement {amp * 1e6:.1f} um, k3 q^2 / Kb = {K3 * amp ** 2 / KB[0, 0]:.2f}")

    t_w, t_r, t_s = woodbury_vs_refactor(M, K, C, G, bdofs, args.dt)
    print("\nPer Newton correction (44 DOFs, 4 nonlinear DOFs):\n")
    print("| method | us |\n| --- | ---: |")
    print(f"| Woodbury on the banded LU of S0 (compiled kernel) | {t_w * 1e6:.2f} |")
    print(f"| refactor dense 44x44 tangent (lu_factor + lu_solve) | {t_r * 1e6:.2f} |")
    print(f"| (one lu_solve with the constant S0 from Python) | {t_s * 1e6:.2f} |")

    if not args.no_profile:
        kw = cases["cubic-nodal"]
        integ = nm.Newmark(**kw)
        n = M.shape[0]
        integ.run(np.zeros(n), np.zeros(n), 0.0, 10 * args.dt, args.dt)
        pr = cProfile.Profile()
        pr.enable()
        integ.run(np.zeros(n), np.zeros(n), 0.0, args.t_end, args.dt)
        pr.disable()
        st = pstats.Stats(pr)
        rows = []
        for (fname, line, func), (cc, nc, tt, ct, callers) in st.stats.items():
            rows.append((tt, nc, f"{Path(fname).name}:{line}({func})" if line else func))
        rows.sort(reverse=True)
        total = sum(r[0] for r in rows)
        print(f"\ncProfile, cubic-nodal, {n_steps} steps (profiler overhead inflates Python calls): "
              f"{total / n_steps * 1e6:.1f} us/step in total\n")
        print("| function | calls/step | own us/step | share |\n| --- | ---: | ---: | ---: |")
        for tt, nc, name in rows[:12]:
            print(f"| {name} | {nc / n_steps:.2f} | {tt / n_steps * 1e6:.2f} | {tt / total:.0%} |")


if __name__ == "__main__":
    main()
