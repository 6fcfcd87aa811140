"""The Taylor surrogate's film fit for a grooved or partial-arc bore (bearing_fmu/surrogates/film.py
GroovedFilmFit, bearing_fmu/fitting/flows.py fit_grooved_film): the side flow J_s and every supply
edge's pressure part P_e of (eps, phi, beta), assembled as the grooved force map's
(physics/solver/film.py grooved_report), and the native Taylor FMU's refusal of such a fit by name.

Independent reference: the Reynolds solver's own film report (``Reynolds.film_report``: cell-face
fluxes of the converged field, validated against Raimondi & Boyd in tests/test_film.py) at held-out
random states, and the Reynolds effective temperature (``physics.thermal.effective_temperature``)
at the static equilibrium. The bearing: the paper's two-groove bore (rotor_host/bundled/bearing_paper_2groove.toml)
with the ISO VG 46 oil of rotor_host/bundled/bearing_paper_vg46.toml, fitted as tests/test_taylor_flows.py fits
the full bore (order 5, a disc of 0.3 CR about the equilibrium under 16.7 N, |v| <= 0.3 omega CR,
500 designed training states; docs/studies/2026-11-26-taylor-groove-flows.md).
"""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.cases import OMEGA_22HZ, surrogate_file
from bearing_fmu.internals.taylor import Taylor
from bearing_fmu.physics.solver.film import flow_scale, film_couette_integral
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.surrogates.film import GroovedFilmFit, n_features
from bearing_fmu.surrogates.surrogate import load_surrogate, save_surrogate
from test_taylor_flows import check_t_eff, held_out_errors_vs_reynolds

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
GROOVED = MODELS / "bearing_paper_2groove.toml"
T_SUPPLY = 313.15  # 40 C


def grooved_vg46(folder: Path) -> BearingParams:
    """The two-groove paper bearing with the VG 46 file's oil law (its [bearing] and [oil] tables, the
    two-groove file's [geometry])."""
    vg46 = (MODELS / "bearing_paper_vg46.toml").read_text()
    geometry = GROOVED.read_text()
    path = folder / "bearing_2groove_vg46.toml"
    path.write_text(vg46 + "\n" + geometry[geometry.index("[geometry]"):])
    return BearingParams.from_toml(path)


def made_up(tmp_path):
    """The contract's order-2 surrogate (made-up force) on the two-groove bore with a made-up grooved
    film fit: J_s = 0.2 + 0.1 eps, P_e = 0.05 e cos(beta) + 0.01 e sin(phi) (the file and the
    evaluation, not the accuracy)."""
    params = BearingParams.from_toml(GROOVED)
    sur = dataclasses.replace(load_surrogate(surrogate_file(tmp_path)), params=params)
    edges = params.geometry.supply_edges()
    nf = n_features(1, 1)  # eps^i (1, cos, sin)(beta), i = 0, 1: 6 per term of (1, cos phi, sin phi)
    coef = np.zeros((1 + len(edges), 3 * nf))
    coef[0, 0], coef[0, 3] = 0.2, 0.1
    for e in range(1, len(edges) + 1):
        coef[e, 1], coef[e, 2 * nf] = 0.05 * e, 0.01 * e
    sur.film = GroovedFilmFit(1, 1, 1, edges, coef, (), {"note": "made up"})
    return sur, save_surrogate(sur, tmp_path / "grooved_film.json")


def test_a_grooved_film_fit_round_trips_and_gives_the_grooved_report(tmp_path):
    """Against the grooved map's formulas by hand (docs/forcemap.md, "Grooved bores: the flows")."""
    sur, path = made_up(tmp_path)
    d = json.loads(path.read_text())
    assert d["version"] == 2 and d["film"]["kind"] == "grooved" and len(d["film"]["edges_deg"]) == 4
    t = Taylor.from_file(path)
    assert t.film_flow_why == "" and registry.film_flow_of(registry.get("taylor"), t) == ""
    np.testing.assert_array_equal(t.surrogate.film.coef, sur.film.coef)
    P, om = sur.params, OMEGA_22HZ
    st = (0.1 * P.CR, -0.45 * P.CR, 0.02 * om * P.CR, -0.01 * om * P.CR)
    rep = t.film_report(*st, om)
    e = math.hypot(st[0], st[1])
    vr, vt = (st[2] * st[0] + st[3] * st[1]) / e, (-st[2] * st[1] + st[3] * st[0]) / e
    eps, a, c, phi = e / P.CR, e / P.CR * om - 2 * vt / P.CR, 2 * vr / P.CR, math.atan2(st[1], st[0])
    r, q0 = math.hypot(a, c), flow_scale(P)
    assert rep.side_flow_m3_s == pytest.approx(r * q0 * (0.2 + 0.1 * eps), rel=1e-12)
    q_in = 0.0
    for k, (theta, sign) in enumerate(P.geometry.supply_edges(), start=1):
        h = P.CR + st[0] * math.sin(theta) - st[1] * math.cos(theta)
        q_in += max(sign * om * q0 * h / (2 * P.CR) - r * q0 * (0.05 * k * a / r + 0.01 * k * math.sin(phi)), 0.0)
    assert rep.inflow_m3_s == pytest.approx(q_in, rel=1e-12)
    F = t.force(*st, om)
    tc = P.mu * om * P.R ** 3 * P.L / P.CR * film_couette_integral(P.geometry, eps, phi)
    assert rep.couette_torque_Nm == pytest.approx(tc, rel=1e-12)
    assert rep.pressure_torque_Nm == pytest.approx(0.5 * (st[0] * F[1] - st[1] * F[0]), rel=1e-12)


@pytest.mark.parametrize("damage, expected", [
    (lambda f: f.update(edges_deg=f["edges_deg"][:3]), "key 'edges_deg' = .* must list the bearing's supply edges"),
    (lambda f: f.update(kind="arc"), "key 'kind' = 'arc' must be 'grooved'"),
    (lambda f: f.update(phi_harmonics=99), "phi_harmonics 99 <= 24"),
    (lambda f: f["coef"]["P_4"].pop(), "film: coef: key 'P_4' must be a list of 18 numbers"),
])
def test_a_damaged_grooved_film_fit_is_refused_by_key(tmp_path, damage, expected):
    _sur, path = made_up(tmp_path)
    d = json.loads(path.read_text())
    damage(d["film"])
    path.write_text(json.dumps(d))
    with pytest.raises(ValueError, match=expected):
        load_surrogate(path)


def test_a_film_fit_of_the_other_bore_is_refused(tmp_path):
    """A grooved fit on the full bore and the full bore's on a grooved bore: each names its bore."""
    sur, _path = made_up(tmp_path)
    full = load_surrogate(surrogate_file(tmp_path))
    with pytest.raises(ValueError, match="kind 'grooved' does not fit the bore"):
        dataclasses.replace(full, film=sur.film)
    d = json.loads(save_surrogate(sur, tmp_path / "g.json").read_text())
    d["film"].pop("kind")
    (tmp_path / "g.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match="a film fit of kind 'full' is for the full 360 deg bore"):
        load_surrogate(tmp_path / "g.json")


def test_a_grooved_bore_with_a_supply_pressure_gets_no_film_fit():
    """The grooved map's reason (groovemap.SUPPLY_WHY): the field is then not proportional to r."""
    from bearing_fmu.fitting.flows import fit_film
    from bearing_fmu.physics.solver.reynolds import Reynolds

    P = BearingParams.from_toml(GROOVED)
    fed = dataclasses.replace(P, geometry=dataclasses.replace(P.geometry, supply_pressure=1e5))
    with pytest.raises(ValueError, match="film fit: supply_pressure_kPa = 100: a supply pressure adds"):
        fit_film(Reynolds(fed, n_theta=32, n_x=4), np.zeros((1000, 4)), OMEGA_22HZ)


def test_the_native_taylor_fmu_refuses_thermal_for_a_grooved_film_fit(tmp_path):
    """c/taylor_film.c computes the full bore's report only: a grooved fit is not compiled in, thermal
    = true is refused before anything is compiled, naming why (fmu/native/generators/taylor.py native_film_why)."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.codegen import native_model

    _sur, path = made_up(tmp_path)
    with pytest.raises(ValueError, match=r"thermal = true needs the film's flows and the bearing's oil law: the "
                                         r"surrogate's film fit is a grooved or partial-arc bore's"):
        build_native_fmu(tmp_path / "x.fmu", "taylor", surrogate=path, compiler="cc", thermal=True)
    model = native_model("taylor", None, surrogate=path)
    assert "#define BN_FILM_FLOW 0" in model.config_h and "TAY_FILM_COEF" not in model.data_h
    thermal = next(v for v in model.variables if v.name == "thermal")
    assert "the native Taylor FMU does not compute" in thermal.description


# ----------------------------------------------------------------------------- fitted to Reynolds (slow)

def fit_grooved(params: BearingParams, hz: float, folder: Path):
    """(surrogate file, fit report) of ``params`` at ``hz`` under 16.7 N (the recipe of the module
    docstring)."""
    from bearing_fmu.fitting import FitRecipe, fit_condition

    res = fit_condition(FitRecipe(load_y=0.0, load_z=-16.7, speed_hz=hz, order=5, ecc_max=0.8, v_max=0.3,
                                  radius=0.3, n_train=500, n_test=200, prune=False),
                        params=params, bias_variance=False)
    return save_surrogate(res.surrogate, folder / f"grooved_{hz:g}hz.json"), res.report


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """(bearing, {speed_hz: surrogate file}) of the two-groove VG 46 bearing, fitted on first use."""
    folder, out = tmp_path_factory.mktemp("taylor_groove_flows"), {}
    params = grooved_vg46(folder)

    def get(hz: float) -> Path:
        if hz not in out:
            out[hz], report = fit_grooved(params, hz, folder)
            assert report["film"]["n_train"] == 500 and set(report["film"]) >= {"test_rel_median", "test_rel_max"}
        return out[hz]

    return params, get


@pytest.mark.slow
@pytest.mark.parametrize("hz", [22.0, 44.0])
def test_the_grooved_film_report_follows_reynolds_at_held_out_states(fitted, hz):
    """200 random states inside the fitted domain (uniform over the training discs, seed 2026, kept
    where the guard says inside), the guarded Taylor surrogate's film report against the Reynolds
    solver's on the same grid. Measured (relative errors; docs/studies/2026-11-26-taylor-groove-flows.md):

                          22 Hz                          44 Hz
                   median   p95      max        median   p95      max
    inflow         1.3e-3   9.3e-3   2.9e-2     1.7e-3   7.9e-3   1.7e-2
    side flow      5.7e-3   6.1e-2   1.4e-1     6.7e-3   5.3e-2   1.0e-1
    friction power 2.4e-4   1.4e-3   3.6e-3     1.8e-4   1.2e-3   2.8e-3   (the force's error)

    (basis: eps^0..2 x 7 terms in beta x 9 in phi, 189 features from 500 training states.)
    Bounds: about twice the worse speed's figures."""
    from bearing_fmu.internals.taylor.guard import DomainGuard

    params, get = fitted
    e = held_out_errors_vs_reynolds(params, DomainGuard(Taylor.from_file(get(hz)), "discard"), 200)
    bounds = {"median": (3.5e-3, 1.4e-2, 5e-4), "p95": (2e-2, 0.13, 3e-3), "max": (6e-2, 0.3, 8e-3)}
    for name, got in (("median", np.median(e, 0)), ("p95", np.percentile(e, 95, 0)), ("max", e.max(0))):
        assert np.all(got < bounds[name]), (name, got)


@pytest.mark.slow
def test_grooved_t_eff_from_taylor_equals_reynolds_at_two_speeds(fitted):
    """T_eff of the two-groove VG 46 bearing under 16.7 N, oil at 40 C, at 22 and 44 Hz: the Taylor
    surrogate fitted at each speed against the Reynolds solver (physics.thermal.effective_temperature,
    the surrogate at mu(T) by the exact scaling F ~ mu). Measured: T_eff 313.5073, 313.7893 K;
    Taylor - Reynolds +1.3e-4, -5.3e-4 K. Bound 2e-3 K: twice the root's tolerance (1e-3 K)."""
    params, get = fitted
    check_t_eff(params, get, (22.0, 44.0))
