"""The Taylor internal behind its domain guard (``guard.DomainGuard``) as a compiled-force
kernel (``internals.compiled``), for states inside the fitted domain.

The kernel decides inside or outside as ``DomainGuard._select`` does (the bounds' distance,
then the nearest stored training state: within the radius of the one nearest to the previous
state, else the nearest of all, found by a scan) and, inside, evaluates the surrogate with the
same compiled code as ``Taylor.force_and_jacobian``. Outside (a warning, a fallback, a
refusal: the guard's business), at the wall or at another speed it answers status 1 and the
host asks the guard itself.

data layout (``pack``): head (HEAD: n_terms, n_shape_terms, n_points, radius, size, index of
the last nearest point (written by the kernel), CR^2, has shape columns), meta (11), dom (17),
exponents (n_terms x 4, int64 bits), coef (2 x n_terms), shape exponents (n_shape x 4, int64
bits), shape coef (4 x n_shape), points (n_points x 4).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc, njit

from ...surrogates.taylor_kernels import domain_distance_nb, force_jac_shape_si_nb, force_jac_si_nb
from ..compiled import KERNEL_SIG, advance, as_int64

HEAD = 8
N_META, N_DOM = 11, 17
INSIDE = 1e-12  # the guard's own threshold: d <= 1e-12 is inside (guard._select)


def pack(meta, dom, exps, coef, sexps, scoef, points, radius, size, cr2) -> np.ndarray:
    """The guarded surrogate as the float64 array ``taylor_kernel`` reads (``points`` None:
    no stored training states, the bounds alone)."""
    exps = np.ascontiguousarray(exps, dtype=np.int64)
    has_shape = sexps is not None
    sexps = np.ascontiguousarray(np.zeros((0, 4)) if sexps is None else sexps, dtype=np.int64)
    scoef = np.ascontiguousarray(np.zeros((4, 0)) if scoef is None else scoef, dtype=np.float64)
    points = np.zeros((0, 4)) if points is None else np.asarray(points, dtype=np.float64)
    head = [exps.shape[0], sexps.shape[0], points.shape[0], radius, size, -1.0, cr2, float(has_shape)]
    parts = [np.array(head, float), np.asarray(meta, float), np.asarray(dom, float), exps.view(np.float64).ravel(),
             np.asarray(coef, float).ravel(), sexps.view(np.float64).ravel(), scoef.ravel(), points.ravel()]
    return np.ascontiguousarray(np.concatenate(parts), dtype=np.float64)


@njit(cache=True)
def _inside(dp, head, dom, y, z, vy, vz):
    """The guard's verdict on the state: inside its fitted domain (d <= INSIDE)."""
    d = domain_distance_nb(y, z, vy, vz, dom)
    if d != d:
        return False
    npnt = int(head[2])
    if npnt == 0:
        return d <= INSIDE
    nt, nst = int(head[0]), int(head[1])
    pts = carray(advance(dp, HEAD + N_META + N_DOM + 6 * nt + 8 * nst), (npnt, 4))
    cr, vs = dom[2], dom[3]
    u0, u1, u2, u3 = (y - dom[0]) / cr, (z - dom[1]) / cr, vy / vs, vz / vs
    radius, size = head[3], head[4]
    last = int(head[5])
    if last >= 0:  # within the radius of the point nearest to the last state: inside (an upper bound)
        a, b, c, e = u0 - pts[last, 0], u1 - pts[last, 1], u2 - pts[last, 2], u3 - pts[last, 3]
        bound = math.sqrt(a * a + b * b + c * c + e * e)
        if bound <= radius:
            return max(d, (bound - radius) / size) <= INSIDE
    best = math.inf
    bi = -1
    for i in range(npnt):
        a, b, c, e = u0 - pts[i, 0], u1 - pts[i, 1], u2 - pts[i, 2], u3 - pts[i, 3]
        s = a * a + b * b + c * c + e * e
        if s < best:
            best = s
            bi = i
    head[5] = bi
    return max(d, (math.sqrt(best) - radius) / size) <= INSIDE


@cfunc(KERNEL_SIG, cache=True)
def taylor_kernel(dp, y, z, vy, vz, omega, op):
    """``internals.compiled`` kernel of the guarded Taylor surrogate; status 1 outside its
    fitted domain, at the wall, at another speed, or for a non-finite value."""
    head = carray(dp, HEAD)
    dom = carray(advance(dp, HEAD + N_META), N_DOM)
    if not _inside(dp, head, dom, y, z, vy, vz):
        return 1
    nt, nst = int(head[0]), int(head[1])
    meta = carray(advance(dp, HEAD), N_META)
    o = HEAD + N_META + N_DOM
    exps = carray(as_int64(advance(dp, o)), (nt, 4))
    coef = carray(advance(dp, o + 4 * nt), (2, nt))
    if head[7] != 0.0:
        sexps = carray(as_int64(advance(dp, o + 6 * nt)), (nst, 4))
        scoef = carray(advance(dp, o + 6 * nt + 4 * nst), (4, nst))
        code, F, dq, dv = force_jac_shape_si_nb(y, z, vy, vz, omega, meta, exps, coef, sexps, scoef)
    else:
        code, F, dq, dv = force_jac_si_nb(y, z, vy, vz, omega, meta, exps, coef)
    if code != 0 or not y * y + z * z < head[6]:
        return 1
    out = carray(op, 10)
    out[0] = F[0]
    out[1] = F[1]
    for i in range(2):
        for j in range(2):
            out[2 + 4 * i + j] = dq[i, j]
            out[4 + 4 * i + j] = dv[i, j]
    return 0
