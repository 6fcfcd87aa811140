"""The damped modes of a rotor on linear bearings in a frequency band, at any size.

``Rotor.modes`` solves the whole state-space eigenproblem densely: 2n x 2n, every mode. That is
right for the bundled rotors (44 DOFs: milliseconds) and impossible for a 2000-element shaft
(n = 8004: a 16 008 x 16 008 dense matrix, 2 GB, hours). Above ``DENSE_MAX_DOF`` DOFs (where
``Rotor.matrices`` turns sparse too), ``band_modes`` finds only the modes around the band of
interest with ARPACK in shift-invert mode on the sparse matrices:

  lambda^2 M x + lambda C x + K x = 0,  z = (x, lambda x):  A z = lambda B z,
  A = [[0, I], [-K, -C]], B = [[I, 0], [0, M]],

  (A - sigma B)^-1 B z = z / (lambda - sigma),

where applying (A - sigma B)^-1 B takes one solve with the n x n sparse complex matrix
D(sigma) = K + sigma C + sigma^2 M (x = -D^-1 (M w2 + (C + sigma M) w1), y = w1 + sigma x),
factorised once (scipy's SuperLU). ARPACK's largest |1 / (lambda - sigma)| are the eigenvalues
nearest sigma; the number asked for doubles until one found lies beyond the disk
|lambda - sigma| <= R, so every eigenvalue inside the disk is found. The disk: sigma = i w_b / 2,
R = 8 w_b for the band's top w_b = 2 pi up_to_hz: every mode with damped frequency in (0, w_b]
and |Re(lambda)| up to 7.98 w_b, so every mode of the band whose log decrement is below
2 pi 7.98 = 50 (amplification factor 0.06) and most heavier ones, the modes a stability analysis
ranks (``analyses.linear.modal``: up to 2 x the top speed); modes of the disk above the band
come too. Modes outside the disk (far above the band, or overdamped ones far to the left) are
not returned.

The same filters as ``Rotor.modes`` follow (oscillatory: Im(lambda) > 1e-3 |lambda|; rigid-body
zeros dropped) and the same normalisation (each shape's largest entry 1), so in the band the
two paths give the same modes to round-off (tests/test_band_modes.py).
"""

from __future__ import annotations

import math

import numpy as np

from .assembly import DENSE_MAX_DOF
from .eigen import OSCILLATORY, modal_table
from .rotor import Rotor

FIRST_K = 16  # eigenvalues asked of ARPACK at first; doubled until the disk is covered
DISK_RADIUS = 8.0  # R / w_b
ZERO_REL = 1e-6  # |lambda| below this times the highest element frequency: a rigid-body zero

__all__ = ["band_modes", "DISK_RADIUS"]


def band_modes(rotor: Rotor, speed: float, bearing_K=None, bearing_C=None, up_to_hz: float = math.inf, *,
               sparse: bool | None = None):
    """(freq_hz, log_dec, shapes) of the damped modes as ``Rotor.modes`` returns them, at
    ``speed`` [rad/s] with the bearings' Lund ``bearing_K`` [N/m] and ``bearing_C`` [N s/m] (one
    2x2, or one per bearing). Up to DENSE_MAX_DOF DOFs (``sparse`` None or False): every mode,
    ``Rotor.modes`` itself; above (or ``sparse=True``): the modes in the disk about the band up to
    ``up_to_hz`` [Hz] (module docstring), which must then be finite and > 0."""
    if not (sparse if sparse is not None else rotor.n_dof > DENSE_MAX_DOF):
        return rotor.modes(speed, bearing_K, bearing_C)
    if not (math.isfinite(up_to_hz) and up_to_hz > 0.0):
        raise ValueError(f"band_modes: a rotor of {rotor.n_dof} DOFs is solved in a band; up_to_hz = {up_to_hz!r} "
                         "must be a finite frequency > 0 Hz")
    M, K, C = _system(rotor, speed, bearing_K, bearing_C)
    wb = 2.0 * math.pi * up_to_hz
    sigma, radius = 0.5j * wb, DISK_RADIUS * wb
    lam, z = _nearest(M, K, C, sigma, radius)
    n = rotor.n_dof
    zero = ZERO_REL * _highest_frequency(M, K)
    keep = (np.abs(lam - sigma) <= radius) & (lam.imag > OSCILLATORY * np.abs(lam)) & (np.abs(lam) >= zero)
    lam, vec = lam[keep], z[:n, keep]
    return modal_table(lam, vec)


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
    import scipy.sparse.linalg as sla

    n = K.shape[0]
    lu = sla.splu((K + sigma * C + sigma ** 2 * M).astype(complex).tocsc())
    CsM = (C + sigma * M).astype(complex)

    def op(w):
        w = np.asarray(w).reshape(-1)
        x = -lu.solve(M @ w[n:] + CsM @ w[:n])
        return np.concatenate([x, w[:n] + sigma * x])

    A = sla.LinearOperator((2 * n, 2 * n), matvec=op, dtype=complex)
    v0 = np.ones(2 * n, dtype=complex)  # a fixed start: the same modes every run
    k = min(FIRST_K, 2 * n - 2)
    while True:
        mu, z = sla.eigs(A, k=k, which="LM", v0=v0, tol=0.0)
        lam = sigma + 1.0 / mu
        if np.max(np.abs(lam - sigma)) > radius or k >= 2 * n - 2:
            return lam, z
        k = min(2 * k, 2 * n - 2)


def _highest_frequency(M, K) -> float:
    """An estimate [rad/s] of the highest natural frequency: max over DOFs of sqrt(K_ii / M_ii),
    the stiffest single element's (within a small factor of the true one); only the scale below
    which an eigenvalue counts as a rigid-body zero."""
    d = np.abs(M.diagonal())
    return float(math.sqrt(np.max(np.abs(K.diagonal())[d > 0] / d[d > 0])))
