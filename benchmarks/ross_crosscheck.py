"""The independent solution behind tests/test_geometry_validation.py's partial-arc and offset-halves
rows: the same bearings solved by ROSS (Rotordynamic Open Source Software, github.com/petrobras/ross,
PyPI ross-rotordynamics 3.1.0), a finite-element Reynolds solver written independently of this
project. No published table of these bearings was reachable (docs/studies/
2026-11-26-partial-arc-validation.md says where we looked), so this stands in for one.

ROSS is not a dependency of this project (it needs Python >= 3.13); run this in its own
environment, e.g.

    python3.13 -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    /tmp/ross/bin/python benchmarks/ross_crosscheck.py > rows.jsonl

Each line is one JSON row in Lund & Thomsen's frame and scaling (x along the downward load, y
horizontal, S = mu N L D (R / C_p)^2 / W, eps = e / C_p, K = k C_p / W, B = c C_p omega / W),
mapped from ROSS's frame as ROSS's own ross/tests/test_fluid_film_literature.py does (lt_frame).

Conventions that matter (read in ROSS 3.1.0's ross/bearings/fluid_film/driver.py and
_numba_kernels.py): ROSS angles alpha run from +x (our +y) toward +y (up), so alpha = theta - 270
deg with theta this project's film angle; the journal turns toward increasing alpha as it turns
toward increasing theta here. A pad's `pivot_angle` is its PRELOAD point, the pad spans
[pivot - offset * arc, pivot + (1 - offset) * arc], and its film is
h = C_p - x cos(alpha) - y sin(alpha) - m C_p cos(alpha - pivot). ROSS's OffsetHalvesBearing keeps
pivot_angle = 90 and 270 deg whatever the offset, so its offset moves the pads and their grooves
round the bore (offset 1.0 puts the grooves near the top and bottom): it is not the bore of
docs/geometry.md, whose grooves stay at the horizontal split. The offset-halves rows therefore use
FixedGeometryBearing with the pads of that bore: 160 deg pads between 20 deg grooves at the split,
preload 0.5, the preload point 10 deg before the trailing groove's centre (ROSS offset 1.0,
pivots 170 and 350 deg; here lobe_offset = 17/18) or at the groove's centre (ROSS offset 1.0625,
pivots 180 and 0 deg; here lobe_offset = 1.0).

Isoviscous (thermal_type=None), ambient pressure at the pad edges, cavitation pressure 0 (ROSS's
defaults). Grid: `total_ex_film` x `total_ez_film` elements per pad, 80 x 40 for the test's rows
(40 x 20 too, to show ROSS's own discretisation error).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np
from ross.bearings.fixed_geometry import EllipticalBearing, FixedGeometryBearing, PartialArcBearing
from ross.units import Q_

D, MU, RPM = 0.1, 0.02, 3000.0  # [m], [Pa s], [rev/min]: any bearing gives the same numbers
N_REV = RPM / 60.0
OMEGA = RPM * np.pi / 30.0

# the Sommerfeld numbers: this project's Raimondi & Boyd configuration at eps 0.2 .. 0.9
# (docs/geometry.md), and the lobed bores' loads
ARC_S = {(180.0, 1.0): [0.6695, 0.2777, 0.128, 0.04624, 0.01924],
         (180.0, 0.5): [2.055, 0.7935, 0.3213, 0.09203, 0.03133],
         (120.0, 1.0): [1.003, 0.3856, 0.1618, 0.053, 0.02082],
         (120.0, 0.5): [2.5, 0.9148, 0.3541, 0.09722, 0.03233]}
LOBED_S = [1.0, 0.3, 0.1, 0.03]
OFFSET_HALVES = {17 / 18: ([170.0, 350.0], 1.0), 1.0: ([180.0, 0.0], 1.0625)}  # ours: (pivots, ROSS offset)


def isoviscous(mu: float) -> dict:
    """Equal viscosities at both reference temperatures: ROSS's viscosity law is then constant."""
    return {"liquid_viscosity1": mu, "temperature1": 313.15, "liquid_viscosity2": mu, "temperature2": 373.15,
            "liquid_density": 860.0, "liquid_specific_heat": 1951.0, "liquid_thermal_conductivity": 0.13}


def lund_thomsen_frame(bearing, load: float, cp: float, L: float) -> dict:
    """eps, phi, K, B as Lund & Thomsen; the friction variable (R / C_p) f (f = friction force /
    load, the friction force = ROSS's power loss / (omega R)), the flow variable Q / (R C_p N L)
    (Q: ROSS's q_in, the oil entering the pads at their leading edges, summed) and the side flow
    ratio Q_s / Q, as Raimondi & Boyd define them."""
    out = bearing._results.outputs[0]
    R = D / 2
    q_in = float(np.sum(out["q_in"]))
    q_side = float(np.sum(out["q_sides"]))

    def dim(name):
        return float(getattr(bearing, name)[0])

    return {"friction_variable": R / cp * float(out["power_loss"][0]) / (OMEGA * R) / load,
            "flow_variable": q_in / (R * cp * N_REV * L), "side_flow_ratio": q_side / q_in,
            "eps": float(out["eccentricity"][0]) * bearing.radial_clearance / cp,
            "phi": float(np.degrees(out["attitude"][0])),
            "Kxx": dim("kyy") * cp / load, "Kxy": -dim("kyx") * cp / load,
            "Kyx": -dim("kxy") * cp / load, "Kyy": dim("kxx") * cp / load,
            "Bxx": dim("cyy") * cp * OMEGA / load, "Bxy": -dim("cyx") * cp * OMEGA / load,
            "Byx": -dim("cxy") * cp * OMEGA / load, "Byy": dim("cxx") * cp * OMEGA / load}


def solve(kind: str, l_over_d: float, S: float, nx: int, nz: int, arc=None, lobe_offset=None) -> dict:
    L = l_over_d * D
    cp = 100e-6 if kind == "arc" else 200e-6
    load = MU * N_REV * L * D * (D / 2 / cp) ** 2 / S
    common = dict(n=0, speed=Q_([RPM], "RPM"), journal_diameter=D, pad_thickness=0.02,
                  lubricant=isoviscous(MU), oil_supply_temperature=Q_(40.0, "degC"),
                  oil_flow_v=Q_(20.0, "l/min"), fys_load=-load, thermal_type=None,
                  total_ex_film=nx, total_ez_film=nz)
    t0 = time.time()
    if kind == "arc":  # one pad centred under the load (ROSS's default arc_center, 270 deg)
        b = PartialArcBearing(pad_arc=Q_(arc, "deg"), pad_axial_length=[L], radial_clearance=cp, **common)
    elif kind == "lemon":
        b = EllipticalBearing(pad_arc=Q_(160, "deg"), preload=0.5, pad_axial_length=[L, L],
                              radial_clearance=cp * 0.5, **common)
    else:
        pivots, offset = OFFSET_HALVES[lobe_offset]
        b = FixedGeometryBearing(pivot_angle=Q_(pivots, "deg"), pad_arc=Q_([160.0, 160.0], "deg"),
                                 preload=[0.5, 0.5], offset=[offset, offset], pad_axial_length=[L, L],
                                 radial_clearance=cp * 0.5, **common)
    row = lund_thomsen_frame(b, load, cp, L)
    row.update(kind=kind, l_over_d=l_over_d, S=S, nx=nx, nz=nz, arc=arc, lobe_offset=lobe_offset,
               seconds=round(time.time() - t0, 1))
    return row


def cases(grids=((80, 40), (40, 20))):
    """Every row at each grid (``--fine-only``: 80 x 40 alone)."""
    for nx, nz in grids:
        for (arc, ld), values in ARC_S.items():
            for S in values:
                yield dict(kind="arc", l_over_d=ld, S=S, nx=nx, nz=nz, arc=arc)
        for S in LOBED_S:
            yield dict(kind="lemon", l_over_d=1.0, S=S, nx=nx, nz=nz)
            for off in OFFSET_HALVES:
                yield dict(kind="offset halves", l_over_d=1.0, S=S, nx=nx, nz=nz, lobe_offset=off)


if __name__ == "__main__":
    for case in cases(((80, 40),) if "--fine-only" in sys.argv else ((80, 40), (40, 20))):
        print(json.dumps(solve(**case)), flush=True)
    sys.exit(0)
