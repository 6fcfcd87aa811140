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
"""

from __future__ import annotations

import math

import numpy as np

from ..physics.film import flow_scale, reduced_flows
from ..surrogates.film import TARGETS, FilmFit, features, n_features
from .ridge import CrossValidation, RidgeSVD, fold_indices, select_lambda

FILM_DEGREE = 6  # eps^0 .. eps^6
FILM_HARMONICS = 6  # 1, cos beta, sin beta .. cos 6 beta, sin 6 beta: 7 x 13 = 91 features
FILM_MAX_ROWS = 3000  # training states whose film is computed at most (each two truth solves)
FILM_TEST_ROWS = 300  # held-out states at most for the recorded errors
NO_BORE_WHY = ("the surrogate's bore is not the full circle: the flows' reduction to (eps, beta) assumes it "
               "(grooves and arcs fix directions), so it has no film fit")


def film_truth(truth):
    """The internal whose film reports a fit's film fit follows: the samples' truth when it has the
    film's flows (Reynolds, a map with flow tables), else the statics' (Reynolds); None if neither."""
    for internal in (truth.samples, truth.statics):
        if getattr(internal, "film_report", None) is not None and not getattr(internal, "film_flow_why", ""):
            return internal
    return None


def reduced_state(params, y, z, vy, vz, omega: float):
    """(eps, beta, r, phi) of a state: the map's coordinates (``forcemap.reduced``)."""
    from ..internals.forcemap import reduced

    eps, phi, a, c = reduced(y, z, vy, vz, omega, params.CR)
    return eps, math.atan2(c, a), math.hypot(a, c), phi


def flow_functions(internal, states, omega: float) -> np.ndarray:
    """(M, 5): eps, beta, r [1/s], J_s, J_i at each state (M, 4) [m, m/s] from the film reports of
    ``internal`` at omega and 2 omega with the same eps, beta, r and attitude (``reduced_flows``)."""
    from ..internals.forcemap import EPS_MIN, state_for

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


def predicted_flows(fit: FilmFit, params, states, omega: float) -> np.ndarray:
    """(M, 2): inflow, side flow [m^3/s] of the film fit at states (M, 4) (``film.reduced_report``'s)."""
    q0 = flow_scale(params)
    out = np.empty((len(states), 2))
    for i, s in enumerate(np.asarray(states, float)):
        eps, beta, r, _phi = reduced_state(params, *s, omega)
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


def fit_film(internal, states, omega: float, *, test_states=None, degree: int = FILM_DEGREE,
             harmonics: int = FILM_HARMONICS, k_folds: int = 5, seed: int = 0) -> FilmFit:
    """The film fit to the film reports of ``internal`` (a full bore) at ``states`` (M, 4) at
    ``omega``; its errors at ``test_states`` against the same internal's reports."""
    params = internal.params
    if not params.geometry.is_full_bore:
        raise ValueError(f"film fit: {NO_BORE_WHY}")
    states = np.asarray(states, float)
    if len(states) < 2 * n_features(degree, harmonics):
        raise ValueError(f"film fit: {len(states)} training states for {n_features(degree, harmonics)} features per "
                         "flow function; need at least twice as many")
    data = flow_functions(internal, states, omega)
    w = data[:, 2] / abs(omega)  # r / |omega|: the rows in units of |omega| Q0
    X = features(data[:, 0], data[:, 1], degree, harmonics) * w[:, None]
    Y = data[:, 3:] * w[:, None]
    lam = select_lambda(CrossValidation(X, Y, fold_indices(len(X), k_folds, seed)))["lam"]
    coef = RidgeSVD(X, Y).coef(lam).T
    fit = FilmFit(degree, harmonics, coef, tuple(float(v) for v in lam))
    rms = np.sqrt(np.mean((X @ coef.T - Y) ** 2, axis=0))
    fit.errors = {"truth": type(internal).__name__, "n_train": int(len(states)),
                  "train_rms": dict(zip(TARGETS, rms.tolist())),
                  "train_rms_unit": "|omega| R L CR (the flows' unit)"}
    if test_states is not None and len(test_states):
        ts = np.asarray(test_states, float)
        truth = np.array([[(rep := internal.film_report(*s, omega)).inflow_m3_s, rep.side_flow_m3_s] for s in ts])
        rel = relative_errors(predicted_flows(fit, params, ts, omega), truth)
        fit.errors.update({"n_test": int(len(ts)),
                           **{f"test_rel_{k}": dict(zip(("inflow", "side_flow"), v)) for k, v in rel.items()}})
    return fit


def basis_for(n_states: int) -> tuple[int, int] | None:
    """(degree, harmonics) of the film fit to ``n_states`` training states: FILM_DEGREE and
    FILM_HARMONICS, lowered by turns while the states are fewer than twice the features (down to
    2 and 2); None when even those are too many."""
    degree, harmonics = FILM_DEGREE, FILM_HARMONICS
    while n_states < 2 * n_features(degree, harmonics):
        if degree == harmonics == 2:
            return None
        degree, harmonics = (degree - 1, harmonics) if degree >= harmonics else (degree, harmonics - 1)
    return degree, harmonics


def attach_film(res, truth, states, *, test_states=None, seed: int = 0, log=None) -> None:
    """Add the film fit to the FitResult ``res`` (``Surrogate.film``; the force untouched) from the
    film reports of the fit's truth (``film_truth``) at up to FILM_MAX_ROWS of its training
    ``states`` (``basis_for`` their number); ``res.report["film"]`` gets its errors, or why there
    is none."""
    internal = film_truth(truth)
    sur = res.surrogate
    basis = basis_for(min(len(states), FILM_MAX_ROWS))
    if internal is None or not sur.params.geometry.is_full_bore or basis is None:
        res.report["film"] = "none: " + ("the fit's truth has no film report" if internal is None else NO_BORE_WHY
                                         if basis is not None else f"{len(states)} training states are too few")
        return
    train = strided(states, FILM_MAX_ROWS)
    test = None if test_states is None else strided(test_states, FILM_TEST_ROWS)
    if log is not None:
        log(f"film fit: the film reports of {type(internal).__name__} at {len(train)} states")
    sur.film = fit_film(internal, train, sur.omega, test_states=test, degree=basis[0], harmonics=basis[1], seed=seed)
    res.report["film"] = sur.film.errors


__all__ = ["basis_for", "FILM_DEGREE", "FILM_HARMONICS", "FILM_MAX_ROWS", "NO_BORE_WHY", "attach_film", "fit_film", "film_truth",
           "flow_functions", "predicted_flows", "reduced_state", "relative_errors", "strided"]
