"""Study (not yet in the product): the Taylor surrogate with short-bearing shape columns.

Model (G-space, g = (1 - eps^2)^p, fs = natural force scale):
    F = fs P_n(u) / g + sum_j (a_yj S_y + a_zj S_z) m_j(u)
S = closed-form short-bearing (Ocvirk, half-Sommerfeld) force (bearing_fmu.shortbearing), m_j the
monomials of order <= r. One ridge regression per force component on the shared predictor
matrix (bearing_fmu.fitting's RidgeSVD / CrossValidation / select_lambda). Anchored: the constant and
degree-1 polynomial coefficients are fixed so that the whole model has the truth's force and
Jacobian at the expansion point; each shape column has its own degree <= 1 Taylor part (central
differences at u = 0) removed. Results and the plan to build it into bearing_fmu.taylor:
docs/taylor.md, "Short-bearing shape columns". This harness evaluates the shape columns in pure
Python (about 34 us per force, 300 us with its central-difference Jacobian): a study tool, not
an internal to ship.

    .venv/bin/python benchmarks/shape_basis/study.py 44hz --closed-loop
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from bearing_fmu import fitting as F
from bearing_fmu.internals import BearingStateError, check_state
from bearing_fmu.reynolds import Reynolds
from bearing_fmu.shortbearing import short_bearing_force
from bearing_fmu.basis import design_matrix, exponents, natural_force_scale
from bearing_fmu.surrogate import Surrogate, load_surrogate
from bearing_fmu.taylor import Taylor
from rotor_host.scene import load_scene
from rotor_host.training import _bearing_params, holdout_mask, scene_series

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "models" / "scenes"
SURR = ROOT / "models" / "surrogates"
CACHE = ROOT / "out" / "series"  # the same cache as benchmarks/order_study.py
SBC = ROOT / "out" / "shape_basis" / "sb_cache"

CASES = {
    "10hz": dict(train=["paper_10hz_500N"], test=["paper_10hz_500N_node1"], shipped="paper_10hz_500N.json"),
    "20hz": dict(train=["paper_20hz_800N", "train_20hz_800N_2.5kg"], test=["train_20hz_800N_1.0kg"], shipped=None),
    "44hz": dict(train=["paper_44hz", "train_44hz_2g", "train_44hz_12g"], test=["heldout_44hz_4g"],
                 shipped="paper_44hz_16.7N.json"),
}


def sb_forces(params, states, omega, tag):
    """Short-bearing force at every state (cached)."""
    SBC.mkdir(parents=True, exist_ok=True)
    path = SBC / f"{tag}.npy"
    if path.is_file():
        S = np.load(path)
        if S.shape == (len(states), 2):
            return S
    S = np.array([short_bearing_force(params, *x, omega) for x in states])
    np.save(path, S)
    return S


class Case:
    def __init__(self, name, stride=2, log=print):
        spec = CASES[name]
        self.name = name
        scenes = [load_scene(SCENES / f"{n}.toml") for n in spec["train"]]
        sc = scenes[0]
        self.scene = sc
        self.params = params = _bearing_params(sc, 1)
        self.omega = omega = sc.omega
        self.truth = Reynolds(params, n_theta=sc.n_theta, n_x=sc.n_x)
        trs, trf, trS, hos, hof, hoS = [], [], [], [], [], []
        load = None
        for n, s in zip(spec["train"], scenes):
            t, st, fo, ld = scene_series(s, 1, CACHE / f"{n}_b1_series.npz", log)
            load = ld if load is None else load
            t, st, fo = t[::stride], st[::stride], fo[::stride]
            S = sb_forces(params, st, omega, f"{n}_s{stride}")
            held = holdout_mask(t, s.speed_hz)
            trs.append(st[~held]); trf.append(fo[~held]); trS.append(S[~held])
            hos.append(st[held]); hof.append(fo[held]); hoS.append(S[held])
        self.s_tr, self.f_tr, self.S_tr = np.vstack(trs), np.vstack(trf), np.vstack(trS)
        self.s_ho, self.f_ho, self.S_ho = np.vstack(hos), np.vstack(hof), np.vstack(hoS)
        self.load = load
        self.others = {}
        for n in spec["test"]:
            s = load_scene(SCENES / f"{n}.toml")
            _, st, fo, _ = scene_series(s, 1, CACHE / f"{n}_b1_series.npz", log)
            st, fo = st[::stride], fo[::stride]
            self.others[n] = (st, fo, sb_forces(params, st, omega, f"{n}_s{stride}"))
        if spec["shipped"]:
            self.shipped = load_surrogate(SURR / spec["shipped"], params)
            self.y0, self.z0 = self.shipped.y0, self.shipped.z0
        else:
            self.shipped = None
            self.y0, self.z0 = F.expansion_point(self.truth, tuple(load), omega)
        self.anchor = F.truth_jacobian(self.truth, self.y0, self.z0, omega)
        self.fs = natural_force_scale(params, omega)
        self.cr, self.vs = params.CR, abs(omega) * params.CR
        self.domain = F.domain_from_data(self.s_tr, self.y0, self.z0, params, omega)

    def scaled(self, s):
        s = np.atleast_2d(s)
        return np.column_stack([(s[:, 0] - self.y0) / self.cr, (s[:, 1] - self.z0) / self.cr,
                                s[:, 2] / self.vs, s[:, 3] / self.vs])

    def unscale(self, u):
        return np.array([self.y0 + u[0] * self.cr, self.z0 + u[1] * self.cr, u[2] * self.vs, u[3] * self.vs])

    def g(self, s, p):
        s = np.atleast_2d(s)
        return (1.0 - (s[:, 0] ** 2 + s[:, 1] ** 2) / self.cr**2) ** p


class Model:
    """Fitted augmented model (F-space evaluation)."""

    def __init__(self, case: Case, n, r, p, coef_poly, coef_aug, c_res, lam):
        self.case, self.n, self.r, self.p = case, n, r, p
        self.ep, self.er = exponents(n), (exponents(r) if r is not None else None)
        self.coef_poly, self.coef_aug, self.c_res, self.lam = coef_poly, coef_aug, c_res, lam

    def predict(self, s, S):
        c = self.case
        U = c.scaled(s)
        out = (design_matrix(U, self.ep) @ self.coef_poly.T) * c.fs / c.g(s, self.p)[:, None]
        if self.er is not None:
            mj = design_matrix(U, self.er)
            A = np.hstack([S[:, :1] * mj, S[:, 1:2] * mj])  # F-space augmented columns (no g, no fs)
            out += A @ self.coef_aug.T
        if self.c_res:
            out += self.c_res * S
        return out

    def surrogate(self):
        """The polynomial part as a project Surrogate (for the compiled Taylor kernel)."""
        c = self.case
        return Surrogate(params=c.params, omega=c.omega, y0=c.y0, z0=c.z0, order=self.n, exponents=self.ep,
                         coef=self.coef_poly, force_scale=c.fs, domain=c.domain, wall_power=self.p,
                         load=tuple(c.load))


def _aug_cols_G(case, s, S, er, p):
    """Augmented columns in G-space, scaled by fs: S_i g / fs * m_j(u)."""
    U = case.scaled(s)
    mj = design_matrix(U, er)
    gS = S * case.g(s, p)[:, None] / case.fs
    return np.hstack([gS[:, :1] * mj, gS[:, 1:2] * mj])


def _taylor1(case, fun, h=1e-6):
    """Value and gradient (w.r.t. u) at u = 0 of fun(state) -> (k,) array; central differences."""
    v0 = fun(case.unscale(np.zeros(4)))
    grad = np.empty((len(v0), 4))
    for i in range(4):
        e = np.zeros(4); e[i] = h
        grad[:, i] = (fun(case.unscale(e)) - fun(case.unscale(-e))) / (2 * h)
    return v0, grad


def fit(case: Case, n, r=None, p=0.0, lam="cv", residual=False, anchor=True, seed=0, k_folds=5):
    """Returns (Model, info). r=None: polynomial only (project's basis)."""
    t0 = time.perf_counter()
    fs, cr, vs = case.fs, case.cr, case.vs
    s, f, S = case.s_tr, case.f_tr, case.S_tr
    ep = exponents(n)
    g = case.g(s, p)
    X = design_matrix(case.scaled(s), ep)
    Y = f / fs * g[:, None]
    c_res = 0.0
    if residual:
        c_res = float(np.sum(f * S) / np.sum(S * S))
        Y = Y - c_res * S * g[:, None] / fs
    er = exponents(r) if r is not None else None
    XA = _aug_cols_G(case, s, S, er, p) if er is not None else np.zeros((len(s), 0))
    nA = XA.shape[1]
    if anchor:
        F0, dq, dv = (np.asarray(a, float) for a in case.anchor)
        y0, z0 = case.y0, case.z0
        if p != 0.0:
            q0 = 1.0 - (y0 * y0 + z0 * z0) / cr**2
            g0 = q0**p
            dg = -2.0 * p * np.array([y0, z0]) / cr**2 * q0 ** (p - 1.0)
            F0, dq, dv = F0 * g0, dq * g0 + np.outer(F0, dg), dv * g0
        c_fix = np.column_stack([F0 / fs, dq[:, 0] * cr / fs, dq[:, 1] * cr / fs, dv[:, 0] * vs / fs, dv[:, 1] * vs / fs])
        if residual:  # the offset's own first-order part is part of the anchor
            def off(st):
                return c_res * np.array(short_bearing_force(case.params, *st, case.omega)) * case.g(st, p)[0] / fs
            o0, og = _taylor1(case, off)
            c_fix = c_fix - np.column_stack([o0, og])
        if nA:
            def acol(st):
                Sx = np.array([short_bearing_force(case.params, *st, case.omega)])
                return _aug_cols_G(case, st[None, :], Sx, er, p)[0]
            a0, ag = _taylor1(case, acol)  # (nA,), (nA, 4)
            lin = np.column_stack([a0, ag])  # (nA, 5): each augmented column's degree <= 1 part
            U = case.scaled(s)
            XA = XA - (a0[None, :] + U @ ag.T)
        nfix = 5
    else:
        c_fix = np.zeros((2, 0)); nfix = 0
    Xf = np.hstack([X[:, nfix:], XA])
    Yr = Y - X[:, :nfix] @ c_fix.T
    full = F.RidgeSVD(Xf, Yr)
    cond = float(full.d[0] / full.d[-1])
    sel = None
    if lam == "cv":
        cv = F.CrossValidation(Xf, Yr, F.fold_indices(len(Xf), k_folds, seed, blocked=True))
        sel = F.select_lambda(cv)
        lams = sel["lam"]
    else:
        lams = np.full(2, float(lam))
    k = full.coef(lams).T  # (2, Nfree)
    npf = X.shape[1] - nfix
    coef_poly = np.hstack([c_fix, k[:, :npf]])
    coef_aug = k[:, npf:]
    if anchor and nA:
        coef_poly[:, :5] -= coef_aug @ lin  # undo the column modification into the polynomial
    m = Model(case, n, r, p, coef_poly, coef_aug if nA else np.zeros((2, 0)), c_res, lams)
    info = {"cond": cond, "lam": lams.tolist(), "n_cols": Xf.shape[1], "fit_s": time.perf_counter() - t0}
    return m, info


def evaluate(case: Case, m: Model):
    """Held-out blocks NRMSE, per other trajectory NRMSE (all states / in domain) and train NRMSE."""
    out = {"blocks": F.nrmse(m.predict(case.s_ho, case.S_ho), case.f_ho),
           "train": F.nrmse(m.predict(case.s_tr, case.S_tr), case.f_tr)}
    tay = Taylor(m.surrogate())
    for n, (st, fo, S) in case.others.items():
        pr = m.predict(st, S)
        inside = np.array([tay.domain_distance(*x) <= 1e-12 for x in st])
        out["other"] = F.nrmse(pr, fo)
        out["other_in"] = F.nrmse(pr[inside], fo[inside])
        out["frac_in"] = float(inside.mean())
    return out


def fmt(ev):
    s = f"blocks {100*ev['blocks'][0]:7.2f} / {100*ev['blocks'][1]:7.2f}"
    if "other" in ev:
        s += f" | other {100*ev['other'][0]:8.2f} / {100*ev['other'][1]:8.2f}"
        s += f" (in-domain {100*ev['other_in'][0]:.2f} / {100*ev['other_in'][1]:.2f}, {100*ev['frac_in']:.0f}% in)"
    s += f" | train {100*ev['train'][0]:.2f} / {100*ev['train'][1]:.2f}"
    return s


# ----------------------------------------------------------------------------- the internal

class AugInternal:
    """Bearing internal of a fitted Model: polynomial part through the project's compiled
    Taylor (analytic Jacobian), short-bearing part in pure Python with central differences.
    ``guard_limit``: refuse states more than this relative excess outside the fitted domain
    (as the project's DomainGuard does with its default 0.5); None = no guard."""

    def __init__(self, model: Model, params, guard_limit=0.5):
        self.model = model
        self.params = params
        self.tay = Taylor(model.surrogate())
        self.er = model.er
        self.A = model.coef_aug  # (2, 2*Nr)
        self.c_res = model.c_res
        self.guard_limit = guard_limit
        c = model.case
        self.y0, self.z0, self.cr, self.vs = c.y0, c.z0, c.cr, c.vs
        self.n_eval = 0

    def _aug(self, y, z, vy, vz, omega):
        sy, sz = short_bearing_force(self.params, y, z, vy, vz, omega)
        out = np.zeros(2)
        if self.er is not None:
            u = np.array([(y - self.y0) / self.cr, (z - self.z0) / self.cr, vy / self.vs, vz / self.vs])
            mj = np.prod(u[None, :] ** self.er, axis=1)
            out += self.A @ np.concatenate([sy * mj, sz * mj])
        if self.c_res:
            out += self.c_res * np.array([sy, sz])
        return out

    def _guard(self, y, z, vy, vz, omega):
        check_state(self.params, y, z, vy, vz, omega)
        if self.guard_limit is not None:
            d = self.tay.domain_distance(y, z, vy, vz)
            if d > self.guard_limit:
                raise BearingStateError(f"state {100*d:.0f} % beyond the fitted domain")

    def force(self, y, z, vy, vz, omega):
        self._guard(y, z, vy, vz, omega)
        self.n_eval += 1
        fp = np.asarray(self.tay.force(y, z, vy, vz, omega))
        return tuple(fp + self._aug(y, z, vy, vz, omega))

    def force_and_jacobian(self, y, z, vy, vz, omega):
        self._guard(y, z, vy, vz, omega)
        self.n_eval += 1
        f, dq, dv = self.tay.force_and_jacobian(y, z, vy, vz, omega)
        f = np.array(f, float) + self._aug(y, z, vy, vz, omega)
        dq, dv = np.array(dq, float), np.array(dv, float)
        x = np.array([y, z, vy, vz])
        hq, hv = 1e-6 * self.cr, 1e-6 * self.vs
        cr = self.cr
        for j, h in enumerate((hq, hq, hv, hv)):
            xp, xm = x.copy(), x.copy()
            xp[j] += h; xm[j] -= h
            if j < 2 and math.hypot(xp[0], xp[1]) >= cr:
                xp[j] = x[j]; h2 = h
                d = (self._aug(*xp, omega) - self._aug(*xm, omega)) / h2
            else:
                d = (self._aug(*xp, omega) - self._aug(*xm, omega)) / (2 * h)
            if j < 2:
                dq[:, j] += d
            else:
                dv[:, j - 2] += d
        return f, dq, dv
