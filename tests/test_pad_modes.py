"""The pads' coordinates in the eigenproblem (rotor_host.analyses.linear.pad_modes) against the
reduction at each mode's own frequency, iterated to its fixed point (the independent route: a
Schur complement of the bearing's (2 + N) x (2 + N) impedance, the rotor solved alone), and against
the synchronously reduced analysis where a mode whirls at 1x."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from rotor_host.analyses.linear import pad_modes as pm
from rotor_host.analyses.linear.stability import Stability
from rotor_host.analyses.linear.inputs import read_rotor

ROTOR = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "rotor_paper_5pad_lbp.toml"
GRID = {"n_theta": 24, "n_x": 4}


@pytest.fixture(scope="module")
def analysis():
    rotor, _ = read_rotor(ROTOR)
    return Stability(rotor, "tilting_pad", GRID)


def _full(analysis, speed_hz, inertia=None):
    om = 2 * math.pi * speed_hz
    q = analysis.equilibrium(om)
    blocks = pm.pad_blocks(analysis.internals, analysis.pairs, q, om)
    if inertia is not None:
        blocks = [replace(b, inertia=np.full_like(b.inertia, inertia)) for b in blocks]
    lam, _ = pm.eigenvalues(analysis.rotor, om, blocks)
    return om, q, blocks, lam


def _lightly_damped(freq_hz, log_dec):
    return [complex(-d * f, 2 * math.pi * f) for f, d in zip(freq_hz, log_dec) if d < 1.0][:4]


@pytest.mark.parametrize("inertia", [None, 2e-6])
def test_every_mode_is_the_fixed_point_of_the_reduction_at_its_own_eigenvalue(analysis, inertia):
    # from each lightly damped mode of the synchronous analysis, the reduction at the mode's complex
    # eigenvalue, iterated, lands on an eigenvalue of the full (2 + N per bearing) model to 1e-9
    # (massless pads: the first-order pad rows; 2e-6 kg m^2: the second-order ones)
    om, q, blocks, lam = _full(analysis, 60.0, inertia)
    K, C = pm.reduced_coefficients(blocks, complex(0.0, om))  # synchronous (Lund at W = omega)
    freq, ld, _ = analysis.rotor.modes(om, K, C)
    starts = _lightly_damped(freq, ld)
    assert len(starts) == 4
    for s0 in starts:
        s, its = pm.iterate_mode(analysis.rotor, om, blocks, s0)
        assert its < 30
        assert np.min(np.abs(lam - s)) <= 1e-9 * abs(s), (s0, s)
    # and the reduction is not the answer at the synchronous frequency: the 22 Hz mode's damping moves
    f_full, ld_full, _ = pm.modes(analysis.rotor, om, blocks)
    i, j = np.argmin(ld), np.argmin(ld_full)
    assert abs(f_full[j] - freq[i]) < 0.1 and abs(ld_full[j] - ld[i]) > 0.1 * abs(ld_full[j])


def test_light_pads_tend_to_massless_pads(analysis):
    # the second-order pad rows with a vanishing inertia give the first-order (massless) rows' modes
    om, _, blocks, _ = _full(analysis, 40.0)
    f0, l0, _ = pm.modes(analysis.rotor, om, blocks)
    f1, l1, _ = pm.modes(analysis.rotor, om, [replace(b, inertia=np.full_like(b.inertia, 1e-13)) for b in blocks])
    light = l0 < 1.0
    np.testing.assert_allclose(f1[: f0.size][light], f0[light], rtol=1e-6)
    np.testing.assert_allclose(l1[: f0.size][light], l0[light], rtol=1e-5)


@pytest.mark.slow  # a fit, a figure or a process end to end (about 1 s): the full suite's, out of the quick loop
def test_the_synchronous_analysis_is_lunds_fixed_point_where_the_mode_whirls_at_1x(analysis):
    # Lund's reduction at the real whirl frequency, iterated per mode: at the speed where the first
    # mode whirls at the shaft speed, its fixed point is the synchronously reduced analysis's mode
    from scipy.optimize import brentq

    def lund(speed_hz):
        om, _, blocks, _ = _full(analysis, speed_hz)
        K, C = pm.reduced_coefficients(blocks, complex(0.0, om))
        freq, ld, _ = analysis.rotor.modes(om, K, C)
        s, _ = pm.iterate_mode(analysis.rotor, om, blocks, _lightly_damped(freq, ld)[0], damped=False)
        return s, freq, ld

    speed = brentq(lambda sp: lund(sp)[0].imag / (2 * math.pi) - sp, 20.0, 25.0, xtol=1e-10)
    s, freq, ld = lund(speed)
    f_sync, ld_sync = freq[0], ld[0]
    assert s.imag / (2 * math.pi) == pytest.approx(f_sync, rel=1e-8)
    assert -2 * math.pi * s.real / s.imag == pytest.approx(ld_sync, rel=1e-6)
    # the full model differs from Lund's fixed point only by the mode's own decay (s = sigma + i W)
    om, _, blocks, lam = _full(analysis, speed)
    full = lam[np.argmin(np.abs(lam - s))]
    assert abs(full - s) < 0.05 * abs(s.real)


def test_the_stability_analysis_takes_the_pads_into_its_eigenproblem(analysis):
    point, q = analysis.at(70.0)
    om = 2 * math.pi * 70.0
    f, ld, _ = pm.modes(analysis.rotor, om, pm.pad_blocks(analysis.internals, analysis.pairs, q, om))
    np.testing.assert_allclose(point.freq_hz, f, rtol=1e-12)
    np.testing.assert_allclose(point.log_dec, ld, rtol=1e-9)
    # the synchronously reduced K, C (reported) give the 22 Hz mode 2.7x the damping it has
    f_s, ld_s, _ = analysis.rotor.modes(om, point.K, point.C)
    assert point.least_log_dec < 0.5 * ld_s[np.argmin(ld_s)]
