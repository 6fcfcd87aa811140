"""The validation tables of docs/thermal.md: friction and flow of the film against Raimondi & Boyd
(1958), the closed forms, the grid, Jindal's design example, and the effective temperature of the
paper bearing with three oils.

The published numbers and helpers are tests/test_film.py's and tests/test_thermal.py's (one source
for both). Prints markdown.

    .venv/bin/python benchmarks/thermal_validation.py
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from bearing_fmu.physics.oil import KELVIN, Oil  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds  # noqa: E402
from bearing_fmu.physics.thermal import effective_temperature, residence_time_s  # noqa: E402
from test_film import H0C, RB_FLOW_LD1, RB_RCF, RB_S, dimensionless_groups, rb_bearing  # noqa: E402
from test_thermal import OMEGA_1440, jindal_bearing  # noqa: E402


def raimondi_boyd() -> None:
    print("| L/D | h0/c | S pub | S | S feed | (r/c)f pub | (r/c)f | (r/c)f feed | Q/(rcNl) pub | Q/(rcNl) | "
          "Q/(rcNl) feed | Qs/Q | Qs/Q feed |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for ld in (1.0, 0.5, 0.25):
        plain, feed = rb_bearing(ld), rb_bearing(ld, feed_line=True)
        rp, rf = Reynolds(plain), Reynolds(feed)
        for h0c, s_ref, f_ref in zip(H0C, RB_S[ld], RB_RCF[ld]):
            a = dimensionless_groups(plain, rp, h0c)
            b = dimensionless_groups(feed, rf, h0c)
            q_ref = RB_FLOW_LD1.get(h0c) if ld == 1.0 else None
            print(f"| {ld:g} | {h0c:g} | {s_ref:g} | {a[0]:.4g} | {b[0]:.4g} | {f_ref:g} | {a[1]:.4g} | {b[1]:.4g} | "
                  f"{q_ref if q_ref else '-'} | {a[2]:.4g} | {b[2]:.4g} | {a[3]:.3f} | {b[3]:.3f} |")


def grid() -> None:
    om = 2 * math.pi * 50
    g = {f: Reynolds(PAPER_BEARING, 128 * f, 16 * f) for f in (1, 2, 4)}
    print("\n| eps | quantity | default | default vs 4x | 2x vs 4x |")
    print("|---:|---|---:|---:|---:|")
    for eps in (0.3, 0.6, 0.9):
        y, z = eps * PAPER_BEARING.CR * math.sin(0.4), -eps * PAPER_BEARING.CR * math.cos(0.4)
        r = {f: g[f].film_report(y, z, 0.0, 0.0, om) for f in g}
        for key in ("friction_torque_Nm", "inflow_m3_s", "side_flow_m3_s"):
            a, b, c = (getattr(r[f], key) for f in (1, 2, 4))
            print(f"| {eps:g} | {key} | {a:.5g} | {100 * (a / c - 1):+.3f} % | {100 * (b / c - 1):+.3f} % |")


def jindal() -> None:
    params, rey, y, z = jindal_bearing()
    rep = rey.film_report(y, z, 0.0, 0.0, OMEGA_1440)
    oil = Oil.grade("ISO VG 32")
    dT = rep.friction_power_W / (oil.density * oil.heat_capacity * rep.inflow_m3_s)
    print("\n| quantity | Jindal ex. 17-4 | computed |")
    print("|---|---:|---:|")
    for name, pub, val in (("friction coefficient", 0.00985, rep.friction_coefficient),
                           ("h0 [mm]", 0.032, (params.CR - math.hypot(y, z)) * 1e3),
                           ("Q [L/min]", 0.638, rep.inflow_m3_s * 6e4),
                           ("friction power [kW]", 0.1337, rep.friction_power_W / 1e3),
                           ("dT = P / (rho c_p Q) [K]", 8.3, dT)):
        print(f"| {name} | {pub:g} | {val:.4g} ({100 * (val / pub - 1):+.1f} %) |")


def paper_bearing() -> None:
    print("\n| oil | speed [Hz] | eps | P [W] | Q [L/min] | Qs/Q | dT [K] | T_eff [C] | mu 40 C -> mu_eff [mPa s] | "
          "t_res [ms] | film solutions |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for grade in ("ISO VG 32", "ISO VG 46", "SAE 30"):
        oil = Oil.grade(grade)
        prm = BearingParams(D=0.031, L=0.02, CR=90e-6, mu=oil.mu(oil.T_supply), oil=oil)
        for hz in (22.0, 50.0, 100.0):
            st = effective_temperature(prm, (0.0, -16.7), 2 * math.pi * hz)
            rep = st.report
            print(f"| {grade} | {hz:g} | {math.hypot(st.y_m, st.z_m) / prm.CR:.3f} | {rep.friction_power_W:.3g} | "
                  f"{rep.inflow_m3_s * 6e4:.3g} | {rep.side_flow_m3_s / rep.inflow_m3_s:.3f} | {st.dT_K:.3g} | "
                  f"{st.T_eff_K - KELVIN:.2f} | {prm.mu * 1e3:.4g} -> {st.mu_eff_Pa_s * 1e3:.4g} | "
                  f"{residence_time_s(prm, rep) * 1e3:.3g} | {st.evaluations} |")


if __name__ == "__main__":
    raimondi_boyd()
    grid()
    jindal()
    paper_bearing()
