"""Tilting pads at the film's effective temperature: the pads' film report (friction and flows summed
over the pads), the heat balance solved with it in ``demo`` (``operating_point``), the exactness of a
viscosity change at a fixed journal state (what every thermal path of the host relies on: the run's
``LaggedThermal``, stability's ``ViscosityScaled``) and the refusals where it is not exact.

Where the expected values come from: the heat balance written out from the record's own friction and
flows (P = rho c_p (Q - Qs / 2) dT, T_eff = T_supply + dT / 2: docs/thermal.md), independent of the
root search; the scaling F ~ mu checked against a second bearing built at the other viscosity (massless
pads: every moment scales with mu, so the tilts do not move); the per-pad reports of the assembly,
summed by hand; Lund's reduction with the pads' inertia unscaled, against the bearing built at mu_eff.
"""

import math
from pathlib import Path
from dataclasses import replace

import numpy as np
import pytest

from bearing_fmu.internals.scaled import ViscosityScaled
from bearing_fmu.internals.tilting_pad.operating import operating_point
from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad
from bearing_fmu.physics.oil import KELVIN
from bearing_fmu.physics.params import BearingParams

GRID = dict(n_theta=24, n_x=4)
OMEGA = 2 * math.pi * 50.0
LOAD = (0.0, -2000.0)

PADS = """[bearing]
D_mm = 100.0
L_mm = 50.0
CR_um = 75.0
{mu}
[geometry]
pads = 4
pad_arc_deg = 80.0
pivots_deg = [45, 135, 225, 315]
pivot_offset = 0.5
preload = 0.5
{inertia}
"""
OIL = '\n[oil]\ngrade = "ISO VG 32"\nsupply_C = 45.0\n'


def pads(tmp_path, *, oil=True, inertia=0.0, mu=0.02) -> BearingParams:
    text = PADS.format(mu="" if oil else f"mu_Pa_s = {mu}",
                       inertia=f"pad_inertia_kg_m2 = {inertia}" if inertia else "") + (OIL if oil else "")
    path = tmp_path / f"pads_{oil}_{inertia}.toml"
    path.write_text(text)
    return BearingParams.from_toml(path)


def test_the_film_report_is_the_pads_reports_summed(tmp_path):
    p = pads(tmp_path, oil=False)
    b = TiltingPad(p, **GRID)
    y, z = 3e-6, -20e-6
    rep = b.film_report(y, z, 0.0, 0.0, OMEGA)
    sol = b.pads.equilibrate(y, z, 0.0, 0.0, OMEGA)
    parts = [b.pads.solvers[k].film_report(*b.pads.frame_state(k, (y, z), (0.0, 0.0), sol.delta[k], 0.0), OMEGA)
             for k in range(b.pads.n)]
    assert rep.inflow_m3_s == pytest.approx(sum(r.inflow_m3_s for r in parts), rel=1e-12)
    assert rep.side_flow_m3_s == pytest.approx(sum(r.side_flow_m3_s for r in parts), rel=1e-12)
    assert rep.friction_torque_Nm == pytest.approx(sum(r.friction_torque_Nm for r in parts), rel=1e-12)
    # a still journal: the film's power is its torque times the speed; every pad loses oil at its sides
    assert rep.friction_power_W == pytest.approx(rep.friction_torque_Nm * OMEGA, rel=1e-12)
    assert 0.0 < rep.side_flow_m3_s < rep.inflow_m3_s
    assert rep.load_N == pytest.approx(float(np.hypot(*sol.F)), rel=1e-12)


def test_massless_pads_scale_exactly_with_the_viscosity(tmp_path):
    """Every pad's moment is mu times a function of the state, so the tilts do not move with mu: the force,
    the friction and the coefficients at 3 mu are 3 times those at mu, the flows the same."""
    p = pads(tmp_path, oil=False)
    one, three = TiltingPad(p, **GRID), TiltingPad(p.with_viscosity(3 * p.mu), **GRID)
    state = (4e-6, -25e-6, 1e-4, -2e-4, OMEGA)
    assert np.allclose(three.force(*state), 3 * np.asarray(one.force(*state)), rtol=1e-9, atol=0)
    r1, r3 = one.film_report(*state), three.film_report(*state)
    assert r3.friction_power_W == pytest.approx(3 * r1.friction_power_W, rel=1e-9)
    assert r3.inflow_m3_s == pytest.approx(r1.inflow_m3_s, rel=1e-9)
    scaled = ViscosityScaled(one, 3 * p.mu)
    K3, C3 = three.reduced_coefficients(4e-6, -25e-6, OMEGA, 0.4 * OMEGA)
    Ks, Cs = scaled.reduced_coefficients(4e-6, -25e-6, OMEGA, 0.4 * OMEGA)
    assert np.allclose(Ks, K3, rtol=1e-8, atol=1e-8 * np.abs(K3).max())
    assert np.allclose(Cs, C3, rtol=1e-8, atol=1e-8 * np.abs(C3).max())
    # its equilibrium under a load is the inner bearing's under the load / 3
    assert np.allclose(scaled.journal_equilibrium(LOAD, OMEGA), three.journal_equilibrium(LOAD, OMEGA),
                       rtol=1e-7, atol=1e-12)


def test_pads_with_inertia_reduce_with_their_inertia_unscaled(tmp_path):
    """Lund's reduction has -whirl^2 I on the pads' diagonal, which does not scale with mu: the scaled
    bearing's reduced K, C are the ones of the bearing built at that viscosity, not the reduced K, C times
    the ratio (which would be 2e-3 .. 1e-1 off here)."""
    p = pads(tmp_path, oil=False, inertia=0.05)
    one, two = TiltingPad(p, **GRID), TiltingPad(p.with_viscosity(2 * p.mu), **GRID)
    whirl = 0.9 * OMEGA
    K2, C2 = two.reduced_coefficients(3e-6, -22e-6, OMEGA, whirl)
    Ks, Cs = ViscosityScaled(one, 2 * p.mu).reduced_coefficients(3e-6, -22e-6, OMEGA, whirl)
    assert np.allclose(Ks, K2, rtol=1e-8, atol=1e-8 * np.abs(K2).max())
    assert np.allclose(Cs, C2, rtol=1e-8, atol=1e-8 * np.abs(C2).max())
    K1, _ = one.reduced_coefficients(3e-6, -22e-6, OMEGA, whirl)
    assert np.abs(2 * K1 - K2).max() > 1e-3 * np.abs(K2).max()  # the naive scaling is measurably wrong


def test_demo_record_closes_the_heat_balance(tmp_path):
    p = pads(tmp_path)
    rec = operating_point(p, LOAD, 50.0, **GRID)
    oil = p.oil
    T_s, T_eff, dT = rec["T_supply_K"], rec["T_eff_K"], rec["temperature_rise_K"]
    assert T_s == pytest.approx(45.0 + KELVIN) and T_eff > T_s
    # the record's own friction and flows at mu_eff balance: P = rho c_p (Q - Qs / 2) dT, T_eff = T_s + dT / 2
    rho_c = oil.density * oil.heat_capacity
    assert rec["friction_power_W"] == pytest.approx(rho_c * (rec["inflow_m3_s"] - 0.5 * rec["side_flow_m3_s"]) * dT,
                                                    rel=2e-4)
    assert T_eff == pytest.approx(T_s + 0.5 * dT, abs=2e-3)
    assert rec["mu_eff_Pa_s"] == pytest.approx(oil.mu(T_eff), rel=1e-12)
    # the point is the isoviscous bearing's at mu_eff (the same equilibrium and coefficients)
    iso = operating_point(replace(p.with_viscosity(rec["mu_eff_Pa_s"]), oil=None), LOAD, 50.0, **GRID)
    assert rec["eccentricity"] == pytest.approx(iso["eccentricity"], rel=1e-7)
    assert np.allclose(rec["K_N_m"], iso["K_N_m"], rtol=1e-6, atol=1e-9 * np.abs(iso["K_N_m"]).max())
    # a hotter supply thins the oil: a larger eccentricity
    hot = operating_point(p, LOAD, 50.0, T_supply_K=70.0 + KELVIN, **GRID)
    assert hot["eccentricity"] > rec["eccentricity"] and hot["mu_eff_Pa_s"] < rec["mu_eff_Pa_s"]


# ------------------------------------------------------------------ the host: stability, a run, the refusals

BUNDLED = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
PAD_OIL = '\n[oil]\ngrade = "ISO VG 46"\nsupply_C = 40.0\n'


def oil_pad_machine(tmp_path, inertia: float = 0.0) -> Path:
    """The bundled five-pad paper rotor with an ISO VG 46 oil law in place of its isoviscous mu: its
    rotor file beside the new bearing file, and the 44 Hz scene on them (2 ms, in-process)."""
    text = (BUNDLED / "bearing_paper_5pad_lbp.toml").read_text()
    text = "\n".join(line for line in text.splitlines() if not line.startswith("mu_Pa_s"))
    if inertia:
        text += f"\npad_inertia_kg_m2 = {inertia}\n"
    (tmp_path / "bearing_paper_5pad_lbp.toml").write_text(text + PAD_OIL)
    (tmp_path / "rotor.toml").write_text((BUNDLED / "rotor_paper_5pad_lbp.toml").read_text())
    scene = (BUNDLED / "scenes" / "paper_5pad_lbp_44hz.toml").read_text()
    scene = scene.replace('rotor = "../rotor_paper_5pad_lbp.toml"', 'rotor = "rotor.toml"')
    scene = scene.replace("t_end_s = 0.05", "t_end_s = 0.002").replace("speed_hz = 44.0",
                                                                        "speed_hz = 44.0\nsupply_temperature_C = 40.0")
    (tmp_path / "scene.toml").write_text(scene + '\n[tilting_pad]\nn_theta = 24\nn_x = 4\n')
    return tmp_path


def test_stability_on_pads_at_their_film_temperature(tmp_path):
    """Each speed's point at the pads' effective temperature under the bearing's static load: demo's
    (``operating_point``) T_eff and mu_eff, and its synchronously reduced K at mu_eff."""
    from rotor_host.analyses.linear.inputs import read_rotor
    from rotor_host.analyses.linear.stability import Stability

    rotor, _ = read_rotor(oil_pad_machine(tmp_path) / "rotor.toml")
    analysis = Stability(rotor, "tilting_pad", GRID, T_supply_K=40.0 + KELVIN)
    point, _ = analysis.at(44.0)
    w = analysis.loads[0]
    rec = operating_point(rotor.bearings[0], (float(w[0]), float(w[1])), 44.0, T_supply_K=40.0 + KELVIN, **GRID)
    assert point.T_eff_K[0] == pytest.approx(rec["T_eff_K"], abs=1e-6) and point.T_eff_K[0] > 40.0 + KELVIN
    assert point.mu_eff_Pa_s[0] == pytest.approx(rec["mu_eff_Pa_s"], rel=1e-9)
    K = np.asarray(rec["K_N_m"])
    assert np.allclose(point.K[0], K, rtol=1e-4, atol=1e-6 * np.abs(K).max())


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_a_run_on_pads_carries_the_film_temperature_and_the_pads_states(tmp_path):
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    run = run_scene(load_scene(oil_pad_machine(tmp_path) / "scene.toml"), tmp_path / "out")
    assert run.ok, run.meta.get("message")
    th = run.meta["thermal"][0]
    w = run.meta["bearing_loads_N"][0]
    rec = operating_point(BearingParams.from_toml(tmp_path / "bearing_paper_5pad_lbp.toml"), w, 44.0,
                          T_supply_K=40.0 + KELVIN, **GRID)
    assert th["T_eff_K"] == pytest.approx(rec["T_eff_K"], abs=1e-6)
    assert np.all(np.isfinite(run.arrays["T_eff"])) and abs(run.arrays["T_eff"][0, 0] - rec["T_eff_K"]) < 1e-3


def test_the_lagged_temperature_hands_the_step_to_the_pads():
    """``LaggedThermal`` around an internal with states of its own (the pads' stepper) passes the host's
    step hooks on: without them the pads would be quasi-static under a film temperature."""
    from bearing_fmu.internals.scaled import LaggedThermal
    from bearing_fmu.physics.solver.film import FilmReport
    from bearing_fmu.physics.params import PAPER_BEARING

    class Stepped:
        params = replace(PAPER_BEARING, oil=BearingParams.from_toml(BUNDLED / "bearing_paper_vg46.toml").oil)
        calls = []

        def force(self, *s):
            return 1.0, -2.0

        def film_report(self, *s):
            return FilmReport(0.01, 1.0, 0.5, 0.1, 0.01, 0.0, 1e-6, 5e-7, 2.2)

        def begin_step(self, dt):
            self.calls.append(("begin", dt))

        def accept_step(self):
            self.calls.append(("accept",))

    inner = Stepped()
    lag = LaggedThermal(inner, inner.params.oil, 313.15)
    lag.begin_step(1e-4)
    lag.force(0.0, 0.0, 0.0, 0.0, 100.0)
    lag.accept_step()
    assert inner.calls == [("begin", 1e-4), ("accept",)]


def test_pads_with_inertia_at_a_film_temperature_are_refused_by_name(tmp_path):
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import SceneError, load_scene

    scene = load_scene(oil_pad_machine(tmp_path, inertia=4e-7) / "scene.toml")
    with pytest.raises(SceneError, match=r"supply_temperature_C with tilting pads of inertia \(pad_inertia_kg_m2 = "
                                         r"4e-07\)"):
        run_scene(scene, tmp_path / "out")
