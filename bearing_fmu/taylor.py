"""The Taylor surrogate: a fitted multivariate polynomial of the film force (paper eq. 6).

The force is expanded about the expansion point ``(y0, z0, 0, 0)`` (normally the static
equilibrium) in the four state variables, written in scaled, dimensionless form

    u = ((y - y0) / CR, (z - z0) / CR, vy / (omega CR), vz / (omega CR)),
    F_i / F_ref = sum_k c_ik * u1^e_k1 * u2^e_k2 * u3^e_k3 * u4^e_k4,

over the full monomial basis of total degree <= ``order``: C(order + 4, 4) terms (126 for
order 5, 5 for the linear model of order 1), the constant first, then degree by degree. The
coefficients of the order-1 terms are the scaled derivatives of the force (Lund's
coefficients, negated, times CR / F_ref or omega CR / F_ref).

Wall factor (``wall_power`` p, default 0 = the plain polynomial): the force is the polynomial
divided by (1 - eps^2)^p, eps^2 = (y^2 + z^2) / CR^2 the absolute eccentricity ratio squared,

    F_i / F_ref = (1 - eps^2)^(-p) * sum_k c_ik * u^e_k,

so the polynomial only has to follow G = F (1 - eps^2)^p, which stays bounded as the journal
approaches the wall where F grows without bound. With p > 0 the force is undefined at
eps >= 1 (``force`` raises BearingStateError there, as the domain guard does for any p).

This module holds the basis, the compiled evaluation (``Taylor``, an ``Internal`` with
analytic ``force_and_jacobian``), the fitted-domain guard and the surrogate file. Fitting
lives in :mod:`bearing_fmu.fit`. It never imports the Reynolds solver.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from dataclasses import dataclass, field
from itertools import combinations_with_replacement
from numbers import Integral
from pathlib import Path

import numpy as np
from numba import njit

from .internals import BearingStateError
from .params import BearingParams
from .shortbearing import short_bearing_constant, short_bearing_kernel

FILE_FORMAT = "bearing-fmu-taylor-surrogate"
FILE_VERSION = 1
N_VARS = 4
VAR_NAMES = ("dy", "dz", "dvy", "dvz")
SHAPE_ROWS = ("Fy_Sy", "Fy_Sz", "Fz_Sy", "Fz_Sz")  # shape_coef rows: force component by short-bearing component
OMEGA_RTOL = 1e-9  # the same tolerance the linear internal uses for "omega equals the fitted speed"


# ----------------------------------------------------------------------------- basis

def n_terms(order: int) -> int:
    """Number of monomials of total degree <= order in 4 variables: C(order + 4, 4)."""
    return math.comb(int(order) + N_VARS, N_VARS)


def exponents(order: int) -> np.ndarray:
    """Exponent table, shape (C(order + 4, 4), 4), int64: row k holds the powers of
    (dy, dz, dvy, dvz) of term k. Constant first, then degree 1, 2, ...; within a degree
    lexicographically descending, so degree 1 is dy, dz, dvy, dvz in that order."""
    order = int(order)
    if order < 0:
        raise ValueError(f"Taylor order must be >= 0, got {order}")
    rows = []
    for deg in range(order + 1):
        block = []
        for combo in combinations_with_replacement(range(N_VARS), deg):
            e = [0] * N_VARS
            for v in combo:
                e[v] += 1
            block.append(tuple(e))
        block.sort(reverse=True)
        rows.extend(block)
    return np.array(rows, dtype=np.int64).reshape(-1, N_VARS)


def term_names(exps: np.ndarray) -> list[str]:
    """Readable names of the terms, e.g. '1', 'dy', 'dy^2*dvz'."""
    names = []
    for e in np.asarray(exps):
        parts = [f"{VAR_NAMES[v]}" + (f"^{p}" if p > 1 else "") for v, p in enumerate(e) if p > 0]
        names.append("*".join(parts) if parts else "1")
    return names


def design_matrix(u: np.ndarray, exps: np.ndarray) -> np.ndarray:
    """Basis columns at the scaled states ``u`` (M, 4) -> (M, N), numpy (reference implementation)."""
    u = np.atleast_2d(np.asarray(u, float))
    exps = np.asarray(exps)
    order = int(exps.max()) if exps.size else 0
    pw = np.ones((N_VARS, order + 1, u.shape[0]))
    for v in range(N_VARS):
        for p in range(1, order + 1):
            pw[v, p] = pw[v, p - 1] * u[:, v]
    X = np.ones((u.shape[0], exps.shape[0]))
    for v in range(N_VARS):
        X *= pw[v, exps[:, v]].T
    return X


def natural_force_scale(params: BearingParams, omega: float) -> float:
    """mu |omega| R L (R / CR)^2 [N]: the hydrodynamic force scale of the bearing at speed omega."""
    return params.mu * abs(omega) * params.R * params.L * (params.R / params.CR) ** 2


# ----------------------------------------------------------------------------- compiled kernels
# Error codes of the kernels, turned into BearingStateError by the Python wrappers.
_OK, _BAD_Y, _BAD_Z, _BAD_VY, _BAD_VZ, _BAD_OMEGA, _WRONG_OMEGA, _AT_WALL = 0, 1, 2, 3, 4, 5, 6, 7


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
        return _WRONG_OMEGA
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
def _force_nb(y, z, vy, vz, omega, meta, exps, coef):
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
    return fy * s, fz * s, 0


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
    return code, F, dq, dv


@njit(cache=True)
def _force_jac_si_nb(y, z, vy, vz, omega, meta, exps, coef):
    out = np.empty(10)
    return _to_si(_force_jac_nb(y, z, vy, vz, omega, meta, exps, coef, out), out, meta)


# With shape columns: separate entry points, so a surrogate without them never compiles the
# short-bearing kernel (numba compiles a function's whole call graph on first use).
@njit(cache=True)
def _inside_wall(y, z, meta):
    cr = meta[3]
    return 1.0 - (y * y + z * z) / (cr * cr) > 0.0


@njit(cache=True)
def _force_shape_nb(y, z, vy, vz, omega, meta, exps, coef, sexps, scoef):
    fy, fz, code = _force_nb(y, z, vy, vz, omega, meta, exps, coef)
    if code != 0:
        return fy, fz, code
    if not _inside_wall(y, z, meta):
        return 0.0, 0.0, _AT_WALL
    out = np.zeros(2)
    _shape_terms(y, z, vy, vz, omega, (y - meta[0]) / meta[3], (z - meta[1]) / meta[3], vy / meta[4],
                 vz / meta[4], meta, sexps, scoef, False, out)
    return fy + out[0] * meta[5], fz + out[1] * meta[5], 0


@njit(cache=True)
def _force_jac_shape_si_nb(y, z, vy, vz, omega, meta, exps, coef, sexps, scoef):
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


def shape_force(u, S, shape_exponents, shape_coef) -> np.ndarray:
    """The shape columns' force [N] (M, 2): sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u) at scaled
    states u (M, 4), with S (M, >= 2) the short-bearing force there and shape_coef (4, Nr) in
    SHAPE_ROWS order. Numpy reference of the compiled _shape_terms."""
    Mp = design_matrix(u, shape_exponents) @ np.asarray(shape_coef).T  # (M, 4): the polynomials M_l(u)
    return np.column_stack([Mp[:, 0] * S[:, 0] + Mp[:, 1] * S[:, 1], Mp[:, 2] * S[:, 0] + Mp[:, 3] * S[:, 1]])


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
def _domain_distance_nb(y, z, vy, vz, dom):
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


# ----------------------------------------------------------------------------- fitted domain

@dataclass(frozen=True)
class Domain:
    """Where the surrogate was fitted, for the guard (a caller decides what to do outside).

    All lengths in scaled units: positions in CR, velocities in omega * CR.
      ecc_max    : bound on the eccentricity ratio |(y, z)| / CR of the training states
      pos_center : centre of the position disc, relative to the expansion point (in CR)
      pos_radius : radius of the position disc (in CR)
      v_max      : radius of the velocity disc |(vy, vz)| / (omega CR)
      box_lo/hi  : bounding box of the training states in u = (dy, dz, dvy, dvz) scaled
    A state is inside when it satisfies all of them.
    """

    ecc_max: float
    pos_center: tuple[float, float]
    pos_radius: float
    v_max: float
    box_lo: tuple[float, float, float, float]
    box_hi: tuple[float, float, float, float]

    def to_dict(self) -> dict:
        return {
            "ecc_max": self.ecc_max, "pos_center": list(self.pos_center), "pos_radius": self.pos_radius,
            "v_max": self.v_max, "box_lo": list(self.box_lo), "box_hi": list(self.box_hi),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "domain") -> "Domain":
        return cls(
            ecc_max=_num(d, "ecc_max", where),
            pos_center=tuple(_vec(d, "pos_center", 2, where)),
            pos_radius=_num(d, "pos_radius", where),
            v_max=_num(d, "v_max", where),
            box_lo=tuple(_vec(d, "box_lo", 4, where)),
            box_hi=tuple(_vec(d, "box_hi", 4, where)),
        )


# ----------------------------------------------------------------------------- surrogate

@dataclass
class Surrogate:
    """Everything a fitted Taylor surrogate is: the model and its metadata.

    coef[i, k] is the scaled coefficient of term ``exponents[k]`` for force component i
    (0: Fy, 1: Fz); F_i = force_scale * sum_k coef[i, k] * prod_v u_v^exponents[k, v].
    Pruned terms have coef = 0 and kept = False. With ``wall_power`` p > 0 that sum is divided
    by (1 - eps^2)^p, eps^2 = (y^2 + z^2) / CR^2 (see the module doc); p = 0 (files without the
    key) is the plain polynomial.
    """

    params: BearingParams
    omega: float
    y0: float
    z0: float
    order: int
    exponents: np.ndarray
    coef: np.ndarray
    force_scale: float
    domain: Domain
    kept: np.ndarray | None = None
    lam: tuple[float, float] = (0.0, 0.0)
    load: tuple[float, float] | None = None
    errors: dict = field(default_factory=dict)
    pruning: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    wall_power: float = 0.0
    shape_order: int | None = None
    shape_coef: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.order = int(self.order)
        self.exponents = np.ascontiguousarray(self.exponents, dtype=np.int64).reshape(-1, N_VARS)
        self.coef = np.ascontiguousarray(self.coef, dtype=float).reshape(2, -1)
        n = self.exponents.shape[0]
        if self.coef.shape[1] != n:
            raise ValueError(f"Surrogate: {self.coef.shape[1]} coefficients per component for {n} terms")
        if n and int(self.exponents.sum(axis=1).max()) > self.order:
            raise ValueError(f"Surrogate: exponents exceed the order {self.order}")
        if self.kept is None:
            self.kept = self.coef != 0.0
        self.kept = np.asarray(self.kept, bool).reshape(2, n)
        for name in ("omega", "y0", "z0", "force_scale"):
            v = float(getattr(self, name))
            if not math.isfinite(v):
                raise ValueError(f"Surrogate.{name} = {v!r} is not finite")
            setattr(self, name, v)
        if self.omega == 0.0:
            raise ValueError("Surrogate.omega must be nonzero (velocities are scaled by omega * CR)")
        if not np.all(np.isfinite(self.coef)):
            raise ValueError("Surrogate.coef has non-finite entries")
        self.lam = (float(self.lam[0]), float(self.lam[1]))
        self.wall_power = float(self.wall_power)
        if not (math.isfinite(self.wall_power) and self.wall_power >= 0.0):
            raise ValueError(f"Surrogate.wall_power = {self.wall_power!r} must be finite and >= 0")
        if self.shape_order is None:
            if self.shape_coef is not None:
                raise ValueError("Surrogate.shape_coef given without shape_order")
        else:
            if isinstance(self.shape_order, bool) or not isinstance(self.shape_order, Integral) or self.shape_order < 0:
                raise ValueError(f"Surrogate.shape_order = {self.shape_order!r} must be an integer >= 0")
            self.shape_order = int(self.shape_order)
            nr = n_terms(self.shape_order)
            sc = np.ascontiguousarray(self.shape_coef, dtype=float)
            if sc.shape != (4, nr):
                raise ValueError(f"Surrogate.shape_coef must have shape (4, {nr}) for shape_order "
                                 f"{self.shape_order}, got {sc.shape}")
            if not np.all(np.isfinite(sc)):
                raise ValueError("Surrogate.shape_coef has non-finite entries")
            self.shape_coef = sc

    @property
    def shape_exponents(self) -> np.ndarray:
        """Exponents of the monomials m_j that multiply the shape columns ((0, 4) without them)."""
        if self.shape_order is None:
            return np.zeros((0, N_VARS), np.int64)
        return exponents(self.shape_order)

    @property
    def pos_scale(self) -> float:
        return self.params.CR

    @property
    def vel_scale(self) -> float:
        return abs(self.omega) * self.params.CR

    def scaled(self, states) -> np.ndarray:
        """Raw states (M, 4) = (y, z, vy, vz) [m, m/s] -> scaled u (M, 4)."""
        s = np.atleast_2d(np.asarray(states, float))
        return np.column_stack([
            (s[:, 0] - self.y0) / self.pos_scale, (s[:, 1] - self.z0) / self.pos_scale,
            s[:, 2] / self.vel_scale, s[:, 3] / self.vel_scale,
        ])

    def wall_factor(self, states) -> np.ndarray:
        """(1 - eps^2)^(-wall_power) at raw states (M, 4) -> (M,); ones for wall_power 0
        (NaN or inf at eps >= 1 for wall_power > 0)."""
        s = np.atleast_2d(np.asarray(states, float))
        if self.wall_power == 0.0:
            return np.ones(len(s))
        q = 1.0 - (s[:, 0] ** 2 + s[:, 1] ** 2) / self.pos_scale**2
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(q > 0, q, np.nan) ** (-self.wall_power)

    def predict(self, states) -> np.ndarray:
        """Vectorised numpy evaluation: raw states (M, 4) -> forces (M, 2) [N]. No checks
        (NaN at eps >= 1 with a wall factor)."""
        X = design_matrix(self.scaled(states), self.exponents)
        F = (X @ self.coef.T) * self.force_scale
        if self.wall_power != 0.0:
            F *= self.wall_factor(states)[:, None]
        if self.shape_order is not None:
            F += self.shape_part(states)
        return F

    def shape_part(self, states, S=None) -> np.ndarray:
        """The shape columns' share of the force at raw states (M, 4) -> (M, 2) [N]:
        sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u). ``S`` (M, >= 2): the short-bearing force there,
        if the caller has it."""
        s = np.atleast_2d(np.asarray(states, float))
        if self.shape_order is None:
            return np.zeros((len(s), 2))
        if S is None:
            S = short_bearing_at(self.params, s, self.omega)
        return shape_force(self.scaled(s), S, self.shape_exponents, self.shape_coef)

    @property
    def recipe(self) -> str:
        """Short description of the model's form, e.g. 'order 7, wall factor 1.25, shape columns 3'."""
        parts = [f"order {self.order}"]
        if self.wall_power:
            parts.append(f"wall factor {self.wall_power:g}")
        if self.shape_order is not None:
            parts.append(f"shape columns {self.shape_order}")
        return ", ".join(parts)

    def n_kept(self) -> tuple[int, int]:
        return int(self.kept[0].sum()), int(self.kept[1].sum())

    # ------------------------------------------------------------------ file I/O
    def to_dict(self) -> dict:
        from . import __version__

        prov = dict(self.provenance)
        prov.setdefault("package_version", __version__)
        prov.setdefault("date", _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
        return {
            "format": FILE_FORMAT,
            "version": FILE_VERSION,
            "params": self.params.as_dict(),
            "omega": self.omega,
            "speed_hz": self.omega / (2 * math.pi),
            "load": None if self.load is None else [float(self.load[0]), float(self.load[1])],
            "expansion_point": {"y0": self.y0, "z0": self.z0, "vy0": 0.0, "vz0": 0.0},
            "scaling": {
                "pos_scale": self.pos_scale, "vel_scale": self.vel_scale, "force_scale": self.force_scale,
                "variables": "u = ((y-y0)/CR, (z-z0)/CR, vy/(omega CR), vz/(omega CR)); F = force_scale * sum coef * u^e"
                             + ("" if self.wall_power == 0.0 else " / (1 - (y^2 + z^2)/CR^2)^wall_power"),
            },
            "wall_power": self.wall_power,
            **({} if self.shape_order is None else {"shape": {
                "order": self.shape_order,
                "model": "F_i += sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u): S = short-bearing (Ocvirk, pi-film) "
                         "force [N] at (y, z, vy, vz, omega) (bearing_fmu.shortbearing), m_j(u) = prod_v u_v^e_jv",
                "exponents": self.shape_exponents.tolist(),
                "coef": {k: self.shape_coef[i].tolist() for i, k in enumerate(SHAPE_ROWS)},
            }}),
            "order": self.order,
            "n_terms": int(self.exponents.shape[0]),
            "exponents": self.exponents.tolist(),
            "coef": {"Fy": self.coef[0].tolist(), "Fz": self.coef[1].tolist()},
            "kept": {"Fy": self.kept[0].astype(int).tolist(), "Fz": self.kept[1].astype(int).tolist()},
            "lambda": {"Fy": self.lam[0], "Fz": self.lam[1]},
            "domain": self.domain.to_dict(),
            "errors": _json_clean(self.errors),
            "pruning": _json_clean(self.pruning),
            "provenance": _json_clean(prov),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "surrogate") -> "Surrogate":
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object at the top level")
        fmt = d.get("format")
        if fmt != FILE_FORMAT:
            raise ValueError(f"{where}: key 'format' is {fmt!r}, expected {FILE_FORMAT!r}")
        if d.get("version") != FILE_VERSION:
            raise ValueError(f"{where}: key 'version' is {d.get('version')!r}, this reader knows {FILE_VERSION}")
        p = _get(d, "params", where)
        try:
            params = BearingParams(**{k: _num(p, k, f"{where}: params") for k in ("D", "L", "CR", "mu")})
        except TypeError as exc:  # pragma: no cover - _num already names missing keys
            raise ValueError(f"{where}: params: {exc}") from None
        ep = _get(d, "expansion_point", where)
        sc = _get(d, "scaling", where)
        order = _get(d, "order", where)
        if isinstance(order, bool) or not isinstance(order, int) or order < 0:
            raise ValueError(f"{where}: key 'order' must be a non-negative integer, got {order!r}")
        exps = np.asarray(_get(d, "exponents", where))
        if exps.ndim != 2 or exps.shape[1] != N_VARS or not np.issubdtype(exps.dtype, np.integer):
            raise ValueError(f"{where}: key 'exponents' must be a list of [e_dy, e_dz, e_dvy, e_dvz] integer rows")
        c = _get(d, "coef", where)
        coef = np.array([_vec(c, "Fy", exps.shape[0], f"{where}: coef"), _vec(c, "Fz", exps.shape[0], f"{where}: coef")])
        kept = None
        if "kept" in d:
            kd = d["kept"]
            kept = np.array([_vec(kd, "Fy", exps.shape[0], f"{where}: kept"),
                             _vec(kd, "Fz", exps.shape[0], f"{where}: kept")]).astype(bool)
        lam = d.get("lambda", {"Fy": 0.0, "Fz": 0.0})
        load = d.get("load")
        wall_power = _num(d, "wall_power", where) if "wall_power" in d else 0.0  # older files: none
        shape_order = shape_coef = None
        if "shape" in d:  # older files: none
            sd = _get(d, "shape", where)
            shape_order = _get(sd, "order", f"{where}: shape")
            if isinstance(shape_order, bool) or not isinstance(shape_order, int) or shape_order < 0:
                raise ValueError(f"{where}: shape: key 'order' must be a non-negative integer, got {shape_order!r}")
            nr = n_terms(shape_order)
            if "exponents" in sd and sd["exponents"] != exponents(shape_order).tolist():
                raise ValueError(f"{where}: shape: key 'exponents' is not the full basis of order {shape_order}")
            shc = _get(sd, "coef", f"{where}: shape")
            shape_coef = np.array([_vec(shc, k, nr, f"{where}: shape: coef") for k in SHAPE_ROWS])
        return cls(
            params=params,
            omega=_num(d, "omega", where),
            y0=_num(ep, "y0", f"{where}: expansion_point"),
            z0=_num(ep, "z0", f"{where}: expansion_point"),
            order=order,
            exponents=exps,
            coef=coef,
            force_scale=_num(sc, "force_scale", f"{where}: scaling"),
            domain=Domain.from_dict(_get(d, "domain", where), f"{where}: domain"),
            kept=kept,
            lam=(float(lam.get("Fy", 0.0)), float(lam.get("Fz", 0.0))),
            load=None if load is None else (float(load[0]), float(load[1])),
            errors=d.get("errors", {}),
            pruning=d.get("pruning", {}),
            provenance=d.get("provenance", {}),
            wall_power=wall_power,
            shape_order=shape_order,
            shape_coef=shape_coef,
        )


def _json_clean(obj):
    """Metadata for JSON: numpy scalars/arrays to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _json_clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _get(d: dict, key: str, where: str):
    if not isinstance(d, dict) or key not in d:
        raise KeyError(f"{where}: missing key {key!r}")
    return d[key]


def _num(d: dict, key: str, where: str) -> float:
    v = _get(d, key, where)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{where}: key {key!r} must be a number, got {v!r}")
    return float(v)


def _vec(d: dict, key: str, n: int, where: str) -> list[float]:
    v = _get(d, key, where)
    if not isinstance(v, list) or len(v) != n or not all(
        isinstance(x, (int, float)) and not isinstance(x, bool) for x in v
    ):
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers")
    return [float(x) for x in v]


def save_surrogate(surrogate: Surrogate, path: str | Path) -> Path:
    """Write the surrogate JSON file (creating its directory)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = surrogate.to_dict()
    path.write_text(json.dumps(data, indent=1, allow_nan=False) + "\n")
    return path


def check_params(surrogate: Surrogate, params: BearingParams, where: str = "surrogate", rtol: float = 1e-9) -> None:
    """Refuse a surrogate fitted for a different bearing, naming the field and both values."""
    for name in ("D", "L", "CR", "mu"):
        a, b = getattr(surrogate.params, name), getattr(params, name)
        if abs(a - b) > rtol * max(abs(a), abs(b)):
            raise ValueError(
                f"{where}: fitted for bearing {name} = {a!r}, but used with {name} = {b!r} "
                "(a surrogate is only valid for the bearing it was fitted to)"
            )


def load_surrogate(path: str | Path, params: BearingParams | None = None) -> Surrogate:
    """Read a surrogate file; with ``params`` also check it belongs to that bearing."""
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise FileNotFoundError(f"surrogate file {str(path)!r} not found") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"surrogate file {str(path)!r} is not valid JSON: {exc}") from None
    where = f"surrogate file {str(path)!r}"
    sur = Surrogate.from_dict(data, where)
    if params is not None:
        check_params(sur, params, where)
    return sur


# ----------------------------------------------------------------------------- the internal

_VAR_OF_CODE = {_BAD_Y: "y", _BAD_Z: "z", _BAD_VY: "vy", _BAD_VZ: "vz", _BAD_OMEGA: "omega"}


class Taylor:
    """The Taylor-surrogate internal: ``force`` and ``force_and_jacobian`` from a Surrogate.

    Evaluates everywhere (also outside the fitted domain, returning the polynomial value);
    ``in_domain`` / ``domain_distance`` tell the caller where the fit holds. Inputs must be
    finite and ``omega`` must equal the fitted speed (relative tolerance 1e-9).
    """

    def __init__(self, surrogate: Surrogate, params: BearingParams | None = None):
        if params is not None:
            check_params(surrogate, params)
        self.surrogate = surrogate
        self.params = surrogate.params
        s = surrogate
        self._meta = np.array([s.y0, s.z0, s.omega, s.pos_scale, s.vel_scale, s.force_scale, OMEGA_RTOL,
                               float(max(s.order, 1)), s.wall_power, short_bearing_constant(s.params),
                               float(s.shape_order or 0)])
        # evaluate only the terms kept by either component
        used = s.kept[0] | s.kept[1]
        used[0] = True
        self._exps = np.ascontiguousarray(s.exponents[used])
        self._coef = np.ascontiguousarray(s.coef[:, used])
        if s.shape_order is None:
            self._args = (self._meta, self._exps, self._coef)
            self._kforce, self._kjac = _force_nb, _force_jac_si_nb
        else:
            self._args = (self._meta, self._exps, self._coef, np.ascontiguousarray(s.shape_exponents),
                          np.ascontiguousarray(s.shape_coef))
            self._kforce, self._kjac = _force_shape_nb, _force_jac_shape_si_nb
        self._out = np.empty(10)
        d = s.domain
        self._dom = np.array([s.y0, s.z0, s.pos_scale, s.vel_scale, d.ecc_max, d.pos_center[0], d.pos_center[1],
                              d.pos_radius, d.v_max, *d.box_lo, *d.box_hi], float)

    @classmethod
    def from_file(cls, path: str | Path, params: BearingParams | None = None) -> "Taylor":
        return cls(load_surrogate(path, params))

    @property
    def omega(self) -> float:
        return self.surrogate.omega

    def _raise(self, code, y, z, vy, vz, omega):
        if code == _AT_WALL:
            ecc = math.hypot(y, z) / self.params.CR
            s = self.surrogate
            what = " and ".join(([f"wall factor (1 - eps^2)^-{s.wall_power:g}"] if s.wall_power else [])
                                + (["short-bearing shape columns"] if s.shape_order is not None else []))
            verb = "are" if s.shape_order is not None else "is"
            raise BearingStateError(
                f"eccentricity ratio {ecc:.4g} >= 1: the journal (y = {y:.4g} m, z = {z:.4g} m) is at or beyond "
                f"the bearing wall; the surrogate's {what} {verb} undefined there"
            )
        if code == _WRONG_OMEGA:
            raise BearingStateError(
                f"Taylor surrogate was fitted at omega = {self.surrogate.omega:.6g} rad/s; got omega = {omega:.6g} rad/s"
            )
        name = _VAR_OF_CODE[code]
        value = {"y": y, "z": z, "vy": vy, "vz": vz, "omega": omega}[name]
        raise BearingStateError(f"bearing input {name} = {value!r} is not finite")

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        fy, fz, code = self._kforce(float(y), float(z), float(vy), float(vz), float(omega), *self._args)
        if code:
            self._raise(code, y, z, vy, vz, omega)
        return fy, fz

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        code, F, dF_dq, dF_dv = self._kjac(float(y), float(z), float(vy), float(vz), float(omega), *self._args)
        if code:
            self._raise(code, y, z, vy, vz, omega)
        return F, dF_dq, dF_dv

    # ------------------------------------------------------------------ guard
    def domain_distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """How far the state lies outside the fitted domain: the largest relative excess over
        its bounds (eccentricity / ecc_max - 1, distance to the position-disc centre / radius
        - 1, |v| / v_max - 1, and the bounding-box excess over the box half width). <= 0
        inside; e.g. 0.1 means 10 % beyond the nearest violated bound."""
        return float(_domain_distance_nb(float(y), float(z), float(vy), float(vz), self._dom))

    def in_domain(self, y: float, z: float, vy: float, vz: float) -> bool:
        """True when the state lies inside the fitted domain (see ``domain_distance``)."""
        return self.domain_distance(y, z, vy, vz) <= 1e-12


__all__ = [
    "Domain", "Surrogate", "Taylor", "design_matrix", "exponents", "n_terms", "term_names",
    "natural_force_scale", "save_surrogate", "load_surrogate", "check_params", "short_bearing_at",
    "shape_force",
]
