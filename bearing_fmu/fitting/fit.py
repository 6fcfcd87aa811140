"""Fitting the Taylor surrogate to the truth's forces: the fit itself (``fit_surrogate``, in
named steps: the design, the anchor, lambda, pruning, the shape part, the errors), the fit
over a designed domain at one load and speed (``fit_condition``), writing and refitting.
Every setting comes from a :class:`~bearing_fmu.fitting.recipe.FitRecipe`.

Conventions
-----------
* Regression in scaled units (see :mod:`bearing_fmu.surrogates.basis`): the design matrix X (M x N)
  holds the monomials of u = ((y-y0)/CR, (z-z0)/CR, vy/(omega CR), vz/(omega CR)), the
  targets are F / force_scale. Ridge, cross validation, pruning: :mod:`.ridge`.
* Pruning keeps the constant and the shape columns always. On more than 6000 samples the
  pruning decisions use every stride-th sample (the final refit of the kept terms uses all).
* Shape columns (``shape_order`` r, optional): the columns g S_y m_j(u) / F_ref and
  g S_z m_j(u) / F_ref beside the monomials, S the closed-form short-bearing force at the
  sample, m_j the monomials of order <= r, g the wall factor's (1 - eps^2)^p: the surrogate is
  F = F_ref P(u) / g + sum_j (a_j^y S_y + a_j^z S_z) m_j(u) (docs/taylor.md). Anchored, each
  shape column's own degree <= 1 part at the expansion point (exact, from the closed form's
  analytic Jacobian) is taken out of the column and put back into the polynomial's constant
  and order-1 coefficients afterwards, so the anchor still fixes the force and Jacobian there.
"""

from __future__ import annotations

import datetime as _dt
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..physics.params import PAPER_BEARING, BearingParams
from ..surrogates.basis import design_matrix, exponents, natural_force_scale, shape_force
from ..surrogates.surrogate import Domain, Surrogate, load_surrogate, save_surrogate
from ..surrogates.taylor_kernels import short_bearing_at
from .flows import attach_film
from .neighbours import neighbours_for_fit
from .recipe import FitRecipe, recipe_of
from .ridge import CrossValidation, RidgeSVD, fold_indices, nrmse, prune_terms, rel_rms, select_lambda
from .sampling import designed_samples, domain_from_data, load_npz
from .truth import fit_truth

COMPONENTS = ("Fy", "Fz")
PRUNE_MAX_ROWS = 6000  # pruning decides on at most this many (strided) samples; the refit uses all


# ----------------------------------------------------------------------------- the fit, step by step

@dataclass
class FitResult:
    """A fitted surrogate, the fit's report (errors, lambda, terms kept, timing), the curves
    of the lambda search (for the plots) and the recipe it was fitted with."""

    surrogate: Surrogate
    report: dict
    curves: dict = field(default_factory=dict)
    recipe: FitRecipe | None = None


class _Units:
    """The regression's units at one expansion point: the scaled states u, the wall factor
    g = (1 - eps^2)^p that turns the force F into the regression target G = F g, the shape
    columns and the prediction of a fitted model in newtons."""

    def __init__(self, params: BearingParams, omega: float, y0: float, z0: float, recipe: FitRecipe, force_scale):
        self.params, self.omega, self.y0, self.z0 = params, omega, y0, z0
        self.wall_power = recipe.wall_power
        self.exps = exponents(recipe.order)
        self.shape_order = recipe.shape_order
        self.sexps = exponents(recipe.shape_order) if recipe.shape_order is not None else np.zeros((0, 4), np.int64)
        self.Nr = len(self.sexps)  # monomials per shape column family (0: no shape columns)
        self.fs = float(force_scale) if force_scale else natural_force_scale(params, omega)
        self.cr, self.vs = params.CR, abs(omega) * params.CR

    def scaled(self, s):
        cr, vs = self.cr, self.vs
        return np.column_stack([(s[:, 0] - self.y0) / cr, (s[:, 1] - self.z0) / cr, s[:, 2] / vs, s[:, 3] / vs])

    def wall_g(self, s):
        """(1 - eps^2)^p at raw states s, the factor that turns F into the regression target G."""
        if self.wall_power == 0.0:
            return np.ones(len(s))
        q = 1.0 - (s[:, 0] ** 2 + s[:, 1] ** 2) / self.cr**2
        if np.any(q <= 0.0):
            raise ValueError(f"fit: {int(np.sum(q <= 0))} state(s) at or beyond the wall (eccentricity >= 1); "
                             "the wall factor is undefined there")
        return q**self.wall_power

    def short_bearing(self, s):
        """The short-bearing force S (M, 2) [N] at raw states s; None without shape columns."""
        return short_bearing_at(self.params, s, self.omega)[:, :2] if self.Nr else None

    def shape_cols(self, s, S, g):
        """(M, 2 Nr): g S_y m_j / fs, then g S_z m_j / fs (the regression's units)."""
        mj = design_matrix(self.scaled(s), self.sexps)
        gS = S[:, :2] * (g / self.fs)[:, None]
        return np.hstack([gS[:, :1] * mj, gS[:, 1:2] * mj])

    def predict(self, s, S, cp, ca):
        """F [N] at raw states s with polynomial coefficients cp (2, N) and shape coefficients ca."""
        F = (design_matrix(self.scaled(s), self.exps) @ cp.T) * self.fs / self.wall_g(s)[:, None]
        if self.Nr:
            F += shape_force(self.scaled(s), S, self.sexps, ca.reshape(4, self.Nr))  # ca rows: Fy (S_y | S_z), Fz (..)
        return F


@dataclass
class _Ridge:
    """Step 3's outcome: lambda per component, the ridge and least-squares coefficients of
    the free columns, CV errors at lambda = 0 and at the chosen lambda, cond(X)."""

    lams: np.ndarray
    coef: np.ndarray
    coef_ls: np.ndarray
    cv_ls: np.ndarray
    cv_chosen: np.ndarray
    cond: float = 1.0
    selection: dict | None = None
    curves: dict = field(default_factory=dict)


def _design(u: _Units, states, forces):
    """Step 1, the design: the monomials X at the training states, the target
    Y = F g / F_ref, the short-bearing force S there and the shape columns XA."""
    X = design_matrix(u.scaled(states), u.exps)
    g = u.wall_g(states)
    Y = forces / u.fs * g[:, None]
    S = u.short_bearing(states)
    XA = u.shape_cols(states, S, g) if u.Nr else np.zeros((X.shape[0], 0))
    return X, Y, S, XA


def _anchor(u: _Units, anchor, states, XA):
    """Step 2, the anchor: the constant and order-1 coefficients c_fix (2, 5) fixed to the
    truth's (F0, dF/dq, dF/dv) at the expansion point, through the wall factor
    (G0 = F0 g0, dG/dq = g0 dF/dq + F0 dg/dq, dG/dv = g0 dF/dv), and the shape columns with
    their own degree <= 1 part there taken out (``lin``: that part, put back by
    ``_split_shape``). Without an anchor nothing is fixed: c_fix (2, 0)."""
    lin = np.zeros((2 * u.Nr, 5))  # each shape column's value and u-gradient at the expansion point
    if anchor is None:
        return np.zeros((2, 0)), lin, XA
    cr, vs, fs, p = u.cr, u.vs, u.fs, u.wall_power
    y0, z0 = u.y0, u.z0
    F0, dq, dv = (np.asarray(a, float) for a in anchor)
    F0, dq, dv = F0.reshape(2), dq.reshape(2, 2), dv.reshape(2, 2)
    if p != 0.0:
        # G = F g, g = (1 - eps^2)^p: G0 = F0 g0, dG/dq = g0 dF/dq + F0 (dg/dq)^T, dG/dv = g0 dF/dv,
        # dg/dq = -2 p q / CR^2 (1 - eps^2)^(p - 1)
        q0 = 1.0 - (y0 * y0 + z0 * z0) / cr**2
        g0 = q0**p
        dg = -2.0 * p * np.array([y0, z0]) / cr**2 * q0 ** (p - 1.0)
        F0, dq, dv = F0 * g0, dq * g0 + np.outer(F0, dg), dv * g0
    else:
        g0, dg = 1.0, np.zeros(2)
    if u.Nr:
        # column (S_i, m_j) = g S_i m_j / fs: at u = 0 only m_0 = 1 has a value and the degree-1
        # m_j = u_v a gradient, so its degree <= 1 part is [g0 S_i0, grad_u(g S_i)] / fs for j = 0
        # and g0 S_i0 / fs along u_v for j = 1 + v (exponents list dy, dz, dvy, dvz first)
        Nr = u.Nr
        r0 = short_bearing_at(u.params, [[y0, z0, 0.0, 0.0]], u.omega, jac=True)[0]
        du = np.array([cr, cr, vs, vs])
        dg_u = np.array([dg[0] * cr, dg[1] * cr, 0.0, 0.0])
        for i in range(2):
            S0, dS_u = r0[i], r0[2 + 4 * i:6 + 4 * i] * du
            lin[i * Nr, 0] = g0 * S0 / fs
            lin[i * Nr, 1:] = (g0 * dS_u + S0 * dg_u) / fs
            if u.shape_order >= 1:
                for v in range(4):
                    lin[i * Nr + 1 + v, 1 + v] = g0 * S0 / fs
        XA = XA - (lin[:, 0] + u.scaled(states) @ lin[:, 1:].T)
    # exponents(order) starts with 1, dy, dz, dvy, dvz
    c_fix = np.column_stack([F0 / fs, dq[:, 0] * cr / fs, dq[:, 1] * cr / fs, dv[:, 0] * vs / fs, dv[:, 1] * vs / fs])
    return c_fix, lin, XA


def _choose_lambda(Xf, Yr, folds, recipe: FitRecipe, bias_variance: bool) -> _Ridge:
    """Step 3, lambda: by k-fold cross validation (``recipe.lam`` 'cv', ridge.select_lambda)
    or as given, the same for both components; then the ridge and LS coefficients."""
    if Xf.shape[1] == 0:  # anchored order 1: nothing left to fit
        cv = np.mean(Yr**2, axis=0)
        return _Ridge(np.zeros(2), np.zeros((2, 0)), np.zeros((2, 0)), cv, cv)
    cv = CrossValidation(Xf, Yr, folds)
    full = RidgeSVD(Xf, Yr)
    cond = float(full.d[0] / full.d[-1]) if full.d[-1] > 0 else math.inf
    sel = None
    curves: dict = {}
    if recipe.lam == "cv":
        sel = select_lambda(cv)
        lams = sel["lam"]
        curves.update(sel)
    else:
        lams = np.full(2, float(recipe.lam))
    cv_ls = cv.mse(0.0)
    cv_ch = cv.mse(lams)
    if bias_variance and sel is not None:
        g = 10.0 ** sel["log10_grid"]
        curves.update(full.bias_variance(g))
        curves["lam_grid"] = g
    return _Ridge(lams, full.coef(lams).T, full.coef(0.0).T, cv_ls, cv_ch, cond, sel, curves)


def _prune(Xf, Yr, lams, folds, recipe: FitRecipe, blocked: bool, protect_first: bool, n_shape: int):
    """Step 4, pruning (ridge.prune_terms) per component, deciding on at most PRUNE_MAX_ROWS
    (strided) rows; the kept columns are refitted on all rows. Returns the kept mask and the
    refitted coefficients of the free columns (2, Nf) and the pruning info per component."""
    M, Nf = Xf.shape
    stride = max(1, -(-M // PRUNE_MAX_ROWS))
    Xp, Yp = Xf[::stride], Yr[::stride]
    folds_p = folds if stride == 1 else fold_indices(len(Xp), recipe.k_folds, recipe.seed, blocked)
    kept = np.ones((2, Nf), bool)
    coef = np.zeros((2, Nf))
    info = {}
    for j in range(2):
        keep, inf = prune_terms(Xp, Yp[:, j:j + 1], float(lams[j]), folds_p, recipe.prune_tol,
                                protect_first=protect_first, protect_last=n_shape)
        inf["rows_used"] = int(len(Xp))
        kept[j] = keep
        coef[j, keep] = RidgeSVD(Xf[:, keep], Yr[:, j]).coef(float(lams[j]))[:, 0]
        info[COMPONENTS[j]] = inf
    return kept, coef, info


def _split_shape(c, N: int, lin, anchored: bool):
    """Step 5: coefficients (2, N + 2 Nr) -> polynomial (2, N) and shape part (2, 2 Nr), with
    the anchor's shift of the shape columns put back into the constant and order-1 terms."""
    cp, ca = c[:, :N].copy(), c[:, N:]
    if ca.shape[1] and anchored:
        cp[:, :5] -= ca @ lin
    return cp, ca


def _errors(u: _Units, states, forces, S, Y, ridge: _Ridge, weights, test, fits: dict) -> dict:
    """Step 6, the errors: NRMSE on the training rows and of the CV objective, and on the
    held-out ``test`` (states, forces) of the chosen, unpruned and least-squares fits."""
    coef, aug = fits["chosen"]
    train_pred = u.predict(states, S, coef, aug)
    errors = {
        "nrmse_definition": "RMS(prediction - truth) / std(truth), per component",
        "train_nrmse": dict(zip(COMPONENTS, nrmse(train_pred, forces).tolist())),
        "cv_nrmse_ls": dict(zip(COMPONENTS, (np.sqrt(ridge.cv_ls) / np.std(Y, axis=0)).tolist())),
        "cv_nrmse_chosen": dict(zip(COMPONENTS, (np.sqrt(ridge.cv_chosen) / np.std(Y, axis=0)).tolist())),
        "n_train": int(len(states)),
    }
    if weights is not None:
        errors["row_weights"] = {"min": float(np.min(weights)), "max": float(np.max(weights)),
                                 "note": "cv_nrmse_* are of the weighted rows"}
    if test is not None:
        ts, tf = np.asarray(test[0], float), np.asarray(test[1], float)
        St = u.short_bearing(ts)
        pred = u.predict(ts, St, *fits["chosen"])
        pred_ls = u.predict(ts, St, *fits["ls"])
        pred_un = u.predict(ts, St, *fits["unpruned"])
        errors.update({
            "test_nrmse": dict(zip(COMPONENTS, nrmse(pred, tf).tolist())),
            "test_nrmse_unpruned": dict(zip(COMPONENTS, nrmse(pred_un, tf).tolist())),
            "test_nrmse_ls_unpruned": dict(zip(COMPONENTS, nrmse(pred_ls, tf).tolist())),
            "test_rel_rms": dict(zip(COMPONENTS, rel_rms(pred, tf).tolist())),
            "test_max_abs_err_N": dict(zip(COMPONENTS, np.max(np.abs(pred - tf), axis=0).tolist())),
            "n_test": int(len(ts)),
        })
    return errors


def fit_surrogate(
    states, forces, params: BearingParams, omega: float, y0: float, z0: float, recipe: FitRecipe, *,
    domain: Domain, anchor=None, weights=None, blocked: bool = False, test=None, load=None,
    force_scale: float | None = None, provenance: dict | None = None, bias_variance: bool = True,
) -> FitResult:
    """Fit both force components of the surrogate of ``recipe`` (order, lambda, folds,
    pruning, wall factor, shape columns, seed of random folds) to the truth's ``forces``
    (M, 2) [N] at ``states`` (M, 4) [m, m/s], about the expansion point (y0, z0) at omega.

    Steps: the design (1), the anchor (2), lambda (3), pruning (4), the shape part split off
    (5), the errors (6), the training states stored for the guard's nearest-neighbour distance
    (7, :mod:`.neighbours`: radius from these CV folds); see the module doc.

    ``anchor`` = (F0 (2,), dF_dq (2, 2), dF_dv (2, 2)) at the expansion point (a truth's
    ``force_and_jacobian``), given exactly when ``recipe.anchor``: it fixes the constant and
    the order-1 coefficients -- the Taylor series proper (eq. 6): the surrogate then has the
    truth's static force and Lund coefficients at the expansion point, and only the terms of
    degree >= 2 are regressed (on the residual). Without it all terms are regressed (a global
    least-squares polynomial).

    ``weights`` (M,), >= 0: a weight per training row in the least-squares term,
    sum_k w_k (f_k - X_k k)^2 (rows of X and f scaled by sqrt(w)); the CV error, lambda choice
    and pruning then use the same weighted objective. None = all 1.

    ``blocked``: the rows are a time series (CV folds of contiguous blocks, ridge.fold_indices).
    ``test`` = (states, forces) held out for the reported errors. With ``recipe.wall_power``
    the CV errors are of G = F (1 - eps^2)^p; train and held-out errors are of F.
    ``force_scale`` [N]: the force unit of the regression (default: natural_force_scale).
    ``provenance``: facts about the data stored in the file beside the recipe."""
    t0 = time.perf_counter()
    if recipe.anchor != (anchor is not None):
        raise ValueError("fit: recipe.anchor is true, give anchor = (F0, dF/dq, dF/dv) at the expansion point"
                         if recipe.anchor else "fit: an anchor was given but recipe.anchor is false")
    u = _Units(params, omega, y0, z0, recipe, force_scale)
    states = np.asarray(states, float)
    forces = np.asarray(forces, float)

    # 1. the design
    X, Y, S_train, XA = _design(u, states, forces)
    M, N = X.shape
    Nr = u.Nr
    # 2. the anchor, and the free columns it leaves
    c_fix, lin, XA = _anchor(u, anchor, states, XA)
    n_fix = c_fix.shape[1]
    Xf = np.hstack([X[:, n_fix:], XA])
    Yr = Y - X[:, :n_fix] @ c_fix.T
    Nf = N - n_fix + 2 * Nr  # free polynomial terms, then the 2 Nr shape columns
    if M < Nf:
        raise ValueError(f"fit: {M} samples for {Nf} free terms of order {recipe.order}"
                         + (f" with shape order {recipe.shape_order}" if Nr else "")
                         + "; need at least as many samples")
    if weights is not None:
        w = np.asarray(weights, float).reshape(-1)
        if w.shape != (M,) or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError(f"fit: weights must be {M} finite values >= 0, got shape {w.shape}")
        sw = np.sqrt(w)[:, None]
        Xf, Yr = Xf * sw, Yr * sw  # the regression sees weighted rows; reported errors stay unweighted
    folds = fold_indices(M, recipe.k_folds, recipe.seed, blocked)
    # 3. lambda
    ridge = _choose_lambda(Xf, Yr, folds, recipe, bias_variance)
    lams = ridge.lams
    coef = np.hstack([c_fix, ridge.coef])  # (2, N + 2 Nr) until the shape part is split off
    coef_unpruned = coef.copy()
    coef_ls = np.hstack([c_fix, ridge.coef_ls])
    kept = np.ones((2, N + 2 * Nr), bool)
    # 4. pruning
    prune_info = {}
    if recipe.prune and Nf > 0:
        kept_free, coef_free, prune_info = _prune(Xf, Yr, lams, folds, recipe, blocked, protect_first=n_fix == 0,
                                                  n_shape=2 * Nr)
        kept[:, n_fix:] = kept_free
        coef[:, n_fix:] = coef_free
    # 5. the shape part
    anchored = anchor is not None
    fits = {"chosen": _split_shape(coef, N, lin, anchored), "unpruned": _split_shape(coef_unpruned, N, lin, anchored),
            "ls": _split_shape(coef_ls, N, lin, anchored)}
    coef, coef_aug = fits["chosen"]
    kept = kept[:, :N]
    # 6. the errors
    errors = _errors(u, states, forces, S_train, Y, ridge, weights, test, fits)
    # 7. the training states the guard measures distances to (fitting.neighbours)
    neighbours = neighbours_for_fit(u.scaled(states), folds)

    from .. import __version__

    prov = {"date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"), "package_version": __version__}
    prov.update(provenance or {})
    prov["recipe"] = recipe.to_dict()
    if anchored:
        prov.setdefault("anchor", "constant and order-1 terms fixed to the truth's force and derivatives "
                                  "at the expansion point; degree >= 2 regressed")
    pruning = {"criterion": f"drop smallest |coef| * RMS(column) while CV RMS error <= (1 + {recipe.prune_tol}) "
                            "x unpruned", **prune_info} if recipe.prune else {"criterion": "none"}
    sur = Surrogate(
        params=params, omega=omega, y0=y0, z0=z0, order=recipe.order, exponents=u.exps, coef=coef,
        force_scale=u.fs, domain=domain, kept=kept, lam=(float(lams[0]), float(lams[1])),
        load=None if load is None else (float(load[0]), float(load[1])),
        errors=errors, pruning=pruning, provenance=prov, wall_power=recipe.wall_power,
        shape_order=recipe.shape_order, shape_coef=coef_aug.reshape(4, Nr) if Nr else None, neighbours=neighbours,
    )
    sel = ridge.selection
    report = {
        "order": recipe.order, "n_terms": N, "n_train": M, "cond_X": ridge.cond, "k_folds": recipe.k_folds,
        "anchored": anchored, "n_fixed": n_fix, "shape_order": recipe.shape_order, "n_shape_columns": 2 * Nr,
        "lambda": dict(zip(COMPONENTS, [float(v) for v in lams])),
        "lambda_search": None if sel is None else dict(zip(COMPONENTS, sel["lam_search"].tolist())),
        "ls_wins": None if sel is None else dict(zip(COMPONENTS, [bool(v == 0.0) for v in lams])),
        "kept": dict(zip(COMPONENTS, [int(kept[0].sum()), int(kept[1].sum())])),
        "errors": errors, "fit_seconds": time.perf_counter() - t0,
        "neighbours": {"n_points": int(len(neighbours.points)), "radius": neighbours.radius,
                       "covering_radius": neighbours.info["covering_radius"]},
    }
    return FitResult(sur, report, ridge.curves, recipe)


def save_fit(res: FitResult, path: str | Path) -> Path:
    """Write the fitted surrogate file, its recipe's paths (scenes, npz) relative to the file."""
    if res.recipe is not None:
        res.surrogate.provenance["recipe"] = res.recipe.to_dict(relative_to=Path(path).resolve().parent)
    return save_surrogate(res.surrogate, path)


# ----------------------------------------------------------------------------- the truth at the expansion point

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
    from ..physics.statics import equilibrium

    return equilibrium(internal, load, omega)


# ----------------------------------------------------------------------------- a designed domain

def fit_condition(recipe: FitRecipe, *, internal=None, params: BearingParams = PAPER_BEARING,
                  bias_variance: bool = True) -> FitResult:
    """The fit of a designed-domain ``recipe`` for the bearing ``params``: the equilibrium
    under the recipe's load at its speed, training data (designed, or its ``from_npz`` time
    series), the fit, the held-out check. ``internal``: the truth of the statics and, without
    ``recipe.truth_map``, of the samples (default: Reynolds on the recipe's grid, or on the
    map's; see :mod:`.truth`).

    With ``recipe.anchor`` the constant and order-1 terms are the truth's force and
    derivatives at the equilibrium (``force_and_jacobian``, else central differences).
    Designed: train on a Latin hypercube with ``recipe.seed``, report errors on another with
    seed + 1000. npz: the first 80 % of the time series trains (blocked CV), the last 20 % is
    held out. The report adds the time of the truth's samples (``sampling_seconds``) and of
    the whole call (``total_seconds``). The film fit (``flows.attach_film``) follows the force's,
    from the same truth at the training states, its errors at the held-out ones."""
    t_start = time.perf_counter()
    if recipe.kind != "designed":
        raise ValueError("fit_condition: the recipe names training scenes; a scene-trained surrogate is fitted by "
                         "the host (`rotor-host fit`)")
    r = recipe
    omega = 2 * math.pi * r.speed_hz
    truth = fit_truth(r, params if internal is None else internal.params, internal,
                      grid_hint="leave --grid out to use the map's grid, or build a map on this grid "
                                "(`bearing-fmu map --grid N_THETAxN_X`)")
    if r.from_npz is None:
        truth.check_reach(r.ecc_max, "ecc_max")
    internal = truth.statics
    params = internal.params
    y0, z0 = expansion_point(internal, r.load, omega)
    prov = truth.provenance()
    t_samples = 0.0
    if r.from_npz is None:
        from scipy.stats import qmc  # noqa: F401 -- the design's sampler, imported (0.3-0.6 s) before the clock:
        # sampling_seconds is the truth's time
        t0 = time.perf_counter()
        states, forces, domain = designed_samples(truth.samples, y0, z0, omega, r.ecc_max, r.v_max, r.n_train,
                                                  r.seed, radius=r.radius)
        ts, tf, _ = designed_samples(truth.samples, y0, z0, omega, r.ecc_max, r.v_max, r.n_test, r.seed + 1000,
                                     radius=r.radius)
        t_samples = time.perf_counter() - t0
        prov.update({"training_source": "designed", "design": "Latin hypercube over position and velocity discs",
                     "held_out": "another Latin hypercube (seed + 1000)"})
        blocked = False
    else:
        s_all, f_all = load_npz(r.from_npz)
        cut = int(0.8 * len(s_all))
        states, forces, ts, tf = s_all[:cut], f_all[:cut], s_all[cut:], f_all[cut:]
        domain = domain_from_data(states, y0, z0, params, omega)
        prov.update({"training_source": f"time series {Path(r.from_npz).name}",
                     "held_out": "last 20 % of the series"})
        blocked = True
    anc = truth_jacobian(internal, y0, z0, omega) if r.anchor else None
    res = fit_surrogate(states, forces, params, omega, y0, z0, r, domain=domain, anchor=anc, blocked=blocked,
                        test=(ts, tf), load=r.load, provenance=prov, bias_variance=bias_variance)
    t_film = time.perf_counter()
    attach_film(res, truth, states, test_states=ts, seed=r.seed)  # the film's flows; the force as fitted above
    res.report["film_seconds"] = time.perf_counter() - t_film
    eq = math.hypot(y0, z0) / params.CR
    res.report.update({"speed_hz": r.speed_hz, "load": list(r.load), "equilibrium": [y0, z0], "eps0": eq,
                       "domain": domain.to_dict(), "sampling_seconds": t_samples,
                       "total_seconds": time.perf_counter() - t_start})
    return res


def refit_order(surrogate_path, order: int, out_path, *, surrogate: Surrogate | None = None) -> Path:
    """Refit the designed-domain surrogate of ``surrogate_path`` at another ``order`` from the
    same domain or time series (its recipe); write ``out_path``. ``surrogate``: the file's
    content if the caller has read it already. (Scene-trained surrogates: the host's refit.)"""
    sur = load_surrogate(surrogate_path) if surrogate is None else surrogate
    recipe = recipe_of(sur, surrogate_path)
    if recipe.kind != "designed":
        raise ValueError(f"{surrogate_path}: fitted to the series of scenes; refit it with "
                         "the host's refit (as `rotor-host compare --orders` does)")
    return save_fit(fit_condition(recipe.with_order(order), params=sur.params), out_path)


__all__ = ["FitResult", "fit_surrogate", "save_fit", "fit_condition", "truth_jacobian",
           "expansion_point", "refit_order", "COMPONENTS"]
