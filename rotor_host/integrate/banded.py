"""Banded matrices for the integrator: storage, products, an LU factorisation and its solve.

The beam FE matrices couple only the DOFs of neighbouring nodes (4 DOFs per node, ordered
node by node: ``rotor_host.model.rotor``), so every matrix of a step (M, K, C, G and the step
matrix S0 = c0 M + (1 + alpha)(c1 D + K)) has half-bandwidth w = 7 whatever the rotor's size,
and a product or a solve costs O(n w) instead of O(n^2). Storage is row-wise:
``B[i, j - i + w] = A[i, j]`` for |i - j| <= w, shape (n, 2 w + 1) (one contiguous row per
equation, the order the products and the substitutions walk).

The LU factorisation has no pivoting: S0's symmetric part, c0 M + (1 + alpha)(c1 C + K), is
positive definite (M positive definite, C and K positive semi-definite; the gyroscopic Omega G
is skew and adds nothing to it), so every leading minor is non-zero and elimination in the
natural order neither breaks down nor grows much (Golub & Van Loan, Matrix Computations, 4th
ed., sec. 4.4.1); a pivot that still comes out zero or tiny is reported as singular.

Every function that takes a matrix takes a dense array or a ``scipy.sparse`` one (a big
rotor's M, K, G: ``Rotor.sparse``), so nothing of size n x n need exist.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["bandwidth", "to_band", "from_band", "lapack_band", "band_to_sparse", "is_sparse", "band_lu", "band_solve",
           "band_matvec", "BandLU"]

PIVOT_RTOL = 1e-13  # a pivot below this fraction of its row's largest entry: singular for our purpose


def is_sparse(A) -> bool:
    """Whether A is a ``scipy.sparse`` matrix or array (without importing scipy for a dense one)."""
    return hasattr(A, "tocoo") and not isinstance(A, np.ndarray)


def _diagonal(A, d: int) -> np.ndarray:
    return A.diagonal(d) if is_sparse(A) else np.diagonal(A, d)


def bandwidth(*mats) -> int:
    """The half-bandwidth w of the matrices together: the largest |i - j| with A[i, j] != 0."""
    w = 0
    for A in mats:
        if A is None:
            continue
        if is_sparse(A):
            c = A.tocoo()
            keep = c.data != 0.0
            i, j = c.row[keep], c.col[keep]
        else:
            i, j = np.nonzero(np.asarray(A))
        if i.size:
            w = max(w, int(np.max(np.abs(i.astype(np.int64) - j))))
    return w


def to_band(A, w: int) -> np.ndarray:
    """Row-wise band storage of the (n, n) matrix A: B[i, j - i + w] = A[i, j]; entries of A
    outside the band are dropped (call ``bandwidth`` first)."""
    if not is_sparse(A):
        A = np.asarray(A, dtype=float)
    n = A.shape[0]
    B = np.zeros((n, 2 * w + 1))
    for d in range(-w, w + 1):
        diag = _diagonal(A, d)
        if d >= 0:
            B[:n - d, w + d] = diag
        else:
            B[-d:, w + d] = diag
    return B


def lapack_band(A, w: int) -> np.ndarray:
    """LAPACK's (``scipy.linalg.solve_banded``'s) storage of A with w sub- and super-diagonals:
    ab[w + i - j, j] = A[i, j], shape (2 w + 1, n)."""
    if not is_sparse(A):
        A = np.asarray(A, dtype=float)
    n = A.shape[0]
    ab = np.zeros((2 * w + 1, n))
    for d in range(-w, w + 1):
        if d >= 0:
            ab[w - d, d:] = _diagonal(A, d)
        else:
            ab[w - d, :n + d] = _diagonal(A, d)
    return ab


def band_to_sparse(B):
    """The ``scipy.sparse`` CSR matrix of the row-wise band storage B (its non-zero entries)."""
    import scipy.sparse as sp

    n, width = B.shape
    w = (width - 1) // 2
    i = np.repeat(np.arange(n), width)
    j = i + np.tile(np.arange(-w, w + 1), n)
    v = B.reshape(-1)
    keep = (j >= 0) & (j < n) & (v != 0.0)
    return sp.csr_matrix((v[keep], (i[keep], j[keep])), shape=(n, n))


def from_band(B) -> np.ndarray:
    """The dense (n, n) matrix of the band storage B (for checks)."""
    n, width = B.shape
    w = (width - 1) // 2
    A = np.zeros((n, n))
    for d in range(-w, w + 1):
        if d >= 0:
            A += np.diag(B[:n - d, w + d], d)
        else:
            A += np.diag(B[-d:, w + d], d)
    return A


@njit(cache=True, fastmath={"reassoc", "contract"})  # vectorised row sums (like newmark_kernels)
def band_matvec(B, x, out):
    """out = A x for A in row-wise band storage B."""
    n, width = B.shape
    w = (width - 1) // 2
    for i in range(n):
        lo = max(0, w - i)
        hi = min(width, n - i + w)
        s = 0.0
        for k in range(lo, hi):
            s += B[i, k] * x[i + k - w]
        out[i] = s


@njit(cache=True)
def band_lu(B):
    """In-place LU of the band storage B (no pivoting; L unit lower, its multipliers below the
    diagonal, U on and above). Returns the index of the first pivot that is zero or smaller
    than PIVOT_RTOL of its row's largest entry, or -1."""
    n, width = B.shape
    w = (width - 1) // 2
    for k in range(n):
        piv = B[k, w]
        rmax = 0.0
        for j in range(width):
            rmax = max(rmax, abs(B[k, j]))
        if not abs(piv) > PIVOT_RTOL * rmax:
            return k
        for i in range(k + 1, min(n, k + w + 1)):
            # A[i, k] sits at B[i, k - i + w]
            fac = B[i, k - i + w] / piv
            B[i, k - i + w] = fac
            if fac != 0.0:
                for j in range(k + 1, min(n, k + w + 1)):
                    B[i, j - i + w] -= fac * B[k, j - k + w]
    return -1


@njit(cache=True)
def band_solve(LU, b, x):
    """x = A^{-1} b from ``band_lu``'s factors (x may be b)."""
    n, width = LU.shape
    w = (width - 1) // 2
    for i in range(n):
        s = b[i]
        for j in range(max(0, i - w), i):
            s -= LU[i, j - i + w] * x[j]
        x[i] = s
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, min(n, i + w + 1)):
            s -= LU[i, j - i + w] * x[j]
        x[i] = s / LU[i, w]


class BandLU:
    """The LU factors of the (n, n) matrix A with half-bandwidth w (``band_lu``); ``solve(b)``.
    ValueError naming ``what`` when a pivot vanishes."""

    def __init__(self, A, w: int, what: str = "the matrix", *, band: bool = False):
        """A dense or sparse (n, n) matrix, or (``band=True``) its row-wise band storage (copied)."""
        self.w = int(w)
        self.LU = np.array(A, dtype=float) if band else to_band(A, self.w)
        k = band_lu(self.LU)
        if k >= 0:
            raise ValueError(f"{what} is singular (pivot {k} of {self.LU.shape[0]} vanishes)")

    def solve(self, b) -> np.ndarray:
        b = np.ascontiguousarray(b, dtype=float)
        if b.ndim == 1:
            x = np.empty_like(b)
            band_solve(self.LU, b, x)
            return x
        X = np.empty_like(b)
        for j in range(b.shape[1]):
            col = np.ascontiguousarray(b[:, j])
            band_solve(self.LU, col, col)
            X[:, j] = col
        return X
