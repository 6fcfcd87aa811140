"""What the interruptible long call costs (bearing_fmu.physics.solver.reynolds, "Long calls").

A Reynolds call on a grid of n_theta (n_x / 2)^3 >= LONG_CALL_WORK runs its kernel in a worker
thread with the GIL released, so Ctrl-C is handled at once; smaller grids call the kernel
directly, as before, through two extra method calls. Measured side by side in one process, the
variants interleaved round by round (medians of the rounds), on a transient-like sequence of
states (the journal moving on a small orbit: warm starts, as in a run):

  1. the default grid 128 x 16: the driver as it is, the driver without the two extra calls
     (the code before the change), and the thread route forced (what it would cost there);
  2. 512 x 64 (the smallest default-aspect grid that takes the thread route): direct vs thread.

Every variant's forces and Jacobians are compared bit for bit. Also timed alone: the two calls
the direct route gained (``_wait``, ``_released``), a million times.

    .venv/bin/python benchmarks/bench_long_calls.py [--rounds 7]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import timeit
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.physics.params import PAPER_BEARING as P  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds, reynolds_kernel  # noqa: E402

OMEGA = 2 * math.pi * 22.0


def orbit(n: int) -> list[tuple]:
    """n states on a small orbit about eps = 0.5 (a transient's neighbouring calls)."""
    out = []
    for k in range(n):
        a = 2 * math.pi * k / n
        y, z = P.CR * (0.25 + 0.05 * math.cos(a)), -P.CR * (0.45 + 0.05 * math.sin(a))
        out.append((y, z, -0.05 * P.CR * OMEGA * math.sin(a), -0.05 * P.CR * OMEGA * math.cos(a), OMEGA))
    return out


def make(grid, variant):
    r = Reynolds(P, *grid)
    if variant == "before":  # the kernel called directly, without _wait and _released
        r._wait = lambda: None
        r._released = lambda kernel: kernel
    elif variant == "thread":
        r._long = True
    elif variant == "direct":
        r._long = False
    return r


def sweep(r, states):
    t0 = time.perf_counter()
    res = [r.force_and_jacobian(*s) for s in states]
    return (time.perf_counter() - t0) / len(states), res


def compare(grid, variants, n_states, rounds):
    states = orbit(n_states)
    solvers = {v: make(grid, v) for v in variants}
    for r in solvers.values():
        sweep(r, states)  # load the kernels, fill the warm start
    times = {v: [] for v in variants}
    results = {}
    for _ in range(rounds):
        for v, r in solvers.items():
            t, results[v] = sweep(r, states)
            times[v].append(t)
    ref = results[variants[0]]
    same = all(all(np.array_equal(a, b) for ra, rb in zip(ref, results[v]) for a, b in zip(ra, rb)) for v in variants)
    return {v: float(np.median(ts)) for v, ts in times.items()}, same


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    args = ap.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f}, {os.cpu_count()} cores\n")
    print("| grid | variant | per force_and_jacobian | vs first | bit for bit |")
    print("|---|---|---|---|---|")
    for grid, variants, n in (((128, 16), ("before", "now", "thread"), 200), ((512, 64), ("direct", "thread"), 20)):
        med, same = compare(grid, variants, n, args.rounds)
        base = med[variants[0]]
        for v in variants:
            print(f"| {grid[0]} x {grid[1]} | {v} | {med[v] * 1e3:.4f} ms | {med[v] / base:.3f} | {same} |")
    r, n = Reynolds(P), 1_000_000
    added = timeit.timeit(lambda: (r._wait(), r._released(reynolds_kernel)), number=n) / n
    print(f"\nthe direct route's two added calls alone: {added * 1e6:.3f} us a call")


if __name__ == "__main__":
    main()
