"""The force map of a grooved or partial-arc bore (internals/map/groovemap.py, docs/forcemap.md,
"Grooved bores"): the reduction F = S r G(eps, phi, beta) checked on the Reynolds solver itself,
the supply pressure that breaks it, the 3-D table, its file and its refusals.

Independent references: the Reynolds solver with the bore's [geometry] (validated against Lund
& Thomsen's table, tests/test_geometry_validation.py); central differences for the Jacobian; the
table's own points for the spline (an interpolant reproduces its data).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map.tables import scale, state_for
from bearing_fmu.internals.map.groovemap import (GroovedForceMap, grooved_row, map_geometry_problem, save_grooved_map,
                                             symmetry_period, tabulate_grooved)
from bearing_fmu.internals.map.mapfile import load_any_map, open_map
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
GROOVED = BearingParams.from_toml(MODELS / "bearing_paper_2groove.toml")
ARC = dataclasses.replace(PAPER_BEARING, geometry=Geometry(arc=(math.radians(90.0), math.radians(270.0))))
COARSE = dict(n_theta=32, n_x=4)
TINY = dict(n_eps=8, n_phi=6, n_beta=8, n_phase=1, **COARSE)


def _G(P, rey, eps, phi, beta, r, omega):
    y, z, vy, vz = state_for(eps, beta, P, phi, omega, r)
    F = np.array(rey.force(y, z, vy, vz, omega))
    return np.array([F @ (math.cos(phi), math.sin(phi)), F @ (-math.sin(phi), math.cos(phi))]) / (scale(P) * r)


@pytest.mark.parametrize("P", [GROOVED, ARC], ids=["two grooves", "180 deg arc"])
def test_the_reduction_holds_for_the_reynolds_solver(P):
    """Equal (eps, phi, beta) give equal G = F / (S r) whatever r (0.01 .. 2500 1/s) and the
    speed's sign; two opposite grooves also repeat after phi + pi (the grid is symmetric)."""
    rey = Reynolds(P, **COARSE)
    period = symmetry_period(P.geometry)
    assert period == pytest.approx(math.pi if P is GROOVED else 2 * math.pi)
    for eps, phi, beta in ((0.3, -1.2, 0.4), (0.85, 0.3, -2.5), (0.6, 2.0, 2.9)):
        ref = _G(P, rey, eps, phi, beta, 1.0, 1.0)
        for r, omega in ((0.01, 3.0), (2500.0, -50.0), (40.0, -900.0)):
            np.testing.assert_allclose(_G(P, rey, eps, phi, beta, r, omega), ref, rtol=0, atol=1e-9 * np.abs(ref).max())
        if period < 2 * math.pi:
            np.testing.assert_allclose(_G(P, rey, eps, phi + period, beta, 3.0, 9.0), ref, rtol=0,
                                       atol=1e-9 * np.abs(ref).max())
    # and the attitude matters: the grooves are fixed in the bearing (not the full bore's 2-D map)
    assert np.abs(_G(P, rey, 0.8, 0.0, 0.0, 1, 1) - _G(P, rey, 0.8, 0.5 * period, 0.0, 1, 1)).max() > 0.05


def test_a_supply_pressure_is_not_superposable():
    """With p_s > 0 the force is not S r G + p_s Q(eps, phi): F(p_s) - F(0) would not depend on
    the motion's scale lambda; with cavitation it changes by a factor of ~2 from lambda 0.5 to 2."""
    fed = dataclasses.replace(GROOVED, geometry=dataclasses.replace(GROOVED.geometry, supply_pressure=100e3))
    r0, r1 = Reynolds(GROOVED, **COARSE), Reynolds(fed, **COARSE)
    w = 2 * math.pi * 22
    y, z, vy, vz = state_for(0.5, 0.0, GROOVED, -0.5 * math.pi, w, 0.5 * w)
    d = [np.subtract(r1.force(y, z, lam * vy, lam * vz, lam * w), r0.force(y, z, lam * vy, lam * vz, lam * w))
         for lam in (0.5, 2.0)]
    assert np.linalg.norm(d[1] - d[0]) > 0.2 * np.linalg.norm(d[0])
    assert "supply_pressure_kPa = 100" in map_geometry_problem(fed.geometry)
    with pytest.raises(ValueError, match="no force map for this bearing's bore .*supply_pressure_kPa = 100: a supply "
                                         "pressure adds a film source independent of the journal's motion"):
        tabulate_grooved(fed, **TINY)


def test_lobed_bores_are_refused_by_name():
    lemon = BearingParams.from_toml(MODELS / "bearing_paper_lemon.toml")
    with pytest.raises(ValueError, match=r"lobes = 2: a lobed bore's film depends on the journal position in two "
                                         r"coordinates .* a 4-D table"):
        tabulate_grooved(lemon, **TINY)


@pytest.fixture(scope="module")
def tiny_map(tmp_path_factory):
    path = tmp_path_factory.mktemp("groovemap") / "tiny.json"
    return save_grooved_map(tabulate_grooved(GROOVED, **TINY), path)


def test_the_map_gives_the_solver_at_its_points_and_its_own_derivatives(tiny_map):
    fmap = open_map(tiny_map, GROOVED)
    assert isinstance(fmap, GroovedForceMap)
    t = fmap.table
    rey = Reynolds(GROOVED, **COARSE)
    w = 2 * math.pi * 22
    # at a table point (eps_i, phi_j, beta_k), any r and speed: the solver's force (the spline
    # interpolates its data; the file keeps 8 digits)
    for i, j, k in ((2, 1, 3), (5, 4, 0), (6, 5, 7)):
        x = state_for(t.eps[i], t.beta[k], GROOVED, t.phi[j], w, 37.0)
        np.testing.assert_allclose(fmap.force(*x, w), rey.force(*x, w), rtol=1e-7, atol=1e-7 * scale(GROOVED) * 37)
    # the Jacobian: central differences of the map's own force
    CR = GROOVED.CR
    for x in ((0.3 * CR, -0.4 * CR, 0.1 * CR * w, -0.05 * CR * w), (-0.5 * CR, 0.2 * CR, 0.0, 0.02 * CR * w)):
        F, dq, dv = fmap.force_and_jacobian(*x, w)
        J, Jn = np.hstack([dq, dv]), np.zeros((2, 4))
        for c in range(4):
            h = 1e-6 * CR * (1 if c < 2 else w)
            xp, xm = np.array(x, float), np.array(x, float)
            xp[c] += h
            xm[c] -= h
            Jn[:, c] = (np.subtract(fmap.force(*xp, w), fmap.force(*xm, w))) / (2 * h)
        np.testing.assert_allclose(J, Jn, rtol=0, atol=1e-6 * np.abs(J).max())


def test_the_row_averages_attitudes_symmetrically_about_the_point():
    rey = Reynolds(GROOVED, **COARSE)
    cell = 2 * math.pi / rey.n_theta
    row = grooved_row(GROOVED, rey.n_theta, rey.n_x, rey.cavitation, 0.5, [0.7], [1.1], 2, rey, False)[0][0, 0]
    want = (_G(GROOVED, rey, 0.5, 0.7 - cell / 4, 1.1, 1, 1) + _G(GROOVED, rey, 0.5, 0.7 + cell / 4, 1.1, 1, 1)) / 2
    np.testing.assert_allclose(row, want, rtol=1e-12)


def test_the_file_round_trips_and_is_checked(tiny_map, tmp_path):
    data = json.loads(tiny_map.read_text())
    assert data["version"] == 4 and data["geometry"]["grooves_deg"] == [90.0, 270.0]
    t = load_any_map(tiny_map)
    assert t.H.shape == (8, 6, 8, 2) and t.period == pytest.approx(math.pi)
    assert t.Q.shape == (8, 6, 8, 5)  # side flow and the four groove edges, in theta order from the first groove
    np.testing.assert_allclose(data["flow_edges_deg"], [[100, 1], [260, -1], [280, 1], [80, -1]], rtol=1e-14)
    # version 1 files still load through the same door: tests/test_forcemap.py::test_the_shipped_maps_pass_the_checks

    def damaged(**change):
        bad = {**data, **change}
        p = tmp_path / "bad.json"
        p.write_text(json.dumps(bad))
        return p

    for change, words in (({"version": 5}, "version 5, this code reads 1 .* 2 and 4"),
                          ({"extra": 1}, "unknown key.*extra"),
                          ({"H": data["H"][:-1]}, "key 'H' has 767 numbers, n_eps x n_phi x n_beta x 2 = 768"),
                          ({"n_phi": 2}, "key 'n_phi' = 2 must be an integer >= 4"),
                          ({"eps_max": 1.5}, "key 'eps_max' = 1.5 must lie in"),
                          ({"geometry": {"grooves_deg": [], "groove_width_deg": 20.0, "arc_deg": None}},
                           "describes the full bore")):
        with pytest.raises(ValueError, match=f"force map file .*bad.json: .*{words}"):
            load_any_map(damaged(**change))


def test_a_map_serves_only_its_own_bore(tiny_map):
    with pytest.raises(ValueError, match=r"is for the bore '2 axial grooves at 90, 270 deg .*', the bearing has "
                                         r"'full 360 deg circular bore': build a map for it"):
        open_map(tiny_map, PAPER_BEARING)
    turned = dataclasses.replace(GROOVED, geometry=Geometry(grooves=(0.0, math.pi)))
    with pytest.raises(ValueError, match="the bearing has '2 axial grooves at 0, 180 deg"):
        open_map(tiny_map, turned)
    with pytest.raises(ValueError, match="models only the full 360 deg circular bore .*builds a 3-D map for grooves"):
        open_map(MODELS / "maps" / "paper_bearing.json", GROOVED)
    wide = dataclasses.replace(GROOVED, L=2 * GROOVED.L)
    with pytest.raises(ValueError, match="is for L/D = 0.645161, the bearing has L/D = 1.29"):
        open_map(tiny_map, wide)


def test_states_beyond_the_table_are_refused(tiny_map):
    from bearing_fmu.internals.registry import BearingStateError

    fmap = open_map(tiny_map, GROOVED)
    with pytest.raises(BearingStateError, match="eccentricity ratio 0.995 >= 0.99: .* beyond the force map's last point"):
        fmap.force(0.0, -0.995 * GROOVED.CR, 0.0, 0.0, 100.0)
    with pytest.raises(BearingStateError):
        fmap.force(math.nan, 0.0, 0.0, 0.0, 100.0)
    assert np.all(np.isfinite(fmap.force_and_jacobian(0.0, 0.0, 0.0, 0.0, 100.0)[1]))  # the centre


@pytest.mark.slow
def test_a_partial_arc_map_matches_the_solver_between_its_points(tmp_path):
    """A 180 deg arc (period 2 pi in phi): at states between the table points the map follows
    the solver to the interpolation error of a coarse table (12 x 16 x 16)."""
    table = tabulate_grooved(ARC, n_eps=12, n_phi=16, n_beta=16, n_phase=1, workers=2, **COARSE)
    fmap = GroovedForceMap(ARC, table)
    rey = Reynolds(ARC, **COARSE)
    rng = np.random.default_rng(5)
    err = []
    for _ in range(60):
        e, a, w = rng.uniform(0, 0.8), rng.uniform(-math.pi, math.pi), rng.uniform(50, 300)
        v = rng.normal(0, 0.3, 2) * w * ARC.CR
        x = (e * ARC.CR * math.cos(a), e * ARC.CR * math.sin(a), v[0], v[1], w)
        F = rey.force(*x)
        err.append(np.linalg.norm(np.subtract(fmap.force(*x), F)) / max(np.linalg.norm(F), scale(ARC) * w))
    assert np.median(err) < 5e-3 and np.max(err) < 0.1, (np.median(err), np.max(err))
