"""Fitting the Taylor surrogate to the truth's forces: the fit itself (``fit_surrogate``) and
the fit over a designed domain at one load and speed (``fit_condition``).

Conventions
-----------
* Regression in scaled units (see :mod:`bearing_fmu.basis`): the design matrix X (M x N)
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
from numbers import Integral
from pathlib import Path

import numpy as np

from .._taylor_kernels import short_bearing_at
from ..basis import design_matrix, exponents, natural_force_scale, shape_force
from ..params import PAPER_BEARING, BearingParams
from ..surrogate import Domain, Surrogate, save_surrogate
from .ridge import CrossValidation, RidgeSVD, fold_indices, nrmse, prune_terms, rel_rms, select_lambda
from .sampling import designed_samples, domain_from_data, load_npz

COMPONENTS = ("Fy", "Fz")
PRUNE_MAX_ROWS = 6000  # pruning decides on at most this many (strided) samples; the refit uses all


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
    from .. import __version__

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
    from ..reynolds import Reynolds

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
    from ..statics import equilibrium

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
    from ..surrogate import load_surrogate

    base = load_surrogate(surrogate_path)
    call = dict(base.provenance.get("fit_call") or {})
    if not call or "speed_hz" not in call:
        raise ValueError(f"{surrogate_path}: its provenance has no 'fit_call' to refit from "
                         "(fitted by an older version); fit it again with `bearing-fmu fit`")
    grid = tuple(call.pop("grid")) if call.get("grid") else None
    load, speed = call.pop("load"), call.pop("speed_hz")
    res = fit_condition(tuple(load), speed, order, params=base.params, grid=grid, **call)
    return save_surrogate(res.surrogate, out_path)


__all__ = ["FitResult", "fit_surrogate", "fit_condition", "make_reynolds", "truth_jacobian", "expansion_point",
           "refit_order", "COMPONENTS"]
