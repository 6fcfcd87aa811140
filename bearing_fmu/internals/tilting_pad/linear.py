"""The tilting pads linearised about a solution (``assembly.PadSolution``): the full coefficients
(coordinates y, z, the tilts and, with flexible pivots, the pads' radial displacements), Lund's
reduction at a whirl frequency and the quasi-static Jacobian (the zero-frequency reduction). Functions
of a ``PadAssembly`` ``A`` (its pivots' tangents ``t``, directions ``s`` = -n_k, arm ``arm``, pivot
stiffness ``kp``): the pads' film and equilibria stay in ``assembly``.
"""

from __future__ import annotations

import math

import numpy as np


def full_coefficients(A, sol) -> tuple[np.ndarray, np.ndarray]:
    """The full K [N/m, N, N m/m, N m] and C (the same per second) at a solution, Lund's signs
    (-df/dx): (2 + N) x (2 + N), coordinates (y, z, delta_1 .. delta_N); with flexible pivots
    (2 + 2N) x (2 + 2N), coordinates (y, z, delta_1 .. delta_N, u_1 .. u_N), the pivots' k_p on
    the u diagonals of K (``physics.bore.pads``, *A flexible pivot*)."""
    n, a = A.n, A.arm
    size = A.coordinate_count()
    out = []
    for J in (sol.Jq, sol.Jv):
        D = np.zeros((size, size))
        D[:2, :2] = J.sum(axis=0)
        for k in range(n):
            t = A.t[k]
            D[:2, 2 + k] = a * J[k] @ t
            D[2 + k, :2] = a * t @ J[k]
            D[2 + k, 2 + k] = a * a * t @ J[k] @ t
            if size > 2 + n:  # the pad's radial coordinate: a journal shift along s_k = -n_k
                s, c = A.s[k], 2 + n + k
                D[:2, c] = J[k] @ s
                D[c, :2] = s @ J[k]
                D[c, c] = s @ J[k] @ s
                D[2 + k, c] = a * t @ J[k] @ s
                D[c, 2 + k] = a * s @ J[k] @ t
        out.append(-D)
    if size > 2 + n:
        out[0][2 + n:, 2 + n:] += A.kp * np.eye(n)
    return out[0], out[1]


def reduce(A, K: np.ndarray, C: np.ndarray, whirl: float) -> tuple[np.ndarray, np.ndarray]:
    """The journal's 2 x 2 K [N/m] and C [N s/m] at whirl frequency ``whirl`` [rad/s] > 0 with the
    pads' coordinates eliminated (their inertia ``A.coordinate_inertia()``: the tilts' moment of inertia,
    0 on the radial displacements)."""
    if not (math.isfinite(whirl) and whirl > 0.0):
        raise ValueError(f"reduce: the whirl frequency {whirl!r} must be a finite number > 0 rad/s")
    Z = K + 1j * whirl * C
    inertia = A.coordinate_inertia()
    n = len(inertia)
    Z[2:, 2:] -= whirl * whirl * np.diag(inertia)
    live = [2 + k for k in range(n) if Z[2 + k, 2 + k] != 0.0]
    Zr = Z[:2, :2]
    if live:
        Zr = Zr - Z[:2][:, live] @ np.linalg.solve(Z[np.ix_(live, live)], Z[live][:, :2])
    return Zr.real.copy(), Zr.imag / whirl


def quasi_static_jacobian(A, sol) -> tuple[np.ndarray, np.ndarray]:
    """dF/dq, dF/dv [N/m, N s/m] of the journal force with the massless pads re-equilibrated
    (M_k = 0 at ddelta = 0) as the journal moves: F_q + F_delta d delta / dq, d delta_k / dq =
    -(dM_k / dq) / (dM_k / d delta_k), the same with v. Flexible pivots: each pad's (delta_k, u_k)
    follows by its 2 x 2 block, F_q - F_p D_pp^-1 D_pq."""
    a = A.arm
    if A.kp is not None:
        return _quasi_static_flexible(A, sol)
    dq, dv = sol.Jq.sum(axis=0).copy(), sol.Jv.sum(axis=0).copy()
    for k in range(A.n):
        t, Jq, Jv = A.t[k], sol.Jq[k], sol.Jv[k]
        Mdd = a * a * t @ Jq @ t
        if Mdd == 0.0:
            continue
        Fd = a * Jq @ t
        dq -= np.outer(Fd, a * t @ Jq) / Mdd
        dv -= np.outer(Fd, a * t @ Jv) / Mdd
    return dq, dv


def _quasi_static_flexible(A, sol) -> tuple[np.ndarray, np.ndarray]:
    """(dF/dq, dF/dv): -(K_jj - K_jp K_pp^-1 K_pj), -(C_jj - K_jp K_pp^-1 C_pj), pad by pad (the pads'
    rates 0, their (delta, u) following the journal's position and velocity)."""
    K, C = full_coefficients(A, sol)
    n, out = A.n, []
    for D in (K, C):
        red = D[:2, :2].copy()
        for k in range(n):
            p = [2 + k, 2 + n + k]
            Kpp = K[np.ix_(p, p)]
            if Kpp[0, 0] == 0.0:  # a pad that carries nothing: its tilt is undetermined, its pivot unloaded
                p, Kpp = p[1:], Kpp[1:, 1:]
            red -= K[:2, p] @ np.linalg.solve(Kpp, D[p, :2])  # the pads' rates 0: K couples them
        out.append(-red)
    return out[0], out[1]


__all__ = ["full_coefficients", "reduce", "quasi_static_jacobian"]
