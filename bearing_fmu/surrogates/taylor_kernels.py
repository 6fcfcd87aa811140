"""The compiled (numba) kernels of the Taylor internal: evaluation of the surrogate's
polynomial, its wall factor and its short-bearing shape columns, with the analytic Jacobian,
and the fitted-domain distance. Plain arrays in (``meta``, exponents, coefficients: see
``taylor.Taylor``), error codes out; the Python wrappers turn those into BearingStateError.

The kernels with shape columns are separate entry points, so a surrogate without them never
compiles the short-bearing kernel (numba compiles a function's whole call graph on first
use). Cached on disk (``cache=True``) beside this file.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.params import BearingParams
from ..physics.solver.shortbearing import short_bearing_constant, short_bearing_kernel

# Error codes of the kernels, turned into BearingStateError by the Python wrappers.
_OK, _BAD_Y, _BAD_Z, _BAD_VY, _BAD_VZ, _BAD_OMEGA, WRONG_OMEGA, _AT_WALL = 0, 1, 2, 3, 4, 5, 6, 7
NOT_FINITE = 8  # finite inputs, a force or derivative beyond the float range (a huge velocity)


@njit(cache=True)
def _check_nb(y, z, vy, vz, omega, meta):
    if not np.isfinite(y):
        return _BAD_Y
    if not np.isfinite(z):
        return _BAD_Z
    if not np.isfinite(vy):
        return _BAD_VY
    if not np.isfinite(vz):
        return _BAD_VZ
    if not np.isfinite(omega):
        return _BAD_OMEGA
    om0 = meta[2]
    if abs(omega - om0) > meta[6] * max(abs(om0), 1.0):
        return WRONG_OMEGA
    return _OK


_sb_nb = njit(cache=True)(short_bearing_kernel)  # the shape columns' closed form, compiled


@njit(cache=True)
def _powers(u0, u1, u2, u3, order):
    """pw[v, p] = u_v^p for p <= order."""
    pw = np.empty((4, order + 1))
    for v in range(4):
        pw[v, 0] = 1.0
    for p in range(1, order + 1):
        pw[0, p] = pw[0, p - 1] * u0
        pw[1, p] = pw[1, p - 1] * u1
        pw[2, p] = pw[2, p - 1] * u2
        pw[3, p] = pw[3, p - 1] * u3
    return pw


@njit(cache=True)
def _poly_grad(pw, exps, coef, out):
    """Accumulate two polynomials (rows of coef) and their u-gradients, term by term:
    out[0:2] += value, out[2:6] += d(row 0)/du, out[6:10] += d(row 1)/du; pw from _powers.
    Two rows written out by hand: the hot path (a loop over rows costs ~40 % here)."""
    for k in range(exps.shape[0]):
        e0, e1, e2, e3 = exps[k, 0], exps[k, 1], exps[k, 2], exps[k, 3]
        a0, a1, a2, a3 = pw[0, e0], pw[1, e1], pw[2, e2], pw[3, e3]
        m = a0 * a1 * a2 * a3
        cy = coef[0, k]
        cz = coef[1, k]
        out[0] += cy * m
        out[1] += cz * m
        # d m / d u_v = e_v u_v^(e_v - 1) * (other factors)
        if e0 > 0:
            d = e0 * pw[0, e0 - 1] * a1 * a2 * a3
            out[2] += cy * d
            out[6] += cz * d
        if e1 > 0:
            d = e1 * pw[1, e1 - 1] * a0 * a2 * a3
            out[3] += cy * d
            out[7] += cz * d
        if e2 > 0:
            d = e2 * pw[2, e2 - 1] * a0 * a1 * a3
            out[4] += cy * d
            out[8] += cz * d
        if e3 > 0:
            d = e3 * pw[3, e3 - 1] * a0 * a1 * a2
            out[5] += cy * d
            out[9] += cz * d


@njit(cache=True)
def _shape_terms(y, z, vy, vz, omega, u0, u1, u2, u3, meta, sexps, scoef, jac, out):
    """Add the shape columns sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u) to out, in the kernels'
    scaled units (force / force_scale, derivatives in u): out[0:2] = F, with ``jac`` also
    out[2:10] = dF/du (2 x 4). scoef rows: (Fy by S_y, Fy by S_z, Fz by S_y, Fz by S_z)."""
    r = _sb_nb(y, z, vy, vz, omega, meta[3], meta[9], jac)
    fs = meta[5]
    pw = _powers(u0, u1, u2, u3, int(meta[10]))
    # the four polynomials M_l(u) = sum_j scoef[l, j] m_j(u) and their u-gradients, two at a time:
    # row i of pq holds (M_2i, M_2i+1, dM_2i/du, dM_2i+1/du)
    pq = np.zeros((2, 10))
    _poly_grad(pw, sexps, scoef[0:2], pq[0])
    _poly_grad(pw, sexps, scoef[2:4], pq[1])
    sy, sz = r[0], r[1]
    for i in range(2):
        out[i] += (pq[i, 0] * sy + pq[i, 1] * sz) / fs
    if jac:
        # dS/du_v = dS/dx_v * (CR for positions, omega CR for velocities)
        for v in range(4):
            sc = meta[3] if v < 2 else meta[4]
            dsy = r[2 + v] * sc
            dsz = r[6 + v] * sc
            for i in range(2):
                out[2 + 4 * i + v] += (pq[i, 2 + v] * sy + pq[i, 0] * dsy + pq[i, 6 + v] * sz + pq[i, 1] * dsz) / fs


@njit(cache=True)
def force_nb(y, z, vy, vz, omega, meta, exps, coef):
    """meta = (y0, z0, omega0, pos_scale, vel_scale, force_scale, omega_rtol, order, wall_power,
    c0, shape_order); pos_scale is CR (the wall factor and the shape columns use it), c0 the
    short-bearing constant (shape kernels only)."""
    code = _check_nb(y, z, vy, vz, omega, meta)
    if code != 0:
        return 0.0, 0.0, code
    order = int(meta[7])
    u0 = (y - meta[0]) / meta[3]
    u1 = (z - meta[1]) / meta[3]
    u2 = vy / meta[4]
    u3 = vz / meta[4]
    pw = _powers(u0, u1, u2, u3, order)
    fy = 0.0
    fz = 0.0
    for k in range(exps.shape[0]):
        m = pw[0, exps[k, 0]] * pw[1, exps[k, 1]] * pw[2, exps[k, 2]] * pw[3, exps[k, 3]]
        fy += coef[0, k] * m
        fz += coef[1, k] * m
    s = meta[5]
    p = meta[8]
    if p != 0.0:  # wall factor (1 - eps^2)^(-p); p = 0 skips it, bit-identical to the plain polynomial
        cr = meta[3]
        q = 1.0 - (y * y + z * z) / (cr * cr)
        if not q > 0.0:
            return 0.0, 0.0, _AT_WALL
        s *= q ** (-p)
    return _finite(fy * s, fz * s)


@njit(cache=True)
def _finite(fy, fz):
    """(fy, fz, 0), or NOT_FINITE when either overflowed (finite inputs: a huge velocity)."""
    if np.isfinite(fy) and np.isfinite(fz):
        return fy, fz, 0
    return 0.0, 0.0, NOT_FINITE


@njit(cache=True)
def _force_jac_nb(y, z, vy, vz, omega, meta, exps, coef, out):
    """Fill out[0:2] = F, out[2:10] = dF/du (row-major, 2 x 4), in scaled units; return code."""
    code = _check_nb(y, z, vy, vz, omega, meta)
    if code != 0:
        return code
    order = int(meta[7])
    u = np.empty(4)
    u[0] = (y - meta[0]) / meta[3]
    u[1] = (z - meta[1]) / meta[3]
    u[2] = vy / meta[4]
    u[3] = vz / meta[4]
    pw = _powers(u[0], u[1], u[2], u[3], order)
    for i in range(10):
        out[i] = 0.0
    _poly_grad(pw, exps, coef, out)
    p = meta[8]
    if p != 0.0:
        # F = h P with h = (1 - eps^2)^(-p): dF/du = h dP/du + P dh/du, and in scaled positions
        # (u0 = (y - y0)/CR) dh/du0 = 2 p (y/CR) h / (1 - eps^2), likewise for z; h is independent of v
        cr = meta[3]
        yc = y / cr
        zc = z / cr
        q = 1.0 - (yc * yc + zc * zc)
        if not q > 0.0:
            return _AT_WALL
        h = q ** (-p)
        gy = 2.0 * p * yc * h / q
        gz = 2.0 * p * zc * h / q
        for i in range(2):
            P = out[i]
            b = 2 + 4 * i
            out[b] = h * out[b] + P * gy
            out[b + 1] = h * out[b + 1] + P * gz
            out[b + 2] *= h
            out[b + 3] *= h
            out[i] = h * P
    return 0


@njit(cache=True)
def _to_si(code, out, meta):
    """(code, F (2,) [N], dF/dq (2, 2) [N/m], dF/dv (2, 2) [N s/m]) from the scaled out[0:10],
    so the Python wrapper does no array arithmetic."""
    F = np.zeros(2)
    dq = np.zeros((2, 2))
    dv = np.zeros((2, 2))
    if code != 0:
        return code, F, dq, dv
    fs = meta[5]
    gq, gv = fs / meta[3], fs / meta[4]
    F[0], F[1] = out[0] * fs, out[1] * fs
    for i in range(2):
        dq[i, 0], dq[i, 1] = out[2 + 4 * i] * gq, out[3 + 4 * i] * gq
        dv[i, 0], dv[i, 1] = out[4 + 4 * i] * gv, out[5 + 4 * i] * gv
    if not (np.all(np.isfinite(F)) and np.all(np.isfinite(dq)) and np.all(np.isfinite(dv))):
        return NOT_FINITE, F, dq, dv
    return code, F, dq, dv


@njit(cache=True)
def force_jac_si_nb(y, z, vy, vz, omega, meta, exps, coef):
    out = np.empty(10)
    return _to_si(_force_jac_nb(y, z, vy, vz, omega, meta, exps, coef, out), out, meta)


# With shape columns: separate entry points, so a surrogate without them never compiles the
# short-bearing kernel (numba compiles a function's whole call graph on first use).
@njit(cache=True)
def _inside_wall(y, z, meta):
    cr = meta[3]
    return 1.0 - (y * y + z * z) / (cr * cr) > 0.0


@njit(cache=True)
def force_shape_nb(y, z, vy, vz, omega, meta, exps, coef, sexps, scoef):
    fy, fz, code = force_nb(y, z, vy, vz, omega, meta, exps, coef)
    if code != 0:
        return fy, fz, code
    if not _inside_wall(y, z, meta):
        return 0.0, 0.0, _AT_WALL
    out = np.zeros(2)
    _shape_terms(y, z, vy, vz, omega, (y - meta[0]) / meta[3], (z - meta[1]) / meta[3], vy / meta[4],
                 vz / meta[4], meta, sexps, scoef, False, out)
    return _finite(fy + out[0] * meta[5], fz + out[1] * meta[5])


@njit(cache=True)
def force_jac_shape_si_nb(y, z, vy, vz, omega, meta, exps, coef, sexps, scoef):
    out = np.empty(10)
    code = _force_jac_nb(y, z, vy, vz, omega, meta, exps, coef, out)
    if code == 0:
        if _inside_wall(y, z, meta):
            _shape_terms(y, z, vy, vz, omega, (y - meta[0]) / meta[3], (z - meta[1]) / meta[3], vy / meta[4],
                         vz / meta[4], meta, sexps, scoef, True, out)
        else:
            code = _AT_WALL
    return _to_si(code, out, meta)


@njit(cache=True)
def _sb_many_nb(states, omega, cr, c0, jac):
    out = np.empty((states.shape[0], 10))
    for k in range(states.shape[0]):
        r = _sb_nb(states[k, 0], states[k, 1], states[k, 2], states[k, 3], omega, cr, c0, jac)
        for i in range(10):
            out[k, i] = r[i]
    return out


def short_bearing_at(params: BearingParams, states, omega: float, jac: bool = False) -> np.ndarray:
    """The short-bearing closed form at raw states (M, 4) -> (M, 10): Fy, Fz [N] and, with
    ``jac``, dFy/d(y, z, vy, vz), dFz/d(y, z, vy, vz) in SI (see shortbearing.short_bearing_kernel).
    Compiled; raises ValueError for a state at or beyond the wall (eccentricity >= 1)."""
    st = np.ascontiguousarray(np.atleast_2d(np.asarray(states, float)))
    q = 1.0 - (st[:, 0] ** 2 + st[:, 1] ** 2) / params.CR**2
    if np.any(~(q > 0.0)):
        raise ValueError(f"short-bearing shape columns: {int(np.sum(~(q > 0.0)))} state(s) at or beyond the wall "
                         "(eccentricity >= 1) or not finite; the closed form is undefined there")
    return _sb_many_nb(st, float(omega), params.CR, short_bearing_constant(params), bool(jac))


@njit(cache=True)
def domain_distance_nb(y, z, vy, vz, dom):
    """dom = (y0, z0, pos_scale, vel_scale, ecc_max, cy, cz, radius, v_max, lo[4], hi[4]);
    see Taylor.domain_distance. NaN input gives NaN."""
    if not (np.isfinite(y) and np.isfinite(z) and np.isfinite(vy) and np.isfinite(vz)):
        return np.nan
    cr, vs = dom[2], dom[3]
    u0, u1, u2, u3 = (y - dom[0]) / cr, (z - dom[1]) / cr, vy / vs, vz / vs
    ecc_max, cy, cz, r, vmax = dom[4], dom[5], dom[6], dom[7], dom[8]
    dist = np.hypot(y, z) / cr / ecc_max - 1.0 if ecc_max > 0 else np.inf
    if r > 0:
        dist = max(dist, np.hypot(u0 - cy, u1 - cz) / r - 1.0)
    if vmax > 0:
        dist = max(dist, np.hypot(u2, u3) / vmax - 1.0)
    elif u2 != 0.0 or u3 != 0.0:
        dist = np.inf
    for v in range(4):
        lo, hi = dom[9 + v], dom[13 + v]
        half = 0.5 * (hi - lo)
        if half > 0:
            uv = u0 if v == 0 else u1 if v == 1 else u2 if v == 2 else u3
            dist = max(dist, abs(uv - 0.5 * (hi + lo)) / half - 1.0)
    return dist

