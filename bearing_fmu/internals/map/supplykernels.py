"""numba kernels of the fed-groove map (``supplymap``): the tensor cubic spline in four variables
(s, phi, beta, u) and the film force with its analytic Jacobian from F = W (G_r u + G_t w),
W = S r + R L p_s, u = R L p_s / W (the derivation: ``supplymap``'s docstring)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels import bspline_basis, bspline_span, force_jacobian, journal_polar

# below 1 - u = S r / W = T_MIN (a journal at rest, r = 0, among them) the derivatives in (a, c) are
# those at r = 0 (``_odd_part``, the first harmonic of the directional derivatives): the general ones carry
# G_beta / (1 - u), whose spline value is
# round-off over (1 - u) there; the force itself is taken where it is (at r = 0 any beta's)
T_MIN = 1e-8
N_HARMONIC = 8  # directions of ``_odd_part``'s first harmonic


@njit(cache=True)
def spline4(ts, tp, tb, tu, C, s, phi, beta, u, out):
    """Tensor cubic spline in (s, phi, beta, u), phi and beta periodic over their knots' base
    intervals: out[k] = (value, d/ds, d/dphi, d/dbeta, d/du) of the components C[..., k]."""
    ns, npp, nb, nu = C.shape[0], C.shape[1], C.shape[2], C.shape[3]
    p = tp[3] + ((phi - tp[3]) % (tp[npp] - tp[3]))
    b = tb[3] + ((beta - tb[3]) % (tb[nb] - tb[3]))
    i = bspline_span(ts, ns, s)
    j = bspline_span(tp, npp, p)
    m = bspline_span(tb, nb, b)
    n = bspline_span(tu, nu, u)
    N = np.empty((4, 4))
    dN = np.empty((4, 4))
    bspline_basis(ts, i, s, N[0], dN[0])
    bspline_basis(tp, j, p, N[1], dN[1])
    bspline_basis(tb, m, b, N[2], dN[2])
    bspline_basis(tu, n, u, N[3], dN[3])
    for k in range(C.shape[4]):
        v = vs = vp = vb = vu = 0.0
        for a in range(4):
            pv = pp = pb = pu = 0.0
            for q in range(4):
                bv = bb = bu = 0.0
                for r in range(4):
                    uv = uu = 0.0
                    for w in range(4):
                        c = C[i - 3 + a, j - 3 + q, m - 3 + r, n - 3 + w, k]
                        uv += N[3, w] * c
                        uu += dN[3, w] * c
                    bv += N[2, r] * uv
                    bb += dN[2, r] * uv
                    bu += N[2, r] * uu
                pv += N[1, q] * bv
                pp += dN[1, q] * bv
                pb += N[1, q] * bb
                pu += N[1, q] * bu
            v += N[0, a] * pv
            vs += dN[0, a] * pv
            vp += N[0, a] * pp
            vb += N[0, a] * pb
            vu += N[0, a] * pu
        out[k, 0] = v
        out[k, 1] = vs
        out[k, 2] = vp
        out[k, 3] = vb
        out[k, 4] = vu


@njit(cache=True)
def _g4(ts, tp, tb, tu, C, eps, phi, beta, u, g):
    """g[k] = (G_k, dG_k/deps, dG_k/dphi, dG_k/dbeta, dG_k/du) from the spline in s = -ln(1 - eps)."""
    s = -math.log1p(-eps)
    spline4(ts, tp, tb, tu, C, s, phi, beta, u, g)
    dsde = math.exp(s)
    for k in range(2):
        g[k, 1] *= dsde


@njit(cache=True)
def _odd_part(ts, tp, tb, tu, C, eps, phi, out):
    """At r = 0 the force's derivative in the direction beta is S D(beta), D = G - G_u at u = 1 (W G with
    W = S r + R L p_s, 1 - u = S r / W). The film's D is cos(beta) A + sin(beta) B (the linear response
    at rest, module docstring); the spline's has interpolation error in other harmonics too, so the
    derivative at r = 0 is its first harmonic, A and B by the 8-point rule: out[k] = (dP_k/da, dP_k/dc)."""
    g = np.empty((2, 5))
    for k in range(2):
        out[k, 0] = 0.0
        out[k, 1] = 0.0
    for j in range(N_HARMONIC):
        b = 2.0 * math.pi * j / N_HARMONIC
        _g4(ts, tp, tb, tu, C, eps, phi, b, 1.0, g)
        for k in range(2):
            d = g[k, 0] - g[k, 4]
            out[k, 0] += 2.0 / N_HARMONIC * math.cos(b) * d
            out[k, 1] += 2.0 / N_HARMONIC * math.sin(b) * d


@njit(cache=True)
def map4_force(ts, tp, tb, tu, C, eps_min, scale, CR, supply, y, z, vy, vz, omega, want_jac, F, J):
    """The fed-groove map's film force F (2,) [N] and, with want_jac, J (2, 4) = dF/d(y, z, vy, vz):
    F = W (G_r u + G_t w), W = S r + supply, u = supply / W (``supply`` = R L p_s [N], ``scale`` = S).
    In the terms of ``map3_force`` (P = F's components over S): P = (W / S) G, and in (a, c)
    dP/dr = G - u G_u, dP/dbeta = (W / S) G_beta = r G_beta / (1 - u), so
    dP/da = cos(beta) (G - u G_u) - sin(beta) G_beta / (1 - u) and dP/dc likewise: finite at r -> 0,
    where G_beta vanishes with 1 - u (below ``T_MIN``: ``_odd_part``). Returns eps (NaN when F or J is not finite)."""
    eps, cp, sp, eps_eval, a, c, r = journal_polar(y, z, vy, vz, omega, CR, eps_min)
    if not eps < 1.0:
        return eps
    phi = math.atan2(sp, cp)
    W = scale * r + supply
    u = supply / W
    t = scale * r / W  # 1 - u without the cancellation
    if r > 0.0:
        beta = math.atan2(c, a)
        cb, sb = a / r, c / r
    else:  # the still journal: the force is beta's (any: the u = 1 row is one value), the derivatives below
        beta, cb, sb = 0.0, 1.0, 0.0
    g = np.empty((2, 5))
    _g4(ts, tp, tb, tu, C, eps_eval, phi, beta, u, g)
    m = W / scale
    Pr, Pt = m * g[0, 0], m * g[1, 0]
    F[0] = scale * (Pr * cp - Pt * sp)
    F[1] = scale * (Pr * sp + Pt * cp)
    if not (math.isfinite(F[0]) and math.isfinite(F[1])):
        return math.nan
    if not want_jac:
        return eps
    Pr_e, Pt_e = m * g[0, 1], m * g[1, 1]
    Pr_p, Pt_p = m * g[0, 2], m * g[1, 2]
    if t < T_MIN:  # at rest (to round-off): the first harmonic of the directional derivatives
        _odd_part(ts, tp, tb, tu, C, eps_eval, phi, g)
        Pr_a, Pt_a, Pr_c, Pt_c = g[0, 0], g[1, 0], g[0, 1], g[1, 1]
    else:
        dr_r, db_r = g[0, 0] - u * g[0, 4], g[0, 3] / t
        dr_t, db_t = g[1, 0] - u * g[1, 4], g[1, 3] / t
        Pr_a, Pr_c = cb * dr_r - sb * db_r, sb * dr_r + cb * db_r
        Pt_a, Pt_c = cb * dr_t - sb * db_t, sb * dr_t + cb * db_t
    if not force_jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p,
                          Pt_p, J):
        return math.nan
    return eps
