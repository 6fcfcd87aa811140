"""One step of the Newmark integrator (``rotor_host.integrate.newmark``) in Python: the predictor,
the Newton iterations with the force's protocol calls, the acceptance or abandonment of the step,
a speed that follows a profile, and the finite-difference tangent. ``NewtonStep`` holds these
methods of ``Newmark``; the compiled driver (``newmark_loop``) makes the same decisions with
the same kernels.

Predictor: the nonlinear force is linearised about the last accepted state with its last
tangent, and the linearised step is solved exactly. With linear forces (or none) the predictor
is the answer and a step costs one force evaluation.

Convergence, per evaluated iterate q_k: ||R(q_k)|| <= rtol_force * force_scale and
||dq_k|| <= rtol_disp * ||q_k|| + atol_disp, where dq_k is the Newton correction at q_k (its
error estimate) and force_scale = ||f_ext(t1)|| + ||f_nl(q_k)|| + ||M a0||. The accepted state is
always the last one evaluated: a NodalForce sees ``accept_step()`` right after the
``evaluate()`` of the accepted iterate.
"""

from __future__ import annotations

import math

import numpy as np

from .forces import StepRejected
from .newmark_kernels import Q0, Q1, k_accept, k_begin, k_iter

OMEGA_RTOL = 1e-3  # a varying speed rebuilds D = C + Omega G when Omega has moved by this fraction

__all__ = ["NewtonStep", "OMEGA_RTOL"]


class NewtonStep:
    """The step methods of ``Newmark`` (its state: ``self._state``, settings ``self.cfg``, the
    force ``self.nf`` at ``self.dofs``)."""

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
