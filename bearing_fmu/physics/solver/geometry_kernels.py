"""numba kernels of the Reynolds solver for a bore with grooves, a partial arc or lobes
(``reynolds.py`` with a non-circular ``physics.bore.geometry.Geometry``; the full bore keeps
``reynolds_kernels.reynolds_kernel`` untouched).

What differs from the full bore, and why it is a separate kernel rather than a branch in the
original one (that one stays bit for bit and as fast):

* the circumferential cells are not uniform (faces on the grooves', arcs' and lobes' edges):
  the face coefficients take per-face distances and per-cell widths (``ct``, ``cx``);
* the film has a centred part that varies with theta (the lobes): h / CR = H0(theta) + (y sin - z cos) / CR,
  which adds the Couette source 6 mu omega CR dH0 to every film cell;
* cells with a prescribed pressure (grooves at the supply pressure, ambient outside an arc) are
  not unknowns: their rows are the identity, their value moves to the right-hand side of the
  neighbouring film cells (Dirichlet on the shared face, whose distance is half the film cell);
* the force adds the prescribed pressures' own force (a constant);
* a circumferential groove (``p_in`` > 0 or its axial stencil, set by the driver): the axial cells
  span one land, ambient at its outer end (j = 0) and the supply pressure p_in on its inner edge
  (j = m - 1), both Dirichlet faces with the same second-order one-sided gradient; the inner row
  scaled by 3/4 too reads 3 p_{m-1} - p_{m-2} - 2 p_in, so 2 ax p_in moves to the right-hand side
  (state-dependent through ax: its derivative 2 dax p_in enters the adjoint's dF/dq).

The banded Cholesky with its periodic border, the operator, the warm start and the call history
are the full bore's (``reynolds_kernels``): the matrix has the same structure. Fixed cells are
marked active (cavitated) for the factorization, so a groove column starts the block order and
the periodic border drops out. The adjoint derivatives hold as before: the prescribed values do
not depend on the state, and A p over all cells, with the fixed values in p, carries the
derivative of their right-hand side through dA/dq.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .reynolds_kernels import (apply_operator, factor_banded, modified_entries, pick_start, remember_call,
                               solve_banded, warm_start_set)


@njit(cache=True)
def _assemble(y, z, vy, vz, omega, CR, mu, dx, sin_c, cos_c, sin_f, cos_f, ds, dc, H0f, H0c, dH0, ct, cx,
              at, ax, b):
    """Face coefficients (scaled by 1/CR^3) and the per-column source, h / CR = H0 + (y sin - z cos) / CR."""
    N = sin_c.shape[0]
    for i in range(N):
        hf = H0f[i] + (y * sin_f[i] - z * cos_f[i]) / CR
        hc = H0c[i] + (y * sin_c[i] - z * cos_c[i]) / CR
        at[i] = hf * hf * hf * ct[i]
        ax[i] = hc * hc * hc * cx[i]
    s = dx / (CR * CR * CR)
    for i in range(N):
        b[i] = -s * (6.0 * mu * omega * (y * ds[i] - z * dc[i] + CR * dH0[i])
                     + 12.0 * mu * (-vy * dc[i] - vz * ds[i]))


@njit(cache=True)
def _rhs(N, m, at, ax, rs, b, fixed, psup, p_in, rhs0):
    """rhs0 = rs (b + the fixed neighbours' pressure over the shared face) on film cells, 0 on fixed ones;
    plus 2 ax p_in on the inner row of a land fed by a circumferential groove at p_in."""
    for i in range(N):
        im = i - 1 if i > 0 else N - 1
        ip = i + 1 if i < N - 1 else 0
        extra = 0.0
        if not fixed[i]:
            if fixed[ip]:
                extra += at[i] * psup[ip]
            if fixed[im]:
                extra += at[im] * psup[im]
        for j in range(m):
            rhs0[i * m + j] = 0.0 if fixed[i] else rs[j] * (b[i] + extra)
        if p_in != 0.0 and not fixed[i]:
            rhs0[i * m + m - 1] += 2.0 * ax[i] * p_in


@njit(cache=True)
def _film(mode, N, m, at, ax, tdiag, rs, b, fixed, psup, p_in, rhs0, grow, max_iter, warm,
          act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info):
    """Pressure p (fixed cells at their value) for the source b; as reynolds_kernels' _film, with
    the fixed cells kept out of the complementarity problem. Returns (s0, has_border, iterations)."""
    n = N * m
    _rhs(N, m, at, ax, rs, b, fixed, psup, p_in, rhs0)
    bmax = 0.0
    for k in range(n):
        if abs(rhs0[k]) > bmax:
            bmax = abs(rhs0[k])
    if mode == 0:
        for i in range(N):
            for j in range(m):
                act[i * m + j] = fixed[i]
        modified_entries(N, m, at, ax, tdiag, rs, act, diag, cxo, cto)
        s0 = pick_start(N, m, act)
        hb = factor_banded(N, m, s0, diag, cxo, cto, act, Lb, Y, S)
        solve_banded(N, m, s0, Lb, Y, S, hb, rhs0, pf, zb, z2)
        for i in range(N):
            for j in range(m):
                k = i * m + j
                if fixed[i]:
                    pf[k] = psup[i]
                p[k] = pf[k] if pf[k] > 0.0 else 0.0
        info[2] = 0.0
        return s0, hb, 1
    if not warm:
        # cold start: cavitated where the column source is not positive, less a margin of `grow`
        # columns around every positive run (the film reaches beyond the converging part)
        for i in range(N):
            free = False
            for d in range(-grow, grow + 1):
                ii = (i + d) % N
                if b[ii] > 0.0 or psup[ii] > 0.0 or p_in > 0.0:
                    free = True
                    break
            for j in range(m):
                act[i * m + j] = not free
    for i in range(N):
        if fixed[i]:
            for j in range(m):
                act[i * m + j] = True
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
        for k in range(n):
            rhs[k] = 0.0 if act[k] else rhs0[k]
        solve_banded(N, m, s0, Lb, Y, S, hb, rhs, p, zb, z2)
        for i in range(N):
            for j in range(m):
                k = i * m + j
                if fixed[i]:
                    p[k] = psup[i]
                elif act[k]:
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
            if fixed[i]:
                continue
            for j in range(m):
                k = i * m + j
                if act[k]:
                    if tmp[k] - rs[j] * b[i] - (2.0 * ax[i] * p_in if j == m - 1 else 0.0) < -tol:
                        act[k] = False
                        changed = True
                elif p[k] < 0.0:
                    act[k] = True
                    changed = True
        if not changed:
            break
    res = 0.0
    for i in range(N):
        if fixed[i]:
            continue
        for j in range(m):
            k = i * m + j
            lam = tmp[k] - rs[j] * b[i] - (2.0 * ax[i] * p_in if j == m - 1 else 0.0)
            v = p[k] if p[k] < lam else lam
            if abs(v) > res:
                res = abs(v)
    scale = bmax + 2.0 * dmax * pmax
    info[2] = res / scale if scale > 0.0 else 0.0
    return s0, hb, iters


@njit(cache=True)
def _integrate(N, m, p, gy, gz, qw, fixed, F0, F):
    """F = F0 + sum over film cells of qw_j p_ij (gy_i, gz_i) (gy, gz: 2 R (sin, -cos) width)."""
    fy = 0.0
    fz = 0.0
    for i in range(N):
        if fixed[i]:
            continue
        s = 0.0
        for j in range(m):
            s += qw[j] * p[i * m + j]
        fy += s * gy[i]
        fz += s * gz[i]
    F[0] = F0[0] + fy
    F[1] = F0[1] + fz


@njit(cache=True)
def geometry_kernel(
    mode, want_jac, y, z, vy, vz, omega, CR, mu, R, dx, m,
    sin_c, cos_c, sin_f, cos_f, ds, dc, H0f, H0c, dH0, ct, cx, gy, gz, fixed, psup, p_in, F0, tdiag, rs, qw,
    at, ax, b, db, dat, dax, diag, cxo, cto, act, Lb, Y, S, zb, z2,
    p, pf, rhs0, rhs, tmp, mu_y, mu_z, F, dFq, dFv, Ft, info, max_iter, grow,
    use_warm, warm_cap, max_turn, max_dlog, hs, order, nvalid, wring,
):
    """One call (the full bore's ``reynolds_kernel`` for this bore); info as there."""
    N = sin_c.shape[0]
    n = N * m
    _assemble(y, z, vy, vz, omega, CR, mu, dx, sin_c, cos_c, sin_f, cos_f, ds, dc, H0f, H0c, dH0, ct, cx,
              at, ax, b)
    use_warm = use_warm and mode == 1
    if not use_warm:
        nvalid[0] = 0
    warm = use_warm and warm_start_set(N, m, y, z, vy, vz, omega, CR, act, hs, order, nvalid, wring,
                                       max_turn, max_dlog)
    info[4] = 1.0 if warm else 0.0
    s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, fixed, psup, p_in, rhs0, grow,
                          warm_cap if warm else max_iter, warm,
                          act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    if warm and iters < 0:
        info[3] += warm_cap
        info[5] = 1.0
        s0, hb, iters = _film(mode, N, m, at, ax, tdiag, rs, b, fixed, psup, p_in, rhs0, grow, max_iter, np.bool_(False),
                              act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)
    info[0] = iters
    if iters < 0:
        nvalid[0] = 0
        return
    info[3] += iters
    if use_warm:
        remember_call(N, m, y, z, vy, vz, omega, CR, rs, b, act, p, tmp, hs, order, nvalid, wring)
    _integrate(N, m, p, gy, gz, qw, fixed, F0, F)
    nact = 0
    nfilm = 0
    for i in range(N):
        if fixed[i]:
            continue
        for j in range(m):
            nfilm += 1
            k = i * m + j
            if act[k] or (mode == 0 and pf[k] <= 0.0):
                nact += 1
    info[1] = nact / nfilm
    if not want_jac:
        return
    # db/ds per column, s = (y, z, vy, vz) (the lobes' source does not depend on the state)
    s = dx / (CR * CR * CR)
    for i in range(N):
        db[0, i] = -s * 6.0 * mu * omega * ds[i]
        db[1, i] = s * 6.0 * mu * omega * dc[i]
        db[2, i] = s * 12.0 * mu * dc[i]
        db[3, i] = s * 12.0 * mu * ds[i]
    quiet = True
    for k in range(n):
        if rhs0[k] != 0.0:
            quiet = False
            break
    if quiet:
        # no source and no supply pressure: p = 0 and the force is only directionally
        # differentiable; report the odd part of the first-order response, as the full bore does
        for q in range(4):
            cy = 0.0
            cz = 0.0
            for sgn in (1.0, -1.0):
                for i in range(N):
                    dat[i] = sgn * db[q, i]
                it2 = _film(mode, N, m, at, ax, tdiag, rs, dat, fixed, psup, p_in, rhs0, grow, max_iter, np.bool_(False),
                            act, diag, cxo, cto, Lb, Y, S, zb, z2, p, pf, rhs, tmp, info)[2]
                if it2 < 0:
                    info[0] = -1.0
                    return
                info[3] += it2
                _integrate(N, m, p, gy, gz, qw, fixed, F0, Ft)
                cy += 0.5 * sgn * (Ft[0] - F0[0])
                cz += 0.5 * sgn * (Ft[1] - F0[1])
            if q < 2:
                dFq[0, q] = cy
                dFq[1, q] = cz
            else:
                dFv[0, q - 2] = cy
                dFv[1, q - 2] = cz
        nvalid[0] = 0
        for k in range(n):
            p[k] = 0.0
            pf[k] = 0.0
            act[k] = mode == 1
        for k in range(n):
            rhs0[k] = 0.0
        info[2] = 0.0
        return
    # adjoints mu_a = A_mod^-1 w_a, w masked to the free (or positive-pressure) film cells
    for i in range(N):
        for j in range(m):
            k = i * m + j
            free = (not fixed[i]) and (pf[k] > 0.0 if mode == 0 else not act[k])
            rhs[k] = qw[j] * gy[i] if free else 0.0
    solve_banded(N, m, s0, Lb, Y, S, hb, rhs, mu_y, zb, z2)
    for i in range(N):
        for j in range(m):
            k = i * m + j
            free = (not fixed[i]) and (pf[k] > 0.0 if mode == 0 else not act[k])
            rhs[k] = qw[j] * gz[i] if free else 0.0
    solve_banded(N, m, s0, Lb, Y, S, hb, rhs, mu_z, zb, z2)
    for k in range(n):
        if act[k]:
            mu_y[k] = 0.0
            mu_z[k] = 0.0
    pp = pf if mode == 0 else p
    for q in range(2):
        # dF/dq = mu^T (db/dq - dA/dq p), p holding the fixed values: their right-hand side's
        # derivative is -dA/dq p on the film cell's row
        for i in range(N):
            hf = H0f[i] + (y * sin_f[i] - z * cos_f[i]) / CR
            hc = H0c[i] + (y * sin_c[i] - z * cos_c[i]) / CR
            gf = sin_f[i] if q == 0 else -cos_f[i]
            gc = sin_c[i] if q == 0 else -cos_c[i]
            dat[i] = 3.0 * hf * hf * gf / CR * ct[i]
            dax[i] = 3.0 * hc * hc * gc / CR * cx[i]
        apply_operator(N, m, dat, dax, tdiag, rs, pp, tmp)
        sy = 0.0
        sz = 0.0
        for i in range(N):
            for j in range(m):
                k = i * m + j
                g = rs[j] * db[q, i] - tmp[k]
                if j == m - 1 and p_in != 0.0 and not fixed[i]:
                    g += 2.0 * dax[i] * p_in  # the groove's Dirichlet term on the inner row
                sy += mu_y[k] * g
                sz += mu_z[k] * g
        dFq[0, q] = sy
        dFq[1, q] = sz
    for q in range(2):
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
