"""Finite-volume Reynolds solver for a journal bearing (a plain cylindrical bore, or grooved, partial, lobed).

Equation (DESIGN.md, paper eq. 2 with the circumferential length R*theta)::

    (1/R^2) d/dth(h^3 dp/dth) + d/dx(h^3 dp/dx) = 6 mu omega dh/dth + 12 mu dh/dt
    h = CR + y sin(th) - z cos(th),   dh/dt = vy sin(th) - vz cos(th)

theta periodic, x in [-L/2, L/2] with p = 0 at both ends. Force on the journal
F = int p (sin th, -cos th) R dth dx.

Discretization (see docs/reynolds.md)
-------------------------------------
Cell-centred finite volumes, ``n_theta`` cells around the circumference (centres at
th_i = i * 2 pi / n_theta, faces half-way) and ``n_x`` cells along the length. The equation
is integrated over each cell (in th, x): diffusive fluxes use h^3 evaluated at the face
(th faces: h(th_{i+1/2}); x faces: h(th_i)); the Couette and squeeze sources are integrated
exactly over the cell, so the right-hand side is
b_i = -dx [6 mu omega (h_{i+1/2} - h_{i-1/2}) + 12 mu int_cell dh/dt dth], the same for all
axial cells of a column. With no misalignment p is symmetric in x, so only the half x < 0
is solved (m = n_x / 2 axial cells, zero flux at x = 0).

End faces (p = 0): the flux uses the second-order one-sided gradient of the quadratic
through p = 0 at the end and the first two cell centres, (9 p0 - p1) / (3 dx), instead of
the first-order p0 / (dx / 2); row 0 is scaled by 3/4 so that A stays symmetric (its axial
part becomes 3 p0 - p1; a positive row scaling changes neither the solution nor the LCP).
The force uses the midpoint sum in theta and, along x, the midpoint sum with the
Euler-Maclaurin end correction -(dx^2/24) p'(end) (weights 7/8 dx and 73/72 dx for the two
cells next to the end). Together these cut the axial error at n_x = 8 from 3 % (half-cell
Dirichlet + plain midpoint sum) to 0.1 %, see docs/reynolds.md.

Written as A p = b, A is a symmetric, irreducibly diagonally dominant M-matrix. Unknowns
are ordered axial-fastest, which makes A a periodic banded matrix of half-bandwidth m.

Linear solver: banded Cholesky of the first n_theta - 1 columns plus a bordered last column
(the periodic wrap), O(n_theta m^3), in numba. When some theta column is entirely cavitated
the ordering starts right after it and the border decouples (plain banded Cholesky).

Cavitation
----------
"reynolds": Swift-Stieber as the linear complementarity problem p >= 0, A p - b >= 0,
p (A p - b) = 0, solved exactly by a primal-dual active-set method (Hintermueller, Ito &
Kunisch 2003, SIAM J. Optim. 13:865): on the active (cavitated) set p = 0, on the rest
A p = b is solved directly; the sets are updated from the sign of p and of the multiplier
A p - b until they repeat. For an M-matrix this terminates in finitely many steps
(monotonically after the first) from any start, in at most n + 1 passes (the method is the
Newton-min iteration; Ben Gharbia & Gilbert 2009, INRIA RR-7160, recall the bound), each pass
one banded Cholesky factorization.

Start. Cold: computed from the inputs only (cavitated where the cell source b <= 0, less a
margin of n_theta/16 columns on either side of the positive-source arc), 3-9 passes. Warm
(the default, ``warm_start=True``): the cavitated set of the last converged call, moved by
extrapolating w = p - (A p - b) (p on free cells, minus the multiplier on cavitated ones)
linearly through the last call and an earlier one; 1-2 passes when the state moves little
between calls, as between the Newton iterates and time steps of a transient. The cold start
is used instead when the source direction is more than WARM_MAX_TURN_CELLS cells from the one
expected (the last call's, extrapolated like w) or |ln(1 - eps)| changed by more than
WARM_MAX_DLOG since the last call (beyond that a warm start took more passes than the cold
one), and a warm start not settled within n_theta/16 + 4 passes is abandoned for the cold
start. Whatever the start, the LCP's unique solution comes
out, and with the same converged set the last pass factors the same matrix, so results do not
depend on the call history: bit for bit in every sequence measured (docs/studies,
2026-11-24). Only a cell degenerate to round-off (p and A p - b both ~0) could settle on
either side; the force would then differ at round-off and the Jacobian take the other
one-sided value.
"gumbel": the full (uncavitated) system, then p < 0 clipped to 0 (half-Sommerfeld).

Derivatives
-----------
With the converged active set fixed, A(q) p = b(q, v) on the free nodes, so
dF_a/ds = w_a^T A^-1 (db/ds - dA/ds p) = mu_a^T (db/ds - dA/ds p) with the adjoint
mu_a = A^-1 w_a (A symmetric): two extra back-substitutions with the existing
factorization give all eight derivatives (equivalent to the four direct solves
dp = A^-1 (db - dA p)). For "gumbel" w_a is masked to the positive-pressure nodes and
dA p uses the unclipped pressure. Where the source vanishes identically (journal centred and
still, or whirling at exactly half speed) p = 0 and the force is only directionally
differentiable; there the derivative reported is the odd part (F(db) - F(-db)) / 2 of the
first-order film response, which is what central differences converge to.

Bores other than the full circle
--------------------------------
With ``params.geometry`` not the full bore (grooves, a partial arc, lobes: ``physics.bore.geometry``),
the circumferential cells have a face on every groove edge, arc edge and lobe boundary
(``Geometry.theta_grid``: one cell per groove and per stretch outside the arc, the rest spread
over the film), the film is h / CR = H0(theta) + (y sin - z cos) / CR with the lobes' centred
film H0, and the cells of a groove (supply pressure) or outside the arc (ambient) hold their
prescribed pressure: identity rows, their value on the shared face of the neighbouring film
cell (a half-cell distance). Cavitation, the warm start and the adjoint derivatives are as
above (``geometry_kernels``); the full bore keeps its own kernel, bit for bit.

Work arrays and the remembered calls live in the object: one Reynolds instance is not
re-entrant (use one per thread); copying or pickling it copies them too.

Long calls. A fine grid's call is one compiled call of minutes (2048 x 256: ~2 s per active-set
pass, 30-50 passes), and Python runs a signal's handler only between bytecodes. A grid whose
pass costs about LONG_CALL_WORK (n_theta (n_x / 2)^3, the banded factorization's work) or more
runs its kernel in a worker thread with the GIL released (``_released``), while the calling
thread waits in short timed joins: Ctrl-C's KeyboardInterrupt (or the command line's
``Interrupted``) is raised in the caller at once, the abandoned call runs to its end in the
background at the lowest priority (it dies with the process; the same instance's next call
waits for it). The same compiled kernel runs either way, so the results are the same bit for
bit; below that grid size the kernel is called directly, as before, through two checks of
0.7 us in all (a call at the default grid: ~0.3 ms; benchmarks/bench_long_calls.py).
"""

from __future__ import annotations

import math
import os
import threading

import numpy as np
from numba import njit

from ...internals.registry import check_state, overflow_error
from .film import FilmReport, edge_flows, field_report, flow_field, peak_pressure
from ..params import BearingParams
from .geometry_kernels import geometry_kernel
from .lands import axial_stencil, has_lands, land_cells
from .reynolds_kernels import reynolds_kernel

__all__ = ["Reynolds", "DEFAULT_N_THETA", "DEFAULT_N_X", "CAVITATION_MODELS"]

# Default grid, from the convergence study in docs/reynolds.md (benchmarks/bench_reynolds.py).
DEFAULT_N_THETA = 128
DEFAULT_N_X = 16
CAVITATION_MODELS = ("reynolds", "gumbel")
_MODE = {"gumbel": 0, "reynolds": 1}
# Warm start (docs/studies/2026-11-24-reynolds-warm-start.md): converged calls remembered, and
# the cold start whenever the source direction is more than WARM_MAX_TURN_CELLS theta cells
# from the one expected or |ln(1 - eps)| changed by more than WARM_MAX_DLOG since the last
# call (beyond these a warm start took more passes than the cold one on average).
WARM_HISTORY = 4
WARM_MAX_TURN_CELLS = 2.0
WARM_MAX_DLOG = 1.0
# n_theta (n_x / 2)^3 from which a call runs in a worker thread (module docstring, "Long calls"):
# 512 x 64 (~50 ms a warm call, seconds cold); the default 128 x 16 is 128 times below it
LONG_CALL_WORK = 2**23
JOIN_POLL_S = 0.1  # the caller's timed joins: a signal's handler runs between them (also on Windows)


# the kernels with the GIL released, for a worker thread; they forward to the same compiled code
@njit(nogil=True, cache=True)
def _reynolds_released(*args):
    reynolds_kernel(*args)


@njit(nogil=True, cache=True)
def _geometry_released(*args):
    geometry_kernel(*args)


_RELEASED = {reynolds_kernel: _reynolds_released, geometry_kernel: _geometry_released}


def _lowest_priority(thread) -> None:
    """Nice 19 for ``thread`` alone (Linux: a thread id is a process id to setpriority); elsewhere
    nothing. An interrupted long call keeps its core until its kernel returns: at normal priority
    it slowed the interpreter's exit by ~1 s on a loaded 2-core machine."""
    try:
        os.setpriority(os.PRIO_PROCESS, thread.native_id, 19)
    except (AttributeError, OSError):
        pass


# ----------------------------------------------------------------------------------------
# the internal
# ----------------------------------------------------------------------------------------


def _check_grid(name: str, value, minimum: int, even: bool):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"Reynolds: {name} must be an integer, got {value!r}")
    value = int(value)
    rule = f"an even integer >= {minimum}" if even else f"an integer >= {minimum}"
    if value < minimum or (even and value % 2):
        raise ValueError(f"Reynolds: {name} must be {rule}, got {value}")
    if value > 100_000:
        raise ValueError(f"Reynolds: {name} = {value} is unreasonably large (at most 100000)")
    return value


class Reynolds:
    """Finite-volume Reynolds solver: the truth internal.

    Reynolds(params, n_theta=None, n_x=None, cavitation="reynolds")

    n_theta : cells around the circumference (integer >= 8), default DEFAULT_N_THETA
    n_x     : cells along the bearing length (even integer >= 2; the half x < 0 is solved),
              default DEFAULT_N_X
    cavitation : "reynolds" (Swift-Stieber, exact complementarity) or "gumbel"
              (half-Sommerfeld: full solution clipped at 0)
    warm_start : start the active-set method from the last converged calls' cavitated set
              (reynolds cavitation; the result is the same whatever the start, see the
              module docstring); False = always the cold start computed from the inputs.
              ``counts()`` sums calls and passes; ``forget()`` drops what was remembered.
    """

    def __init__(self, params: BearingParams, n_theta: int | None = None, n_x: int | None = None,
                 cavitation: str = "reynolds", warm_start: bool = True):
        if not isinstance(params, BearingParams):
            raise TypeError(f"Reynolds: params must be a BearingParams, got {type(params).__name__}")
        if not isinstance(cavitation, str) or cavitation.lower() not in CAVITATION_MODELS:
            raise ValueError(
                f"Reynolds: cavitation must be one of {', '.join(repr(c) for c in CAVITATION_MODELS)}, "
                f"got {cavitation!r}"
            )
        if params.geometry.pads is not None:  # each pad is a partial arc of this solver (internals.tilting_pad)
            raise ValueError(f"Reynolds: the bore is tilting pads ({params.geometry.describe()}): the film moves with "
                             "the pads; solve each pad as a partial arc (the tilting_pad internal)")
        params.geometry.require_placed("Reynolds")
        self.params = params
        self.n_theta = _check_grid("n_theta", DEFAULT_N_THETA if n_theta is None else n_theta, 8, False)
        self.n_x = _check_grid("n_x", DEFAULT_N_X if n_x is None else n_x, 2, True)
        self.cavitation = cavitation.lower()
        self._mode = _MODE[self.cavitation]
        N, m = self.n_theta, self.n_x // 2
        self._m = m
        self._dth = 2.0 * math.pi / N
        # the axial cells: the half length, or one land of a circumferential groove (physics.solver.lands)
        self._dx, self._x = land_cells(params, self.n_x)
        self._p_in = params.geometry.supply_pressure if has_lands(params) else 0.0
        th = np.arange(N) * self._dth
        thf = th + 0.5 * self._dth
        self._theta = th
        self._sin_c, self._cos_c = np.sin(th), np.cos(th)
        self._sin_f, self._cos_f = np.sin(thf), np.cos(thf)
        self._grid = None  # the bore's ThetaGrid (set by _bore); None: uniform cells of the full bore
        self._geo = None if params.geometry.is_full_bore else self._bore(params, N)
        # differences of face values: exactly h_{i+1/2} - h_{i-1/2} and the squeeze integral
        self._ds = self._sin_f - np.roll(self._sin_f, 1)
        self._dc = self._cos_f - np.roll(self._cos_f, 1)
        # axial stencil (in units of h^3 dth / dx), half domain from the end (j = 0) to the
        # symmetry plane (j = m - 1, zero flux), or a land to the groove's edge (p = p_s). End face:
        # second-order one-sided flux from the quadratic through p = 0 at the end and the first two
        # cell centres, (9 p0 - p1) / (3 dx); row 0 is scaled by rs0 = 3/4 to keep A symmetric, which
        # leaves the axial row as 3 p0 - p1 (the LCP is unchanged by a positive row scaling).
        td, rs, qw = axial_stencil(m, self._dx, has_lands(params))
        self._tdiag, self._rs, self._qw = td, rs, qw
        n = N * m
        f = np.zeros
        self._at, self._ax, self._b, self._dat, self._dax = f(N), f(N), f(N), f(N), f(N)
        self._diag, self._cxo, self._cto = f(n), f(n), f(n)
        self._act = np.zeros(n, dtype=np.bool_)
        self._Lb = f(((N - 1) * m, m + 1))
        self._Y = f(((N - 1) * m, m))
        self._S = f((m, m))
        self._zb, self._z2 = f((N - 1) * m), f(m)
        self._p, self._pf, self._rhs, self._tmp = f(n), f(n), f(n), f(n)
        self._mu_y, self._mu_z = f(n), f(n)
        self._F, self._dFq, self._dFv, self._Ft = f(2), f((2, 2)), f((2, 2)), f(2)
        self._db = f((4, N))
        self._info = f(6)
        self._max_iter = 4 * n + 10
        self._grow = max(1, int(round(N / 16)))
        self.warm_start = bool(warm_start)
        # warm start (see reynolds_kernels.warm_start_set): the last WARM_HISTORY converged calls, and the limits
        # beyond which the cold start is used (measured, docs/studies/2026-11-24-reynolds-warm-start.md)
        self._hs = f((WARM_HISTORY, 4))
        self._order = np.arange(WARM_HISTORY, dtype=np.int64)
        self._nvalid = np.zeros(1, dtype=np.int64)
        self._wring = f((WARM_HISTORY, n))
        self._max_turn = min(WARM_MAX_TURN_CELLS * self._dth, math.pi)
        self._warm_cap = self._grow + 4
        self._solved = None  # the state of the last converged solve (film_report reads its field)
        self._long = self.n_theta * m ** 3 >= LONG_CALL_WORK
        self._worker = None  # a long call's thread while it runs (see _released)
        self.reset_counts()

    def _bore(self, params: BearingParams, N: int) -> dict:
        """Grid and film of a bore that is not the full circle (``physics.bore.geometry``): cells with
        faces on its edges replace the uniform ones (theta, sin, cos at centres and faces), and
        the arrays of ``geometry_kernels.geometry_kernel``."""
        try:
            grid = params.geometry.theta_grid(N)
        except ValueError as exc:
            raise ValueError(f"Reynolds: {exc}") from None
        R, w = params.R, grid.width
        self._grid = grid
        self._theta = grid.centre
        self._sin_c, self._cos_c = np.sin(grid.centre), np.cos(grid.centre)
        self._sin_f, self._cos_f = np.sin(grid.right), np.cos(grid.right)
        safe = np.where(grid.dist > 0.0, grid.dist, 1.0)
        return {
            "H0f": grid.face_film, "H0c": grid.centre_film, "dH0": grid.dfilm,
            # face coefficient dx / (R^2 dist) (0 between two fixed cells), cell one dth / dx
            "ct": np.where(grid.dist > 0.0, self._dx / (R * R * safe), 0.0), "cx": w / self._dx,
            # force weights of a film cell over both halves of the length: 2 R (sin, -cos) width
            "gy": 2.0 * R * w * self._sin_c, "gz": -2.0 * R * w * self._cos_c,
            "fixed": grid.fixed.astype(np.bool_), "psup": grid.supply,
            "F0": grid.supply_force(R, params.L), "rhs0": np.zeros(N * (self.n_x // 2)),
        }

    @classmethod
    def from_options(cls, params: BearingParams, options, context=None) -> "Reynolds":
        """From the registry's checked options (``internals.REGISTRY["reynolds"]``; grid 0 = default)."""
        return cls(params, n_theta=options["n_theta"] or None, n_x=options["n_x"] or None,
                   cavitation=options["cavitation"])

    def __repr__(self) -> str:
        return (f"Reynolds({self.params!r}, n_theta={self.n_theta}, n_x={self.n_x}, "
                f"cavitation={self.cavitation!r})")

    # -- warm start and counters ------------------------------------------------------------
    def forget(self) -> None:
        """Drop the remembered calls: the next call starts cold (results do not change)."""
        self._nvalid[0] = 0

    def reset_counts(self) -> None:
        """Zero the call and pass counters of ``counts``."""
        self._n_calls = 0
        self._n_passes = 0
        self._n_warm = 0
        self._n_fallback = 0

    def counts(self) -> dict:
        """Counters since construction or ``reset_counts``: calls, banded factorizations
        (active-set passes) in all, calls started warm, warm starts abandoned for the cold start."""
        return {"calls": self._n_calls, "passes": self._n_passes, "warm_starts": self._n_warm,
                "cold_fallbacks": self._n_fallback}

    def _count(self) -> None:
        self._n_calls += 1
        self._n_passes += int(self._info[3])
        self._n_warm += bool(self._info[4])
        self._n_fallback += bool(self._info[5])

    def _released(self, kernel):
        """``kernel`` for this grid: itself, or for a long call (``LONG_CALL_WORK``) a function that
        runs it in a worker thread with the GIL released and waits for it in timed joins, so a
        signal's handler runs in the caller within JOIN_POLL_S (module docstring, "Long calls")."""
        if not self._long:
            return kernel
        raised = []

        def work(*args):
            try:
                _RELEASED[kernel](*args)
            except BaseException as exc:  # noqa: BLE001 - handed to the caller, as a direct call would raise it
                raised.append(exc)

        def call(*args):
            self._worker = threading.Thread(target=work, args=args, daemon=True, name="reynolds-long-call")
            self._worker.start()
            self._wait()
            if raised:
                raise raised[0]

        return call

    def _wait(self) -> None:
        """Until the long call's thread has ended (an interrupted call's, too: it still writes the
        work arrays), in timed joins that a signal's handler can end."""
        worker = self._worker
        try:
            while worker is not None and worker.is_alive():
                worker.join(JOIN_POLL_S)
        except BaseException:
            _lowest_priority(worker)  # abandoned: what the caller does next (its exit, too) runs first
            raise
        self._worker = None

    def __getstate__(self):
        self._wait()  # a copy takes the finished arrays, not the thread
        return self.__dict__

    def _run(self, y, z, vy, vz, omega, want_jac):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        check_state(self.params, y, z, vy, vz, omega)
        pr = self.params
        self._wait()
        self._solved = None  # the state whose field _p holds, once it is known to be finite
        self._info[:] = 0.0
        if self._geo is not None:
            self._run_bore(y, z, vy, vz, omega, want_jac)
        else:
            self._released(reynolds_kernel)(
                self._mode, want_jac, y, z, vy, vz, omega, pr.CR, pr.mu, pr.R, self._dth, self._dx, self._m,
                self._sin_c, self._cos_c, self._sin_f, self._cos_f, self._ds, self._dc, self._tdiag,
                self._rs, self._qw,
                self._at, self._ax, self._b, self._db, self._dat, self._dax, self._diag, self._cxo, self._cto,
                self._act, self._Lb, self._Y, self._S, self._zb, self._z2,
                self._p, self._pf, self._rhs, self._tmp, self._mu_y, self._mu_z,
                self._F, self._dFq, self._dFv, self._Ft, self._info, self._max_iter, self._grow,
                self.warm_start, self._warm_cap, self._max_turn, WARM_MAX_DLOG,
                self._hs, self._order, self._nvalid, self._wring,
            )
        self._count()
        if self._info[0] < 0:  # pragma: no cover - not observed; guards against cycling
            raise RuntimeError(
                f"Reynolds: active-set iteration did not converge in {self._max_iter} steps at "
                f"y={y!r}, z={z!r}, vy={vy!r}, vz={vz!r}, omega={omega!r}"
            )
        if not (np.all(np.isfinite(self._F)) and (not want_jac or (np.all(np.isfinite(self._dFq))
                                                                    and np.all(np.isfinite(self._dFv))))):
            # finite inputs (checked above) whose source overflows (|v| / CR or omega near 1e308):
            # the force is linear in the source, so no finite value is the answer; refused by name
            raise overflow_error(pr, y, z, vy, vz, omega, "force and its Jacobian" if want_jac else "force")
        self._solved = (y, z, vy, vz, omega)

    def _run_bore(self, y, z, vy, vz, omega, want_jac):
        pr, g = self.params, self._geo
        self._released(geometry_kernel)(
            self._mode, want_jac, y, z, vy, vz, omega, pr.CR, pr.mu, pr.R, self._dx, self._m,
            self._sin_c, self._cos_c, self._sin_f, self._cos_f, self._ds, self._dc, g["H0f"], g["H0c"], g["dH0"],
            g["ct"], g["cx"], g["gy"], g["gz"], g["fixed"], g["psup"], self._p_in, g["F0"], self._tdiag, self._rs, self._qw,
            self._at, self._ax, self._b, self._db, self._dat, self._dax, self._diag, self._cxo, self._cto,
            self._act, self._Lb, self._Y, self._S, self._zb, self._z2,
            self._p, self._pf, g["rhs0"], self._rhs, self._tmp, self._mu_y, self._mu_z,
            self._F, self._dFq, self._dFv, self._Ft, self._info, self._max_iter, self._grow,
            self.warm_start, self._warm_cap, self._max_turn, WARM_MAX_DLOG,
            self._hs, self._order, self._nvalid, self._wring,
        )

    def compiled_force(self):
        """Its force and Jacobian as a compiled kernel (``internals.compiled``;
        ``internals.reynolds.force``: the same kernel on this instance's arrays, its warm start
        shared)."""
        from ...internals.reynolds.force import ARRAYS, reynolds_force

        pr = self.params
        scalars = {"CR": pr.CR, "mu": pr.mu, "R": pr.R, "dth": self._dth, "dx": self._dx,
                   "max_turn": self._max_turn, "max_dlog": WARM_MAX_DLOG, "mode": self._mode, "m": self._m,
                   "N": self.n_theta, "max_iter": self._max_iter, "grow": self._grow, "warm": self.warm_start,
                   "warm_cap": self._warm_cap, "p_in": self._p_in}
        geo = None
        if self._geo is not None:  # the bore's film arrays and its wall (Geometry.closure's weights)
            geo = dict(self._geo)
            geo["wall_a"], geo["wall_b"] = pr.geometry.closure_weights()
        return reynolds_force(scalars, {name: getattr(self, f"_{name}") for name in ARRAYS}, self._compiled_kept, geo)

    def _compiled_kept(self, counts) -> None:
        """The compiled kernel's calls since the last: counted (``counts``), and the field no
        longer the one ``_solved`` names."""
        self._n_calls += int(counts[0])
        self._n_passes += int(counts[1])
        self._n_warm += int(counts[2])
        self._n_fallback += int(counts[3])
        self._solved = None

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] on the journal."""
        self._run(y, z, vy, vz, omega, False)
        return float(self._F[0]), float(self._F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF_dq (2,2), dF_dv (2,2)): raw derivatives dF_i/dq_j, q = (y, z), v = (vy, vz),
        exact for the discrete system with the converged cavitation set held fixed."""
        self._run(y, z, vy, vz, omega, True)
        return self._F.copy(), self._dFq.copy(), self._dFv.copy()

    def pressure(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(theta (n_theta,), x (n_x,), p (n_theta, n_x)) [rad, m, Pa] at the cell centres."""
        self._run(y, z, vy, vz, omega, False)
        half = self._p.reshape(self.n_theta, self._m)
        p = np.concatenate([half, half[:, ::-1]], axis=1)
        return self._theta.copy(), self._x.copy(), p

    def peak_pressure(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """(p_peak [Pa], theta_peak [rad]) of the film at a state: its largest pressure, refined between
        cell centres (``film.peak_pressure``); as ``film_report``, it reads the field of a force call at
        the same state."""
        state = (float(y), float(z), float(vy), float(vz), float(omega))
        if self._solved != state:
            self._run(*state, False)
        half = self._p.reshape(self.n_theta, self._m)
        if self._p_in or has_lands(self.params):
            # lands: the largest cell's column refined around the circumference (its axial profile is no
            # even parabola about the mid-plane); the groove's own pressure counts where it is the largest
            j = int(np.argmax(half.max(axis=0)))
            pk, th = peak_pressure(self._theta, self._x[j:j + 1], half[:, j:j + 1])
            return (pk, th) if pk >= self._p_in else (self._p_in, th)
        return peak_pressure(self._theta, self._x, np.concatenate([half, half[:, ::-1]], axis=1))

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction (torque, force, power, coefficient) and flow (inflow, side flow) of the film at a
        state, from its converged pressure field (``physics.solver.film``: the definitions, Raimondi &
        Boyd's assumptions); not part of the force call, so it costs the hot loop nothing. Right
        after a force call at the same state it reads that call's field (no second solve)."""
        state = (float(y), float(z), float(vy), float(vz), float(omega))
        if self._solved != state:
            self._run(*state, False)
        half = self._p.reshape(self.n_theta, self._m).copy()
        return field_report(self.params, float(y), float(z), float(vy), float(vz), float(omega),
                            (float(self._F[0]), float(self._F[1])), half, self._dx, self._grid)

    def flow_field(self, y: float, z: float, vy: float, vz: float, omega: float) -> dict:
        """The film's flows cell by cell at a state (``film.flow_field``): ``face`` [rad] the right
        face of every cell, ``flux`` [m^3/s] across it, ``side`` [m^3/s] out of the cell's ends, and
        ``pressurised`` whether every node of the cell's column holds a pressure > 0 (the cells where
        the discrete Reynolds equation holds as an equality: no cavitation, no prescribed value)."""
        state = (float(y), float(z), float(vy), float(vz), float(omega))
        if self._solved != state:
            self._run(*state, False)
        half = self._p.reshape(self.n_theta, self._m).copy()
        flux, side = flow_field(self.params, state[0], state[1], state[4], half, self._dx, self._grid)
        fixed = np.zeros(self.n_theta, bool) if self._grid is None else self._grid.fixed.astype(bool)
        face = (np.arange(self.n_theta) + 0.5) * (2.0 * np.pi / self.n_theta) if self._grid is None else self._grid.right
        return {"face": face.copy(), "flux": flux, "side": side, "pressurised": ~fixed & np.all(half > 0.0, axis=1)}

    def supply_flows(self, y: float, z: float, vy: float, vz: float, omega: float) -> dict:
        """A grooved or partial-arc bore's side flow and the pressure parts of its supply edges' inflow
        at a state (``film.edge_flows``: what the grooved map tabulates); as ``film_report``, it reads
        the field of a force call at the same state."""
        if self._grid is None or not self._grid.fixed.any():
            raise ValueError("supply_flows: the bore has no grooves and no arc (no supply edges)")
        state = (float(y), float(z), float(vy), float(vz), float(omega))
        if self._solved != state:
            self._run(*state, False)
        half = self._p.reshape(self.n_theta, self._m).copy()
        return edge_flows(self.params, state[0], state[1], half, self._dx, self._grid)

    def diagnostics(self, y: float, z: float, vy: float, vz: float, omega: float) -> dict:
        """Solver statistics of a call at a state: active-set iterations of the converged solve,
        banded factorizations in all (``passes``: more than ``iterations`` only when a warm
        start was abandoned for the cold one, ``cold_fallback``), whether the start was the
        remembered set (``warm_start``), cavitated fraction of the cells, and (for "reynolds")
        the scaled complementarity residual max|min(p, A p - b)| / scale."""
        self._run(y, z, vy, vz, omega, False)
        return {
            "iterations": int(self._info[0]),
            "passes": int(self._info[3]),
            "warm_start": bool(self._info[4]),
            "cold_fallback": bool(self._info[5]),
            "cavitated_fraction": float(self._info[1]),
            "complementarity_residual": float(self._info[2]),
        }
