"""Fitting the Taylor surrogate: ridge regression (paper eqs. 9-11), the lambda line search,
bias^2 / variance, pruning, training data (designed or from a co-simulation), reports, plots.

Conventions
-----------
* Regression in scaled units (see :mod:`bearing_fmu.basis`): the design matrix X (M x N)
  holds the monomials of u = ((y-y0)/CR, (z-z0)/CR, vy/(omega CR), vz/(omega CR)), the
  targets are F / force_scale.
* The ridge objective is written per sample, (1/M) ||f - X k||^2 + lambda ||k||^2, so one
  lambda means the same for any number of samples; the paper's eq. 9-10 lambda (a plain sum)
  is M * lambda. Solution (eq. 11) through the SVD X = U diag(d) V^T:
  k(lambda) = V diag(d / (d^2 + M lambda)) U^T f -- one SVD serves every lambda, no inverse.
  lambda = 0 is ordinary least squares (singular values below 1e-13 d_max dropped).
* lambda is chosen per force component by k-fold cross validation (the held-out objective):
  a coarse log grid to bracket, then ``scipy.optimize.minimize_scalar`` (bounded) on
  log10 lambda; lambda = 0 is compared too and wins when its CV error is not larger.
* Bias^2 and variance vs lambda (Fig. 10 of the paper), from the SVD of the full training
  design, averaged over the training points (units of the objective):
      sigma^2   = RSS_LS / (M - rank)          (LS residual variance: the truncation error
                                                treated as noise; the truth itself is noise-free)
      variance  = sigma^2 / M * sum_i d_i^4 / (d_i^2 + M lambda)^2
      bias^2    = 1 / M * sum_i (M lambda / (d_i^2 + M lambda))^2 (u_i^T f)^2
  bias^2 is the plug-in estimate taking the LS fit as the unbiased mean response; both are
  0 / sigma^2 rank / M at lambda = 0. The coefficient variance sigma^2 sum d_i^2/(d_i^2+M lambda)^2
  is reported too.
* NRMSE of a force component = RMS(prediction - truth) / standard deviation of the truth
  over the same samples (= sqrt(1 - R^2)), so a fit of the mean alone scores 1.
* Pruning: terms ranked by their contribution |k_j| * RMS(X[:, j]); the largest number of
  the smallest ones is dropped (bisection, repeated after re-ranking) while the CV RMS error
  stays within (1 + prune_tol) of the unpruned CV RMS error; the kept terms are refitted.
  The constant and the shape columns are always kept. On more than 6000 samples the pruning
  decisions use every stride-th sample (the final refit of the kept terms uses all).
* Shape columns (``shape_order`` r, optional): the columns g S_y m_j(u) / F_ref and
  g S_z m_j(u) / F_ref beside the monomials, S the closed-form short-bearing force at the
  sample, m_j the monomials of order <= r, g the wall factor's (1 - eps^2)^p: the surrogate is
  F = F_ref P(u) / g + sum_j (a_j^y S_y + a_j^z S_z) m_j(u) (docs/taylor.md). Anchored, each
  shape column's own degree <= 1 part at the expansion point (exact, from the closed form's
  analytic Jacobian) is taken out of the column and put back into the polynomial's constant
  and order-1 coefficients afterwards, so the anchor still fixes the force and Jacobian there.
* CV folds: a seeded random partition for designed data; for a time series, contiguous
  blocks dealt round-robin to the folds (see ``fold_indices``).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import math
import time
from numbers import Integral
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .params import PAPER_BEARING, BearingParams
from ._taylor_kernels import short_bearing_at
from .basis import design_matrix, exponents, natural_force_scale, shape_force, term_names
from .surrogate import Domain, Surrogate, save_surrogate

COMPONENTS = ("Fy", "Fz")
RCOND = 1e-13
LOG10_LAM_BOUNDS = (-14.0, 1.0)
PRUNE_MAX_ROWS = 6000  # pruning decides on at most this many (strided) samples; the refit uses all


# ----------------------------------------------------------------------------- errors

def nrmse(pred, truth) -> np.ndarray:
    """Per-column RMS error over the standard deviation of the truth (see module doc)."""
    pred = np.asarray(pred, float).reshape(len(pred), -1)
    truth = np.asarray(truth, float).reshape(len(truth), -1)
    rms = np.sqrt(np.mean((pred - truth) ** 2, axis=0))
    sd = np.std(truth, axis=0)
    return rms / np.where(sd > 0, sd, np.nan)


def rel_rms(pred, truth) -> np.ndarray:
    """Per-column RMS error over the RMS force magnitude |F| (a gentler, load-level measure)."""
    pred = np.asarray(pred, float).reshape(len(pred), -1)
    truth = np.asarray(truth, float).reshape(len(truth), -1)
    rms = np.sqrt(np.mean((pred - truth) ** 2, axis=0))
    return rms / np.sqrt(np.mean(np.sum(truth**2, axis=1)))


# ----------------------------------------------------------------------------- ridge via SVD

class RidgeSVD:
    """Ridge solutions of (1/M)||Y - X K||^2 + lambda ||K||^2 for every lambda from one SVD.

    Y may have several columns (the force components share X)."""

    def __init__(self, X: np.ndarray, Y: np.ndarray):
        X = np.asarray(X, float)
        Y = np.asarray(Y, float)
        self.M = X.shape[0]
        self.Y = Y.reshape(self.M, -1)
        U, d, Vt = np.linalg.svd(X, full_matrices=False)
        self.U, self.d, self.Vt = U, d, Vt
        self.rank_mask = d > RCOND * (d[0] if d.size else 0.0)
        self.rank = int(self.rank_mask.sum())
        self.UtY = U.T @ self.Y  # (r, ncol)

    def filt(self, lam: float) -> np.ndarray:
        d = self.d
        if lam == 0.0:
            f = np.zeros_like(d)
            f[self.rank_mask] = 1.0 / d[self.rank_mask]
            return f
        return d / (d * d + self.M * lam)

    def coef(self, lam) -> np.ndarray:
        """Coefficients (N, ncol); ``lam`` a scalar or one value per column."""
        lams = np.broadcast_to(np.asarray(lam, float), (self.Y.shape[1],))
        out = np.empty((self.Vt.shape[1], self.Y.shape[1]))
        for j, lj in enumerate(lams):
            out[:, j] = self.Vt.T @ (self.filt(float(lj)) * self.UtY[:, j])
        return out

    def bias_variance(self, lams: np.ndarray) -> dict:
        """bias^2, variance (of the fitted values, mean over the training points) and the
        coefficient variance per lambda and column (see module doc)."""
        M, d = self.M, self.d[self.rank_mask]
        uty = self.UtY[self.rank_mask]
        rss_ls = np.sum(self.Y**2, axis=0) - np.sum(uty**2, axis=0)
        sigma2 = np.maximum(rss_ls, 0.0) / max(M - self.rank, 1)
        lams = np.asarray(lams, float)
        bias2 = np.empty((lams.size, self.Y.shape[1]))
        var = np.empty_like(bias2)
        cvar = np.empty_like(bias2)
        for i, lam in enumerate(lams):
            s = d * d + M * lam
            bias2[i] = np.sum(((M * lam / s) ** 2)[:, None] * uty**2, axis=0) / M
            var[i] = sigma2 / M * np.sum(d**4 / s**2)
            cvar[i] = sigma2 * np.sum(d**2 / s**2)
        return {"sigma2": sigma2, "bias2": bias2, "variance": var, "coef_variance": cvar}


def ridge_normal_equations(X, y, lam: float) -> np.ndarray:
    """Reference only (tests): solve (X^T X / M + lambda I) k = X^T y / M directly."""
    X = np.asarray(X, float)
    M = X.shape[0]
    A = X.T @ X / M + lam * np.eye(X.shape[1])
    return np.linalg.solve(A, X.T @ np.asarray(y, float) / M)


# ----------------------------------------------------------------------------- cross validation

def fold_indices(M: int, k: int, seed: int = 0, blocked: bool = False, blocks_per_fold: int = 10) -> list[np.ndarray]:
    """k folds of range(M): a seeded random partition, or for time series (``blocked``)
    k * blocks_per_fold contiguous blocks dealt round-robin to the folds, so a held-out block
    is not predicted from its near-identical neighbours, yet every fold spans the whole run
    (plain contiguous folds would turn CV into extrapolation along a transient)."""
    if not blocked:
        idx = np.random.default_rng(seed).permutation(M)
        return [np.sort(a) for a in np.array_split(idx, k)]
    blocks = np.array_split(np.arange(M), min(k * blocks_per_fold, M))
    return [np.concatenate(blocks[f::k]) for f in range(k)]


class CrossValidation:
    """k-fold CV error of the ridge fit as a function of lambda, one SVD per fold."""

    def __init__(self, X, Y, folds: list[np.ndarray]):
        X = np.asarray(X, float)
        Y = np.asarray(Y, float).reshape(X.shape[0], -1)
        self.M = X.shape[0]
        self.ncol = Y.shape[1]
        self._parts = []
        for test in folds:
            train = np.ones(self.M, bool)
            train[test] = False
            r = RidgeSVD(X[train], Y[train])
            A = X[test] @ r.Vt.T  # (m_test, r)
            self._parts.append((r, A, Y[test]))

    def mse(self, lam) -> np.ndarray:
        """CV mean squared error per column at ``lam`` (scalar or per column)."""
        lams = np.broadcast_to(np.asarray(lam, float), (self.ncol,))
        sse = np.zeros(self.ncol)
        for r, A, Yt in self._parts:
            for j in range(self.ncol):
                pred = A @ (r.filt(float(lams[j])) * r.UtY[:, j])
                sse[j] += np.sum((pred - Yt[:, j]) ** 2)
        return sse / self.M


def select_lambda(cv: CrossValidation, bounds=LOG10_LAM_BOUNDS, n_grid: int = 29) -> dict:
    """Per column: bracket the CV minimum on a log grid, refine it with minimize_scalar
    (bounded, on log10 lambda), compare with lambda = 0. Returns the curves and choices."""
    from scipy.optimize import minimize_scalar

    grid = np.linspace(bounds[0], bounds[1], n_grid)
    curve = np.array([cv.mse(10.0**g) for g in grid])  # (n_grid, ncol)
    ls = cv.mse(0.0)
    chosen, best_search, mse_search, zooms = [], [], [], []
    for j in range(cv.ncol):
        i = int(np.argmin(curve[:, j]))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, n_grid - 1)]
        zg = np.linspace(grid[max(i - 2, 0)], grid[min(i + 2, n_grid - 1)], 25)
        zooms.append((zg, np.array([cv.mse(10.0**g)[j] for g in zg])))

        def obj(g, j=j):
            lam = np.zeros(cv.ncol)
            lam[:] = 10.0**g
            return float(cv.mse(lam)[j])

        res = minimize_scalar(obj, bounds=(lo, hi), method="bounded", options={"xatol": 1e-3})
        g_best, f_best = (float(res.x), float(res.fun)) if res.fun <= curve[i, j] else (float(grid[i]), float(curve[i, j]))
        best_search.append(10.0**g_best)
        mse_search.append(f_best)
        chosen.append(0.0 if ls[j] <= f_best else 10.0**g_best)
    return {
        "log10_grid": grid, "cv_curve": curve, "cv_ls": ls,
        "lam_search": np.array(best_search), "cv_search": np.array(mse_search),
        "lam": np.array(chosen), "zoom": zooms,
    }


# ----------------------------------------------------------------------------- pruning

def _cv_mse_cols(X, y, cols, lam, folds) -> float:
    return float(CrossValidation(X[:, cols], y, folds).mse(lam)[0])


def prune_terms(X, y, lam: float, folds, tol: float = 0.10, rounds: int = 3,
                protect_first: bool = True, protect_last: int = 0) -> tuple[np.ndarray, dict]:
    """Boolean mask of the kept columns of X for target y (see module doc); with
    ``protect_first`` column 0 (the constant) is never dropped, nor are the last
    ``protect_last`` columns (the shape columns)."""
    N = X.shape[1]
    protected = np.zeros(N, bool)
    protected[0] = protect_first
    if protect_last:
        protected[N - protect_last:] = True
    keep = np.ones(N, bool)
    base = _cv_mse_cols(X, y, keep, lam, folds)
    limit = (1.0 + tol) ** 2 * base  # on the mean squared error, i.e. (1 + tol) on the RMS error
    rms_col = np.sqrt(np.mean(X**2, axis=0))
    final = base
    for _ in range(rounds):
        idx = np.flatnonzero(keep)
        k = RidgeSVD(X[:, idx], y).coef(lam)[:, 0]
        contrib = np.abs(k) * rms_col[idx]
        order = [i for i in np.argsort(contrib) if not protected[idx[i]]]
        ranked = idx[order]

        def ok(n):
            m = keep.copy()
            m[ranked[:n]] = False
            e = _cv_mse_cols(X, y, m, lam, folds)
            return e <= limit, e

        lo, hi = 0, len(ranked)  # ok(lo) holds; find the largest n with ok(n)
        best_e = None
        while lo < hi:
            mid = (lo + hi + 1) // 2
            good, e = ok(mid)
            if good:
                lo, best_e = mid, e
            else:
                hi = mid - 1
        if lo == 0:
            break
        keep[ranked[:lo]] = False
        final = best_e
    info = {"cv_rmse_unpruned": math.sqrt(base), "cv_rmse_pruned": math.sqrt(final), "tol": tol,
            "kept": int(keep.sum() - protect_last), "of": int(N - protect_last)}
    return keep, info


# ----------------------------------------------------------------------------- training data

def designed_samples(internal, y0: float, z0: float, omega: float, ecc_max: float, v_max: float, n: int,
                     seed: int = 0, *, radius: float | None = None):
    """n states over a declared domain and their forces from ``internal`` (no rotor run).

    Positions: uniform over a disc -- of radius ``ecc_max`` (in CR) about the bearing centre
    when ``radius`` is None, else of ``radius`` (in CR) about (y0, z0) intersected with the
    eccentricity bound |(y, z)| <= ecc_max CR. Velocities: uniform over the disc
    |(vy, vz)| <= v_max * omega * CR. Drawn as a Latin hypercube (scipy.stats.qmc) in
    (r^2, angle) of each disc; states beyond the eccentricity bound are discarded.
    Returns (states (n, 4) [m, m/s], forces (n, 2) [N], domain: Domain).
    """
    from scipy.stats import qmc

    p = internal.params
    cr, vs = p.CR, abs(omega) * p.CR
    if not 0 < ecc_max < 1:
        raise ValueError(f"designed_samples: ecc_max = {ecc_max!r} must lie in (0, 1)")
    if v_max < 0:
        raise ValueError(f"designed_samples: v_max = {v_max!r} must be >= 0")
    if radius is None:
        cy, cz, rad = 0.0, 0.0, ecc_max
    else:
        cy, cz, rad = y0 / cr, z0 / cr, float(radius)
        if math.hypot(cy, cz) > ecc_max:
            raise ValueError(f"designed_samples: the expansion point (eccentricity {math.hypot(cy, cz):.3f}) "
                             f"lies beyond ecc_max = {ecc_max}")
    sampler = qmc.LatinHypercube(d=4, seed=seed)
    pts = []
    have = 0
    m = n
    while have < n:
        s = sampler.random(max(m, 16))
        r = rad * np.sqrt(s[:, 0])
        a = 2 * np.pi * s[:, 1]
        qy, qz = cy + r * np.cos(a), cz + r * np.sin(a)
        ok = np.hypot(qy, qz) <= ecc_max
        rv = v_max * np.sqrt(s[:, 2])
        b = 2 * np.pi * s[:, 3]
        blk = np.column_stack([qy * cr, qz * cr, rv * np.cos(b) * vs, rv * np.sin(b) * vs])[ok]
        pts.append(blk)
        have += len(blk)
        m = int(1.3 * (n - have) * len(s) / max(len(blk), 1)) + 16
    states = np.concatenate(pts)[:n]
    forces = sample_forces(internal, states, omega)
    u = np.column_stack([(states[:, 0] - y0) / cr, (states[:, 1] - z0) / cr, states[:, 2] / vs, states[:, 3] / vs])
    domain = Domain(
        ecc_max=float(ecc_max),
        pos_center=(cy - y0 / cr, cz - z0 / cr),
        pos_radius=float(rad),
        v_max=float(v_max),
        box_lo=tuple(float(v) for v in u.min(axis=0)),
        box_hi=tuple(float(v) for v in u.max(axis=0)),
    )
    return states, forces, domain


def tube_samples(internal, orbit_states, y0: float, z0: float, omega: float, radius: float, n: int,
                 seed: int = 0, *, ecc_max: float | None = None):
    """n states in a tube about recorded orbit states and their forces from ``internal``.

    Each sample is a randomly chosen orbit state plus a displacement uniform in the 4-D ball
    of ``radius`` in scaled units (positions in CR, velocities in omega CR: the units of the
    surrogate's u); samples beyond eccentricity ``ecc_max`` (default: the orbit's largest) are
    drawn again. Returns (states (n, 4) [m, m/s], forces (n, 2) [N])."""
    p = internal.params
    cr, vs = p.CR, abs(omega) * p.CR
    orbit = np.asarray(orbit_states, float).reshape(-1, 4)
    if radius <= 0 or not len(orbit):
        raise ValueError(f"tube_samples: radius = {radius!r} must be > 0 and the orbit non-empty")
    ecc_orbit = float(np.max(np.hypot(orbit[:, 0], orbit[:, 1])) / cr)
    ecc_max = min(ecc_orbit if ecc_max is None else float(ecc_max), 0.999)
    rng = np.random.default_rng(seed)
    scale = np.array([cr, cr, vs, vs])
    out = []
    have = 0
    while have < n:
        m = 2 * (n - have) + 16
        base = orbit[rng.integers(0, len(orbit), m)]
        d = rng.normal(size=(m, 4))
        d *= (radius * rng.uniform(size=m) ** 0.25 / np.linalg.norm(d, axis=1))[:, None]
        st = base + d * scale
        st = st[np.hypot(st[:, 0], st[:, 1]) <= ecc_max * cr]
        out.append(st)
        have += len(st)
    states = np.concatenate(out)[:n]
    return states, sample_forces(internal, states, omega)


def sample_forces(internal, states, omega: float) -> np.ndarray:
    states = np.asarray(states, float)
    out = np.empty((len(states), 2))
    for i, (y, z, vy, vz) in enumerate(states):
        out[i] = internal.force(y, z, vy, vz, omega)
    if not np.all(np.isfinite(out)):
        raise ValueError("training forces contain non-finite values")
    return out


def load_npz(path: str | Path):
    """Training time series from a co-simulation: an .npz with arrays y, z, vy, vz, Fy, Fz
    (one bearing, equal lengths). Returns (states (M, 4), forces (M, 2))."""
    path = Path(path)
    try:
        data = np.load(path)
    except FileNotFoundError:
        raise FileNotFoundError(f"training file {str(path)!r} not found") from None
    keys = ("y", "z", "vy", "vz", "Fy", "Fz")
    missing = [k for k in keys if k not in data.files]
    if missing:
        raise KeyError(f"training file {str(path)!r}: missing array(s) {', '.join(missing)}; "
                       f"expected {', '.join(keys)}, found {', '.join(data.files) or 'none'}")
    arrs = [np.asarray(data[k], float).ravel() for k in keys]
    n = {len(a) for a in arrs}
    if len(n) != 1:
        raise ValueError(f"training file {str(path)!r}: arrays have different lengths "
                         + ", ".join(f"{k}={len(a)}" for k, a in zip(keys, arrs)))
    for k, a in zip(keys, arrs):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"training file {str(path)!r}: array {k} has non-finite values")
    return np.column_stack(arrs[:4]), np.column_stack(arrs[4:])


def domain_from_data(states, y0, z0, params: BearingParams, omega: float, margin: float = 0.0) -> Domain:
    """Domain covering time-series states: discs about the expansion point and the box."""
    cr, vs = params.CR, abs(omega) * params.CR
    s = np.asarray(states, float)
    u = np.column_stack([(s[:, 0] - y0) / cr, (s[:, 1] - z0) / cr, s[:, 2] / vs, s[:, 3] / vs])
    f = 1.0 + margin
    return Domain(
        ecc_max=float(min(np.max(np.hypot(s[:, 0], s[:, 1])) / cr * f, 0.9999)),
        pos_center=(0.0, 0.0),
        pos_radius=float(np.max(np.hypot(u[:, 0], u[:, 1])) * f),
        v_max=float(np.max(np.hypot(u[:, 2], u[:, 3])) * f),
        box_lo=tuple(float(v) for v in u.min(axis=0)),
        box_hi=tuple(float(v) for v in u.max(axis=0)),
    )


# ----------------------------------------------------------------------------- the fit

@dataclass
class FitResult:
    surrogate: Surrogate
    report: dict
    curves: dict = field(default_factory=dict)


def fit_surrogate(
    states, forces, params: BearingParams, omega: float, y0: float, z0: float, order: int = 5, *,
    domain: Domain, lam="cv", k_folds: int = 5, blocked: bool = False, prune: bool = True,
    prune_tol: float = 0.05, force_scale: float | None = None, load=None, seed: int = 0,
    test: tuple[np.ndarray, np.ndarray] | None = None, provenance: dict | None = None,
    bias_variance: bool = True, anchor=None, weights=None, wall_power: float = 0.0,
    shape_order: int | None = None,
) -> FitResult:
    """Fit both force components; ``lam`` = "cv" (line search), or a number (the same for
    both). ``test`` = (states, forces) held out for the reported errors.

    ``anchor`` = (F0 (2,), dF_dq (2, 2), dF_dv (2, 2)) at the expansion point (a truth's
    ``force_and_jacobian``) fixes the constant and the order-1 coefficients to them -- the
    Taylor series proper (eq. 6): the surrogate then has the truth's static force and Lund
    coefficients at the expansion point, and only the terms of degree >= 2 are regressed (on
    the residual). Without it all terms are regressed (a global least-squares polynomial).

    ``weights`` (M,), >= 0: a weight per training row in the least-squares term,
    sum_k w_k (f_k - X_k k)^2 (rows of X and f scaled by sqrt(w)); the CV error, lambda choice
    and pruning then use the same weighted objective. None = all 1.

    ``wall_power`` = p > 0 fits the polynomial to G = F (1 - eps^2)^p (eps: the absolute
    eccentricity ratio of each row) instead of F, so the surrogate is F = P(u) / (1 - eps^2)^p
    (see :mod:`bearing_fmu.basis`); the anchor is transformed consistently,
    G0 = F0 g0 and dG/dq = g0 dF/dq + F0 dg/dq (g = (1 - eps^2)^p), dG/dv = g0 dF/dv. The CV
    errors are then of G; train and held-out errors are of F.

    ``shape_order`` = r adds the short-bearing shape columns S_y m_j, S_z m_j (m_j: monomials
    of order <= r) to the regression (module doc); None = the polynomial alone."""
    t0 = time.perf_counter()
    wall_power = float(wall_power)
    if not (math.isfinite(wall_power) and wall_power >= 0.0):
        raise ValueError(f"fit: wall_power = {wall_power!r} must be finite and >= 0")
    if shape_order is not None and (isinstance(shape_order, bool) or not isinstance(shape_order, Integral)
                                    or shape_order < 0):
        raise ValueError(f"fit: shape_order = {shape_order!r} must be an integer >= 0 (or None: no shape columns)")
    exps = exponents(order)
    sexps = exponents(shape_order) if shape_order is not None else np.zeros((0, 4), np.int64)
    Nr = len(sexps)
    fs = float(force_scale) if force_scale else natural_force_scale(params, omega)
    cr, vs = params.CR, abs(omega) * params.CR
    states = np.asarray(states, float)
    forces = np.asarray(forces, float)

    def scaled(s):
        return np.column_stack([(s[:, 0] - y0) / cr, (s[:, 1] - z0) / cr, s[:, 2] / vs, s[:, 3] / vs])

    def wall_g(s):  # (1 - eps^2)^p, the factor that turns F into the regression target G
        if wall_power == 0.0:
            return np.ones(len(s))
        q = 1.0 - (s[:, 0] ** 2 + s[:, 1] ** 2) / cr**2
        if np.any(q <= 0.0):
            raise ValueError(f"fit: {int(np.sum(q <= 0))} state(s) at or beyond the wall (eccentricity >= 1); "
                             "the wall factor is undefined there")
        return q**wall_power

    def shape_cols(s, S, g):  # (M, 2 Nr): g S_y m_j / fs, then g S_z m_j / fs (the regression's units)
        mj = design_matrix(scaled(s), sexps)
        gS = S[:, :2] * (g / fs)[:, None]
        return np.hstack([gS[:, :1] * mj, gS[:, 1:2] * mj])

    def predict(s, S, cp, ca):  # F [N] at raw states s with polynomial coefs cp and shape coefs ca
        F = (design_matrix(scaled(s), exps) @ cp.T) * fs / wall_g(s)[:, None]
        if Nr:
            F += shape_force(scaled(s), S, sexps, ca.reshape(4, Nr))  # ca rows: Fy (S_y | S_z), Fz (S_y | S_z)
        return F

    X = design_matrix(scaled(states), exps)
    g_train = wall_g(states)
    Y = forces / fs * g_train[:, None]
    M, N = X.shape
    S_train = short_bearing_at(params, states, omega)[:, :2] if Nr else None
    XA = shape_cols(states, S_train, g_train) if Nr else np.zeros((M, 0))
    lin = np.zeros((2 * Nr, 5))  # each shape column's value and u-gradient at the expansion point
    if anchor is not None:
        if order < 1:
            raise ValueError("fit: an anchored fit needs order >= 1")
        F0, dq, dv = (np.asarray(a, float) for a in anchor)
        F0, dq, dv = F0.reshape(2), dq.reshape(2, 2), dv.reshape(2, 2)
        if wall_power != 0.0:
            # G = F g, g = (1 - eps^2)^p: G0 = F0 g0, dG/dq = g0 dF/dq + F0 (dg/dq)^T, dG/dv = g0 dF/dv,
            # dg/dq = -2 p q / CR^2 (1 - eps^2)^(p - 1)
            q0 = 1.0 - (y0 * y0 + z0 * z0) / cr**2
            g0 = q0**wall_power
            dg = -2.0 * wall_power * np.array([y0, z0]) / cr**2 * q0 ** (wall_power - 1.0)
            F0, dq, dv = F0 * g0, dq * g0 + np.outer(F0, dg), dv * g0
        else:
            g0, dg = 1.0, np.zeros(2)
        if Nr:
            # column (S_i, m_j) = g S_i m_j / fs: at u = 0 only m_0 = 1 has a value and the degree-1
            # m_j = u_v a gradient, so its degree <= 1 part is [g0 S_i0, grad_u(g S_i)] / fs for j = 0
            # and g0 S_i0 / fs along u_v for j = 1 + v (exponents list dy, dz, dvy, dvz first)
            r0 = short_bearing_at(params, [[y0, z0, 0.0, 0.0]], omega, jac=True)[0]
            du = np.array([cr, cr, vs, vs])
            dg_u = np.array([dg[0] * cr, dg[1] * cr, 0.0, 0.0])
            for i in range(2):
                S0, dS_u = r0[i], r0[2 + 4 * i:6 + 4 * i] * du
                lin[i * Nr, 0] = g0 * S0 / fs
                lin[i * Nr, 1:] = (g0 * dS_u + S0 * dg_u) / fs
                if shape_order >= 1:
                    for v in range(4):
                        lin[i * Nr + 1 + v, 1 + v] = g0 * S0 / fs
            XA = XA - (lin[:, 0] + scaled(states) @ lin[:, 1:].T)
        # exponents(order) starts with 1, dy, dz, dvy, dvz
        c_fix = np.column_stack([F0 / fs, dq[:, 0] * cr / fs, dq[:, 1] * cr / fs,
                                 dv[:, 0] * vs / fs, dv[:, 1] * vs / fs])
    else:
        c_fix = np.zeros((2, 0))
    n_fix = c_fix.shape[1]
    Xf = np.hstack([X[:, n_fix:], XA])
    Yr = Y - X[:, :n_fix] @ c_fix.T
    Np = N - n_fix  # free polynomial terms; the 2 Nr shape columns follow them in Xf
    Nf = Np + 2 * Nr
    if M < Nf:
        raise ValueError(f"fit: {M} samples for {Nf} free terms of order {order}"
                         + (f" with shape order {shape_order}" if Nr else "") + "; need at least as many samples")
    if weights is not None:
        w = np.asarray(weights, float).reshape(-1)
        if w.shape != (M,) or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError(f"fit: weights must be {M} finite values >= 0, got shape {w.shape}")
        sw = np.sqrt(w)[:, None]
        Xf, Yr = Xf * sw, Yr * sw  # the regression sees weighted rows; reported errors stay unweighted
    folds = fold_indices(M, k_folds, seed, blocked)
    curves: dict = {}
    sel = None
    cond = 1.0
    if Nf == 0:  # anchored order 1: nothing left to fit
        lams = np.zeros(2)
        coef_f = np.zeros((2, 0))
        coef_ls_f = coef_f
        cv_ls = cv_ch = np.mean(Yr**2, axis=0)
    else:
        cv = CrossValidation(Xf, Yr, folds)
        full = RidgeSVD(Xf, Yr)
        cond = float(full.d[0] / full.d[-1]) if full.d[-1] > 0 else math.inf
        if lam == "cv":
            sel = select_lambda(cv)
            lams = sel["lam"]
            curves.update(sel)
        else:
            lams = np.full(2, float(lam))
        cv_ls = cv.mse(0.0)
        cv_ch = cv.mse(lams)
        if bias_variance and sel is not None:
            g = 10.0 ** sel["log10_grid"]
            curves.update(full.bias_variance(g))
            curves["lam_grid"] = g
        coef_f = full.coef(lams).T  # (2, Nf)
        coef_ls_f = full.coef(0.0).T
    coef = np.hstack([c_fix, coef_f])  # (2, N + 2 Nr) until the shape part is split off below
    coef_unpruned = coef.copy()
    coef_ls = np.hstack([c_fix, coef_ls_f])
    kept = np.ones((2, N + 2 * Nr), bool)
    prune_info = {}
    if prune and Nf > 0:
        # the pruning decisions need many CV refits: on long series use every stride-th sample
        stride = max(1, -(-M // PRUNE_MAX_ROWS))
        Xp, Yp = Xf[::stride], Yr[::stride]
        folds_p = folds if stride == 1 else fold_indices(len(Xp), k_folds, seed, blocked)
        for j in range(2):
            keep, info = prune_terms(Xp, Yp[:, j:j + 1], float(lams[j]), folds_p, prune_tol,
                                     protect_first=n_fix == 0, protect_last=2 * Nr)
            info["rows_used"] = int(len(Xp))
            kept[j, n_fix:] = keep
            cj = np.zeros(Nf)
            cj[keep] = RidgeSVD(Xf[:, keep], Yr[:, j]).coef(float(lams[j]))[:, 0]
            coef[j, n_fix:] = cj
            prune_info[COMPONENTS[j]] = info
    def split(c):  # (2, N + 2 Nr) -> polynomial (2, N), shape (2, 2 Nr); the anchor's shift put back
        cp, ca = c[:, :N].copy(), c[:, N:]
        if Nr and anchor is not None:
            cp[:, :5] -= ca @ lin
        return cp, ca

    (coef, coef_aug), (coef_unpruned, aug_unpruned), (coef_ls, aug_ls) = map(split, (coef, coef_unpruned, coef_ls))
    kept = kept[:, :N]
    train_pred = predict(states, S_train, coef, coef_aug)
    errors = {
        "nrmse_definition": "RMS(prediction - truth) / std(truth), per component",
        "train_nrmse": dict(zip(COMPONENTS, nrmse(train_pred, forces).tolist())),
        "cv_nrmse_ls": dict(zip(COMPONENTS, (np.sqrt(cv_ls) / np.std(Y, axis=0)).tolist())),
        "cv_nrmse_chosen": dict(zip(COMPONENTS, (np.sqrt(cv_ch) / np.std(Y, axis=0)).tolist())),
        "n_train": int(M),
    }
    if weights is not None:
        errors["row_weights"] = {"min": float(np.min(weights)), "max": float(np.max(weights)),
                                 "note": "cv_nrmse_* are of the weighted rows"}
    if test is not None:
        ts, tf = np.asarray(test[0], float), np.asarray(test[1], float)
        St = short_bearing_at(params, ts, omega)[:, :2] if Nr else None
        pred = predict(ts, St, coef, coef_aug)
        pred_ls = predict(ts, St, coef_ls, aug_ls)
        pred_un = predict(ts, St, coef_unpruned, aug_unpruned)
        errors.update({
            "test_nrmse": dict(zip(COMPONENTS, nrmse(pred, tf).tolist())),
            "test_nrmse_unpruned": dict(zip(COMPONENTS, nrmse(pred_un, tf).tolist())),
            "test_nrmse_ls_unpruned": dict(zip(COMPONENTS, nrmse(pred_ls, tf).tolist())),
            "test_rel_rms": dict(zip(COMPONENTS, rel_rms(pred, tf).tolist())),
            "test_max_abs_err_N": dict(zip(COMPONENTS, np.max(np.abs(pred - tf), axis=0).tolist())),
            "n_test": int(len(ts)),
        })
    prov = {"date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")}
    from . import __version__

    prov["package_version"] = __version__
    prov.update(provenance or {})
    prov["anchored"] = anchor is not None
    prov["wall_power"] = wall_power
    prov["shape_order"] = shape_order
    if anchor is not None:
        prov.setdefault("anchor", "constant and order-1 terms fixed to the truth's force and derivatives "
                                  "at the expansion point; degree >= 2 regressed")
    pruning = {"criterion": f"drop smallest |coef| * RMS(column) while CV RMS error <= (1 + {prune_tol}) x unpruned",
               **prune_info} if prune else {"criterion": "none"}
    sur = Surrogate(
        params=params, omega=omega, y0=y0, z0=z0, order=order, exponents=exps, coef=coef,
        force_scale=fs, domain=domain, kept=kept, lam=(float(lams[0]), float(lams[1])),
        load=None if load is None else (float(load[0]), float(load[1])),
        errors=errors, pruning=pruning, provenance=prov, wall_power=wall_power,
        shape_order=shape_order, shape_coef=coef_aug.reshape(4, Nr) if Nr else None,
    )
    report = {
        "order": order, "n_terms": N, "n_train": M, "cond_X": cond, "k_folds": k_folds,
        "anchored": anchor is not None, "n_fixed": n_fix, "shape_order": shape_order, "n_shape_columns": 2 * Nr,
        "lambda": dict(zip(COMPONENTS, [float(v) for v in lams])),
        "lambda_search": None if sel is None else dict(zip(COMPONENTS, sel["lam_search"].tolist())),
        "ls_wins": None if sel is None else dict(zip(COMPONENTS, [bool(v == 0.0) for v in lams])),
        "kept": dict(zip(COMPONENTS, [int(kept[0].sum()), int(kept[1].sum())])),
        "errors": errors, "fit_seconds": time.perf_counter() - t0,
    }
    return FitResult(sur, report, curves)


# ----------------------------------------------------------------------------- conditions

def make_reynolds(params: BearingParams, grid: tuple[int, int] | None = None):
    """The truth (imported lazily: the surrogate never needs it)."""
    from .reynolds import Reynolds

    if grid is None:
        return Reynolds(params)
    return Reynolds(params, n_theta=int(grid[0]), n_x=int(grid[1]))


def truth_jacobian(internal, y: float, z: float, omega: float, rel_step: float = 1e-5):
    """(F, dF/dq, dF/dv) of ``internal`` at (y, z, 0, 0): its own ``force_and_jacobian`` when
    it has one (Reynolds: adjoint, exact for the discrete solution), else central differences
    with steps rel_step * CR and rel_step * omega * CR."""
    fj = getattr(internal, "force_and_jacobian", None)
    if fj is not None:
        f, dq, dv = fj(y, z, 0.0, 0.0, omega)
        return np.asarray(f, float), np.asarray(dq, float), np.asarray(dv, float)
    x0 = np.array([y, z, 0.0, 0.0])
    cr = internal.params.CR
    jac = np.empty((2, 4))
    for j, h in enumerate((rel_step * cr, rel_step * cr, rel_step * cr * abs(omega), rel_step * cr * abs(omega))):
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        jac[:, j] = (np.array(internal.force(*xp, omega)) - np.array(internal.force(*xm, omega))) / (2 * h)
    return np.array(internal.force(y, z, 0.0, 0.0, omega), float), jac[:, :2], jac[:, 2:]


def expansion_point(internal, load, omega: float) -> tuple[float, float]:
    """The static equilibrium of ``internal`` under ``load`` (Wy, Wz) [N] at omega [rad/s]."""
    from .statics import equilibrium

    return equilibrium(internal, load, omega)


def fit_condition(
    load, speed_hz: float, order: int = 5, *, ecc_max: float, v_max: float, radius: float | None = None,
    n_train: int = 3000, n_test: int = 2000, seed: int = 1, internal=None, params: BearingParams = PAPER_BEARING,
    grid=None, npz: str | Path | None = None, anchor: bool = True, **fit_kw,
) -> FitResult:
    """Equilibrium, training data (designed or from ``npz``), fit, held-out check.

    With ``anchor`` (default) the constant and order-1 terms are the truth's force and
    derivatives at the equilibrium (``force_and_jacobian``, else central differences).
    Designed: train on a Latin hypercube with ``seed``, report errors on another with seed + 1000.
    npz: the first 80 % of the time series trains (blocked CV), the last 20 % is held out."""
    omega = 2 * math.pi * float(speed_hz)
    if internal is None:
        internal = make_reynolds(params, grid)
    params = internal.params
    y0, z0 = expansion_point(internal, load, omega)
    prov = {"truth": type(internal).__name__,
            "fit_call": {"load": [float(v) for v in load], "speed_hz": float(speed_hz), "ecc_max": ecc_max,
                         "v_max": v_max, "radius": radius, "n_train": n_train, "n_test": n_test, "seed": seed,
                         "grid": list(grid) if grid else None, "npz": str(Path(npz).resolve()) if npz else None,
                         "anchor": anchor, **{k: v for k, v in fit_kw.items() if k in _REFIT_KW}}}
    for attr in ("n_theta", "n_x", "cavitation"):
        if hasattr(internal, attr):
            prov[f"truth_{attr}"] = getattr(internal, attr)
    if npz is None:
        states, forces, domain = designed_samples(internal, y0, z0, omega, ecc_max, v_max, n_train, seed, radius=radius)
        ts, tf, _ = designed_samples(internal, y0, z0, omega, ecc_max, v_max, n_test, seed + 1000, radius=radius)
        prov.update({"training_source": "designed", "design": "Latin hypercube over position and velocity discs",
                     "seed_train": seed, "seed_test": seed + 1000, "ecc_max": ecc_max, "v_max": v_max,
                     "radius": radius})
        blocked = False
    else:
        s_all, f_all = load_npz(npz)
        cut = int(0.8 * len(s_all))
        states, forces, ts, tf = s_all[:cut], f_all[:cut], s_all[cut:], f_all[cut:]
        domain = domain_from_data(states, y0, z0, params, omega)
        prov.update({"training_source": f"time series {Path(npz).name}", "held_out": "last 20 % of the series"})
        blocked = True
    fit_kw.setdefault("blocked", blocked)
    anc = None
    if anchor:
        anc = truth_jacobian(internal, y0, z0, omega)
    res = fit_surrogate(states, forces, params, omega, y0, z0, order, domain=domain, load=load, seed=seed,
                        test=(ts, tf), provenance=prov, anchor=anc, **fit_kw)
    eq = math.hypot(y0, z0) / params.CR
    res.report.update({"speed_hz": speed_hz, "load": list(load), "equilibrium": [y0, z0], "eps0": eq,
                       "domain": domain.to_dict()})
    return res


_REFIT_KW = ("lam", "k_folds", "prune", "prune_tol", "wall_power", "shape_order")


def refit_order(surrogate_path, order: int, out_path) -> Path:
    """Refit the surrogate of ``surrogate_path`` at another ``order`` from the same designed
    domain or time series (the call stored in its provenance); write ``out_path``."""
    from .surrogate import load_surrogate

    base = load_surrogate(surrogate_path)
    call = dict(base.provenance.get("fit_call") or {})
    if not call or "speed_hz" not in call:
        raise ValueError(f"{surrogate_path}: its provenance has no 'fit_call' to refit from "
                         "(fitted by an older version); fit it again with `bearing-fmu fit`")
    grid = tuple(call.pop("grid")) if call.get("grid") else None
    load, speed = call.pop("load"), call.pop("speed_hz")
    res = fit_condition(tuple(load), speed, order, params=base.params, grid=grid, **call)
    return save_surrogate(res.surrogate, out_path)


# ----------------------------------------------------------------------------- report, plots

def format_report(res: FitResult) -> str:
    r, e = res.report, res.report["errors"]
    s = res.surrogate
    lines = [
        f"Taylor surrogate, order {r['order']} ({r['n_terms']} terms), speed {s.omega / (2 * math.pi):g} Hz, "
        f"load {list(s.load) if s.load else None} N",
        f"expansion point y0 = {s.y0 * 1e6:.3f} um, z0 = {s.z0 * 1e6:.3f} um "
        f"(eccentricity {math.hypot(s.y0, s.z0) / s.params.CR:.4f}); force scale {s.force_scale:.4g} N",
        f"domain: ecc <= {s.domain.ecc_max:g}, position disc radius {s.domain.pos_radius:g} CR, "
        f"|v| <= {s.domain.v_max:g} omega CR; {r['n_train']} training samples, cond(X) = {r['cond_X']:.3g}",
        f"NRMSE = RMS error / std of the truth; {r['k_folds']}-fold CV chooses lambda (per-sample objective)"
        + (f"; wall factor: the polynomial fits F (1 - eps^2)^{s.wall_power:g} (CV errors of that)"
           if s.wall_power else "")
        + (f"; short-bearing shape columns of order {s.shape_order} ({r['n_shape_columns']} per component, "
           "never pruned)" if s.shape_order is not None else ""),
        "| component | lambda chosen | lambda search | train NRMSE | CV NRMSE (LS) | held-out NRMSE | "
        "held-out unpruned | held-out LS (lambda = 0) | terms kept |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in COMPONENTS:
        ls = r["lambda_search"][c] if r["lambda_search"] else float("nan")
        lines.append(
            f"| {c} | {r['lambda'][c]:.3g} | {ls:.3g} | {e['train_nrmse'][c]:.3e} | {e['cv_nrmse_ls'][c]:.3e} | "
            f"{e.get('test_nrmse', {}).get(c, float('nan')):.3e} | "
            f"{e.get('test_nrmse_unpruned', {}).get(c, float('nan')):.3e} | "
            f"{e.get('test_nrmse_ls_unpruned', {}).get(c, float('nan')):.3e} | {r['kept'][c]} / {r['n_terms']} |"
        )
    for name, o in e.get("other_scenes", {}).items():
        lines.append(f"held out, scene {name}: NRMSE Fy {o['nrmse']['Fy']:.3e}, Fz {o['nrmse']['Fz']:.3e}; "
                     f"{o['out_of_domain_fraction']:.1%} of its states outside the fitted domain")
    lines.append(f"fit time {r['fit_seconds']:.1f} s")
    return "\n".join(lines)


def plot_lambda(res: FitResult, outdir: str | Path, stem: str = "fit") -> list[Path]:
    """Figs. 9-10 in the manner of the paper: CV objective vs lambda (full range and zoom on
    the minimum, LS level dashed) and bias^2 / variance vs lambda, per component."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = res.curves
    if "cv_curve" not in c:
        return []
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    lam = 10.0 ** c["log10_grid"]
    paths = []
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for j, comp in enumerate(COMPONENTS):
        for k, zoom in enumerate((False, True)):
            ax = axes[j, k]
            y = c["cv_curve"][:, j]
            if zoom:
                zg, zy = c["zoom"][j]
                ax.semilogx(10.0**zg, zy, "o-", ms=3, label="k-fold CV objective")
            else:
                ax.loglog(lam, y, "o-", ms=3, label="k-fold CV objective")
            ax.axhline(c["cv_ls"][j], color="k", ls="--", lw=1, label="least squares (lambda = 0)")
            lamc = res.report["lambda_search"][comp]
            ax.axvline(lamc, color="r", lw=1, label=f"line search: {lamc:.2g}")
            if zoom:
                yy = np.concatenate([zy, [c["cv_ls"][j]]])
                pad = 0.05 * (yy.max() - yy.min()) + 1e-300
                ax.set_ylim(yy.min() - pad, yy.max() + pad)
                ax.set_title(f"({'abcd'[2 * j + k]}) zoom, {comp}")
            else:
                ax.set_title(f"({'abcd'[2 * j + k]}) objective, {comp} adjustment")
            ax.set_xlabel("lambda (per-sample ridge penalty)")
            ax.set_ylabel("CV mean squared error (scaled)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    p = outdir / f"{stem}_objective.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)
    if "bias2" in c:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        lg = c["lam_grid"]
        for j, comp in enumerate(COMPONENTS):
            ax = axes[j]
            b, v = c["bias2"][:, j], c["variance"][:, j]
            ax.loglog(lg, np.maximum(b, 1e-300), label="bias^2")
            ax.loglog(lg, v, label="variance")
            ax.loglog(lg, b + v, "k--", label="bias^2 + variance")
            ax.set_title(f"({'ab'[j]}) bias-variance trade-off, {comp}")
            ax.set_xlabel("lambda")
            ax.set_ylabel("mean squared (scaled force)")
            lo = max(min(v.min(), (b + v).min()) * 0.1, 1e-30)
            ax.set_ylim(lo, (b + v).max() * 2)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        p = outdir / f"{stem}_bias_variance.png"
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths


# ----------------------------------------------------------------------------- CLI

def add_fit_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Arguments of ``bearing-fmu fit``."""
    parser.add_argument("--load-y", type=float, default=0.0, help="static load on the journal, y [N] (default 0)")
    parser.add_argument("--load-z", type=float, default=-16.7,
                        help="static load on the journal, z [N] (default -16.7: half the paper rotor's weight)")
    parser.add_argument("--speed-hz", type=float, default=22.0, help="shaft speed [Hz] (default 22)")
    parser.add_argument("--order", type=int, default=5, help="Taylor order (default 5; 1 = linear)")
    parser.add_argument("--ecc-max", type=float, default=0.7, help="eccentricity bound of the design (default 0.7)")
    parser.add_argument("--v-max", type=float, default=0.5, help="velocity bound in units of omega*CR (default 0.5)")
    parser.add_argument("--radius", type=float, default=None,
                        help="position disc radius about the equilibrium in CR (default: the whole disc ecc <= ecc-max)")
    parser.add_argument("--n-train", type=int, default=3000, help="training samples (default 3000)")
    parser.add_argument("--n-test", type=int, default=1500, help="held-out samples (default 1500)")
    parser.add_argument("--seed", type=int, default=1, help="design seed (held-out uses seed + 1000)")
    parser.add_argument("--grid", type=int, nargs=2, metavar=("N_THETA", "N_X"), default=None,
                        help="Reynolds grid (default: the solver's default)")
    parser.add_argument("--lambda", dest="lam", default="cv", help="'cv' (line search, default) or a fixed value")
    parser.add_argument("--k-folds", type=int, default=5, help="cross-validation folds (default 5)")
    parser.add_argument("--no-prune", action="store_true", help="keep all terms")
    parser.add_argument("--no-anchor", action="store_true",
                        help="regress the constant and order-1 terms too (default: fixed to the Reynolds force and "
                             "derivatives at the equilibrium)")
    parser.add_argument("--prune-tol", type=float, default=0.05,
                        help="allowed relative increase of the CV RMS error by pruning (default 0.05)")
    parser.add_argument("--from-npz", default=None, help="train on a co-simulation time series (y, z, vy, vz, Fy, Fz)")
    parser.add_argument("--scene", action="append", default=None, metavar="SCENE",
                        help="train on the Reynolds time series of this scene (models/scenes/*.toml), the paper's "
                             "way; its speed and bearing load replace --speed-hz/--load-*. Repeatable: several "
                             "scenes (other unbalances, same speed and load) are fitted together")
    parser.add_argument("--test-scene", action="append", default=[], metavar="SCENE",
                        help="with --scene: another scene at the same speed whose series is held out (repeatable)")
    parser.add_argument("--bearing", type=int, default=1, help="with --scene: which bearing's series (default 1)")
    parser.add_argument("--stride", type=int, default=2, help="with --scene: use every stride-th step (default 2)")
    parser.add_argument("--designed", type=int, default=2000,
                        help="with --scene: Reynolds samples added over the domain the series spans (default 2000; "
                             "0 = the series only, the paper's way, which holds on the training orbit only)")
    parser.add_argument("--designed-ecc-max", type=float, default=None,
                        help="with --scene: eccentricity bound of the designed samples (default: the series')")
    parser.add_argument("--designed-v-max", type=float, default=None,
                        help="with --scene: velocity bound of the designed samples in omega*CR (default: the series')")
    parser.add_argument("--designed-weight", type=float, default=1.0,
                        help="with --scene: weight of a designed row against a series row in the least-squares "
                             "fit (default 1)")
    parser.add_argument("--designed-tube", type=float, default=None,
                        help="with --scene: draw the designed samples in a tube of this radius (CR and omega*CR "
                             "units) about the training series' states instead of over the discs they span")
    parser.add_argument("--ecc-weight", type=float, default=0.0, metavar="P",
                        help="with --scene: weigh each row by (1 - eccentricity^2)^P, so the rows near the wall "
                             "(forces without bound) do not dominate the fit (default 0: equal weights)")
    parser.add_argument("--wall-power", type=float, default=0.0, metavar="P",
                        help="fit the polynomial to F * (1 - eccentricity^2)^P and evaluate F = polynomial / "
                             "(1 - eccentricity^2)^P, so it can follow the force's growth near the wall "
                             "(default 0: the plain polynomial)")
    parser.add_argument("--shape-order", type=int, default=None, metavar="R",
                        help="add the short-bearing shape columns S_y m_j, S_z m_j (S: the closed-form short-bearing "
                             "force, m_j: monomials of order <= R) to the regression, so the surrogate carries the "
                             "film's growth at the wall and its dependence on the squeeze direction "
                             "(default: none; docs/taylor.md)")
    parser.add_argument("--cache-dir", default=None,
                        help="with --scene: folder caching the Reynolds series (default: beside --output)")
    parser.add_argument("--plots", default=None, help="directory for the lambda plots")
    parser.add_argument("--note", default=None, help="free text stored in the file's provenance")
    parser.add_argument("-o", "--output", required=True, help="surrogate JSON file to write")
    return parser


def run_fit(args: argparse.Namespace) -> int:
    lam = args.lam if args.lam == "cv" else float(args.lam)
    grid = tuple(args.grid) if args.grid else None
    if args.order < 1:
        raise ValueError(f"--order {args.order}: the Taylor order must be >= 1")
    if args.shape_order is not None and args.shape_order < 0:
        raise ValueError(f"--shape-order {args.shape_order}: must be >= 0 (omit it for no shape columns)")
    if getattr(args, "scene", None):
        from rotor_host.training import fit_scene

        cache = Path(args.cache_dir) if args.cache_dir else Path(args.output).resolve().parent / "series"
        scenes = args.scene if len(args.scene) > 1 else args.scene[0]
        res = fit_scene(scenes, args.order, bearing=args.bearing, test_scenes=args.test_scene,
                        stride=args.stride, cache_dir=cache, lam=lam, prune=not args.no_prune,
                        prune_tol=args.prune_tol, anchor=not args.no_anchor, designed=args.designed,
                        designed_ecc_max=args.designed_ecc_max, designed_v_max=args.designed_v_max,
                        designed_weight=args.designed_weight, designed_tube=args.designed_tube,
                        ecc_weight=args.ecc_weight, wall_power=args.wall_power, shape_order=args.shape_order,
                        seed=args.seed)
    else:
        res = _fit_designed(args, lam, grid)
    return _write_fit(res, args)


def _fit_designed(args, lam, grid) -> FitResult:
    return fit_condition(
        (args.load_y, args.load_z), args.speed_hz, args.order, ecc_max=args.ecc_max, v_max=args.v_max,
        radius=args.radius, n_train=args.n_train, n_test=args.n_test, seed=args.seed, grid=grid,
        npz=args.from_npz, lam=lam, k_folds=args.k_folds, prune=not args.no_prune, prune_tol=args.prune_tol,
        anchor=not args.no_anchor, wall_power=args.wall_power, shape_order=args.shape_order,
    )


def _write_fit(res: FitResult, args) -> int:
    if getattr(args, "note", None):
        res.surrogate.provenance["note"] = args.note
    if getattr(args, "scene", None):
        from rotor_host.training import portable_fit_call

        portable_fit_call(res.surrogate, args.output)
    path = save_surrogate(res.surrogate, args.output)
    print(format_report(res))
    print(f"wrote {path}")
    if args.plots:
        for p in plot_lambda(res, args.plots, Path(args.output).stem):
            print(f"wrote {p}")
    return 0


__all__ = [
    "RidgeSVD", "CrossValidation", "select_lambda", "prune_terms", "designed_samples", "tube_samples", "load_npz",
    "domain_from_data", "sample_forces", "truth_jacobian", "fit_surrogate", "fit_condition", "expansion_point", "nrmse", "rel_rms",
    "format_report", "plot_lambda", "add_fit_arguments", "run_fit", "term_names", "refit_order",
]
