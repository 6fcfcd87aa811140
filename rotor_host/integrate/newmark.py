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

Predictor: the nonlinear force is linearised about the last accepted state with its last
tangent, and the linearised step is solved exactly. With linear forces (or none) the predictor
is the answer and a step costs one force evaluation.

Convergence, per evaluated iterate q_k: ||R(q_k)|| <= rtol_force * force_scale and
||dq_k|| <= rtol_disp * ||q_k|| + atol_disp, where dq_k is the Newton correction at q_k (its
error estimate) and force_scale = ||f_ext(t1)|| + ||f_nl(q_k)|| + ||M a0||. The accepted state is
always the last one evaluated: a NodalForce sees ``accept_step()`` right after the
``evaluate()`` of the accepted iterate.

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
from .newmark_kernels import Q0, Q1, StepOps, k_accept, k_begin, k_iter
from .newmark_loop import ChunkDriver
from .newmark_record import RunState

OMEGA_RTOL = 1e-3  # a varying speed rebuilds D = C + Omega G when Omega has moved by this fraction

__all__ = [
    "IntegrationError",
    "NewmarkConfig",
    "NewmarkResult",
    "Newmark",
    "integrate",
]


# =============================================================================== integrator

class Newmark:
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

    def _attempt(self, t_a, t_b, level):
        """One step from the current state (at t_a) to t_b: the predictor, then Newton
        iterations (evaluate the force at the iterate, residual and correction, convergence
        test) until an evaluated iterate passes the test and is accepted, or the step is
        abandoned. Returns (True, None) or (False, (iterations, residual, tolerance, reason,
        cause))."""
        st = self._state
        cfg = self.cfg
        dofs = self.dofs
        h = st.dt / (1 << level)
        if self.omega_of_t is not None:
            self._follow_speed(0.5 * (t_a + t_b))
        ops = self._ops_cache.get(h) or self._ops(h)
        ok, fe1, fe1n, bn = self._predict(t_a, t_b, h, ops)
        if not ok:
            self.nf.reject_step()
            return False, (0, math.nan, math.nan, "the predictor's tangent is singular", None)
        # converged: ||R|| <= rtol_force (||f_ext(t_b)|| + ||M a0|| + ||f_nl||) + floor
        # and ||dq|| <= rtol_disp ||q|| + atol_disp
        fscale = fe1n + st.Ma_norm
        floor = 1e-13 * bn
        rtol_f, rtol_q, atol_q = cfg.rtol_force, cfg.rtol_disp, cfg.atol_disp
        SB, W, cs, V, Pm, AJ = ops.SB, ops.W, ops.cs, st.V, st.Pm, st.AJ
        trace = [] if st.trace is not None else None
        qP, vP = st.qP, st.vP
        iq = Q0  # the row of V holding the iterate
        rn = tol = math.nan
        reason = f"Newton did not converge in {cfg.max_iter} corrections"
        cause = None
        fd_fresh = False
        its = 0
        prev_rn = math.inf
        for k in range(cfg.max_iter + 1):
            # the force at the iterate, given fresh copies (the force may keep them)
            qPe = qP.copy()
            vPe = vP.copy()
            its += 1
            try:
                f, Jq, Jv, exact = self._evaluate(qPe, vPe, h)
            except StepRejected as e:
                reason = f"the nonlinear force rejected the state ({e})"
                cause = e
                break
            # residual, Newton correction, and the next iterate in the other row of V
            rn, dn, qnorm, fn, ok = k_iter(iq, f, Jq, Jv, SB, W, dofs, cs, V, Pm, AJ)
            # the convergence test: accept the iterate just evaluated, or see why Newton stops
            tol = rtol_f * (fscale + fn) + floor
            if trace is not None:
                trace.append(rn)
            if rn <= tol and dn <= rtol_q * qnorm + atol_q:
                self._accept(iq, t_b, cs, fe1, f, exact, its, trace)
                return True, None
            if not (math.isfinite(rn) and math.isfinite(dn)):
                reason = "the residual is not finite"
                break
            if not ok:
                reason = "the Newton tangent is singular"
                break
            if k == cfg.max_iter:
                break
            if st.use_fd and not exact and dofs.size and self._fd_tangent_due(k, h, rn, prev_rn, tol, fd_fresh):
                # a finite-difference tangent at the iterate, then the correction again with it
                try:
                    self._fd_tangent(qPe, vPe, f, ops.c1, h)
                except StepRejected as e:
                    reason = f"the nonlinear force rejected a finite-difference state ({e})"
                    cause = e
                    break
                fd_fresh = True
                k_iter(iq, f, st.fd_J, st.Z, SB, W, dofs, cs, V, Pm, AJ)
            prev_rn = rn
            iq = Q0 + Q1 - iq
        self._abandon(its, trace)
        return False, (its, rn, tol, reason, cause)

    def _follow_speed(self, t: float) -> None:
        """A varying speed: D = C + Omega(t) G and the step operators follow it once it has
        moved by OMEGA_RTOL (the gyroscopic term then lags by less than that fraction)."""
        om = float(self.omega_of_t(t))
        if abs(om - self.omega) > OMEGA_RTOL * max(abs(self.omega), 1.0):
            self.omega = om
            self.D = self.C + om * self.G
            self.DB = self.CB + om * self.GB
            self._ops_cache.clear()

    def _predict(self, t_a, t_b, h, ops):
        """Open the step (``begin_step``, except for the first step, whose bracket is already
        open), the external force at t_b, and the predictor: the step solved with the force
        linearised about the last accepted state with its last tangent (the force's own, else
        the finite-difference one for this h, else none). The predictor is the first iterate,
        in V[Q0] and (qP, vP). Returns (ok, f_ext(t_b), ||f_ext(t_b)||, ||b||); not ok: the
        predictor's tangent is singular."""
        st = self._state
        if st.in_first_bracket:
            st.in_first_bracket = False
        else:
            self.nf.begin_step(t_a, h)
        fe1 = self.f_ext(t_b)
        if type(fe1) is not np.ndarray or fe1.shape != st.fe_shape or fe1.dtype != np.float64:
            fe1 = self._fext(t_b)
        Z = st.Z
        if st.have_J:
            Jq0, Jv0 = st.Jq_prev, st.Jv_prev
        elif st.use_fd and st.fd_J is not None and st.fd_h == h:
            Jq0, Jv0 = st.fd_J, Z
        else:
            Jq0, Jv0 = Z, Z
        ok, fe1n, bn = k_begin(st.X, ops.MDK, ops.SB, ops.W, self.dofs, fe1, st.fe0, st.f0, Jq0, Jv0, ops.cs,
                                st.V, st.Pm, st.AJ)
        return ok, fe1, fe1n, bn

    def _evaluate(self, qPe, vPe, h):
        """The nonlinear force at the iterate (qPe, vPe) and the tangent of its Newton correction:
        the derivatives the force returns (unless tangent = "linear"), else the finite-difference
        tangent for this h (tangent = "fd"), else none (zero: the linear tangent). Returns
        (f, Jq, Jv, exact), exact = the force's own derivatives; StepRejected passes through."""
        st = self._state
        f, dfq, dfv = self.nf.evaluate(qPe, vPe)
        f = np.array(f, dtype=np.float64)  # a copy: forces may hand back a reused buffer
        if f.shape != st.f_shape:
            self._fcheck(f)
        Z = st.Z
        if not st.tangent_linear and (dfq is not None or dfv is not None):
            Jq = Z if dfq is None else dfq
            Jv = Z if dfv is None else dfv
            if type(Jq) is not np.ndarray or Jq.shape != st.mm:
                Jq = self._jcheck(Jq, "df/dq")
            if type(Jv) is not np.ndarray or Jv.shape != st.mm:
                Jv = self._jcheck(Jv, "df/dv")
            return f, Jq, Jv, True
        if st.use_fd and st.fd_J is not None and st.fd_h == h:
            return f, st.fd_J, Z, False
        return f, Z, Z, False

    def _accept(self, iq, t_b, cs, fe1, f, exact, its, trace):
        """The iterate in V[iq], the state evaluated last, becomes the state at t_b."""
        st = self._state
        st.Ma_norm = k_accept(st.X, iq, cs, st.V, self.MB)
        st.t = t_b
        if self.cfg.alpha != 0.0:
            st.fe0[:] = fe1
        st.f0 = f
        st.have_J = exact  # its tangent is in st.Jq_prev, st.Jv_prev (written by k_iter)
        if st.use_fd and its > max(3, self.dofs.size):
            # the chord iterations cost more than a new FD tangent (m evaluations)
            st.fd_stale = True
        self.nf.accept_step()
        st.n_eval += its
        st.step_its += its
        if trace is not None:
            st.trace.append(np.array(trace))

    def _abandon(self, its, trace):
        """The step failed after ``its`` evaluations: the force hears ``reject_step``."""
        st = self._state
        if st.use_fd:
            st.fd_stale = True
        self.nf.reject_step()
        st.n_eval += its
        st.step_its += its
        if trace is not None:
            st.trace.append(np.array(trace))

    def _fd_tangent_due(self, k, h, rn, prev_rn, tol, fd_fresh):
        """Whether to build a new finite-difference tangent at iteration k: when there is none
        for this h, after a failure, or when the observed contraction predicts more chord
        iterations than the m evaluations a new tangent costs."""
        st = self._state
        m = self.dofs.size
        need = st.fd_J is None or st.fd_h != h or (k == 0 and st.fd_stale)
        if not need and not fd_fresh and k >= 1 and rn > 0.0:
            rho = rn / prev_rn
            need = rho >= 1.0 or math.log(max(tol, 1e-300) / rn) / math.log(rho) > m + 1
        return need

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
