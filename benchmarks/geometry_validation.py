"""The validation tables of docs/geometry.md: the Reynolds solver on grooved, partial-arc and
lobed bores against Lund & Thomsen (1978), and what it computes where no table was reached.

Prints markdown: for every published row the computed eps, attitude and the 8 coefficients with
their errors; the partial arcs of Raimondi & Boyd's configuration (180 and 120 deg, centrally
loaded, L/D 1 and 0.5) with the default grid and its 2x refinement; the offset-halves and lemon
bores at a few loads; the cost of a force call per bore. The published rows and the helpers are
tests/test_geometry_validation.py's (one source for both).

    .venv/bin/python benchmarks/geometry_validation.py
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from bearing_fmu.physics.bore.geometry import Geometry  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds  # noqa: E402
from test_geometry_validation import (COEFFS, D90, D270, LT_ELLIPTICAL, LT_TWO_AXIAL_GROOVE,  # noqa: E402
                                      ROSS_KEYS, ROSS_LOBED, ROSS_PARTIAL_ARC, lund_thomsen_row, published,
                                      raimondi_boyd_case)


def lt_table(title, geo, l_over_d, cp, rows, grid=(None, None)):
    print(f"\n### {title}\n")
    print("| S | eps pub / comp | phi [deg] pub / comp | " + " | ".join(COEFFS) + " | worst |")
    print("|---:|---|---|" + "---:|" * (len(COEFFS) + 1))
    worst_all = 0.0
    for row in rows:
        ref = published(row)
        got = lund_thomsen_row(geo, l_over_d, cp, ref["S"], *grid)
        errs = {n: 100 * (got[n] - ref[n]) / abs(ref[n]) for n in COEFFS}
        big = {n: e for n, e in errs.items() if abs(ref[n]) >= 0.5}  # relative errors of small terms mislead
        w = max(big, key=lambda n: abs(big[n]))
        worst_all = max(worst_all, abs(big[w]))
        cells = " | ".join(f"{got[n]:.3g} ({ref[n]:g})" for n in COEFFS)
        print(f"| {ref['S']:g} | {ref['eps']:.3f} / {got['eps']:.3f} | {ref['phi']:.2f} / {got['phi']:.2f} | "
              f"{cells} | {w} {big[w]:+.1f} % |")
    print(f"\nworst coefficient error (terms >= 0.5): {worst_all:.1f} %")


def partial_arcs():
    print("\n### Partial arcs, centrally loaded (Raimondi & Boyd's configuration): computed\n")
    print("| arc | L/D | eps | S (128 x 16) | S (256 x 32) | phi [deg] (128 x 16) | phi [deg] (256 x 32) |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for arc in (180.0, 120.0):
        for ld in (1.0, 0.5):
            for eps in (0.2, 0.4, 0.6, 0.8, 0.9):
                s1, p1 = raimondi_boyd_case(arc, ld, eps)
                s2, p2 = raimondi_boyd_case(arc, ld, eps, 256, 32)
                print(f"| {arc:g} | {ld:g} | {eps:g} | {s1:.4g} | {s2:.4g} | {p1:.2f} | {p2:.2f} |")


def lobed():
    print("\n### Lemon and offset-halves bores (preload 0.5, 20 deg grooves at the split, L/D = 1): computed\n")
    print("| bore | S (pad clearance) | eps (pad) | phi [deg] | Kxx | Kxy | Kyx | Kyy | Bxx | Bxy | Byy |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, off in (("lemon", 0.5), ("offset halves", 1.0)):
        geo = Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_offset=off)
        for S in (1.0, 0.3, 0.1, 0.03):
            g = lund_thomsen_row(geo, 1.0, 2e-4, S)
            print(f"| {name} | {S:g} | {g['eps']:.3f} | {g['phi']:.2f} | "
                  + " | ".join(f"{g[n]:.3g}" for n in COEFFS) + " |")


def against_ross():
    """The partial arcs and lobed bores against ROSS's rows (tests/test_geometry_validation.py; made
    by benchmarks/ross_crosscheck.py): computed on the default grid, ROSS in brackets."""
    print("\n### Partial arcs, centrally loaded, and lobed bores against ROSS 3.1.0 (in brackets), "
          "default grid\n")
    print("| bore | L/D | S | eps | phi [deg] | " + " | ".join(COEFFS) + " | worst |")
    print("|---|---:|---:|---|---|" + "---:|" * (len(COEFFS) + 1))
    rows = [(f"arc {a:g} deg", ld, S, Geometry(arc=(math.pi - math.radians(a) / 2, math.pi + math.radians(a) / 2)),
             1e-4, v) for a, ld, S, *v in ROSS_PARTIAL_ARC]
    rows += [("lemon" if off == 0.5 else f"offset halves, offset {off:.3g}", 1.0, S,
              Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_offset=off), 2e-4, v)
             for off, S, *v in ROSS_LOBED]
    flows = []
    for name, ld, S, geo, cp, values in rows:
        ref = dict(zip(ROSS_KEYS, values))
        got = lund_thomsen_row(geo, ld, cp, S)
        flows.append(f"| {name} | {ld:g} | {S:g} | {got['Q']:.4g} ({ref['Q']:.4g}) | {got['Qs_Q']:.4g} ({ref['Qs_Q']:.4g}) |")
        errs = {n: 100 * (got[n] - ref[n]) / abs(ref[n]) for n in COEFFS if abs(ref[n]) >= 0.5}
        w = max(errs, key=lambda n: abs(errs[n]))  # relative errors of small terms mislead
        cells = " | ".join(f"{got[n]:.3g} ({ref[n]:.4g})" for n in COEFFS)
        print(f"| {name} | {ld:g} | {S:g} | {got['eps']:.4f} ({ref['eps']:.4f}) | {got['phi']:.2f} ({ref['phi']:.2f}) | "
              f"{cells} | {w} {errs[w]:+.1f} % |")
    print("\nRaimondi & Boyd's flow variable Q / (R C_p N L) (Q: the oil entering the film) and side-flow "
          "ratio, ROSS in brackets:\n")
    print("| bore | L/D | S | Q / (R C_p N L) | Q_s / Q |")
    print("|---|---:|---:|---|---|")
    print("\n".join(flows))


def speed():
    print("\n### Cost of a force call, paper bearing, default grid 128 x 16 (median of 300, warm start)\n")
    print("| bore | eps 0.3 [ms] | eps 0.6 [ms] | eps 0.9 [ms] |")
    print("|---|---:|---:|---:|")
    P = PAPER_BEARING
    bores = {"full 360 deg": None, "two grooves": Geometry(grooves=(D90, D270)),
             "partial arc 180 deg": Geometry(arc=(D90, D270)),
             "lemon": Geometry(grooves=(D90, D270), lobes=2, preload=0.5),
             "offset halves": Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_offset=1.0),
             "three lobes": Geometry(lobes=3, preload=0.3)}
    for name, geo in bores.items():
        prm = P if geo is None else BearingParams(P.D, P.L, P.CR, P.mu, geometry=geo)
        r = Reynolds(prm)
        cells = []
        for eps in (0.3, 0.6, 0.9):
            s = (eps * P.CR * math.sin(math.pi + 0.4), -eps * P.CR * math.cos(math.pi + 0.4), 0.0, 0.0, 2 * math.pi * 50)
            r.force(*s)
            ts = []
            for _ in range(300):
                t0 = time.perf_counter()
                r.force(*s)
                ts.append(time.perf_counter() - t0)
            cells.append(f"{1e3 * np.median(ts):.3f}")
        print(f"| {name} | " + " | ".join(cells) + " |")


def main():
    g20 = Geometry(grooves=(D90, D270), groove_width=math.radians(20.0))
    for ld in (0.5, 1.0):
        lt_table(f"Lund & Thomsen (1978), two axial grooves, L/D = {ld:g}: published (in brackets) vs computed",
                 g20, ld, 1e-4, LT_TWO_AXIAL_GROOVE[ld])
    lt_table("Lund & Thomsen (1978), elliptical bore, preload 0.5, L/D = 1", Geometry(grooves=(D90, D270), lobes=2,
             preload=0.5), 1.0, 2e-4, LT_ELLIPTICAL)
    partial_arcs()
    lobed()
    against_ross()
    speed()


if __name__ == "__main__":
    main()
