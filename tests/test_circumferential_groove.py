"""A bore fed by a circumferential (360 deg) groove at mid-length (``[geometry] circumferential_groove_mm``
with ``supply_pressure_kPa``): the film in two lands of l' = (L - width) / 2, fed along the groove
(physics/solver/lands.py). Checked against what does not come from this solver:

* the closed-form flow of a circumferentially-grooved bearing (Shigley's Mechanical Engineering Design,
  "Pressure-fed bearings": the flow out of both lands Qs = pi p_s r c^3 (1 + 1.5 eps^2) / (3 mu l'), i.e.
  pi D c^3 p_s (1 + 1.5 eps^2) / (6 mu l')): exact for a journal that does not turn (the pressure is
  p_s (1 - x / l') at every theta, the axial flow h^3 p_s / (12 mu l') integrated round the bore);
* linearity where no cell cavitates: the supply part of the field is that linear profile, which carries
  no force, so the force does not depend on p_s and the side flow grows by exactly the formula's flow;
* the plain full-bore solver (the other kernel) on a bearing of length l': with the groove at ambient
  pressure each land is such a bearing (p = 0 at both of its ends, the same film), so the force is
  twice its force;
* the adjoint Jacobian against central differences, the mass balance of the lands, grid convergence.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.solver.lands import groove_inflow
from bearing_fmu.physics.params import BearingFileError, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

D, L, CR, MU, WIDTH = 0.040, 0.045, 42e-6, 0.02, 0.005  # l' = 20 mm, l'/D = 1/2
LAND = 0.5 * (L - WIDTH)
OMEGA = 2.0 * math.pi * 46.67


def grooved(ps: float = 200e3, width: float = WIDTH) -> BearingParams:
    return BearingParams(D=D, L=L, CR=CR, mu=MU, geometry=Geometry(circumferential_groove=width, supply_pressure=ps))


def shigley_flow(ps: float, eps: float) -> float:
    """Both lands' flow driven by the supply pressure (Shigley), [m^3/s]."""
    return math.pi * D * CR ** 3 * ps * (1.0 + 1.5 * eps * eps) / (6.0 * MU * LAND)


@pytest.mark.parametrize("eps", [0.0, 0.5, 0.8])
def test_still_journal_flow_is_the_closed_form(eps):
    r = Reynolds(grooved(), n_theta=32, n_x=8)
    rep = r.film_report(0.3 * eps * CR, -math.sqrt(0.91) * eps * CR, 0.0, 0.0, 0.0)
    q = shigley_flow(200e3, eps)
    assert rep.side_flow_m3_s == pytest.approx(q, rel=1e-12)
    assert rep.inflow_m3_s == pytest.approx(q, rel=1e-12)
    assert max(abs(f) for f in r.force(0.3 * eps * CR, -math.sqrt(0.91) * eps * CR, 0.0, 0.0, 0.0)) < 1e-9


def test_centred_turning_journal_flow_is_the_closed_form():
    rep = Reynolds(grooved(), n_theta=32, n_x=8).film_report(0.0, 0.0, 0.0, 0.0, OMEGA)
    assert rep.side_flow_m3_s == pytest.approx(shigley_flow(200e3, 0.0), rel=1e-12)


def test_no_cavitation_superposes_the_supply_profile():
    # p_s 2 and 3 MPa keep every cell pressurised at eps 0.2: the field is the hydrodynamic one plus
    # p_s (1 - x / l'), which has no force; the side flow grows by the closed form's flow
    y, z = 0.1 * CR, -math.sqrt(0.03) * CR
    r2, r3 = Reynolds(grooved(2e6), n_theta=64, n_x=16), Reynolds(grooved(3e6), n_theta=64, n_x=16)
    assert r2.diagnostics(y, z, 0.0, 0.0, OMEGA)["cavitated_fraction"] == 0.0
    assert r3.diagnostics(y, z, 0.0, 0.0, OMEGA)["cavitated_fraction"] == 0.0
    f2, f3 = np.array(r2.force(y, z, 0.0, 0.0, OMEGA)), np.array(r3.force(y, z, 0.0, 0.0, OMEGA))
    assert np.allclose(f2, f3, rtol=1e-9, atol=1e-9 * np.abs(f2).max())
    eps = math.hypot(y, z) / CR
    dq = r3.film_report(y, z, 0.0, 0.0, OMEGA).side_flow_m3_s - r2.film_report(y, z, 0.0, 0.0, OMEGA).side_flow_m3_s
    assert dq == pytest.approx(shigley_flow(1e6, eps), rel=1e-9)
    # mass balance of the lands: the flow across the groove's edges is the side flow (none cavitates)
    th, _x, field = r3.pressure(y, z, 0.0, 0.0, OMEGA)
    half = field[:, :8]
    q_edges = groove_inflow(grooved(3e6), y, z, half, LAND / 8, th, np.full(64, 2.0 * math.pi / 64))
    assert float(np.sum(q_edges)) == pytest.approx(r3.film_report(y, z, 0.0, 0.0, OMEGA).side_flow_m3_s, rel=1e-9)


@pytest.mark.parametrize("n_theta, n_x, tol", [(64, 8, 3e-3), (128, 16, 1e-3)])
def test_ambient_groove_is_two_bearings_of_the_land_length(n_theta, n_x, tol):
    # each land is a plain bearing of length l' (ambient at both ends): the full-bore kernel on L = l'
    y, z = 0.3 * CR, -0.6 * CR
    f = np.array(Reynolds(grooved(0.0), n_theta=n_theta, n_x=n_x).force(y, z, 0.0, 0.0, OMEGA))
    ref = np.array(Reynolds(BearingParams(D=D, L=LAND, CR=CR, mu=MU), n_theta=n_theta, n_x=n_x).force(y, z, 0.0, 0.0,
                                                                                                      OMEGA))
    assert np.abs(f - 2.0 * ref).max() < tol * np.abs(2.0 * ref).max()


def test_jacobian_against_central_differences():
    # steps small enough not to move the cavitated set (the discrete force is piecewise smooth)
    r = Reynolds(grooved(), n_theta=64, n_x=8)
    y, z, vy, vz = 0.3 * CR, -0.6 * CR, 0.001, 0.002
    _f, jq, jv = r.force_and_jacobian(y, z, vy, vz, OMEGA)
    h, hv = 1e-5 * CR, 1e-5
    for k in range(2):
        d = np.array([h, 0.0]) if k == 0 else np.array([0.0, h])
        fd = (np.array(r.force(y + d[0], z + d[1], vy, vz, OMEGA)) - np.array(r.force(y - d[0], z - d[1], vy, vz, OMEGA)))
        assert np.allclose(jq[:, k], fd / (2 * h), rtol=1e-5, atol=1e-5 * np.abs(jq).max())
        d = d / h * hv
        fd = (np.array(r.force(y, z, vy + d[0], vz + d[1], OMEGA)) - np.array(r.force(y, z, vy - d[0], vz - d[1], OMEGA)))
        assert np.allclose(jv[:, k], fd / (2 * hv), rtol=1e-6, atol=1e-6 * np.abs(jv).max())


def test_grid_convergence():
    # the force converges: each doubling of both grids at least nearly halves the change (the Swift-Stieber
    # boundary, where the film ruptures between cells, holds it near first order, as on the plain bore)
    y, z = 0.3 * CR, -0.6 * CR
    f = [np.array(Reynolds(grooved(), n_theta=n, n_x=m).force(y, z, 0.0, 0.0, OMEGA))
         for n, m in ((64, 8), (128, 16), (256, 32))]
    d1, d2 = np.linalg.norm(f[1] - f[0]), np.linalg.norm(f[2] - f[1])
    assert d2 < 0.6 * d1
    assert d2 < 2e-3 * np.linalg.norm(f[2])


def test_peak_pressure_at_least_the_supply():
    r = Reynolds(grooved(), n_theta=64, n_x=8)
    assert r.peak_pressure(0.0, 0.0, 0.0, 0.0, 0.0)[0] == 200e3
    pk, th = r.peak_pressure(0.3 * CR, -0.6 * CR, 0.0, 0.0, OMEGA)
    assert pk > r.pressure(0.3 * CR, -0.6 * CR, 0.0, 0.0, OMEGA)[2].max() > 200e3


@pytest.mark.parametrize("geometry, words", [
    ("circumferential_groove_mm = 45.0\nsupply_pressure_kPa = 100", "must be < L_mm = 45"),
    ("circumferential_groove_mm = -1.0", "circumferential_groove_mm"),
    ("circumferential_groove_mm = 5.0\nsupply_pressure_kPa = -100", "supply_pressure_kPa"),
    ("circumferential_groove_mm = 5.0\ngrooves_deg = [90, 270]", "leave out grooves_deg"),
    ("circumferential_groove_mm = 5.0\nlobes = 2\npreload = 0.5", "leave out grooves_deg"),
    ("circumferential_groove_mm = 5.0\nfeed = 'thickest'", "leave out grooves_deg"),
])
def test_refused_by_key(tmp_path, geometry, words):
    f = tmp_path / "b.toml"
    f.write_text(f"[bearing]\nD_mm = 40\nL_mm = 45\nCR_um = 42\nmu_Pa_s = 0.02\n\n[geometry]\n{geometry}\n")
    with pytest.raises(BearingFileError, match=words):
        BearingParams.from_toml(f)


def test_half_outflow_rise_refused(tmp_path):
    f = tmp_path / "b.toml"
    f.write_text("[bearing]\nD_mm = 40\nL_mm = 45\nCR_um = 42\n\n[geometry]\ncircumferential_groove_mm = 5\n"
                 "supply_pressure_kPa = 200\n\n[oil]\ngrade = 'SAE 30'\nsupply_C = 50\n")
    with pytest.raises(BearingFileError, match="outflow_rise = 'full'"):
        BearingParams.from_toml(f)


def test_too_few_axial_cells_refused():
    with pytest.raises(ValueError, match="n_x >= 4"):
        Reynolds(grooved(), n_theta=32, n_x=2)


def test_fmu_ports_carry_it():
    # the FMUs' parameters (tests/test_fmu_groove.py: the Python FMU computes it)
    from bearing_fmu.fmu.ports import port_defaults

    assert port_defaults(grooved())["circumferential_groove"] == WIDTH


def test_operating_point_heat_balance(tmp_path):
    # the worked case of docs/geometry.md: SAE 30 at 50 C, 675 N at 2800 rpm; the groove's oil all leaves by
    # the ends at the full rise, so the friction power is rho c_p Qs dT (Shigley's pressure-fed balance)
    from bearing_fmu.physics.operating import operating_point

    f = tmp_path / "cg.toml"
    f.write_text("[bearing]\nD_mm = 40\nL_mm = 45\nCR_um = 42\n\n[geometry]\ncircumferential_groove_mm = 5\n"
                 "supply_pressure_kPa = 200\n\n[oil]\ngrade = 'SAE 30'\nsupply_C = 50\noutflow_rise = 'full'\n")
    p = BearingParams.from_toml(f)
    rec = operating_point(p, (0.0, -675.0), 46.67)
    assert rec["inflow_m3_s"] == rec["side_flow_m3_s"]
    rho_c = p.oil.density * p.oil.heat_capacity
    assert rec["friction_power_W"] == pytest.approx(rho_c * rec["side_flow_m3_s"] * rec["temperature_rise_K"], rel=1e-6)
    assert rec["T_eff_K"] == pytest.approx(rec["T_supply_K"] + 0.5 * rec["temperature_rise_K"], abs=1e-3)  # the root's tolerance
    # Shigley's supply-pressure flow is a part of the side flow (the loaded film drives the rest)
    eps = rec["eccentricity"]
    assert rec["side_flow_m3_s"] > math.pi * D * CR ** 3 * 200e3 * (1 + 1.5 * eps ** 2) / (6 * rec["mu_eff_Pa_s"] * LAND)
    assert rec["peak_pressure_Pa"] > 200e3


@pytest.mark.parametrize("eps", [0.3, 0.6])
def test_short_lands_reach_the_ocvirk_limit(eps):
    # groove at ambient, Gumbel's condition: each land is a short bearing of length l'; Ocvirk's load
    # W = mu U l'^3 / (4 c^2) eps / (1 - eps^2)^2 sqrt(pi^2 (1 - eps^2) + 16 eps^2), attitude
    # atan(pi sqrt(1 - eps^2) / (4 eps)); the finite land's deficit is O((l'/D)^2): a quarter per halving
    d, c, omega = 0.1, 100e-6, 100.0
    err = []
    for ratio in (1 / 8, 1 / 16):
        land, w = ratio * d, 0.01
        p = BearingParams(D=d, L=2 * land + w, CR=c, mu=MU, geometry=Geometry(circumferential_groove=w))
        fy, fz = Reynolds(p, 128, 16, cavitation="gumbel").force(0.0, -eps * c, 0.0, 0.0, omega)
        ocvirk = (MU * omega * d / 2 * land ** 3 / (4 * c * c) * eps / (1 - eps ** 2) ** 2
                  * math.sqrt(math.pi ** 2 * (1 - eps ** 2) + 16 * eps ** 2))
        err.append(math.hypot(fy, fz) / (2 * ocvirk) - 1)
        attitude = math.degrees(math.atan2(abs(fy), abs(fz)))
        assert attitude == pytest.approx(math.degrees(math.atan(math.pi * math.sqrt(1 - eps ** 2) / (4 * eps))), abs=0.6)
    assert -0.01 < err[1] < 0.0
    assert 3.0 < err[0] / err[1] < 4.5


def test_the_compiled_route_takes_the_groove_pressure():
    # the host's compiled loop calls the solver's kernel through internals.reynolds.force, which hands
    # it the lands' supply pressure: the same force and Jacobian as the Python driver, to the bit
    from bearing_fmu.internals.compiled import evaluate

    p, om = grooved(), 2 * math.pi * 2800 / 60
    py, compiled = Reynolds(p), Reynolds(p)
    cf = compiled.compiled_force()
    for st in ((5e-6, -15e-6, 1e-4, -2e-4), (-8e-6, -25e-6, 0.0, 0.0)):
        F, dq, dv = py.force_and_jacobian(*st, om)
        status, Fc, dqc, dvc = evaluate(cf, *st, om)
        assert status == 0
        assert np.array_equal(Fc, F) and np.array_equal(dqc, dq) and np.array_equal(dvc, dv)
