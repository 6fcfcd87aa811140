"""The pads' states in a transient (bearing_fmu/internals/tilting_pad/stepping.py through the host's
step hooks): exact derivatives for the host's Newton, the pads' time response against the reduced
impedance (frequency domain, an independent route), and light pads converging to massless ones in
a run of the paper rotor on five pads."""

from __future__ import annotations

import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad
from bearing_fmu.physics.params import BearingParams

BUNDLED = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
GRID = dict(n_theta=24, n_x=4)
OMEGA = 2 * math.pi * 44.0


def _bearing(inertia=0.0):
    p = BearingParams.from_toml(BUNDLED / "bearing_paper_5pad_lbp.toml")
    return replace(p, geometry=replace(p.geometry, pads=replace(p.geometry.pads, inertia=inertia)))


@pytest.mark.parametrize("inertia", [0.0, 1e-6])
def test_the_stepped_force_has_the_total_derivatives_the_host_needs(inertia):
    # central differences of the force over one step (the pads re-solved at each perturbed journal)
    tp = TiltingPad(_bearing(inertia), **GRID)
    tp.force(0.0, -25e-6, 0.0, 0.0, OMEGA)  # static: the state the step starts from
    tp.begin_step(1e-4)
    x = np.array([1e-6, -24e-6, 2e-3, 1e-3])
    _, dq, dv = tp.force_and_jacobian(*x, OMEGA)
    J = np.zeros((2, 4))
    for i, h in enumerate((1e-9, 1e-9, 1e-6, 1e-6)):
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        J[:, i] = (np.array(tp.force(*xp, OMEGA)) - np.array(tp.force(*xm, OMEGA))) / (2 * h)
    np.testing.assert_allclose(dq, J[:, :2], rtol=0, atol=1e-7 * np.abs(dq).max())
    np.testing.assert_allclose(dv, J[:, 2:], rtol=0, atol=1e-7 * np.abs(dv).max())


def test_a_still_journal_keeps_its_pads_still_and_a_static_call_stays_memoryless():
    tp = TiltingPad(_bearing(), **GRID)
    F0 = tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA)
    delta = tp.last.delta.copy()
    for _ in range(3):
        tp.begin_step(1e-4)
        F = tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA)
        tp.accept_step()
    np.testing.assert_allclose(F, F0, rtol=0, atol=1e-9 * np.hypot(*F0))
    np.testing.assert_allclose(tp.stepper.delta, delta, rtol=0, atol=1e-12)
    tp.begin_step(0.0)
    assert tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA) == pytest.approx(F0, rel=1e-12)


@pytest.mark.parametrize("inertia", [0.0, 2e-5])
def test_the_pads_stepped_in_time_give_the_reduced_impedance(inertia):
    # the journal driven along y at 0.4 x speed through the host's hooks (BDF2 on the pads): the force's
    # fundamental in the third period against -(K_red + i W C_red) amp, Lund's reduction at W with
    # the -W^2 I term (the frequency domain: an independent route). Measured: 5.4e-4 of |F| at 80 steps a
    # period, 1.35e-4 at 160 (massless; 6.3e-4, 1.6e-4 with 2e-5 kg m^2): BDF2's second order
    tp = TiltingPad(_bearing(inertia), **GRID)
    y0, z0, amp, W = 0.0, -25e-6, 1e-3 * 90e-6, 0.4 * OMEGA
    co = tp.coefficients(y0, z0, OMEGA, W)
    want = -(co["K"] + 1j * W * co["C"]) @ np.array([amp, 0.0])
    tp.force(y0 + amp, z0, 0.0, 0.0, OMEGA)
    n_per, periods = 80, 3
    dt = 2 * math.pi / W / n_per
    got = np.zeros(2, complex)
    for i in range(1, n_per * periods + 1):
        t = i * dt
        tp.begin_step(dt)
        F = np.array(tp.force(y0 + amp * math.cos(W * t), z0, -amp * W * math.sin(W * t), 0.0, OMEGA))
        tp.accept_step()
        if i > n_per * (periods - 1):
            got += 2.0 / n_per * F * np.exp(-1j * W * t)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-3 * np.abs(want).max())


def test_the_variable_step_bdf2_is_exact_for_a_quadratic_motion():
    # BDF2 of any step ratio integrates a quadratic exactly: x(t) = 3 + 2 t - 5 t^2 for the tilts, its
    # rate for the rates, over steps 1e-4 then 0.37e-4 and 2.5e-4 (a step cut, a step grown)
    from bearing_fmu.internals.tilting_pad.stepping import PadStepper

    def x(t):
        return 3.0 + 2.0 * t - 5.0 * t * t

    def xdot(t):
        return 2.0 - 10.0 * t

    st = PadStepper(TiltingPad(_bearing(), **GRID).pads)
    for h_prev, h in ((1e-4, 0.37e-4), (1e-4, 2.5e-4)):
        t0 = 1e-3
        st.prev = (np.full(5, x(t0 - h_prev)), np.full(5, xdot(t0 - h_prev)), h_prev)
        st.delta, st.rate = np.full(5, x(t0)), np.full(5, xdot(t0))
        st.begin_step(h)
        b, hd, hw = st.coefficients()
        np.testing.assert_allclose(hd + b * xdot(t0 + h), x(t0 + h), rtol=1e-13)
        np.testing.assert_allclose(hw + b * (-10.0), xdot(t0 + h), rtol=1e-13)


def test_accepted_steps_keep_the_gap_to_their_history():
    # the stepper's own sequence: steps of 1e-4 then 0.37e-4 accepted, the next of 2.5e-4 is BDF2 over
    # the last two committed states, 0.37e-4 apart (not the step before them): exact for a quadratic
    from bearing_fmu.internals.tilting_pad.stepping import PadStepper

    def x(t):
        return 3.0 + 2.0 * t - 5.0 * t * t

    def xdot(t):
        return 2.0 - 10.0 * t

    st = PadStepper(TiltingPad(_bearing(), **GRID).pads)
    t = 1e-3
    st.delta, st.rate, st.dt_committed = np.full(5, x(t)), np.full(5, xdot(t)), 1e-4  # a state after a step
    for h in (1e-4, 0.37e-4):
        st.begin_step(h)
        t += h
        st.trial = (np.full(5, x(t)), np.full(5, xdot(t)))
        st.accept()
    assert st.prev[2] == 0.37e-4
    st.begin_step(2.5e-4)
    b, hd, hw = st.coefficients()
    np.testing.assert_allclose(hd + b * xdot(t + 2.5e-4), x(t + 2.5e-4), rtol=1e-13)
    np.testing.assert_allclose(hw + b * (-10.0), xdot(t + 2.5e-4), rtol=1e-13)


def _run(tmp_path, inertia, t_end):
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    d = tmp_path / f"I{inertia:g}"
    d.mkdir()
    text = (BUNDLED / "bearing_paper_5pad_lbp.toml").read_text()
    (d / "bearing_paper_5pad_lbp.toml").write_text(text + (f"pad_inertia_kg_m2 = {inertia!r}\n" if inertia else ""))
    shutil.copy(BUNDLED / "rotor_paper_5pad_lbp.toml", d)
    scene = (BUNDLED / "scenes" / "paper_5pad_lbp_44hz.toml").read_text()
    (d / "scene.toml").write_text(scene.replace('"../rotor_paper_5pad_lbp.toml"', '"rotor_paper_5pad_lbp.toml"'))
    sc = load_scene(d / "scene.toml").with_internal("tilting_pad", options={"reynolds": GRID}, t_end_s=t_end)
    res = run_scene(sc, out_dir=d / "out")
    assert res.ok, res.meta
    return np.asarray(res.arrays["y"]), np.asarray(res.arrays["z"])


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_light_pads_converge_to_massless_pads_in_a_run(tmp_path):
    # the paper rotor on five pads at 44 Hz with its unbalance, 5 ms: the orbit's RMS distance from
    # the massless pads' falls as the inertia (first order in I: the pad's inertial moment I ddot
    # delta against its film's); measured 5.4e-4, 5.6e-5, 5.6e-6 CR at 1e-5, 1e-6, 1e-7 kg m^2 over
    # 10 ms (a 5 mm steel pad of this bearing has about 4e-7 kg m^2)
    y0, z0 = _run(tmp_path, 0.0, 0.005)
    rms = []
    for inertia in (1e-6, 1e-7):
        y, z = _run(tmp_path, inertia, 0.005)
        rms.append(math.sqrt(np.mean((y - y0) ** 2 + (z - z0) ** 2)) / 90e-6)
    assert 8.0 < rms[0] / rms[1] < 12.0, rms
    assert rms[1] < 1e-5, rms
