"""Time per call of every shipped surrogate file next to Reynolds, side by side in one run.

For each file in rotor_host/bundled/surrogates (and any extra files given) it times ``force`` and
``force_and_jacobian`` of the Taylor internal in a plain Python loop (as the FMU slave calls
it) at states of that file's own fitted domain, and Reynolds at its default grid at the same
states, then prints one markdown table with the ratios.

    .venv/bin/python benchmarks/bench_surrogates.py [--calls 20000] [extra.json ...]
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bearing_fmu.internals.taylor import Taylor  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds  # noqa: E402
from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402


def states_in_domain(sur, n: int, seed: int = 0) -> np.ndarray:
    """n states of the fitted domain (its position disc within its eccentricity bound, a
    quarter of its velocity disc), so each call does the work of a typical state."""
    rng = np.random.default_rng(seed)
    d = sur.domain
    tay = Taylor(sur)
    out = []
    while len(out) < n:
        a, b = rng.uniform(0, 2 * math.pi, 2)
        r, v = d.pos_radius * math.sqrt(rng.uniform()), 0.25 * d.v_max * rng.uniform()
        y = sur.y0 + (d.pos_center[0] + r * math.cos(a)) * sur.pos_scale
        z = sur.z0 + (d.pos_center[1] + r * math.sin(a)) * sur.pos_scale
        x = (y, z, v * math.cos(b) * sur.vel_scale, v * math.sin(b) * sur.vel_scale)
        if tay.bounds_distance(*x) <= 1e-12:  # the bounds: off the training orbits too, for a typical call's work
            out.append(x)
    return np.array(out)


def per_call_us(fn, states, omega, calls: int) -> float:
    fn(*states[0], omega)
    m = len(states)
    t0 = time.perf_counter()
    for i in range(calls):
        fn(*states[i % m], omega)
    return 1e6 * (time.perf_counter() - t0) / calls


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*", help="extra surrogate files")
    ap.add_argument("--calls", type=int, default=20000)
    args = ap.parse_args()
    files = sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("*.json")) + [Path(f) for f in args.files]
    print(f"# Surrogate call cost ({platform.processor() or platform.machine()}, Python {platform.python_version()}; "
          f"{args.calls} calls each, plain Python loop)\n")
    print("| file | model | Taylor force [us] | Taylor force + Jacobian [us] | Reynolds force + Jacobian [us] "
          "| ratio (with Jacobian) |")
    print("|---|---|---|---|---|---|")
    for f in files:
        sur = load_surrogate(f)
        tay = Taylor(sur)
        rey = Reynolds(sur.params)
        st = states_in_domain(sur, 64)
        t_f = per_call_us(tay.force, st, sur.omega, args.calls)
        t_j = per_call_us(tay.force_and_jacobian, st, sur.omega, args.calls)
        t_r = per_call_us(rey.force_and_jacobian, st, sur.omega, max(200, args.calls // 50))
        print(f"| {f.name} | {sur.recipe} | {t_f:.2f} | {t_j:.2f} | {t_r:.0f} | {t_r / t_j:.0f} |")


if __name__ == "__main__":
    main()
