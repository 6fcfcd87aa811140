"""The unbalance response of ``rotor-host response`` against ROSS 3.1's ``run_unbalance_response``
with the same rotor and the same bearing coefficients (docs/response.md, Validation).

ROSS (github.com/petrobras/ross, PyPI ross-rotordynamics 3.1.0) is not a dependency of this
project (it needs Python >= 3.13); run this in its own environment, e.g.

    python3.13 -m venv /tmp/ross && /tmp/ross/bin/pip install ross-rotordynamics==3.1.0
    rotor-host response rotor_host/bundled/rotor_paper.toml --speeds-hz 10:40:0.5 --unbalance 6:1:40 \\
        --internal map --out out/resp
    /tmp/ross/bin/python benchmarks/ross_response_crosscheck.py out/resp/response.json > rows.json

from the folder the response ran in (the response.json names its rotor file as given). ROSS's
thermodynamics package may print a banner about REFPROP on stdout first; the JSON follows it.
About 3 minutes on 2 cores for the paper rotor.

It reads the response.json (its rotor file, unbalances, speeds, the bearings' K and C at every
speed and the peaks) and builds the same rotor in ROSS: Timoshenko shaft elements with the
Hutchinson shear coefficient (as rotor_host.model.fe), shear, rotary inertia and gyroscopics,
stiffness-proportional damping beta (ROSS's ShaftElement beta), the disks from their geometry,
each bearing a BearingElement with the eight coefficients tabulated at the speeds (ROSS
interpolates them between the speeds by pchip). Axes: this project's (y horizontal, z vertical,
x along the shaft) are ROSS's (x, y, z), both right-handed with the spin about the shaft axis,
so K_yy -> kxx, K_yz -> kxy, K_zy -> kyx, K_zz -> kyy. ROSS's unbalance force is this
project's: (m e w^2 e^{i p}, -i m e w^2 e^{i p}) on (x, y).

It prints one JSON document: the amplitudes at every speed of the grid at the probe nodes
compared (there the coefficients are the same numbers), and each peak of the response.json
against ROSS's maximum on a fine grid (801 speeds over +/- 2 % of the peak; ROSS's
coefficients there interpolated, ours solved at the refined speed).
"""

from __future__ import annotations

import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
import ross as rs


def ross_rotor(resp: dict):
    path = Path(resp["rotor_file"])
    data = tomllib.loads(path.read_text())
    m = data["material"]
    mat = rs.Material("rotor_material", rho=m["density_kg_m3"], E=m["E_GPa"] * 1e9, Poisson=m["poisson"])
    beta = m.get("damping_beta_s", 0.0)
    shaft = [rs.ShaftElement(L=e["length_mm"] / 1e3, idl=e.get("id_mm", 0.0) / 1e3, odl=e["od_mm"] / 1e3, material=mat,
                             n=i, shear_effects=True, rotary_inertia=True, gyroscopic=True,
                             shear_method_calc="hutchinson", beta=beta)
             for i, e in enumerate(data["elements"])]
    disks = [rs.DiskElement.from_geometry(n=d["node"] - 1, material=mat, width=d["width_mm"] / 1e3,
                                          i_d=d.get("id_mm", 0.0) / 1e3, o_d=d["od_mm"] / 1e3)
             for d in data.get("disks", [])]
    ok = [i for i, k in enumerate(resp["bearings"]["K_N_m"]) if k is not None]
    w = 2 * math.pi * np.array(resp["speeds_hz"])[ok]
    K = np.array([resp["bearings"]["K_N_m"][i] for i in ok])
    C = np.array([resp["bearings"]["C_N_s_m"][i] for i in ok])
    bearings = [rs.BearingElement(n=node - 1, kxx=K[:, b, 0, 0], kxy=K[:, b, 0, 1], kyx=K[:, b, 1, 0],
                                  kyy=K[:, b, 1, 1], cxx=C[:, b, 0, 0], cxy=C[:, b, 0, 1], cyx=C[:, b, 1, 0],
                                  cyy=C[:, b, 1, 1], frequency=w)
                for b, node in enumerate(resp["bearings"]["nodes"])]
    return rs.Rotor(shaft, disks, bearings), ok


def unbalance(rotor, resp, speeds_hz):
    u = resp["unbalances"]
    return rotor.run_unbalance_response([x["node"] - 1 for x in u],
                                        [x["mass_g"] * 1e-3 * x["radius_mm"] * 1e-3 for x in u],
                                        [math.radians(x["phase_deg"]) for x in u],
                                        speed_range=2 * math.pi * np.asarray(speeds_hz)).forced_resp


def main(path: str) -> dict:
    resp = json.loads(Path(path).read_text())
    rotor, ok = ross_rotor(resp)
    ndof = rotor.number_dof
    s = np.array(resp["speeds_hz"])[ok]
    X = unbalance(rotor, resp, s)
    grid = []
    for node in resp["probes"]:
        for d, k in (("y", 0), ("z", 1)):
            ours = np.array([resp["nodes"][str(node)][f"{d}_amplitude_m"][i] for i in ok])
            theirs = np.abs(X[ndof * (node - 1) + k])
            ph_ours = np.array([resp["nodes"][str(node)][f"{d}_phase_deg"][i] for i in ok])
            ph_theirs = np.degrees(np.angle(X[ndof * (node - 1) + k]))
            dph = (ph_ours - ph_theirs + 180.0) % 360.0 - 180.0
            grid.append({"node": node, "direction": d, "max_rel_amplitude_diff": float(np.max(np.abs(theirs / ours - 1))),
                         "max_phase_diff_deg": float(np.max(np.abs(dph)))})
    peaks = []
    for p in resp["peaks"]:
        fine = np.linspace(0.98 * p["speed_hz"], 1.02 * p["speed_hz"], 801)
        a = np.abs(unbalance(rotor, resp, fine)[ndof * (p["node"] - 1) + (0 if p["direction"] == "y" else 1)])
        j = int(np.argmax(a))
        peaks.append({"node": p["node"], "direction": p["direction"], "speed_hz": p["speed_hz"],
                      "ross_speed_hz": float(fine[j]), "speed_diff_pct": 100 * (fine[j] / p["speed_hz"] - 1),
                      "amplitude_m": p["amplitude_m"], "ross_amplitude_m": float(a[j]),
                      "amplitude_diff_pct": 100 * (a[j] / p["amplitude_m"] - 1)})
    return {"response_json": path, "ross": rs.__version__, "grid": grid, "peaks": peaks}


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), indent=1))
