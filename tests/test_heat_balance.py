"""The [oil] table's heat-balance options (``outflow_rise``, ``ambient_W_K``, ``ambient_C``) in
``physics.thermal``: a textbook case, the balance itself, its limits, the two paths (static and at a
fixed state) agreeing, and the FMUs' parameters carrying every balance (the FMUs' own checks:
tests/test_fmu_heat_balance.py, tests/test_native_heat_balance.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from bearing_fmu.physics.oil import KELVIN, Oil
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.thermal import effective_temperature, film_temperature, temperature_rise

from test_thermal import OMEGA_1440, jindal_bearing


def test_full_outflow_rise_is_jindals_example():
    """outflow_rise = 'full' (all the inflow heated by the full rise: P = rho c_p Q dT) is the balance of
    Jindal's example 17-4 (Machine Design, 2010, p. 483; see tests/test_thermal.py): dT = 8.3 C in the
    book, within 2 % here; 'half' (Shigley's) is higher by Q / (Q - Qs / 2)."""
    params, rey, y, z = jindal_bearing()
    rep = rey.film_report(y, z, 0.0, 0.0, OMEGA_1440)
    full = Oil.grade("ISO VG 32", outflow_rise="full")
    assert temperature_rise(rep, full) == pytest.approx(8.3, rel=0.02)
    q, qs = rep.inflow_m3_s, rep.side_flow_m3_s
    assert temperature_rise(rep, replace(full, outflow_rise="half")) == pytest.approx(
        temperature_rise(rep, full) * q / (q - qs / 2), rel=1e-12)


def _bearing(**oil_kw) -> BearingParams:
    oil = Oil.grade("SAE 30", T_supply=40.0 + KELVIN, T_max=140.0 + KELVIN, **oil_kw)
    return BearingParams(D=0.031, L=0.02, CR=90e-6, mu=oil.mu(oil.T_supply), oil=oil)


@pytest.mark.parametrize("kw", [{}, {"outflow_rise": "full"}, {"ambient_W_K": 0.05},
                                {"ambient_W_K": 0.05, "T_ambient": 20.0 + KELVIN},
                                {"ambient_W_K": 5.0, "T_ambient": 20.0 + KELVIN, "rise_factor": 0.8}])
def test_the_balance_holds_at_the_effective_temperature(kw):
    """Energy conservation at the solved point: the film's friction power equals the heat the oil carries
    away, rho c_p (Q - s Qs) dT, plus what the housing loses, h A (T_eff - T_ambient), with T_eff =
    T_supply + k dT (to the root's tolerance); the fixed-state path (``film_temperature``, what a
    transient and the Python FMU use) finds the same temperature from the same film."""
    prm = _bearing(**kw)
    om = 2 * math.pi * 100.0
    st = effective_temperature(prm, (0.0, -16.7), om, tol_K=1e-8)
    oil, rep = prm.oil, st.report
    s = 0.5 if oil.outflow_rise == "half" else 0.0
    T_amb = oil.T_supply if oil.T_ambient is None else oil.T_ambient
    carried = oil.density * oil.heat_capacity * (rep.inflow_m3_s - s * rep.side_flow_m3_s) * st.dT_K
    lost = oil.ambient_W_K * (st.T_eff_K - T_amb)
    assert carried + lost == pytest.approx(rep.friction_power_W, rel=1e-9)
    assert st.T_eff_K == pytest.approx(oil.T_supply + oil.rise_factor * st.dT_K, abs=1e-7)
    at_ref = Reynolds(prm).film_report(st.y_m, st.z_m, 0.0, 0.0, om)  # the same film at the file's mu
    T, _mu, _tau = film_temperature(prm, at_ref, oil, oil.T_supply)
    assert T == pytest.approx(st.T_eff_K, abs=1e-6)


def test_limits_of_the_ambient_loss():
    """A housing that loses much (h A = 1 MW/K: P / h A is a few mK) holds the film at the ambient's temperature; with the
    ambient colder than the supply the film then runs below the supply; h A = 0 is the adiabatic case."""
    om = 2 * math.pi * 100.0
    adiabatic = effective_temperature(_bearing(), (0.0, -16.7), om)
    zero = effective_temperature(_bearing(ambient_W_K=0.0, T_ambient=0.0 + KELVIN), (0.0, -16.7), om)
    assert zero.T_eff_K == adiabatic.T_eff_K
    cold = effective_temperature(_bearing(ambient_W_K=1e6, T_ambient=30.0 + KELVIN), (0.0, -16.7), om, tol_K=1e-9)
    assert cold.T_eff_K - KELVIN == pytest.approx(30.0, abs=0.01)
    same = effective_temperature(_bearing(ambient_W_K=1e6), (0.0, -16.7), om, tol_K=1e-9)
    assert same.T_eff_K - KELVIN == pytest.approx(40.0, abs=1e-3)


def test_file_keys_and_fmu_parameters(tmp_path):
    """The keys read from a bearing file; the FMUs' parameters carry them (s = 0 for 'full', h A [W/K], the
    ambient [K])."""
    from bearing_fmu.fmu.ports import port_defaults

    (tmp_path / "b.toml").write_text("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\n[oil]\ngrade = \"SAE 30\"\n"
                                     "outflow_rise = \"full\"\nambient_W_K = 2.5\nambient_C = 25\n")
    prm = BearingParams.from_toml(tmp_path / "b.toml")
    assert (prm.oil.outflow_rise, prm.oil.ambient_W_K, prm.oil.T_ambient) == ("full", 2.5, 25.0 + KELVIN)
    got = port_defaults(prm)
    assert (got["oil_outflow_share"], got["oil_ambient_loss"], got["oil_T_ambient"]) == (0.0, 2.5, 25.0 + KELVIN)
    (tmp_path / "c.toml").write_text("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\n[oil]\ngrade = \"SAE 30\"\n"
                                     "outflow_rise = \"most\"\n")
    with pytest.raises(ValueError, match="outflow_rise"):
        BearingParams.from_toml(tmp_path / "c.toml")
