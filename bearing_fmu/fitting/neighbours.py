"""The training states a surrogate file stores for the nearest-neighbour guard (``Neighbours``).

The domain guard (bearing_fmu.internals.taylor.guard) flags a state whose distance to the nearest stored
training state, in the scaled state space u = ((y - y0)/CR, (z - z0)/CR, vy/(omega CR),
vz/(omega CR)), exceeds a radius. Both are chosen here, from the training states alone, at fit
time:

* q, the ``QUANTILE`` (99 %) of the distances from each row held out by the fit's
  cross-validation folds to the nearest row of the other folds: the distances at which
  cross-validation tested the fit (for a time series the folds are blocks of a few
  revolutions, so q is the gap between neighbouring orbit passes and trajectories; for a
  designed sample, the spacing of its points).
* points: farthest-point thinning of the training states in u (start at the state farthest
  from their mean, then repeatedly add the state farthest from those chosen) until every
  training state lies within ``COVER_FRACTION`` q (a quarter) of a chosen one, or
  ``MAX_POINTS`` are chosen; rounded to ``DECIMALS`` decimals (1e-4 CR, 9 nm on the paper
  bearing). c, the covering radius, is measured after rounding. Farthest-point thinning keeps
  the rare states (a transient's first swing) that a random subset would drop.
* radius = q + c: a state within q of the training states is within q + c of the stored
  ones. Never below ``MIN_RADIUS``. This is r_cv, the data's spacing; the guard widens it
  to r_lin where the fit checks out farther (bearing_fmu.guard.linear_radius, at load).

On the shipped files the rule puts every state of the held-out trajectories at 22 and 44 Hz
inside and (0, -0.5 CR, 0, 0) at 22 Hz 4x the radius away (docs/studies/2026-11-24-nearest-neighbour-guard.md).
"""

from __future__ import annotations

import math

import numpy as np

from ..surrogates.surrogate import Neighbours

MAX_POINTS = 2000  # stored points at most (~80 kB of JSON)
COVER_FRACTION = 0.25  # thinning stops once the chosen points cover the training states to this fraction of q
DECIMALS = 4  # stored coordinates rounded to 1e-4 in u
QUANTILE = 0.99  # of the cross-validation held-out rows' nearest-neighbour distances
MIN_RADIUS = 1e-3  # in u: a floor for degenerate data (all rows alike)

RULE = (f"radius = {QUANTILE:g} quantile of the distance (in u) from each cross-validation held-out row to the "
        "nearest row of the other folds (the distances at which cross-validation tested the fit) + "
        "covering_radius (every training state lies within it of a stored point)")


def farthest_points(u: np.ndarray, n_max: int, cover: float = 0.0) -> np.ndarray:
    """Indices of rows of ``u`` (M, 4) by farthest-point thinning, starting at the row farthest
    from the mean, until every row lies within ``cover`` of a chosen one or ``n_max`` are
    chosen. Deterministic."""
    u = np.asarray(u, float)
    centred = u - u.mean(axis=0)
    idx = [int(np.argmax(np.einsum("ij,ij->i", centred, centred)))]
    diff = u - u[idx[0]]
    d2 = np.einsum("ij,ij->i", diff, diff)  # squared distance of each row to the nearest chosen one
    while len(idx) < min(n_max, len(u)):
        j = int(np.argmax(d2))
        if d2[j] <= cover * cover:
            break
        idx.append(j)
        diff = u - u[j]
        np.minimum(d2, np.einsum("ij,ij->i", diff, diff), out=d2)
    return np.array(idx, np.int64)


def held_out_distances(u: np.ndarray, folds) -> np.ndarray:
    """(M,): the distance of each row to the nearest row outside its cross-validation fold."""
    from scipy.spatial import cKDTree

    u = np.asarray(u, float)
    dist = np.full(len(u), np.nan)
    for test in folds:
        train = np.ones(len(u), bool)
        train[test] = False
        if train.any() and len(test):
            dist[test] = cKDTree(u[train]).query(u[test])[0]
    return dist


def neighbours_for_fit(u: np.ndarray, folds, n_max: int = MAX_POINTS) -> Neighbours:
    """The stored training states and their radius (see the module doc) for a fit to the
    scaled training states ``u`` (M, 4) with cross-validation ``folds`` (index arrays)."""
    from scipy.spatial import cKDTree

    u = np.asarray(u, float)
    cv = held_out_distances(u, folds)
    cv = cv[np.isfinite(cv)]
    q = float(np.quantile(cv, QUANTILE)) if len(cv) else 0.0
    chosen = farthest_points(u, n_max, COVER_FRACTION * q)
    points = np.unique(np.round(u[chosen], DECIMALS), axis=0) + 0.0  # + 0.0: no -0.0 in the file
    cover = float(cKDTree(points).query(u)[0].max())
    radius = max(q + cover, MIN_RADIUS)
    info = {
        "rule": RULE,
        "n_training": int(len(u)),
        "covering_radius": round(cover, 6),
        "cv_distance": {f"q{round(100 * p)}": round(float(np.quantile(cv, p)), 6) if len(cv) else None
                        for p in (0.5, 0.9, QUANTILE)} | {"max": round(float(cv.max()), 6) if len(cv) else None},
        "thinning": f"farthest-point thinning of the training states in u until they lie within "
                    f"{COVER_FRACTION:g} x the q{round(100 * QUANTILE)} cv_distance of a chosen one or {n_max} are "
                    f"chosen; rounded to {DECIMALS} decimals",
    }
    return Neighbours(points, math.ceil(radius * 1e6) / 1e6, info)


__all__ = ["neighbours_for_fit", "farthest_points", "held_out_distances", "MAX_POINTS", "COVER_FRACTION", "DECIMALS",
           "QUANTILE", "MIN_RADIUS", "RULE"]
