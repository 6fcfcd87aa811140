"""The force map's flow tables: the reduction of the film's side flow and inflow, checked on the
Reynolds solver itself, and the map's film report against the solver's.

Independent references: (1) the Reynolds solver's own film report (``physics.solver.film.field_report``,
validated against Raimondi & Boyd in tests/test_film.py) at states related by the reduction (same
eps and beta, attitudes turned by whole grid cells so the discrete problems are the same one,
speeds of both signs, r from 0.01 to 2500 1/s): the reduced flows J_s, J_i equal to round-off;
(2) the solver's report at random states, the map built from the same grid; (3) the closed-form
friction of the full bore (``film.full_bore_friction``) for the map's friction.
"""

import json
import math

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.map.forcemap import ForceMap
from bearing_fmu.internals.map.tablefile import load_map, save_map
from bearing_fmu.internals.map.tables import state_for, tabulate
from bearing_fmu.physics.solver.film import flow_scale, reduced_flows
from bearing_fmu.physics.params import PAPER_BEARING
from bearing_fmu.physics.solver.reynolds import Reynolds
from conftest import damaged_map_refused

P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0
GRID = {"n_theta": 64, "n_x": 8}


@pytest.fixture(scope="module")
def rey():
    return Reynolds(P, **GRID)


@pytest.fixture(scope="module")
def table():
    return tabulate(P, n_eps=24, n_beta=32, n_phase=1, **GRID)


@pytest.fixture(scope="module")
def tiny():
    return tabulate(P, n_eps=6, n_beta=8, n_phase=1, n_theta=16, n_x=4)


@pytest.mark.parametrize("eps, beta", [(0.3, 0.4), (0.7, -2.5), (0.93, 1.7), (0.05, 3.0)])
def test_the_flow_reduction_holds_for_the_reynolds_solver(rey, eps, beta):
    # side flow r Q0 J_s(eps, beta), inflow |omega Q0 (1 + eps) / 2 - r Q0 J_i(eps, beta)|:
    # four states with other speeds (both signs), r and attitudes give the same (J_s, J_i)
    cell = 2 * math.pi / rey.n_theta
    J = []
    for phi_cells, omega, r in ((-16, 1.0, 1.0), (5, OMEGA, 37.0), (23, -OMEGA, 2.5e3), (40, 3 * OMEGA, 0.01)):
        reports = {w: rey.film_report(*state_for(eps, beta, P, phi=phi_cells * cell, omega=w, r=r), w)
                   for w in (omega, 2.0 * omega)}
        J.append(reduced_flows(P, eps, r, reports))
    np.testing.assert_allclose(J[1:], [J[0]] * 3, rtol=1e-8, atol=1e-10)
    assert J[0][0] > 0.0  # the film leaks at its ends


@pytest.mark.slow
def test_the_map_reports_the_solvers_flows_at_random_states(table, rey):
    # the map built on the solver's grid against the solver; bounds from the measured errors of
    # this coarse 24 x 32 table with margin (docs/forcemap.md, "The flows", has the shipped ones).
    # The flows relative to max(the flow, 0.1 |omega| Q0), as the force's error is relative to S |omega|
    m = ForceMap(P, table)
    rng = np.random.default_rng(7)
    err = {"inflow": [], "side": [], "power": []}
    for _ in range(40):
        eps, phi = rng.uniform(0.0, 0.9), rng.uniform(-math.pi, math.pi)
        om = OMEGA * rng.uniform(0.2, 3.0) * rng.choice([1.0, -1.0])
        vy, vz = rng.uniform(-0.5, 0.5, 2) * abs(om) * P.CR
        y, z = eps * P.CR * math.cos(phi), eps * P.CR * math.sin(phi)
        a, b = m.film_report(y, z, vy, vz, om), rey.film_report(y, z, vy, vz, om)
        floor = 0.1 * abs(om) * flow_scale(P)
        err["inflow"].append(abs(a.inflow_m3_s - b.inflow_m3_s) / max(b.inflow_m3_s, floor))
        err["side"].append(abs(a.side_flow_m3_s - b.side_flow_m3_s) / max(b.side_flow_m3_s, floor))
        err["power"].append(abs(a.friction_power_W - b.friction_power_W) / abs(b.friction_power_W))
        assert set(a.as_dict()) == set(b.as_dict())
    for k, e in err.items():
        assert np.median(e) < 2e-3 and np.max(e) < 2e-2, (k, np.median(e), np.max(e))


@pytest.mark.parametrize("bore", ["full", "two grooves"])
def test_flows_scale_with_speed_and_velocity_together(tiny, bore):
    # the flows are linear in (omega, v) together (both parts: omega Q0 and r Q0; on a grooved map
    # each edge's positive part too, tests/test_groovemap_flows.py)
    m = ForceMap(P, tiny)
    if bore == "two grooves":
        from pathlib import Path

        from bearing_fmu.internals.map.groovemap import GroovedForceMap, tabulate_grooved

        grooved = P.from_toml(Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "bearing_paper_2groove.toml")
        m = GroovedForceMap(grooved, tabulate_grooved(grooved, n_eps=4, n_phi=4, n_beta=4, n_phase=1, n_theta=16,
                                                      n_x=4))
    s = (0.2 * P.CR, -0.5 * P.CR, 0.1 * OMEGA * P.CR, 0.05 * OMEGA * P.CR)
    a = m.film_report(*s, OMEGA)
    b = m.film_report(*s[:2], 3 * s[2], 3 * s[3], 3 * OMEGA)
    assert b.inflow_m3_s == pytest.approx(3 * a.inflow_m3_s, rel=1e-12)
    assert b.side_flow_m3_s == pytest.approx(3 * a.side_flow_m3_s, rel=1e-12)
    assert b.friction_power_W == pytest.approx(9 * a.friction_power_W, rel=1e-12)


def test_a_map_file_without_flow_tables_says_to_rebuild_it(tiny, tmp_path):
    import dataclasses

    new = save_map(tiny, tmp_path / "new.json")
    assert json.loads(new.read_text())["version"] == 3
    assert registry.film_flow_of(registry.get("map"), ForceMap.from_file(new, P)) == ""
    old = save_map(dataclasses.replace(tiny, Q=None, flow_coefficients=None), tmp_path / "old.json")
    d = json.loads(old.read_text())
    assert d["version"] == 1 and "Q" not in d  # what the map files before the flow tables were
    m = ForceMap.from_file(old, P)
    why = registry.film_flow_of(registry.get("map"), m)
    assert f"the map file {old} has no flow tables" in why and "rebuild it with `bearing-fmu map" in why
    with pytest.raises(ValueError, match="film_report: the map file .* has no flow tables"):
        m.film_report(0.0, -0.3 * P.CR, 0.0, 0.0, OMEGA)
    assert m.force(0.0, -0.3 * P.CR, 0.0, 0.0, OMEGA) == ForceMap.from_file(new, P).force(0.0, -0.3 * P.CR, 0.0, 0.0,
                                                                                          OMEGA)


@pytest.mark.parametrize("damage, expected", [
    (lambda d: d["Q"][3][4].__setitem__(1, d["Q"][3][4][1] + 0.01), r"key 'flow_spline' does not reproduce the table 'Q'"),
    (lambda d: d.__setitem__("Q", [[1.0]]), r"key 'Q' has shape \(1, 1\), expected that of 'H'"),
    (lambda d: d.__setitem__("version", 1), r"unknown key\(s\) Q, flow_meaning, flow_spline"),
    (lambda d: d.pop("Q"), r"missing key 'Q'"),
])
def test_damaged_flow_tables_are_refused_by_key(tiny, tmp_path, damage, expected):
    damaged_map_refused(json.loads(save_map(tiny, tmp_path / "good.json").read_text()), damage, expected, tmp_path,
                        load_map)


@pytest.mark.slow
def test_a_scene_with_a_supply_temperature_runs_on_the_map(tmp_path):
    """The shipped 44 Hz scene with ISO VG 46 supplied at 40 C, as a run-up to 60 Hz in 4 ms, on the
    shipped map (its flow tables; refused before: no flows, no run-up with a supply temperature):
    in-process (LaggedThermal) and through the Python FMU's thermal ports the same to round-off (the
    same model); against the Reynolds run within the map's force error (docs/forcemap.md: 0.008 % CR
    orbit RMS isothermal); the quasi-static film temperature at the start (the map's film report at the
    Reynolds equilibrium) equals the Reynolds T_eff to 1e-3 K (the root's tolerance). A version 1 map
    (no flow tables) is refused through the FMU naming the file and the rebuild."""
    import dataclasses
    from pathlib import Path

    from bearing_fmu.internals.scaled import LaggedThermal
    from bearing_fmu.physics.thermal import effective_temperature
    from rotor_host.scenes.run import run_scene
    from rotor_host.model.speed import SpeedProfile
    from rotor_host.scenes.scene import load_scene

    models = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    scene = dataclasses.replace(load_scene(models / "scenes" / "paper_vg46_44hz.toml"),
                                speed_profile=SpeedProfile((0.0, 0.004), (44.0, 60.0)))
    from thermal_runs import check_three_runs, three_runs

    shipped = str(models / "maps" / "paper_bearing.json")
    out = three_runs(scene, "map", {"map": {"map": shipped}}, 0.004, tmp_path)
    check_three_runs(out, reynolds_rtol=1e-3)
    assert out["direct"]["speed_hz"][-1] == pytest.approx(60.0)
    prm = load_scene(models / "scenes" / "paper_vg46_44hz.toml").rotor_path
    from rotor_host.model.rotor import Rotor

    bearing = Rotor.from_toml(prm).bearings[0]
    om = 2 * math.pi * 44.0
    st = effective_temperature(bearing, (0.0, -16.66), om, 313.15, n_theta=128, n_x=16)
    lagged = LaggedThermal(ForceMap.from_file(shipped, bearing), bearing.oil, 313.15)
    assert lagged.start(st.y_m, st.z_m, 0.0, 0.0, om) == pytest.approx(st.T_eff_K, abs=1e-3)
    # a map file from before the flow tables: through the FMU's thermal ports it is refused by name
    old = tmp_path / "old.json"
    d = json.loads(Path(shipped).read_text())
    d["version"] = 1
    for k in ("Q", "flow_spline", "flow_meaning"):
        d.pop(k)
    old.write_text(json.dumps(d))
    from rotor_host.coupling.cosim import FMUError

    with pytest.raises(FMUError, match=r"thermal = true needs .* has no flow tables .*rebuild it with `bearing-fmu map"):
        run_scene(dataclasses.replace(scene.with_internal("map", options={"map": {"map": str(old)}}, t_end_s=0.001),
                                      via="fmu"), tmp_path / "old")
