"""Flexible pivots in a transient (bearing_fmu/internals/tilting_pad/stepping.py: each pad's radial
displacement stepped with its tilt, BDF2, a 2 x 2 Newton per pad): the total derivatives the host's
Newton needs (central differences), a still journal keeping its pads still, the pads' time response
against the reduced (2 + 2N) impedance (the frequency domain: an independent route, which also checks
the full coefficients' damping entries), and stiff pivots converging to rigid ones in a run."""

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
KP = 2e6  # [N/m]: about the film's stiffness of the bundled 5-pad bearing at these loads


def _bearing(kp=KP, inertia=0.0):
    p = BearingParams.from_toml(BUNDLED / "bearing_paper_5pad_lbp.toml")
    return replace(p, geometry=replace(p.geometry, pads=replace(p.geometry.pads, inertia=inertia,
                                                                 pivot_stiffness=kp)))


@pytest.mark.parametrize("inertia", [0.0, 1e-6])
def test_the_stepped_force_on_flexible_pivots_has_the_total_derivatives(inertia):
    tp = TiltingPad(_bearing(inertia=inertia), **GRID)
    tp.force(0.0, -25e-6, 0.0, 0.0, OMEGA)  # static: the state the step starts from
    tp.begin_step(1e-4)
    x = np.array([1e-6, -24e-6, 2e-3, 1e-3])
    _, dq, dv = tp.force_and_jacobian(*x, OMEGA)
    assert np.any(tp.last.u != 0.0) and np.any(tp.last.du != 0.0)
    J = np.zeros((2, 4))
    for i, h in enumerate((1e-9, 1e-9, 1e-6, 1e-6)):
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        J[:, i] = (np.array(tp.force(*xp, OMEGA)) - np.array(tp.force(*xm, OMEGA))) / (2 * h)
    np.testing.assert_allclose(dq, J[:, :2], rtol=0, atol=1e-7 * np.abs(dq).max())
    np.testing.assert_allclose(dv, J[:, 2:], rtol=0, atol=1e-7 * np.abs(dv).max())


def test_a_still_journal_keeps_its_pads_on_their_pivots_still():
    tp = TiltingPad(_bearing(), **GRID)
    F0 = tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA)
    u = tp.last.u.copy()
    for _ in range(3):
        tp.begin_step(1e-4)
        F = tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA)
        tp.accept_step()
    np.testing.assert_allclose(F, F0, rtol=0, atol=1e-9 * np.hypot(*F0))
    np.testing.assert_allclose(tp.stepper.u, u, rtol=0, atol=1e-12 * np.abs(u).max())
    np.testing.assert_allclose(tp.last.pivot_loads(tp.pads.s), KP * tp.stepper.u, rtol=0,
                               atol=1e-9 * np.abs(KP * u).max())


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
@pytest.mark.parametrize("inertia", [0.0, 2e-5])
def test_the_pads_on_flexible_pivots_stepped_in_time_give_the_reduced_impedance(inertia):
    # as tests/test_pad_transient.py for rigid pivots: the journal driven along y at 0.4 x speed, the force's
    # fundamental in the third period against -(K_red + i W C_red) amp, Lund's reduction of the
    # (2 + 2N) x (2 + 2N) coefficients at W (the radial coordinates massless). Measured: 6.3e-4 of |F| at
    # 80 steps a period, 1.58e-4 at 160 (massless; 7.8e-4 with 2e-5 kg m^2): BDF2's second order, while
    # the pivots move the impedance by 41 % (against rigid pivots carrying the same load)
    tp = TiltingPad(_bearing(inertia=inertia), **GRID)
    y0, z0, amp, W = 0.0, -25e-6, 1e-3 * 90e-6, 0.4 * OMEGA
    co = tp.coefficients(y0, z0, OMEGA, W)
    want = -(co["K"] + 1j * W * co["C"]) @ np.array([amp, 0.0])
    rigid = TiltingPad(_bearing(None, inertia), **GRID)
    cr = rigid.coefficients(*rigid.journal_equilibrium(-co["solution"].F, OMEGA), OMEGA, W)
    shift = np.abs(-(cr["K"] + 1j * W * cr["C"]) @ np.array([amp, 0.0]) - want).max()
    assert shift > 0.05 * np.abs(want).max()  # the pivots matter here
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


def _run(tmp_path, kp, t_end):
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    d = tmp_path / f"kp{kp}"
    d.mkdir()
    text = (BUNDLED / "bearing_paper_5pad_lbp.toml").read_text()
    (d / "bearing_paper_5pad_lbp.toml").write_text(text + (f"pivot_stiffness_N_m = {kp!r}\n" if kp else ""))
    shutil.copy(BUNDLED / "rotor_paper_5pad_lbp.toml", d)
    scene = (BUNDLED / "scenes" / "paper_5pad_lbp_44hz.toml").read_text()
    (d / "scene.toml").write_text(scene.replace('"../rotor_paper_5pad_lbp.toml"', '"rotor_paper_5pad_lbp.toml"'))
    sc = load_scene(d / "scene.toml").with_internal("tilting_pad", options={"reynolds": GRID}, t_end_s=t_end)
    res = run_scene(sc, out_dir=d / "out")
    assert res.ok, res.meta
    return np.asarray(res.arrays["y"]), np.asarray(res.arrays["z"])


@pytest.mark.slow
def test_stiff_pivots_converge_to_rigid_pivots_in_a_run(tmp_path):
    # the paper rotor on five pads at 44 Hz with its unbalance, 5 ms: the orbit's RMS distance from the
    # rigid pivots' falls as 1 / k_p (measured 1.42e-3 and 1.42e-4 CR at 1e8 and 1e9 N/m)
    y0, z0 = _run(tmp_path, None, 0.005)
    rms = []
    for kp in (1e8, 1e9):
        y, z = _run(tmp_path, kp, 0.005)
        rms.append(math.sqrt(np.mean((y - y0) ** 2 + (z - z0) ** 2)) / 90e-6)
    assert 8.0 < rms[0] / rms[1] < 12.0, rms
    assert rms[1] < 2e-4, rms
