"""numba kernels of the Reynolds solver (``reynolds.py``, whose docstring explains the
discretisation, the cavitation problem, the active-set method and its warm start, and the
adjoint derivatives): assembly, the banded Cholesky with the periodic border, the active-set
iteration, the force integral and the whole call (``reynolds_kernel``)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


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
def apply_operator(N, m, at, ax, tdiag, rs, p, out):
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
def modified_entries(N, m, at, ax, tdiag, rs, act, diag, cxo, cto):
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
def factor_banded(N, m, s0, diag, cxo, cto, act, Lb, Y, S):
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
def solve_banded(N, m, s0, Lb, Y, S, has_border, rhs, x, zb, z2):
    """x = A_mod^-1 rhs with the factors of factor_banded (rhs, x in the physical order)."""
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
def pick_start(N, m, act):
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
        modified_entries(N, m, at, ax, tdiag, rs, act, diag, cxo, cto)
        hb = factor_banded(N, m, np.int64(0), diag, cxo, cto, act, Lb, Y, S)  # int64, not a literal 0: one compilation
        for i in range(N):
            for j in range(m):
                rhs[i * m + j] = rs[j] * b[i]
        solve_banded(N, m, np.int64(0), Lb, Y, S, hb, rhs, pf, zb, z2)
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
        modified_entries(N, m, at, ax, tdiag, rs, act, diag, cxo, cto)
        s0 = pick_start(N, m, act)
        hb = factor_banded(N, m, s0, diag, cxo, cto, act, Lb, Y, S)
        for i in range(N):
            for j in range(m):
                k = i * m + j
                rhs[k] = 0.0 if act[k] else rs[j] * b[i]
        solve_banded(N, m, s0, Lb, Y, S, hb, rhs, p, zb, z2)
        for k in range(n):
            if act[k]:
                p[k] = 0.0
        apply_operator(N, m, at, ax, tdiag, rs, p, tmp)
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
def warm_start_set(N, m, y, z, vy, vz, omega, CR, act, hs, order, nvalid, wring, max_turn, max_dlog):
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
def remember_call(N, m, y, z, vy, vz, omega, CR, rs, b, act, p, tmp, hs, order, nvalid, wring):
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
def reynolds_kernel(
    mode, want_jac, y, z, vy, vz, omega, CR, mu, R, dth, dx, m,
    sin_c, cos_c, sin_f, cos_f, ds, dc, tdiag, rs, qw,
    at, ax, b, db, dat, dax, diag, cxo, cto, act, Lb, Y, S, zb, z2,
    p, pf, rhs, tmp, mu_y, mu_z, F, dFq, dFv, Ft, info, max_iter, grow,
    use_warm, warm_cap, max_turn, max_dlog, hs, order, nvalid, wring,
):
    """One call. info = [passes of the converged solve (-1: not converged), cavitated fraction,
    complementarity residual, banded factorizations in all, warm start used, warm start
    abandoned for the cold start]. use_warm: remember converged calls and start from them
    (reynolds cavitation only; see warm_start_set)."""
    N = sin_c.shape[0]
    n = N * m
    wr = 2.0 * R * dth
    _assemble(y, z, vy, vz, omega, CR, mu, R, dth, dx, sin_c, cos_c, sin_f, cos_f, ds, dc, at, ax, b)
    use_warm = use_warm and mode == 1
    if not use_warm:
        nvalid[0] = 0  # act is overwritten below: nothing remembered stays valid
    warm = use_warm and warm_start_set(N, m, y, z, vy, vz, omega, CR, act, hs, order, nvalid, wring,
                                    max_turn, max_dlog)
    info[4] = 1.0 if warm else 0.0
    s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, grow, warm_cap if warm else max_iter, warm,
                          act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    if warm and iters < 0:
        # not settled within warm_cap passes from the previous set: today's cold start
        info[3] += warm_cap
        info[5] = 1.0
        # np.bool_ (and np.int64(0) in _film): typed as the warm call's, so _film etc. compile once, not twice
        s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, grow, max_iter, np.bool_(False),
                              act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    info[0] = iters
    if iters < 0:
        nvalid[0] = 0
        return
    info[3] += iters
    if use_warm:
        remember_call(N, m, y, z, vy, vz, omega, CR, rs, b, act, p, tmp, hs, order, nvalid, wring)
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
                it2 = _film(mode, N, m, at, ax, tdiag, rs, dat, grow, max_iter, np.bool_(False),
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
    # adjoints mu_a = A_mod^-1 w_a (w masked to the free / positive-pressure nodes), a = y, z
    for a in range(2):
        for i in range(N):
            for j in range(m):
                k = i * m + j
                free = pf[k] > 0.0 if mode == 0 else not act[k]
                rhs[k] = (wr * qw[j] * sin_c[i] if a == 0 else -wr * qw[j] * cos_c[i]) if free else 0.0
        solve_banded(N, m, s0, Lb, Y, S, hb, rhs, mu_y if a == 0 else mu_z, zb, z2)
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
        apply_operator(N, m, dat, dax, tdiag, rs, pp, tmp)
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
