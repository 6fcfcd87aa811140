"""The damped modes of a rotor on linear bearings in a frequency band, at any size.

``Rotor.modes`` solves the whole state-space eigenproblem densely: 2n x 2n, every mode. That is
right for the bundled rotors (44 DOFs: milliseconds) and impossible for a 2000-element shaft
(n = 8004: a 16 008 x 16 008 dense matrix, 2 GB, hours); it is also one LAPACK call, which Python
cannot interrupt: 0.6 s at 300 DOFs, 1.7 s at 400, 10 s at 1000 (one BLAS thread, a loaded
2-core machine; with OpenBLAS's default threads 5-31 s at 300-1000). Above
``DENSE_MODES_MAX_DOF`` DOFs ``band_modes`` finds only the modes around the band of interest
with ARPACK in shift-invert mode on the sparse matrices (0.02-0.07 s at 300-1000 DOFs):

  lambda^2 M x + lambda C x + K x = 0,  z = (x, lambda x):  A z = lambda B z,
  A = [[0, I], [-K, -C]], B = [[I, 0], [0, M]],

  (A - sigma B)^-1 B z = z / (lambda - sigma),

where applying (A - sigma B)^-1 B takes one solve with the n x n sparse complex matrix
D(sigma) = K + sigma C + sigma^2 M (x = -D^-1 (M w2 + (C + sigma M) w1), y = w1 + sigma x),
factorised once (LAPACK's banded LU: a shaft's D is banded, half-bandwidth 7; SuperLU for a wide
band). ARPACK's largest |1 / (lambda - sigma)| are the eigenvalues nearest sigma; the number
asked for starts from the disk's count without damping (Sylvester's inertia, ``_undamped_count``)
and doubles until one found lies beyond the disk |lambda - sigma| <= R, so every eigenvalue
inside the disk is found. ARPACK runs with one BLAS thread (``one_blas_thread``). The disk: sigma = i w_b / 2,
R = 8 w_b for the band's top w_b = 2 pi up_to_hz: every mode with damped frequency in (0, w_b]
and |Re(lambda)| up to 7.98 w_b, so every mode of the band whose log decrement is below
2 pi 7.98 = 50 (amplification factor 0.06) and most heavier ones, the modes a stability analysis
ranks (``analyses.linear.modal``: up to 2 x the top speed); modes of the disk above the band
come too. Modes outside the disk (far above the band, or overdamped ones far to the left) are
not returned.

The same filters as ``Rotor.modes`` follow (oscillatory: Im(lambda) > 1e-3 |lambda|; rigid-body
zeros dropped) and the same normalisation (each shape's largest entry 1), so in the band the
two paths give the same modes to round-off (tests/test_band_modes.py).

Cost per speed of a 2000-element shaft (8004 DOFs, band 48 Hz; 2 cores at load 8, side by side,
benchmarks/bench_band_modes.py): 0.4-0.6 s; with SuperLU, OpenBLAS's default threads and a first
count of 16 doubled to 32, 9-11 s (one thread: 1.0-1.3 s, and the banded LU: 0.8-0.95 s).
"""

from __future__ import annotations

import contextlib
import functools
import math
import threading
from pathlib import Path

import numpy as np

from .assembly import DENSE_MAX_DOF
from .eigen import OSCILLATORY, modal_table
from .rotor import Rotor

FIRST_K = 16  # eigenvalues asked of ARPACK at first when _undamped_count cannot count them; doubled until the disk is covered
DISK_RADIUS = 8.0  # R / w_b
ZERO_REL = 1e-6  # |lambda| below this times the highest element frequency: a rigid-body zero
BAND_MAX = 64  # D(sigma) of a half-bandwidth up to this: banded LU (LAPACK), else SuperLU
# every mode, densely, up to this (module docstring: within about a second); never above the
# size where the matrices themselves turn sparse
DENSE_MODES_MAX_DOF = min(300, DENSE_MAX_DOF)

__all__ = ["band_modes", "band_modes_with_pads", "DISK_RADIUS", "DENSE_MODES_MAX_DOF"]


def band_modes(rotor: Rotor, speed: float, bearing_K=None, bearing_C=None, up_to_hz: float = math.inf, *,
               sparse: bool | None = None):
    """(freq_hz, log_dec, shapes) of the damped modes as ``Rotor.modes`` returns them, at
    ``speed`` [rad/s] with the bearings' Lund ``bearing_K`` [N/m] and ``bearing_C`` [N s/m] (one
    2x2, or one per bearing). Up to DENSE_MODES_MAX_DOF DOFs (``sparse`` None or False): every mode,
    ``Rotor.modes`` itself (on one BLAS thread); above (or ``sparse=True``): the modes in the disk
    about the band up to ``up_to_hz`` [Hz] (module docstring), which must then be finite and > 0."""
    if not (sparse if sparse is not None else rotor.n_dof > DENSE_MODES_MAX_DOF):
        with one_blas_thread():
            return rotor.modes(speed, bearing_K, bearing_C)
    if not (math.isfinite(up_to_hz) and up_to_hz > 0.0):
        raise ValueError(f"band_modes: a rotor of {rotor.n_dof} DOFs is solved in a band; up_to_hz = {up_to_hz!r} "
                         "must be a finite frequency > 0 Hz")
    M, K, C = _system(rotor, speed, bearing_K, bearing_C)
    wb = 2.0 * math.pi * up_to_hz
    sigma, radius = 0.5j * wb, DISK_RADIUS * wb
    lam, z = _nearest(M, K, C, sigma, radius)
    return _table(lam, z[:rotor.n_dof], sigma, radius, ZERO_REL * _highest_frequency(M, K))


def _table(lam, x, sigma: complex, radius: float, zero: float):
    """``modal_table`` of the disk's modes that ``Rotor.modes`` keeps (oscillatory, not a rigid-body
    zero: |lambda| >= ``zero``), x their shapes (n x k)."""
    keep = (np.abs(lam - sigma) <= radius) & (lam.imag > OSCILLATORY * np.abs(lam)) & (np.abs(lam) >= zero)
    return modal_table(lam[keep], x[:, keep])


def band_modes_with_pads(rotor: Rotor, speed: float, blocks, up_to_hz: float):
    """``band_modes`` for bearings with coordinates of their own (tilting pads): what
    ``analyses.linear.pad_modes.modes`` gives densely, for the disk about the band up to
    ``up_to_hz`` [Hz] (module docstring). ``blocks``: one per bearing, each with ``dofs`` (its
    journal's y, z DOF indices), ``K``, ``C`` ((2 + N) x (2 + N), Lund's signs), ``inertia`` (N,)
    and ``live()`` (``pad_modes.PadBlock``).

    The equations of ``pad_modes.state_matrix`` in descriptor form B X' = A X, nothing inverted,
    X = (q, v = q', p), p = (massless tilts, tilts with inertia, their rates):
      q' = v;   M v' + B_vp p' = -Kt q - Ct v + A_vp p;   B_pp p' = A_pq q + A_pv v + A_pp p
    (a massless pad: C_pp delta' = -(K_pj q_j + C_pj v_j + K_pp delta), its C_jp delta' in the
    journal's row; a pad with inertia: delta' = rate, I rate' = -(... + C_pp rate); a bearing's own
    coordinates coupled among themselves, a flexible pivot's tilt and radial displacement: their
    K_pd, C_pd in App and Bpp as pad_modes._descriptor has them). Shift-invert,
    (A - sigma B) X = B w, with v = w_q + sigma q eliminated: the (n + N_p) square
      [[-D(sigma), A_vp - sigma B_vp], [A_pq + sigma A_pv, A_pp - sigma B_pp]] (q, p)
        = (M w_v + B_vp w_p + (Ct + sigma M) w_q, B_pp w_p - A_pv w_q)
    factorised once by SuperLU (the rotor's rows scaled as D(sigma) is, not as the 1 of q' = v).
    The same filters and normalisation follow. A 2000-element shaft on the bundled five-pad
    bearings: 0.4-0.7 s a speed (2 cores, load 7-8); at 300 elements 0.12-0.18 s, where the dense
    path took 54-165 s (38-44 s with one BLAS thread), growing as n^3: hours and GBs at 2000
    (benchmarks/bench_band_modes.py --pads)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    if not (math.isfinite(up_to_hz) and up_to_hz > 0.0):
        raise ValueError(f"band_modes_with_pads: up_to_hz = {up_to_hz!r} must be a finite frequency > 0 Hz")
    M, K, G, C = rotor.sparse()
    n = rotor.n_dof
    Kt, Ct = _journal_blocks(K, blocks, "K"), _journal_blocks(C + speed * G, blocks, "C")
    pads = [(blk, int(k)) for blk in blocks for k in blk.live() if blk.inertia[k] <= 0.0]  # massless first
    pads += [(blk, int(k)) for blk in blocks for k in blk.live() if blk.inertia[k] > 0.0]
    nm = sum(blk.inertia[k] <= 0.0 for blk, k in pads)
    ni = len(pads) - nm
    npad = nm + 2 * ni
    parts = {name: ([], [], []) for name in ("Avp", "Bvp", "Apq", "Apv", "App", "Bpp")}

    def put(name, i, j, v):
        parts[name][0].append(i)
        parts[name][1].append(j)
        parts[name][2].append(v)

    index = {(id(blk), k): r for r, (blk, k) in enumerate(pads)}
    for r, (blk, k) in enumerate(pads):
        c, j = 2 + k, blk.dofs
        tilt, rate = r, (r + ni if r >= nm else None)  # a pad with inertia: its rate ni rows after its tilt
        for d in blk.live():  # coordinates of one bearing coupled among themselves (a flexible pivot)
            r2 = index[(id(blk), int(d))]
            if int(d) == k or (blk.K[c, 2 + d] == 0.0 and blk.C[c, 2 + d] == 0.0):
                continue
            row, rate2 = (rate if rate is not None else tilt), (r2 + ni if r2 >= nm else None)
            put("App", row, r2, -blk.K[c, 2 + d])
            if rate2 is None:
                put("Bpp", row, r2, blk.C[c, 2 + d])
            else:
                put("App", row, rate2, -blk.C[c, 2 + d])
        for a in range(2):
            put("Avp", j[a], tilt, -blk.K[a, c])
            put("Apq", rate if rate is not None else tilt, j[a], -blk.K[c, a])
            put("Apv", rate if rate is not None else tilt, j[a], -blk.C[c, a])
            if rate is None:
                put("Bvp", j[a], tilt, blk.C[a, c])
            else:
                put("Avp", j[a], rate, -blk.C[a, c])
        if rate is None:
            put("Bpp", tilt, tilt, blk.C[c, c])
            put("App", tilt, tilt, -blk.K[c, c])
        else:
            put("Bpp", tilt, tilt, 1.0)
            put("App", tilt, rate, 1.0)
            put("Bpp", rate, rate, blk.inertia[k])
            put("App", rate, tilt, -blk.K[c, c])
            put("App", rate, rate, -blk.C[c, c])
    shapes = {"Avp": (n, npad), "Bvp": (n, npad), "Apq": (npad, n), "Apv": (npad, n), "App": (npad, npad),
              "Bpp": (npad, npad)}
    P = {name: sp.csr_matrix((np.array(x, float), (np.array(i, int), np.array(j, int))), shape=shapes[name])
         for name, (i, j, x) in parts.items()}
    wb = 2.0 * math.pi * up_to_hz
    sigma, radius = 0.5j * wb, DISK_RADIUS * wb
    S = sp.bmat([[-(Kt + sigma * Ct + sigma ** 2 * M), P["Avp"] - sigma * P["Bvp"]],
                 [P["Apq"] + sigma * P["Apv"], P["App"] - sigma * P["Bpp"]]], format="csc").astype(complex)
    solve = sla.splu(S).solve
    CsM, Bvp, Bpp, Apv = (Ct + sigma * M).astype(complex), P["Bvp"], P["Bpp"], P["Apv"]

    def op(w):
        w = np.asarray(w).reshape(-1)
        wq, wv, wp = w[:n], w[n:2 * n], w[2 * n:]
        qp = solve(np.concatenate([M @ wv + Bvp @ wp + CsM @ wq, Bpp @ wp - Apv @ wq]))
        return np.concatenate([qp[:n], wq + sigma * qp[:n], qp[n:]])

    count = _undamped_count(M, Kt, sigma, radius)  # the shaft's, and each pad coordinate may add one in the disk
    lam, z = _arpack(op, 2 * n + npad, sigma, radius, None if count is None else count + npad)
    return _table(lam, z[:n], sigma, radius, ZERO_REL * _highest_frequency(M, Kt))


def _journal_blocks(A, blocks, which: str):
    """A (the shaft's K, or its C + speed G) with each bearing's journal 2 x 2 of ``which`` added."""
    import scipy.sparse as sp

    rows, cols, vals = [], [], []
    for blk in blocks:
        for a in range(2):
            for b in range(2):
                rows.append(blk.dofs[a])
                cols.append(blk.dofs[b])
                vals.append(getattr(blk, which)[a, b])
    return (A + sp.csr_matrix((vals, (rows, cols)), shape=A.shape)).tocsr()


def _system(rotor: Rotor, speed: float, bearing_K, bearing_C):
    """(M, K_total, C_total) as CSC matrices: the shaft's with the bearings' 2x2 blocks added and
    the gyroscopic term speed * G in the damping, as ``Rotor.modes`` builds them densely."""
    import scipy.sparse as sp

    M, K, G, C = rotor.sparse()
    nb = len(rotor.bearing_nodes)
    rows, cols = [], []
    for node in rotor.bearing_nodes:
        idx = [rotor.dof(node, "y"), rotor.dof(node, "z")]
        rows += [idx[0], idx[0], idx[1], idx[1]]
        cols += [idx[0], idx[1], idx[0], idx[1]]

    def blocks(value):
        a = np.zeros((nb, 2, 2)) if value is None else np.broadcast_to(np.asarray(value, dtype=float), (nb, 2, 2))
        return sp.csc_matrix((a.reshape(-1), (rows, cols)), shape=K.shape)

    return (M.tocsc(), (K + blocks(bearing_K)).tocsc(), (C + blocks(bearing_C) + speed * G).tocsc())


def _nearest(M, K, C, sigma: complex, radius: float):
    """Eigenvalues lambda and state vectors z (2n x k) nearest ``sigma``, every one within
    ``radius`` of it (fewer only when ARPACK's limit of 2n - 2 is reached)."""
    n = K.shape[0]
    solve = _factorised((K + sigma * C + sigma ** 2 * M).astype(complex), f"K + s C + s^2 M at the shift s = {sigma:g}")
    CsM = (C + sigma * M).astype(complex).tocsr()
    Mr = M.tocsr()

    def op(w):
        w = np.asarray(w).reshape(-1)
        x = -solve(Mr @ w[n:] + CsM @ w[:n])
        return np.concatenate([x, w[:n] + sigma * x])

    return _arpack(op, 2 * n, sigma, radius, _undamped_count(M, K, sigma, radius))


def _arpack(op, size: int, sigma: complex, radius: float, count: int | None):
    """ARPACK's eigenvalues 1 / (lambda - sigma) of the shift-invert operator ``op`` (size x size),
    as (lambda, vectors): its first count ``count`` plus a margin for damping's moves (FIRST_K
    without a count), doubled until one lies beyond the disk (or ARPACK's limit size - 2)."""
    import scipy.sparse.linalg as sla

    A = sla.LinearOperator((size, size), matvec=op, dtype=complex)
    v0 = np.ones(size, dtype=complex)  # a fixed start: the same modes every run
    k = min(FIRST_K if count is None else count + 4 + count // 4, size - 2)
    with one_blas_thread():
        while True:
            mu, z = sla.eigs(A, k=k, which="LM", v0=v0, tol=0.0)
            lam = sigma + 1.0 / mu
            if np.max(np.abs(lam - sigma)) > radius or k >= size - 2:
                return lam, z
            k = min(2 * k, size - 2)


def _undamped_count(M, K, sigma: complex, radius: float) -> int | None:
    """How many eigenvalues the disk holds without damping and gyroscopics (ARPACK's first count).

    Undamped, the eigenvalues are +-i w_j, w_j^2 those of (K_s, M) with K_s = (K + K^T) / 2; +i w_j
    lies in the disk for w_j <= Im(sigma) + R, -i w_j for w_j <= R - Im(sigma). How many w_j lie
    below a w is Sylvester's count of negative pivots of K_s - w^2 M (M positive definite),
    eliminated in the natural order (``integrate.banded.band_lu``: banded, O(n w^2)). Damping and
    the gyroscopic term move the modes a little; the doubling in ``_nearest`` covers what the
    count misses. None when a pivot vanishes or the band is wide."""
    from ..integrate.banded import band_lu, bandwidth, to_band

    Ks = 0.5 * (K + K.T)
    w = bandwidth(Ks, M)
    if w > BAND_MAX:
        return None
    count = 0
    for reach in (sigma.imag + radius, radius - sigma.imag):
        if reach > 0.0:
            B = to_band(Ks - reach ** 2 * M, w)
            if band_lu(B) >= 0:
                return None
            count += int(np.count_nonzero(B[:, w] < 0.0))
    return count


def _factorised(D, what: str):
    """x = D^-1 b for the sparse complex D: LAPACK's banded LU with partial pivoting (zgbtrf) when
    D is banded (a shaft's matrices: half-bandwidth 7 whatever its length; a solve O(n w)), else
    SuperLU (its fill-reducing order makes a wide or irregular pattern's solve ~20x dearer)."""
    from scipy.linalg import lapack

    from ..integrate.banded import bandwidth

    n = D.shape[0]
    w = bandwidth(D)
    if w > BAND_MAX:
        import scipy.sparse.linalg as sla

        return sla.splu(D.tocsc()).solve
    c = D.tocoo()
    ab = np.zeros((3 * w + 1, n), dtype=complex)  # zgbtrf's storage: A[i, j] at ab[2 w + i - j, j]
    np.add.at(ab, (2 * w + c.row - c.col, c.col), c.data)
    lu, piv, info = lapack.zgbtrf(ab, w, w, overwrite_ab=True)
    if info != 0:
        raise ValueError(f"band_modes: {what} is singular (pivot {info} of {n} vanishes)")

    def solve(b):
        return lapack.zgbtrs(lu, w, w, b, piv)[0]

    return solve
def _highest_frequency(M, K) -> float:
    """An estimate [rad/s] of the highest natural frequency: max over DOFs of sqrt(K_ii / M_ii),
    the stiffest single element's (within a small factor of the true one); only the scale below
    which an eigenvalue counts as a rigid-body zero."""
    d = np.abs(M.diagonal())
    return float(math.sqrt(np.max(np.abs(K.diagonal())[d > 0] / d[d > 0])))


@contextlib.contextmanager
def one_blas_thread():
    """One OpenBLAS thread inside the block (the one scipy's ARPACK calls), restored after.

    ARPACK's steps are BLAS-2 products with the Krylov basis (2n x ~2k): OpenBLAS spreads each
    over every core and its threads spin between them, so on a loaded machine a speed of a
    2000-element shaft took 7-10 s with two threads and 1.1 s with one (2 cores, load 8,
    benchmarks/bench_band_modes.py). Without OpenBLAS (Accelerate, MKL) or its thread functions,
    nothing changes; nor outside the main thread (the count is the process's, and OpenBLAS must
    not have it changed under a call running in another thread; Dask's nanny starts its worker
    processes with OPENBLAS_NUM_THREADS=1 anyway)."""
    calls = _openblas_threads()
    if calls is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    get, put = calls
    before = get()
    put(1)
    try:
        yield
    finally:
        put(before)


@functools.lru_cache(maxsize=1)
def _openblas_threads():
    """(get, set) of the thread count of scipy's OpenBLAS (its wheels' scipy.libs or .dylibs, as
    loaded: the same library, not a second copy), or None."""
    import ctypes

    import scipy

    root = Path(scipy.__file__).resolve().parent
    for lib in sorted([*root.parent.glob("scipy.libs/*openblas*"), *root.glob(".dylibs/*openblas*")]):
        try:
            dll = ctypes.CDLL(str(lib))
        except OSError:
            continue
        for prefix in ("scipy_openblas", "openblas"):
            for suffix in ("", "64_"):
                get = getattr(dll, f"{prefix}_get_num_threads{suffix}", None)
                put = getattr(dll, f"{prefix}_set_num_threads{suffix}", None)
                if get is not None and put is not None:
                    get.restype, get.argtypes = ctypes.c_int, []
                    put.restype, put.argtypes = None, [ctypes.c_int]
                    return get, put
    return None
