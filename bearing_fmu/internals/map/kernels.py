"""numba kernels of the force map (``forcemap.py``): tensor cubic B-spline evaluation and the
film force with its Jacobian from the map's reduced variables.

Reduced variables (derivation in docs/forcemap.md, DESIGN.md conventions): the journal centre
at (y, z) = e (cos phi, sin phi); eps = e / CR; radial and tangential velocities
v_r = v . u, v_t = v . w with u = (cos phi, sin phi), w = (-sin phi, cos phi);
a = eps omega - 2 v_t / CR  (= eps (omega - 2 phidot)),  c = 2 v_r / CR  (= 2 epsdot);
r = hypot(a, c), beta = atan2(c, a). The force is F = S r (G_r(eps, beta) u + G_t(eps, beta) w)
with S = mu R L (R / CR)^2; the table holds H = G (1 - eps)^k on s = -ln(1 - eps).
``map_kernel`` is the same force as a compiled-force kernel (``internals.compiled``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc, njit

from ..compiled import KERNEL_SIG, advance

TWO_PI = 2.0 * math.pi


@njit(cache=True)
def _span(t, n, x):
    """Knot span i (3 <= i <= n - 1) with t[i] <= x < t[i + 1], clamped to the base interval."""
    if x >= t[n]:
        return n - 1
    if x <= t[3]:
        return 3
    lo, hi = 3, n
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if x >= t[mid]:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def _basis(t, i, x, N, dN):
    """The four non-zero cubic B-splines N_{i-3..i} at x and their derivatives (Cox-de Boor,
    Piegl & Tiller, The NURBS Book, A2.2; derivatives from the degree-2 values)."""
    left = np.empty(4)
    right = np.empty(4)
    N[0] = 1.0
    N2 = np.zeros(3)
    for j in range(1, 4):
        left[j] = x - t[i + 1 - j]
        right[j] = t[i + j] - x
        saved = 0.0
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            N[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        N[j] = saved
        if j == 2:
            N2[0], N2[1], N2[2] = N[0], N[1], N[2]
    for r in range(4):
        d = 0.0
        if r >= 1:
            d += N2[r - 1] / (t[i + r] - t[i - 3 + r])
        if r <= 2:
            d -= N2[r] / (t[i + 1 + r] - t[i - 2 + r])
        dN[r] = 3.0 * d


@njit(cache=True)
def spline2(ts, tb, C, ns, nb, s, beta, out):
    """Tensor cubic spline: out = (value, d/ds, d/dbeta) of the components C[:, :, k]
    (out shape (n_components, 3)); beta periodic over the base interval of tb."""
    period = tb[nb] - tb[3]
    b = tb[3] + ((beta - tb[3]) % period)
    i = _span(ts, ns, s)
    j = _span(tb, nb, b)
    Ns, dNs, Nb, dNb = np.empty(4), np.empty(4), np.empty(4), np.empty(4)
    _basis(ts, i, s, Ns, dNs)
    _basis(tb, j, b, Nb, dNb)
    for k in range(C.shape[2]):
        v = 0.0
        vs = 0.0
        vb = 0.0
        for p in range(4):
            row_v = 0.0
            row_b = 0.0
            for q in range(4):
                c = C[i - 3 + p, j - 3 + q, k]
                row_v += Nb[q] * c
                row_b += dNb[q] * c
            v += Ns[p] * row_v
            vs += dNs[p] * row_v
            vb += Ns[p] * row_b
        out[k, 0] = v
        out[k, 1] = vs
        out[k, 2] = vb


@njit(cache=True)
def _g(ts, tb, C, ns, nb, kwall, eps, beta, g):
    """G(eps, beta) = H(s, beta) / (1 - eps)^k and its eps and beta derivatives:
    g[k] = (G_k, dG_k/deps, dG_k/dbeta) for the radial (k = 0) and tangential (k = 1) parts."""
    s = -math.log1p(-eps)
    spline2(ts, tb, C, ns, nb, s, beta, g)
    grow = math.exp(kwall * s)  # (1 - eps)^-k
    dsde = math.exp(s)  # ds/deps = 1 / (1 - eps)
    for k in range(2):
        h, hs, hb = g[k, 0], g[k, 1], g[k, 2]
        g[k, 0] = h * grow
        g[k, 1] = (hs + kwall * h) * grow * dsde
        g[k, 2] = hb * grow


@njit(cache=True)
def journal_polar(y, z, vy, vz, omega, CR, eps_min):
    """The journal state in the maps' polar terms: (eps, cos phi, sin phi, eps_eval, a, c, r) with
    eps = e / CR, phi the attitude (+y at the centre), eps_eval = max(eps, eps_min), the film's
    source a = eps_eval omega - 2 v_t / CR, c = 2 v_r / CR and r = |(a, c)|. Every map's force
    (2-D, grooved 3-D, fed-groove 4-D) starts here; eps not finite or >= 1 is the caller's to refuse."""
    e = math.hypot(y, z)
    if e > 0.0:
        cp, sp = y / e, z / e
    else:
        cp, sp = 1.0, 0.0
    eps = e / CR
    eps_eval = max(eps, eps_min)
    vr = vy * cp + vz * sp
    vt = -vy * sp + vz * cp
    a = eps_eval * omega - 2.0 * vt / CR
    c = 2.0 * vr / CR
    return eps, cp, sp, eps_eval, a, c, math.hypot(a, c)


@njit(cache=True)
def map_force(ts, tb, C, ns, nb, kwall, eps_min, scale, CR, y, z, vy, vz, omega, want_jac, F, J):
    """Film force F (2,) [N] and, with want_jac, J (2, 4) = dF/d(y, z, vy, vz); returns eps
    (NaN when F or J is not finite: finite inputs whose force overflows the float range).

    eps below eps_min is evaluated at eps_min along the same direction (+y at the centre):
    the frame (u, w) turns with phi, whose derivatives carry 1/e; the force is continuous
    there, and the shift moves it by less than its stiffness times eps_min CR."""
    eps, cp, sp, eps_eval, a, c, r = journal_polar(y, z, vy, vz, omega, CR, eps_min)
    if not eps < 1.0:  # at or beyond the wall, or not finite: the caller refuses it
        return eps
    g = np.empty((2, 3))
    if r > 0.0:
        beta = math.atan2(c, a)
        _g(ts, tb, C, ns, nb, kwall, eps_eval, beta, g)
        cb, sb = a / r, c / r
        Pr, Pt = r * g[0, 0], r * g[1, 0]
        # d(r G)/da = cos(beta) G - sin(beta) G_beta ; d(r G)/dc = sin(beta) G + cos(beta) G_beta
        Pr_a = cb * g[0, 0] - sb * g[0, 2]
        Pr_c = sb * g[0, 0] + cb * g[0, 2]
        Pt_a = cb * g[1, 0] - sb * g[1, 2]
        Pt_c = sb * g[1, 0] + cb * g[1, 2]
        Pr_e, Pt_e = r * g[0, 1], r * g[1, 1]
    else:
        # no film source (e.g. whirling at exactly half speed, no radial velocity): no force;
        # the derivative is the odd part (F(d) - F(-d)) / 2 of the directional response,
        # what central differences converge to (as the Reynolds internal reports it)
        Pr = Pt = Pr_e = Pt_e = 0.0
        g2 = np.empty((2, 3))
        _g(ts, tb, C, ns, nb, kwall, eps_eval, 0.0, g)
        _g(ts, tb, C, ns, nb, kwall, eps_eval, math.pi, g2)
        Pr_a = 0.5 * (g[0, 0] - g2[0, 0])
        Pt_a = 0.5 * (g[1, 0] - g2[1, 0])
        _g(ts, tb, C, ns, nb, kwall, eps_eval, 0.5 * math.pi, g)
        _g(ts, tb, C, ns, nb, kwall, eps_eval, -0.5 * math.pi, g2)
        Pr_c = 0.5 * (g[0, 0] - g2[0, 0])
        Pt_c = 0.5 * (g[1, 0] - g2[1, 0])
    F[0] = scale * (Pr * cp - Pt * sp)
    F[1] = scale * (Pr * sp + Pt * cp)
    if not (math.isfinite(F[0]) and math.isfinite(F[1])):
        return math.nan  # overflow (a huge velocity or speed): the caller refuses the state
    if not want_jac:
        return eps
    if not _jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, 0.0, 0.0,
                     J):
        return math.nan
    return eps


@njit(cache=True)
def _jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p,
              J):
    """J (2, 4) = dF/d(y, z, vy, vz) of F = S (Pr u + Pt w) from the partial derivatives of
    P = r G in (eps, a, c) and, for a grooved bore's table, r dG/dphi (Pr_p, Pt_p; 0 for the full
    bore); False when an entry is not finite."""
    # chain rule through (eps, phi, a, c); phi enters through u, w and v_r, v_t:
    # da/dphi = 2 v_r / CR = c, dc/dphi = 2 v_t / CR = eps omega - a (at fixed eps)
    da_dphi = c
    dc_dphi = eps_eval * omega - a
    dPr_dphi = Pr_a * da_dphi + Pr_c * dc_dphi + Pr_p
    dPt_dphi = Pt_a * da_dphi + Pt_c * dc_dphi + Pt_p
    # d(Pr u + Pt w)/dphi = dPr u + Pr w + dPt w - Pt u
    dFphi_y = scale * ((dPr_dphi - Pt) * cp - (dPt_dphi + Pr) * sp)
    dFphi_z = scale * ((dPr_dphi - Pt) * sp + (dPt_dphi + Pr) * cp)
    # d/deps at fixed phi and v (a depends on eps through eps omega)
    dPr_de = Pr_e + Pr_a * omega
    dPt_de = Pt_e + Pt_a * omega
    dFe_y = scale * (dPr_de * cp - dPt_de * sp)
    dFe_z = scale * (dPr_de * sp + dPt_de * cp)
    e_eval = eps_eval * CR
    # eps = e / CR: deps/dy = cos(phi) / CR ; dphi/dy = -sin(phi) / e
    J[0, 0] = dFe_y * cp / CR - dFphi_y * sp / e_eval
    J[1, 0] = dFe_z * cp / CR - dFphi_z * sp / e_eval
    J[0, 1] = dFe_y * sp / CR + dFphi_y * cp / e_eval
    J[1, 1] = dFe_z * sp / CR + dFphi_z * cp / e_eval
    # velocities: a = eps omega - 2 v_t / CR, c = 2 v_r / CR
    # dv_r/dvy = cos, dv_r/dvz = sin ; dv_t/dvy = -sin, dv_t/dvz = cos
    for col in range(2):
        dvr = cp if col == 0 else sp
        dvt = -sp if col == 0 else cp
        da = -2.0 * dvt / CR
        dc = 2.0 * dvr / CR
        dPr = Pr_a * da + Pr_c * dc
        dPt = Pt_a * da + Pt_c * dc
        J[0, 2 + col] = scale * (dPr * cp - dPt * sp)
        J[1, 2 + col] = scale * (dPr * sp + dPt * cp)
    for i in range(2):
        for j in range(4):
            if not math.isfinite(J[i, j]):
                return False
    return True


# ------------------------------------------------------- grooved bores: G(eps, phi, beta)

@njit(cache=True)
def spline3(ts, tp, tb, C, s, phi, beta, out):
    """Tensor cubic spline in (s, phi, beta), phi and beta periodic over their knots' base
    intervals: out[k] = (value, d/ds, d/dphi, d/dbeta) of the components C[:, :, :, k]."""
    ns, npp, nb = C.shape[0], C.shape[1], C.shape[2]
    p = tp[3] + ((phi - tp[3]) % (tp[npp] - tp[3]))
    b = tb[3] + ((beta - tb[3]) % (tb[nb] - tb[3]))
    i = _span(ts, ns, s)
    j = _span(tp, npp, p)
    m = _span(tb, nb, b)
    Ns, dNs, Np, dNp, Nb, dNb = np.empty(4), np.empty(4), np.empty(4), np.empty(4), np.empty(4), np.empty(4)
    _basis(ts, i, s, Ns, dNs)
    _basis(tp, j, p, Np, dNp)
    _basis(tb, m, b, Nb, dNb)
    for k in range(C.shape[3]):
        v = vs = vp = vb = 0.0
        for a in range(4):
            pv = pp = pb = 0.0
            for q in range(4):
                bv = bb = 0.0
                for r in range(4):
                    c = C[i - 3 + a, j - 3 + q, m - 3 + r, k]
                    bv += Nb[r] * c
                    bb += dNb[r] * c
                pv += Np[q] * bv
                pp += dNp[q] * bv
                pb += Np[q] * bb
            v += Ns[a] * pv
            vs += dNs[a] * pv
            vp += Ns[a] * pp
            vb += Ns[a] * pb
        out[k, 0] = v
        out[k, 1] = vs
        out[k, 2] = vp
        out[k, 3] = vb


@njit(cache=True)
def _g3(ts, tp, tb, C, eps, phi, beta, g):
    """g[k] = (G_k, dG_k/deps, dG_k/dphi, dG_k/dbeta) from the spline in s = -ln(1 - eps)."""
    s = -math.log1p(-eps)
    spline3(ts, tp, tb, C, s, phi, beta, g)
    dsde = math.exp(s)
    for k in range(2):
        g[k, 1] *= dsde


@njit(cache=True)
def map3_force(ts, tp, tb, C, eps_min, scale, CR, y, z, vy, vz, omega, want_jac, F, J):
    """map_force for a grooved bore: F = S r (G_r u + G_t w) with G also a function of the
    attitude phi; the Jacobian gains r dG/dphi in the attitude terms. Returns eps (NaN when F
    or J is not finite); eps below eps_min is evaluated at eps_min along the same direction."""
    eps, cp, sp, eps_eval, a, c, r = journal_polar(y, z, vy, vz, omega, CR, eps_min)
    if not eps < 1.0:
        return eps
    phi = math.atan2(sp, cp)
    g = np.empty((2, 4))
    if r > 0.0:
        _g3(ts, tp, tb, C, eps_eval, phi, math.atan2(c, a), g)
        cb, sb = a / r, c / r
        Pr, Pt = r * g[0, 0], r * g[1, 0]
        Pr_a = cb * g[0, 0] - sb * g[0, 3]
        Pr_c = sb * g[0, 0] + cb * g[0, 3]
        Pt_a = cb * g[1, 0] - sb * g[1, 3]
        Pt_c = sb * g[1, 0] + cb * g[1, 3]
        Pr_e, Pt_e = r * g[0, 1], r * g[1, 1]
        Pr_p, Pt_p = r * g[0, 2], r * g[1, 2]
    else:  # no film source: no force; the odd part of the directional response (as map_force)
        Pr = Pt = Pr_e = Pt_e = Pr_p = Pt_p = 0.0
        g2 = np.empty((2, 4))
        _g3(ts, tp, tb, C, eps_eval, phi, 0.0, g)
        _g3(ts, tp, tb, C, eps_eval, phi, math.pi, g2)
        Pr_a = 0.5 * (g[0, 0] - g2[0, 0])
        Pt_a = 0.5 * (g[1, 0] - g2[1, 0])
        _g3(ts, tp, tb, C, eps_eval, phi, 0.5 * math.pi, g)
        _g3(ts, tp, tb, C, eps_eval, phi, -0.5 * math.pi, g2)
        Pr_c = 0.5 * (g[0, 0] - g2[0, 0])
        Pt_c = 0.5 * (g[1, 0] - g2[1, 0])
    F[0] = scale * (Pr * cp - Pt * sp)
    F[1] = scale * (Pr * sp + Pt * cp)
    if not (math.isfinite(F[0]) and math.isfinite(F[1])):
        return math.nan
    if not want_jac:
        return eps
    # as map_force, plus the table's own attitude dependence r dG/dphi
    if not _jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p,
                     J):
        return math.nan
    return eps


# ------------------------------------------------------------------ the compiled-force kernel
# data layout (``pack``): ns, nb, len(ts), len(tb), kwall, eps_min, scale, CR, eps_max, ts, tb, C
_HEAD = 9


def pack(ts, tb, C, kwall, eps_min, scale, CR, eps_max) -> np.ndarray:
    """The map's arrays and constants as the one float64 array ``map_kernel`` reads."""
    ns, nb = C.shape[0], C.shape[1]
    head = np.array([ns, nb, ts.size, tb.size, kwall, eps_min, scale, CR, eps_max], dtype=np.float64)
    return np.ascontiguousarray(np.concatenate([head, np.ravel(ts), np.ravel(tb), np.ravel(C)]), dtype=np.float64)


def _map_kernel(dp, y, z, vy, vz, omega, op):
    """``internals.compiled`` kernel of the force map: ``map_force`` with its Jacobian and the
    refusals of ``ForceMap._run`` (beyond eps_max, a non-finite input or result): status 1."""
    head = carray(dp, _HEAD)
    ns, nb, nts, ntb = int(head[0]), int(head[1]), int(head[2]), int(head[3])
    ts = carray(advance(dp, _HEAD), nts)
    tb = carray(advance(dp, _HEAD + nts), ntb)
    C = carray(advance(dp, _HEAD + nts + ntb), (ns, nb, 2))
    F = carray(op, 2)
    J = carray(advance(op, 2), (2, 4))
    eps = map_force(ts, tb, C, ns, nb, head[4], head[5], head[6], head[7], y, z, vy, vz, omega, True, F, J)
    if not eps < head[8] or not math.isfinite(vy + vz + omega):
        return 1
    return 0


_KERNEL = []


def map_kernel():
    """The cfunc of ``_map_kernel``, compiled (or loaded from its cache) at the first call, not
    at import: the FMU and the Python driver import this module and never call it."""
    if not _KERNEL:
        _KERNEL.append(cfunc(KERNEL_SIG, cache=True)(_map_kernel))
    return _KERNEL[0]


# ------------------------------------------------------------------ the lobed bore (``lobemap``)
@njit(cache=True)
def lobes_force(ts, tp, tb, C, eps_min, scale, CR, eps_max, centre, rot, y, z, vy, vz, omega, want_jac, F, J):
    """A lobed bore's force from its lobe arc's 3-D map (``lobemap``'s docstring): the sum over the
    lobes k of Rot(alpha_k) map3_force(Rot(-alpha_k) e - O_0, Rot(-alpha_k) v), the Jacobian's position
    and velocity blocks turned as Rot(alpha_k) J_k Rot(-alpha_k). ``rot`` (N, 2): (cos, sin) alpha_k;
    ``centre``: O_0 [m]; CR the arc's clearance C_pad. Returns the largest eps' of the lobes, or the
    first lobe's eps' that is >= eps_max or NaN (then F and J are not the answer)."""
    Fk = np.empty(2)
    Jk = np.empty((2, 4))
    F[0] = 0.0
    F[1] = 0.0
    for i in range(2):
        for j in range(4):
            J[i, j] = 0.0
    worst = 0.0
    for k in range(rot.shape[0]):
        c, s = rot[k, 0], rot[k, 1]
        eps = map3_force(ts, tp, tb, C, eps_min, scale, CR, c * y + s * z - centre[0], -s * y + c * z - centre[1],
                         c * vy + s * vz, -s * vy + c * vz, omega, want_jac, Fk, Jk)
        if not eps < eps_max:
            return eps
        worst = max(worst, eps)
        F[0] += c * Fk[0] - s * Fk[1]
        F[1] += s * Fk[0] + c * Fk[1]
        if want_jac:
            for b in range(0, 4, 2):  # R Jb R^T of the position (b = 0) and velocity (b = 2) blocks
                m00 = c * Jk[0, b] - s * Jk[1, b]
                m01 = c * Jk[0, b + 1] - s * Jk[1, b + 1]
                m10 = s * Jk[0, b] + c * Jk[1, b]
                m11 = s * Jk[0, b + 1] + c * Jk[1, b + 1]
                J[0, b] += m00 * c - m01 * s
                J[0, b + 1] += m00 * s + m01 * c
                J[1, b] += m10 * c - m11 * s
                J[1, b + 1] += m10 * s + m11 * c
    return worst


# data layout (``pack_lobes``): n_lobes, C's 3 dims, len(ts), len(tp), len(tb), eps_min, scale, CR, eps_max,
# O_0 (2), then rot (n_lobes, 2), ts, tp, tb, C
_LHEAD = 13


def pack_lobes(ts, tp, tb, C, eps_min, scale, CR, eps_max, centre, rot) -> np.ndarray:
    """The lobe map's arrays and constants as the one float64 array ``lobes_kernel`` reads."""
    head = np.array([rot.shape[0], *C.shape[:3], ts.size, tp.size, tb.size, eps_min, scale, CR, eps_max, *centre],
                    dtype=np.float64)
    return np.ascontiguousarray(np.concatenate([head, *(np.ravel(a) for a in (rot, ts, tp, tb, C))]), dtype=np.float64)


def _lobes_kernel(dp, y, z, vy, vz, omega, op):
    """``internals.compiled`` kernel of the lobed bore's map: ``lobes_force`` with its Jacobian and the
    refusals of ``LobedForceMap`` (beyond eps_max of a lobe, a non-finite input or result): status 1."""
    head = carray(dp, _LHEAD)
    n, n0, n1, n2 = int(head[0]), int(head[1]), int(head[2]), int(head[3])
    nts, ntp, ntb = int(head[4]), int(head[5]), int(head[6])
    rot = carray(advance(dp, _LHEAD), (n, 2))
    at = _LHEAD + 2 * n
    ts = carray(advance(dp, at), nts)
    tp = carray(advance(dp, at + nts), ntp)
    tb = carray(advance(dp, at + nts + ntp), ntb)
    C = carray(advance(dp, at + nts + ntp + ntb), (n0, n1, n2, 2))
    centre = carray(advance(dp, 11), 2)
    F = carray(op, 2)
    J = carray(advance(op, 2), (2, 4))
    if not (math.isfinite(y) and math.isfinite(z) and math.isfinite(vy + vz + omega)):
        return 1
    eps = lobes_force(ts, tp, tb, C, head[7], head[8], head[9], head[10], centre, rot, y, z, vy, vz, omega, True, F, J)
    if not eps < head[10]:
        return 1
    return 0


_LOBES_KERNEL = []


def lobes_kernel():
    """The cfunc of ``_lobes_kernel``, compiled (or loaded from its cache) at the first call."""
    if not _LOBES_KERNEL:
        _LOBES_KERNEL.append(cfunc(KERNEL_SIG, cache=True)(_lobes_kernel))
    return _LOBES_KERNEL[0]


# the spline's pieces and the force's chain rule, by public names for the fed-groove map's kernel
# (``supplykernels``: a 4-D spline and the supply pressure's force)
bspline_span, bspline_basis, force_jacobian = _span, _basis, _jacobian
