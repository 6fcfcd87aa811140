"""The monomial basis of the Taylor surrogate (paper eq. 6) in scaled, dimensionless variables.

The force is expanded about the expansion point ``(y0, z0, 0, 0)`` (normally the static
equilibrium) in the four state variables, written in scaled form

    u = ((y - y0) / CR, (z - z0) / CR, vy / (omega CR), vz / (omega CR)),
    F_i / F_ref = sum_k c_ik * u1^e_k1 * u2^e_k2 * u3^e_k3 * u4^e_k4,

over the full monomial basis of total degree <= ``order``: C(order + 4, 4) terms (126 for
order 5, 5 for the linear model of order 1), the constant first, then degree by degree. The
coefficients of the order-1 terms are the scaled derivatives of the force (Lund's
coefficients, negated, times CR / F_ref or omega CR / F_ref).

Numpy only (the compiled evaluation is :mod:`bearing_fmu.surrogates.taylor_kernels`); the model and
its file are :mod:`bearing_fmu.surrogates.surrogate`, the internal :mod:`bearing_fmu.internals.taylor`.
"""

from __future__ import annotations

import math
from itertools import combinations_with_replacement

import numpy as np

from ..physics.params import BearingParams

N_VARS = 4
VAR_NAMES = ("dy", "dz", "dvy", "dvz")


def n_terms(order: int) -> int:
    """Number of monomials of total degree <= order in 4 variables: C(order + 4, 4)."""
    return math.comb(int(order) + N_VARS, N_VARS)


def exponents(order: int) -> np.ndarray:
    """Exponent table, shape (C(order + 4, 4), 4), int64: row k holds the powers of
    (dy, dz, dvy, dvz) of term k. Constant first, then degree 1, 2, ...; within a degree
    lexicographically descending, so degree 1 is dy, dz, dvy, dvz in that order."""
    order = int(order)
    if order < 0:
        raise ValueError(f"Taylor order must be >= 0, got {order}")
    rows = []
    for deg in range(order + 1):
        block = []
        for combo in combinations_with_replacement(range(N_VARS), deg):
            e = [0] * N_VARS
            for v in combo:
                e[v] += 1
            block.append(tuple(e))
        block.sort(reverse=True)
        rows.extend(block)
    return np.array(rows, dtype=np.int64).reshape(-1, N_VARS)


def term_names(exps: np.ndarray) -> list[str]:
    """Readable names of the terms, e.g. '1', 'dy', 'dy^2*dvz'."""
    names = []
    for e in np.asarray(exps):
        parts = [f"{VAR_NAMES[v]}" + (f"^{p}" if p > 1 else "") for v, p in enumerate(e) if p > 0]
        names.append("*".join(parts) if parts else "1")
    return names


def design_matrix(u: np.ndarray, exps: np.ndarray) -> np.ndarray:
    """Basis columns at the scaled states ``u`` (M, 4) -> (M, N), numpy (reference implementation)."""
    u = np.atleast_2d(np.asarray(u, float))
    exps = np.asarray(exps)
    order = int(exps.max()) if exps.size else 0
    pw = np.ones((N_VARS, order + 1, u.shape[0]))
    for v in range(N_VARS):
        for p in range(1, order + 1):
            pw[v, p] = pw[v, p - 1] * u[:, v]
    X = np.ones((u.shape[0], exps.shape[0]))
    for v in range(N_VARS):
        X *= pw[v, exps[:, v]].T
    return X


def natural_force_scale(params: BearingParams, omega: float) -> float:
    """mu |omega| R L (R / CR)^2 [N]: the hydrodynamic force scale of the bearing at speed omega."""
    return params.mu * abs(omega) * params.R * params.L * (params.R / params.CR) ** 2


def shape_force(u, S, shape_exponents, shape_coef) -> np.ndarray:
    """The shape columns' force [N] (M, 2): sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u) at scaled
    states u (M, 4), with S (M, >= 2) the short-bearing force there and shape_coef (4, Nr) in
    the rows of surrogate.SHAPE_ROWS. Numpy reference of the compiled _taylor_kernels._shape_terms."""
    Mp = design_matrix(u, shape_exponents) @ np.asarray(shape_coef).T  # (M, 4): the polynomials M_l(u)
    return np.column_stack([Mp[:, 0] * S[:, 0] + Mp[:, 1] * S[:, 1], Mp[:, 2] * S[:, 0] + Mp[:, 3] * S[:, 1]])



__all__ = ["N_VARS", "VAR_NAMES", "n_terms", "exponents", "term_names", "design_matrix", "natural_force_scale",
           "shape_force"]
