"""A big rotor's modes per speed (rotor_host.model.band_modes): what each change cut.

The 2000-element shaft of benchmarks/bench_big_rotor.py (8004 DOFs, the paper bearing at both
ends, the map internal), its bearings linearised at each speed, then ``band_modes`` in the band a
stability sweep of 20-24 Hz ranks (2 x 24 = 48 Hz), variants side by side in one process, the
speeds interleaved round by round (medians):

  before      SuperLU's solve, OpenBLAS with its default threads (one per core), ARPACK asked
              for 16 eigenvalues first, doubled until one lies beyond the disk
  one thread  the same, ARPACK inside ``one_blas_thread``
  banded LU   and LAPACK's banded LU (zgbtrf / zgbtrs) instead of SuperLU
  now         and the first count from the undamped modes' inertia (``_undamped_count``)

and the largest relative difference of each variant's eigenvalues from the first's.

    python benchmarks/bench_band_modes.py [--elements 2000] [--rounds 3]
    python benchmarks/bench_band_modes.py --pads [--dense-elements 300]

``--pads``: the same shaft on the bundled five-pad bearings (bearing_paper_5pad_lbp.toml, the
tilting_pad internal), ``band_modes_with_pads`` against the dense ``pad_modes.modes`` side by side
on a shorter shaft (``--dense-elements``: the dense path grows as n^3), then the sparse path alone
at ``--elements``; the largest relative difference of the disk's eigenvalues.

Run without OPENBLAS_NUM_THREADS set (the tests set it to 1); say the machine's load.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_big_rotor import MODELS, shaft  # noqa: E402

from rotor_host.analyses.linear.stability import Stability  # noqa: E402
from rotor_host.model import band_modes as bm  # noqa: E402
from rotor_host.model.rotor import Rotor  # noqa: E402

SPEEDS_HZ = (20.0, 22.0, 24.0)
BAND_HZ = 48.0


def superlu(D, what):
    import scipy.sparse.linalg as sla

    return sla.splu(D.tocsc()).solve


def sixteen(M, K, sigma, radius):
    return None  # no count: FIRST_K


VARIANTS = {
    "before": {"_factorised": superlu, "one_blas_thread": contextlib.nullcontext, "_undamped_count": sixteen},
    "one thread": {"_factorised": superlu, "_undamped_count": sixteen},
    "banded LU": {"_undamped_count": sixteen},
    "now": {},
}


def pads(n_dense: int, n_sparse: int) -> None:
    from rotor_host.analyses.linear import pad_modes as pm

    print("\n| elements | DOFs | speed | sparse | dense | modes | max rel. diff. of lambda |\n|---|---|---|---|---|---|---|")
    for n_el in (n_dense, n_sparse):
        with tempfile.TemporaryDirectory() as tmp:
            path = shaft(Path(tmp), n_el)
            path.write_text(path.read_text().replace("bearing_paper.toml", "bearing_paper_5pad_lbp.toml"))
            rotor = Rotor.from_toml(path)
        st = Stability(rotor, "tilting_pad", {})
        for hz in SPEEDS_HZ:
            omega = 2 * math.pi * hz
            blocks = pm.pad_blocks(st.internals, st.pairs, st.equilibrium(omega), omega)
            t0 = time.perf_counter()
            fs, ls, _ = bm.band_modes_with_pads(rotor, omega, blocks, BAND_HZ)
            ts = time.perf_counter() - t0
            dense, diff = "-", "-"
            if n_el == n_dense:
                t0 = time.perf_counter()
                fd, ld, _ = pm.modes(rotor, omega, blocks)
                dense = f"{time.perf_counter() - t0:.2f} s"
                lam_d, lam_s = -ld * fd + 2j * math.pi * fd, -ls * fs + 2j * math.pi * fs
                wb = 2 * math.pi * BAND_HZ
                inside = np.abs(lam_d - 0.5j * wb) <= bm.DISK_RADIUS * wb
                diff = (f"{np.max(np.abs(lam_s - lam_d[inside]) / np.abs(lam_d[inside])):.1e}"
                        if inside.sum() == lam_s.size else "not the same modes")
            print(f"| {n_el} | {rotor.n_dof} | {hz:g} Hz | {ts:.2f} s | {dense} | {fs.size} | {diff} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--pads", action="store_true")
    ap.add_argument("--dense-elements", type=int, default=300)
    a = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}")
    if a.pads:
        pads(a.dense_elements, a.elements)
        return
    with tempfile.TemporaryDirectory() as tmp:
        rotor = Rotor.from_toml(shaft(Path(tmp), a.elements))
    st = Stability(rotor, "map", {"map": str(MODELS / "maps" / "paper_bearing.json")})
    lin = {}
    for hz in SPEEDS_HZ:
        omega = 2 * math.pi * hz
        lin[hz] = st.linearise(st.equilibrium(omega), omega)
    kept = {name: getattr(bm, name) for name in ("_factorised", "one_blas_thread", "_undamped_count")}
    times = {v: {hz: [] for hz in SPEEDS_HZ} for v in VARIANTS}
    lams = {}
    for _ in range(a.rounds):
        for hz in SPEEDS_HZ:
            for v, patch in VARIANTS.items():
                for name, f in {**kept, **patch}.items():
                    setattr(bm, name, f)
                t0 = time.perf_counter()
                f, ld, _ = bm.band_modes(rotor, 2 * math.pi * hz, *lin[hz], BAND_HZ)
                times[v][hz].append(time.perf_counter() - t0)
                lams[v, hz] = (-ld * f + 2j * math.pi * f)  # lambda / (2 pi) * 2 pi
    for name, f in kept.items():
        setattr(bm, name, f)
    print(f"\n{rotor.n_dof} DOFs, band {BAND_HZ:g} Hz, medians of {a.rounds} rounds\n")
    print("| variant | " + " | ".join(f"{hz:g} Hz" for hz in SPEEDS_HZ) + " | modes | max rel. diff. of lambda |")
    print("|---|" + "---|" * (len(SPEEDS_HZ) + 2))
    first = next(iter(VARIANTS))
    for v in VARIANTS:
        diff = max(float(np.max(np.abs(np.sort_complex(lams[v, hz]) - np.sort_complex(lams[first, hz]))
                                / np.abs(np.sort_complex(lams[first, hz])))) for hz in SPEEDS_HZ)
        cells = " | ".join(f"{np.median(times[v][hz]):.2f} s" for hz in SPEEDS_HZ)
        print(f"| {v} | {cells} | {lams[v, SPEEDS_HZ[0]].size} | {diff:.1e} |")


if __name__ == "__main__":
    main()
