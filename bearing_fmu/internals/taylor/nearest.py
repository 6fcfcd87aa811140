"""The nearest-neighbour part of the Taylor surrogate's fitted domain: how far a journal state
lies from the training states its file stores, and the radius within which the fit is trusted
(r_lin: how far it agrees with its own linear extrapolation from those states). Used by the
``Taylor`` internal (``domain_distance``) and its ``DomainGuard``; this module imports neither.
"""

from __future__ import annotations

import math

import numpy as np

TOLERANCE = 0.05  # r_lin: the fit's departure from its linear extrapolation, relative to max(|F|, static force)
LIN_POINTS = 16  # r_lin: rays from this many stored states (evenly spaced in the file's order) ...
LIN_DIRECTIONS = 8  # ... in as many fixed random directions of u ...
LIN_MAX = 2.0  # ... probed at distances doubling from a start up to this (in u)


def _directions(n: int) -> np.ndarray:
    """n fixed unit vectors of u, isotropic (the same every time: r_lin is a property of the file)."""
    v = np.random.default_rng(0).normal(size=(n, 4))
    return v / np.linalg.norm(v, axis=1)[:, None]


DIRECTIONS = _directions(LIN_DIRECTIONS)


def linear_radius(taylor, points: np.ndarray, start: float = 1e-3, tol: float = TOLERANCE) -> float:
    """max(start, r_lin). r_lin: the median, over rays from LIN_POINTS of the stored training
    states ``points`` (in u) in LIN_DIRECTIONS fixed directions, of the distance in u at which
    the fit departs from its first-order extrapolation from the ray's start p by ``tol``:

        |F(x) - F(p) - J(p) (x - p)| / max(|F(x)|, |F(y0, z0, 0, 0)|) = tol.

    Each ray is probed at start, 2 start, 4 start, ... up to LIN_MAX, the crossing interpolated
    in log-log (exact for a power law); a ray that departs at ``start`` already, or reaches the
    wall, counts as crossing there, so the guard (start = r_cv) pays one call for most rays of a
    file whose r_lin is below r_cv. At a training state the fit is right; from its own
    first-order extrapolation the truth differs by its curvature only, so this departure is the
    fit's error where the truth is nearly linear and overstates it where it bends: the median
    crossing is where a state in a random direction becomes more likely wrong than right, or
    before. 128 rays, at most ~1000 compiled force calls: a few ms."""
    s = taylor.surrogate
    om, cr2 = s.omega, s.params.CR ** 2
    scale = (s.pos_scale, s.pos_scale, s.vel_scale, s.vel_scale)
    fref = max(math.hypot(*taylor.force(s.y0, s.z0, 0.0, 0.0, om)), 1e-12 * s.force_scale)
    steps = [start * 2.0 ** k for k in range(64) if start * 2.0 ** k < LIN_MAX] + [LIN_MAX]
    idx = np.unique(np.linspace(0, len(points) - 1, min(LIN_POINTS, len(points))).round().astype(int))
    rays = DIRECTIONS * scale  # the directions in raw units
    crossings = []
    for p in points[idx]:
        x0 = (s.y0 + p[0] * scale[0], s.z0 + p[1] * scale[1], p[2] * scale[2], p[3] * scale[3])
        if x0[0] ** 2 + x0[1] ** 2 >= cr2:
            continue
        F0, dq, dv = taylor.force_and_jacobian(*x0, om)
        slopes = (rays @ np.hstack([dq, dv]).T).tolist()  # J(p) dx per ray
        for dx, (jy, jz) in zip(rays.tolist(), slopes):
            last, w_last, cross = start, 0.0, LIN_MAX
            for r in steps:
                y, z = x0[0] + r * dx[0], x0[1] + r * dx[1]
                if y * y + z * z >= cr2:
                    cross = last
                    break
                fy, fz = taylor.force(y, z, x0[2] + r * dx[2], x0[3] + r * dx[3], om)
                w = math.hypot(fy - F0[0] - r * jy, fz - F0[1] - r * jz) / max(math.hypot(fy, fz), fref)
                if not w < tol:  # NaN too
                    ok = w_last > 0.0 and math.isfinite(w) and w > w_last
                    cross = last * (r / last) ** (math.log(tol / w_last) / math.log(w / w_last)) if ok else last
                    break
                last, w_last = r, w
            crossings.append(cross)
    return max(start, float(np.median(crossings))) if crossings else start


class NearestTraining:
    """Distance of a journal state to the nearest training state a surrogate file stores
    (``Surrogate.neighbours``: points in the scaled state space u, and their spacing r_cv).

    nn is the Euclidean distance in u = ((y - y0)/CR, (z - z0)/CR, vy/(omega CR), vz/(omega CR))
    to the nearest stored point; ``distance`` = (nn - radius) / size: <= 0 within the radius
    of a stored state, and beyond it the excess as a fraction of the fitted domain's size (half
    the diagonal of its bounding box in u, or the radius if that is larger), the way the
    bounds' part measures its excess relative to each bound's size. So d = 0.5 (the default
    domain_limit) is half the domain's size beyond the radius: the radius flags a state off the
    training orbits, the limit refuses one far from them.

    radius = max(``cv_radius``, r_lin): the file's r_cv and the distance over which the fit
    agrees with its own extrapolation from its training states (``linear_radius`` of
    ``taylor``, the Taylor internal of this file). ``widening`` =
    radius - r_cv: how far r_lin carries the fit beyond the training states' spacing (the
    bounds widen by it too).

    One scipy cKDTree query (~10 us). The guard, which needs the exact value only outside,
    skips it (``exact=False``) when the state lies within the radius of the stored point
    nearest to the previous state queried: then nn <= that distance <= radius, the state is
    inside, and that bound gives a result <= 0 (~1.5 us; successive evaluations of a run lie
    close together). So its result is exact when > 0, an upper bound when <= 0.
    """

    def __init__(self, surrogate, taylor):
        from scipy.spatial import cKDTree

        nb = surrogate.neighbours
        if nb is None:
            raise ValueError("NearestTraining: the surrogate stores no training states (key 'neighbours')")
        self.cv_radius = nb.radius
        self.radius = linear_radius(taylor, nb.points, start=nb.radius)
        self.widening = self.radius - self.cv_radius
        d = surrogate.domain
        # against a box much smaller than the radius (thin orbits, one state) the default limit
        # would refuse a state a hair beyond the radius: the excess is in the larger of the two
        self.size = max(0.5 * math.dist(d.box_lo, d.box_hi), self.radius)
        self.points = nb.points
        self._rows = [tuple(map(float, row)) for row in nb.points]
        self._tree = cKDTree(nb.points)
        self._shift = (surrogate.y0, surrogate.z0)
        self._scale = (surrogate.pos_scale, surrogate.vel_scale)
        self._last = None  # the stored point nearest to the last state queried
        self.queries = 0  # KD-tree queries so far (benchmarks/bench_guard.py reports the share skipped)

    def scaled(self, y: float, z: float, vy: float, vz: float) -> tuple[float, float, float, float]:
        """The state in u (see the class doc)."""
        cr, vs = self._scale
        return (y - self._shift[0]) / cr, (z - self._shift[1]) / cr, vy / vs, vz / vs

    def nearest(self, y: float, z: float, vy: float, vz: float) -> tuple[float, np.ndarray]:
        """(nn, the nearest stored point in u): one exact KD-tree query."""
        nn, i = self._tree.query(self.scaled(y, z, vy, vz))
        self.queries += 1
        self._last = self._rows[i]
        return float(nn), self.points[i]

    def distance(self, y: float, z: float, vy: float, vz: float, exact: bool = True) -> float:
        """(nn - radius) / size. ``exact=False`` (the guard, at every evaluation) may skip the
        query for a state inside: the result is then an upper bound <= 0 (see the class doc)."""
        if not exact and self._last is not None:
            bound = math.dist(self.scaled(y, z, vy, vz), self._last)
            if bound <= self.radius:
                return (bound - self.radius) / self.size
        return (self.nearest(y, z, vy, vz)[0] - self.radius) / self.size


__all__ = ["NearestTraining", "linear_radius", "DIRECTIONS", "TOLERANCE"]
