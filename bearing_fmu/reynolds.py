"""Finite-volume Reynolds solver for a plain cylindrical journal bearing.

Equation (DESIGN.md, paper eq. 2 with the circumferential length R*theta)::

    (1/R^2) d/dth(h^3 dp/dth) + d/dx(h^3 dp/dx) = 6 mu omega dh/dth + 12 mu dh/dt
    h = CR + y sin(th) - z cos(th),   dh/dt = vy sin(th) - vz cos(th)

theta periodic, x in [-L/2, L/2] with p = 0 at both ends. Force on the journal
F = int p (sin th, -cos th) R dth dx.

Discretization (see docs/reynolds.md)
-------------------------------------
Cell-centred finite volumes, ``n_theta`` cells around the circumference (centres at
th_i = i * 2 pi / n_theta, faces half-way) and ``n_x`` cells along the length. The equation
is integrated over each cell (in th, x): diffusive fluxes use h^3 evaluated at the face
(th faces: h(th_{i+1/2}); x faces: h(th_i)); the Couette and squeeze sources are integrated
exactly over the cell, so the right-hand side is
b_i = -dx [6 mu omega (h_{i+1/2} - h_{i-1/2}) + 12 mu int_cell dh/dt dth], the same for all
axial cells of a column. With no misalignment p is symmetric in x, so only the half x < 0
is solved (m = n_x / 2 axial cells, zero flux at x = 0).

End faces (p = 0): the flux uses the second-order one-sided gradient of the quadratic
through p = 0 at the end and the first two cell centres, (9 p0 - p1) / (3 dx), instead of
the first-order p0 / (dx / 2); row 0 is scaled by 3/4 so that A stays symmetric (its axial
part becomes 3 p0 - p1; a positive row scaling changes neither the solution nor the LCP).
The force uses the midpoint sum in theta and, along x, the midpoint sum with the
Euler-Maclaurin end correction -(dx^2/24) p'(end) (weights 7/8 dx and 73/72 dx for the two
cells next to the end). Together these cut the axial error at n_x = 8 from 3 % (half-cell
Dirichlet + plain midpoint sum) to 0.1 %, see docs/reynolds.md.

Written as A p = b, A is a symmetric, irreducibly diagonally dominant M-matrix. Unknowns
are ordered axial-fastest, which makes A a periodic banded matrix of half-bandwidth m.

Linear solver: banded Cholesky of the first n_theta - 1 columns plus a bordered last column
(the periodic wrap), O(n_theta m^3), in numba. When some theta column is entirely cavitated
the ordering starts right after it and the border decouples (plain banded Cholesky).

Cavitation
----------
"reynolds": Swift-Stieber as the linear complementarity problem p >= 0, A p - b >= 0,
p (A p - b) = 0, solved exactly by a primal-dual active-set method (Hintermueller, Ito &
Kunisch 2003, SIAM J. Optim. 13:865): on the active (cavitated) set p = 0, on the rest
A p = b is solved directly; the sets are updated from the sign of p and of the multiplier
A p - b until they repeat. For an M-matrix this terminates in finitely many steps
(monotonically after the first) from any start, in at most n + 1 passes (the method is the
Newton-min iteration; Ben Gharbia & Gilbert 2009, INRIA RR-7160, recall the bound), each pass
one banded Cholesky factorization.

Start. Cold: computed from the inputs only (cavitated where the cell source b <= 0, less a
margin of n_theta/16 columns on either side of the positive-source arc), 3-9 passes. Warm
(the default, ``warm_start=True``): the cavitated set of the last converged call, moved by
extrapolating w = p - (A p - b) (p on free cells, minus the multiplier on cavitated ones)
linearly through the last call and an earlier one; 1-2 passes when the state moves little
between calls, as between the Newton iterates and time steps of a transient. The cold start
is used instead when the source direction is more than WARM_MAX_TURN_CELLS cells from the one
expected (the last call's, extrapolated like w) or |ln(1 - eps)| changed by more than
WARM_MAX_DLOG since the last call (beyond that a warm start took more passes than the cold
one), and a warm start not settled within n_theta/16 + 4 passes is abandoned for the cold
start. Whatever the start, the LCP's unique solution comes
out, and with the same converged set the last pass factors the same matrix, so results do not
depend on the call history: bit for bit in every sequence measured (docs/studies,
2026-11-24). Only a cell degenerate to round-off (p and A p - b both ~0) could settle on
either side; the force would then differ at round-off and the Jacobian take the other
one-sided value.
"gumbel": the full (uncavitated) system, then p < 0 clipped to 0 (half-Sommerfeld).

Derivatives
-----------
With the converged active set fixed, A(q) p = b(q, v) on the free nodes, so
dF_a/ds = w_a^T A^-1 (db/ds - dA/ds p) = mu_a^T (db/ds - dA/ds p) with the adjoint
mu_a = A^-1 w_a (A symmetric): two extra back-substitutions with the existing
factorization give all eight derivatives (equivalent to the four direct solves
dp = A^-1 (db - dA p)). For "gumbel" w_a is masked to the positive-pressure nodes and
dA p uses the unclipped pressure. Where the source vanishes identically (journal centred and
still, or whirling at exactly half speed) p = 0 and the force is only directionally
differentiable; there the derivative reported is the odd part (F(db) - F(-db)) / 2 of the
first-order film response, which is what central differences converge to.

Work arrays and the remembered calls live in the object: one Reynolds instance is not
re-entrant (use one per thread); copying or pickling it copies them too.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .internals import check_state
from .params import BearingParams

__all__ = ["Reynolds", "DEFAULT_N_THETA", "DEFAULT_N_X", "CAVITATION_MODELS"]

# Default grid, from the convergence study in docs/reynolds.md (benchmarks/bench_reynolds.py).
DEFAULT_N_THETA = 128
DEFAULT_N_X = 16
CAVITATION_MODELS = ("reynolds", "gumbel")
_MODE = {"gumbel": 0, "reynolds": 1}
# Warm start (docs/studies/2026-11-24-reynolds-warm-start.md): converged calls remembered, and
# the cold start whenever the source direction is more than WARM_MAX_TURN_CELLS theta cells
# from the one expected or |ln(1 - eps)| changed by more than WARM_MAX_DLOG since the last
# call (beyond these a warm start took more passes than the cold one on average).
WARM_HISTORY = 4
WARM_MAX_TURN_CELLS = 2.0
WARM_MAX_DLOG = 1.0


# ----------------------------------------------------------------------------------------
# numba kernels
# ----------------------------------------------------------------------------------------


@njit(cache=True)
def _assemble(y, z, vy, vz, omega, CR, mu, R, dth, dx, sin_c, cos_c, sin_f, cos_f, ds, dc, at, ax, b):
    """Face coefficients (scaled by 1/CR^3: H = h/CR) and the per-column right-hand side."""
    N = sin_c.shape[0]
    ct = dx / (R * R * dth)
    cx = dth / dx
    for i in range(N):
        hf = 1.0 + (y * sin_f[i] - z * cos_f[i]) / CR
        hc = 1.0 + (y * sin_c[i] - z * cos_c[i]) / CR
        at[i] = hf * hf * hf * ct
        ax[i] = hc * hc * hc * cx
    s = dx / (CR * CR * CR)
    for i in range(N):
        # h_{i+1/2} - h_{i-1/2} = y ds - z dc ; int dh/dt = -vy dc - vz ds
        b[i] = -s * (6.0 * mu * omega * (y * ds[i] - z * dc[i]) + 12.0 * mu * (-vy * dc[i] - vz * ds[i]))


@njit(cache=True)
def _apply(N, m, at, ax, tdiag, rs, p, out):
    """out = A p (unmodified operator, half axial domain)."""
    for i in range(N):
        im = i - 1 if i > 0 else N - 1
        ip = i + 1 if i < N - 1 else 0
        a0 = at[i]
        a1 = at[im]
        axi = ax[i]
        for j in range(m):
            k = i * m + j
            v = rs[j] * ((a0 + a1) * p[k] - a0 * p[ip * m + j] - a1 * p[im * m + j])
            w = tdiag[j] * p[k]
            if j > 0:
                w -= p[k - 1]
            if j < m - 1:
                w -= p[k + 1]
            out[k] = v + axi * w


@njit(cache=True)
def _modified(N, m, at, ax, tdiag, rs, act, diag, cxo, cto):
    """Entries of A with the rows and columns of active (cavitated) nodes replaced by identity."""
    for i in range(N):
        im = i - 1 if i > 0 else N - 1
        for j in range(m):
            k = i * m + j
            if act[k]:
                diag[k] = 1.0
                cxo[k] = 0.0
                cto[k] = 0.0
                continue
            diag[k] = rs[j] * (at[i] + at[im]) + ax[i] * tdiag[j]
            if j > 0 and not act[k - 1]:
                cxo[k] = -ax[i]
            else:
                cxo[k] = 0.0
            if not act[im * m + j]:
                cto[k] = -rs[j] * at[im]
            else:
                cto[k] = 0.0


@njit(cache=True)
def _factor(N, m, s0, diag, cxo, cto, act, Lb, Y, S):
    """Bordered banded Cholesky of the modified matrix in the block order s0, s0+1, ... (mod N).

    Lb[k, d] = L[k, k-d] for the first N-1 blocks (half-bandwidth m); the last block in this
    order is the border: Y = L^-1 E, S = chol(S0 - Y^T Y). Returns whether the border couples.
    """
    n1 = (N - 1) * m
    for k in range(n1):
        r = k // m
        j = k - r * m
        ib = s0 + r
        if ib >= N:
            ib -= N
        kp = ib * m + j
        if act[kp]:
            for d in range(1, m + 1):
                Lb[k, d] = 0.0
            Lb[k, 0] = 1.0
            continue
        for d in range(m, 0, -1):
            c = k - d
            if c < 0:
                Lb[k, d] = 0.0
                continue
            s = 0.0
            if d == 1 and j > 0:
                s = cxo[kp]
            if d == m and r > 0:
                s += cto[kp]
            for t in range(1, m - d + 1):
                if c - t < 0:
                    break
                s -= Lb[k, d + t] * Lb[c, t]
            Lb[k, d] = s / Lb[c, 0]
        s = diag[kp]
        for d in range(1, m + 1):
            s -= Lb[k, d] * Lb[k, d]
        Lb[k, 0] = math.sqrt(s)
    ibB = s0 + N - 1
    if ibB >= N:
        ibB -= N
    has_border = False
    for j in range(m):
        if cto[s0 * m + j] != 0.0 or cto[ibB * m + j] != 0.0:
            has_border = True
    # S0: the border block's own (tridiagonal) entries
    for a in range(m):
        for c in range(m):
            S[a, c] = 0.0
        S[a, a] = diag[ibB * m + a]
        if a > 0:
            S[a, a - 1] = cxo[ibB * m + a]
            S[a - 1, a] = cxo[ibB * m + a]
    if has_border:
        # Y = L^-1 E; E couples block 0 (row j) and block N-2 (row (N-2) m + j) to border j
        for k in range(n1):
            for c in range(m):
                Y[k, c] = 0.0
        for j in range(m):
            Y[j, j] = cto[s0 * m + j]
            Y[(N - 2) * m + j, j] += cto[ibB * m + j]
        for k in range(n1):
            for c in range(m):
                s = Y[k, c]
                for d in range(1, m + 1):
                    if k - d < 0:
                        break
                    s -= Lb[k, d] * Y[k - d, c]
                Y[k, c] = s / Lb[k, 0]
        for a in range(m):
            for c in range(a + 1):
                s = 0.0
                for k in range(n1):
                    s += Y[k, a] * Y[k, c]
                S[a, c] -= s
                if c != a:
                    S[c, a] -= s
    # dense Cholesky of S (lower triangle)
    for a in range(m):
        for c in range(a + 1):
            s = S[a, c]
            for t in range(c):
                s -= S[a, t] * S[c, t]
            if c == a:
                S[a, a] = math.sqrt(s)
            else:
                S[a, c] = s / S[c, c]
    return has_border


@njit(cache=True)
def _solve(N, m, s0, Lb, Y, S, has_border, rhs, x, zb, z2):
    """x = A_mod^-1 rhs with the factors of _factor (rhs, x in the physical order)."""
    n1 = (N - 1) * m
    for k in range(n1):
        r = k // m
        j = k - r * m
        ib = s0 + r
        if ib >= N:
            ib -= N
        s = rhs[ib * m + j]
        for d in range(1, m + 1):
            if k - d < 0:
                break
            s -= Lb[k, d] * zb[k - d]
        zb[k] = s / Lb[k, 0]
    ibB = s0 + N - 1
    if ibB >= N:
        ibB -= N
    for a in range(m):
        s = rhs[ibB * m + a]
        if has_border:
            for k in range(n1):
                s -= Y[k, a] * zb[k]
        for t in range(a):
            s -= S[a, t] * z2[t]
        z2[a] = s / S[a, a]
    for a in range(m - 1, -1, -1):
        s = z2[a]
        for t in range(a + 1, m):
            s -= S[t, a] * z2[t]
        z2[a] = s / S[a, a]
        x[ibB * m + a] = z2[a]
    for k in range(n1 - 1, -1, -1):
        s = zb[k]
        if has_border:
            for c in range(m):
                s -= Y[k, c] * z2[c]
        for d in range(1, m + 1):
            if k + d >= n1:
                break
            s -= Lb[k + d, d] * zb[k + d]
        zb[k] = s / Lb[k, 0]
        r = k // m
        j = k - r * m
        ib = s0 + r
        if ib >= N:
            ib -= N
        x[ib * m + j] = zb[k]


@njit(cache=True)
def _pick_start(N, m, act):
    """Block order start: right after the first fully cavitated column, else 0."""
    for i in range(N):
        full = True
        for j in range(m):
            if not act[i * m + j]:
                full = False
                break
        if full:
            return i + 1 if i + 1 < N else 0
    return 0


@njit(cache=True)
def _film(mode, N, m, at, ax, tdiag, rs, b, grow, max_iter, warm,
          act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info):
    """Pressure p for the column source b (A p = rs b per cell) with the cavitation model.

    Leaves the factorization of the final (modified) matrix in Lb, Y, S and returns
    (s0, has_border, iterations) with iterations = -1 if the active-set loop did not settle
    within max_iter passes. warm (reynolds only): start from the set already in act (the
    previous call's converged set) instead of the cold start computed from b.
    gumbel: pf = full solution, p = max(pf, 0), act = False everywhere.
    """
    n = N * m
    bmax = 0.0
    for i in range(N):
        if abs(b[i]) > bmax:
            bmax = abs(b[i])
    if mode == 0:
        for k in range(n):
            act[k] = False
        _modified(N, m, at, ax, tdiag, rs, act, diag, cxo, cto)
        hb = _factor(N, m, 0, diag, cxo, cto, act, Lb, Y, S)
        for i in range(N):
            for j in range(m):
                rhs[i * m + j] = rs[j] * b[i]
        _solve(N, m, 0, Lb, Y, S, hb, rhs, pf, zb, z2)
        for k in range(n):
            p[k] = pf[k] if pf[k] > 0.0 else 0.0
        info[2] = 0.0
        return 0, hb, 1
    # Reynolds (Swift-Stieber) LCP by the primal-dual active-set method.
    # Cold start: cavitated where the source is not positive, minus a margin of `grow` columns
    # on either side of every positive-source run (the Reynolds film extends beyond the
    # converging part; the iteration frees cavitated nodes only one layer per step).
    # Warm start: act as left by the previous call. The LCP of an M-matrix has one solution
    # and the method reaches it from any start (Hintermueller, Ito & Kunisch 2003, Thm 3.1).
    if not warm:
        for i in range(N):
            free = False
            for d in range(-grow, grow + 1):
                ii = (i + d) % N
                if b[ii] > 0.0:
                    free = True
                    break
            for j in range(m):
                act[i * m + j] = not free
    iters = 0
    s0 = 0
    hb = False
    dmax = 0.0
    pmax = 0.0
    while True:
        if iters >= max_iter:
            return s0, hb, -1
        iters += 1
        _modified(N, m, at, ax, tdiag, rs, act, diag, cxo, cto)
        s0 = _pick_start(N, m, act)
        hb = _factor(N, m, s0, diag, cxo, cto, act, Lb, Y, S)
        for i in range(N):
            for j in range(m):
                k = i * m + j
                rhs[k] = 0.0 if act[k] else rs[j] * b[i]
        _solve(N, m, s0, Lb, Y, S, hb, rhs, p, zb, z2)
        for k in range(n):
            if act[k]:
                p[k] = 0.0
        _apply(N, m, at, ax, tdiag, rs, p, tmp)
        pmax = 0.0
        dmax = 0.0
        for k in range(n):
            if p[k] > pmax:
                pmax = p[k]
            if diag[k] > dmax:
                dmax = diag[k]
        tol = 1e-12 * (bmax + 2.0 * dmax * pmax)
        changed = False
        for i in range(N):
            for j in range(m):
                k = i * m + j
                if act[k]:
                    if tmp[k] - rs[j] * b[i] < -tol:
                        act[k] = False
                        changed = True
                elif p[k] < 0.0:
                    act[k] = True
                    changed = True
        if not changed:
            break
    # complementarity residual max |min(p, A p - b)|, scaled
    res = 0.0
    for i in range(N):
        for j in range(m):
            k = i * m + j
            lam = tmp[k] - rs[j] * b[i]
            v = p[k] if p[k] < lam else lam
            if abs(v) > res:
                res = abs(v)
    scale = bmax + 2.0 * dmax * pmax
    info[2] = res / scale if scale > 0.0 else 0.0
    return s0, hb, iters


@njit(cache=True)
def _warm_start(N, m, y, z, vy, vz, omega, CR, act, hs, order, nvalid, wring, max_turn, max_dlog):
    """Start set of a warm call, or False for the cold start (then the history is dropped).

    hs[slot] = (y/CR, z/CR, uy, uz) of a remembered converged call, wring[slot] its
    complementarity variable w (p on free nodes, -(A p - b) on cavitated ones), order the
    slots newest first, nvalid[0] how many are valid. The source b is a sinusoid in theta whose
    phase is the direction of u = (omega y - 2 vz, omega z + 2 vy) (and the LCP is positively
    homogeneous in b), so the cavitated region turns with u. The start is the newest set (call
    a), moved by the linear extrapolation of w through a and an earlier call b: cavitated where
    w_a + alpha (w_a - w_b) <= 0, alpha = the projection of the position step on the step from
    b to a, in [0, 2] (a time step's first Newton iterate continues the last step's motion; a
    Newton correction gets alpha ~ 0). Warm only if u is at most max_turn [rad] from
    u_a + alpha (u_a - u_b), the direction the extrapolated set belongs to, and |ln(1 - eps)|
    changed by at most max_dlog since a (docs/studies/2026-11-24-reynolds-warm-start.md).
    """
    if nvalid[0] == 0:
        return False
    a = order[0]
    qy = y / CR
    qz = z / CR
    # the anchor: the most recent earlier call at least a quarter of this step away
    dy = qy - hs[a, 0]
    dz = qz - hs[a, 1]
    dd = dy * dy + dz * dz
    alpha = 0.0
    bslot = a
    for r in range(1, nvalid[0]):
        bslot = order[r]
        ey = hs[a, 0] - hs[bslot, 0]
        ez = hs[a, 1] - hs[bslot, 1]
        ee = ey * ey + ez * ez
        if ee > 0.0 and ee >= 0.0625 * dd:
            alpha = min(max((dy * ey + dz * ez) / ee, 0.0), 2.0)
            break
    # the source direction expected at this call (extrapolated like w) against the actual one
    uy = omega * y - 2.0 * vz
    uz = omega * z + 2.0 * vy
    ey = hs[a, 2] + alpha * (hs[a, 2] - hs[bslot, 2])
    ez = hs[a, 3] + alpha * (hs[a, 3] - hs[bslot, 3])
    cu = math.sqrt(uy * uy + uz * uz)
    pu = math.sqrt(ey * ey + ez * ez)
    eps = math.sqrt(qy * qy + qz * qz)
    eps_a = math.sqrt(hs[a, 0] * hs[a, 0] + hs[a, 1] * hs[a, 1])
    if cu == 0.0 or pu == 0.0 or abs(math.log1p(-eps) - math.log1p(-eps_a)) > max_dlog \
            or (uy * ey + uz * ez) < math.cos(max_turn) * cu * pu:
        nvalid[0] = 0
        return False
    if alpha > 0.0:
        for k in range(N * m):
            act[k] = wring[a, k] + alpha * (wring[a, k] - wring[bslot, k]) <= 0.0
    return True


@njit(cache=True)
def _remember(N, m, y, z, vy, vz, omega, CR, rs, b, act, p, tmp, hs, order, nvalid, wring):
    """Store the converged call (tmp = A p of the final pass) as the newest history entry."""
    H = order.shape[0]
    slot = order[H - 1]
    for r in range(H - 1, 0, -1):
        order[r] = order[r - 1]
    order[0] = slot
    if nvalid[0] < H:
        nvalid[0] += 1
    hs[slot, 0] = y / CR
    hs[slot, 1] = z / CR
    hs[slot, 2] = omega * y - 2.0 * vz
    hs[slot, 3] = omega * z + 2.0 * vy
    for i in range(N):
        for j in range(m):
            k = i * m + j
            wring[slot, k] = -(tmp[k] - rs[j] * b[i]) if act[k] else p[k]


@njit(cache=True)
def _integrate(N, m, p, sin_c, cos_c, qw, wr, F):
    """F = 2 sum_i sum_j qw_j p_ij (sin th_i, -cos th_i) R dth (both halves of the length)."""
    fy = 0.0
    fz = 0.0
    for i in range(N):
        s = 0.0
        for j in range(m):
            s += qw[j] * p[i * m + j]
        fy += s * sin_c[i]
        fz -= s * cos_c[i]
    F[0] = fy * wr
    F[1] = fz * wr


@njit(cache=True)
def _source_derivatives(y, z, omega, CR, mu, dx, ds, dc, db):
    """db[q] = d b / d s_q per column, s = (y, z, vy, vz) (b is linear in all four)."""
    s = dx / (CR * CR * CR)
    for i in range(ds.shape[0]):
        db[0, i] = -s * 6.0 * mu * omega * ds[i]
        db[1, i] = s * 6.0 * mu * omega * dc[i]
        db[2, i] = s * 12.0 * mu * dc[i]
        db[3, i] = s * 12.0 * mu * ds[i]


@njit(cache=True)
def _kernel(
    mode, want_jac, y, z, vy, vz, omega, CR, mu, R, dth, dx, m,
    sin_c, cos_c, sin_f, cos_f, ds, dc, tdiag, rs, qw,
    at, ax, b, db, dat, dax, diag, cxo, cto, act, Lb, Y, S, zb, z2,
    p, pf, rhs, tmp, mu_y, mu_z, F, dFq, dFv, Ft, info, max_iter, grow,
    use_warm, warm_cap, max_turn, max_dlog, hs, order, nvalid, wring,
):
    """One call. info = [passes of the converged solve (-1: not converged), cavitated fraction,
    complementarity residual, banded factorizations in all, warm start used, warm start
    abandoned for the cold start]. use_warm: remember converged calls and start from them
    (reynolds cavitation only; see _warm_start)."""
    N = sin_c.shape[0]
    n = N * m
    wr = 2.0 * R * dth
    _assemble(y, z, vy, vz, omega, CR, mu, R, dth, dx, sin_c, cos_c, sin_f, cos_f, ds, dc, at, ax, b)
    use_warm = use_warm and mode == 1
    if not use_warm:
        nvalid[0] = 0  # act is overwritten below: nothing remembered stays valid
    warm = use_warm and _warm_start(N, m, y, z, vy, vz, omega, CR, act, hs, order, nvalid, wring,
                                    max_turn, max_dlog)
    info[4] = 1.0 if warm else 0.0
    s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, grow, warm_cap if warm else max_iter, warm,
                          act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    if warm and iters < 0:
        # not settled within warm_cap passes from the previous set: today's cold start
        info[3] += warm_cap
        info[5] = 1.0
        s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, grow, max_iter, False,
                              act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    info[0] = iters
    if iters < 0:
        nvalid[0] = 0
        return
    info[3] += iters
    if use_warm:
        _remember(N, m, y, z, vy, vz, omega, CR, rs, b, act, p, tmp, hs, order, nvalid, wring)
    _integrate(N, m, p, sin_c, cos_c, qw, wr, F)
    nact = 0
    for k in range(n):
        if act[k] or (mode == 0 and pf[k] <= 0.0):
            nact += 1
    info[1] = nact / n
    if not want_jac:
        return
    _source_derivatives(y, z, omega, CR, mu, dx, ds, dc, db)
    bzero = True
    for i in range(N):
        if b[i] != 0.0:
            bzero = False
            break
    if bzero:
        # No source at all (journal still and centred, or whirling at exactly half speed):
        # p = 0 and the force is only directionally differentiable. To first order a
        # perturbation ds gives the film of the source db ds on the unchanged matrix, and that
        # map is positively homogeneous; report its odd part (F(db) - F(-db)) / 2, which is
        # the derivative wherever the map is linear (exactly so for the continuum at the
        # centre, by rotational symmetry) and what central differences converge to.
        for q in range(4):
            cy = 0.0
            cz = 0.0
            for sgn in (1.0, -1.0):
                for i in range(N):
                    dat[i] = sgn * db[q, i]
                it2 = _film(mode, N, m, at, ax, tdiag, rs, dat, grow, max_iter, False,
                            act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)[2]
                if it2 < 0:
                    info[0] = -1.0
                    return
                info[3] += it2
                _integrate(N, m, p, sin_c, cos_c, qw, wr, Ft)
                cy += 0.5 * sgn * Ft[0]
                cz += 0.5 * sgn * Ft[1]
            if q < 2:
                dFq[0, q] = cy
                dFq[1, q] = cz
            else:
                dFv[0, q - 2] = cy
                dFv[1, q - 2] = cz
        # restore the state's own (zero) film; no source to warm-start from
        nvalid[0] = 0
        for k in range(n):
            p[k] = 0.0
            pf[k] = 0.0
            act[k] = mode == 1
        info[2] = 0.0
        return
    # adjoints mu_a = A_mod^-1 w_a (w masked to the free / positive-pressure nodes)
    for i in range(N):
        for j in range(m):
            k = i * m + j
            free = pf[k] > 0.0 if mode == 0 else not act[k]
            rhs[k] = wr * qw[j] * sin_c[i] if free else 0.0
    _solve(N, m, s0, Lb, Y, S, hb, rhs, mu_y, zb, z2)
    for i in range(N):
        for j in range(m):
            k = i * m + j
            free = pf[k] > 0.0 if mode == 0 else not act[k]
            rhs[k] = -wr * qw[j] * cos_c[i] if free else 0.0
    _solve(N, m, s0, Lb, Y, S, hb, rhs, mu_z, zb, z2)
    if mode == 1:
        for k in range(n):
            if act[k]:
                mu_y[k] = 0.0
                mu_z[k] = 0.0
    pp = pf if mode == 0 else p
    ctf = dx / (R * R * dth)
    cxf = dth / dx
    for q in range(2):
        # dF/dq = mu^T (db/dq - dA/dq p); d(H^3)/dq at faces and centres, dH/dy = sin / CR,
        # dH/dz = -cos / CR
        for i in range(N):
            hf = 1.0 + (y * sin_f[i] - z * cos_f[i]) / CR
            hc = 1.0 + (y * sin_c[i] - z * cos_c[i]) / CR
            gf = sin_f[i] if q == 0 else -cos_f[i]
            gc = sin_c[i] if q == 0 else -cos_c[i]
            dat[i] = 3.0 * hf * hf * gf / CR * ctf
            dax[i] = 3.0 * hc * hc * gc / CR * cxf
        _apply(N, m, dat, dax, tdiag, rs, pp, tmp)
        sy = 0.0
        sz = 0.0
        for i in range(N):
            for j in range(m):
                k = i * m + j
                g = rs[j] * db[q, i] - tmp[k]
                sy += mu_y[k] * g
                sz += mu_z[k] * g
        dFq[0, q] = sy
        dFq[1, q] = sz
    for q in range(2):
        # dF/dv = mu^T db/dv (A does not depend on v)
        sy = 0.0
        sz = 0.0
        for i in range(N):
            ty = 0.0
            tz = 0.0
            for j in range(m):
                ty += rs[j] * mu_y[i * m + j]
                tz += rs[j] * mu_z[i * m + j]
            sy += ty * db[q + 2, i]
            sz += tz * db[q + 2, i]
        dFv[0, q] = sy
        dFv[1, q] = sz


# ----------------------------------------------------------------------------------------
# the internal
# ----------------------------------------------------------------------------------------


def _check_grid(name: str, value, minimum: int, even: bool):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"Reynolds: {name} must be an integer, got {value!r}")
    value = int(value)
    rule = f"an even integer >= {minimum}" if even else f"an integer >= {minimum}"
    if value < minimum or (even and value % 2):
        raise ValueError(f"Reynolds: {name} must be {rule}, got {value}")
    if value > 100_000:
        raise ValueError(f"Reynolds: {name} = {value} is unreasonably large (at most 100000)")
    return value


class Reynolds:
    """Finite-volume Reynolds solver: the truth internal.

    Reynolds(params, n_theta=None, n_x=None, cavitation="reynolds")

    n_theta : cells around the circumference (integer >= 8), default DEFAULT_N_THETA
    n_x     : cells along the bearing length (even integer >= 2; the half x < 0 is solved),
              default DEFAULT_N_X
    cavitation : "reynolds" (Swift-Stieber, exact complementarity) or "gumbel"
              (half-Sommerfeld: full solution clipped at 0)
    warm_start : start the active-set method from the last converged calls' cavitated set
              (reynolds cavitation; the result is the same whatever the start, see the
              module docstring); False = always the cold start computed from the inputs.
              ``counts()`` sums calls and passes; ``forget()`` drops what was remembered.
    """

    def __init__(self, params: BearingParams, n_theta: int | None = None, n_x: int | None = None,
                 cavitation: str = "reynolds", warm_start: bool = True):
        if not isinstance(params, BearingParams):
            raise TypeError(f"Reynolds: params must be a BearingParams, got {type(params).__name__}")
        if not isinstance(cavitation, str) or cavitation.lower() not in CAVITATION_MODELS:
            raise ValueError(
                f"Reynolds: cavitation must be one of {', '.join(repr(c) for c in CAVITATION_MODELS)}, "
                f"got {cavitation!r}"
            )
        self.params = params
        self.n_theta = _check_grid("n_theta", DEFAULT_N_THETA if n_theta is None else n_theta, 8, False)
        self.n_x = _check_grid("n_x", DEFAULT_N_X if n_x is None else n_x, 2, True)
        self.cavitation = cavitation.lower()
        self._mode = _MODE[self.cavitation]
        N, m = self.n_theta, self.n_x // 2
        self._m = m
        self._dth = 2.0 * math.pi / N
        self._dx = params.L / self.n_x
        th = np.arange(N) * self._dth
        thf = th + 0.5 * self._dth
        self._theta = th
        self._x = -0.5 * params.L + (np.arange(self.n_x) + 0.5) * self._dx
        self._sin_c, self._cos_c = np.sin(th), np.cos(th)
        self._sin_f, self._cos_f = np.sin(thf), np.cos(thf)
        # differences of face values: exactly h_{i+1/2} - h_{i-1/2} and the squeeze integral
        self._ds = self._sin_f - np.roll(self._sin_f, 1)
        self._dc = self._cos_f - np.roll(self._cos_f, 1)
        # axial stencil (in units of h^3 dth / dx), half domain from the end (j = 0) to the
        # symmetry plane (j = m - 1, zero flux). End face: second-order one-sided flux from
        # the quadratic through p = 0 at the end and the first two cell centres,
        # (9 p0 - p1) / (3 dx); row 0 is scaled by rs0 = 3/4 to keep A symmetric, which
        # leaves the axial row as 3 p0 - p1 (the LCP is unchanged by a positive row scaling).
        td = np.full(m, 2.0)
        rs = np.ones(m)
        qw = np.full(m, self._dx)
        if m == 1:
            # one cell per half: symmetric quadratic p0 (L^2/4 - x^2) / (3 L^2 / 16)
            td[0] = 8.0 / 3.0
            qw[0] = 8.0 / 9.0 * self._dx
        else:
            td[0] = 3.0
            td[-1] = 1.0
            rs[0] = 0.75
            # axial quadrature: midpoint sum with the Euler-Maclaurin end correction
            # -(dx^2 / 24) p'(end), p'(end) = (9 p0 - p1) / (3 dx); p' = 0 at the symmetry plane
            qw[0] -= self._dx / 8.0
            qw[1] += self._dx / 72.0
        self._tdiag, self._rs, self._qw = td, rs, qw
        n = N * m
        f = np.zeros
        self._at, self._ax, self._b, self._dat, self._dax = f(N), f(N), f(N), f(N), f(N)
        self._diag, self._cxo, self._cto = f(n), f(n), f(n)
        self._act = np.zeros(n, dtype=np.bool_)
        self._Lb = f(((N - 1) * m, m + 1))
        self._Y = f(((N - 1) * m, m))
        self._S = f((m, m))
        self._zb, self._z2 = f((N - 1) * m), f(m)
        self._p, self._pf, self._rhs, self._tmp = f(n), f(n), f(n), f(n)
        self._mu_y, self._mu_z = f(n), f(n)
        self._F, self._dFq, self._dFv, self._Ft = f(2), f((2, 2)), f((2, 2)), f(2)
        self._db = f((4, N))
        self._info = f(6)
        self._max_iter = 4 * n + 10
        self._grow = max(1, int(round(N / 16)))
        self.warm_start = bool(warm_start)
        # warm start (see _warm_start): the last WARM_HISTORY converged calls, and the limits
        # beyond which the cold start is used (measured, docs/studies/2026-11-24-reynolds-warm-start.md)
        self._hs = f((WARM_HISTORY, 4))
        self._order = np.arange(WARM_HISTORY, dtype=np.int64)
        self._nvalid = np.zeros(1, dtype=np.int64)
        self._wring = f((WARM_HISTORY, n))
        self._max_turn = min(WARM_MAX_TURN_CELLS * self._dth, math.pi)
        self._warm_cap = self._grow + 4
        self.reset_counts()

    @classmethod
    def from_options(cls, params: BearingParams, options, context=None) -> "Reynolds":
        """From the registry's checked options (``internals.REGISTRY["reynolds"]``; grid 0 = default)."""
        return cls(params, n_theta=options["n_theta"] or None, n_x=options["n_x"] or None,
                   cavitation=options["cavitation"])

    def __repr__(self) -> str:
        return (f"Reynolds({self.params!r}, n_theta={self.n_theta}, n_x={self.n_x}, "
                f"cavitation={self.cavitation!r})")

    # -- warm start and counters ------------------------------------------------------------
    def forget(self) -> None:
        """Drop the remembered calls: the next call starts cold (results do not change)."""
        self._nvalid[0] = 0

    def reset_counts(self) -> None:
        """Zero the call and pass counters of ``counts``."""
        self._n_calls = 0
        self._n_passes = 0
        self._n_warm = 0
        self._n_fallback = 0

    def counts(self) -> dict:
        """Counters since construction or ``reset_counts``: calls, banded factorizations
        (active-set passes) in all, calls started warm, warm starts abandoned for the cold start."""
        return {"calls": self._n_calls, "passes": self._n_passes, "warm_starts": self._n_warm,
                "cold_fallbacks": self._n_fallback}

    def _count(self) -> None:
        self._n_calls += 1
        self._n_passes += int(self._info[3])
        self._n_warm += bool(self._info[4])
        self._n_fallback += bool(self._info[5])

    def _run(self, y, z, vy, vz, omega, want_jac):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        check_state(self.params, y, z, vy, vz, omega)
        pr = self.params
        self._info[:] = 0.0
        _kernel(
            self._mode, want_jac, y, z, vy, vz, omega, pr.CR, pr.mu, pr.R, self._dth, self._dx, self._m,
            self._sin_c, self._cos_c, self._sin_f, self._cos_f, self._ds, self._dc, self._tdiag,
            self._rs, self._qw,
            self._at, self._ax, self._b, self._db, self._dat, self._dax, self._diag, self._cxo, self._cto,
            self._act, self._Lb, self._Y, self._S, self._zb, self._z2,
            self._p, self._pf, self._rhs, self._tmp, self._mu_y, self._mu_z,
            self._F, self._dFq, self._dFv, self._Ft, self._info, self._max_iter, self._grow,
            self.warm_start, self._warm_cap, self._max_turn, WARM_MAX_DLOG,
            self._hs, self._order, self._nvalid, self._wring,
        )
        self._count()
        if self._info[0] < 0:  # pragma: no cover - not observed; guards against cycling
            raise RuntimeError(
                f"Reynolds: active-set iteration did not converge in {self._max_iter} steps at "
                f"y={y!r}, z={z!r}, vy={vy!r}, vz={vz!r}, omega={omega!r}"
            )
        if not (np.all(np.isfinite(self._F)) and (not want_jac or (np.all(np.isfinite(self._dFq))
                                                                    and np.all(np.isfinite(self._dFv))))):
            raise RuntimeError(  # pragma: no cover - never observed
                f"Reynolds: non-finite result at y={y!r}, z={z!r}, vy={vy!r}, vz={vz!r}, omega={omega!r}"
            )

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] on the journal."""
        self._run(y, z, vy, vz, omega, False)
        return float(self._F[0]), float(self._F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF_dq (2,2), dF_dv (2,2)): raw derivatives dF_i/dq_j, q = (y, z), v = (vy, vz),
        exact for the discrete system with the converged cavitation set held fixed."""
        self._run(y, z, vy, vz, omega, True)
        return self._F.copy(), self._dFq.copy(), self._dFv.copy()

    def pressure(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(theta (n_theta,), x (n_x,), p (n_theta, n_x)) [rad, m, Pa] at the cell centres."""
        self._run(y, z, vy, vz, omega, False)
        half = self._p.reshape(self.n_theta, self._m)
        p = np.concatenate([half, half[:, ::-1]], axis=1)
        return self._theta.copy(), self._x.copy(), p

    def diagnostics(self, y: float, z: float, vy: float, vz: float, omega: float) -> dict:
        """Solver statistics of a call at a state: active-set iterations of the converged solve,
        banded factorizations in all (``passes``: more than ``iterations`` only when a warm
        start was abandoned for the cold one, ``cold_fallback``), whether the start was the
        remembered set (``warm_start``), cavitated fraction of the cells, and (for "reynolds")
        the scaled complementarity residual max|min(p, A p - b)| / scale."""
        self._run(y, z, vy, vz, omega, False)
        return {
            "iterations": int(self._info[0]),
            "passes": int(self._info[3]),
            "warm_start": bool(self._info[4]),
            "cold_fallback": bool(self._info[5]),
            "cavitated_fraction": float(self._info[1]),
            "complementarity_residual": float(self._info[2]),
        }
