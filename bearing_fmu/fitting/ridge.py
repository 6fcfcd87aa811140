"""Ridge regression (paper eqs. 9-11) through one SVD, k-fold cross validation, the lambda
line search, bias^2 / variance, pruning, and the error measures of a fit.

Conventions
-----------
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
* CV folds: a seeded random partition for designed data; for a time series, contiguous
  blocks dealt round-robin to the folds (see ``fold_indices``).
"""

from __future__ import annotations

import math

import numpy as np

RCOND = 1e-13
LOG10_LAM_BOUNDS = (-14.0, 1.0)


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


__all__ = ["RidgeSVD", "CrossValidation", "select_lambda", "prune_terms", "fold_indices", "nrmse", "rel_rms",
           "ridge_normal_equations"]
