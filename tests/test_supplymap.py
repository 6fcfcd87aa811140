"""The fed grooves' 4-D force map (bearing_fmu/internals/map/supplymap.py, docs/forcemap.md "Fed grooves").
Independent checks: the Reynolds solver's own joint homogeneity in (r, p_s) that makes the map exact;
the map against that solver at its table nodes (to round-off) and at states between them (the spline's
interpolation error); its u = 0 end against the ambient grooves' 3-D map, bit for bit; the analytic
Jacobian against central differences of the map's own force; the film report's flows against the
solver's; the build through ``bearing-fmu map`` (rows (eps, u), the map store, resumed)."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map.build import build_map
from bearing_fmu.internals.map.groovemap import tabulate_grooved
from bearing_fmu.internals.map.mapfile import load_any_map, open_map
from bearing_fmu.internals.map.store import map_key, settings_for, store_path
from bearing_fmu.internals.map.supplymap import (SupplyForceMap, SupplyMapTable, row_state, save_supply_map,
                                                 tabulate_supplied)
from bearing_fmu.internals.map.tables import state_for
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from conftest import run_cli

ROOT = Path(__file__).resolve().parents[1]
AMBIENT = BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / "bearing_paper_2groove.toml")
FED = dataclasses.replace(AMBIENT, geometry=dataclasses.replace(AMBIENT.geometry, supply_pressure=100e3))
COARSE = dict(n_theta=32, n_x=4)
TINY = dict(n_eps=6, n_phi=6, n_beta=8, n_sup=5, n_phase=1, **COARSE)
W22 = 2 * math.pi * 22


@pytest.fixture(scope="module")
def tiny():
    return tabulate_supplied(FED, **TINY)


def fed_toml(tmp_path, kpa=100.0) -> Path:
    text = (ROOT / "rotor_host" / "bundled" / "bearing_paper_2groove.toml").read_text()
    p = tmp_path / "fed.toml"
    p.write_text(text.replace("supply_pressure_kPa = 0.0", f"supply_pressure_kPa = {kpa}"))
    return p


def test_the_solver_is_jointly_homogeneous_in_motion_and_supply_pressure():
    """What makes the map exact: scaling the film source (the velocities and omega) and p_s by the
    same lambda scales the force by lambda, though it is not linear in either alone."""
    rey = Reynolds(FED, **COARSE)
    y, z, vy, vz = state_for(0.5, 0.7, FED, 0.3, W22, 0.4 * W22)
    F = np.array(rey.force(y, z, vy, vz, W22))
    for lam in (0.5, 3.0):
        fed = dataclasses.replace(FED, geometry=dataclasses.replace(FED.geometry, supply_pressure=lam * 100e3))
        F_lam = np.array(Reynolds(fed, **COARSE).force(y, z, lam * vy, lam * vz, lam * W22))
        np.testing.assert_allclose(F_lam, lam * F, rtol=1e-9, atol=1e-12 * np.abs(F).max())


def test_at_the_nodes_the_map_is_the_solver(tiny, tmp_path):
    path = save_supply_map(tiny, tmp_path / "fed.json")
    m = open_map(path, FED)  # through the file: 8 significant digits
    assert isinstance(m, SupplyForceMap) and json.loads(path.read_text())["version"] == 7
    rey = Reynolds(FED, **COARSE)
    rng = np.random.default_rng(3)
    for _ in range(12):
        i, j, k = rng.integers(1, tiny.n_eps - 1), rng.integers(tiny.n_phi), rng.integers(tiny.n_beta)
        l = rng.integers(1, tiny.n_sup)  # u = 0 is p_s / r -> 0: not a finite state of this bearing
        _, r, _ = row_state(FED, tiny.u[l])
        state = state_for(tiny.eps[i], tiny.beta[k], FED, tiny.phi[j], 1.0, r)
        Fr = np.array(rey.force(*state, 1.0))
        np.testing.assert_allclose(m.force(*state, 1.0), Fr, rtol=0, atol=1e-7 * np.abs(Fr).max())


def test_the_file_is_checked(tiny, tmp_path):
    data = json.loads(save_supply_map(tiny, tmp_path / "fed.json").read_text())
    assert data["n_sup"] == 5 and data["u_grading"] == 2.0 and data["supply_pressure_kPa"] == 100.0
    for change, words in (({"n_sup": 3}, "key 'n_sup' = 3 must be an integer >= 4"),
                          ({"u_grading": 9}, "key 'u_grading' = 9.0 must be a number in 1 .. 4"),
                          ({"supply_pressure_kPa": 0}, "key 'supply_pressure_kPa' = 0.0 must be > 0"),
                          ({"H": data["H"][:-1]}, "key 'H' has 2879 numbers, n_eps x n_phi x n_beta x n_sup x 2 = 2880"),
                          ({"extra": 1}, "unknown key.*extra")):
        p = tmp_path / "bad.json"
        p.write_text(json.dumps({**data, **change}))
        with pytest.raises(ValueError, match=f"force map file .*bad.json: .*{words}"):
            load_any_map(p)
    del data["u_grading"]
    (tmp_path / "bad.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match="missing key 'u_grading'"):
        load_any_map(tmp_path / "bad.json")


def test_the_u0_end_is_the_ambient_3d_map(tiny):
    t3 = tabulate_grooved(AMBIENT, **{k: v for k, v in TINY.items() if k != "n_sup"})
    assert np.array_equal(tiny.H[:, :, :, 0], t3.H) and np.array_equal(tiny.Q[:, :, :, 0], t3.Q)


def test_the_map_between_the_nodes_and_at_rest(tiny):
    """Off the nodes the error is the spline's (this 6 x 6 x 8 x 5 table is far too coarse for use; the
    measured error of finer ones: docs/forcemap.md); the still journal (r = 0, u = 1) is the pure
    supply force p_s R L Q(eps, phi), its table row one value for every beta."""
    m, rey = SupplyForceMap(FED, tiny), Reynolds(FED, **COARSE)
    still = (0.4 * FED.CR * math.cos(-1.0), 0.4 * FED.CR * math.sin(-1.0), 0.0, 0.0)
    Fm, Fr = np.array(m.force(*still, 0.0)), np.array(rey.force(*still, 0.0))
    assert np.linalg.norm(Fm - Fr) < 0.05 * np.linalg.norm(Fr)
    assert np.ptp(tiny.H[:, :, :, -1], axis=2).max() == 0.0


def test_the_jacobian_is_the_derivative_of_the_force(tiny):
    m = SupplyForceMap(FED, tiny)
    rng = np.random.default_rng(5)
    for _ in range(10):
        eps, phi = rng.uniform(0.1, 0.8), rng.uniform(0, 2 * math.pi)
        om = rng.uniform(0.01, 1.0) * W22
        s = np.array([eps * FED.CR * math.cos(phi), eps * FED.CR * math.sin(phi), *(rng.normal(size=2) * 0.2 * om
                                                                                    * FED.CR)])
        F, Jq, Jv = m.force_and_jacobian(*s, om)
        J, Jn = np.hstack([Jq, Jv]), np.zeros((2, 4))
        for c in range(4):
            h = 1e-7 * FED.CR * (1.0 if c < 2 else om)
            e = np.eye(4)[c] * h
            Jn[:, c] = (np.array(m.force(*(s + e), om)) - np.array(m.force(*(s - e), om))) / (2 * h)
        np.testing.assert_allclose(J, Jn, rtol=0, atol=2e-6 * np.abs(J).max())


def test_at_rest_the_damping_is_the_first_harmonic_of_the_directional_derivatives(tiny):
    """At r = 0 the spline's force has a derivative in each direction of the velocity, not one
    linear map (its interpolation error is not a pure first harmonic in beta): the kernel's is the
    first harmonic of those, here from central differences in the kernel's 8 directions (beta_j = 2 pi j / 8
    in the journal's frame: the velocity's direction b = beta + phi - pi / 2; other directions alias the
    spline's 7th and 9th harmonics differently, 0.2 % on this coarse table)."""
    m = SupplyForceMap(FED, tiny)
    s = np.array([0.3 * FED.CR, -0.2 * FED.CR, 0.0, 0.0])
    _, _, Jv = m.force_and_jacobian(*s, 0.0)
    h = 1e-7 * FED.CR
    fit = np.zeros((2, 2))
    phi = math.atan2(s[1], s[0])
    for beta in 2 * np.pi * np.arange(8) / 8:
        b = beta + phi - 0.5 * math.pi
        d = np.array([0, 0, math.cos(b), math.sin(b)]) * h
        dF = (np.array(m.force(*(s + d), 0.0)) - np.array(m.force(*(s - d), 0.0))) / (2 * h)
        fit += np.outer(dF, [math.cos(b), math.sin(b)]) * 2 / 8
    np.testing.assert_allclose(Jv, fit, rtol=0, atol=1e-5 * np.abs(Jv).max())


def test_the_film_report_is_the_solvers_at_a_node(tiny):
    m, rey = SupplyForceMap(FED, tiny), Reynolds(FED, **COARSE)
    _, r, _ = row_state(FED, tiny.u[2])
    state = state_for(tiny.eps[3], tiny.beta[5], FED, tiny.phi[1], 1.0, r)
    a, b = m.film_report(*state, 1.0), rey.film_report(*state, 1.0)
    assert a.inflow_m3_s == pytest.approx(b.inflow_m3_s, rel=1e-7)
    assert a.side_flow_m3_s == pytest.approx(b.side_flow_m3_s, rel=1e-7)
    # the pressure torque by parts (the fed edges' term added) against the solver's sum over faces
    assert a.friction_torque_Nm == pytest.approx(b.friction_torque_Nm, rel=5e-3)


def test_the_bore_and_the_kind_of_grooves_are_checked(tiny):
    with pytest.raises(ValueError, match="is for fed grooves .*the bearing's are at ambient pressure"):
        SupplyForceMap(AMBIENT, tiny)
    other = dataclasses.replace(FED, geometry=dataclasses.replace(FED.geometry, grooves=(0.0, math.pi)))
    with pytest.raises(ValueError, match="is for the bore '2 axial grooves at 90, 270 deg"):
        SupplyForceMap(other, tiny)
    # any supply pressure: the same table (D, CR, mu, p_s enter through W and u only)
    SupplyForceMap(dataclasses.replace(FED, geometry=dataclasses.replace(FED.geometry, supply_pressure=3e5)), tiny)


def test_the_store_key_and_an_interrupted_build(tmp_path):
    fed = settings_for(FED, resolution=(4, 4), n_phi=4, grid=(16, 4), phases=1, n_sup=4)
    amb = settings_for(AMBIENT, resolution=(4, 4), n_phi=4, grid=(16, 4), phases=1)
    assert fed.n_sup == 4 and amb.n_sup is None
    assert map_key(FED, fed) != map_key(AMBIENT, dataclasses.replace(fed, n_sup=None))
    assert "_fed_" in store_path(FED, fed).name and "_fed_" not in store_path(AMBIENT, amb).name
    partial = tmp_path / "m.partial"

    def stop(resumed):
        def on(n):
            if n == 5:
                raise KeyboardInterrupt
        return on

    with pytest.raises(KeyboardInterrupt):
        build_map(FED, fed, partial, progress=stop)
    said = []
    table = build_map(FED, fed, partial, log=said.append)
    assert said == [f"resuming: 5 of 16 rows already solved in {partial}"]
    ref = tabulate_supplied(FED, n_eps=4, n_phi=4, n_beta=4, n_sup=4, n_theta=16, n_x=4, n_phase=1)
    assert isinstance(table, SupplyMapTable) and np.array_equal(table.H, ref.H) and np.array_equal(table.Q, ref.Q)


def test_bearing_fmu_map_builds_a_pressurised_bearings_map(tmp_path, capsys):
    out = tmp_path / "fed.json"
    code, stdout, stderr = run_cli("bearing-fmu", ["map", "--bearing", str(fed_toml(tmp_path)), "-o", str(out),
                                                   "--resolution", "4x8", "--phi-points", "4", "--grid", "16x4",
                                                   "--quiet", "--workers", "1"], capsys)
    assert code == 0, stderr
    assert "4 x 4 x 8 x 13 points" in stdout and "the fed grooves' 4-D" in stdout
    assert isinstance(load_any_map(out), SupplyMapTable)


@pytest.mark.slow
def test_between_the_nodes_the_error_is_the_splines():
    """At 150 random states (eps 0.05-0.85, speeds 0.4-22 Hz, velocities 0.2 omega CR: u from 0.1 to 1) a
    16 x 16 x 24 x 13 map on Reynolds 64 x 8 against that solver: |dF| / W median 6.3e-4, p95 8.6e-3 in the
    study of docs/forcemap.md (W = S r + R L p_s; the error is the spline's, the map being the solver at
    its nodes); bounds at about twice those."""
    from bearing_fmu.internals.map.supplymap import supply_force
    from bearing_fmu.internals.map.tables import reduced, scale

    grid = dict(n_theta=64, n_x=8)
    m = SupplyForceMap(FED, tabulate_supplied(FED, n_eps=16, n_phi=16, n_beta=24, n_sup=13, eps_max=0.9, flows=False,
                                              workers=2, **grid))
    rey, rng = Reynolds(FED, **grid), np.random.default_rng(11)
    err = []
    for _ in range(150):
        eps, phi, om = rng.uniform(0.05, 0.85), rng.uniform(0, 2 * math.pi), rng.uniform(0.02, 1.0) * W22
        v = rng.normal(size=2) * 0.2 * om * FED.CR
        s = (eps * FED.CR * math.cos(phi), eps * FED.CR * math.sin(phi), v[0], v[1], om)
        _, _, a, c = reduced(*s, FED.CR)
        W = scale(FED) * math.hypot(a, c) + supply_force(FED)
        err.append(np.linalg.norm(np.subtract(m.force(*s), rey.force(*s))) / W)
    assert np.median(err) < 1.5e-3 and np.percentile(err, 95) < 2e-2
