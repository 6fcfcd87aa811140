"""The effective temperature (physics/thermal.py): a published design example, Shigley's heat
balance, the converged fixed point, and the refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.oil import KELVIN, Oil
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.statics import equilibrium
from bearing_fmu.physics.thermal import ThermalError, effective_temperature, residence_time_s, temperature_rise

OMEGA_1440 = 2 * math.pi * 1440 / 60


def jindal_bearing():
    """U. C. Jindal, Machine Design (Pearson, 2010), example 17-4, p. 483 (as transcribed in FOSSEE's
    Python Textbook Companions, Machine_Design_by_U.C._Jindal/Ch17_2.ipynb): full journal bearing,
    l = d = 60 mm, radial clearance 0.06 mm, W = 3000 N, 1440 rev/min, mu = 30 cP; with Raimondi &
    Boyd's table (L/D = 1, interpolated between h0/c 0.6 and 0.4) it gives f = 0.00985,
    h0 = 0.032 mm, Q = 0.638 L/min, friction power 0.1337 kW and the temperature rise
    dT = 8.3 p (r/c) f / (Q / (r c N l)) = 8.3 C (p in MPa). Raimondi & Boyd's bearing is fed at the
    thickest film: a one-cell feed line there, placed at the equilibrium (two passes)."""
    params = BearingParams(D=0.06, L=0.06, CR=0.06e-3, mu=0.03)
    y, z = equilibrium(Reynolds(params), (0.0, -3000.0), OMEGA_1440)
    for _ in range(2):
        feed = Geometry(grooves=(math.atan2(y, -z),), groove_width=math.radians(360 / 128))
        params = BearingParams(D=0.06, L=0.06, CR=0.06e-3, mu=0.03, geometry=feed)
        rey = Reynolds(params)
        y, z = equilibrium(rey, (0.0, -3000.0), OMEGA_1440, start=(y, z))
    return params, rey, y, z


def test_jindal_example_17_4():
    """Friction coefficient, friction power, inflow and the temperature rise in Jindal's form within
    2 % of the book (computed 0.00989, 0.1342 kW, 0.631 L/min, 8.43 C), h0 within 4 % (0.0330 mm):
    the book interpolates the table linearly, a percent or two off the curve."""
    params, rey, y, z = jindal_bearing()
    rep = rey.film_report(y, z, 0.0, 0.0, OMEGA_1440)
    assert rep.friction_coefficient == pytest.approx(0.00985, rel=0.02)
    assert rep.friction_power_W == pytest.approx(133.7, rel=0.02)
    assert rep.inflow_m3_s * 60e3 == pytest.approx(0.638, rel=0.02)
    assert params.CR - math.hypot(y, z) == pytest.approx(0.032e-3, rel=0.04)
    p_mpa = 3000.0 / (0.06 * 0.06) / 1e6
    rcf = rep.friction_coefficient * params.R / params.CR
    qv = rep.inflow_m3_s / (params.R * params.CR * 24.0 * params.L)
    assert 8.3 * p_mpa * rcf / qv == pytest.approx(8.3, rel=0.02)
    # the same rise from the heat balance with all the inflow heated by dT (Jindal's form), with the
    # default oil (rho c_p = 4 pi / 8.3 K/MPa: Shigley's and Jindal's constant)
    oil = Oil.grade("ISO VG 32")
    assert 4 * math.pi / (oil.density * oil.heat_capacity) * 1e6 == pytest.approx(8.3, rel=2e-3)
    jindal = rep.friction_power_W / (oil.density * oil.heat_capacity * rep.inflow_m3_s)
    assert jindal == pytest.approx(8.3, rel=0.02)
    # Shigley's balance, which lets the side flow leave at half the rise, is higher by Q / (Q - Qs/2)
    q, qs = rep.inflow_m3_s, rep.side_flow_m3_s
    assert temperature_rise(rep, oil) == pytest.approx(jindal * q / (q - qs / 2), rel=1e-12)


def test_shigley_si_equation():
    """temperature_rise is Shigley's SI equation dT = 8.30 P (r/c) f / [(1 - Qs / 2Q) Q / (r c N l)]
    (P = W / (l d) in MPa) written with the film's own numbers, to the 8.30's rounding."""
    oil = Oil.grade("ISO VG 46")
    rey = Reynolds(PAPER_BEARING)
    om = 2 * math.pi * 40
    y, z = equilibrium(rey, (0.0, -30.0), om)
    rep = rey.film_report(y, z, 0.0, 0.0, om)
    prm = PAPER_BEARING
    P = 30.0 / (prm.L * prm.D) / 1e6
    rcf = rep.friction_coefficient * prm.R / prm.CR
    qv = rep.inflow_m3_s / (prm.R * prm.CR * (om / (2 * math.pi)) * prm.L)
    shigley = 8.30 * P * rcf / ((1 - 0.5 * rep.side_flow_m3_s / rep.inflow_m3_s) * qv)
    assert temperature_rise(rep, oil) == pytest.approx(shigley, rel=2e-3)


def _oiled(grade="SAE 30", supply_C=40.0):
    oil = Oil.grade(grade, T_supply=supply_C + KELVIN)
    return BearingParams(D=0.031, L=0.02, CR=90e-6, mu=oil.mu(oil.T_supply), oil=oil)


def test_effective_temperature_is_the_fixed_point():
    """T_eff = T_supply + k dT(mu(T_eff)) to the tolerance, the journal in equilibrium at mu_eff,
    mu_eff = mu(T_eff); hotter and thinner at a higher speed (paper bearing, SAE 30)."""
    prm = _oiled()
    load = (0.0, -16.7)
    states = []
    for hz in (22.0, 50.0, 100.0):
        om = 2 * math.pi * hz
        st = effective_temperature(prm, load, om, tol_K=1e-6)
        assert st.mu_eff_Pa_s == pytest.approx(prm.oil.mu(st.T_eff_K), rel=1e-12)
        again = effective_temperature(prm.with_viscosity(st.mu_eff_Pa_s), load, om)  # same oil, same root
        assert again.T_eff_K == pytest.approx(st.T_eff_K, abs=1e-3)
        rey = Reynolds(prm.with_viscosity(st.mu_eff_Pa_s))
        F = rey.force(st.y_m, st.z_m, 0.0, 0.0, om)
        assert np.allclose(F, [0.0, 16.7], atol=1e-6)
        assert st.T_supply_K + 0.5 * temperature_rise(rey.film_report(st.y_m, st.z_m, 0.0, 0.0, om), prm.oil) \
            == pytest.approx(st.T_eff_K, abs=1e-5)
        assert st.evaluations <= 8
        states.append(st)
    assert states[0].T_eff_K < states[1].T_eff_K < states[2].T_eff_K
    assert states[2].T_eff_K - KELVIN == pytest.approx(45.15, abs=0.05)  # recorded in docs/thermal.md
    assert residence_time_s(prm, states[1].report) == pytest.approx(0.0377, rel=0.02)


def test_a_film_hotter_than_the_range_is_refused():
    """The SAE 30 law used up to 42 C only, the film at 100 Hz would run at 45 C: refused, naming it."""
    oil = Oil.grade("SAE 30", T_supply=40 + KELVIN, T_max=42 + KELVIN)
    prm = BearingParams(D=0.031, L=0.02, CR=90e-6, mu=oil.mu(oil.T_supply), oil=oil)
    with pytest.raises(ThermalError, match=r"above the oil's range \(SAE 30: up to 42 C\): at 42 C the film would "
                                           r"still heat to 4[4-7].* C; widen \[oil\] range_C"):
        effective_temperature(prm, (0.0, -16.7), 2 * math.pi * 100.0)


@pytest.mark.parametrize("kw, match", [
    ({"params": PAPER_BEARING}, r"the bearing has no \[oil\] table"),
    ({"omega": 0.0}, r"omega = 0.0 rad/s: a film without rotation"),
    ({"T_supply_K": 500.0}, r"T_supply = 500 K \(226.85 C\) is outside the viscosity law's range"),
])
def test_refused_by_name(kw, match):
    args = {"params": _oiled(), "load": (0.0, -16.7), "omega": 2 * math.pi * 50.0}
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        effective_temperature(**args)


def test_no_equilibrium_is_named():
    """A load the thinned film cannot carry: the equilibrium's diagnosis, with the temperature."""
    with pytest.raises(ThermalError, match=r"at T = .* C \(mu = .* Pa s\): equilibrium: the bearing carries at most"):
        effective_temperature(_oiled(grade="ISO VG 32"), (0.0, -1e5), 2 * math.pi * 5.0)


# ------------------------------------------------------------------------- bearing-fmu demo


def test_demo_json_paper_bearing(capsys):
    """`bearing-fmu demo --json`: the record's friction and flows are the film report's at the printed
    equilibrium; no [oil]: T_eff None, mu_eff = mu, a rise with the default oil's rho c_p."""
    import json

    from bearing_fmu.cli import main

    assert main(["demo", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    for key in ("eccentricity", "attitude_deg", "h_min_m", "sommerfeld", "friction_coefficient", "friction_power_W",
                "inflow_m3_s", "side_flow_m3_s", "T_eff_K", "mu_eff_Pa_s", "K_N_m", "C_N_s_m", "K_dimensionless",
                "C_dimensionless"):
        assert key in rec, key
    assert rec["T_eff_K"] is None and rec["mu_eff_Pa_s"] == PAPER_BEARING.mu
    assert rec["sommerfeld"] == pytest.approx(1.2113, abs=1e-4)
    om = 2 * math.pi * 22.0
    rep = Reynolds(PAPER_BEARING).film_report(rec["y0_m"], rec["z0_m"], 0.0, 0.0, om)
    assert rec["friction_power_W"] == rep.friction_power_W and rec["side_flow_m3_s"] == rep.side_flow_m3_s
    assert np.allclose(np.array(rec["K_dimensionless"]), np.array(rec["K_N_m"]) * PAPER_BEARING.CR / 16.7)
    assert rec["temperature_rise_K"] > 0.0


def test_demo_with_oil_and_supply(tmp_path, capsys):
    """With [oil]: the point at mu_eff (T_eff from effective_temperature), the text lines name the law;
    --supply-c moves it; without [oil] --supply-c is refused by name."""
    import json

    from bearing_fmu.cli import main

    f = tmp_path / "b.toml"
    f.write_text('[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\n[oil]\ngrade = "SAE 30"\n')
    assert main(["demo", "--bearing", str(f), "--speed-hz", "50", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    st = effective_temperature(BearingParams.from_toml(f), (0.0, -16.7), 2 * math.pi * 50)
    assert rec["T_eff_K"] == pytest.approx(st.T_eff_K, abs=1e-6) and rec["mu_eff_Pa_s"] == st.mu_eff_Pa_s
    assert rec["T_eff_C"] == pytest.approx(42.93, abs=0.01)
    assert main(["demo", "--bearing", str(f), "--speed-hz", "50", "--supply-c", "60"]) == 0
    out = capsys.readouterr().out
    assert "thermal: SAE 30 (oil of b.toml): Vogel" in out and "supply 60 C" in out
    assert "friction: torque" in out and "oil flow: inflow Q" in out
    assert main(["demo", "--supply-c", "60"]) == 2
    assert "a supply temperature needs the bearing's [oil] table" in capsys.readouterr().err
