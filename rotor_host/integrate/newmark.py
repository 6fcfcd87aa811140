"""Implicit Newmark / HHT-alpha time integration with Newton-Raphson, for

    M a + (C + Omega G) v + K q = f_ext(t) + f_nl(q, v)            (paper eq. 1)

at constant speed Omega, or a speed Omega(t) that changes slowly (a run-up: ``omega`` a callable;
D follows it to OMEGA_RTOL). ``f_ext(t)`` is the full external force vector (unbalance, weight,
static loads); ``f_nl`` are nonlinear forces (the bearings) acting on a few DOFs through the
:class:`~rotor_host.integrate.forces.NodalForce` protocol (``rotor_host.integrate.forces``). This module knows
nothing of FMI or of any bearing model; the static equilibrium is ``rotor_host.integrate.equilibrium``.

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

where b holds everything known at the start of the step. S0 is constant for a fixed h. The
beam FE matrices are banded (4 DOFs per node, node by node: half-bandwidth 7 at any size), so
S0 is kept in band storage and factorised once per step size by a banded LU
(``rotor_host.integrate.banded``): a product or a solve costs O(n), not O(n^2) as an explicit
inverse does. The tangent S0 - (1 + alpha) P^T J P, J = df/dq + c1 df/dv, differs from S0 only
on the m nonlinear DOFs, so each Newton correction uses the Woodbury identity against the
banded factors: one banded solve, m precomputed columns W = S0^{-1} P^T and one m x m solve.
The inner linear algebra is compiled with numba (``rotor_host.integrate.newmark_kernels``).

Two drivers run the same kernels. The compiled one (``rotor_host.integrate.newmark_loop``)
runs whole chunks of steps in one numba call, Newton iterations and force evaluations
included, when the nonlinear force offers compiled kernels (``NodalForce.compiled``: the
bearing internals that have one, through the internals' registry, and memoryless native
bearing FMUs, ``rotor_host.coupling.fmu_kernel``) and the external force is
a constant or a ``RotatingLoads``; Python handles, between chunks, the recording, progress
(checkpoints, interrupts) and any step the compiled loop gives back (a rejected state, a
Newton failure, a step to cut), which it redoes from the same state. The Python driver does
everything else, one protocol call at a time.

Step cutting: when Newton fails (max_iter, non-finite residual, singular tangent) or
``evaluate`` raises :class:`~rotor_host.integrate.forces.StepRejected`, ``reject_step()`` is called and
the step is done as two half steps, recursively up to ``max_halvings`` times; outputs stay on
the user's grid.
When even the smallest step fails, :class:`IntegrationError` is raised with the partial result.
"""

from __future__ import annotations

import math
import time
from typing import Callable, Sequence

import numpy as np

from .banded import BandLU, bandwidth, is_sparse, to_band
from .forces import NodalForce, StepRejected, as_dofs, as_nodal_force
from .loads import RotatingLoads
from .newmark_data import IntegrationError, NewmarkConfig, NewmarkResult
from .newmark_kernels import StepOps
from .newmark_loop import ChunkDriver
from .newmark_record import RunState
from .newmark_step import NewtonStep

__all__ = [
    "IntegrationError",
    "NewmarkConfig",
    "NewmarkResult",
    "Newmark",
    "integrate",
]


# =============================================================================== integrator

class Newmark(NewtonStep):
    """Implicit Newmark / HHT-alpha integrator for M a + (C + omega G) v + K q = f_ext(t) + f_nl.

    M, K, C, G: (n, n) arrays, or scipy.sparse matrices (a big rotor: nothing n x n is made);
    C, G default zero;
    omega: constant speed [rad/s], or a callable t -> Omega(t) [rad/s] (a run-up);
    f_ext: callable t -> (n,) array, a constant (n,) array, or None (zero);
    nodal_force: a NodalForce, a sequence of them (combined with CompositeForce), or None.
    """

    def __init__(self, M, K, C=None, G=None, omega: float = 0.0, f_ext=None,
                 nodal_force: NodalForce | Sequence[NodalForce] | None = None,
                 config: NewmarkConfig | None = None):
        self.M = M.tocsr().astype(float) if is_sparse(M) else np.ascontiguousarray(np.asarray(M, dtype=float))
        n = self.M.shape[0]
        if self.M.shape != (n, n):
            raise ValueError(f"M must be square, got shape {self.M.shape}")
        self._sparse = is_sparse(M)
        self.K = self._mat(K, n, "K")
        self.C = self._mat(C, n, "C")
        self.G = self._mat(G, n, "G")
        # a speed that changes over the run (a run-up): D = C + Omega G is rebuilt, with the
        # step operators, whenever Omega (at the step's middle) has moved by OMEGA_RTOL
        self.omega_of_t = omega if callable(omega) else None
        self.omega = float(omega(0.0)) if callable(omega) else float(omega)
        self.D = self.C + self.omega * self.G
        self.n = n
        # band storage of everything a step touches (banded.py): O(n) per step
        self.w = w = bandwidth(self.M, self.K, self.C, self.G)
        self.MB, self.KB, self.CB, self.GB = (to_band(A, w) for A in (self.M, self.K, self.C, self.G))
        self.DB = self.CB + self.omega * self.GB
        # the external force as the compiled loop evaluates it (loads.py), None: Python only
        self._loads = f_ext if isinstance(f_ext, RotatingLoads) else None
        if f_ext is None:
            zero = np.zeros(n)
            self.f_ext = lambda t: zero
            self._loads = RotatingLoads(zero)
        elif callable(f_ext):
            self.f_ext = f_ext
        else:
            const = np.asarray(f_ext, dtype=float).reshape(n)
            self.f_ext = lambda t: const
            self._loads = RotatingLoads(const)
        if self._loads is not None and self._loads.f_static.shape != (n,):
            raise ValueError(f"f_ext has {self._loads.f_static.size} entries, expected {n}")
        self.nf = as_nodal_force(nodal_force)
        self.dofs = as_dofs(self.nf.dofs)
        if self.dofs.size and (self.dofs.min() < 0 or self.dofs.max() >= n):
            raise ValueError(f"nonlinear-force DOFs {self.dofs.tolist()} outside 0..{n - 1}")
        self.cfg = config or NewmarkConfig()
        self._ops_cache: dict[float, StepOps] = {}

    def _mat(self, A, n, name):
        if A is None:
            if self._sparse:
                import scipy.sparse as sp

                return sp.csr_matrix((n, n))
            return np.zeros((n, n))
        A = A.tocsr().astype(float) if is_sparse(A) else np.ascontiguousarray(np.asarray(A, dtype=float))
        if A.shape != (n, n):
            raise ValueError(f"{name} must have shape ({n}, {n}), got {A.shape}")
        return A

    def _ops(self, h: float) -> StepOps:
        ops = self._ops_cache.get(h)
        if ops is None:
            ops = self._ops_cache[h] = StepOps(h, self.MB, self.DB, self.KB, self.dofs, self.cfg)
        return ops

    # ------------------------------------------------------------------ public
    def run(self, q0, v0, t0: float, t_end: float, dt: float, *, record_every: int = 1,
            record_dofs=None, progress: Callable[[float], None] | None = None,
            progress_every: int | None = None, record_extra: Callable[[], np.ndarray] | None = None) -> NewmarkResult:
        """Integrate from t0 to t_end (a whole number of steps dt). Outputs every
        ``record_every`` steps at t0 + k dt; ``record_dofs`` selects the recorded DOFs
        (default all). ``progress(t)`` is called every ``progress_every`` steps (default
        ~200 calls per run) and at the end. ``record_extra()``, when given, at every record right
        after the force recorded there was evaluated (the Python driver: no compiled chunks), its
        array kept in the result's ``extra``. Raises IntegrationError with the partial result."""
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
        st = self._state = RunState(n, m, n_steps, n_out, rec, cfg.trace, cfg.tangent)
        st.t0, st.dt, st.record_every, st.extra_fn = float(t0), dt, record_every, record_extra

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
            a0 = BandLU(self.M, w=self.w, what="M").solve(rhs)
        except ValueError:
            if self._sparse:
                from scipy.sparse.linalg import spsolve

                a0 = spsolve(self.M.tocsc(), rhs)
            else:
                a0 = np.linalg.solve(self.M, rhs)
        X[2 * n:] = a0
        st.Ma_norm = float(np.linalg.norm(self.M @ a0))
        st.in_first_bracket = True
        st.record(0)

        attempt = self._attempt
        record = st.record
        iters = st.iters
        plan = self._compiled_plan() if record_extra is None else None
        if plan is not None:
            chunk = ChunkDriver(self, plan, n, rec)
        k = 0
        try:
            while k < n_steps:
                if plan is not None:
                    # compiled up to the next progress call; a step it gives back is done below
                    k_end = min(n_steps, (k // progress_every + 1) * progress_every)
                    k = chunk.run(k, k_end)
                    if k == k_end:
                        if progress is not None and k % progress_every == 0:
                            progress(t0 + k * dt)
                        continue
                t_a = t0 + k * dt
                t_b = t0 + (k + 1) * dt
                st.step_its = 0
                ok, info = attempt(t_a, t_b, 0)  # self._advance inlined: one Python call less a step
                if not ok:
                    self._cut(t_a, t_b, 0, info)
                iters[k] = st.step_its
                st.steps_done = k + 1
                if (k + 1) % record_every == 0:
                    record((k + 1) // record_every)
                if progress is not None and (k + 1) % progress_every == 0:
                    progress(t_b)
                k += 1
        except _StepFailure as fail:
            res = self._partial(status="failed", message=fail.message)
            raise IntegrationError(fail.message, res, t=fail.t, iterations=fail.iterations,
                                   residual=fail.residual,
                                   state=(st.t, X[:n].copy(), X[n:2 * n].copy(), X[2 * n:].copy())) from fail.cause
        if progress is not None and n_steps % progress_every != 0:
            progress(t0 + n_steps * dt)
        return self._partial()

    # ------------------------------------------------------------------ internals
    def _compiled_plan(self):
        """The nonlinear force's compiled kernels (``NodalForce.compiled``: (forces, omega))
        when the compiled driver can run this integration, else None: the setting is
        off, the speed varies, the residuals are traced, the tangent is built here (fd,
        linear), f_ext is not a RotatingLoads or a constant, or the force has no kernels."""
        cfg = self.cfg
        if (not cfg.compiled or self.omega_of_t is not None or cfg.trace or cfg.tangent in ("fd", "linear")
                or self._loads is None or not self.dofs.size):
            return None
        get = getattr(self.nf, "compiled", None)
        return get() if get is not None else None

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
        if st.tangent_linear or (dfq is None and dfv is None):
            st.have_J = False
            return
        st.have_J = True
        st.Jq_prev[:] = 0.0 if dfq is None else self._jcheck(dfq, "df/dq")
        st.Jv_prev[:] = 0.0 if dfv is None else self._jcheck(dfv, "df/dv")

    @property
    def started(self) -> bool:
        """True once ``run`` has recorded its initial state (a partial result exists)."""
        st = getattr(self, "_state", None)
        return st is not None and st.n_rec > 0

    def partial_result(self, status: str = "ok", message: str = "") -> NewmarkResult:
        """What the current (or last) ``run`` has recorded so far: for checkpoints and for
        keeping the result of an interrupted run."""
        return self._partial(status, message)

    def _partial(self, status="ok", message="") -> NewmarkResult:
        return self._state.result(self.dofs, time.perf_counter() - self._wall0, status, message)

    def _advance(self, t_a, t_b, level):
        ok, info = self._attempt(t_a, t_b, level)
        if not ok:
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
