r"""Closed-form short-bearing (Ocvirk) film force with the half-Sommerfeld ("gumbel") condition.

Derivation in the DESIGN.md coordinates
---------------------------------------
Reynolds' equation with the circumferential length R*theta (DESIGN.md)

    (1/R^2) d/dth(h^3 dp/dth) + d/dx(h^3 dp/dx) = 6 mu omega dh/dth + 12 mu dh/dt

loses its first term when L << D (Ocvirk & DuBois 1953). Then h^3 p_xx = G(theta) with
G = 6 mu (omega h_th + 2 h_t), and p(+-L/2) = 0 gives

    p = (3 mu / h^3) (x^2 - L^2/4) [omega dh/dth + 2 dh/dt],   int p dx = -(mu L^3 / (2 h^3)) [...].

Journal position (y, z) = e (sin a, -cos a): the film is thickest at theta = a, and with
phi = theta - a, h = CR (1 + eps cos phi). Let u_r = (sin a, -cos a) (along the eccentricity)
and u_t = (cos a, sin a) (a turned by +90 deg, from +y toward +z), v_r = v.u_r, v_t = v.u_t.
Then dh/dt = vy sin th - vz cos th = v_r cos phi + v_t sin phi and

    omega h_th + 2 h_t = -CR [A sin phi - B cos phi],  A = eps omega - 2 v_t / CR,  B = 2 v_r / CR.

The pressure is positive where A sin phi - B cos phi > 0, i.e. on the half circle
phi in (phi1, phi1 + pi), phi1 = atan2(B, A) (the moving pi-film). The film pushes the journal
along (sin th, -cos th) = cos phi u_r + sin phi u_t, so with C0 = mu L^3 R / (2 CR^2):

    F_r = C0 [A J_sc - B J_cc],   F_t = C0 [A J_ss - B J_sc],
    J_sc = int sin cos / (1 + eps cos)^3,  J_ss = int sin^2 / (...)^3,  J_cc = int cos^2 / (...)^3

over (phi1, phi1 + pi). With the Sommerfeld substitution (eccentric anomaly) gamma,
tan(gamma/2) = sqrt((1 - eps)/(1 + eps)) tan(phi/2), s = sqrt(1 - eps^2),
sin gamma = s sin phi / (1 + eps cos phi), cos gamma = (cos phi + eps)/(1 + eps cos phi),
dphi / (1 + eps cos phi)^3 becomes a trigonometric polynomial and

    J_ss = s^-3 [gamma/2 - sin(2 gamma)/4]
    J_sc = s^-4 [sin^2(gamma)/2 + eps cos(gamma)]
    J_cc = s^-5 [(1/2 + eps^2) gamma + sin(2 gamma)/4 - 2 eps sin(gamma)]

evaluated between the limits (gamma continuous: gamma = phi - 2 atan(beta sin phi /
(1 + beta cos phi)), beta = eps / (1 + s)). Static check (v = 0, omega > 0, region (0, pi)):
F_r = -mu U L^3 eps^2 / (CR^2 (1 - eps^2)^2), F_t = pi mu U L^3 eps / (4 CR^2 (1 - eps^2)^1.5),
U = omega R: the classical Ocvirk result (e.g. Hamrock, Fundamentals of Fluid Film
Lubrication, ch. 11; Childs, Turbomachinery Rotordynamics, 1993, sec. 3).

Coefficients (Lund's sign, K = -dF/dq, C = -dF/dqdot) at v = 0 from the same closed form:
the integrand vanishes at the moving limits, so only the integrand is differentiated. In the
(r, t) frame, with U = omega R, s = sqrt(1 - eps^2), k0 = mu R L^3 / CR^3:

    K_rr = 2 k0 |omega| eps (1 + eps^2) / s^6      K_rt = k0 omega pi / (4 s^3)
    K_tr = -k0 omega pi (1 + 2 eps^2) / (4 s^5)     K_tt = k0 |omega| eps / s^4
    C_rr = k0 pi (1 + 2 eps^2) / (2 s^5)   C_rt = C_tr = -2 k0 sgn(omega) eps / s^4   C_tt = k0 pi / (2 s^3)

(K_rt = F_t / e and K_tt = -F_r / e from turning the force with the frame; K_rr, K_tr from
dF/d eps; C = (2 C0 / CR) [[J_cc, J_sc], [J_sc, J_ss]]). These agree with Childs (1993,
eqs. 3.46-3.47) and, turned into the load frame at equilibrium, with the dimensionless short
bearing coefficients of Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines (2010),
sec. 5.5.2 (checked in tests/test_shortbearing.py). They are rotated to (y, z) with
T = [u_r u_t]: K = T K_rt T^T.

This module is pure Python (no numba, no reynolds import); bearing_fmu.surrogates.taylor_kernels compiles
``short_bearing_kernel`` for the surrogate's shape columns.
"""

from __future__ import annotations

import math

import numpy as np

from ...internals.registry import check_state
from ..params import BearingParams

__all__ = ["short_bearing_force", "short_bearing_force_and_jacobian", "short_bearing_kernel",
           "short_bearing_constant", "short_bearing_coefficients", "short_bearing_eccentricity",
           "short_bearing_load"]


def _frame(params: BearingParams, y: float, z: float):
    """(eps, u_r, u_t): eccentricity ratio and the radial / tangential unit vectors."""
    e = math.hypot(y, z)
    eps = e / params.CR
    if e > 0.0:
        ur = (y / e, z / e)
    else:
        ur = (0.0, -1.0)  # any frame will do at the centre; a = 0
    ut = (-ur[1], ur[0])
    return eps, ur, ut


def short_bearing_kernel(y, z, vy, vz, omega, cr, c0, jac):
    """The closed form and, with ``jac``, its analytic Jacobian: plain Python on floats, so
    that bearing_fmu.surrogates.taylor_kernels can compile this very function with numba (one implementation).

    cr = CR [m], c0 = mu L^3 R / (2 CR^2). No input checks (eps < 1 is the caller's). Returns
    (Fy, Fz, dFy/dy, dFy/dz, dFy/dvy, dFy/dvz, dFz/dy, dFz/dz, dFz/dvy, dFz/dvz) in SI; the
    derivatives are 0 without ``jac``.

    Jacobian: F_r, F_t depend on (eps, A, B); the moving limits phi1 = atan2(B, A) contribute
    nothing (the integrand A sin - B cos vanishes there), so dF/dA and dF/dB are the J
    integrals themselves and dJ/deps at fixed limits is the difference of dP/deps, with
    (at fixed phi) dgamma/deps = -sin(gamma)/s^2, dsin(gamma)/deps = -sin cos(gamma)/s^2,
    dcos(gamma)/deps = sin^2(gamma)/s^2, ds/deps = -eps/s. The frame turns with the journal:
    du_r/dq = u_t u_t^T / e, du_t/dq = -u_r u_t^T / e. At w = 0 (A = B = 0) the force is 0 and
    the derivatives are those of the region (0, pi), the limit from A > 0. Within 1e-8 CR of
    the centre the 1/e frame terms are capped (the position derivatives are not exact there;
    the force is).
    """
    e = math.sqrt(y * y + z * z)
    eps = e / cr
    if e > 0.0:
        ury = y / e
        urz = z / e
    else:
        ury = 0.0
        urz = -1.0
    uty = -urz
    utz = ury
    vr = vy * ury + vz * urz
    vt = vy * uty + vz * utz
    A = eps * omega - 2.0 * vt / cr
    B = 2.0 * vr / cr
    phi1 = math.atan2(B, A)
    s2 = 1.0 - eps * eps
    s = math.sqrt(s2)
    beta = eps / (1.0 + s)
    jss = jsc = jcc = 0.0
    dss = dsc = dcc = 0.0
    for k in range(2):  # the primitives P at phi2 = phi1 + pi (sign +1) and phi1 (sign -1)
        phi = phi1 + math.pi if k == 0 else phi1
        sgn = 1.0 if k == 0 else -1.0
        sp = math.sin(phi)
        cp = math.cos(phi)
        g = phi - 2.0 * math.atan(beta * sp / (1.0 + beta * cp))  # continuous eccentric anomaly
        den = 1.0 + eps * cp
        sg = s * sp / den
        cg = (cp + eps) / den
        a = 0.5 * g - 0.5 * sg * cg
        b = 0.5 * sg * sg + eps * cg
        c = (0.5 + eps * eps) * g + 0.5 * sg * cg - 2.0 * eps * sg
        jss += sgn * a / s**3
        jsc += sgn * b / s**4
        jcc += sgn * c / s**5
        if jac:
            a_e = -(sg**3) / s2
            b_e = -sg * sg * cg / s2 + cg + eps * sg * sg / s2
            c_e = (2.0 * eps * g - (0.5 + eps * eps) * sg / s2 + 0.5 * sg * (sg * sg - cg * cg) / s2
                   - 2.0 * sg + 2.0 * eps * sg * cg / s2)
            dss += sgn * (3.0 * eps * a / s**5 + a_e / s**3)
            dsc += sgn * (4.0 * eps * b / s**6 + b_e / s**4)
            dcc += sgn * (5.0 * eps * c / s**7 + c_e / s**5)
    fr = c0 * (A * jsc - B * jcc)
    ft = c0 * (A * jss - B * jsc)
    fy = fr * ury + ft * uty
    fz = fr * urz + ft * utz
    if not jac:
        return fy, fz, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # partial derivatives of (F_r, F_t) in eps, A, B
    fr_e = c0 * (A * dsc - B * dcc)
    ft_e = c0 * (A * dss - B * dsc)
    fr_a, fr_b = c0 * jsc, -c0 * jcc
    ft_a, ft_b = c0 * jss, -c0 * jsc
    einv = 1.0 / max(e, 1e-8 * cr)
    # gradients of eps, A, B in (y, z) and (vy, vz)
    eps_y, eps_z = ury / cr, urz / cr
    a_y = omega * ury / cr + 2.0 * vr * uty * einv / cr
    a_z = omega * urz / cr + 2.0 * vr * utz * einv / cr
    a_vy, a_vz = -2.0 * uty / cr, -2.0 * utz / cr
    b_y, b_z = 2.0 * vt * uty * einv / cr, 2.0 * vt * utz * einv / cr
    b_vy, b_vz = 2.0 * ury / cr, 2.0 * urz / cr
    gr_y = fr_e * eps_y + fr_a * a_y + fr_b * b_y
    gr_z = fr_e * eps_z + fr_a * a_z + fr_b * b_z
    gr_vy = fr_a * a_vy + fr_b * b_vy
    gr_vz = fr_a * a_vz + fr_b * b_vz
    gt_y = ft_e * eps_y + ft_a * a_y + ft_b * b_y
    gt_z = ft_e * eps_z + ft_a * a_z + ft_b * b_z
    gt_vy = ft_a * a_vy + ft_b * b_vy
    gt_vz = ft_a * a_vz + ft_b * b_vz
    # F = F_r u_r + F_t u_t: dF/dq = u_r g_r^T + u_t g_t^T + (F_r u_t - F_t u_r) u_t^T / e
    wy = (fr * uty - ft * ury) * einv
    wz = (fr * utz - ft * urz) * einv
    return (fy, fz,
            ury * gr_y + uty * gt_y + wy * uty, ury * gr_z + uty * gt_z + wy * utz,
            ury * gr_vy + uty * gt_vy, ury * gr_vz + uty * gt_vz,
            urz * gr_y + utz * gt_y + wz * uty, urz * gr_z + utz * gt_z + wz * utz,
            urz * gr_vy + utz * gt_vy, urz * gr_vz + utz * gt_vz)


def short_bearing_constant(params: BearingParams) -> float:
    """c0 = mu L^3 R / (2 CR^2) [N s]: the force scale of the closed form (module docstring)."""
    return params.mu * params.L**3 * params.R / (2.0 * params.CR**2)


def short_bearing_force(params: BearingParams, y: float, z: float, vy: float, vz: float,
                        omega: float) -> tuple[float, float]:
    """Ocvirk short-bearing film force (Fy, Fz) [N], half-Sommerfeld (pi-film), with the
    squeeze velocities (vy, vz) [m/s]; see the module docstring for the derivation."""
    check_state(params, y, z, vy, vz, omega)
    r = short_bearing_kernel(float(y), float(z), float(vy), float(vz), float(omega), params.CR,
                             short_bearing_constant(params), False)
    return float(r[0]), float(r[1])


def short_bearing_force_and_jacobian(params: BearingParams, y: float, z: float, vy: float, vz: float,
                                     omega: float):
    """(F (2,) [N], dF/dq (2, 2) [N/m], dF/dv (2, 2) [N s/m]) of ``short_bearing_force``,
    analytic (see ``short_bearing_kernel``)."""
    check_state(params, y, z, vy, vz, omega)
    r = short_bearing_kernel(float(y), float(z), float(vy), float(vz), float(omega), params.CR,
                             short_bearing_constant(params), True)
    return np.array(r[:2]), np.array([r[2:4], r[6:8]]), np.array([r[4:6], r[8:10]])


def short_bearing_coefficients(params: BearingParams, y0: float, z0: float, omega: float):
    """Lund's stiffness and damping (K, C), 2x2 arrays in (y, z) [N/m, N s/m], of the closed
    form short-bearing force at the journal position (y0, z0) with zero velocity:
    K_ij = -dF_i/dq_j, C_ij = -dF_i/dqdot_j. Formulae in the module docstring."""
    check_state(params, y0, z0, 0.0, 0.0, omega)
    if omega == 0.0:
        raise ValueError("short_bearing_coefficients: omega = 0 gives no film (the force is not "
                         "differentiable in the velocity there); give omega != 0")
    eps, ur, ut = _frame(params, y0, z0)
    s = math.sqrt(1.0 - eps * eps)
    k0 = params.mu * params.R * params.L**3 / params.CR**3
    w, aw, sg = omega, abs(omega), math.copysign(1.0, omega)
    K_rt = np.array([
        [2.0 * k0 * aw * eps * (1.0 + eps**2) / s**6, k0 * w * math.pi / (4.0 * s**3)],
        [-k0 * w * math.pi * (1.0 + 2.0 * eps**2) / (4.0 * s**5), k0 * aw * eps / s**4],
    ])
    C_rt = np.array([
        [k0 * math.pi * (1.0 + 2.0 * eps**2) / (2.0 * s**5), -2.0 * k0 * sg * eps / s**4],
        [-2.0 * k0 * sg * eps / s**4, k0 * math.pi / (2.0 * s**3)],
    ])
    T = np.array([[ur[0], ut[0]], [ur[1], ut[1]]])
    return T @ K_rt @ T.T, T @ C_rt @ T.T


def short_bearing_load(params: BearingParams, eps: float, omega: float) -> float:
    """Static load capacity |F| [N] of the short bearing at eccentricity ratio eps:
    W = mu |omega| R L^3 / (4 CR^2) eps / (1 - eps^2)^2 sqrt(pi^2 (1 - eps^2) + 16 eps^2)."""
    e2 = eps * eps
    return (params.mu * abs(omega) * params.R * params.L**3 / (4.0 * params.CR**2)
            * eps / (1.0 - e2) ** 2 * math.sqrt(math.pi**2 * (1.0 - e2) + 16.0 * e2))


def short_bearing_eccentricity(params: BearingParams, W: float, omega: float) -> tuple[float, float]:
    """Solve the short-bearing load-eccentricity relation for a static load of magnitude W [N].

    Returns (eps, phi): the eccentricity ratio and the attitude angle [rad] between the load
    line and the journal's displacement, tan(phi) = pi sqrt(1 - eps^2) / (4 eps), signed so that
    the displacement is the load direction turned by phi (positive = from +y toward +z): phi has
    the sign of omega. W(eps) rises monotonically from 0 to infinity; safeguarded Newton.
    """
    W = float(W)
    omega = float(omega)
    if not (math.isfinite(W) and W >= 0.0):
        raise ValueError(f"short_bearing_eccentricity: W = {W!r} must be finite and >= 0")
    if not math.isfinite(omega):
        raise ValueError(f"short_bearing_eccentricity: omega = {omega!r} must be finite")
    sgn = math.copysign(1.0, omega)
    if W == 0.0:
        return 0.0, sgn * 0.5 * math.pi
    if omega == 0.0:
        raise ValueError("short_bearing_eccentricity: omega = 0 carries no static load; give omega != 0")
    k = params.mu * abs(omega) * params.R * params.L**3 / (4.0 * params.CR**2)
    c = 16.0 - math.pi**2
    lo, hi = 0.0, 1.0
    eps = 0.5
    for _ in range(200):
        e2 = eps * eps
        g = math.sqrt(math.pi**2 + c * e2)
        q = 1.0 - e2
        f = k * eps * g / q**2 - W
        if f > 0.0:
            hi = eps
        else:
            lo = eps
        # dW/deps = k [g / q^2 + 4 eps^2 g / q^3 + c eps^2 / (g q^2)] > 0
        d = k * (g / q**2 + 4.0 * e2 * g / q**3 + c * e2 / (g * q**2))
        new = eps - f / d
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        done = abs(new - eps) <= 2e-15 * eps or hi - lo <= 2e-15
        eps = new
        if done:
            break
    phi = math.atan2(math.pi * math.sqrt(1.0 - eps * eps), 4.0 * eps)
    return eps, sgn * phi
