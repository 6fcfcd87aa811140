"""Implicit Newmark / HHT-alpha time integration with Newton-Raphson, for

    M a + (C + Omega G) v + K q = f_ext(t) + f_nl(q, v)            (paper eq. 1)

at constant speed Omega. ``f_ext(t)`` is the full external force vector (unbalance, weight,
static loads); ``f_nl`` are nonlinear forces (the bearings) acting on a few DOFs through the
:class:`NodalForce` protocol. This module knows nothing of FMI or of any bearing model.

The scheme
----------
HHT-alpha (Hilber, Hughes, Taylor, Earthquake Eng. Struct. Dyn. 5 (1977) 283-292), with the
nonlinear force weighted like the internal forces:

    M a1 + (1 + alpha) (D v1 + K q1 - F1) - alpha (D v0 + K q0 - F0) = 0,
    F = f_ext(t) + P^T f_nl(P q, P v),   D = C + Omega G,
    q1 = q0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1),   v1 = v0 + h ((1 - gamma) a0 + gamma a1),

alpha in [-1/3, 0], beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha. alpha = 0 is the average
acceleration (trapezoidal) rule: unconditionally stable, second order, no numerical damping.
alpha < 0 damps the high-frequency content (spectral radius at h omega -> infinity equals
(1 + alpha) / (1 - alpha)) and stays second order.

The unknown of Newton's method is q1. With a(q) = c0 q - ahat, v(q) = c1 q - vhat
(c0 = 1 / (beta h^2), c1 = gamma / (beta h)) the residual is

    R(q) = S0 q - b - (1 + alpha) P^T f_nl(P q, P v(q)),   S0 = c0 M + (1 + alpha)(c1 D + K),

where b holds everything known at the start of the step. S0 is constant for a fixed h; it is
factorised once per step size (LU) and kept as its explicit inverse, because a 44 x 44
matrix-vector product costs well under a microsecond while a LAPACK triangular solve called
from Python costs several (benchmarks/bench_newmark.py measures both). The tangent S0 - (1 + alpha) P^T J P,
J = df/dq + c1 df/dv, differs from S0 only on the m nonlinear DOFs, so each Newton correction
uses the Woodbury identity: one n x n product and one m x m solve. The inner linear algebra is
compiled with numba; Python does the protocol calls and the decisions.

Predictor: the nonlinear force is linearised about the last accepted state with its last
tangent, and the linearised step is solved exactly. With linear forces (or none) the predictor
is the answer and a step costs one force evaluation.

Convergence, per evaluated iterate q_k: ||R(q_k)|| <= rtol_force * force_scale and
||dq_k|| <= rtol_disp * ||q_k|| + atol_disp, where dq_k is the Newton correction at q_k (its
error estimate) and force_scale = ||f_ext(t1)|| + ||f_nl(q_k)|| + ||M a0||. The accepted state is
always the last one evaluated: a NodalForce sees ``accept_step()`` right after the
``evaluate()`` of the accepted iterate.

Step cutting: when Newton fails (max_iter, non-finite residual, singular tangent) or
``evaluate`` raises :class:`StepRejected`, ``reject_step()`` is called and the step is done as
two half steps, recursively up to ``max_halvings`` times; outputs stay on the user's grid.
When even the smallest step fails, :class:`IntegrationError` is raised with the partial result.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Protocol, Sequence, runtime_checkable

import numpy as np
import scipy.linalg as sla
from numba import njit

__all__ = [
    "StepRejected",
    "IntegrationError",
    "EquilibriumError",
    "NodalForce",
    "FunctionForce",
    "LinearForce",
    "CompositeForce",
    "NewmarkConfig",
    "NewmarkResult",
    "Newmark",
    "integrate",
    "static_equilibrium",
]


# =============================================================================== errors

class StepRejected(Exception):
    """Raised by ``NodalForce.evaluate`` when the state cannot be evaluated (for example the
    journal at or beyond the bearing wall). The integrator cuts the step; give a message
    that says why (it appears in the final error if cutting does not help)."""


class IntegrationError(RuntimeError):
    """The integration could not continue. ``result`` holds everything computed so far
    (status "failed"); ``t``, ``iterations``, ``residual`` describe the failing step;
    ``state`` = (t, q, v, a) is the last accepted state (possibly between output times)."""

    def __init__(self, message: str, result: "NewmarkResult | None" = None, *, t: float = math.nan,
                 iterations: int = 0, residual: float = math.nan, state=None):
        super().__init__(message)
        self.result = result
        self.t = t
        self.iterations = iterations
        self.residual = residual
        self.state = state


class EquilibriumError(RuntimeError):
    """static_equilibrium failed; ``q`` is the last iterate, ``residual`` its residual norm."""

    def __init__(self, message: str, q: np.ndarray | None = None, residual: float = math.nan,
                 iterations: int = 0):
        super().__init__(message)
        self.q = q
        self.residual = residual
        self.iterations = iterations


# =============================================================================== protocol

@runtime_checkable
class NodalForce(Protocol):
    """Nonlinear force acting on a few DOFs.

    Call sequence per time step (t, dt): ``begin_step(t, dt)``; then ``evaluate(q, v)`` one or
    more times with the DOF values at the END of the step (t + dt) of the current iterate;
    then ``accept_step()`` (the last evaluate was at the accepted state) or ``reject_step()``
    (the step is abandoned and will be redone in smaller pieces). The arrays passed to
    ``evaluate`` are fresh copies: the force may keep them; v is the Newmark velocity of the
    iterate, v = gamma / (beta dt) (q - q0) + ..., so df/dv enters the tangent times
    gamma / (beta dt). The returned arrays are copied at once: a force may reuse its buffers.
    The first step's bracket also holds the evaluation at (q0, v0) that gives the initial
    acceleration. With tangent="fd" some evaluations are at perturbed states; the accepted
    state is still the last one evaluated before ``accept_step()``.
    ``static_equilibrium`` brackets its evaluations in ``begin_step(t, 0.0)`` ...
    ``accept_step()`` (``reject_step()`` on failure); dt = 0.0 marks a static evaluation.
    """

    dofs: np.ndarray

    def begin_step(self, t: float, dt: float) -> None: ...

    def evaluate(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
        """Return f (m,), and df/dq (m, m), df/dv (m, m) (raw derivatives) or None."""
        ...

    def accept_step(self) -> None: ...

    def reject_step(self) -> None: ...


def _as_dofs(dofs) -> np.ndarray:
    d = np.ascontiguousarray(np.asarray(dofs, dtype=np.int64).reshape(-1))
    if np.unique(d).size != d.size:
        raise ValueError(f"nonlinear-force DOFs must be distinct, got {d.tolist()}")
    return d


class FunctionForce:
    """A NodalForce from a plain callable ``fn(q, v) -> (f, dfdq, dfdv)`` (or just ``f``);
    the step hooks do nothing."""

    def __init__(self, dofs, fn: Callable):
        self.dofs = _as_dofs(dofs)
        self.fn = fn

    def begin_step(self, t: float, dt: float) -> None:
        pass

    def evaluate(self, q, v):
        out = self.fn(q, v)
        if isinstance(out, tuple):
            if len(out) == 3:
                return out
            if len(out) == 1:
                return out[0], None, None
            raise ValueError("FunctionForce callable must return f or (f, dfdq, dfdv)")
        return out, None, None

    def accept_step(self) -> None:
        pass

    def reject_step(self) -> None:
        pass


class LinearForce:
    """f = f0 - Kb (q - q_ref) - Cb v on ``dofs`` (Lund's sign: Kb, Cb are the stiffness and
    damping the force opposes the motion with). Exact derivatives. For linear bearings and tests."""

    def __init__(self, dofs, Kb, Cb=None, f0=None, q_ref=None):
        self.dofs = _as_dofs(dofs)
        m = self.dofs.size
        self.Kb = np.array(Kb, dtype=float).reshape(m, m)
        self.Cb = np.zeros((m, m)) if Cb is None else np.array(Cb, dtype=float).reshape(m, m)
        self.f0 = np.zeros(m) if f0 is None else np.array(f0, dtype=float).reshape(m)
        self.q_ref = np.zeros(m) if q_ref is None else np.array(q_ref, dtype=float).reshape(m)
        self._dq = -self.Kb
        self._dv = -self.Cb

    def begin_step(self, t: float, dt: float) -> None:
        pass

    def evaluate(self, q, v):
        return self.f0 - self.Kb @ (q - self.q_ref) - self.Cb @ v, self._dq, self._dv

    def accept_step(self) -> None:
        pass

    def reject_step(self) -> None:
        pass


class CompositeForce:
    """Several NodalForces (e.g. one per bearing) seen as one: DOFs concatenated, derivatives
    block-diagonal. A member that returns no derivatives contributes zero blocks (its part of
    the tangent is then the linear one). Hooks are forwarded to every member."""

    def __init__(self, forces: Sequence[NodalForce]):
        self.forces = list(forces)
        sizes = [len(np.asarray(f.dofs).reshape(-1)) for f in self.forces]
        self.dofs = _as_dofs(np.concatenate([np.asarray(f.dofs, dtype=np.int64).reshape(-1) for f in self.forces])
                             if self.forces else np.zeros(0, np.int64))
        self._slices = []
        o = 0
        for s in sizes:
            self._slices.append(slice(o, o + s))
            o += s
        m = self.dofs.size
        self._f = np.zeros(m)
        self._dq = np.zeros((m, m))
        self._dv = np.zeros((m, m))

    def begin_step(self, t: float, dt: float) -> None:
        for f in self.forces:
            f.begin_step(t, dt)

    def evaluate(self, q, v):
        f_all = np.empty(self.dofs.size)
        dq_all = np.zeros((self.dofs.size, self.dofs.size))
        dv_all = np.zeros((self.dofs.size, self.dofs.size))
        any_dq = any_dv = False
        for frc, s in zip(self.forces, self._slices):
            f, dq, dv = frc.evaluate(q[s].copy(), v[s].copy())
            f_all[s] = f
            if dq is not None:
                dq_all[s, s] = dq
                any_dq = True
            if dv is not None:
                dv_all[s, s] = dv
                any_dv = True
        return f_all, (dq_all if any_dq else None), (dv_all if any_dv else None)

    def accept_step(self) -> None:
        for f in self.forces:
            f.accept_step()

    def reject_step(self) -> None:
        for f in self.forces:
            f.reject_step()


class _NoForce:
    dofs = np.zeros(0, dtype=np.int64)
    _f = np.zeros(0)

    def begin_step(self, t, dt):
        pass

    def evaluate(self, q, v):
        return self._f, None, None

    def accept_step(self):
        pass

    def reject_step(self):
        pass


# =============================================================================== kernels

@njit(cache=True, fastmath={"reassoc", "contract"})  # lets LLVM vectorise the dot products (3x)
def _matvec(A, x, out):
    n, k = A.shape
    for i in range(n):
        s = 0.0
        for j in range(k):
            s += A[i, j] * x[j]
        out[i] = s


@njit(cache=True)
def _solve_small(A, b):
    """Solve A x = b in place (x in b) by Gaussian elimination with partial pivoting.
    Returns False if A is (numerically) singular."""
    m = b.size
    for k in range(m):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        if amax == 0.0 or not np.isfinite(amax):
            return False
        if p != k:
            for j in range(m):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
        piv = A[k, k]
        for i in range(k + 1, m):
            fac = A[i, k] / piv
            if fac != 0.0:
                for j in range(k + 1, m):
                    A[i, j] -= fac * A[k, j]
                b[i] -= fac * b[k]
    for k in range(m - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, m):
            s -= A[k, j] * b[j]
        b[k] = s / A[k, k]
    return True


# Packed buffers (each numba call costs ~0.07 us per argument, so the kernels take few):
#   SS (2, n, n)  : S0, S0^{-1} for the current step size
#   cs (7,)       : alpha, c0, c1, h, a3, cv, ca   (see _Ops)
#   V  (10, n)    : rows below
#   Pm (4, m)     : qP, vP (the next iterate at the nonlinear DOFs), y, fl (work)
#   AJ (4, m, m)  : A (capacitance matrix), Jt (scaled tangent), and the raw tangent
#                   (df/dq, df/dv) of the last evaluated state, the predictor's tangent
_B, _AH, _VH, _Q0, _Q1, _QS, _R, _X, _DQ, _MA = range(10)


@njit(cache=True)
def _correction(R, Jq, Jv, c1, opa, S0inv, dofs, x, A, y, Jt, dq):
    """dq = -S^{-1} R with S = S0 - opa P^T (Jq + c1 Jv) P, by the Woodbury identity
    S^{-1} = S0^{-1} + W (I - Jt WP)^{-1} Jt P S0^{-1}, W = S0^{-1} P^T, WP = P W, Jt = opa J.
    Returns False if the m x m capacitance matrix is singular."""
    n = R.size
    m = dofs.size
    _matvec(S0inv, R, x)
    for i in range(m):
        for j in range(m):
            Jt[i, j] = opa * (Jq[i, j] + c1 * Jv[i, j])
    for i in range(m):
        s = 0.0
        for j in range(m):
            s += Jt[i, j] * x[dofs[j]]
        y[i] = s
        for j in range(m):
            acc = 0.0
            dj = dofs[j]
            for l in range(m):
                acc += Jt[i, l] * S0inv[dofs[l], dj]
            A[i, j] = -acc
        A[i, i] += 1.0
    ok = _solve_small(A, y)
    for i in range(n):
        s = x[i]
        for j in range(m):
            s += S0inv[i, dofs[j]] * y[j]
        dq[i] = -s
    return ok


@njit(cache=True)
def _k_begin(X, H, SS, dofs, fe1, fe0, f0, Jq, Jv, cs, V, Pm, AJ):
    """Start a step from the state X = [q0, v0, a0]: b, ahat, vhat, and the predictor (in
    V[_Q0]): the step solved exactly with the nonlinear force linearised about the state at t0
    with tangent (Jq, Jv). Returns (ok, ||fe1||, ||b||)."""
    alpha, c0, c1, h, a3, cv, ca = cs[0], cs[1], cs[2], cs[3], cs[4], cs[5], cs[6]
    b, ahat, vhat, q, qstart, R = V[_B], V[_AH], V[_VH], V[_Q0], V[_QS], V[_R]
    fl = Pm[3]
    n = b.size
    m = dofs.size
    opa = 1.0 + alpha
    _matvec(H, X, b)
    fen = 0.0
    bn = 0.0
    for i in range(n):
        b[i] += opa * fe1[i] - alpha * fe0[i]
        fen += fe1[i] * fe1[i]
        qi = X[i]
        vi = X[n + i]
        ai = X[2 * n + i]
        ahat[i] = c0 * qi + c0 * h * vi + a3 * ai
        vhat[i] = c1 * qi + cv * vi + ca * ai
        qstart[i] = qi + h * vi + 0.5 * h * h * ai
    if alpha != 0.0:
        for j in range(m):
            b[dofs[j]] -= alpha * f0[j]
    for i in range(n):
        bn += b[i] * b[i]
    # linearised force at qstart: fl = f0 + Jq (qs - q0)_P + Jv (vs - v0)_P
    for i in range(m):
        s = f0[i]
        for j in range(m):
            dj = dofs[j]
            s += Jq[i, j] * (qstart[dj] - X[dj]) + Jv[i, j] * (c1 * qstart[dj] - vhat[dj] - X[n + dj])
        fl[i] = s
    _matvec(SS[0], qstart, R)
    for i in range(n):
        R[i] -= b[i]
    for j in range(m):
        R[dofs[j]] -= opa * fl[j]
    ok = _correction(R, Jq, Jv, c1, opa, SS[1], dofs, V[_X], AJ[0], Pm[2], AJ[1], q)
    for i in range(n):
        q[i] += qstart[i]
    qP, vP = Pm[0], Pm[1]
    for j in range(m):
        dj = dofs[j]
        qP[j] = q[dj]
        vP[j] = c1 * q[dj] - vhat[dj]
    return ok, math.sqrt(fen), math.sqrt(bn)


@njit(cache=True)
def _k_iter(iq, f, Jq, Jv, SS, dofs, cs, V, Pm, AJ):
    """Residual at q = V[iq] with force f, Newton correction, next iterate in the other q row
    (V[_Q0] <-> V[_Q1]) and its (qP, vP) in Pm. Returns (||R||, ||dq||, ||q||, ||f||, ok)."""
    alpha, c1 = cs[0], cs[2]
    q = V[iq]
    qn = V[_Q0 + _Q1 - iq]
    b, vhat, R, dq = V[_B], V[_VH], V[_R], V[_DQ]
    n = q.size
    m = dofs.size
    opa = 1.0 + alpha
    _matvec(SS[0], q, R)
    for i in range(n):
        R[i] -= b[i]
    fn = 0.0
    for j in range(m):
        R[dofs[j]] -= opa * f[j]
        fn += f[j] * f[j]
    rn = 0.0
    for i in range(n):
        rn += R[i] * R[i]
    ok = _correction(R, Jq, Jv, c1, opa, SS[1], dofs, V[_X], AJ[0], Pm[2], AJ[1], dq)
    # keep the tangent of the state just evaluated: after acceptance it is the predictor's
    Jql, Jvl = AJ[2], AJ[3]
    for i in range(m):
        for j in range(m):
            Jql[i, j] = Jq[i, j]
            Jvl[i, j] = Jv[i, j]
    dn = 0.0
    qnorm = 0.0
    for i in range(n):
        dn += dq[i] * dq[i]
        qnorm += q[i] * q[i]
        qn[i] = q[i] + dq[i]
    qP, vP = Pm[0], Pm[1]
    for j in range(m):
        dj = dofs[j]
        qP[j] = qn[dj]
        vP[j] = c1 * qn[dj] - vhat[dj]
    return math.sqrt(rn), math.sqrt(dn), math.sqrt(qnorm), math.sqrt(fn), ok


@njit(cache=True)
def _k_accept(X, iq, cs, V, M):
    """X <- [q, v(q), a(q)] with q = V[iq]; returns ||M a||."""
    c0, c1 = cs[1], cs[2]
    q, ahat, vhat, Ma = V[iq], V[_AH], V[_VH], V[_MA]
    n = q.size
    for i in range(n):
        X[i] = q[i]
        X[n + i] = c1 * q[i] - vhat[i]
        X[2 * n + i] = c0 * q[i] - ahat[i]
    _matvec(M, X[2 * n:], Ma)
    s = 0.0
    for i in range(n):
        s += Ma[i] * Ma[i]
    return math.sqrt(s)


# =============================================================================== config / result

@dataclass
class NewmarkConfig:
    """Integrator settings.

    alpha: HHT parameter in [-1/3, 0]; 0 = average acceleration (no numerical damping).
    beta, gamma: Newmark parameters; None = the HHT values (1 - alpha)^2 / 4 and 1/2 - alpha.
    rtol_force: residual tolerance relative to ||f_ext|| + ||f_nl|| + ||M a||.
    rtol_disp, atol_disp: tolerance on the Newton correction, relative to ||q|| plus absolute.
    max_iter: Newton corrections allowed per step (force evaluations <= max_iter + 1).
    max_halvings: how many times a step may be halved before IntegrationError.
    tangent: "auto" = use the derivatives evaluate returns, the linear tangent if it returns
        none (modified Newton); "fd" = as auto, but finite differences when it returns none
        (m extra evaluations per tangent, kept across steps and refreshed when the chord
        iteration gets slow); "linear" = never use the nonlinear tangent.
    fd_rel, fd_qtyp: finite-difference step h_j = fd_rel * max(|q_j|, fd_qtyp) (q units).
    trace: keep each step's residual norms ||R(q_k)|| (one array per attempt) in the result.
    """

    alpha: float = 0.0
    beta: float | None = None
    gamma: float | None = None
    rtol_force: float = 1e-8
    rtol_disp: float = 1e-8
    atol_disp: float = 0.0
    max_iter: int = 20
    max_halvings: int = 6
    tangent: str = "auto"
    fd_rel: float = 1.5e-8
    fd_qtyp: float = 1e-6
    trace: bool = False

    def __post_init__(self):
        if not (-1.0 / 3.0 - 1e-15 <= self.alpha <= 0.0):
            raise ValueError(f"HHT alpha must lie in [-1/3, 0], got {self.alpha}")
        if self.beta is None:
            self.beta = (1.0 - self.alpha) ** 2 / 4.0
        if self.gamma is None:
            self.gamma = 0.5 - self.alpha
        if not self.beta > 0.0:
            raise ValueError(f"Newmark beta must be > 0, got {self.beta}")
        if self.tangent not in ("auto", "fd", "linear"):
            raise ValueError(f"tangent must be 'auto', 'fd' or 'linear', got {self.tangent!r}")
        if self.max_iter < 1 or self.max_halvings < 0:
            raise ValueError("max_iter must be >= 1 and max_halvings >= 0")


@dataclass
class NewmarkResult:
    """Time history on the output grid.

    t (n_out,); q, v (n_out, len(dofs)) for the recorded DOFs ``dofs``; f_nl (n_out, m) the
    nonlinear force on ``nl_dofs``; iterations (n_steps,) force evaluations (= Newton
    iterations, 1 = predictor accepted) spent on each grid step, failed attempts and sub-steps
    included; n_cuts step halvings; n_evaluations all force evaluations (incl. the initial
    one and finite differences); wall_time [s]; status "ok" or "failed" with message.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    f_nl: np.ndarray
    dofs: np.ndarray
    nl_dofs: np.ndarray
    iterations: np.ndarray
    n_cuts: int = 0
    n_evaluations: int = 0
    wall_time: float = 0.0
    status: str = "ok"
    message: str = ""
    residual_history: list | None = field(default=None, repr=False)

    @property
    def mean_iterations(self) -> float:
        return float(np.mean(self.iterations)) if self.iterations.size else 0.0

    def save(self, path) -> Path:
        path = Path(path)
        np.savez(path, t=self.t, q=self.q, v=self.v, f_nl=self.f_nl, dofs=self.dofs,
                 nl_dofs=self.nl_dofs, iterations=self.iterations, n_cuts=self.n_cuts,
                 n_evaluations=self.n_evaluations, wall_time=self.wall_time,
                 status=self.status, message=self.message)
        return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")

    @classmethod
    def load(cls, path) -> "NewmarkResult":
        with np.load(path) as d:
            return cls(t=d["t"], q=d["q"], v=d["v"], f_nl=d["f_nl"], dofs=d["dofs"],
                       nl_dofs=d["nl_dofs"], iterations=d["iterations"], n_cuts=int(d["n_cuts"]),
                       n_evaluations=int(d["n_evaluations"]), wall_time=float(d["wall_time"]),
                       status=str(d["status"]), message=str(d["message"]))


# =============================================================================== integrator

class _Ops:
    """Everything that depends on the step size h only."""

    def __init__(self, h, M, D, K, dofs, cfg: NewmarkConfig):
        a, b_, g = cfg.alpha, cfg.beta, cfg.gamma
        opa = 1.0 + a
        self.h = h
        self.c0 = 1.0 / (b_ * h * h)
        self.c1 = g / (b_ * h)
        self.a3 = 1.0 / (2.0 * b_) - 1.0
        self.cv = self.c1 * h - 1.0
        self.ca = g * h * self.a3 - h * (1.0 - g)
        S0 = self.c0 * M + opa * (self.c1 * D + K)
        lu = sla.lu_factor(S0, check_finite=True)
        if np.any(np.diag(lu[0]) == 0.0):
            raise ValueError(f"the linear Newmark matrix is singular for dt = {h:g}")
        n = M.shape[0]
        S0inv = sla.lu_solve(lu, np.eye(n))
        self.SS = np.ascontiguousarray(np.stack([S0, S0inv]))
        self.cs = np.array([a, self.c0, self.c1, h, self.a3, self.cv, self.ca])
        Hq = self.c0 * M + opa * self.c1 * D + a * K
        Hv = self.c0 * h * M + (opa * self.cv + a) * D
        Ha = self.a3 * M + opa * self.ca * D
        self.H = np.ascontiguousarray(np.hstack([Hq, Hv, Ha]))


class Newmark:
    """Implicit Newmark / HHT-alpha integrator for M a + (C + omega G) v + K q = f_ext(t) + f_nl.

    M, K, C, G: (n, n) arrays (C, G default zero); omega: constant speed [rad/s];
    f_ext: callable t -> (n,) array, a constant (n,) array, or None (zero);
    nodal_force: a NodalForce, a sequence of them (combined with CompositeForce), or None.
    """

    def __init__(self, M, K, C=None, G=None, omega: float = 0.0, f_ext=None,
                 nodal_force: NodalForce | Sequence[NodalForce] | None = None,
                 config: NewmarkConfig | None = None):
        self.M = np.ascontiguousarray(np.asarray(M, dtype=float))
        n = self.M.shape[0]
        if self.M.shape != (n, n):
            raise ValueError(f"M must be square, got shape {self.M.shape}")
        self.K = self._mat(K, n, "K")
        self.C = self._mat(C, n, "C")
        self.G = self._mat(G, n, "G")
        self.omega = float(omega)
        self.D = self.C + self.omega * self.G
        self.n = n
        if f_ext is None:
            zero = np.zeros(n)
            self.f_ext = lambda t: zero
        elif callable(f_ext):
            self.f_ext = f_ext
        else:
            const = np.asarray(f_ext, dtype=float).reshape(n)
            self.f_ext = lambda t: const
        if nodal_force is None:
            self.nf = _NoForce()
        elif isinstance(nodal_force, (list, tuple)):
            self.nf = CompositeForce(nodal_force)
        else:
            self.nf = nodal_force
        self.dofs = _as_dofs(self.nf.dofs)
        if self.dofs.size and (self.dofs.min() < 0 or self.dofs.max() >= n):
            raise ValueError(f"nonlinear-force DOFs {self.dofs.tolist()} outside 0..{n - 1}")
        self.cfg = config or NewmarkConfig()
        self._ops_cache: dict[float, _Ops] = {}

    @staticmethod
    def _mat(A, n, name):
        if A is None:
            return np.zeros((n, n))
        A = np.ascontiguousarray(np.asarray(A, dtype=float))
        if A.shape != (n, n):
            raise ValueError(f"{name} must have shape ({n}, {n}), got {A.shape}")
        return A

    def _ops(self, h: float) -> _Ops:
        ops = self._ops_cache.get(h)
        if ops is None:
            ops = self._ops_cache[h] = _Ops(h, self.M, self.D, self.K, self.dofs, self.cfg)
        return ops

    # ------------------------------------------------------------------ public
    def run(self, q0, v0, t0: float, t_end: float, dt: float, *, record_every: int = 1,
            record_dofs=None, progress: Callable[[float], None] | None = None,
            progress_every: int | None = None) -> NewmarkResult:
        """Integrate from t0 to t_end (a whole number of steps dt). Outputs every
        ``record_every`` steps at t0 + k dt; ``record_dofs`` selects the recorded DOFs
        (default all). ``progress(t)`` is called every ``progress_every`` steps (default
        ~200 calls per run) and at the end. Raises IntegrationError with the partial result."""
        cfg = self.cfg
        n, m = self.n, self.dofs.size
        dt = float(dt)
        if not dt > 0.0:
            raise ValueError(f"dt must be > 0, got {dt}")
        n_steps = int(round((t_end - t0) / dt))
        if n_steps < 1 or abs(n_steps * dt - (t_end - t0)) > 1e-6 * dt:
            raise ValueError(f"t_end - t0 = {t_end - t0:g} s is not a positive whole number of steps dt = {dt:g} s")
        record_every = max(1, int(record_every))
        rec = np.arange(n) if record_dofs is None else np.asarray(record_dofs, dtype=np.int64).reshape(-1)
        n_out = n_steps // record_every + 1
        if progress_every is None:
            progress_every = max(1, n_steps // 200)

        self._wall0 = time.perf_counter()
        st = self._state = _RunState(n, m, n_steps, n_out, rec, cfg.trace)
        st.t0, st.dt, st.record_every = float(t0), dt, record_every

        q0 = np.asarray(q0, dtype=float).reshape(n)
        v0 = np.asarray(v0, dtype=float).reshape(n)
        X = st.X
        X[:n] = q0
        X[n:2 * n] = v0
        st.t = float(t0)

        # first step's bracket also holds the evaluation at (q0, v0) for the initial acceleration
        self.nf.begin_step(st.t, dt)
        st.fe0[:] = self._fext(st.t)
        try:
            f, dfq, dfv = self.nf.evaluate(q0[self.dofs].copy(), v0[self.dofs].copy())
        except StepRejected as e:
            self.nf.reject_step()
            raise IntegrationError(f"the initial state at t = {t0:g} s was rejected: {e}", self._partial(),
                                   t=t0, iterations=0, residual=math.nan) from e
        st.n_eval += 1
        st.f0 = self._fcheck(f)
        self._store_tangent(dfq, dfv)
        F = st.fe0.copy()
        F[self.dofs] += st.f0
        rhs = F - self.D @ v0 - self.K @ q0
        try:
            a0 = sla.cho_solve(sla.cho_factor(self.M), rhs)
        except np.linalg.LinAlgError:
            a0 = np.linalg.solve(self.M, rhs)
        X[2 * n:] = a0
        st.Ma_norm = float(np.linalg.norm(self.M @ a0))
        st.in_first_bracket = True
        self._record(0)

        advance = self._advance
        record = self._record
        iters = st.iters
        try:
            for k in range(n_steps):
                t_b = t0 + (k + 1) * dt
                st.step_its = 0
                advance(t0 + k * dt, t_b, 0)
                iters[k] = st.step_its
                st.steps_done = k + 1
                if (k + 1) % record_every == 0:
                    record((k + 1) // record_every)
                if progress is not None and (k + 1) % progress_every == 0:
                    progress(t_b)
        except _StepFailure as fail:
            res = self._partial(status="failed", message=fail.message)
            raise IntegrationError(fail.message, res, t=fail.t, iterations=fail.iterations,
                                   residual=fail.residual,
                                   state=(st.t, X[:n].copy(), X[n:2 * n].copy(), X[2 * n:].copy())) from fail.cause
        if progress is not None and n_steps % progress_every != 0:
            progress(t0 + n_steps * dt)
        return self._partial()

    # ------------------------------------------------------------------ internals
    def _fext(self, t):
        fe = np.asarray(self.f_ext(t), dtype=float)
        if fe.shape != (self.n,):
            raise ValueError(f"f_ext({t:g}) has shape {fe.shape}, expected ({self.n},)")
        return fe

    def _fcheck(self, f):
        f = np.array(f, dtype=float)  # a copy: forces may hand back a reused buffer
        if f.shape != (self.dofs.size,):
            raise ValueError(f"NodalForce.evaluate returned f of shape {f.shape}, expected ({self.dofs.size},)")
        return f

    def _jcheck(self, J, name):
        J = np.ascontiguousarray(J, dtype=float)
        m = self.dofs.size
        if J.shape != (m, m):
            raise ValueError(f"NodalForce.evaluate returned {name} of shape {J.shape}, expected ({m}, {m})")
        return J

    def _store_tangent(self, dfq, dfv):
        st = self._state
        if self.cfg.tangent == "linear" or (dfq is None and dfv is None):
            st.have_J = False
            return
        st.have_J = True
        st.Jq_prev[:] = 0.0 if dfq is None else self._jcheck(dfq, "df/dq")
        st.Jv_prev[:] = 0.0 if dfv is None else self._jcheck(dfv, "df/dv")

    def _record(self, i):
        st = self._state
        n = self.n
        st.out_t[i] = st.t0 + i * st.record_every * st.dt
        if st.rec_all:
            st.out_q[i] = st.X[:n]
            st.out_v[i] = st.X[n:2 * n]
        else:
            st.out_q[i] = st.X[:n][st.rec]
            st.out_v[i] = st.X[n:2 * n][st.rec]
        st.out_f[i] = st.f0
        st.n_rec = i + 1

    def _partial(self, status="ok", message="") -> NewmarkResult:
        st = self._state
        k = st.n_rec
        return NewmarkResult(
            t=st.out_t[:k].copy(), q=st.out_q[:k].copy(), v=st.out_v[:k].copy(), f_nl=st.out_f[:k].copy(),
            dofs=st.rec.copy(), nl_dofs=self.dofs.copy(), iterations=st.iters[:st.steps_done].copy(),
            n_cuts=st.n_cuts, n_evaluations=st.n_eval, wall_time=time.perf_counter() - self._wall0,
            status=status, message=message, residual_history=st.trace)

    def _advance(self, t_a, t_b, level):
        ok, info = self._attempt(t_a, t_b, level)
        if ok:
            return
        self._cut(t_a, t_b, level, info)

    def _cut(self, t_a, t_b, level, info):
        st = self._state
        if level >= self.cfg.max_halvings:
            its, rn, tol, reason, cause = info
            msg = (f"Newmark step failed at t = {t_a:.9g} s (step {t_b - t_a:.3g} s after {level} halvings of "
                   f"dt = {st.dt:g} s): {reason}; {its} iterations, residual {rn:.3e} (tolerance {tol:.3e})")
            raise _StepFailure(msg, t_a, its, rn, cause)
        st.n_cuts += 1
        t_m = t_a + 0.5 * (t_b - t_a)
        self._advance(t_a, t_m, level + 1)
        self._advance(t_m, t_b, level + 1)

    def _attempt(self, t_a, t_b, level):
        """One step from the current state (at t_a) to t_b. Returns (ok, info)."""
        st = self._state
        cfg = self.cfg
        nf = self.nf
        dofs = self.dofs
        h = st.dt / (1 << level)
        ops = self._ops_cache.get(h) or self._ops(h)
        if st.in_first_bracket:
            st.in_first_bracket = False
        else:
            nf.begin_step(t_a, h)
        fe1 = self.f_ext(t_b)
        if type(fe1) is not np.ndarray or fe1.shape != st.fe_shape or fe1.dtype != np.float64:
            fe1 = self._fext(t_b)
        use_fd = cfg.tangent == "fd"
        Z = st.Z
        if st.have_J:
            Jq0, Jv0 = st.Jq_prev, st.Jv_prev
        elif use_fd and st.fd_J is not None and st.fd_h == h:
            Jq0, Jv0 = st.fd_J, Z
        else:
            Jq0, Jv0 = Z, Z
        SS, cs, V, Pm, AJ = ops.SS, ops.cs, st.V, st.Pm, st.AJ
        ok, fe1n, bn = _k_begin(st.X, ops.H, SS, dofs, fe1, st.fe0, st.f0, Jq0, Jv0, cs, V, Pm, AJ)
        if not ok:
            nf.reject_step()
            return False, (0, math.nan, math.nan, "the predictor's tangent is singular", None)
        fscale = fe1n + st.Ma_norm
        floor = 1e-13 * bn
        rtol_f, rtol_q, atol_q = cfg.rtol_force, cfg.rtol_disp, cfg.atol_disp
        tangent_linear = cfg.tangent == "linear"
        trace = [] if st.trace is not None else None
        qP, vP = st.qP, st.vP
        iq = _Q0
        rn = tol = math.nan
        reason = f"Newton did not converge in {cfg.max_iter} corrections"
        cause = None
        fd_fresh = False
        its = 0
        prev_rn = math.inf
        for k in range(cfg.max_iter + 1):
            qPe = qP.copy()
            vPe = vP.copy()
            its += 1
            try:
                f, dfq, dfv = nf.evaluate(qPe, vPe)
            except StepRejected as e:
                reason = f"the nonlinear force rejected the state ({e})"
                cause = e
                break
            f = np.array(f, dtype=np.float64)  # a copy: forces may hand back a reused buffer
            if f.shape != st.f_shape:
                self._fcheck(f)
            exact = not tangent_linear and (dfq is not None or dfv is not None)
            if exact:
                Jq = Z if dfq is None else dfq
                Jv = Z if dfv is None else dfv
                if type(Jq) is not np.ndarray or Jq.shape != st.mm:
                    Jq = self._jcheck(Jq, "df/dq")
                if type(Jv) is not np.ndarray or Jv.shape != st.mm:
                    Jv = self._jcheck(Jv, "df/dv")
            elif use_fd and st.fd_J is not None and st.fd_h == h:
                Jq, Jv = st.fd_J, Z
            else:
                Jq, Jv = Z, Z
            rn, dn, qnorm, fn, ok = _k_iter(iq, f, Jq, Jv, SS, dofs, cs, V, Pm, AJ)
            tol = rtol_f * (fscale + fn) + floor
            if trace is not None:
                trace.append(rn)
            if rn <= tol and dn <= rtol_q * qnorm + atol_q:
                # accept V[iq], the state evaluated last
                st.Ma_norm = _k_accept(st.X, iq, cs, V, self.M)
                st.t = t_b
                if cfg.alpha != 0.0:
                    st.fe0[:] = fe1
                st.f0 = f
                st.have_J = exact  # its tangent is in st.Jq_prev, st.Jv_prev (written by _k_iter)
                if use_fd and its > max(3, dofs.size):
                    # the chord iterations cost more than a new FD tangent (m evaluations)
                    st.fd_stale = True
                nf.accept_step()
                st.n_eval += its
                st.step_its += its
                if trace is not None:
                    st.trace.append(np.array(trace))
                return True, None
            if not (math.isfinite(rn) and math.isfinite(dn)):
                reason = "the residual is not finite"
                break
            if not ok:
                reason = "the Newton tangent is singular"
                break
            if k == cfg.max_iter:
                break
            if use_fd and not exact and dofs.size:
                # refresh the FD tangent when there is none for this h, after a failure, or
                # when the observed contraction predicts more chord iterations than the m
                # evaluations a new tangent costs
                need = st.fd_J is None or st.fd_h != h or (k == 0 and st.fd_stale)
                if not need and not fd_fresh and k >= 1 and rn > 0.0:
                    rho = rn / prev_rn
                    need = rho >= 1.0 or math.log(max(tol, 1e-300) / rn) / math.log(rho) > dofs.size + 1
                if need:
                    # finite-difference tangent at the current iterate, then redo the correction
                    try:
                        self._fd_tangent(qPe, vPe, f, ops.c1, h)
                    except StepRejected as e:
                        reason = f"the nonlinear force rejected a finite-difference state ({e})"
                        cause = e
                        break
                    fd_fresh = True
                    _k_iter(iq, f, st.fd_J, Z, SS, dofs, cs, V, Pm, AJ)
            prev_rn = rn
            iq = _Q0 + _Q1 - iq
        # failure: the step is abandoned
        if use_fd:
            st.fd_stale = True
        nf.reject_step()
        st.n_eval += its
        st.step_its += its
        if trace is not None:
            st.trace.append(np.array(trace))
        return False, (its, rn, tol, reason, cause)

    def _fd_tangent(self, qP0, vP0, f, c1, h):
        """Combined tangent J = df/dq + c1 df/dv at (qP0, vP0) where the force is f, by
        forward differences along q with v following v(q) = c1 q - vhat."""
        st = self._state
        m = self.dofs.size
        J = np.empty((m, m))
        for j in range(m):
            hj = self.cfg.fd_rel * max(abs(qP0[j]), self.cfg.fd_qtyp)
            qq = qP0.copy()
            vv = vP0.copy()
            qq[j] += hj
            vv[j] += c1 * hj
            fj = self._fcheck(self.nf.evaluate(qq, vv)[0])
            st.n_eval += 1
            J[:, j] = (fj - f) / hj
        st.fd_J = J
        st.fd_h = h
        st.fd_stale = False


class _RunState:
    def __init__(self, n, m, n_steps, n_out, rec, trace):
        self.X = np.zeros(3 * n)
        self.V = np.zeros((10, n))
        self.Pm = np.zeros((4, m))
        self.AJ = np.zeros((4, m, m))
        self.qP, self.vP = self.Pm[0], self.Pm[1]
        self.fe0 = np.zeros(n)
        self.f0 = np.zeros(m)
        self.fe_shape = (n,)
        self.f_shape = (m,)
        self.Jq_prev, self.Jv_prev = self.AJ[2], self.AJ[3]  # views: _k_iter writes them
        self.Z = np.zeros((m, m))
        self.mm = (m, m)
        self.have_J = False
        self.fd_J = None
        self.fd_h = None
        self.fd_stale = True
        self.rec = rec
        self.rec_all = rec.size == n and bool(np.all(rec == np.arange(n)))
        self.out_t = np.zeros(n_out)
        self.out_q = np.zeros((n_out, rec.size))
        self.out_v = np.zeros((n_out, rec.size))
        self.out_f = np.zeros((n_out, m))
        self.iters = np.zeros(n_steps, dtype=np.int32)
        self.step_its = 0
        self.n_rec = 0
        self.steps_done = 0
        self.n_cuts = 0
        self.n_eval = 0
        self.Ma_norm = 0.0
        self.trace = [] if trace else None
        self.in_first_bracket = False


class _StepFailure(Exception):
    def __init__(self, message, t, iterations, residual, cause):
        super().__init__(message)
        self.message = message
        self.t = t
        self.iterations = iterations
        self.residual = residual
        self.cause = cause


# =============================================================================== conveniences

def integrate(M, K, q0, v0, t_span: tuple[float, float], dt: float, *, C=None, G=None, omega: float = 0.0,
              f_ext=None, nodal_force=None, config: NewmarkConfig | None = None, **run_kw) -> NewmarkResult:
    """One-call form of ``Newmark(M, K, C, G, omega, f_ext, nodal_force, config).run(...)``."""
    return Newmark(M, K, C=C, G=G, omega=omega, f_ext=f_ext, nodal_force=nodal_force,
                   config=config).run(q0, v0, t_span[0], t_span[1], dt, **run_kw)


def static_equilibrium(K, f_static, nodal_force: NodalForce | Sequence[NodalForce] | None, q0, *,
                       t: float = 0.0, rtol: float = 1e-10, xtol: float = 1e-10, atol_x: float = 0.0,
                       max_iter: int = 50, max_backtracks: int = 30, fd_rel: float = 1.5e-8,
                       fd_qtyp: float = 1e-6) -> np.ndarray:
    """Solve K q = f_static + P^T f_nl(P q, 0) by damped Newton (backtracking line search on
    ||R||; a state the force rejects with StepRejected shortens the step).

    The tangent is K - P^T df/dq P (finite differences if evaluate returns no df/dq); K alone
    may be singular (a free shaft held only by its bearings). Converged when
    ||R|| <= rtol (||f_static|| + ||f_nl|| + ||K q||) and the Newton step
    ||dq|| <= xtol ||q|| + atol_x. Evaluations are bracketed by begin_step(t, 0.0) and
    accept_step() (reject_step() on failure). Returns q; raises EquilibriumError."""
    K = np.asarray(K, dtype=float)
    n = K.shape[0]
    fs = np.asarray(f_static, dtype=float).reshape(n)
    if nodal_force is None:
        nf = _NoForce()
    elif isinstance(nodal_force, (list, tuple)):
        nf = CompositeForce(nodal_force)
    else:
        nf = nodal_force
    dofs = _as_dofs(nf.dofs)
    m = dofs.size
    q = np.array(q0, dtype=float).reshape(n)
    zero_v = np.zeros(m)

    def ev(qq):
        f, dfq, _ = nf.evaluate(qq[dofs].copy(), zero_v.copy())
        f = np.array(f, dtype=float).reshape(m)  # copies: forces may reuse their buffers
        if dfq is not None:
            dfq = np.array(dfq, dtype=float).reshape(m, m)
        R = K @ qq - fs
        R[dofs] -= f
        return R, f, dfq

    def fail(msg, qq, rn, it):
        nf.reject_step()
        raise EquilibriumError(msg, q=qq, residual=rn, iterations=it)

    nf.begin_step(t, 0.0)
    try:
        R, f, dfq = ev(q)
    except StepRejected as e:
        fail(f"static equilibrium: the start q0 was rejected by the nonlinear force ({e})", q, math.nan, 0)
    rn = float(np.linalg.norm(R))
    fs_n = float(np.linalg.norm(fs))
    for it in range(max_iter + 1):
        if not math.isfinite(rn):
            fail(f"static equilibrium: non-finite residual after {it} iterations", q, rn, it)
        T = K.copy()
        if m:
            if dfq is None:
                J = np.empty((m, m))
                for j in range(m):
                    hj = fd_rel * max(abs(q[dofs[j]]), fd_qtyp)
                    qq = q.copy()
                    qq[dofs[j]] += hj
                    try:
                        try:
                            fj = np.array(nf.evaluate(qq[dofs].copy(), zero_v.copy())[0], dtype=float)
                        except StepRejected:  # one-sided the other way
                            qq[dofs[j]] -= 2 * hj
                            hj = -hj
                            fj = np.array(nf.evaluate(qq[dofs].copy(), zero_v.copy())[0], dtype=float)
                    except StepRejected as e:
                        fail(f"static equilibrium: finite differences at iteration {it} rejected ({e})", q, rn, it)
                    J[:, j] = (fj - f) / hj
            else:
                J = np.asarray(dfq, dtype=float).reshape(m, m)
            T[np.ix_(dofs, dofs)] -= J
        try:
            dq = np.linalg.solve(T, -R)
            if not np.all(np.isfinite(dq)):
                raise np.linalg.LinAlgError
        except np.linalg.LinAlgError:
            fail(f"static equilibrium: singular tangent at iteration {it} (residual {rn:.3e}); "
                 "is every rigid-body motion held by a force?", q, rn, it)
        scale = fs_n + float(np.linalg.norm(f)) + float(np.linalg.norm(K @ q))
        dn = float(np.linalg.norm(dq))
        if rn <= rtol * scale and dn <= xtol * float(np.linalg.norm(q)) + atol_x:
            if m and dfq is None:
                ev(q)  # leave the force evaluated at the accepted state, not at a perturbed one
            nf.accept_step()
            return q
        if it == max_iter:
            break
        lam = 1.0
        for _ in range(max_backtracks + 1):
            q_try = q + lam * dq
            try:
                R_try, f_try, dfq_try = ev(q_try)
                rn_try = float(np.linalg.norm(R_try))
                if math.isfinite(rn_try) and rn_try <= (1.0 - 1e-4 * lam) * rn:
                    break
                if math.isfinite(rn_try) and dn <= 4 * np.finfo(float).eps * float(np.linalg.norm(q)):
                    break  # stagnation at round-off: take the step and let the test above decide
            except StepRejected:
                pass
            lam *= 0.5
        else:
            fail(f"static equilibrium: line search failed at iteration {it} (residual {rn:.3e}, "
                 f"tolerance {rtol * scale:.3e})", q, rn, it)
        q, R, f, dfq, rn = q_try, R_try, f_try, dfq_try, rn_try
    fail(f"static equilibrium did not converge in {max_iter} iterations (residual {rn:.3e}, "
         f"tolerance {rtol * scale:.3e})", q, rn, max_iter)
