"""The force map: the reduction it rests on, checked on the Reynolds solver itself, and the map
against the solver it tabulates.

Independent references: (1) the Reynolds solver at states related by the reduction (same
eps and beta; attitude turned by whole grid cells, so the discrete problems are the same one;
speeds and velocities scaled): forces equal up to the scale r and the rotation, to round-off;
(2) the solver at random states, the map built from the same grid; (3) scipy's own B-spline
evaluation for the compiled spline; (4) `statics.linearize` on Reynolds for the Lund
coefficients.
"""

import json
import math
import re

import numpy as np
import pytest

from bearing_fmu.internals.map.forcemap import ForceMap
from bearing_fmu.internals.map.tablefile import load_map, save_map
from bearing_fmu.internals.map.tables import reduced, scale, state_for, tabulate
from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0
GRID = {"n_theta": 64, "n_x": 8}


@pytest.fixture(scope="module")
def table():
    # 32 x 48 on a 64 x 8 Reynolds grid: 6144 solves, well under a second
    return tabulate(P, n_eps=32, n_beta=48, n_phase=2, flows=False, **GRID)  # the flows: test_forcemap_flows.py


@pytest.fixture(scope="module")
def fmap(table):
    return ForceMap(P, table)


@pytest.fixture(scope="module")
def rey():
    return Reynolds(P, **GRID)


def _in_frame(F, phi):
    u = np.array([math.cos(phi), math.sin(phi)])
    w = np.array([-u[1], u[0]])
    return np.array([F @ u, F @ w])


@pytest.mark.parametrize("eps, beta", [(0.3, 0.4), (0.7, -2.5), (0.93, 1.7), (0.05, 3.0)])
def test_the_reduction_holds_for_the_reynolds_solver(rey, eps, beta):
    # F / r in the line-of-centres frame depends on (eps, beta) only: two states with other
    # speeds (both signs of omega - 2 phidot), velocities and attitudes (turned by whole
    # cells, so the discrete problem is literally the same) give the same G to round-off
    cell = 2 * math.pi / rey.n_theta
    G = []
    for phi_cells, omega, r in ((-16, 1.0, 1.0), (5, OMEGA, 37.0), (23, -OMEGA, 2.5e3), (40, 3 * OMEGA, 0.01)):
        phi = phi_cells * cell
        y, z, vy, vz = state_for(eps, beta, P, phi=phi, omega=omega, r=r)
        e, ph, a, c = reduced(y, z, vy, vz, omega, P.CR)
        assert (e, math.hypot(a, c), math.atan2(c, a)) == pytest.approx((eps, r, beta), rel=1e-9)
        G.append(_in_frame(np.array(rey.force(y, z, vy, vz, omega)), phi) / (scale(P) * r))
    np.testing.assert_allclose(G[1:], [G[0]] * 3, rtol=1e-9, atol=1e-12 * np.abs(G[0]).max())


def test_the_map_reproduces_its_table_points(table, rey):
    # the spline interpolates: at a node (eps_i, beta_j) and one of the tabulation attitudes
    # the map gives the average over attitudes, within the solver's scatter between them
    i, j = 20, 7
    eps, beta = table.eps[i], table.beta[j]
    m = ForceMap(P, table)
    y, z, vy, vz = state_for(eps, beta, P, phi=0.3)
    G = _in_frame(np.array(m.force(y, z, vy, vz, 1.0)), 0.3) / scale(P)
    np.testing.assert_allclose(G * (1 - eps) ** table.wall_exponent, table.H[i, j], rtol=1e-10, atol=1e-14)


def test_the_map_against_reynolds_at_random_states(fmap, rey):
    # speeds of both signs, velocities up to 3 omega CR (whirl faster and slower than half
    # speed), eccentricity up to 0.95. Bounds from the measured errors with margin (median
    # 3e-5, 95th percentile 4e-4, max 3.4e-3 at the default resolution); the maximum is the
    # solver's own scatter when its grid turns under the journal (docs/forcemap.md)
    rng = np.random.default_rng(7)
    err = []
    for _ in range(150):
        eps, phi = rng.uniform(0, 0.95), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        y, z = eps * P.CR * math.cos(phi), eps * P.CR * math.sin(phi)
        Fr, Fm = np.array(rey.force(y, z, *v, om)), np.array(fmap.force(y, z, *v, om))
        err.append(np.linalg.norm(Fm - Fr) / max(np.linalg.norm(Fr), scale(P) * abs(om)))
    err = np.array(err)
    assert np.median(err) < 3e-4 and np.percentile(err, 95) < 3e-3 and err.max() < 1.5e-2, \
        (np.median(err), np.percentile(err, 95), err.max())


def test_jacobian_against_central_differences(fmap, central_jacobian):
    for state in ((2e-5, -3e-5, 1e-3, -2e-3), (-6e-5, 5e-5, -4e-3, 1e-3), (1e-7, 0.0, 1e-3, 0.0)):
        F, dq, dv = fmap.force_and_jacobian(*state, OMEGA)
        h = min(1e-5 * P.CR, 1e-3 * math.hypot(*state[:2]))  # near the centre: small against e
        cq, cv = central_jacobian(fmap.force, state, OMEGA, (h, h, h * OMEGA, h * OMEGA))
        np.testing.assert_allclose(dq, cq, atol=1e-5 * np.abs(cq).max())
        np.testing.assert_allclose(dv, cv, atol=1e-5 * np.abs(cv).max())


def test_no_source_no_force_and_a_finite_jacobian(fmap, central_jacobian):
    # whirl at exactly half speed with no radial velocity: r = 0, the film has no source.
    # Powers of two make a = eps omega - 2 v_t / CR exactly 0 in floating point.
    e, omega = 2.0**-14, 128.0  # eccentricity ratio 0.68
    y, z, vy, vz = e, 0.0, 0.0, e * omega / 2  # phidot = omega / 2
    assert reduced(y, z, vy, vz, omega, P.CR)[2:] == (0.0, 0.0)
    F, dq, dv = fmap.force_and_jacobian(y, z, vy, vz, omega)
    assert np.all(F == 0.0)
    assert np.all(np.isfinite(dq)) and np.all(np.isfinite(dv))
    h = 1e-5 * P.CR
    _, cv = central_jacobian(fmap.force, (y, z, vy, vz), omega, (h, h, h * omega, h * omega))
    np.testing.assert_allclose(dv, cv, atol=1e-6 * np.abs(cv).max())  # the odd part, as differences see it


def test_force_scales_with_speed_and_velocity_together(fmap):
    # r is homogeneous of degree 1 in (omega, v) at fixed position: so is the force
    y, z, vy, vz = 3e-5, -4e-5, 2e-3, 1e-3
    F1 = np.array(fmap.force(y, z, vy, vz, OMEGA))
    F3 = np.array(fmap.force(y, z, 3 * vy, 3 * vz, 3 * OMEGA))
    np.testing.assert_allclose(F3, 3 * F1, rtol=1e-12)


def test_lund_coefficients_from_the_map(table):
    # at the paper bearing's 22 Hz equilibrium under half the rotor weight: K and C from the
    # map's analytic Jacobian against linearize on Reynolds at the same grid
    from bearing_fmu.physics.statics import equilibrium, linearize

    rey = Reynolds(P, **GRID)
    fmap = ForceMap(P, table)
    for internal in (rey, fmap):
        internal.eq = equilibrium(internal, (0.0, -16.7), OMEGA)
    assert np.hypot(*np.subtract(fmap.eq, rey.eq)) < 2e-3 * P.CR
    Kr, Cr = linearize(rey, *rey.eq, OMEGA)
    Km, Cm = linearize(fmap, *rey.eq, OMEGA)
    assert np.abs(Km - Kr).max() < 5e-3 * np.abs(Kr).max()
    assert np.abs(Cm - Cr).max() < 5e-3 * np.abs(Cr).max()


def test_other_bearings_of_the_same_l_over_d_scale(table, rey):
    # D, CR and mu enter through S = mu R L (R/CR)^2 only: a bearing twice the size, with
    # another clearance and oil, gets its force from the same table
    big = BearingParams(D=2 * P.D, L=2 * P.L, CR=1.5 * P.CR, mu=0.02)
    m, r = ForceMap(big, table), Reynolds(big, **GRID)
    y, z, vy, vz = 0.4 * big.CR, -0.5 * big.CR, 0.1 * big.CR * OMEGA, 0.05 * big.CR * OMEGA
    Fm, Fr = np.array(m.force(y, z, vy, vz, OMEGA)), np.array(r.force(y, z, vy, vz, OMEGA))
    assert np.linalg.norm(Fm - Fr) < 3e-3 * np.linalg.norm(Fr)


def test_refusals_name_what_is_wrong(table, tmp_path):
    with pytest.raises(ValueError, match=r"L/D = 0.645.*bearing has L/D = 0.5"):
        ForceMap(BearingParams(D=0.04, L=0.02, CR=P.CR, mu=P.mu), table)
    m = ForceMap(P, table)
    with pytest.raises(BearingStateError, match=r"eccentricity ratio 0.995 >= 0.99: .*beyond the force map's last point"):
        m.force(0.0, -0.995 * P.CR, 0.0, 0.0, OMEGA)
    with pytest.raises(BearingStateError, match=r"eccentricity ratio 1.03 >= 1: .*at or beyond the bearing wall"):
        m.force(0.0, -1.03 * P.CR, 0.0, 0.0, OMEGA)
    with pytest.raises(BearingStateError, match="bearing input vz = nan is not finite"):
        m.force(0.0, 0.0, 0.0, math.nan, OMEGA)
    path = save_map(table, tmp_path / "m.json")
    back = load_map(path)
    np.testing.assert_allclose(back.H, table.H, rtol=1e-11, atol=1e-12)  # saved to 12 decimals
    text = path.read_text()
    (tmp_path / "cut.json").write_text(text[: len(text) // 2])
    with pytest.raises(ValueError, match=r"cut.json: not valid JSON .* truncated"):
        load_map(tmp_path / "cut.json")
    data = json.loads(text)
    del data["eps_max"]
    (tmp_path / "nokey.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"nokey.json: missing key 'eps_max'"):
        load_map(tmp_path / "nokey.json")


def test_compiled_spline_equals_scipy(table):
    # the numba tensor spline against scipy's BSpline evaluated axis by axis
    from scipy.interpolate import BSpline

    from bearing_fmu.internals.map.kernels import spline2

    ts, tb, C = table.spline()
    rng = np.random.default_rng(3)
    out = np.empty((2, 3))
    for _ in range(20):
        s, b = rng.uniform(0, table.s[-1]), rng.uniform(-math.pi, math.pi)
        spline2(ts, tb, C, C.shape[0], C.shape[1], s, b, out)
        cb = BSpline(tb, np.moveaxis(C, 1, 0), 3, extrapolate="periodic")(b)  # (ns, 2)
        want = BSpline(ts, cb, 3)(s)
        np.testing.assert_allclose(out[:, 0], want, rtol=1e-12, atol=1e-14)


@pytest.mark.slow
def test_linear_from_the_map_needs_no_reynolds(table, tmp_path):
    # linear_from = "map": the Lund coefficients from the map's analytic Jacobian, within the
    # map's accuracy of those from Reynolds, without importing the solver (a fresh process)
    import subprocess
    import sys

    from bearing_fmu.internals import registry

    path = save_map(table, tmp_path / "m.json")
    opts = {"load_z": -16.7, "omega_lin": OMEGA, **GRID}
    lin_map = registry.create("linear", P, {**opts, "linear_from": "map", "map": str(path)})
    lin_rey = registry.create("linear", P, opts)
    assert np.abs(lin_map.K - lin_rey.K).max() < 5e-3 * np.abs(lin_rey.K).max()
    assert np.abs(lin_map.C - lin_rey.C).max() < 5e-3 * np.abs(lin_rey.C).max()
    code = ("import sys; from bearing_fmu import internals as r; from bearing_fmu.physics.params import PAPER_BEARING as P; "
            f"r.create('linear', P, {{'linear_from': 'map', 'map': {str(path)!r}, 'load_z': -16.7, "
            f"'omega_lin': {OMEGA!r}}}); print('bearing_fmu.physics.solver.reynolds' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_huge_finite_velocity_is_refused_by_name(fmap):
    # F = S r G is linear in r ~ |v| / CR: at 1e308 m/s the force is beyond the float range, so
    # no finite value is the model's answer: refused by name (was NaN); 1e200 m/s stays finite
    for call in (fmap.force, fmap.force_and_jacobian):
        with pytest.raises(BearingStateError, match=r"bearing input vy = 1e\+308 m/s is too large"):
            call(1e-5, -4e-5, 1e308, 0.0, OMEGA)
        with pytest.raises(BearingStateError, match=r"bearing input vz = -1e\+308 m/s is too large"):
            call(1e-5, -4e-5, 0.0, -1e308, OMEGA)
    assert np.all(np.isfinite(fmap.force(1e-5, -4e-5, 1e200, 0.0, OMEGA)))
    with pytest.raises(BearingStateError, match=r"eccentricity ratio 0.995 >= 0.99"):  # the table first
        fmap.force(0.0, -0.995 * P.CR, 1e308, 0.0, OMEGA)


def _set(key, value):
    def damage(d):
        *parents, last = key.split(".")
        for k in parents:
            d = d[k]
        d[last] = value
    return damage


def _edit_table(d):
    d["H"][5][7][0] *= 1.001  # edited after the spline was written: the map would serve the old spline


def _spline_of_other_table(d):
    d["spline"]["coefficients"][3][4][1] += 1.0


@pytest.mark.parametrize("damage, expected", [
    (_set("L_over_D", math.nan), r"key 'L_over_D' = nan must be a finite number in 0.05 .. 5"),
    (_set("L_over_D", 30.0), r"key 'L_over_D' = 30.0 must be a finite number in 0.05 .. 5"),
    (_set("wall_exponent", math.nan), r"key 'wall_exponent' = nan must be a finite number >= 0"),
    (_set("wall_exponent", "2"), r"key 'wall_exponent' = '2' must be a number"),
    (_set("eps_max", math.inf), r"key 'eps_max' = inf must lie in \(0, 1\)"),
    (_set("n_eps", math.nan), r"key 'n_eps' is not a finite number"),
    (_set("reynolds.n_theta", 64.5), r"key 'reynolds.n_theta' = 64.5 must be an integer >= 1"),
    (_set("provenance.built_s", math.nan), r"key 'provenance.built_s' is not a finite number"),
    (_set("geometry", {"grooves": 2}), r"unknown key\(s\) geometry; allowed: format, version, L_over_D"),
    (_set("H", [[1.0]]), r"key 'H' has shape \(1, 1\), expected \(n_eps >= 4"),
    (_set("H", [[1.0, 2.0], [1.0]]), r"key 'H' must be a regular array of numbers"),
    (_edit_table, r"key 'spline' does not reproduce the table 'H' at its points .*: rebuild the map"),
    (_spline_of_other_table, r"key 'spline' does not reproduce the table 'H'"),
    (_set("spline.knots_s", [0.0, 1.0]), r"key 'spline' has shapes knots_s \(2,\)"),
    (_set("spline.coefficients", None), r"key 'spline' is incomplete or damaged \(key 'coefficients' must be"),
    (_set("H", [[[math.nan, 0.0]] * 4] * 4), r"key 'H' has a non-finite entry H\[0, 0, 0\] = nan"),
])
def test_damaged_map_file_is_refused_naming_file_and_key(table, tmp_path, damage, expected):
    good = save_map(table, tmp_path / "good.json")
    d = json.loads(good.read_text())
    damage(d)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))  # a NaN is written as NaN (Python's json allows it; a damaged file may have it)
    with pytest.raises(ValueError) as err:
        load_map(bad)
    text = str(err.value)
    assert text.startswith(f"force map file {bad}: ") and "\n" not in text, text
    assert re.search(expected, text), text


def test_nan_l_over_d_never_passes_the_bearing_check(table):
    # NaN compares false: the old check let such a table serve any bearing (the Friswell map
    # then ran the paper scene to status ok with a wrong eccentricity); now no table holds it
    import dataclasses

    with pytest.raises(ValueError, match=r"force map table: key 'L_over_D' = nan"):
        dataclasses.replace(table, L_over_D=math.nan)
    table_nan = dataclasses.replace(table)
    table_nan.L_over_D = math.nan  # mutated after the checks: the bearing check still refuses it
    with pytest.raises(ValueError, match=r"force map is for L/D = nan, the bearing has L/D = 0.645"):
        ForceMap(P, table_nan)


def test_the_shipped_maps_pass_the_checks():
    from pathlib import Path

    from bearing_fmu.internals.map.mapfile import load_any_map

    for path in sorted((Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "maps").glob("*.json")):
        table = load_any_map(path)
        if table.H.ndim == 3:  # version 1: the stored spline, checked against its table
            assert load_map(path).coefficients is not None
        else:  # version 2 (a grooved bore): the spline is fitted on loading, and gives the table back
            assert table.spline()[-1].shape == (table.n_eps, table.n_phi + 3, table.n_beta + 3, 2)


def test_worker_processes_tabulate_the_same_map():
    """The rows computed in a process pool (``workers``) are those computed in order here."""
    kw = dict(n_eps=6, n_beta=8, n_phase=1, n_theta=16, n_x=4)
    assert np.array_equal(tabulate(P, workers=2, **kw).H, tabulate(P, workers=1, **kw).H)
