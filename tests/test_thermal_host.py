"""The effective viscosity in the host: any internal scaled to mu_eff (exact), a scene's supply
temperature in a run, and the stability sweep at mu_eff per speed."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.scaled import ViscosityScaled
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.statics import linearize
from bearing_fmu.physics.thermal import effective_temperature
from rotor_host.analyses.linear.stability import Stability, stability
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import SceneError, load_scene
from thermal_runs import check_native, check_thermal_records, native_equals_python, run_routes

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
VG46_ROTOR = MODELS / "rotor_paper_vg46.toml"
VG46_SCENE = MODELS / "scenes" / "paper_vg46_44hz.toml"


def test_scaling_is_the_solver_at_that_viscosity():
    """F ~ mu at a fixed state: the Reynolds force and Jacobian at mu_eff equal the ones at mu times
    mu_eff / mu to round-off (the active set does not depend on mu), so scaling any internal is exact."""
    om = 2 * math.pi * 44
    state = (30e-6, -40e-6, 0.002, -0.001, om)
    scaled = ViscosityScaled(Reynolds(PAPER_BEARING), 0.031)
    direct = Reynolds(PAPER_BEARING.with_viscosity(0.031))
    assert np.allclose(scaled.force(*state), direct.force(*state), rtol=1e-12, atol=0)
    for a, b in zip(scaled.force_and_jacobian(*state), direct.force_and_jacobian(*state)):
        assert np.allclose(a, b, rtol=1e-10, atol=0)
    assert scaled.params.mu == 0.031 and scaled.counts() == scaled.inner.counts()
    scaled.set_viscosity(PAPER_BEARING.mu)
    assert scaled.force(*state) == Reynolds(PAPER_BEARING).force(*state)
    with pytest.raises(ValueError, match="mu_eff = -1.0 Pa s must be finite and > 0"):
        scaled.set_viscosity(-1.0)

    class NoJacobian:
        params = PAPER_BEARING

        def force(self, *s):
            return (1.0, 2.0)

    assert not hasattr(ViscosityScaled(NoJacobian()), "force_and_jacobian")


def test_stability_at_mu_eff():
    """With a supply temperature every bearing runs at its film's effective temperature at each speed:
    the point's T_eff and mu_eff are effective_temperature's for the bearing's static load, and its
    K is the Reynolds solver's at mu_eff at the journal's position."""
    rotor = Rotor.from_toml(VG46_ROTOR)
    analysis = Stability(rotor, T_supply_K=313.15)
    point, _ = analysis.at(44.0)
    w = analysis.loads[0]
    st = effective_temperature(rotor.bearings[0], (float(w[0]), float(w[1])), 2 * math.pi * 44.0, 313.15)
    assert point.T_eff_K[0] == pytest.approx(st.T_eff_K, abs=1e-9)
    assert point.mu_eff_Pa_s[0] == pytest.approx(st.mu_eff_Pa_s, rel=1e-12)
    K, C = linearize(Reynolds(rotor.bearings[0].with_viscosity(st.mu_eff_Pa_s)), *point.journal[0], 2 * math.pi * 44)
    assert np.allclose(point.K[0], K, rtol=1e-9) and np.allclose(point.C[0], C, rtol=1e-9)
    iso, _ = Stability(rotor).at(44.0)  # isoviscous at the file's supply viscosity: a different film
    assert iso.T_eff_K.size == 0 and not np.allclose(iso.K[0], point.K[0], rtol=1e-3)


def test_stability_refuses_a_supply_temperature_without_oil():
    with pytest.raises(ValueError, match=r"bearing 1 \(node 3\): a supply temperature needs the bearing file's \[oil\]"):
        stability(MODELS / "rotor_paper.toml", [40.0], T_supply_K=313.15)
    with pytest.raises(ValueError, match=r"the supply temperature = 473.15 K \(200 C\) is outside"):
        stability(VG46_ROTOR, [40.0], T_supply_K=473.15)


def test_scene_supply_temperature_runs_at_mu_eff(tmp_path):
    """The shipped scene at 44 Hz for 5 ms: its json records each bearing's T_eff, mu_eff, P_loss and
    flows, the same as effective_temperature under the bearing's static load; the npz their history
    at every recorded time (the inflow too, in-process), the json their start, end and largest value;
    the first record (the state at t = 0) is the quasi-static start to the root's 1 mK."""
    scene = load_scene(VG46_SCENE)
    assert scene.supply_temperature_K == pytest.approx(313.15)
    run = run_scene(scene.with_internal("reynolds", t_end_s=0.005), tmp_path)
    assert run.ok
    meta = json.loads(run.json.read_text())
    w = meta["bearing_loads_N"][0]
    st = effective_temperature(Rotor.from_toml(VG46_ROTOR).bearings[0], w, 2 * math.pi * 44.0, 313.15,
                               name="bearing 1 (node 3)")
    th = meta["thermal"][0]
    assert th["T_eff_K"] == pytest.approx(st.T_eff_K, abs=1e-9) and th["mu_eff_Pa_s"] == st.mu_eff_Pa_s
    assert th["P_loss_W"] == pytest.approx(st.report.friction_power_W, rel=1e-12)
    # the journal starts at the static equilibrium at mu_eff: where effective_temperature found it
    eq = np.array(meta["equilibrium_eccentricity"])
    assert eq[0] == pytest.approx(math.hypot(st.y_m, st.z_m) / PAPER_BEARING.CR, rel=1e-3)
    a = np.load(run.npz)
    for name, key in (("T_eff", "T_eff_K"), ("mu_eff", "mu_eff_Pa_s"), ("P_loss", "P_loss_W"),
                      ("Q_side", "Q_side_m3_s"), ("Q_in", "Q_in_m3_s")):
        assert a[name].shape == a["Fy"].shape == (51, 2) and np.all(np.isfinite(a[name])), name
        assert th["over_time"][key] == {"start": a[name][0, 0], "end": a[name][-1, 0], "max": a[name][:, 0].max()}
    assert abs(a["T_eff"][0, 0] - st.T_eff_K) <= 1e-3 and a["mu_eff"][0, 0] == pytest.approx(st.mu_eff_Pa_s, rel=1e-4)
    assert a["P_loss"][0, 0] == pytest.approx(st.report.friction_power_W, rel=1e-3)
    assert a["Q_in"][0, 0] == pytest.approx(st.report.inflow_m3_s, rel=1e-3)
    # the unbalance moves the journal off the static point: the film's power and flows follow it
    assert np.ptp(a["Q_side"][:, 0]) > 1e-3 * a["Q_side"][0, 0]


def test_a_scaled_internal_hands_no_unscaled_compiled_force():
    """The compiled loop calls an internal's compiled force, which knows nothing of the viscosity
    scale: a scaled internal must not offer its inner's (formerly it did, through __getattr__, and a
    run held at mu_eff on the linear model integrated at the file's viscosity)."""
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.registry import Context

    inner = registry.create("linear", PAPER_BEARING, {}, Context(load=(0.0, -16.66), omega=2 * math.pi * 44.0))
    assert inner.compiled_force() is not None
    assert getattr(ViscosityScaled(inner, 0.5 * PAPER_BEARING.mu), "compiled_force", None) is None


@pytest.mark.slow
def test_a_run_held_at_mu_eff_stays_at_its_equilibrium(tmp_path):
    """The linear model (no film flows: held at the start's mu_eff) under the shipped scene without
    its unbalance: the rotor starts at its static equilibrium at mu_eff and stays there (to 1e-6 of
    the clearance; at the file's viscosity the film force is 6 % off and the journal moves by 1e-2);
    it records no thermal arrays (nothing changes: the json's start values hold)."""
    import dataclasses

    scene = dataclasses.replace(load_scene(VG46_SCENE).with_internal("linear", t_end_s=0.005), unbalances=[])
    run = run_scene(scene, tmp_path)
    assert run.ok and "T_eff" not in run.arrays and "over_time" not in run.meta["thermal"][0]
    ecc = run.arrays["eccentricity"]
    assert np.max(np.abs(ecc - ecc[0])) < 1e-6


@pytest.mark.parametrize("edit, match", [
    (lambda t: t.replace('via = "direct"', 'via = "fmu"\nfmu_kind = "native"').replace('internal = "reynolds"',
                                                                                     'internal = "linear"'),
     r"supply_temperature_C = 40 through an FMU's thermal ports needs an internal with the film's friction and "
     r"flows \(reynolds, taylor, map, tilting_pad\); internal = 'linear'"),
    (lambda t: t.replace('via = "direct"', 'via = "fmu"').replace('internal = "reynolds"', 'internal = "linear"'),
     r"supply_temperature_C = 40 through an FMU's thermal ports needs an internal with the film's friction and "
     r"flows \(reynolds, taylor, map, tilting_pad\); internal = 'linear': a linear model holds the force about one point"),
    (lambda t: t.replace("speed_hz = 44.0", "[speed_profile]\ntimes_s = [0.0, 0.1]\nspeeds_hz = [40.0, 44.0]\n")
     .replace('internal = "reynolds"', 'internal = "linear"'),
     r"supply_temperature_C = 40 with a \[speed_profile\] needs an internal with the film's friction and flows"),
    (lambda t: t.replace("rotor_paper_vg46.toml", "rotor_paper.toml"),
     r"supply_temperature_C = 40: bearing 1 \(node 3\) has no \[oil\] table"),
    (lambda t: t.replace("supply_temperature_C = 40.0", "supply_temperature_C = 190.0"),
     r"bearing 1: Oil .*supply_temperature_C = 463.15 K \(190 C\) is outside"),
])
def test_scene_supply_temperature_refused_by_name(tmp_path, edit, match):
    text = edit(VG46_SCENE.read_text())
    # the speed profile's table must come after the top-level keys
    if "[speed_profile]" in text:
        head, _, tail = text.partition("[speed_profile]")
        prof, _, rest = tail.partition("\n\n")
        text = head + rest + "\n[speed_profile]" + prof + "\n"
    f = tmp_path / "s.toml"
    f.write_text(text.replace('rotor = "../', f'rotor = "{MODELS}/'))
    with pytest.raises(SceneError, match=match):
        load_scene(f)


def test_shipped_oil_files_load():
    b = BearingParams.from_toml(MODELS / "bearing_paper_vg46.toml")
    assert b.oil is not None and b.mu == pytest.approx(46e-6 * 861.0, rel=1e-12)
    assert all(p.oil is not None for p in Rotor.from_toml(VG46_ROTOR).bearings)


def _runs(tmp_path, scene, t_end_s):
    """The scene run in-process and through the Python FMU (its thermal ports): their npz arrays."""
    import dataclasses

    out = {}
    for via in ("direct", "fmu"):
        run = run_scene(dataclasses.replace(scene.with_internal("reynolds", t_end_s=t_end_s), via=via), tmp_path / via)
        assert run.ok, run
        out[via] = np.load(run.npz)
    return out["direct"], out["fmu"]


@pytest.mark.slow
def test_fmu_run_with_a_supply_temperature_equals_the_direct_run(tmp_path):
    """The shipped 44 Hz scene through the FMU's thermal ports (T_supply in, T_eff a state of the FMU,
    restored at every Newton iteration) equals the in-process run (the same lagged film temperature,
    LaggedThermal) to round-off, and differs from the run at the file's isothermal viscosity."""
    import dataclasses

    scene = load_scene(VG46_SCENE)
    direct, fmu = _runs(tmp_path, scene, 0.004)
    for key in ("y", "z", "Fy", "Fz"):
        scale = np.max(np.abs(direct[key]))
        assert np.max(np.abs(fmu[key] - direct[key])) <= 1e-9 * scale, key
    check_thermal_records({"direct": direct, "fmu": fmu})  # the FMU's outputs as LaggedThermal has them
    iso = run_scene(dataclasses.replace(scene.with_internal("reynolds", t_end_s=0.004), supply_temperature_K=None),
                    tmp_path / "iso")
    iso_ecc = np.load(iso.npz)["eccentricity"]  # a thinner oil: the journal runs more eccentric
    assert np.min(direct["eccentricity"][0] - iso_ecc[0]) > 1e-3


@pytest.mark.slow
@pytest.mark.native
def test_native_fmu_run_with_a_supply_temperature_equals_the_python_fmu_run(tmp_path):
    """The shipped 44 Hz scene through the native Reynolds FMU's thermal ports (its film report, oil
    law and lagged film temperature in C) equals the run through the Python FMU to round-off."""
    native_equals_python(load_scene(VG46_SCENE).with_internal("reynolds", t_end_s=0.003), tmp_path)


@pytest.mark.slow
@pytest.mark.native
def test_native_map_fmu_run_with_a_supply_temperature(tmp_path):
    """The shipped 44 Hz scene on the shipped paper map (version 3: its flow table) through the native
    map FMU's thermal ports (refused before: its film report was not in C) equals the run through the
    Python FMU to round-off (1e-12 of each signal's largest value: the same film report, oil law and
    lag, tests/test_native_fmu_thermal.py), and the in-process run (LaggedThermal on the map
    internal) within 1e-9, the tolerance of the Reynolds comparison above (the FMU restores T_eff
    at every Newton iteration; the host's state is its own). Measured over 3 ms: the native and the
    Python FMU run the same bits; the in-process run within 4e-11 of the largest force (the run at the
    file's isothermal viscosity differs by 1.4 % of the largest y)."""
    scene = load_scene(VG46_SCENE).with_internal("map", options={"map": {"map": MODELS / "maps" / "paper_bearing.json"}},
                                                 t_end_s=0.003)
    out = run_routes(scene, tmp_path)
    check_native(out, 1e-12, 1e-9)
    check_thermal_records(out)  # T_eff, mu_eff, P_loss, Q_side: the FMUs' outputs as LaggedThermal's
    check_thermal_records({k: out[k] for k in ("python", "native")}, 1e-12, reference="python")
    # a map file without flow tables (version 1): the native FMU refuses thermal at initialisation, by name
    from rotor_host.coupling.cosim import FMUError

    data = json.loads((MODELS / "maps" / "paper_bearing.json").read_text())
    for key in ("Q", "flow_spline", "flow_meaning"):
        data.pop(key)
    old = tmp_path / "v1.json"
    old.write_text(json.dumps({**data, "version": 1}))
    v1 = scene.with_internal("map", options={"map": {"map": old}}, via="fmu", fmu_kind="native")
    with pytest.raises(FMUError, match=r"which internal = 'map' does not have \(the map file .*v1.json has no flow "
                                       r"tables \(format version 1"):
        run_scene(v1, tmp_path / "v1")


@pytest.mark.slow
def test_run_up_with_a_supply_temperature(tmp_path):
    """A run-up 44 -> 60 Hz in 5 ms with the oil supplied at 40 C (refused before): in-process and
    through the FMU the same to round-off (the film temperature lags the heat balance in both)."""
    import dataclasses

    from rotor_host.model.speed import SpeedProfile

    scene = dataclasses.replace(load_scene(VG46_SCENE), speed_profile=SpeedProfile((0.0, 0.005), (44.0, 60.0)))
    direct, fmu = _runs(tmp_path, scene, 0.005)
    for key in ("y", "z", "Fy", "Fz"):
        assert np.max(np.abs(fmu[key] - direct[key])) <= 1e-9 * np.max(np.abs(direct[key])), key
    assert direct["speed_hz"][-1] == pytest.approx(60.0)
    check_thermal_records({"direct": direct, "fmu": fmu})
    # the film heats with the speed (5 ms is a fraction of its 30 ms residence time: it lags)
    assert np.all(np.diff(direct["P_loss"][::10], axis=0) > 0) and np.all(direct["T_eff"][-1] > direct["T_eff"][0])


@pytest.mark.slow
def test_t_eff_settles_on_the_quasi_static_heat_balance(tmp_path):
    """The lag's fixed point is the quasi-static balance: the shipped scene on the shipped map (its
    flow tables) without unbalance, the speed raised from 20 to 30 Hz over 0.3 s and then held for
    0.6 s (11 residence times at 30 Hz, 53 ms; below the 43 Hz threshold: the journal settles at its
    static equilibrium, slowly raised so that it does not whirl). At the end the recorded T_eff equals
    ``physics.thermal.effective_temperature`` at 30 Hz under the bearing's load on the same map (an
    independent solution: Brent on T_supply + k dT(mu(T)) - T at the equilibrium found at each
    viscosity, its tolerance set to 1e-7 K) to 1e-5 K (measured 1.1e-6 K), mu_eff and P_loss to 1e-5
    (5e-8, 1.5e-6), the side flow to 1e-3 (8e-5: a velocity of 1e-7 m/s is left, and the squeeze
    moves the flows), having risen by 0.28 K from the quasi-static start at 20 Hz (the first record)."""
    import dataclasses

    from bearing_fmu.internals.map.forcemap import ForceMap
    from rotor_host.model.speed import SpeedProfile

    shipped = MODELS / "maps" / "paper_bearing.json"
    scene = dataclasses.replace(load_scene(VG46_SCENE).with_internal("map", options={"map": {"map": shipped}},
                                                                     t_end_s=0.9, dt_s=5e-4),
                                unbalances=[], speed_hz=20.0, speed_profile=SpeedProfile((0.0, 0.3), (20.0, 30.0)))
    run = run_scene(scene, tmp_path)
    assert run.ok, run.meta["message"]
    a = run.arrays
    bearing = Rotor.from_toml(VG46_ROTOR).bearings[0]
    load = run.meta["bearing_loads_N"][0]
    st = {f: effective_temperature(bearing, load, 2 * math.pi * f, 313.15, tol_K=1e-7,
                                   internal=ForceMap.from_file(shipped, bearing)) for f in (20.0, 30.0)}
    assert abs(a["T_eff"][0, 0] - st[20.0].T_eff_K) < 1e-4
    assert a["T_eff"][-1, 0] - a["T_eff"][0, 0] > 0.25
    assert abs(a["T_eff"][-1, 0] - st[30.0].T_eff_K) < 1e-5
    assert a["mu_eff"][-1, 0] == pytest.approx(st[30.0].mu_eff_Pa_s, rel=1e-5)
    assert a["P_loss"][-1, 0] == pytest.approx(st[30.0].report.friction_power_W, rel=1e-5)
    assert a["Q_side"][-1, 0] == pytest.approx(st[30.0].report.side_flow_m3_s, rel=1e-3)


def test_thermal_lines_say_how_hot_and_how_much_power():
    from rotor_host.scenes.thermal import thermal_lines

    arrays = {"speed_hz": np.array([20.0, 25.0, 30.0]), "bearing_nodes": np.array([3, 9]),
              "T_eff": 273.15 + np.array([[40.0, 41.0], [40.5, 41.5], [40.25, 41.75]]),
              "P_loss": np.array([[2.0, 2.0], [3.0, 3.0], [4.5, 4.5]])}
    assert thermal_lines(arrays)[1] == ("bearing 2 (node 9) oil from 20.0 to 30.0 Hz: T_eff 41.00 -> 41.75 C (max "
                                        "41.75 C), friction power 2 -> 4.5 W (max 4.5 W)")
    arrays["speed_hz"] = np.full(3, 44.0)
    assert thermal_lines(arrays)[0].startswith("bearing 1 (node 3) oil: T_eff 40.00 -> 40.25 C (max 40.50 C)")
    assert thermal_lines({"speed_hz": arrays["speed_hz"]}) == []


@pytest.mark.slow
def test_the_waterfall_draws_t_eff_against_speed(tmp_path, monkeypatch):
    """A run-up's waterfall with the thermal arrays has a panel of each bearing's T_eff [C] against
    the speed, the curves the run's (a synthetic 10 -> 30 Hz run: no integration)."""
    from rotor_host.analyses import waterfall

    t = np.arange(0.0, 1.0 + 5e-4, 1e-3)
    speed = 10.0 + 20.0 * t
    angle = 2 * math.pi * np.cumsum(speed) * 1e-3
    y = 1e-6 * np.stack([np.cos(angle)] * 2, axis=1)
    z = 1e-6 * np.stack([np.sin(angle)] * 2, axis=1)
    T = 313.15 + np.stack([0.05 * speed, 0.06 * speed], axis=1)
    arrays = {"t": t, "speed_hz": speed, "nodes": np.array([3, 9]), "bearing_nodes": np.array([3, 9]), "y": y,
              "z": z, "T_eff": T}
    figs = []
    monkeypatch.setattr(waterfall, "save_figure", lambda fig, path: figs.append(fig) or path)
    waterfall.plot_waterfall(arrays, tmp_path / "w.png", nodes=[3])
    ax = next(ax for ax in figs[0].axes if ax.get_ylabel() == "T_eff [C]")
    assert ax.get_xlabel() == "shaft speed [Hz]" and len(ax.lines) == 2
    np.testing.assert_allclose(ax.lines[1].get_ydata(), T[:, 1] - 273.15)
    np.testing.assert_allclose(ax.lines[1].get_xdata(), speed)
    waterfall.pyplot().close(figs[0])


@pytest.mark.slow
def test_sweep_and_compare_carry_t_eff(tmp_path, capsys):
    """`rotor-host sweep` (2 speeds, its own cluster of 1 worker) and `rotor-host compare` (the map
    against Reynolds) of the shipped scene with its supply temperature: each run's npz has the
    thermal arrays; the sweep's rows and table give each bearing's mean T_eff and P_loss over the
    settled part, the compare's rows and table the hottest T_eff and the power at the end and the
    T_eff error against the reference (the map's T_eff within 1e-3 K of the solver's: its force and
    flow tables' error, tests/test_forcemap_flows.py). The faster run is the hotter film."""
    from rotor_host.cli import main

    shipped = MODELS / "maps" / "paper_bearing.json"
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(VG46_SCENE.read_text().replace('rotor = "../', f'rotor = "{MODELS}/').replace(
        'internal = "reynolds"', 'internal = "map"') + f'\n[map]\nmap = "{shipped}"\n')
    out = tmp_path / "sweep"
    assert main(["sweep", str(scene_file), "--speeds-hz", "30", "40", "--t-end", "0.004", "--workers", "1",
                 "--quiet", "--out", str(out)]) == 0
    summary = json.loads((out / "sweep_s_map.json").read_text())
    rows = {r["speed_hz"]: r for r in summary["rows"]}
    for f, row in rows.items():
        a = np.load(out / f"s_map_{f:g}hz.npz")
        late = a["t"] >= 0.002 - 1e-12
        for k, b in enumerate(row["bearings"]):
            assert b["T_eff_K"] == pytest.approx(a["T_eff"][late, k].mean(), rel=1e-12)
            assert b["P_loss_W"] == pytest.approx(a["P_loss"][late, k].mean(), rel=1e-12)
    assert rows[40.0]["bearings"][0]["T_eff_K"] > rows[30.0]["bearings"][0]["T_eff_K"] + 0.1
    md = (out / "sweep_s_map.md").read_text()
    assert "| T_eff [C] | P_loss [W] |" in md and f"| {rows[40.0]['bearings'][0]['T_eff_K'] - 273.15:.2f} |" in md

    capsys.readouterr()
    cmp_out = tmp_path / "compare"
    assert main(["compare", str(scene_file), "--internals", "map", "--ref-grid", "", "--t-end", "0.003", "--quiet",
                 "--out", str(cmp_out)]) == 0
    data = json.loads((cmp_out / "compare_s.json").read_text())
    ref, row = data["rows"]
    a = np.load(cmp_out / "s_map.npz")
    assert row["T_eff_end_C"] == pytest.approx(a["T_eff"][-1].max() - 273.15, rel=1e-12)
    assert row["P_loss_end_W"] == pytest.approx(a["P_loss"][-1].sum(), rel=1e-12)
    assert ref["T_eff_error_K"] == 0.0 and 0.0 < row["T_eff_error_K"] < 1e-3
    assert "| T_eff end [C] | T_eff error max [K] | P_loss end [W] |" in (cmp_out / "compare_s.md").read_text()
