"""The force map's flow tables against the Reynolds solver (docs/forcemap.md, "The flows" and
"Grooved bores: the flows"; docs/studies/2026-11-26-groove-flows.md for the grooved maps).

1. Random states (as forcemap_study.py draws them: eps up to 0.95, any attitude, speeds of both
   signs 0.2-3 x 22 Hz, velocities up to 1.5 omega CR): the map's film report against
   Reynolds.film_report on the map's own grid (128 x 16): median, p95, max relative error of the
   inflow and side flow (relative to max(|Q_rey|, 0.1 |omega| R L CR), as the force's error is
   relative to max(|F|, S |omega|)) and of the friction power.
2. The effective temperature at the static equilibrium under the bearing's load, supply 40 C:
   the Reynolds solver (physics.thermal.effective_temperature) against the same fixed point with the
   map's equilibrium and film report. The paper bearing with ISO VG 46 (bearing_paper_vg46.toml)
   and the Friswell bearing with SAE 30 (its file has no [oil]: added here); their two-groove
   versions (the 3-D maps) with the same oils.

    .venv/bin/python benchmarks/mapflow_validation.py [--states 300] [--maps paper,friswell,paper_2groove,...]
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bearing_fmu.internals.map.mapfile import load_any_map, map_internal  # noqa: E402
from bearing_fmu.physics.solver.film import flow_scale  # noqa: E402
from bearing_fmu.physics.params import BearingParams  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds  # noqa: E402
from bearing_fmu.physics.statics import equilibrium  # noqa: E402
from bearing_fmu.physics.thermal import KELVIN, effective_temperature, temperature_rise  # noqa: E402

MAPS = {"paper": ("bearing_paper_vg46.toml", "paper_bearing.json"),
        "friswell": ("bearing_friswell.toml", "friswell.json"),
        "paper_2groove": ("bearing_paper_2groove.toml", "paper_2groove.json"),
        "friswell_2groove": ("bearing_friswell_2groove.toml", "friswell_2groove.json")}
# the static loads of the rotors' bearings (rotor_host.scenes.run.bearing_loads): paper 16.66 N on each,
# Friswell 494 N and 556 N (the heavier); the two-groove rotors are the same machines
T_EFF = {"paper": ((22.0, 44.0, 100.0), (0.0, -16.66)), "friswell": ((20.0, 35.0, 60.0), (0.0, -556.37))}


def with_oil(name: str, prm: BearingParams) -> BearingParams:
    """The bearing with the oil of docs/thermal.md's examples: ISO VG 46 (bearing_paper_vg46.toml) on
    the paper bearings, SAE 30 on Friswell's (their files have no [oil])."""
    if prm.oil is not None:
        return prm
    if name.startswith("paper"):
        return dataclasses.replace(prm, oil=BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / MAPS["paper"][0]).oil)
    from bearing_fmu.physics.oil import Oil

    return dataclasses.replace(prm, oil=Oil.grade("SAE 30", name="SAE 30"))


def random_states(prm: BearingParams, n: int, rng):
    om0 = 2 * math.pi * 22.0
    for _ in range(n):
        eps, phi = rng.uniform(0.0, 0.95), rng.uniform(-math.pi, math.pi)
        om = om0 * rng.uniform(0.2, 3.0) * rng.choice([1.0, -1.0])
        v = rng.uniform(-1.5, 1.5, 2) * abs(om) * prm.CR / math.sqrt(2.0)
        yield eps * prm.CR * math.cos(phi), eps * prm.CR * math.sin(phi), v[0], v[1], om


def against_reynolds(prm, table, n, rng):
    m, rey = map_internal(prm, table), Reynolds(prm, table.n_theta, table.n_x, table.cavitation)
    err = {"inflow": [], "side flow": [], "friction power": []}
    for s in random_states(prm, n, rng):
        a, b = m.film_report(*s), rey.film_report(*s)
        floor = 0.1 * abs(s[4]) * flow_scale(prm)
        err["inflow"].append(abs(a.inflow_m3_s - b.inflow_m3_s) / max(b.inflow_m3_s, floor))
        err["side flow"].append(abs(a.side_flow_m3_s - b.side_flow_m3_s) / max(b.side_flow_m3_s, floor))
        err["friction power"].append(abs(a.friction_power_W - b.friction_power_W) / abs(b.friction_power_W))
    return {k: (np.median(e), np.percentile(e, 95), np.max(e)) for k, e in err.items()}


def map_effective_temperature(prm, table, load, omega, T_s):
    """T_eff [K], mu_eff of the map: the fixed point T = T_s + k dT(mu(T)) with the map's equilibrium."""
    oil, start = prm.oil, [None]

    def residual(T):
        m = map_internal(prm.with_viscosity(oil.mu(T)), table)
        y, z = equilibrium(m, load, omega, start=start[0])
        start[0] = (y, z)
        return T_s + oil.rise_factor * temperature_rise(m.film_report(y, z, 0.0, 0.0, omega), oil) - T

    hi = T_s + residual(T_s)
    T = brentq(residual, T_s, hi, xtol=1e-4) if hi > T_s + 1e-4 else T_s
    return T, oil.mu(T)


def main() -> None:
    n = int(sys.argv[sys.argv.index("--states") + 1]) if "--states" in sys.argv else 300
    names = sys.argv[sys.argv.index("--maps") + 1].split(",") if "--maps" in sys.argv else list(MAPS)
    rng = np.random.default_rng(2026)
    print(f"{'map':>16} | {'quantity':>14} | median | p95 | max   ({n} random states, Reynolds on the map's grid)")
    tables = {}
    for name in names:
        bfile, mfile = MAPS[name]
        prm = BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / bfile)
        table = tables[name] = load_any_map(ROOT / "rotor_host" / "bundled" / "maps" / mfile)
        t0 = time.perf_counter()
        for k, (med, p95, mx) in against_reynolds(prm, table, n, rng).items():
            print(f"{name:>16} | {k:>14} | {med:.2e} | {p95:.2e} | {mx:.2e}")
        print(f"{'':>16}   ({time.perf_counter() - t0:.1f} s)")
    print("\nT_eff at the static equilibrium, supply 40 C: Reynolds 128 x 16 | map | difference")
    for name in names:
        speeds, load = T_EFF[name.split("_")[0]]
        prm = with_oil(name, BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / MAPS[name][0]))
        for f in speeds:
            om = 2 * math.pi * f
            T_s = 40.0 + KELVIN
            st = effective_temperature(prm, load, om, T_s, n_theta=128, n_x=16)
            Tm, mum = map_effective_temperature(prm, tables[name], load, om, T_s)
            print(f"{name:>16} {f:5.0f} Hz, load {abs(load[1]):g} N ({prm.oil.name}): T_eff {st.T_eff_K - KELVIN:.4f} | "
                  f"{Tm - KELVIN:.4f} C ({Tm - st.T_eff_K:+.2e} K; dT {st.dT_K:.3f} K, rel {(Tm - st.T_eff_K) / st.dT_K / 0.5:+.1e}), "
                  f"mu_eff {st.mu_eff_Pa_s * 1e3:.5f} | {mum * 1e3:.5f} mPa s ({mum / st.mu_eff_Pa_s - 1:+.1e})")


if __name__ == "__main__":
    main()
