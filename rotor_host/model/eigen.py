"""The rotor's damped eigenproblem in state space (dense), and the modal table every eigensolver of
the rotor returns (frequencies, log decrements, shapes scaled by their largest entry)."""

from __future__ import annotations

import math

import numpy as np

OSCILLATORY = 1e-3  # modes(): keep eigenvalues with Im(lam) > OSCILLATORY * |lam|


def zero_tol(M, K) -> float:
    """|lam| [rad/s] below which an eigenvalue is numerically zero: 1e-6 * highest natural frequency.

    A double zero eigenvalue (rigid-body mode) is perturbed by about sqrt(eps) * w_max.
    """
    return 1e-6 * math.sqrt(np.linalg.norm(np.linalg.solve(M, K), 2))


def state_matrix(M, K, C) -> np.ndarray:
    n = M.shape[0]
    Minv_K = np.linalg.solve(M, K)
    Minv_C = np.linalg.solve(M, C)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv_K, -Minv_C]])


def state_eigvals(M, K, C) -> np.ndarray:
    return np.linalg.eigvals(state_matrix(M, K, C))


def state_eig(M, K, C):
    return np.linalg.eig(state_matrix(M, K, C))


def modal_table(lam: np.ndarray, vec: np.ndarray, n: int | None = None):
    """(frequencies [Hz], log decrements, shapes) of the oscillatory eigenpairs ``lam``, ``vec`` (a
    column each, the rotor's DOFs), by increasing frequency (the first ``n``), each shape scaled by
    its largest entry (the one all eigensolvers of the rotor share)."""
    order = np.argsort(lam.imag)
    if n is not None:
        order = order[:n]
    lam, vec = lam[order], vec[:, order]
    big = vec[np.argmax(np.abs(vec), axis=0), np.arange(vec.shape[1])]
    vec = vec / big
    return lam.imag / (2.0 * math.pi), -2.0 * math.pi * lam.real / lam.imag, vec

