"""Static equilibrium of a linear structure held by nonlinear nodal forces:

    K q = f_static + P^T f_nl(P q, 0),

solved by damped Newton. The host starts every scene from it (``rotor_host.scene``); the
forces are the same NodalForce objects the integrator uses (``rotor_host.forces``), their
evaluations bracketed as a static step (``begin_step(t, 0.0)``). Failure raises
``bearing_fmu.statics.EquilibriumError`` (the same class a single bearing's equilibrium raises),
with the last iterate, its residual and the iteration count.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from bearing_fmu.statics import EquilibriumError

from .forces import NodalForce, StepRejected, _as_dofs, as_nodal_force

__all__ = ["static_equilibrium"]


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
    nf = as_nodal_force(nodal_force)
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
