"""Taylor surrogate vs Reynolds: time per force call and held-out NRMSE per order.

    .venv/bin/python benchmarks/bench_taylor.py [--orders 1 2 3 4 5 6 7] [--n-train 3000]
        [--n-test 1500] [--conditions 22 44 10h 20h] [--grid N_THETA N_X] [--calls 20000]

For each condition (see CONDITIONS: load, speed and the designed domain) it computes the
equilibrium with Reynolds, draws one training and one held-out Latin-hypercube design (seeds
1 and 1001) with Reynolds forces, fits every order (lambda by 5-fold CV, no pruning: the
order study compares bases; constant and order-1 terms anchored to Reynolds' force and
derivatives at the equilibrium unless --no-anchor), and prints markdown tables: held-out NRMSE (the larger of Fy,
Fz; NRMSE = RMS error / std of the truth) per condition and order, and the time per call
of Taylor.force and Reynolds.force in a plain Python loop.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu import fitting as F  # noqa: E402
from bearing_fmu.internals.taylor import Taylor  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING  # noqa: E402
from bearing_fmu.physics.statics import equilibrium  # noqa: E402

# name: (load (Wy, Wz) [N], speed [Hz], domain keywords of designed_samples)
# 22, 44: the domains of the shipped surrogates (rotor_host/bundled/surrogates/paper_*hz_16.7N.json);
# 22s, 44s: small discs (0.1 CR, 0.1 omega CR) about the equilibrium, where order 5 is ~1 %;
# 10h, 20h: the paper's eccentricity-0.9 cases, 0.05 CR / 0.05 omega CR about the equilibrium.
CONDITIONS = {
    "22": ((0.0, -16.7), 22.0, dict(ecc_max=0.95, v_max=0.4, radius=0.4)),
    "22s": ((0.0, -16.7), 22.0, dict(ecc_max=0.95, v_max=0.1, radius=0.1)),
    "44": ((0.0, -16.7), 44.0, dict(ecc_max=0.7, v_max=0.4, radius=None)),
    "44s": ((0.0, -16.7), 44.0, dict(ecc_max=0.95, v_max=0.1, radius=0.1)),
    "10h": ((0.0, -500.0), 10.0, dict(ecc_max=0.97, v_max=0.05, radius=0.05)),
    "20h": ((0.0, -800.0), 20.0, dict(ecc_max=0.97, v_max=0.05, radius=0.05)),
}


def describe(dom) -> str:
    if dom["radius"] is None:
        pos = f"ecc <= {dom['ecc_max']:g} about the centre"
    else:
        pos = f"{dom['radius']:g} CR about eq. (ecc <= {dom['ecc_max']:g})"
    return f"{pos}, v <= {dom['v_max']:g}"


def time_calls(fn, args, n):
    fn(*args)
    t0 = time.perf_counter()
    for _ in range(n):
        fn(*args)
    return (time.perf_counter() - t0) / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--orders", type=int, nargs="+", default=list(range(1, 8)))
    ap.add_argument("--conditions", nargs="+", default=list(CONDITIONS))
    ap.add_argument("--n-train", type=int, default=3000)
    ap.add_argument("--n-test", type=int, default=1500)
    ap.add_argument("--grid", type=int, nargs=2, default=None)
    ap.add_argument("--calls", type=int, default=20000, help="calls timed per Taylor order")
    ap.add_argument("--no-anchor", action="store_true",
                    help="regress the constant and order-1 terms too (default: fixed to Reynolds at the equilibrium)")
    args = ap.parse_args(argv)

    rey = F.make_reynolds(PAPER_BEARING, tuple(args.grid) if args.grid else None)
    grid = f"{getattr(rey, 'n_theta', '?')} x {getattr(rey, 'n_x', '?')}"
    nrmse: dict[str, dict[int, tuple[float, float]]] = {}
    timing: dict[int, float] = {}
    rey_time = None
    for name in args.conditions:
        load, hz, dom = CONDITIONS[name]
        omega = 2 * math.pi * hz
        y0, z0 = equilibrium(rey, load, omega)
        anchor = None if args.no_anchor else F.truth_jacobian(rey, y0, z0, omega)
        t0 = time.perf_counter()
        st, fo, domain = F.designed_samples(rey, y0, z0, omega, n=args.n_train, seed=1, **dom)
        ts, tf, _ = F.designed_samples(rey, y0, z0, omega, n=args.n_test, seed=1001, **dom)
        t_samp = time.perf_counter() - t0
        if rey_time is None:
            x = (st[0, 0], st[0, 1], st[0, 2], st[0, 3], omega)
            rey_time = time_calls(rey.force, x, 300)
        eps0 = math.hypot(y0, z0) / PAPER_BEARING.CR
        print(f"# condition {name}: load {load} N, {hz:g} Hz, equilibrium eccentricity {eps0:.4f}, "
              f"domain {dom}; {args.n_train}+{args.n_test} Reynolds samples in {t_samp:.1f} s", flush=True)
        nrmse[name] = {}
        for order in args.orders:
            recipe = F.FitRecipe(order=order, prune=False, anchor=anchor is not None, seed=0)
            res = F.fit_surrogate(st, fo, PAPER_BEARING, omega, y0, z0, recipe, domain=domain, anchor=anchor,
                                  bias_variance=False, test=(ts, tf), load=load)
            e = res.report["errors"]["test_nrmse"]
            lam = res.report["lambda"]
            nrmse[name][order] = (e["Fy"], e["Fz"])
            print(f"  order {order}: held-out NRMSE Fy {e['Fy']:.4f} Fz {e['Fz']:.4f}; "
                  f"lambda Fy {lam['Fy']:.3g} Fz {lam['Fz']:.3g}; fit {res.report['fit_seconds']:.1f} s", flush=True)
            if order not in timing:
                t = Taylor(res.surrogate)
                timing[order] = time_calls(t.force, (ts[0, 0], ts[0, 1], ts[0, 2], ts[0, 3], omega), args.calls)

    print()
    mode = "all terms regressed" if args.no_anchor else "constant and order-1 terms anchored to Reynolds"
    print(f"Held-out NRMSE, max of (Fy, Fz), RMS error / std of truth; Reynolds grid {grid}; {mode}")
    print()
    print("| condition | domain | " + " | ".join(f"order {o}" for o in args.orders) + " |")
    print("|---|---|" + "---|" * len(args.orders))
    for name in args.conditions:
        load, hz, dom = CONDITIONS[name]
        row = " | ".join(f"{max(nrmse[name][o]) * 100:.2f} %" for o in args.orders)
        print(f"| {abs(load[1]):g} N, {hz:g} Hz | {describe(dom)} | {row} |")
    print()
    print("Time per force call (Python loop, one state)")
    print()
    print("| internal | terms | time per call [us] | speed-up vs Reynolds |")
    print("|---|---|---|---|")
    print(f"| Reynolds {grid} | - | {rey_time * 1e6:.1f} | 1 |")
    from bearing_fmu.surrogates.basis import n_terms

    for o in args.orders:
        print(f"| Taylor order {o} | {n_terms(o)} | {timing[o] * 1e6:.2f} | {rey_time / timing[o]:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
