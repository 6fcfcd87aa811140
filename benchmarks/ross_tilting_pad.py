"""The independent solution behind tests/test_tilting_pad_validation.py's ROSS rows: tilting-pad
bearings of 4 and 5 pads, load on and between pads, solved by ROSS 3.1's TiltingPad (PyPI
ross-rotordynamics 3.1.0: a finite-element Reynolds solver written independently of this project,
pads in moment equilibrium, the pad degrees of freedom condensed at the synchronous frequency).

ROSS needs Python >= 3.13 and is not a dependency of this project; run this in its own environment:

    python3.13 -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    /tmp/ross/bin/python benchmarks/ross_tilting_pad.py > rows.jsonl

Frames (read in ROSS 3.1.0's ross/bearings/fluid_film): ROSS's x is this project's y (horizontal),
its y this project's z (up); its angles alpha run from +x toward +y, so alpha = theta - 270 deg
with theta this project's film angle (docs/geometry.md), and the journal turns toward increasing
alpha as it turns toward increasing theta here. A pad spans [pivot - offset arc, pivot + (1 -
offset) arc] in both, with its preload point at the pivot. So the pivots below are given in theta
and passed to ROSS as theta - 270 deg. Each row is in this project's frame and scaling:
eps = e / C_bearing, y/C, z/C of the journal, K = k C / W, C = c C omega / W (y, z axes), the
pads' tilt angles as ROSS reports them, and the grid. Isoviscous (thermal_type=None), ambient
pressure at the pad edges, cavitation at 0 (ROSS's defaults).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np
from ross.bearings.tilting_pad import TiltingPad
from ross.units import Q_

D, L, CB, MU, RPM = 0.1, 0.05, 75e-6, 0.02, 3000.0  # [m], [m], [m], [Pa s], [rev/min]
OMEGA = RPM * np.pi / 30.0

# name: (pivots in theta [deg], pad arc [deg], offset, preload, loads [N])
CASES = {
    "4-pad LBP": ([45.0, 135.0, 225.0, 315.0], 80.0, 0.5, 0.5, [2000.0, 8000.0]),
    "4-pad LOP": ([0.0, 90.0, 180.0, 270.0], 80.0, 0.5, 0.5, [2000.0, 8000.0]),
    "5-pad LBP": ([0.0, 72.0, 144.0, 216.0, 288.0], 60.0, 0.5, 0.3, [2000.0, 8000.0]),
    "5-pad LOP": ([36.0, 108.0, 180.0, 252.0, 324.0], 60.0, 0.5, 0.3, [2000.0, 8000.0]),
    "5-pad LBP offset 0.6": ([0.0, 72.0, 144.0, 216.0, 288.0], 60.0, 0.6, 0.3, [4000.0]),
}


def isoviscous(mu: float) -> dict:
    """Equal viscosities at both reference temperatures: ROSS's viscosity law is then constant."""
    return {"liquid_viscosity1": mu, "temperature1": 313.15, "liquid_viscosity2": mu, "temperature2": 373.15,
            "liquid_density": 860.0, "liquid_specific_heat": 1951.0, "liquid_thermal_conductivity": 0.13}


def solve(name: str, load: float, nx: int, nz: int) -> dict:
    pivots, arc, offset, preload, _loads = CASES[name]
    n = len(pivots)
    t0 = time.time()
    b = TiltingPad(n=0, speed=Q_([RPM], "RPM"), equilibrium_type="match_load", thermal_type=None,
                   journal_diameter=D, radial_clearance=CB, pad_thickness=0.02,
                   pivot_angle=Q_([(p - 270.0) % 360.0 for p in pivots], "deg"), pad_arc=Q_([arc] * n, "deg"),
                   pad_axial_length=[L] * n, preload=[preload] * n, offset=[offset] * n,
                   lubricant=isoviscous(MU), oil_supply_temperature=Q_(40.0, "degC"), oil_flow_v=Q_(20.0, "l/min"),
                   fxs_load=0.0, fys_load=-load, total_ex_film=nx, total_ez_film=nz)
    out = b._results.outputs[0]
    s, sc = CB / load, CB * OMEGA / load
    k = {a: float(getattr(b, a)[0]) for a in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}
    return {"case": name, "load_N": load, "nx": nx, "nz": nz, "eps": float(out["eccentricity"][0]),
            "attitude_rad_ross": float(out["attitude"][0]),
            "tilt_angle": np.asarray(out["tilt_angle"], float).ravel().tolist(),
            "K": [[k["kxx"] * s, k["kxy"] * s], [k["kyx"] * s, k["kyy"] * s]],
            "C": [[k["cxx"] * sc, k["cxy"] * sc], [k["cyx"] * sc, k["cyy"] * sc]],
            "seconds": round(time.time() - t0, 1)}


if __name__ == "__main__":
    nx, nz = (int(v) for v in (sys.argv[1:3] if len(sys.argv) > 2 else (40, 20)))
    for name, (*_, loads) in CASES.items():
        for load in loads:
            print(json.dumps(solve(name, load, nx, nz)), flush=True)
    sys.exit(0)
