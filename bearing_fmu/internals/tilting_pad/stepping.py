"""The pads' states carried through a transient: each pad's tilt (and, with inertia, its rate)
integrated over the host's time step together with the journal, so the force has the pads'
history (their squeeze, their inertia) and not only their quasi-static equilibrium.

The host's step protocol (``rotor_host.integrate.forces.NodalForce``): ``begin_step(dt)``, then
evaluations at the journal's state at the END of the step (y, z, vy, vz), then ``accept_step``
(the last evaluation's pads become the state) or another ``begin_step`` (a rejected step is
redone from the committed state). dt = 0 is a static evaluation: the pads massless and in moment
equilibrium (``PadAssembly.equilibrate``), which also becomes the state a run starts from.

The scheme, per pad, the pads coupled only through the journal (the state x = delta, w = its rate):

    delta_1 = h_delta + b w_1,        I (w_1 - h_w) = b M(y, z, vy, vz, delta_1, w_1),

BDF2 with variable steps (h = dt, rho = h / h_prev: b = h (1 + rho) / (1 + 2 rho), h_x = ((1 + rho)^2
x_0 - rho^2 x_-1) / (1 + 2 rho)); the first step after a static evaluation is backward Euler (b = h,
h_x = x_0). Why BDF2 and not the host's trapezoidal rule: it is L-stable, so a pad's own fast
motion (massless: the pad's relaxation; light: its rate, decaying at C_pp / I) is damped out and not
rung at the Nyquist frequency, and with I -> 0 the inertia equation becomes exactly the massless
one, M(delta_1, w_1) = 0: light pads tend to massless pads step by step. Second order, as the host.

Each pad is one scalar Newton on delta_1, w_1 = (delta_1 - h_delta) / b: r(delta_1) = I (w_1 - h_w) -
b M, r' = I / b - b M_delta - M_w > 0 (the moment falls with the tilt and with its rate: a pad's
squeeze), warm-started from delta_0 + h w_0 and kept inside the tilts that leave its film open
(bisection where a step would leave them). The journal force's derivatives for the host's Newton are
total, the pads following: d delta_1 / dq = b M_q / r', dF/dq = F_q + (F_delta + F_w / b) d delta_1 / dq
(the same with v).

A flexible pivot (``pivot_stiffness_N_m``) adds each pad's radial displacement u (massless: the film's
load on the pivot balances k_p u at every instant, its squeeze through du/dt), stepped by the same BDF2,
u_1 = h_u + b du_1 (h_u from u_0 and u_-1 as h_delta): per pad a 2 x 2 Newton on (delta_1, u_1),

    r_1 = I (w_1 - h_w) - b M,     r_2 = -b Q = -b (P - k_p u_1),     P = F' . s the pivot's load,

with the Jacobian's columns d/d delta_1 = d/d delta + (1 / b) d/dw and d/du_1 = d/du + (1 / b) d/d(du/dt),
a step halved until the pad's film stays open; the journal force's total derivatives follow from the
same 2 x 2 (d(delta_1, u_1)/dq = -R^-1 dr/dq).
"""

from __future__ import annotations

import math

import numpy as np

from ..base import BearingStateError, check_finite
from .assembly import PadAssembly, PadSolution

NEWTON_MAX = 60


class PadStepper:
    """The pads' committed state (tilts ``delta`` [rad], rates ``rate`` [rad/s]) of ``assembly``, and
    the step being tried (``begin_step``, ``solve``, ``accept``)."""

    def __init__(self, assembly: PadAssembly):
        self.A = assembly
        n = assembly.n
        self.delta, self.rate = np.zeros(n), np.zeros(n)
        self.prev = None  # (delta, rate, dt) the step before the committed one: BDF2's history
        self.dt_committed = 0.0  # the step that led to the committed state (0: a static one)
        self.dt = 0.0
        self.trial = None
        self.inertia = assembly.pads.inertia
        self.flexible = assembly.kp is not None
        self.u, self.du = np.zeros(n), np.zeros(n)  # flexible pivots: radial displacements [m], rates [m/s]
        self.prev_u = None  # the radial displacement of BDF2's history state
        self.trial_u = None

    def begin_step(self, dt: float) -> None:
        self.dt, self.trial = float(dt), None

    def accept(self) -> None:
        if self.trial is None or self.dt <= 0.0:
            return
        # the history is the old committed state, this step (dt) before the new one (after a static state: none)
        self.prev = (self.delta, self.rate, self.dt) if self.dt_committed > 0.0 else None
        self.delta, self.rate = self.trial
        if self.flexible:
            self.prev_u = self.u if self.prev is not None else None
            self.u, self.du = self.trial_u
        self.dt_committed, self.trial = self.dt, None

    def static(self, sol: PadSolution) -> None:
        """A static evaluation: its equilibrium is the state (rates 0), history dropped."""
        self.delta, self.rate = sol.delta.copy(), np.zeros(self.A.n)
        self.prev, self.dt_committed = None, 0.0
        if self.flexible:
            self.u, self.du, self.prev_u = sol.u.copy(), np.zeros(self.A.n), None

    def state(self) -> tuple[float, ...]:
        """The committed state as floats (what an FMU state carries): (dt_committed [s], the gap from
        the history state to the committed one [s] (0: no history), tilts [rad], rates [rad/s], and that step's tilts and rates (0s
        without history)), 2 + 4 N floats. Rigid pivots (the FMUs refuse a flexible one)."""
        if self.flexible:
            raise ValueError(f"the pads' step state: pivot_stiffness_N_m = {self.A.kp:g}, a flexible pivot is not "
                             "carried by the bearing FMUs")
        n = self.A.n
        d1, w1, h1 = self.prev if self.prev is not None else (np.zeros(n), np.zeros(n), 0.0)
        return (float(self.dt_committed), float(h1), *map(float, self.delta), *map(float, self.rate),
                *map(float, d1), *map(float, w1))

    def restore(self, values) -> None:
        """The committed state from ``state()``'s floats (the step being tried dropped); ValueError
        naming what does not fit (the count, a non-finite or negative value)."""
        n = self.A.n
        try:
            v = [float(x) for x in values]
        except (TypeError, ValueError):
            raise ValueError(f"the pads' state must be {2 + 4 * n} numbers, got {values!r:.60}") from None
        if len(v) != 2 + 4 * n:
            raise ValueError(f"the pads' state has {len(v)} numbers, {n} pads need {2 + 4 * n}")
        if not all(map(math.isfinite, v)):
            raise ValueError("the pads' state has a non-finite number")
        if v[0] < 0.0 or v[1] < 0.0:
            raise ValueError(f"the pads' state has a negative step ({v[0]!r}, {v[1]!r} s)")
        a = np.array(v[2:])
        self.dt_committed = v[0]
        self.delta, self.rate = a[:n].copy(), a[n:2 * n].copy()
        self.prev = (a[2 * n:3 * n].copy(), a[3 * n:].copy(), v[1]) if v[1] > 0.0 and v[0] > 0.0 else None
        self.trial, self.dt = None, 0.0

    def coefficients(self):
        """(b, h_delta, h_rate) of the step (module docstring)."""
        h = self.dt
        if self.prev is None:
            return h, self.delta, self.rate
        d_1, w_1, h_prev = self.prev
        rho = h / h_prev
        c = 1.0 + 2.0 * rho
        return (h * (1.0 + rho) / c, ((1.0 + rho) ** 2 * self.delta - rho * rho * d_1) / c,
                ((1.0 + rho) ** 2 * self.rate - rho * rho * w_1) / c)

    def solve(self, y, z, vy, vz, omega) -> tuple[PadSolution, np.ndarray, np.ndarray]:
        """The pads at the end of the step with the journal there: (solution, dF/dq, dF/dv), the
        derivatives total (the pads following the journal)."""
        check_finite(y, z, vy, vz, omega)
        if self.flexible:
            return self._solve_flexible(y, z, vy, vz, omega)
        A, I = self.A, self.inertia
        a, n = A.arm, A.n
        b, hd, hw = self.coefficients()
        e, v = np.array([y, z], float), np.array([vy, vz], float)
        frames, delta, rate = [], np.empty(n), np.empty(n)
        dq, dv = np.zeros((2, 2)), np.zeros((2, 2))
        for k in range(n):
            t = A.t[k]
            lo, hi = A.tilt_range(k, y, z)
            if not lo < hi:
                raise A.wall_error(k, y, z)
            d = self.delta[k] + self.dt * self.rate[k]
            span = hi - lo if math.isfinite(hi - lo) else 1.0
            d = min(max(d, lo + 1e-3 * span), hi - 1e-3 * span)
            tol = 1e-13 * A.params.CR / a
            for _ in range(NEWTON_MAX):
                w = (d - hd[k]) / b
                F, Jq, Jv = A.pad(k, e, v, d, w, omega)
                r0 = A.rot[k]
                Jqb, Jvb = r0.T @ Jq @ r0, r0.T @ Jv @ r0
                M, M_d, M_w = a * F[0], a * a * Jq[0, 0], a * a * Jv[0, 0]
                r = I * (w - hw[k]) - b * M
                dr = I / b - b * M_d - M_w
                if r == 0.0 and dr == 0.0:  # the film carries nothing here: the loaded root is downstream
                    lo = d
                elif r > 0.0:
                    hi = d
                else:
                    lo = d
                step = -r / dr if dr > 0.0 else math.nan
                if abs(step) <= tol:
                    break
                nxt = d + step
                if not lo < nxt < hi:
                    nxt = 0.5 * (lo + hi)
                if abs(nxt - d) <= tol:
                    break
                d = nxt
            else:
                raise BearingStateError(f"tilting pads: the pad pivoted at {math.degrees(A.pads.pivots[k]):.4g} deg "
                                        f"found no tilt for the step in {NEWTON_MAX} Newton steps (y = {y:.4g} m, "
                                        f"z = {z:.4g} m)")
            delta[k], rate[k] = d, (d - hd[k]) / b
            frames.append((F, Jq, Jv))
            if dr > 0.0:  # the pad follows the journal: d delta / dq = b M_q / r'
                Mq, Mv = a * t @ Jqb, a * t @ Jvb
                Fd = a * Jqb @ t + a * Jvb @ t / b
                dq += np.outer(Fd, b * Mq / dr)
                dv += np.outer(Fd, b * Mv / dr)
        sol = A.assemble(frames, delta, rate)
        self.trial = (delta.copy(), rate.copy())
        return sol, sol.Jq.sum(axis=0) + dq, sol.Jv.sum(axis=0) + dv


    def _solve_flexible(self, y, z, vy, vz, omega):
        """``solve`` with each pad's radial displacement: the 2 x 2 Newton of the module docstring."""
        A, I = self.A, self.inertia
        a, n, kp = A.arm, A.n, A.kp
        b, hd, hw = self.coefficients()
        hu = self.u if self.prev is None else self._history_u()
        e, v = np.array([y, z], float), np.array([vy, vz], float)
        frames, delta, rate, u, du = [], np.empty(n), np.empty(n), np.empty(n), np.empty(n)
        dq, dv = np.zeros((2, 2)), np.zeros((2, 2))
        tol_d, tol_u = 1e-13 * A.params.CR / a, 1e-13 * A.params.CR
        for k in range(n):
            x = np.array([self.delta[k] + self.dt * self.rate[k], self.u[k] + self.dt * self.du[k]])
            lo, hi = A.tilt_range(k, y, z, float(x[1]))
            if not lo < x[0] < hi:
                x = np.array([self.delta[k], self.u[k]])
            for _ in range(NEWTON_MAX):
                F, Jq, Jv = self._pad_at(k, e, v, x, b, hd[k], hu[k], omega)
                w = (x[0] - hd[k]) / b
                r = np.array([I * (w - hw[k]) - b * a * F[0], -b * (F[1] - kp * x[1])])
                # d/d delta_1 = d/d delta + d/dw / b, d/du_1 = d/du + d/dvu / b; M = a F'_y, Q = F'_z - k_p u
                R = np.array([[I / b - b * a * a * Jq[0, 0] - a * a * Jv[0, 0], -b * a * Jq[0, 1] - a * Jv[0, 1]],
                              [-b * a * Jq[1, 0] - a * Jv[1, 0], -b * (Jq[1, 1] - kp) - Jv[1, 1]]])
                step = -np.linalg.solve(R, r)
                if abs(step[0]) <= tol_d and abs(step[1]) <= tol_u:
                    break
                alpha = 1.0
                while alpha > 1e-6:  # halved until the pad's film stays open at the new (delta, u)
                    lo, hi = A.tilt_range(k, y, z, float(x[1] + alpha * step[1]))
                    if lo < x[0] + alpha * step[0] < hi:
                        break
                    alpha *= 0.5
                else:
                    raise A.wall_error(k, y, z, float(x[0]))
                x = x + alpha * step
            else:
                raise BearingStateError(f"tilting pads: the pad pivoted at {math.degrees(A.pads.pivots[k]):.4g} deg "
                                        f"on its flexible pivot found no tilt and displacement for the step in "
                                        f"{NEWTON_MAX} Newton steps (y = {y:.4g} m, z = {z:.4g} m)")
            delta[k], u[k] = x
            rate[k], du[k] = (x[0] - hd[k]) / b, (x[1] - hu[k]) / b
            frames.append((F, Jq, Jv))
            # the pad follows the journal: d x / dq = -R^-1 dr/dq, dr/dq = -b (a M_q; Q_q) in the frame, turned back
            r0 = A.rot[k]
            dr_q = -b * np.array([a * Jq[0], Jq[1]]) @ r0
            dr_v = -b * np.array([a * Jv[0], Jv[1]]) @ r0
            dx_q, dx_v = -np.linalg.solve(R, dr_q), -np.linalg.solve(R, dr_v)
            # the pad's force on the journal at (delta_1, u_1) and their rates (1 / b of each)
            Fx = r0.T @ np.array([[a * Jq[0, 0] + a * Jv[0, 0] / b, Jq[0, 1] + Jv[0, 1] / b],
                                  [a * Jq[1, 0] + a * Jv[1, 0] / b, Jq[1, 1] + Jv[1, 1] / b]])
            dq += Fx @ dx_q
            dv += Fx @ dx_v
        sol = A.assemble(frames, delta, rate, u, du)
        self.trial, self.trial_u = (delta.copy(), rate.copy()), (u.copy(), du.copy())
        return sol, sol.Jq.sum(axis=0) + dq, sol.Jv.sum(axis=0) + dv

    def _pad_at(self, k, e, v, x, b, hd, hu, omega):
        return self.A.pad(k, e, v, float(x[0]), float((x[0] - hd) / b), omega, float(x[1]), float((x[1] - hu) / b))

    def _history_u(self):
        """BDF2's h_u: ((1 + rho)^2 u_0 - rho^2 u_-1) / (1 + 2 rho)."""
        rho = self.dt / self.prev[2]
        return ((1.0 + rho) ** 2 * self.u - rho * rho * self.prev_u) / (1.0 + 2.0 * rho)


__all__ = ["PadStepper"]
