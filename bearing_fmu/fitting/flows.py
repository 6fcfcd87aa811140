"""The surrogate's film fit: the film's side flow and inflow by the force map's reduction, its
two functions J_s, J_i of (eps, beta) fitted by ridge regression beside the force, from the
same truth (``bearing_fmu.surrogates.film``: the reduction and the basis).

The force fit is not touched: ``attach_film`` only adds ``Surrogate.film``. At up to
FILM_MAX_ROWS of the training states (evenly strided) the truth's film reports at the fit's
speed omega and at 2 omega with the same (eps, beta, r) give J_s and J_i exactly as the map's
table has them (``film.reduced_flows``: the second speed recovers the inflow's sign). The
regression is of the flows themselves in units of |omega| Q0: rows (r / |omega|) features(eps,
beta), so a state with a small source r (whose flows hardly depend on J) weighs little and the
cone of r at r = 0 is exact. One lambda per function by k-fold cross validation
(``ridge.select_lambda``). Errors: at held-out states, the median, 95th percentile and maximum
relative error of the inflow and the side flow against the truth's report there.

A grooved or partial-arc bore (``fit_grooved_film``; no supply pressure, no lobes, as the grooved
map): at each training state one Reynolds solve gives the side flow and every supply edge's pressure
part exactly (``Reynolds.supply_flows``, ``film.supply_functions``: the grooved map's own), so J_s
and P_e at (eps, phi, beta); each fitted in the full bore's basis times a Fourier series in phi up
to GROOVED_PHI_HARMONICS (``surrogates.film.grooved_features``), with the same row weights and lambdas.
"""

from __future__ import annotations

import math

import numpy as np

from ..physics.solver.film import flow_scale, grooved_report, reduced_flows, supply_functions
from ..surrogates.film import TARGETS, FilmFit, GroovedFilmFit, features, grooved_features, n_features
from .ridge import CrossValidation, RidgeSVD, fold_indices, select_lambda

FILM_DEGREE = 6  # eps^0 .. eps^6
FILM_HARMONICS = 6  # 1, cos beta, sin beta .. cos 6 beta, sin 6 beta: 7 x 13 = 91 features
FILM_MAX_ROWS = 3000  # training states whose film is computed at most (each two truth solves)
FILM_TEST_ROWS = 300  # held-out states at most for the recorded errors
GROOVED_PHI_HARMONICS = 4  # 1, cos phi, sin phi .. sin 4 phi: near the centre the attitude takes any value

def film_truth(truth, grooved: bool = False):
    """The internal whose film reports a fit's film fit follows: the samples' truth when it has the
    film's flows (Reynolds, a map with flow tables), else the statics' (Reynolds); None if neither.
    ``grooved``: one with the supply edges' flows (``supply_flows``: Reynolds)."""
    for internal in (truth.samples, truth.statics):
        if getattr(internal, "film_report", None) is not None and not getattr(internal, "film_flow_why", ""):
            if not grooved or getattr(internal, "supply_flows", None) is not None:
                return internal
    return None


def reduced_state(params, y, z, vy, vz, omega: float):
    """(eps, beta, r, phi) of a state: the map's coordinates (``forcemap.reduced``)."""
    from ..internals.map.tables import reduced

    eps, phi, a, c = reduced(y, z, vy, vz, omega, params.CR)
    return eps, math.atan2(c, a), math.hypot(a, c), phi


def flow_functions(internal, states, omega: float) -> np.ndarray:
    """(M, 5): eps, beta, r [1/s], J_s, J_i at each state (M, 4) [m, m/s] from the film reports of
    ``internal`` at omega and 2 omega with the same eps, beta, r and attitude (``reduced_flows``)."""
    from ..internals.map.tables import EPS_MIN, state_for

    params = internal.params
    out = np.empty((len(states), 5))
    for i, s in enumerate(np.asarray(states, float)):
        eps, beta, r, phi = reduced_state(params, *s, omega)
        eps = max(eps, EPS_MIN)  # as the map's centre row
        r = max(r, 1e-9 * abs(omega))  # J at r = 0 is the limit along beta; its flows do not depend on it
        reports = {w: internal.film_report(*state_for(eps, beta, params, phi=phi, omega=w, r=r), w)
                   for w in (omega, 2.0 * omega)}
        out[i] = (eps, beta, r, *reduced_flows(params, eps, r, reports))
    if not np.all(np.isfinite(out)):
        raise ValueError("film fit: the truth's film report is not finite at a training state")
    return out


def grooved_flow_functions(internal, states, omega: float) -> np.ndarray:
    """(M, 5 + E): eps, phi, beta, r [1/s], J_s, P_1 .. P_E at each state (M, 4) [m, m/s] of a grooved
    or partial-arc bore, from one solve of ``internal`` (Reynolds) there (``film.supply_functions``)."""
    params = internal.params
    out = np.empty((len(states), 5 + len(params.geometry.supply_edges())))
    for i, s in enumerate(np.asarray(states, float)):
        eps, beta, r, phi = reduced_state(params, *s, omega)
        j_s, p_e = supply_functions(params, internal.supply_flows(*s, omega), r)
        out[i] = (eps, phi, beta, r, j_s, *p_e)
    if not np.all(np.isfinite(out)):
        raise ValueError("film fit: the truth's supply flows are not finite at a training state (r = 0?)")
    return out


def predicted_flows(fit, params, states, omega: float) -> np.ndarray:
    """(M, 2): inflow, side flow [m^3/s] of the film fit at states (M, 4) (``film.reduced_report``'s, or
    ``film.grooved_report``'s for a grooved fit)."""
    q0 = flow_scale(params)
    out = np.empty((len(states), 2))
    for i, s in enumerate(np.asarray(states, float)):
        eps, beta, r, phi = reduced_state(params, *s, omega)
        if isinstance(fit, GroovedFilmFit):
            f = fit.values(eps, phi, beta)[0]
            rep = grooved_report(params, *s, omega, (0.0, 0.0), r, float(f[0]), f[1:], fit.edges)
            out[i] = rep.inflow_m3_s, rep.side_flow_m3_s
            continue
        j_s, j_i = fit.values(eps, beta)[0]
        out[i] = abs(omega * q0 * 0.5 * (1.0 + eps) - r * q0 * j_i), r * q0 * j_s
    return out


def relative_errors(pred, truth) -> dict:
    """Median, 95th percentile and maximum of |pred - truth| / |truth| per column."""
    e = np.abs(pred - truth) / np.abs(truth)
    return {"median": np.median(e, axis=0).tolist(), "p95": np.percentile(e, 95, axis=0).tolist(),
            "max": np.max(e, axis=0).tolist()}


def strided(states, n_max: int) -> np.ndarray:
    """At most ``n_max`` rows of ``states``, evenly strided (a series keeps its spread)."""
    states = np.asarray(states, float)
    if len(states) <= n_max:
        return states
    return states[np.linspace(0, len(states) - 1, n_max).round().astype(int)]


def ridge_fit(X, Y, w, k_folds: int, seed: int):
    """(coef (targets, features), lambdas, train rms per target) of the rows X, Y weighted by w."""
    X, Y = X * w[:, None], Y * w[:, None]
    lam = select_lambda(CrossValidation(X, Y, fold_indices(len(X), k_folds, seed)))["lam"]
    coef = RidgeSVD(X, Y).coef(lam).T
    return coef, tuple(float(v) for v in lam), np.sqrt(np.mean((X @ coef.T - Y) ** 2, axis=0))


def held_out_errors(fit, internal, test_states, omega: float) -> dict:
    """The fit's errors at ``test_states`` against ``internal``'s film reports (``relative_errors``)."""
    ts = np.asarray(test_states, float)
    truth = np.array([[(rep := internal.film_report(*s, omega)).inflow_m3_s, rep.side_flow_m3_s] for s in ts])
    rel = relative_errors(predicted_flows(fit, internal.params, ts, omega), truth)
    return {"n_test": int(len(ts)), **{f"test_rel_{k}": dict(zip(("inflow", "side_flow"), v)) for k, v in rel.items()}}


def grooved_problem(params) -> str:
    """Why a grooved or partial-arc bore gets no film fit ('' when it does): the grooved map's
    (``groovemap.map_geometry_problem``: a supply pressure, lobes)."""
    from ..internals.map.groovemap import map_geometry_problem

    return map_geometry_problem(params.geometry) or ""


def fit_grooved_film(internal, states, omega: float, *, test_states=None, degree: int = FILM_DEGREE,
                     harmonics: int = FILM_HARMONICS, phi_harmonics: int = GROOVED_PHI_HARMONICS, k_folds: int = 5,
                     seed: int = 0) -> GroovedFilmFit:
    """The film fit of a grooved or partial-arc bore to ``internal``'s (Reynolds) supply flows at
    ``states`` (M, 4) at ``omega``; its errors at ``test_states`` against its film reports."""
    params = internal.params
    why = grooved_problem(params)
    if why:
        raise ValueError(f"film fit: {why}")
    nf = (2 * phi_harmonics + 1) * n_features(degree, harmonics)
    if len(states) < 2 * nf:
        raise ValueError(f"film fit: {len(states)} training states for {nf} features per flow function; need at "
                         "least twice as many")
    data = grooved_flow_functions(internal, states, omega)
    X = grooved_features(data[:, 0], data[:, 1], data[:, 2], degree, harmonics, phi_harmonics)
    coef, lam, rms = ridge_fit(X, data[:, 4:], data[:, 3] / abs(omega), k_folds, seed)
    fit = GroovedFilmFit(degree, harmonics, phi_harmonics, params.geometry.supply_edges(), coef, lam)
    fit.errors = {"truth": type(internal).__name__, "n_train": int(len(states)),
                  "train_rms": dict(zip(fit.targets, rms.tolist())),
                  "train_rms_unit": "|omega| R L CR (the flows' unit)"}
    if test_states is not None and len(test_states):
        fit.errors.update(held_out_errors(fit, internal, test_states, omega))
    return fit


def fit_film(internal, states, omega: float, *, test_states=None, degree: int = FILM_DEGREE,
             harmonics: int = FILM_HARMONICS, k_folds: int = 5, seed: int = 0):
    """The film fit to the film reports of ``internal`` at ``states`` (M, 4) at ``omega``; its errors
    at ``test_states`` against the same internal's reports. A grooved or partial-arc bore:
    ``fit_grooved_film``."""
    params = internal.params
    if not params.geometry.is_full_bore:
        return fit_grooved_film(internal, states, omega, test_states=test_states, degree=degree,
                                harmonics=harmonics, k_folds=k_folds, seed=seed)
    states = np.asarray(states, float)
    if len(states) < 2 * n_features(degree, harmonics):
        raise ValueError(f"film fit: {len(states)} training states for {n_features(degree, harmonics)} features per "
                         "flow function; need at least twice as many")
    data = flow_functions(internal, states, omega)
    # r / |omega|: the rows in units of |omega| Q0
    coef, lam, rms = ridge_fit(features(data[:, 0], data[:, 1], degree, harmonics), data[:, 3:],
                               data[:, 2] / abs(omega), k_folds, seed)
    fit = FilmFit(degree, harmonics, coef, lam)
    fit.errors = {"truth": type(internal).__name__, "n_train": int(len(states)),
                  "train_rms": dict(zip(TARGETS, rms.tolist())),
                  "train_rms_unit": "|omega| R L CR (the flows' unit)"}
    if test_states is not None and len(test_states):
        fit.errors.update(held_out_errors(fit, internal, test_states, omega))
    return fit


def basis_for(n_states: int, phi_harmonics: int = 0) -> tuple[int, int] | None:
    """(degree, harmonics) of the film fit to ``n_states`` training states (a grooved bore's:
    ``phi_harmonics`` GROOVED_PHI_HARMONICS): FILM_DEGREE and FILM_HARMONICS, lowered by turns while the
    states are fewer than twice the features (down to 2 and 2); None when even those are too many."""
    degree, harmonics = FILM_DEGREE, FILM_HARMONICS
    while n_states < 2 * (2 * phi_harmonics + 1) * n_features(degree, harmonics):
        if degree == harmonics == 2:
            return None
        degree, harmonics = (degree - 1, harmonics) if degree >= harmonics else (degree, harmonics - 1)
    return degree, harmonics


def attach_film(res, truth, states, *, test_states=None, seed: int = 0, log=None) -> None:
    """Add the film fit to the FitResult ``res`` (``Surrogate.film``; the force untouched) from the
    film reports of the fit's truth (``film_truth``) at up to FILM_MAX_ROWS of its training
    ``states`` (``basis_for`` their number); ``res.report["film"]`` gets its errors, or why there
    is none."""
    sur = res.surrogate
    grooved = not sur.params.geometry.is_full_bore
    internal = film_truth(truth, grooved)
    why = grooved_problem(sur.params) if grooved else ""
    basis = basis_for(min(len(states), FILM_MAX_ROWS), GROOVED_PHI_HARMONICS if grooved else 0)
    if internal is None or why or basis is None:
        res.report["film"] = "none: " + ("the fit's truth has no film report" if internal is None else why
                                         if why else f"{len(states)} training states are too few")
        return
    train = strided(states, FILM_MAX_ROWS)
    test = None if test_states is None else strided(test_states, FILM_TEST_ROWS)
    if log is not None:
        log(f"film fit: the film reports of {type(internal).__name__} at {len(train)} states")
    sur.film = fit_film(internal, train, sur.omega, test_states=test, degree=basis[0], harmonics=basis[1], seed=seed)
    res.report["film"] = sur.film.errors


__all__ = ["GROOVED_PHI_HARMONICS", "fit_grooved_film", "grooved_flow_functions", "grooved_problem", "ridge_fit",
           "held_out_errors", "basis_for", "FILM_DEGREE", "FILM_HARMONICS", "FILM_MAX_ROWS", "attach_film", "fit_film", "film_truth",
           "flow_functions", "predicted_flows", "reduced_state", "relative_errors", "strided"]
