"""The pads of a tilting-pad bearing around one journal: each pad's film force and moment, the
massless pads' moment equilibrium, the pads' equations of motion, the full (2 + N) x (2 + N)
coefficients and their reduction to the journal at a whirl frequency.

The film of pad k with tilt delta_k is the fixed pad's film with the journal at the equivalent
state e + a delta_k t_k, v + a ddelta_k/dt t_k (a = R + C_pad the pivot's radius, t_k the tangent at
the pivot; ``physics.bore.pads``' derivation), and the pad's moment about its pivot is
M_k = a F_k . t_k. In pad k's own frame (pivot at the bottom, t = (1, 0)) that is the partial-arc
Reynolds solver of ``pad_frame_geometry`` (below) at (y' + a delta, z', vy' + a ddelta/dt, vz'),
with M_k = a F'_y: no new film term in any kernel. The solver's adjoint Jacobian gives every
derivative: with Jq' = dF'/de', Jv' = dF'/dv' in the frame,

    dF'/d delta = a Jq'[:, 0],  dM/de' = a Jq'[0, :],  dM/d delta = a^2 Jq'[0, 0]   (the same with v).

Generalised coordinates x = (y, z, delta_1 .. delta_N), forces f = (Fy, Fz, M_1 .. M_N);
K = -df/dx, C = -df/dxdot (Lund's signs, as the 2 x 2 coefficients of the other internals).
Reduced at a whirl frequency Omega (Lund 1964's pad assembly): with Z = K + i Omega C - Omega^2 I_pad
on the pads' diagonal, Z_red = Z_jj - Z_jp Z_pp^-1 Z_pj, K_red = Re Z_red, C_red = Im Z_red / Omega.
Synchronous: Omega = omega. A pad whose film carries nothing (all cavitated: its row and column
are zero) drops out of the reduction.

Massless pads in equilibrium (``equilibrate``): M_k(delta_k) = 0 per pad (the pads are coupled only
through the journal), by Newton on delta_k with dM/d delta from the adjoint, started from the last
solution (warm) and kept inside the tilts that leave the pad's film open (the solver's own wall,
``Geometry.closure_weights``: a tilt is a journal motion along y' in the frame), bisecting where a
Newton step would leave them. The moment decreases with delta (a tilt toward the journal moves the
pressure toward the trailing edge), which the bisection uses. A tilt at which the pad's film
diverges all along (no pressure, M = 0 with dM/d delta = 0: a plateau, not the pad's equilibrium)
lies upstream of the loaded root (omega > 0: at smaller delta), so it moves the bracket's lower end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...physics.bore.geometry import Geometry
from ...physics.bore.pads import PAD_FRAME_PIVOT, PadGeometry, rotation
from ...physics.params import BearingParams
from ..base import BearingStateError, check_finite, overflow_error
from .linear import full_coefficients, quasi_static_jacobian, reduce

NEWTON_MAX = 120  # bisection from a wide bracket to 1e-13 CR / a takes ~50; Newton's steps far fewer
MIN_PAD_CELLS = 16  # default cells along a pad's arc, at least (0.3 % in K at 24, docs/geometry.md)
WALL_MARGIN = 1e-9  # the bracket stops this far (in closure) inside each pad's wall


@dataclass
class PadSolution:
    """The pads at one journal state, in the bearing's frame.

    delta, ddelta : tilts [rad] and their rates [rad/s], (N,)
    F             : total film force on the journal (Fy, Fz) [N]
    pad_F         : each pad's film force on the journal, (N, 2) [N]
    M             : each pad's moment about its pivot (about +x) [N m], (N,)
    Jq, Jv        : each pad's dF/de, dF/dv at its equivalent state, (N, 2, 2), bearing frame
    newton        : Newton iterations of the equilibrium (0 when the tilts were given)
    u, du         : flexible pivots: each pad's radial displacement [m] (outward) and its rate [m/s],
                    (N,); None with rigid pivots
    """

    delta: np.ndarray
    ddelta: np.ndarray
    F: np.ndarray
    pad_F: np.ndarray
    M: np.ndarray
    Jq: np.ndarray
    Jv: np.ndarray
    newton: int = 0
    u: np.ndarray | None = None
    du: np.ndarray | None = None

    def pivot_loads(self, s: np.ndarray) -> np.ndarray:
        """Each pad's film load on its pivot [N], outward positive: -F_k . n_k = F_k . s_k (``s`` the
        assembly's (N, 2) directions -n_k)."""
        return np.einsum("ki,ki->k", self.pad_F, s)


def pad_frame_geometry(pads: PadGeometry) -> Geometry:
    """The bore every pad is in its own frame (``physics.bore.pads``, *The pad frame*): the partial arc
    [pi - o beta, pi + (1 - o) beta], preload m about the pivot at pi. The preloaded film is the
    lobed bore's: two lobes (each 180 deg, wider than any pad) with lobe_offset = o and the first
    lobe placed so its preload point is the pivot, lobe_angle = 3 pi / 2 - o pi; the lobes'
    boundaries, pi - o pi and 2 pi - o pi, lie outside the pad, where the film is not solved."""
    o, b = pads.offset, pads.arc
    return Geometry(arc=(PAD_FRAME_PIVOT - o * b, PAD_FRAME_PIVOT + (1.0 - o) * b), lobes=2,
                    preload=pads.preload, lobe_offset=o, lobe_angle=1.5 * math.pi - o * math.pi)


class PadAssembly:
    """The pads of ``params.geometry.pads`` on the partial-arc Reynolds solver (one per pad, so each
    keeps its own warm start), ``n_theta`` cells along each pad's arc (None: the full bore's default
    resolution, 128 a turn, at least MIN_PAD_CELLS) and ``n_x`` along the length (None: the solver's
    default). Not re-entrant (the solvers hold work arrays)."""

    def __init__(self, params: BearingParams, n_theta: int | None = None, n_x: int | None = None,
                 cavitation: str = "reynolds"):
        from ...physics.solver.reynolds import Reynolds

        pg = params.geometry.pads
        if pg is None:
            raise ValueError(f"tilting pads: the bearing has no pads ([geometry] pads), its bore is the "
                             f"{params.geometry.describe()}")
        self.params, self.pads = params, pg
        self.n = pg.n
        self.kp = pg.pivot_stiffness  # [N/m]; None: rigid pivots (no radial coordinates)
        self.arm = params.R + pg.pad_clearance(params.CR)  # a = R + C_pad [m]
        frame = pad_frame_geometry(pg)
        self.pad_params = replace(params, geometry=frame)
        if n_theta is None:
            n_theta = self.default_cells(pg)
        n_theta = n_theta + len(frame.segments()[0]) - 1  # cells over the pad's arc, plus those outside it
        self.solvers = [Reynolds(self.pad_params, n_theta, n_x, cavitation) for _ in range(self.n)]
        self.rot = [rotation(pg.frame_angle(k)) for k in range(self.n)]
        self.t = np.array([r.T @ np.array([1.0, 0.0]) for r in self.rot])  # tangents at the pivots
        self.s = np.array([r.T @ np.array([0.0, 1.0]) for r in self.rot])  # -n_k: a pad's u as a journal shift
        a, b = frame.closure_weights()
        self._wa, self._wb = a, b
        self._warm = np.zeros(self.n)
        self._warm_u = np.zeros(self.n)
        self._warm_set = False  # flexible pivots: a solution to start the plain 2 x 2 Newton from

    @staticmethod
    def default_cells(pads: PadGeometry) -> int:
        """Cells along a pad's arc by default: the full bore's resolution (128 a turn), at least MIN_PAD_CELLS."""
        from ...physics.solver.reynolds import DEFAULT_N_THETA

        return max(MIN_PAD_CELLS, round(DEFAULT_N_THETA * pads.arc / (2.0 * math.pi)))

    def use_solver(self, solver) -> None:
        """Every pad from ``solver`` instead (its ``force_and_jacobian`` in the pad's frame, as the
        partial-arc Reynolds solver's: the pads' force map, ``padmap``)."""
        self.solvers = [solver] * self.n

    # ------------------------------------------------------------------ one pad
    def frame_state(self, k, e, v, delta, ddelta, u=0.0, du=0.0) -> tuple[float, float, float, float]:
        """Pad k's equivalent journal state (y', z', vy', vz') in its frame for the bearing's journal
        position e, velocity v, the pad's tilt and rate and (flexible pivot) its radial displacement
        u [m] (outward) and rate du [m/s]: the journal shifted by +u along z' (``physics.bore.pads``)."""
        r, a = self.rot[k], self.arm
        ep, vp = r @ np.asarray(e, float), r @ np.asarray(v, float)
        with np.errstate(over="ignore", invalid="ignore"):
            zp = ep[1] + u if u else ep[1]  # (rigid: z' itself, not z' + 0.0)
            vzp = vp[1] + du if du else vp[1]
            return float(ep[0] + a * delta), float(zp), float(vp[0] + a * ddelta), float(vzp)

    def _pad(self, k, e, v, delta, ddelta, omega, u=0.0, du=0.0):
        """Pad k in its frame: (F', Jq', Jv') at the equivalent state; a film beyond the float range
        is refused naming the bearing's own inputs (not the frame's)."""
        try:
            state = self.frame_state(k, e, v, delta, ddelta, u, du)
            if not all(map(math.isfinite, state)):
                raise BearingStateError("too large")
            return self.solvers[k].force_and_jacobian(*state, omega)
        except BearingStateError as exc:
            if "too large" not in str(exc):
                raise
            raise overflow_error(self.params, *(float(x) for x in (e[0], e[1], v[0], v[1], omega))) from None

    def pad(self, k, e, v, delta, ddelta, omega, u=0.0, du=0.0):
        """Pad k at its tilt and rate (and radial displacement and rate, flexible pivot) with the journal
        at e, v: (F', Jq', Jv') in the pad's frame."""
        return self._pad(k, e, v, delta, ddelta, omega, u, du)

    def assemble(self, frames, delta, ddelta, u=None, du=None) -> PadSolution:
        """The PadSolution of every pad's (F', Jq', Jv') at the given tilts and rates (and radial
        displacements and rates: flexible pivots)."""
        return self._assemble(frames, delta, ddelta, 0, u, du)

    def tilt_range(self, k: int, y: float, z: float, u: float = 0.0) -> tuple[float, float]:
        """The tilts [rad] that leave pad k's film open with the journal at (y, z) and the pad at its
        radial displacement u [m] (open interval; empty, lo >= hi, when the journal closes the film
        at the pivot, which no tilt moves)."""
        ep = self.rot[k] @ np.array([y, z])
        if u:
            ep[1] += u
        cr, a = self.params.CR * (1.0 - WALL_MARGIN), self.arm
        wa = self._wa
        with np.errstate(over="ignore", invalid="ignore"):  # a huge journal position: no room, refused below
            room = cr - wa * ep[0] - self._wb * ep[1]  # a_i (y' + a delta) + b_i z' < CR for every sample i
            up = room[wa > 0] / (wa[wa > 0] * a)
            down = room[wa < 0] / (wa[wa < 0] * a)
        if not (np.all(np.isfinite(up)) and np.all(np.isfinite(down))):
            return 0.0, 0.0
        lo = float(down.max()) if down.size else -math.inf
        hi = float(up.min()) if up.size else math.inf
        domain = getattr(self.solvers[k], "y_range", None)  # a pad solver with a domain of its own (padmap)
        if domain is not None:
            ylo, yhi = domain(float(ep[1]))
            lo, hi = max(lo, (ylo - ep[0]) / a), min(hi, (yhi - ep[0]) / a)
        if np.any((wa == 0) & (room <= 0)):
            lo, hi = 0.0, 0.0
        return lo, hi

    def wall_error(self, k: int, y: float, z: float, tilt: float | None = None) -> BearingStateError:
        """The journal at or beyond pad k's wall: whatever its tilt (None), or at the given one [rad]."""
        p = self.params
        pivot = math.degrees(self.pads.pivots[k])
        how = "whatever its tilt" if tilt is None else f"at its tilt {tilt:.4g} rad"
        return BearingStateError(
            f"eccentricity ratio {math.hypot(y, z) / p.CR:.4g}: the journal (y = {y:.4g} m, z = {z:.4g} m) closes "
            f"the film of the pad pivoted at {pivot:.4g} deg {how} (it is at or beyond that pad's wall; "
            f"CR = {p.CR:.4g} m, {self.pads.describe()})")

    def _moment_root(self, k, e, v, omega, start, u=0.0):
        """delta_k with M_k = 0 (ddelta = 0) at the pad's radial displacement u [m]: safeguarded Newton;
        returns (delta, F', Jq', Jv', iterations)."""
        lo, hi = self.tilt_range(k, e[0], e[1], u)
        if not lo < hi:
            raise self.wall_error(k, e[0], e[1])
        span = hi - lo if math.isfinite(hi - lo) else 1.0
        d = min(max(start, lo + 1e-3 * span), hi - 1e-3 * span) if math.isfinite(span) else start
        a, p = self.arm, self.params
        tol = 1e-13 * p.CR / a
        # the film's moment scale, a mu (|omega| + 2 |v| / CR) L R (R / CR)^2: below 1e-13 of it a moment is 0
        m_scale = a * p.mu * (abs(omega) + 2.0 * math.hypot(*v) / p.CR) * p.L * p.R * (p.R / p.CR) ** 2
        m_tol = 1e-13 * m_scale
        for it in range(1, NEWTON_MAX + 1):
            F, Jq, Jv = self._pad(k, e, v, d, 0.0, omega, u)
            M, dM = a * F[0], a * a * Jq[0, 0]
            if M != 0.0 and abs(M) <= m_tol:  # (M = 0 exactly may be a no-pressure plateau: below)
                return d, F, Jq, Jv, it
            if M == 0.0 and dM == 0.0:  # the pad carries nothing at this tilt: its film diverges all along
                if omega == 0.0:  # nor at any other tilt (no wedge): every tilt is an equilibrium
                    return d, F, Jq, Jv, it
                # the tilt that opens the converging (upstream) edge too far: the loaded root is downstream
                lo, hi = (d, hi) if omega > 0.0 else (lo, d)
            elif M > 0.0:
                lo = d
            else:
                hi = d
            step = -M / dM if dM < 0.0 else math.nan
            if abs(step) <= tol:  # converged at d: the step left is below the tolerance (no solve more)
                return d, F, Jq, Jv, it
            nxt = d + step
            if not (lo < nxt < hi):
                nxt = 0.5 * (lo + hi)
            if abs(nxt - d) <= tol or hi - lo <= tol:
                F, Jq, Jv = self._pad(k, e, v, nxt, 0.0, omega, u)
                if abs(a * F[0]) > 1e-8 * m_scale:  # squeezed to a wall with a moment left: no balance
                    raise BearingStateError(
                        f"tilting pads: the pad pivoted at {math.degrees(self.pads.pivots[k]):.4g} deg finds no tilt "
                        f"that balances its moment with its film open (moment {a * F[0]:.4g} N m left at the wall; "
                        f"y = {e[0]:.4g} m, z = {e[1]:.4g} m; pivot_offset = {self.pads.offset:g})")
                return nxt, F, Jq, Jv, it
            d = nxt
        raise BearingStateError(f"tilting pads: the moment of the pad pivoted at {math.degrees(self.pads.pivots[k]):.4g} "
                                f"deg did not settle in {NEWTON_MAX} Newton steps (y = {e[0]:.4g} m, z = {e[1]:.4g} m)")

    # ------------------------------------------------------------------ all pads
    def _assemble(self, frames, delta, ddelta, newton, u=None, du=None) -> PadSolution:
        a = self.arm
        pad_F = np.empty((self.n, 2))
        Jq = np.empty((self.n, 2, 2))
        Jv = np.empty((self.n, 2, 2))
        M = np.empty(self.n)
        for k, (Fp, Jqp, Jvp) in enumerate(frames):
            r = self.rot[k]
            pad_F[k] = r.T @ Fp
            Jq[k] = r.T @ Jqp @ r
            Jv[k] = r.T @ Jvp @ r
            M[k] = a * Fp[0]
        return PadSolution(np.array(delta, float), np.array(ddelta, float), pad_F.sum(axis=0), pad_F, M, Jq, Jv,
                           newton, None if u is None else np.array(u, float),
                           None if u is None else (np.zeros(self.n) if du is None else np.array(du, float)))

    def equilibrate(self, y, z, vy, vz, omega) -> PadSolution:
        """The massless pads in moment equilibrium (ddelta = 0) with the journal at (y, z, vy, vz),
        warm-started from the last call's tilts."""
        check_finite(y, z, vy, vz, omega)
        e, v = np.array([y, z], float), np.array([vy, vz], float)
        if self.kp is not None:
            return self._equilibrate_flexible(e, v, omega)
        frames, delta, its = [], np.empty(self.n), 0
        for k in range(self.n):
            d, F, Jq, Jv, it = self._moment_root(k, e, v, omega, float(self._warm[k]))
            frames.append((F, Jq, Jv))
            delta[k] = d
            its += it
        self._warm[:] = delta
        return self._assemble(frames, delta, np.zeros(self.n), its)

    def _equilibrate_flexible(self, e, v, omega) -> PadSolution:
        """Massless pads on flexible pivots: per pad M_k = 0 and Q_k = P_k - k_p u_k = 0 (``pivot_root``)."""
        frames, delta, u, its = [], np.empty(self.n), np.empty(self.n), 0
        for k in range(self.n):
            d, uk, F, Jq, Jv, it = self.pivot_root(k, e, v, omega)
            frames.append((F, Jq, Jv))
            delta[k], u[k] = d, uk
            its += it
        self._warm[:], self._warm_u[:], self._warm_set = delta, u, True
        return self._assemble(frames, delta, np.zeros(self.n), its, u)

    def pivot_root(self, k, e, v, omega):
        """Pad k on its flexible pivot in equilibrium: (delta, u, F', Jq', Jv', solver calls). First the plain
        2 x 2 Newton from the last call's (``_pivot_newton``); where it fails, the 2 x 2 Newton condensed onto u: for each u the tilt's own safeguarded root
        (``_moment_root``, warm), and the u step the 2 x 2 Newton's at that root,
        -g / g', g(u) = F'_z - k_p u, g' = Jq'_zz - k_p - a Jq'_zy a Jq'_yz / (a^2 Jq'_yy) (the pad's
        radial stiffness with its tilt following, a Schur complement). g falls with u (an outward pad
        opens its film), so a sign change brackets the root and a step outside the bracket bisects; a
        u that closes the film (inward, toward the journal) counts as g > 0 (the film's load grows
        without bound there)."""
        fast = self._pivot_newton(k, e, v, omega) if self._warm_set else None
        if fast is not None:
            return fast
        kp, CR = self.kp, self.params.CR
        u, lo, hi, its = float(self._warm_u[k]), -math.inf, math.inf, 0
        d = float(self._warm[k])
        for _ in range(NEWTON_MAX):
            try:
                d, F, Jq, Jv, it = self._moment_root(k, e, v, omega, d, u)
            except BearingStateError:
                if not math.isfinite(hi):
                    raise
                lo, u = u, 0.5 * (u + hi)  # a film closed inward: the root lies outward
                continue
            its += it
            g = F[1] - kp * u
            dg = Jq[1, 1] - kp - (Jq[1, 0] * Jq[0, 1] / Jq[0, 0] if Jq[0, 0] != 0.0 else 0.0)
            if g > 0.0:
                lo = u
            elif g < 0.0:
                hi = u
            else:
                return d, u, F, Jq, Jv, its
            step = -g / dg if dg < 0.0 else (CR if g > 0.0 else -CR)
            if abs(step) <= 1e-13 * abs(u) + 1e-15 * CR:
                return d, u, F, Jq, Jv, its
            nxt = u + step
            if not lo < nxt < hi:
                nxt = 0.5 * (lo + hi) if math.isfinite(lo) and math.isfinite(hi) else nxt
            u = nxt
        raise BearingStateError(f"tilting pads: the pad pivoted at {math.degrees(self.pads.pivots[k]):.4g} deg found "
                                f"no balance of its pivot (pivot_stiffness_N_m = {kp:g}) in {NEWTON_MAX} Newton steps "
                                f"(y = {e[0]:.4g} m, z = {e[1]:.4g} m)")

    def _pivot_newton(self, k, e, v, omega, max_steps: int = 8):
        """``pivot_root``'s fast path: the plain 2 x 2 Newton on (delta, u) from the last call's, one solve a
        step; None (the safeguarded route then) when a step leaves the open film, the pad carries nothing
        or it has not converged in ``max_steps``. Only from a previous solution: a first call takes the
        safeguarded route, whose first tilt is the rigid pivot's bracketed root (a pad's moment need not be
        monotone far from its loaded root: a force map's interpolation near the film's no-pressure tilts)."""
        a, kp, CR = self.arm, self.kp, self.params.CR
        d, u = float(self._warm[k]), float(self._warm_u[k])
        tol_d = 1e-13 * CR / a
        for it in range(1, max_steps + 1):
            lo, hi = self.tilt_range(k, e[0], e[1], u)
            if not lo < d < hi:
                return None
            F, Jq, Jv = self._pad(k, e, v, d, 0.0, omega, u)
            if F[0] == 0.0 and F[1] == 0.0:
                return None
            R = np.array([[a * a * Jq[0, 0], a * Jq[0, 1]], [a * Jq[1, 0], Jq[1, 1] - kp]])
            try:
                step = -np.linalg.solve(R, np.array([a * F[0], F[1] - kp * u]))
            except np.linalg.LinAlgError:
                return None
            if abs(step[0]) <= tol_d and abs(step[1]) <= 1e-13 * abs(u) + 1e-15 * CR:
                return d, u, F, Jq, Jv, it
            d, u = d + float(step[0]), u + float(step[1])
        return None

    def at_tilts(self, y, z, vy, vz, omega, delta, ddelta, u=None, du=None) -> PadSolution:
        """The pads at given tilts and rates (the pads' own states: ``derivatives``), and with flexible
        pivots at the given radial displacements and rates."""
        check_finite(y, z, vy, vz, omega)
        e, v = np.array([y, z], float), np.array([vy, vz], float)
        frames = []
        for k in range(self.n):
            uk, duk = (0.0, 0.0) if u is None else (float(u[k]), float(du[k]))
            lo, hi = self.tilt_range(k, y, z, uk)
            if not lo < delta[k] < hi:
                raise self.wall_error(k, y, z, None if not lo < hi else float(delta[k]))
            frames.append(self._pad(k, e, v, float(delta[k]), float(ddelta[k]), omega, uk, duk))
        return self._assemble(frames, delta, ddelta, 0, u, du)

    # ------------------------------------------------------------------ coefficients
    def coefficients(self, sol: PadSolution) -> tuple[np.ndarray, np.ndarray]:
        """The full K and C at a solution (``linear.full_coefficients``): (2 + N) x (2 + N), or with flexible
        pivots (2 + 2N) x (2 + 2N); Lund's signs."""
        return full_coefficients(self, sol)

    def coordinate_count(self) -> int:
        """2 + N (rigid pivots) or 2 + 2N (flexible: each pad's radial displacement too)."""
        return 2 + (2 * self.n if self.kp is not None else self.n)

    def coordinate_names(self) -> list[str]:
        """The full coefficients' coordinates, with units."""
        names = ["y [m]", "z [m]"] + [f"delta_{k + 1} [rad]" for k in range(self.n)]
        return names + ([f"u_{k + 1} [m]" for k in range(self.n)] if self.kp is not None else [])

    def coordinate_inertia(self) -> np.ndarray:
        """Each internal coordinate's inertia: the pads' moment of inertia [kg m^2] on the tilts, 0 on
        the radial displacements (the pad's mass is not modelled: massless on its pivot spring)."""
        tilts = np.full(self.n, self.pads.inertia)
        return tilts if self.kp is None else np.concatenate([tilts, np.zeros(self.n)])

    def reduce(self, K: np.ndarray, C: np.ndarray, whirl: float) -> tuple[np.ndarray, np.ndarray]:
        """The journal's 2 x 2 K [N/m] and C [N s/m] at whirl frequency ``whirl`` [rad/s] > 0, the pads'
        coordinates condensed (``linear.reduce``)."""
        return reduce(self, K, C, whirl)

    def quasi_static_jacobian(self, sol: PadSolution) -> tuple[np.ndarray, np.ndarray]:
        """dF/dq, dF/dv [N/m, N s/m] with the massless pads re-equilibrated (``linear.quasi_static_jacobian``)."""
        return quasi_static_jacobian(self, sol)

    # ------------------------------------------------------------------ pad dynamics
    def state_size(self) -> int:
        """Length of the pads' state vector: (delta, ddelta/dt) per pad with inertia, delta alone
        for massless pads."""
        return 2 * self.n if self.pads.inertia > 0.0 else self.n

    def derivatives(self, state, y, z, vy, vz, omega) -> tuple[np.ndarray, np.ndarray, PadSolution]:
        """(journal force F [N], d state / dt, the pads' solution) for the pads' state vector.

        With inertia I: state = (delta_1..N, ddelta_1..N), d/dt = (ddelta, M / I).
        Massless: state = delta, and ddelta solves M_k(delta_k, ddelta_k) = 0 per pad (the pad's
        squeeze balances the moment): Newton on ddelta, dM/d ddelta = a^2 Jv'[0, 0] < 0.
        Rigid pivots only (the FMUs' Model Exchange states; a flexible pivot's radial states are carried
        in the host's steps, ``stepping``)."""
        if self.kp is not None:
            raise ValueError(f"[geometry] pivot_stiffness_N_m = {self.kp:g}: the pads' Model Exchange states "
                             "(derivatives) are for rigid pivots; a flexible pivot is carried by the host's "
                             "steps (run) and the linear analyses, not by the FMUs")
        state = np.asarray(state, float)
        n, a = self.n, self.arm
        if self.pads.inertia > 0.0:
            delta, rate = state[:n], state[n:]
            sol = self.at_tilts(y, z, vy, vz, omega, delta, rate)
            return sol.F, np.concatenate([rate, sol.M / self.pads.inertia]), sol
        delta, rate = state, np.zeros(n)
        e, v = np.array([y, z], float), np.array([vy, vz], float)
        sol = self.at_tilts(y, z, vy, vz, omega, delta, rate)
        for k in range(n):
            for _ in range(NEWTON_MAX):
                t = self.t[k]
                M, dM = sol.M[k], a * a * t @ sol.Jv[k] @ t
                if dM >= 0.0:
                    break  # no squeeze (the pad carries nothing): no rate is determined by it
                step = -M / dM
                rate[k] += step
                Fp, Jqp, Jvp = self._pad(k, e, v, float(delta[k]), float(rate[k]), omega)
                r = self.rot[k]
                sol.pad_F[k], sol.Jq[k], sol.Jv[k], sol.M[k] = r.T @ Fp, r.T @ Jqp @ r, r.T @ Jvp @ r, a * Fp[0]
                if abs(step) <= 1e-12 * (abs(rate[k]) + omega * self.params.CR / a):
                    break
        sol.ddelta = rate.copy()
        sol.F = sol.pad_F.sum(axis=0)
        return sol.F, rate, sol


__all__ = ["PadAssembly", "PadSolution", "pad_frame_geometry"]
