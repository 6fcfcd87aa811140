"""The compiled inner linear algebra of the Newmark integrator (rotor_host.integrate.newmark).

These numba kernels do the n-sized work of a step: the start of a step with its linearised
predictor (``k_begin``), one Newton iteration (``k_iter``: residual, Woodbury correction, next
iterate) and the acceptance of an iterate (``k_accept``). The Python driver
(``rotor_host.integrate.newmark``) calls them one by one; the compiled driver
(``rotor_host.integrate.newmark_loop``) calls the same kernels from its loop over steps, so both
paths give the same numbers. ``_correction`` is the Woodbury solve against the banded LU of the
step matrix (``rotor_host.integrate.banded``), ``_solve_small`` the m x m elimination.
``StepOps`` holds the packed arrays that depend on the step size only. Compiled once and cached
on disk (``cache=True``); the fastmath flags are part of the results (they decide the summation
order), so change them only on purpose.
"""

import math

import numpy as np
from numba import njit

from .banded import band_lu, band_matvec, band_solve


@njit(cache=True)
def _solve_small(A, b):
    """Solve A x = b in place (x in b) by Gaussian elimination with partial pivoting.
    Returns False if A is (numerically) singular."""
    m = b.size
    for k in range(m):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        if amax == 0.0 or not np.isfinite(amax):
            return False
        if p != k:
            for j in range(m):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
        piv = A[k, k]
        for i in range(k + 1, m):
            fac = A[i, k] / piv
            if fac != 0.0:
                for j in range(k + 1, m):
                    A[i, j] -= fac * A[k, j]
                b[i] -= fac * b[k]
    for k in range(m - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, m):
            s -= A[k, j] * b[j]
        b[k] = s / A[k, k]
    return True


# Packed buffers (each numba call costs ~0.07 us per argument, so the kernels take few):
#   SB (2, n, 2w+1) : S0 and its LU factors in row-wise band storage (banded.py), this step size
#   W  (m, n)       : row j = S0^{-1} e_{dofs[j]}, the Woodbury columns S0^{-1} P^T
#   MDK (3, n, 2w+1): the bands of M, D = C + Omega G, K: the known part of the residual is
#                     b = M ahat + D ((1 + alpha) vhat + alpha v0) + alpha K q0 + forces
#   cs (7,)         : alpha, c0, c1, h, a3, cv, ca   (see StepOps below)
#   V  (10, n)      : rows below
#   Pm (4, m)       : qP, vP (the next iterate at the nonlinear DOFs), y, fl (work)
#   AJ (4, m, m)    : A (capacitance matrix), Jt (scaled tangent), and the raw tangent
#                     (df/dq, df/dv) of the last evaluated state, the predictor's tangent
_B, _AH, _VH, Q0, Q1, _QS, _R, _X, _DQ, _MA = range(10)


@njit(cache=True)
def _correction(R, Jq, Jv, c1, opa, LU, W, dofs, x, A, y, Jt, dq):
    """dq = -S^{-1} R with S = S0 - opa P^T (Jq + c1 Jv) P, by the Woodbury identity
    S^{-1} = S0^{-1} + W (I - Jt WP)^{-1} Jt P S0^{-1}, W = S0^{-1} P^T, WP = P W, Jt = opa J.
    Returns False if the m x m capacitance matrix is singular."""
    n = R.size
    m = dofs.size
    band_solve(LU, R, x)
    for i in range(m):
        for j in range(m):
            Jt[i, j] = opa * (Jq[i, j] + c1 * Jv[i, j])
    for i in range(m):
        s = 0.0
        for j in range(m):
            s += Jt[i, j] * x[dofs[j]]
        y[i] = s
        for j in range(m):
            acc = 0.0
            Wj = W[j]
            for l in range(m):
                acc += Jt[i, l] * Wj[dofs[l]]
            A[i, j] = -acc
        A[i, i] += 1.0
    ok = _solve_small(A, y)
    for i in range(n):
        s = x[i]
        for j in range(m):
            s += W[j, i] * y[j]
        dq[i] = -s
    return ok


@njit(cache=True)
def k_begin(X, MDK, SB, W, dofs, fe1, fe0, f0, Jq, Jv, cs, V, Pm, AJ):
    """Start a step from the state X = [q0, v0, a0]: b, ahat, vhat, and the predictor (in
    V[Q0]): the step solved exactly with the nonlinear force linearised about the state at t0
    with tangent (Jq, Jv). Returns (ok, ||fe1||, ||b||)."""
    alpha, c0, c1, h, a3, cv, ca = cs[0], cs[1], cs[2], cs[3], cs[4], cs[5], cs[6]
    b, ahat, vhat, q, qstart, R = V[_B], V[_AH], V[_VH], V[Q0], V[_QS], V[_R]
    fl = Pm[3]
    n = b.size
    m = dofs.size
    opa = 1.0 + alpha
    tmp = V[_X]  # free until the correction below
    fen = 0.0
    bn = 0.0
    for i in range(n):
        qi = X[i]
        vi = X[n + i]
        ai = X[2 * n + i]
        ahat[i] = c0 * qi + c0 * h * vi + a3 * ai
        vhat[i] = c1 * qi + cv * vi + ca * ai
        qstart[i] = qi + h * vi + 0.5 * h * h * ai
        R[i] = opa * vhat[i] + alpha * vi  # (R is free until below)
    # b = Hq q0 + Hv v0 + Ha a0 with Hq = c0 M + opa c1 D + alpha K, Hv = c0 h M + (opa cv + alpha) D,
    # Ha = a3 M + opa ca D: two band products (three with alpha), not three
    band_matvec(MDK[0], ahat, b)
    band_matvec(MDK[1], R, tmp)
    for i in range(n):
        b[i] += tmp[i]
    if alpha != 0.0:
        band_matvec(MDK[2], X[:n], tmp)
        for i in range(n):
            b[i] += alpha * tmp[i]
    for i in range(n):
        b[i] += opa * fe1[i] - alpha * fe0[i]
        fen += fe1[i] * fe1[i]
    if alpha != 0.0:
        for j in range(m):
            b[dofs[j]] -= alpha * f0[j]
    for i in range(n):
        bn += b[i] * b[i]
    # linearised force at qstart: fl = f0 + Jq (qs - q0)_P + Jv (vs - v0)_P
    for i in range(m):
        s = f0[i]
        for j in range(m):
            dj = dofs[j]
            s += Jq[i, j] * (qstart[dj] - X[dj]) + Jv[i, j] * (c1 * qstart[dj] - vhat[dj] - X[n + dj])
        fl[i] = s
    band_matvec(SB[0], qstart, R)
    for i in range(n):
        R[i] -= b[i]
    for j in range(m):
        R[dofs[j]] -= opa * fl[j]
    ok = _correction(R, Jq, Jv, c1, opa, SB[1], W, dofs, V[_X], AJ[0], Pm[2], AJ[1], q)
    for i in range(n):
        q[i] += qstart[i]
    qP, vP = Pm[0], Pm[1]
    for j in range(m):
        dj = dofs[j]
        qP[j] = q[dj]
        vP[j] = c1 * q[dj] - vhat[dj]
    return ok, math.sqrt(fen), math.sqrt(bn)


@njit(cache=True)
def k_iter(iq, f, Jq, Jv, SB, W, dofs, cs, V, Pm, AJ):
    """Residual at q = V[iq] with force f, Newton correction, next iterate in the other q row
    (V[Q0] <-> V[Q1]) and its (qP, vP) in Pm. Returns (||R||, ||dq||, ||q||, ||f||, ok)."""
    alpha, c1 = cs[0], cs[2]
    q = V[iq]
    qn = V[Q0 + Q1 - iq]
    b, vhat, R, dq = V[_B], V[_VH], V[_R], V[_DQ]
    n = q.size
    m = dofs.size
    opa = 1.0 + alpha
    band_matvec(SB[0], q, R)
    for i in range(n):
        R[i] -= b[i]
    fn = 0.0
    for j in range(m):
        R[dofs[j]] -= opa * f[j]
        fn += f[j] * f[j]
    rn = 0.0
    for i in range(n):
        rn += R[i] * R[i]
    ok = _correction(R, Jq, Jv, c1, opa, SB[1], W, dofs, V[_X], AJ[0], Pm[2], AJ[1], dq)
    # keep the tangent of the state just evaluated: after acceptance it is the predictor's
    Jql, Jvl = AJ[2], AJ[3]
    for i in range(m):
        for j in range(m):
            Jql[i, j] = Jq[i, j]
            Jvl[i, j] = Jv[i, j]
    dn = 0.0
    qnorm = 0.0
    for i in range(n):
        dn += dq[i] * dq[i]
        qnorm += q[i] * q[i]
        qn[i] = q[i] + dq[i]
    qP, vP = Pm[0], Pm[1]
    for j in range(m):
        dj = dofs[j]
        qP[j] = qn[dj]
        vP[j] = c1 * qn[dj] - vhat[dj]
    return math.sqrt(rn), math.sqrt(dn), math.sqrt(qnorm), math.sqrt(fn), ok


@njit(cache=True)
def k_accept(X, iq, cs, V, MB):
    """X <- [q, v(q), a(q)] with q = V[iq]; returns ||M a|| (M in band storage MB)."""
    c0, c1 = cs[1], cs[2]
    q, ahat, vhat, Ma = V[iq], V[_AH], V[_VH], V[_MA]
    n = q.size
    for i in range(n):
        X[i] = q[i]
        X[n + i] = c1 * q[i] - vhat[i]
        X[2 * n + i] = c0 * q[i] - ahat[i]
    band_matvec(MB, X[2 * n:], Ma)
    s = 0.0
    for i in range(n):
        s += Ma[i] * Ma[i]
    return math.sqrt(s)


# ---------------------------------------------------------------- the arrays per step size

class StepOps:
    """Everything that depends on the step size h only: the coefficients cs, S0 and its LU
    factors (SB, band storage), the Woodbury columns W = S0^{-1} P^T (as rows), and MDK, the
    bands of M, D, K stacked (the known part of the step's residual). MB, DB, KB
    are M, D = C + Omega G and K in band storage (``banded.to_band``, one half-bandwidth);
    ``cfg`` is the NewmarkConfig (alpha, beta, gamma). O(n w^2) to build."""

    def __init__(self, h, MB, DB, KB, dofs, cfg):
        a, b_, g = cfg.alpha, cfg.beta, cfg.gamma
        opa = 1.0 + a
        self.h = h
        self.c0 = 1.0 / (b_ * h * h)
        self.c1 = g / (b_ * h)
        self.a3 = 1.0 / (2.0 * b_) - 1.0
        self.cv = self.c1 * h - 1.0
        self.ca = g * h * self.a3 - h * (1.0 - g)
        S0 = self.c0 * MB + opa * (self.c1 * DB + KB)
        if not np.all(np.isfinite(S0)):
            raise ValueError(f"the linear Newmark matrix has non-finite entries for dt = {h:g}")
        LU = S0.copy()
        if band_lu(LU) >= 0:
            raise ValueError(f"the linear Newmark matrix is singular for dt = {h:g}")
        self.SB = np.ascontiguousarray(np.stack([S0, LU]))
        n = MB.shape[0]
        dofs = np.asarray(dofs, dtype=np.int64)
        self.W = np.zeros((dofs.size, n))
        for j, d in enumerate(dofs):
            e = np.zeros(n)
            e[d] = 1.0
            band_solve(LU, e, self.W[j])
        self.cs = np.array([a, self.c0, self.c1, h, self.a3, self.cv, self.ca])
        self.MDK = np.ascontiguousarray(np.stack([MB, DB, KB]))
