"""Static equilibrium of a linear structure held by nonlinear nodal forces:

    K q = f_static + P^T f_nl(P q, 0),

solved by damped Newton. The host starts every scene from it (``rotor_host.scenes.scene``); the
forces are the same NodalForce objects the integrator uses (``rotor_host.integrate.forces``), their
evaluations bracketed as a static step (``begin_step(t, 0.0)``). Failure raises
``bearing_fmu.physics.statics.EquilibriumError`` (the same class a single bearing's equilibrium raises),
with the last iterate, its residual and the iteration count. Before it blames Newton, a failure
checks whether a bearing is simply asked for more than it carries (``bearing_overload``): then
the error names that bearing, its static load and its load capacity near the wall.

An answer is physical or it is refused (``RotorNotSupported``, a bad input): given the
structure's rigid-body motions, a rotor whose bearings sit at one place only (a journal bearing
takes no moment) is refused before any iteration, and a converged state only when its journals
lie inside their clearances and the bearing forces balance the loads (forces and moments, to
``BALANCE_RTOL``). Newton's round-off acceptance alone does not suffice: it grows with |q|, and
a step that throws an unsupported shaft kilometres away passes it.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from bearing_fmu.physics.statics import (CAPACITY_ECCENTRICITY, EquilibriumError, capacity_message,
                                         format_newtons, journal_at_eccentricity)

from .banded import BandLU, bandwidth, is_sparse, to_band
from .forces import NodalForce, StepRejected, as_dofs, as_nodal_force

__all__ = ["static_equilibrium", "pinned_loads", "solve_part", "bearing_overload", "RotorNotSupported",
           "support_check", "placement_refusal", "BALANCE_RTOL"]

# the bearing forces of an accepted state balance the loads' resultant (forces, and moments about
# x = 0) to this fraction of the sum of the magnitudes that enter it (a true equilibrium: ~1e-12)
BALANCE_RTOL = 1e-6

# the round-off of R = K q - f in units of eps times its scale (a row of a beam's K sums ~8-16
# terms); a residual below it is as small as R can be computed, and the Newton step from it is
# that round-off amplified by the tangent's conditioning, not an error estimate of q
ROUNDOFF = 32.0 * np.finfo(float).eps


class RotorNotSupported(EquilibriumError, ValueError):
    """The bearings cannot hold the rotor (all at one place), or the state Newton accepted lies
    outside their reach (a journal outside its clearance, forces that do not balance the loads):
    the rotor and its loads are the input to change (exit code 2), no solver setting is."""


def _newtons(x: float) -> str:
    return format_newtons(abs(x))


def _names(nf, n: int) -> list[str]:
    names = getattr(nf, "names", None)
    return list(names) if names is not None and len(names) == n else [f"bearing {k + 1}" for k in range(n)]


def placement_refusal(rigid: np.ndarray, fs: np.ndarray, dofs: np.ndarray, names: list[str]) -> str | None:
    """Why the bearings cannot hold the rotor, before any iteration: none at all, or all at one
    axial place (each holds y and z only, so a tilt about that place is free). None if they can."""
    if dofs.size == 0:
        return "static equilibrium: the rotor is not supported: it has no bearing"
    if np.linalg.matrix_rank(rigid[dofs]) == rigid.shape[1]:
        return None
    x_b = float(np.mean(rigid[dofs[0::2], 2]))  # the bearings' common x (the slope mode's y there)
    Fy, Fz, My, Mz = rigid.T @ fs
    load = math.hypot(Fy, Fz)
    moment = math.hypot(My - x_b * Fy, Mz - x_b * Fz)
    who = f"{names[0]} is its only support" if len(names) == 1 else f"{', '.join(names)} sit at one place"
    return (f"static equilibrium: the rotor is not supported: {who} (x = {x_b * 1e3:.6g} mm): a journal bearing "
            f"takes no moment, so the {_newtons(load)} load (weight and static loads) with its moment of "
            f"{moment:.3g} N m about that place has nothing to hold it; a shaft on journal bearings needs "
            "bearings at two places at least")


def support_check(q, f, fs, dofs, rigid, names, clearances=None) -> str | None:
    """Why the state q (bearing forces f on ``dofs``, loads fs) is not a supported rotor, or None:
    a journal outside its clearance (``clearances`` [m] per bearing, None: not known), or bearing
    forces that do not balance the loads' resultant (``rigid``: the structure's rigid-body
    motions as columns, translations y, z and slopes in the x-y, x-z planes; None: not checked)
    to BALANCE_RTOL of the magnitudes that enter it."""
    n = dofs.size // 2
    if clearances is not None and len(clearances) == n:
        for k, c in enumerate(clearances):
            e = math.hypot(q[dofs[2 * k]], q[dofs[2 * k + 1]]) / c if c else math.nan
            if c and not e < 1.0:
                return (f"static equilibrium: no state within the bearings' reach: {names[k]} has its journal at "
                        f"eccentricity ratio {e:.3g}, outside its clearance of {c * 1e6:.4g} um (the rotor is not "
                        "held by its films there)")
    if rigid is None:
        return None
    fb = np.zeros(fs.size)
    fb[dofs] = f
    load, held = rigid.T @ fs, rigid.T @ fb
    ra = np.abs(rigid).T
    scale = ra @ np.abs(fs) + ra @ np.abs(fb)
    rest = load + held
    off = [math.hypot(*rest[:2]) > BALANCE_RTOL * (scale[0] + scale[1]),  # forces [N]
           math.hypot(*rest[2:]) > BALANCE_RTOL * (scale[2] + scale[3])]  # moments [N m]
    if not any(off):
        return None
    carried = [_newtons(math.hypot(f[2 * k], f[2 * k + 1])) for k in range(n)]
    each = "; ".join(f"{nm} {c}" for nm, c in zip(names, carried))
    total = _newtons(math.hypot(held[0], held[1]))
    if off[0]:
        what = (f"{names[0]} carries {carried[0]}" if n == 1 else f"the bearings carry {total} ({each})")
        return (f"static equilibrium: the rotor is not supported: {what} of {_newtons(math.hypot(load[0], load[1]))} "
                f"(weight and static loads; the forces must balance to {BALANCE_RTOL:g} of them)")
    return (f"static equilibrium: the rotor is not supported: the bearing forces ({each}) leave "
            f"{math.hypot(*rest[2:]):.3g} N m of the loads' moment {math.hypot(*load[2:]):.3g} N m about "
            f"x = 0 unbalanced (to {BALANCE_RTOL:g} of them)")


def pinned_loads(K, f_static, dofs) -> np.ndarray:
    """Static load [N] on each (y, z) pair of ``dofs``: the reactions of the structure pinned
    at those DOFs under ``f_static`` (K q = f + r, q = 0 there), as loads on the journal (-r),
    shape (len(dofs) // 2, 2). On two bearings a shaft is statically determinate, so these are
    the film forces at any equilibrium. Raises numpy's LinAlgError if the pinned structure is
    not held (a free part)."""
    if not is_sparse(K):
        K = np.asarray(K, dtype=float)
    fs = np.asarray(f_static, dtype=float).reshape(K.shape[0])
    dofs = np.asarray(dofs, dtype=int)
    free = np.setdiff1d(np.arange(K.shape[0]), dofs)
    q = np.zeros(K.shape[0])
    if free.size:
        q[free] = solve_part(K, free, fs[free])
    return -(K @ q - fs)[dofs].reshape(-1, 2)


def solve_part(K, idx, rhs) -> np.ndarray:
    """x = K[idx, idx]^{-1} rhs, dense or (a sparse K) by a sparse LU; numpy's LinAlgError when
    that part of K is singular."""
    if not is_sparse(K):
        return np.linalg.solve(K[np.ix_(idx, idx)], rhs)
    import warnings

    from scipy.sparse.linalg import MatrixRankWarning, spsolve

    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            x = spsolve(K.tocsr()[idx][:, idx].tocsc(), rhs)
        except MatrixRankWarning:
            raise np.linalg.LinAlgError("singular matrix") from None
    if not np.all(np.isfinite(x)):
        raise np.linalg.LinAlgError("singular matrix")
    return x


def bearing_overload(K, f_static, bearings) -> dict | None:
    """The bearing asked for more than it carries at eccentricity ``CAPACITY_ECCENTRICITY``
    (the largest load / capacity ratio), or None when every bearing carries its static load or
    it cannot be told: ``bearings`` is not a bearing set (``rotor_host.coupling.bearings.BearingSet``:
    ``names``, ``omega``, ``clearances`` [m]), the structure pinned at the bearings is not held,
    or the force refuses the probe. The capacities come from one evaluation of the force with
    every journal at that eccentricity, placed to push back against its load
    (``journal_at_eccentricity``); call it inside a static ``begin_step`` bracket. Returns
    {"bearing", "load_N", "capacity_N", "speed_hz", "others"} with ``others`` the other
    overloaded bearings as (name, load_N, capacity_N)."""
    names = getattr(bearings, "names", None)
    omega = getattr(bearings, "omega", None)
    clearances = getattr(bearings, "clearances", None)
    dofs = as_dofs(bearings.dofs)
    n = dofs.size // 2
    if names is None or omega is None or clearances is None or len(names) != n or len(clearances) != n \
            or any(c is None for c in clearances):
        return None
    try:
        loads = pinned_loads(K, f_static, dofs)
    except np.linalg.LinAlgError:
        return None
    w = np.hypot(loads[:, 0], loads[:, 1])
    if omega == 0.0:
        caps = np.zeros(n)
    else:
        probe = np.array([journal_at_eccentricity(loads[k], omega, CAPACITY_ECCENTRICITY, clearances[k])
                          for k in range(n)]).reshape(-1)
        try:
            f = np.array(bearings.evaluate(probe, np.zeros(2 * n))[0], dtype=float).reshape(n, 2)
        except (StepRejected, ValueError, RuntimeError, ArithmeticError):  # no diagnosis, not a second failure
            return None
        caps = np.hypot(f[:, 0], f[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(w > caps, w / caps, 0.0)
    over = [int(k) for k in np.argsort(-ratio, kind="stable") if ratio[k] > 0.0]  # ties: first bearing first
    if not over:
        return None
    k = over[0]
    return {"bearing": names[k], "load_N": float(w[k]), "capacity_N": float(caps[k]),
            "speed_hz": float(f"{omega / (2.0 * math.pi):.12g}"),  # 22, not 21.999999999999996
            "others": [(names[j], float(w[j]), float(caps[j])) for j in over[1:]]}


def _overload_message(d: dict, newton: str) -> str:
    """One line: the overloaded bearing(s) first, then what Newton did."""
    msg = "static equilibrium: " + capacity_message(d["bearing"], d["load_N"], d["capacity_N"], d["speed_hz"])
    for name, w, cap in d["others"]:
        carries = f"at most ~{format_newtons(cap)}, " if d["speed_hz"] != 0.0 else ""
        msg += f" (also {name}: {carries}asked for {format_newtons(w)})"
    return f"{msg}; no equilibrium found: {newton}"


def static_equilibrium(K, f_static, nodal_force: NodalForce | Sequence[NodalForce] | None, q0, *,
                       t: float = 0.0, rtol: float = 1e-10, xtol: float = 1e-10, atol_x: float = 0.0,
                       max_iter: int = 50, max_backtracks: int = 30, fd_rel: float = 1.5e-8,
                       fd_qtyp: float = 1e-6, rigid_modes=None) -> np.ndarray:
    """Solve K q = f_static + P^T f_nl(P q, 0) by damped Newton (backtracking line search on
    ||R||; a state the force rejects with StepRejected shortens the step).

    The tangent is K - P^T df/dq P (finite differences if evaluate returns no df/dq); K alone
    may be singular (a free shaft held only by its bearings). It is solved as the banded
    K + s P^T P, factorised once, with the bearings' coupling as a rank-m correction
    (``_Tangent``: O(n) per iteration at any size; K dense or scipy.sparse). Converged when
    ||R|| <= rtol (||f_static|| + ||f_nl|| + ||K q||) and the Newton step
    ||dq|| <= xtol ||q|| + atol_x, or when ||R|| is at its round-off,
    ||R|| <= ROUNDOFF (||f_static|| + ||f_nl|| + || |K| |q| ||). R sums terms of the sizes
    |K| |q| (entrywise), not of their sum K q: a finely cut shaft has stiff elements (EI / L^3),
    so K q is the sum of large terms that cancel to the small load, and its round-off grows
    with them (eps || |K| |q| ||; Higham, Accuracy and Stability of Numerical Algorithms,
    sec. 7.1, the componentwise backward error) until it passes the first test's tolerance
    (the paper rotor cut into 160 elements: residual floor 9.2e-9, tolerance 8.1e-9). At that
    floor the Newton step is the round-off amplified by the tangent's conditioning (a fine mesh:
    about 1e-8 of ||q||), which no iteration can make smaller: q is as good as R can tell.
    Evaluations are bracketed by begin_step(t, 0.0) and accept_step()
    (reject_step() on failure). ``rigid_modes`` (n, 4), the structure's rigid-body motions
    (``Rotor.rigid_modes``): bearings all at one place are refused before any iteration, and a
    converged q only when its bearing forces balance the loads (``support_check``; a bearing set
    with ``clearances`` also has its journals checked inside them, with or without rigid_modes).
    Returns q; raises EquilibriumError, RotorNotSupported where no state within the bearings'
    reach is found."""
    if not is_sparse(K):
        K = np.asarray(K, dtype=float)
    n = K.shape[0]
    fs = np.asarray(f_static, dtype=float).reshape(n)
    nf = as_nodal_force(nodal_force)
    dofs = as_dofs(nf.dofs)
    m = dofs.size
    names = _names(nf, m // 2)
    rigid = None if rigid_modes is None else np.asarray(rigid_modes, dtype=float).reshape(n, -1)
    if rigid is not None:
        why = placement_refusal(rigid, fs, dofs, names)
        if why is not None:
            raise RotorNotSupported(why)
    q = np.array(q0, dtype=float).reshape(n)
    zero_v = np.zeros(m)
    absK = abs(K)
    tangent = _Tangent(K, dofs)

    def ev(qq):
        f, dfq, _ = nf.evaluate(qq[dofs].copy(), zero_v.copy())
        f = np.array(f, dtype=float).reshape(m)  # copies: forces may reuse their buffers
        if dfq is not None:
            dfq = np.array(dfq, dtype=float).reshape(m, m)
        R = K @ qq - fs
        R[dofs] -= f
        return R, f, dfq

    def fail(msg, qq, rn, it):
        # a load beyond a bearing's capacity explains any failure below better than Newton does
        d = bearing_overload(K, fs, nf)
        nf.reject_step()
        if d is None:
            raise EquilibriumError(msg, q=qq, residual=rn, iterations=it)
        raise EquilibriumError(_overload_message(d, msg.removeprefix("static equilibrium: ")), q=qq, residual=rn,
                               iterations=it, bearing=d["bearing"], load_N=d["load_N"], capacity_N=d["capacity_N"],
                               speed_hz=d["speed_hz"])

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
        J = None
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
        try:
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # singular: refused below
                dq = tangent.solve(J, -R)
            if not np.all(np.isfinite(dq)):
                raise np.linalg.LinAlgError
        except (np.linalg.LinAlgError, ValueError):
            fail(f"static equilibrium: singular tangent at iteration {it} (residual {rn:.3e}); "
                 "is every rigid-body motion held by a force?", q, rn, it)
        fn = float(np.linalg.norm(f))
        scale = fs_n + fn + float(np.linalg.norm(K @ q))
        dn = float(np.linalg.norm(dq))
        if (rn <= rtol * scale and dn <= xtol * float(np.linalg.norm(q)) + atol_x
                or rn <= ROUNDOFF * (fs_n + fn + float(np.linalg.norm(absK @ np.abs(q))))):
            if m and dfq is None:
                ev(q)  # leave the force evaluated at the accepted state, not at a perturbed one
            why = support_check(q, f, fs, dofs, rigid, names, getattr(nf, "clearances", None))
            if why is not None:
                nf.reject_step()
                raise RotorNotSupported(why, q=q, residual=rn, iterations=it)
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
    fail(f"static equilibrium: no convergence in {max_iter} iterations (residual {rn:.3e}, "
         f"tolerance {rtol * scale:.3e})", q, rn, max_iter)


class _Tangent:
    """Solves (K - P^T J P) x = b for the Newton tangent without widening K's band to the bearing
    DOFs (a dense solve on a long shaft with bearings at both ends): with springs s at the
    bearing DOFs, A = K + s P^T P is banded like K and holds every rigid-body motion, so it is
    factorised once (``banded.BandLU``, pivoting LAPACK if that finds a tiny pivot); then
    K - P^T J P = A - P^T (J + s I) P, and with W = A^{-1} P^T and x0 = A^{-1} b
    (Woodbury; the transient step's tangent is solved the same way, ``newmark``):

        x = x0 + W (J + s I) y,   (I - P W (J + s I)) y = P x0   (an m x m solve).

    s is the scale of the first tangent J (the bearings' own stiffness, so the m x m system is
    as well conditioned as the tangent), else K's largest diagonal entry."""

    def __init__(self, K, dofs):
        self.K, self.dofs, self.m = K, dofs, dofs.size
        self.w = bandwidth(K)
        self.solve_A = None

    def _factor(self, J):
        m, dofs, w = self.m, self.dofs, self.w
        AB = to_band(self.K, w)
        s = float(np.max(np.abs(J))) if J is not None and m else 0.0
        if not (s > 0.0 and math.isfinite(s)):
            s = float(np.max(np.abs(AB[:, w])))
        self.s = s
        AB[dofs, w] += s
        try:
            self.solve_A = BandLU(AB, w, "K + s P^T P", band=True).solve
        except ValueError:  # a tiny pivot without pivoting: LAPACK's banded LU with pivoting
            import scipy.linalg as sla

            ab = _lapack_from_rows(AB)
            self.solve_A = lambda b: sla.solve_banded((w, w), ab, b, check_finite=False)
        if m:
            E = np.zeros((self.K.shape[0], m))
            E[dofs, np.arange(m)] = 1.0
            self.W = self.solve_A(E)
            self.PW = self.W[dofs]

    def solve(self, J, b):
        if self.solve_A is None:
            self._factor(J)
        x0 = self.solve_A(b)
        if not self.m:
            return x0
        Cm = (np.zeros((self.m, self.m)) if J is None else J) + self.s * np.eye(self.m)
        y = np.linalg.solve(np.eye(self.m) - self.PW @ Cm, x0[self.dofs])
        return x0 + self.W @ (Cm @ y)


def _lapack_from_rows(B):
    """LAPACK's band storage ab[w + i - j, j] of the row-wise band storage B[i, j - i + w]."""
    n, width = B.shape
    w = (width - 1) // 2
    ab = np.zeros((width, n))
    for d in range(-w, w + 1):
        if d >= 0:
            ab[w - d, d:] = B[:n - d, w + d]
        else:
            ab[w - d, :n + d] = B[-d:, w + d]
    return ab
