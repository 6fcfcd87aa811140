"""Cost of the domain guard's nearest-neighbour distance per evaluation.

For the shipped 22 and 44 Hz surrogates, at the states of their held-out scene's Reynolds
orbit (heldout_22hz_6g, heldout_44hz_4g; series from rotor_host.analyses.training.scene_series,
cached in --cache-dir), in a plain Python loop as the FMU slave calls them:

* one cKDTree query of the stored training states (the exact distance);
* the guard's ``NearestTraining.distance(..., exact=False)`` along the orbit, in time order
  (successive states lie close together, so most calls skip the query: the share of calls
  that queried is printed) and shuffled (no locality: nearly every call queries);
* ``Taylor.force`` / ``force_and_jacobian`` alone, behind the guard with the stored states,
  and behind the guard with the file's bounds only (the file without its ``neighbours``).

    .venv/bin/python benchmarks/bench_guard.py --cache-dir ../cache-guard [--calls 20000]
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

CASES = (("paper_22hz_16.7N.json", "heldout_22hz_6g"), ("paper_44hz_16.7N.json", "heldout_44hz_4g"))


def per_call_us(fn, states, calls: int) -> float:
    """Mean time of fn(*state) over ``calls`` calls cycling through ``states`` [us]."""
    fn(*states[0])
    m = len(states)
    t0 = time.perf_counter()
    for i in range(calls):
        fn(*states[i % m])
    return 1e6 * (time.perf_counter() - t0) / calls


def orbit(scene_stem: str, cache_dir: Path) -> np.ndarray:
    from rotor_host.analyses.training import scene_series
    from rotor_host.scenes.scene import load_scene

    sc = load_scene(ROOT / "rotor_host" / "bundled" / "scenes" / f"{scene_stem}.toml")
    return scene_series(sc, 1, cache_dir / f"{scene_stem}_b1_series.npz")[1]


def main() -> None:
    import dataclasses

    from bearing_fmu.internals.taylor.guard import DomainGuard, NearestTraining
    from bearing_fmu.internals.taylor import Taylor
    from bearing_fmu.surrogates.surrogate import load_surrogate

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache-dir", type=Path, required=True, help="folder of the scenes' Reynolds series (reused)")
    ap.add_argument("--calls", type=int, default=20000)
    args = ap.parse_args()
    n = args.calls
    print(f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, {n} calls each [us]")
    print("| surrogate | stored states | cKDTree query | distance, orbit in time order (share queried) | "
          "distance, shuffled (share queried) | force | guard.force, bounds only | guard.force, with states | "
          "force_and_jacobian | guard.f_and_j, bounds only | guard.f_and_j, with states |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, scene in CASES:
        sur = load_surrogate(ROOT / "rotor_host" / "bundled" / "surrogates" / name)
        st = orbit(scene, args.cache_dir)
        st = st[np.array([Taylor(sur).domain_distance(*x) <= 0.0 for x in st])][:n]  # inside: no warning path
        om = sur.omega
        near = NearestTraining(sur, Taylor(sur))
        u = np.array([near.scaled(*x) for x in st])
        query = per_call_us(lambda *x: near._tree.query(x), u, n)
        q0 = near.queries
        fast = lambda *x: near.distance(*x, exact=False)  # noqa: E731 - the guard's call
        ordered = per_call_us(fast, st, n)
        share_o = (near.queries - q0) / (n + 1)
        shuffled = st[np.random.default_rng(0).permutation(len(st))]
        q0 = near.queries
        mixed = per_call_us(fast, shuffled, n)
        share_m = (near.queries - q0) / (n + 1)
        tay = Taylor(sur)
        old = DomainGuard(Taylor(dataclasses.replace(sur, neighbours=None)))
        new = DomainGuard(Taylor(sur))
        withom = [(*x, om) for x in st]
        t = {k: per_call_us(f, withom, n) for k, f in (
            ("force", tay.force), ("old", old.force), ("new", new.force),
            ("fj", tay.force_and_jacobian), ("old_fj", old.force_and_jacobian), ("new_fj", new.force_and_jacobian))}
        print(f"| {name} | {len(sur.neighbours.points)} | {query:.2f} | {ordered:.2f} ({share_o:.1%}) | "
              f"{mixed:.2f} ({share_m:.1%}) | {t['force']:.2f} | {t['old']:.2f} | {t['new']:.2f} | {t['fj']:.2f} | "
              f"{t['old_fj']:.2f} | {t['new_fj']:.2f} |")
        assert not math.isnan(t["new"])


if __name__ == "__main__":
    main()
