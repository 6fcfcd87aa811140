"""Closed-form short-bearing (Ocvirk, half-Sommerfeld) force, coefficients and eccentricity."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import quad

from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.shortbearing import (short_bearing_coefficients, short_bearing_eccentricity,
                                              short_bearing_force, short_bearing_force_and_jacobian,
                                              short_bearing_load)

P = BearingParams(D=0.1, L=0.01, CR=1e-4, mu=0.05)


def quadrature_force(prm, y, z, vy, vz, w):
    """Independent check: integrate the short-bearing pressure
    int p dx = -(mu L^3 / (2 h^3)) (omega h_th + 2 h_t) over its positive part numerically."""

    def f(th, comp):
        h = prm.CR + y * math.sin(th) - z * math.cos(th)
        g = w * (y * math.cos(th) + z * math.sin(th)) + 2 * (vy * math.sin(th) - vz * math.cos(th))
        ip = max(-(prm.mu * prm.L**3 / (2 * h**3)) * g, 0.0)
        return ip * prm.R * (math.sin(th) if comp == 0 else -math.cos(th))

    return [quad(f, 0, 2 * math.pi, args=(c,), limit=500, epsabs=0, epsrel=1e-11)[0] for c in (0, 1)]


def test_force_matches_quadrature_with_velocities():
    rng = np.random.default_rng(1)
    for _ in range(12):
        e, a = rng.uniform(0, 0.95), rng.uniform(0, 2 * math.pi)
        y, z = e * P.CR * math.sin(a), -e * P.CR * math.cos(a)
        vy, vz = rng.normal(size=2) * P.CR * 30
        w = float(rng.choice([-100.0, 0.0, 100.0]))
        F = short_bearing_force(P, y, z, vy, vz, w)
        assert np.allclose(F, quadrature_force(P, y, z, vy, vz, w), rtol=1e-8, atol=1e-9 * np.abs(F).max())


def test_static_force_is_the_classical_ocvirk_result():
    """F_r = -mu U L^3 eps^2 / (CR^2 (1 - eps^2)^2), F_t = pi mu U L^3 eps / (4 CR^2 (1 - eps^2)^1.5)
    (e.g. Hamrock, Fundamentals of Fluid Film Lubrication, ch. 11); journal straight down,
    so the radial direction is -z and the tangential (direction of rotation) is +y."""
    w = 150.0
    U = w * P.R
    for eps in (0.1, 0.5, 0.9):
        Fy, Fz = short_bearing_force(P, 0.0, -eps * P.CR, 0.0, 0.0, w)
        Fr = -P.mu * U * P.L**3 * eps**2 / (P.CR**2 * (1 - eps**2) ** 2)
        Ft = math.pi * P.mu * U * P.L**3 * eps / (4 * P.CR**2 * (1 - eps**2) ** 1.5)
        assert Fz == pytest.approx(-Fr, rel=1e-12)
        assert Fy == pytest.approx(Ft, rel=1e-12)
        assert math.hypot(Fy, Fz) == pytest.approx(short_bearing_load(P, eps, w), rel=1e-12)


def test_zero_motion_zero_force_and_bad_input():
    assert short_bearing_force(P, 1e-5, 2e-5, 0.0, 0.0, 0.0) == (0.0, 0.0)
    with pytest.raises(BearingStateError, match="vz = nan is not finite"):
        short_bearing_force(P, 0.0, 0.0, 0.0, math.nan, 1.0)
    with pytest.raises(BearingStateError, match="eccentricity ratio 1 >= 1"):
        short_bearing_force(P, 0.0, -P.CR, 0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="omega = 0"):
        short_bearing_coefficients(P, 0.0, -0.5 * P.CR, 0.0)


@pytest.mark.parametrize("sgn", [1.0, -1.0])
def test_analytic_jacobian_matches_differences_with_squeeze_velocities(sgn):
    # Expected values: central differences of the force itself (step 1e-7 CR and 1e-7 omega CR,
    # truncation ~1e-12 relative, round-off ~1e-8), over eccentricities 0.01-0.95 and squeeze
    # velocities up to ~2 omega CR, where the moving cavitation limits turn with the velocity.
    w = sgn * 2 * math.pi * 22
    vs = abs(w) * P.CR
    rng = np.random.default_rng(7)
    for _ in range(60):
        e, a = rng.uniform(0.01, 0.95), rng.uniform(0, 2 * math.pi)
        x0 = np.array([e * P.CR * math.sin(a), -e * P.CR * math.cos(a), *rng.normal(0.0, 0.7, 2) * vs])
        F, dq, dv = short_bearing_force_and_jacobian(P, *x0, w)
        assert np.allclose(F, short_bearing_force(P, *x0, w), rtol=0, atol=1e-14 * np.abs(F).max())
        J = np.empty((2, 4))
        for j in range(4):
            h = 1e-7 * (P.CR if j < 2 else vs)
            xp, xm = x0.copy(), x0.copy()
            xp[j] += h
            xm[j] -= h
            J[:, j] = (np.array(short_bearing_force(P, *xp, w)) - np.array(short_bearing_force(P, *xm, w))) / (2 * h)
        scale = np.abs(J).max()
        assert np.abs(np.hstack([dq, dv]) - J).max() < 1e-5 * scale


def test_analytic_jacobian_at_rest_is_minus_the_closed_form_coefficients():
    # Expected: the independent closed-form K, C (Childs 1993; checked against Friswell below)
    w = 2 * math.pi * 44
    for e, a in ((0.3, 0.4), (0.9, -1.2)):
        y, z = e * P.CR * math.sin(a), -e * P.CR * math.cos(a)
        K, C = short_bearing_coefficients(P, y, z, w)
        _, dq, dv = short_bearing_force_and_jacobian(P, y, z, 0.0, 0.0, w)
        np.testing.assert_allclose(-dq, K, rtol=1e-12, atol=1e-12 * np.abs(K).max())
        np.testing.assert_allclose(-dv, C, rtol=1e-12, atol=1e-12 * np.abs(C).max())


@pytest.mark.parametrize("sgn", [1.0, -1.0])
def test_coefficients_match_differences_of_the_closed_form(sgn):
    w = sgn * 120.0
    rng = np.random.default_rng(4)
    for _ in range(6):
        e, a = rng.uniform(0, 0.9), rng.uniform(0, 2 * math.pi)
        x0 = np.array([e * P.CR * math.sin(a), -e * P.CR * math.cos(a), 0.0, 0.0])
        K, C = short_bearing_coefficients(P, x0[0], x0[1], w)
        J = np.empty((2, 4))
        for j in range(4):
            h = 1e-6 * P.CR * (1.0 if j < 2 else abs(w))
            xp, xm = x0.copy(), x0.copy()
            xp[j] += h
            xm[j] -= h
            J[:, j] = (np.array(short_bearing_force(P, *xp, w)) - np.array(short_bearing_force(P, *xm, w))) / (2 * h)
        assert np.allclose(K, -J[:, :2], rtol=1e-6, atol=1e-7 * np.abs(K).max())
        assert np.allclose(C, -J[:, 2:], rtol=1e-6, atol=1e-7 * np.abs(C).max())


@pytest.mark.parametrize("W", [10.0, 300.0, 5000.0])
def test_coefficients_match_friswell_table(W):
    """Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines (2010), sec. 5.5.2: the
    short-bearing coefficients at equilibrium under a vertical load f0, K = (f0 / CR) a,
    C = f0 / (CR omega) b, h0 = 1 / (pi^2 (1 - eps^2) + 16 eps^2)^1.5 and
    a_uu = 4 h0 (pi^2 (2 - eps^2) + 16 eps^2), a_uv = h0 pi (pi^2 (1 - eps^2)^2 - 16 eps^4) / (eps s),
    a_vu = -h0 pi (pi^2 (1 - eps^2)(1 + 2 eps^2) + 32 eps^2 (1 + eps^2)) / (eps s),
    a_vv = 4 h0 (pi^2 (1 + 2 eps^2) + 32 eps^2 (1 + eps^2) / (1 - eps^2)),
    b_uu = 2 h0 pi s (pi^2 (1 + 2 eps^2) - 16 eps^2) / eps, b_uv = b_vu = -8 h0 (pi^2 (1 + 2 eps^2) - 16 eps^2),
    b_vv = 2 h0 pi (pi^2 (1 - eps^2)^2 + 48 eps^2) / (eps s), s = sqrt(1 - eps^2);
    u horizontal (y), v vertical (z), load along -z, omega > 0."""
    w = 150.0
    eps, phi = short_bearing_eccentricity(P, W, w)
    # displacement: the load direction (0, -1) turned by phi
    y, z = eps * P.CR * math.sin(phi), -eps * P.CR * math.cos(phi)
    assert short_bearing_force(P, y, z, 0.0, 0.0, w) == pytest.approx((0.0, W), abs=1e-9 * W)
    K, C = short_bearing_coefficients(P, y, z, w)
    e, s = eps, math.sqrt(1 - eps**2)
    pi2 = math.pi**2
    h0 = 1 / (pi2 * (1 - e**2) + 16 * e**2) ** 1.5
    a = h0 * np.array([
        [4 * (pi2 * (2 - e**2) + 16 * e**2), math.pi * (pi2 * (1 - e**2) ** 2 - 16 * e**4) / (e * s)],
        [-math.pi * (pi2 * (1 - e**2) * (1 + 2 * e**2) + 32 * e**2 * (1 + e**2)) / (e * s),
         4 * (pi2 * (1 + 2 * e**2) + 32 * e**2 * (1 + e**2) / (1 - e**2))],
    ])
    b = h0 * np.array([
        [2 * math.pi * s * (pi2 * (1 + 2 * e**2) - 16 * e**2) / e, -8 * (pi2 * (1 + 2 * e**2) - 16 * e**2)],
        [-8 * (pi2 * (1 + 2 * e**2) - 16 * e**2), 2 * math.pi * (pi2 * (1 - e**2) ** 2 + 48 * e**2) / (e * s)],
    ])
    assert np.allclose(K * P.CR / W, a, rtol=1e-9)
    assert np.allclose(C * P.CR * w / W, b, rtol=1e-9)


def test_eccentricity_round_trip_and_sign():
    for W in (1e-3, 1.0, 100.0, 1e4, 1e7):
        for w in (50.0, -50.0):
            eps, phi = short_bearing_eccentricity(P, W, w)
            assert 0 < eps < 1
            assert short_bearing_load(P, eps, w) == pytest.approx(W, rel=1e-12)
            assert math.tan(abs(phi)) == pytest.approx(math.pi * math.sqrt(1 - eps**2) / (4 * eps), rel=1e-12)
            assert math.copysign(1.0, phi) == math.copysign(1.0, w)
            # the film force at that position balances the load (0, -W)
            y, z = eps * P.CR * math.sin(phi), -eps * P.CR * math.cos(phi)
            assert short_bearing_force(P, y, z, 0.0, 0.0, w) == pytest.approx((0.0, W), abs=1e-9 * W)
    assert short_bearing_eccentricity(P, 0.0, 10.0) == (0.0, math.pi / 2)
    with pytest.raises(ValueError, match="omega = 0"):
        short_bearing_eccentricity(P, 5.0, 0.0)
    with pytest.raises(ValueError, match="W = -1.0"):
        short_bearing_eccentricity(P, -1.0, 10.0)


def test_module_imports_neither_numba_nor_reynolds():
    code = ("import sys, bearing_fmu.physics.solver.shortbearing; "
            "bad = [m for m in ('numba', 'bearing_fmu.physics.solver.reynolds') if m in sys.modules]; "
            "assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True)
