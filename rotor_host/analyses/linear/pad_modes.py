"""Damped modes of a rotor on bearings with degrees of freedom of their own (tilting pads): the
pads' rotations in the eigenproblem, so that every mode sees the pads at its own frequency.

Why the pads' coordinates and not the reduced coefficients iterated per mode: a tilting-pad
bearing linearised about its equilibrium is exactly the (2 + N) x (2 + N) K, C (and the pads'
inertia) of its journal and its pads (``Capabilities.whirl_reduced``'s ``full_coefficients``).
Put into the rotor's state space they give every mode at once, from one eigenvalue solve a speed,
each mode with the pads at its own complex frequency; the reduction at a whirl frequency is the
same algebra done per mode (a Schur complement), which needs one fixed-point iteration per mode
(and a mode to follow through it), and with a real whirl frequency, as Lund's reduction is
usually taken, it is exact only for an undamped mode. Both are here: ``modes`` (what
``rotor-host stability`` uses) and ``iterate_mode`` (the per-mode fixed point, the check).

The equations (Lund's signs: the bearing's generalised force is -K x - C xdot, x = (y, z,
delta_1 .. delta_N) of each bearing, its journal at the node's (y, z)):

    M qdd + (C_s + omega G) qd + K_s q = -sum_b [K_jj x_j + C_jj xd_j + K_jp delta + C_jp deltad]_b
    I deltadd = -(K_pj x_j + C_pj xd_j + K_pp delta + C_pp deltad)          (pads with inertia)
    0         = -(K_pj x_j + C_pj xd_j + K_pp delta + C_pp deltad)          (massless pads)

A massless pad's equation is first order (its squeeze C_pp balances the moment): its tilt is a
state and its rate the algebraic deltad = -C_pp^-1 (K_pj x_j + C_pj xd_j + K_pp delta), substituted
into the journal's force. A pad whose film carries nothing (all cavitated: its row and column
zero) drops out, as in the reduction. The state is (q, qd, massless tilts, tilts and rates of
pads with inertia); its eigenvalues and the rotor's part of the eigenvectors are kept as
``Rotor.modes`` keeps them (oscillatory, not numerically zero), so a pad's own overdamped
motion (real eigenvalues) is not listed as a mode.

Flexible pivots add each pad's radial displacement u_k (massless: first order through its
squeeze, like a massless tilt), coupled to the pad's own tilt through its film (K, C entries
between delta_k and u_k), so a pad's coordinates no longer have one row each: ``state_matrix``
then builds the descriptor form B X' = A X (``_descriptor``: the massless coordinates' rates on
the left through their C block, a tilt with inertia second order beside a massless radial row) and
solves it; blocks without such couplings (rigid pivots) keep the one-coordinate rows as they were.

The check (tests/test_pad_modes.py; flexible pivots: tests/test_tilting_pad_pivot.py): for each mode, the journal's impedance reduced at the
mode's own complex eigenvalue s, Z_red(s) = Z_jj - Z_jp Z_pp^-1 Z_pj with Z = K + s C + s^2 I,
put into the rotor as real K, C (C = Im Z_red / Im s, K = Re Z_red - Re s C: the same impedance
at s) gives s back as an eigenvalue of the rotor alone; iterated from the synchronous reduction
it converges to the full model's eigenvalue. With a real whirl frequency (s = i Im s) the
fixed point is Lund's per-mode reduction, which at the speed where the mode whirls at 1x is the
synchronously reduced analysis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.eigen import OSCILLATORY, modal_table
from ...model.rotor import Rotor


@dataclass
class PadBlock:
    """One bearing linearised with its own coordinates: ``dofs`` the rotor's (y, z) DOF indices of
    its journal, ``K``, ``C`` the (2 + N) x (2 + N) coefficients (Lund's signs; coordinates y, z,
    then the N internal ones), ``inertia`` (N,) each internal coordinate's inertia (0: massless)."""

    dofs: tuple[int, int]
    K: np.ndarray
    C: np.ndarray
    inertia: np.ndarray

    def live(self) -> np.ndarray:
        """The internal coordinates that carry anything (a row of K or C not zero), 0-based."""
        n = self.K.shape[0] - 2
        return np.array([k for k in range(n) if np.any(self.K[2 + k] != 0.0) or np.any(self.C[2 + k] != 0.0)],
                        dtype=int)

    def coupled(self) -> bool:
        """Do its internal coordinates couple among themselves (a flexible pivot: each pad's tilt and radial
        displacement), not only through the journal?"""
        live = 2 + self.live()
        off = ~np.eye(live.size, dtype=bool)
        return bool(np.any(self.K[np.ix_(live, live)][off] != 0.0) or np.any(self.C[np.ix_(live, live)][off] != 0.0))

    def reduced(self, s: complex) -> np.ndarray:
        """The journal's 2 x 2 impedance at the complex frequency s [1/s], its own coordinates
        eliminated: Z_jj - Z_jp Z_pp^-1 Z_pj, Z = K + s C + s^2 I."""
        Z = self.K + s * self.C
        live = 2 + self.live()
        Z[live, live] += s * s * self.inertia[live - 2]
        out = Z[:2, :2].astype(complex)
        if live.size:
            out = out - Z[:2][:, live] @ np.linalg.solve(Z[np.ix_(live, live)], Z[live][:, :2])
        return out


def pad_blocks(internals, pairs, q, omega: float) -> list[PadBlock]:
    """Each bearing's ``PadBlock`` at the rotor's equilibrium q, its internal's
    ``full_coefficients(y, z, omega)`` -> (K, C, inertia) (``Capabilities.whirl_reduced``)."""
    out = []
    for internal, (iy, iz) in zip(internals, pairs):
        K, C, inertia = internal.full_coefficients(float(q[iy]), float(q[iz]), omega)
        out.append(PadBlock((int(iy), int(iz)), np.asarray(K, float), np.asarray(C, float),
                            np.asarray(inertia, float)))
    return out


def state_matrix(rotor: Rotor, speed: float, blocks: list[PadBlock]) -> np.ndarray:
    """The first-order system X' = A X, X = (q, qd, massless tilts, tilts with inertia, their rates),
    of the rotor at ``speed`` [rad/s] with every bearing's block (module docstring). Blocks whose own
    coordinates couple (``PadBlock.coupled``: flexible pivots) take ``_descriptor``'s general form."""
    if any(blk.coupled() for blk in blocks):
        B, A = _descriptor(rotor, speed, blocks)
        return np.linalg.solve(B, A)
    n = rotor.n_dof
    Kt = rotor.K.copy()
    Ct = rotor.C + speed * rotor.G
    # the internal coordinates, split into massless (first order) and with inertia (second order)
    mass_rows, iner_rows = [], []  # per coordinate: (block, k)
    for b, blk in enumerate(blocks):
        j = list(blk.dofs)
        Kt[np.ix_(j, j)] += blk.K[:2, :2]
        Ct[np.ix_(j, j)] += blk.C[:2, :2]
        for k in blk.live():
            (iner_rows if blk.inertia[k] > 0.0 else mass_rows).append((b, int(k)))
    nm, ni = len(mass_rows), len(iner_rows)
    size = 2 * n + nm + 2 * ni
    A = np.zeros((size, size))
    # rows of the rotor's force: F = -Kt q - Ct v - sum (K_jp delta + C_jp deltad); collected as
    # a linear form in X, then M^-1 applied
    Fq = np.zeros((n, size))
    Fq[:, :n] = -Kt
    Fq[:, n:2 * n] = -Ct
    iq, iv = np.arange(n), n + np.arange(n)
    for r, (b, k) in enumerate(mass_rows):
        blk, c = blocks[b], 2 + k
        j = list(blk.dofs)
        col = 2 * n + r
        # deltad = -(K_pj x_j + C_pj xd_j + K_pp delta) / C_pp
        rate = np.zeros(size)
        rate[iq[j]] = -blk.K[c, :2] / blk.C[c, c]
        rate[iv[j]] = -blk.C[c, :2] / blk.C[c, c]
        rate[col] = -blk.K[c, c] / blk.C[c, c]
        A[col] = rate
        Fq[j, col] -= blk.K[:2, c]
        Fq[j] -= np.outer(blk.C[:2, c], rate)
    for r, (b, k) in enumerate(iner_rows):
        blk, c = blocks[b], 2 + k
        j = list(blk.dofs)
        cd, cw = 2 * n + nm + r, 2 * n + nm + ni + r
        A[cd, cw] = 1.0
        A[cw, iq[j]] = -blk.K[c, :2] / blk.inertia[k]
        A[cw, iv[j]] = -blk.C[c, :2] / blk.inertia[k]
        A[cw, cd] = -blk.K[c, c] / blk.inertia[k]
        A[cw, cw] = -blk.C[c, c] / blk.inertia[k]
        Fq[j, cd] -= blk.K[:2, c]
        Fq[j, cw] -= blk.C[:2, c]
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n] = np.linalg.solve(rotor.M, Fq)
    return A


def _descriptor(rotor: Rotor, speed: float, blocks: list[PadBlock]) -> tuple[np.ndarray, np.ndarray]:
    """(B, A) of B X' = A X, X ordered as ``state_matrix``'s, for internal coordinates that couple among
    themselves: every live coordinate c of a block, massless (m) or with inertia (i, its rate w a state
    of its own), obeys  I_c w_c' + sum_d C_cd p_d' + K_cd p_d + K_cj x_j + C_cj xd_j = 0  with p_d' = w_d
    for d with inertia, so the massless coordinates' rates stay on the left (B holds C_cm) and B is
    invertible when each block's C_mm is (a film's squeeze): ``state_matrix`` solves it. The journal's
    row holds -K_jp p - C_jp p' in the same way."""
    n = rotor.n_dof
    Kt = rotor.K.copy()
    Ct = rotor.C + speed * rotor.G
    for b, blk in enumerate(blocks):
        j = list(blk.dofs)
        Kt[np.ix_(j, j)] += blk.K[:2, :2]
        Ct[np.ix_(j, j)] += blk.C[:2, :2]
    coords = [(b, int(k)) for b, blk in enumerate(blocks) for k in blk.live() if blk.inertia[k] <= 0.0]
    nm = len(coords)
    coords += [(b, int(k)) for b, blk in enumerate(blocks) for k in blk.live() if blk.inertia[k] > 0.0]
    ni = len(coords) - nm
    size = 2 * n + nm + 2 * ni
    col = {c: 2 * n + r for r, c in enumerate(coords)}  # each coordinate's value column
    rate = {c: 2 * n + nm + ni + (r - nm) for r, c in enumerate(coords) if r >= nm}  # with inertia: its rate
    B, A = np.eye(size), np.zeros((size, size))
    B[n:2 * n, n:2 * n] = rotor.M
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n], A[n:2 * n, n:2 * n] = -Kt, -Ct
    iq, iv = np.arange(n), n + np.arange(n)
    for b, k in coords:
        blk, c = blocks[b], 2 + k
        j = list(blk.dofs)
        row = rate.get((b, k), col[(b, k)])  # the equation of coordinate c: its rate's row (inertia) or its own
        if (b, k) in rate:
            A[col[(b, k)], rate[(b, k)]] = 1.0  # p' = w
            B[row, row] = blk.inertia[k]
        else:
            B[row, row] = 0.0
        A[row, iq[j]] -= blk.K[c, :2]
        A[row, iv[j]] -= blk.C[c, :2]
        A[iv[j], col[(b, k)]] -= blk.K[:2, c]
        for d in blk.live():
            other, dd = (b, int(d)), 2 + int(d)
            A[row, col[other]] -= blk.K[c, dd]
            if other in rate:  # C_cd p_d' = C_cd w_d: a state
                A[row, rate[other]] -= blk.C[c, dd]
            else:
                B[row, col[other]] += blk.C[c, dd]
        if (b, k) in rate:
            A[iv[j], rate[(b, k)]] -= blk.C[:2, c]
        else:
            B[iv[j], col[(b, k)]] += blk.C[:2, c]
    return B, A


def _kept(rotor: Rotor, lam: np.ndarray, Kt: np.ndarray) -> np.ndarray:
    """``Rotor.modes``' rule: oscillatory (Im lam > OSCILLATORY |lam|) and not numerically zero (|lam|
    below 1e-6 of the highest undamped natural frequency: a rigid-body mode's round-off)."""
    zero = 1e-6 * math.sqrt(np.linalg.norm(np.linalg.solve(rotor.M, Kt), 2))
    return (lam.imag > OSCILLATORY * np.abs(lam)) & (np.abs(lam) >= zero)


def eigenvalues(rotor: Rotor, speed: float, blocks: list[PadBlock]):
    """(lam, X): every eigenvalue [1/s] of the rotor with the bearings' own coordinates and the
    eigenvectors (columns of the whole state)."""
    return np.linalg.eig(state_matrix(rotor, speed, blocks))


def modes(rotor: Rotor, speed: float, blocks: list[PadBlock]):
    """(freq_hz, log_dec, shapes) as ``Rotor.modes`` gives them (damped frequencies sorted, log
    decrements, the rotor's part of the complex shapes with its largest entry 1), with every
    bearing's own coordinates in the eigenproblem."""
    n = rotor.n_dof
    lam, vec = eigenvalues(rotor, speed, blocks)
    Kt = rotor.K + rotor.bearing_matrix([blk.K[:2, :2] for blk in blocks])
    keep = _kept(rotor, lam, Kt)
    lam, vec = lam[keep], vec[:n, keep]
    return modal_table(lam, vec)


def reduced_coefficients(blocks: list[PadBlock], s: complex) -> tuple[np.ndarray, np.ndarray]:
    """Every bearing's real 2 x 2 (K [N/m], C [N s/m]) whose impedance K + s C at the complex
    frequency s (Im s > 0) is the reduced one, Z_red(s): C = Im Z / Im s, K = Re Z - Re s C. For a
    real whirl frequency (s = i W) that is Lund's K(W) = Re Z, C(W) = Im Z / W."""
    Z = np.array([blk.reduced(s) for blk in blocks])
    C = Z.imag / s.imag
    return Z.real - s.real * C, C


def iterate_mode(rotor: Rotor, speed: float, blocks: list[PadBlock], s0: complex, *, damped: bool = True,
                 rtol: float = 1e-10, max_iter: int = 100) -> tuple[complex, int]:
    """The fixed point of one mode with every bearing reduced at the mode's own frequency: from s0,
    reduce at s (``damped``: the complex eigenvalue itself; else the real whirl frequency i Im s,
    Lund's), solve the rotor alone with those coefficients, take its eigenvalue (Im > 0) nearest to s,
    until it moves less than ``rtol`` |s| (1e-10: the eigenvalue solver's round-off is about 1e-11). Returns (s, iterations); RuntimeError if it does not settle."""
    s = complex(s0)
    for it in range(1, max_iter + 1):
        K, C = reduced_coefficients(blocks, s if damped else complex(0.0, s.imag))
        lam = np.linalg.eigvals(_rotor_state(rotor, speed, K, C, [blk.dofs for blk in blocks]))
        lam = lam[lam.imag > 0.0]
        new = complex(lam[np.argmin(np.abs(lam - s))])
        if abs(new - s) <= rtol * abs(s):
            return new, it
        s = new
    raise RuntimeError(f"iterate_mode: the mode near {s0:.6g} did not settle in {max_iter} iterations (last {s:.6g})")


def _rotor_state(rotor: Rotor, speed: float, K, C, dofs) -> np.ndarray:
    """The rotor's own first-order matrix with each bearing's 2 x 2 K, C at its (y, z) DOFs."""
    n = rotor.n_dof
    Kt = rotor.K.copy()
    Ct = rotor.C + speed * rotor.G
    for k, c, j in zip(K, C, dofs):
        Kt[np.ix_(j, j)] += k
        Ct[np.ix_(j, j)] += c
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -np.linalg.solve(rotor.M, Kt)
    A[n:, n:] = -np.linalg.solve(rotor.M, Ct)
    return A


def modes_at(rotor: Rotor, internals, pairs, q, omega: float):
    """``modes`` at the rotor's equilibrium q and speed omega [rad/s], each bearing's internal (with
    ``full_coefficients``) at its (y, z) DOF pair: what ``Stability.at`` takes for such internals."""
    return modes(rotor, omega, pad_blocks(internals, pairs, q, omega))


__all__ = ["PadBlock", "modes_at", "pad_blocks", "state_matrix", "eigenvalues", "modes", "reduced_coefficients",
           "iterate_mode"]
