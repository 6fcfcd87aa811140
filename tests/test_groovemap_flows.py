"""The grooved map's flow tables (internals/map/groovemap.py, docs/forcemap.md, "Grooved bores: the
flows"): the reduction of the side flow and of each supply edge's inflow checked on the Reynolds
solver itself, the map's film report against the solver's, the closed-form Couette integral, and
the files with and without the tables.

Independent references: (1) the Reynolds solver's own film report (``physics.solver.film.field_report``,
validated against Raimondi & Boyd in tests/test_film.py) at states with equal (eps, phi, beta) and
other r (0.01 .. 2500 1/s) and speeds of both signs; (2) numerical quadrature (scipy.integrate.quad)
for the film's Couette integral, and 2 pi / sqrt(1 - eps^2) for the full circle; (3) the bore's
symmetry: two opposite grooves turned by 180 deg are the same bore with the edges renumbered.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.map.tables import state_for
from bearing_fmu.internals.map.groovemap import GroovedForceMap, save_grooved_map, tabulate_grooved
from bearing_fmu.internals.map.mapfile import load_any_map, open_map
from bearing_fmu.physics.solver.film import film_couette_integral, flow_scale
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from conftest import damaged_map_refused

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
GROOVED = BearingParams.from_toml(MODELS / "bearing_paper_2groove.toml")
ARC = dataclasses.replace(PAPER_BEARING, geometry=Geometry(arc=(math.radians(90.0), math.radians(270.0))))
COARSE = dict(n_theta=32, n_x=4)
OMEGA = 2 * math.pi * 22.0


def _components(P, rey, eps, phi, beta, r, omega):
    """(J_s, P_1 .. P_E) of the solver's field at a state, and the inflow assembled from them with
    the Couette parts in closed form (groovemap's docstring), beside the solver's own report."""
    s = state_for(eps, beta, P, phi, omega, r)
    e = rey.supply_flows(*s, omega)
    q0 = flow_scale(P)
    comp = np.r_[e["side_flow"], -e["pressure"]] / (r * q0)
    q_in = sum(max(sg * omega * q0 * 0.5 * (1 + eps * math.sin(t - phi)) - r * q0 * p, 0.0)
               for t, sg, p in zip(e["theta"], e["sign"], comp[1:]))
    return comp, q_in, rey.film_report(*s, omega), e


@pytest.mark.parametrize("P", [GROOVED, ARC], ids=["two grooves", "180 deg arc"])
def test_the_edge_flow_reduction_holds_for_the_reynolds_solver(P):
    """Equal (eps, phi, beta) give equal J_s and P_e whatever r and the speed's sign (to 1e-12), and
    the positive parts taken after the sum give the solver's inflow to round-off, also where the
    edges switch between inflow and outflow with omega / r (the solver's inflow is not linear there)."""
    rey = Reynolds(P, **COARSE)
    q0 = flow_scale(P)
    for eps, phi, beta in ((0.3, -1.2, 0.4), (0.85, 0.3, -2.5), (0.6, 2.0, 2.9)):
        ref = _components(P, rey, eps, phi, beta, 1.0, 1.0)[0]
        for r, omega in ((0.01, 3.0), (2500.0, -50.0), (40.0, -900.0), (1.0, 0.2), (1.0, 3.0)):
            comp, q_in, rep, e = _components(P, rey, eps, phi, beta, r, omega)
            np.testing.assert_allclose(comp, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
            assert q_in == pytest.approx(rep.inflow_m3_s, rel=1e-12, abs=1e-15 * q0 * (r + abs(omega)))
            assert comp[0] * r * q0 == pytest.approx(rep.side_flow_m3_s, rel=1e-14)
            # the solver's edges are the bore's (Geometry.supply_edges: the file's flow_edges_deg)
            np.testing.assert_allclose(np.c_[np.mod(e["theta"], 2 * math.pi), e["sign"]], P.geometry.supply_edges(),
                                       rtol=0, atol=1e-12)
    # not linear in (omega, r) as one table: (0.3, -1.2, 0.4) at omega / r = 0.2, 1, 3 (docs/forcemap.md)
    q = [_components(P, rey, 0.3, -1.2, 0.4, 1.0, w)[2].inflow_m3_s / q0 for w in (0.2, 1.0, 3.0)]
    if P is GROOVED:
        assert q[2] - q[1] == pytest.approx(2.0, rel=1e-9)  # slope 1 between 1 and 3: the Couette part
        assert q[0] > q[1] - 0.8 * 1.0 + 0.05  # but not at 0.2: an edge has turned to outflow


def test_two_opposite_grooves_turned_by_half_a_turn_renumber_the_edges():
    # the table covers phi over one period (180 deg) only: the map folds phi there and the edges'
    # P_e belong to the folded attitude; the solver at phi + pi gives the same with edges (1, 2) <-> (3, 4)
    rey = Reynolds(GROOVED, **COARSE)
    a = _components(GROOVED, rey, 0.7, 0.4, 1.3, 1.0, 1.0)[0]
    b = _components(GROOVED, rey, 0.7, 0.4 + math.pi, 1.3, 1.0, 1.0)[0]
    np.testing.assert_allclose(b, np.r_[a[0], a[3:5], a[1:3]], rtol=0, atol=1e-12 * np.abs(a).max())
    assert np.abs(a[1:] - b[1:]).max() > 0.01  # so the renumbering matters


@pytest.mark.parametrize("geometry", [GROOVED.geometry, ARC.geometry, Geometry()], ids=["grooves", "arc", "full"])
def test_the_couette_integral_in_closed_form(geometry):
    from scipy.integrate import quad

    segs, fixed, _ = geometry.segments() if not geometry.is_full_bore else ([(0.0, 2 * math.pi)], [False], None)
    for eps, phi in ((0.0, 0.3), (0.5, -2.0), (0.95, 1.1), (0.99, 4.0)):
        want = sum(quad(lambda t: 1 / (1 + eps * math.sin(t - phi)), a, b, epsabs=1e-13, epsrel=1e-13, limit=400)[0]
                   for (a, b), f in zip(segs, fixed) if not f)
        assert film_couette_integral(geometry, eps, phi) == pytest.approx(want, rel=1e-11)
        if geometry.is_full_bore:
            assert want == pytest.approx(2 * math.pi / math.sqrt(1 - eps * eps), rel=1e-11)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("groove_flows") / "tiny.json"
    return save_grooved_map(tabulate_grooved(GROOVED, n_eps=8, n_phi=12, n_beta=8, n_phase=1, **COARSE), path)


def test_the_map_reports_the_solvers_flows_at_its_points(tiny):
    """At a table point, any r and speed (both signs) and the attitude also half a turn on (folded):
    the solver's inflow and side flow (the spline interpolates its data; 8 digits in the file), the
    Couette torque (exact) to the solver's Simpson sum over its cells (eps <= 0.93 here: 2e-5 on 32
    cells, 7e-4 at eps 0.98; 1e-8 on the shipped maps' 128), the pressure torque to the cells'
    midpoint rule of the solver's force (sinc(w/2) - 1 ~ 2e-3 of it at w = 0.17 rad)."""
    fmap = open_map(tiny, GROOVED)
    assert registry.film_flow_of(registry.get("map"), fmap) == ""
    t, rey, q0 = fmap.table, Reynolds(GROOVED, **COARSE), flow_scale(GROOVED)
    for (i, j, k), r, omega, turn in (((2, 1, 3), 37.0, OMEGA, 0.0), ((3, 4, 0), 900.0, -OMEGA, math.pi),
                                      ((4, 5, 7), 3.0, 2 * OMEGA, -math.pi), ((1, 2, 5), 300.0, 0.5 * OMEGA, 0.0)):
        x = state_for(t.eps[i], t.beta[k], GROOVED, t.phi[j] + turn, omega, r)
        a, b = fmap.film_report(*x, omega), rey.film_report(*x, omega)
        floor = 1e-7 * q0 * (r + abs(omega))
        assert a.inflow_m3_s == pytest.approx(b.inflow_m3_s, rel=1e-7, abs=floor)
        assert a.side_flow_m3_s == pytest.approx(b.side_flow_m3_s, rel=1e-7, abs=floor)
        assert a.couette_torque_Nm == pytest.approx(b.couette_torque_Nm, rel=1e-4)
        assert a.pressure_torque_Nm == pytest.approx(b.pressure_torque_Nm, rel=3e-3)
        assert set(a.as_dict()) == set(b.as_dict())


def test_the_edges_flows_are_splined_over_the_whole_turn(tiny):
    """The table holds phi over one period (180 deg) of the bore, but an edge's P_e repeats only after
    a whole turn: past the period the journal meets the other groove's edges (``unrolled_flows``). A
    spline periodic over the period would join P_e to itself across the period's end: there, half a
    cell before 180 deg, the inflow was 5.4e-2 off the solver at worst (relative to max(Q, 0.1 omega
    Q0)); over the whole turn 4.5e-3, as between any two points (3.2e-3 half a cell after 0 deg). The
    spline kept holds one period, its last coefficients the next period's first renumbered exactly."""
    fmap = open_map(tiny, GROOVED)
    t, rey, q0 = fmap.table, Reynolds(GROOVED, **COARSE), flow_scale(GROOVED)
    ts, tp, tb, C = t.flow_spline()
    assert C.shape == (8, 15, 11, 5)  # one period: 12 + 3 coefficients in phi
    np.testing.assert_array_equal(C[:, 12:], C[:, :3][..., [0, 3, 4, 1, 2]])
    u = t.unrolled_flows()
    assert u.shape == (8, 24, 8, 5)
    np.testing.assert_array_equal(u[:, 12:], t.Q[..., [0, 3, 4, 1, 2]])  # edges (100, 260) <-> (280, 80) deg
    h = t.period / t.n_phi
    for phi in (t.period - 0.5 * h, 0.5 * h):
        err = []
        for eps in t.eps[1:5]:
            for b in t.beta:
                x = state_for(eps, b, GROOVED, phi, OMEGA, OMEGA)
                a, c = fmap.film_report(*x, OMEGA), rey.film_report(*x, OMEGA)
                err.append(abs(a.inflow_m3_s - c.inflow_m3_s) / max(c.inflow_m3_s, 0.1 * OMEGA * q0))
        assert max(err) < 1e-2, (phi, max(err))


def test_the_one_period_flow_spline_is_the_whole_turns(tiny):
    """The flow spline kept over one period and renumbered (``flow_components``) against the spline
    fitted over the whole turn (``unrolled_flows``, as before it was halved; independent of the
    renumbering at evaluation): at random states and at attitudes within two cells of 0, +-90 and
    +-180 deg, the ends of the period included (-0.0, 1e-300, pi, -pi, one ulp before them), every
    component and derivative equal to 1e-13 of the largest (the two fits' round-off)."""
    from bearing_fmu.internals.map.groovemap import flow_components
    from bearing_fmu.internals.map.kernels import spline3

    t = open_map(tiny, GROOVED).table
    whole, images = t.fit_spline(t.unrolled_flows(), 2), t.flow_images()
    rng = np.random.default_rng(7)
    h = t.period / t.n_phi
    phis = np.r_[rng.uniform(-math.pi, math.pi, 100), rng.choice([-math.pi, -0.5 * math.pi, 0.0, 0.5 * math.pi,
                                                                    math.pi], 100) + rng.uniform(-2 * h, 2 * h, 100),
                 -0.0, 1e-300, -1e-300, math.pi, -math.pi, math.nextafter(math.pi, 0.0), math.nextafter(0.0, -1.0)]
    a, b = np.zeros((5, 4)), np.zeros((5, 4))
    for phi in phis:
        s, beta = rng.uniform(0.0, t.s[-1]), rng.uniform(-math.pi, math.pi)
        spline3(*whole, s, phi, beta, b)
        np.testing.assert_allclose(flow_components(t.flow_spline(), images, s, phi, beta, a), b, rtol=0,
                                   atol=1e-13 * np.abs(b).max(), err_msg=f"phi = {phi!r}")


@pytest.mark.slow
def test_the_map_reports_the_solvers_flows_at_random_states(tmp_path):
    # a coarse 12 x 16 x 24 map on the solver's grid against the solver, as the full bore's test
    # (tests/test_forcemap_flows.py); bounds from the measured errors with margin (inflow, side flow,
    # power: median 2.5e-4, 7.8e-4, 4.5e-4; max 5.0e-3, 3.5e-3, 6.7e-3); the shipped maps' in docs/forcemap.md
    m = GroovedForceMap(GROOVED, tabulate_grooved(GROOVED, n_eps=12, n_phi=16, n_beta=24, **COARSE))
    rey = Reynolds(GROOVED, **COARSE)
    rng = np.random.default_rng(1)
    err = {"inflow": [], "side": [], "power": []}
    for _ in range(60):
        eps, phi = rng.uniform(0, 0.9), rng.uniform(-math.pi, math.pi)
        om = OMEGA * rng.uniform(0.2, 3) * rng.choice([1, -1])
        v = rng.uniform(-1.5, 1.5, 2) * abs(om) * GROOVED.CR / math.sqrt(2)
        s = (eps * GROOVED.CR * math.cos(phi), eps * GROOVED.CR * math.sin(phi), v[0], v[1], om)
        a, b = m.film_report(*s), rey.film_report(*s)
        floor = 0.1 * abs(om) * flow_scale(GROOVED)
        err["inflow"].append(abs(a.inflow_m3_s - b.inflow_m3_s) / max(b.inflow_m3_s, floor))
        err["side"].append(abs(a.side_flow_m3_s - b.side_flow_m3_s) / max(b.side_flow_m3_s, floor))
        err["power"].append(abs(a.friction_power_W - b.friction_power_W) / abs(b.friction_power_W))
    for k, e in err.items():
        assert np.median(e) < 3e-3 and np.max(e) < 2e-2, (k, np.median(e), np.max(e))


def test_a_grooved_map_without_flow_tables_says_to_rebuild_it(tiny, tmp_path):
    # a version 2 file (before the flow tables) still loads and serves the force, but no flows:
    # the registry's per-instance answer names the file and the rebuild
    d = json.loads(tiny.read_text())
    for k in ("Q", "flow_edges_deg", "flow_meaning"):
        d.pop(k)
    d["version"] = 2
    old = tmp_path / "old.json"
    old.write_text(json.dumps(d))
    m = open_map(old, GROOVED)
    assert isinstance(m, GroovedForceMap) and m.table.Q is None
    why = registry.film_flow_of(registry.get("map"), m)
    assert why.startswith(f"the grooved map file {old} has no flow tables")
    assert "rebuild it with `bearing-fmu map" in why
    with pytest.raises(ValueError, match="film_report: the grooved map file .* has no flow tables"):
        m.film_report(0.0, -0.3 * GROOVED.CR, 0.0, 0.0, OMEGA)
    x = (0.1 * GROOVED.CR, -0.3 * GROOVED.CR, 0.0, 0.0, OMEGA)
    assert m.force(*x) == open_map(tiny, GROOVED).force(*x)


@pytest.mark.parametrize("damage, expected", [
    (lambda d: d.__setitem__("Q", d["Q"][:-1]), r"key 'Q' has 3839 numbers, n_eps x n_phi x n_beta x \(1 \+ 4 supply "
                                                r"edges\) = 3840"),
    (lambda d: d["flow_edges_deg"][1].__setitem__(1, 1.0), r"key 'flow_edges_deg' = .* must list the bore's supply "
                                                          r"edges \[theta_deg, sign\] in order: \[\[100.0, 1.0\]"),
    (lambda d: d.pop("flow_edges_deg"), r"missing key 'flow_edges_deg'"),
    (lambda d: d["flow_edges_deg"][0].__setitem__(0, "100"), r"key 'flow_edges_deg' = .* must list the bore's"),
    (lambda d: d.__setitem__("version", 2), r"unknown key\(s\) Q, flow_edges_deg, flow_meaning"),
    (lambda d: d["Q"].__setitem__(7, float("nan")), r"key 'Q' has a non-finite entry"),
])
def test_damaged_flow_tables_are_refused_by_key(tiny, tmp_path, damage, expected):
    damaged_map_refused(json.loads(tiny.read_text()), damage, expected, tmp_path, load_any_map)


@pytest.mark.slow
def test_the_shipped_grooved_map_gives_the_reynolds_film_temperature():
    """The paper bearing with two grooves and ISO VG 46 (bearing_paper_vg46.toml's oil) supplied at
    40 C, at 44 Hz under 16.66 N: the quasi-static film temperature from the shipped map's film report
    at the Reynolds equilibrium equals the Reynolds T_eff (physics.thermal.effective_temperature,
    128 x 16, the map's grid) to 1e-3 K, the root's tolerance (docs/studies/2026-11-26-groove-flows.md:
    the fixed point on the map alone, at three speeds)."""
    from bearing_fmu.internals.scaled import LaggedThermal
    from bearing_fmu.physics.thermal import effective_temperature

    bearing = dataclasses.replace(GROOVED, oil=BearingParams.from_toml(MODELS / "bearing_paper_vg46.toml").oil)
    om = 2 * math.pi * 44.0
    st = effective_temperature(bearing, (0.0, -16.66), om, 313.15, n_theta=128, n_x=16)
    lagged = LaggedThermal(open_map(MODELS / "maps" / "paper_2groove.json", bearing), bearing.oil, 313.15)
    assert lagged.start(st.y_m, st.z_m, 0.0, 0.0, om) == pytest.approx(st.T_eff_K, abs=1e-3)


@pytest.mark.slow
def test_a_scene_with_a_supply_temperature_runs_on_the_grooved_map(tmp_path):
    """The paper rotor on two-groove bearings with ISO VG 46 supplied at 40 C, a run-up 22 -> 30 Hz in
    4 ms on the shipped grooved map (refused before its flow tables: no flows, no run-up with a supply
    temperature): in-process (LaggedThermal) and through the Python FMU's thermal ports the same to
    round-off (the same model), and against the Reynolds run within the map's force error (docs/forcemap.md:
    0.0035 % CR orbit RMS isothermal)."""
    from rotor_host.model.speed import SpeedProfile
    from rotor_host.scenes.scene import load_scene
    from thermal_runs import check_three_runs, three_runs

    oil = (MODELS / "bearing_paper_vg46.toml").read_text().split("[oil]")[1]
    bearing = (MODELS / "bearing_paper_2groove.toml").read_text()
    bearing = "\n".join(line for line in bearing.splitlines() if not line.startswith("mu_Pa_s"))
    (tmp_path / "bearing.toml").write_text(bearing + "\n[oil]" + oil)  # the viscosity law instead of 50 mPa s
    (tmp_path / "rotor.toml").write_text((MODELS / "rotor_paper_2groove.toml").read_text().replace(
        '"bearing_paper_2groove.toml"', '"bearing.toml"'))
    scene_text = (MODELS / "scenes" / "paper_2groove_22hz.toml").read_text().replace(
        'rotor = "../rotor_paper_2groove.toml"', 'rotor = "rotor.toml"\nsupply_temperature_C = 40.0').replace(
        '"../maps/paper_2groove.json"', json.dumps(str(MODELS / "maps" / "paper_2groove.json")))
    (tmp_path / "scene.toml").write_text(scene_text)
    scene = dataclasses.replace(load_scene(tmp_path / "scene.toml"),
                                speed_profile=SpeedProfile((0.0, 0.004), (22.0, 30.0)))
    assert scene.supply_temperature_K == pytest.approx(313.15)
    out = three_runs(scene, "map", {"map": {"map": str(MODELS / "maps" / "paper_2groove.json")}}, 0.004, tmp_path)
    check_three_runs(out, reynolds_rtol=1e-3)
    assert out["direct"]["speed_hz"][-1] == pytest.approx(30.0)

