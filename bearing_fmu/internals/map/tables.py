"""The force map: the Reynolds film force for every speed, load and velocity from one table.

In the line-of-centres frame the right-hand side of Reynolds' equation depends on the state
only through r sin(psi - beta) (derivation: docs/forcemap.md), the film thickness on eps and
psi only, and the cavitation problem is positively homogeneous in its right-hand side. So

    F = S r (G_r(eps, beta) u + G_t(eps, beta) w),    S = mu R L (R / CR)^2,

with u the unit vector toward the journal centre, w = u turned by +90 degrees (toward the
rotation), r and beta from the velocities (``kernels``). For one L/D, Reynolds grid and
cavitation model, G is one smooth function of two variables: the map tabulates it from the
Reynolds internal on s = -ln(1 - eps) (clustered toward the wall) x beta (periodic), with the
wall growth (1 - eps)^-k factored out, and interpolates it with a tensor cubic spline (not-a-
knot in s, periodic in beta). D, CR and mu enter only through S.

This module: the reduction (``reduced``, ``state_for``, ``scale``), the table (``MapTable``: its
axes, its spline, its file's content ``to_dict``) and its tabulation from the Reynolds solver
(``tabulate``). The file (``save_map`` / ``load_map``, every key checked): ``tablefile``; the
map internal evaluating the table: ``forcemap``; the grooved bore's 3-D map: ``groovemap``.
"""


from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...physics.solver.film import reduced_flows
from ...physics.params import L_OVER_D_RANGE, BearingParams

FORMAT = "bearing-fmu-force-map"
VERSION = 1  # the force table alone (read still: such a map has no film flows)
FLOW_VERSION = 3  # with the flow table Q (2 and 4 are the grooved map's, groovemap.py)
NO_FLOWS_WHY = ("the map file {source} has no flow tables (format version 1, built before they were added): "
                "rebuild it with `bearing-fmu map --bearing FILE -o MAP` to get the film's inflow and side flow")
# defaults from the resolution study (docs/studies/2026-11-24-forcemap-resolution.md): 96 points in
# s and k = 0 take the interpolation error near the centre, where a growing 44 Hz whirl spends its
# first seconds, from 1.4e-3 (48 points, k = 2) to 5e-5; the held-out 44 Hz orbit from 0.059 to 0.002 % CR
DEFAULT_N_EPS = 96  # table points in s = -ln(1 - eps)
DEFAULT_N_BETA = 96  # table points in beta over one period
DEFAULT_EPS_MAX = 0.99  # last table point: beyond it the map refuses the state
DEFAULT_WALL_EXPONENT = 0.0  # k in H = G (1 - eps)^k (the s axis already follows the wall growth)
DEFAULT_N_PHASE = 4  # attitudes per table point, spread over one Reynolds cell (averaged)
EPS_MIN = 1e-6  # below: evaluated at EPS_MIN along the same direction (kernel docstring: 1/e in the
# attitude derivatives would amplify round-off; the shift moves the force by ~1e-6 of S omega)
LD_RTOL = 1e-9  # a map serves bearings whose L/D equals its own to this relative tolerance

# the map reduces the force to F = r G(eps, beta): true for the circular full bore only (a groove,
# an arc or a lobe fixes directions in the bore, docs/geometry.md)
REDUCTION_WHY = ("a version 1 map's reduction to eccentricity and one angle assumes the circular full bore; "
                 "`bearing-fmu map --bearing FILE` builds a 3-D map for grooves and partial arcs")

def scale(params: BearingParams) -> float:
    """S = mu R L (R / CR)^2 [N s]: the map's force per unit r [1/s]."""
    return params.mu * params.R * params.L * (params.R / params.CR) ** 2


def reduced(y: float, z: float, vy: float, vz: float, omega: float, CR: float):
    """(eps, phi, a, c): eccentricity ratio, attitude [rad], and the source coefficients
    a = eps (omega - 2 phidot), c = 2 epsdot [1/s] (docs/forcemap.md). e by libm's hypot, as the numba
    kernels and the native map (CPython's math.hypot rounds its own way, at times 1 ulp apart)."""
    e = float(np.hypot(y, z))
    cp, sp = (y / e, z / e) if e > 0.0 else (1.0, 0.0)
    vr, vt = vy * cp + vz * sp, -vy * sp + vz * cp
    eps = e / CR
    return eps, math.atan2(sp, cp), eps * omega - 2.0 * vt / CR, 2.0 * vr / CR


def state_for(eps: float, beta: float, params: BearingParams, phi: float = -0.5 * math.pi, omega: float = 1.0,
              r: float = 1.0):
    """A journal state (y, z, vy, vz) with the given eps and beta, attitude phi and r [1/s] at
    ``omega``: the inverse of ``reduced`` (v_t = CR (eps omega - a) / 2, v_r = CR c / 2)."""
    a, c = r * math.cos(beta), r * math.sin(beta)
    CR = params.CR
    vt, vr = 0.5 * CR * (eps * omega - a), 0.5 * CR * c
    cp, sp = math.cos(phi), math.sin(phi)
    return eps * CR * cp, eps * CR * sp, vr * cp - vt * sp, vr * sp + vt * cp


# ------------------------------------------------------------------------------ the table

class TableAxes:
    """The s, eps and beta axes of a map table (``n_eps``, ``n_beta``, ``eps_max``)."""

    @property
    def s(self) -> np.ndarray:
        return np.linspace(0.0, -math.log1p(-self.eps_max), self.n_eps)

    @property
    def eps(self) -> np.ndarray:
        return -np.expm1(-self.s)

    @property
    def beta(self) -> np.ndarray:
        return -math.pi + 2.0 * math.pi * np.arange(self.n_beta) / self.n_beta


@dataclass
class MapTable(TableAxes):
    """G tabulated as H = G (1 - eps)^k on s_i = i s_max / (n_eps - 1), s = -ln(1 - eps), and
    beta_j = -pi + j 2 pi / n_beta; H has shape (n_eps, n_beta, 2) (radial, tangential)."""

    L_over_D: float
    n_theta: int
    n_x: int
    cavitation: str
    eps_max: float
    wall_exponent: float
    H: np.ndarray
    provenance: dict = field(default_factory=dict)
    coefficients: tuple | None = field(default=None, repr=False)  # (ts, tb, C) of ``spline``
    Q: np.ndarray | None = None  # (n_eps, n_beta, 2): (J_s, J_i) of film.reduced_flows, or None
    flow_coefficients: tuple | None = field(default=None, repr=False)  # (ts, tb, C) of ``flow_spline``

    def __post_init__(self):
        self.H = np.asarray(self.H, float)
        self.Q = None if self.Q is None else np.asarray(self.Q, float)
        problem = self.problem()
        if problem:
            raise ValueError(f"force map table: {problem}")

    def problem(self) -> str | None:
        """What makes the table unusable, naming its file key and what it must be, or None. A NaN
        L/D would pass every L/D comparison (NaN compares false) and a NaN wall exponent makes
        every force NaN: both are refused here, before any bearing meets the map."""
        problem = header_problem(self)
        if problem:
            return problem
        if self.H.ndim != 3 or self.H.shape[2] != 2 or self.H.shape[0] < 4 or self.H.shape[1] < 4:
            return f"key 'H' has shape {self.H.shape}, expected (n_eps >= 4, n_beta >= 4, 2)"
        if self.Q is not None and self.Q.shape != self.H.shape:
            return f"key 'Q' has shape {self.Q.shape}, expected that of 'H' {self.H.shape}"
        return finite_problem(self.H) or (None if self.Q is None else finite_problem(self.Q, "Q"))

    @property
    def n_eps(self) -> int:
        return self.H.shape[0]

    @property
    def n_beta(self) -> int:
        return self.H.shape[1]

    def spline(self):
        """(ts, tb, C): knots in s and beta and the tensor spline coefficients C (ns, nb, 2);
        stored in the file, so loading needs no scipy (0.6 s of import)."""
        if self.coefficients is None:
            self.coefficients = self._fit_spline(self.H)
        return self.coefficients

    def flow_spline(self):
        """(ts, tb, C) of the flow table Q, as ``spline`` of H (None without flow tables)."""
        if self.flow_coefficients is None and self.Q is not None:
            self.flow_coefficients = self._fit_spline(self.Q)
        return self.flow_coefficients

    def _fit_spline(self, H):
        from scipy.interpolate import make_interp_spline

        s, beta = self.s, self.beta
        along_s = make_interp_spline(s, H, k=3, axis=0)  # not-a-knot
        wrapped = np.concatenate([along_s.c, along_s.c[:, :1]], axis=1)  # periodic: first column again
        along_b = make_interp_spline(np.append(beta, math.pi), wrapped, k=3, axis=1, bc_type="periodic")
        # scipy keeps a BSpline's coefficients with the interpolation axis first: put beta back second
        return (np.ascontiguousarray(along_s.t), np.ascontiguousarray(along_b.t),
                np.ascontiguousarray(np.moveaxis(along_b.c, 0, 1)))

    def to_dict(self) -> dict:
        flows = {} if self.Q is None else {
            "flow_meaning": "Q[i][j] = (J_s, J_i): side flow r R L CR J_s, inflow |omega R L CR (1 + eps) / 2 - r R L CR J_i|",
            "Q": np.round(self.Q, 12).tolist(),
            "flow_spline": dict(zip(("knots_s", "knots_beta", "coefficients"),
                                    (a.tolist() for a in self.flow_spline())))}
        return {"format": FORMAT, "version": VERSION if self.Q is None else FLOW_VERSION, "L_over_D": self.L_over_D,
                "reynolds": {"n_theta": self.n_theta, "n_x": self.n_x, "cavitation": self.cavitation},
                "eps_max": self.eps_max, "wall_exponent": self.wall_exponent,
                "n_eps": self.n_eps, "n_beta": self.n_beta,
                "grid": "s = -ln(1 - eps) uniform on [0, -ln(1 - eps_max)]; beta = -pi + j 2 pi / n_beta",
                "meaning": "H[i][j] = (G_r, G_t) (1 - eps_i)^wall_exponent; F = mu R L (R/CR)^2 r (G_r u + G_t w)",
                "H": np.round(self.H, 12).tolist(),
                "spline": dict(zip(("knots_s", "knots_beta", "coefficients"), (a.tolist() for a in self.spline()))),
                "provenance": self.provenance, **flows}


def header_problem(t) -> str | None:
    """What makes a map table's L/D, eps_max, wall exponent, Reynolds grid or cavitation model
    unusable (``t`` a MapTable or a grooved table), naming the file key, or None."""
    lo, hi = L_OVER_D_RANGE
    if not lo <= t.L_over_D <= hi:  # NaN fails too
        return f"key 'L_over_D' = {t.L_over_D!r} must be a finite number in {lo:g} .. {hi:g} (a bearing's L/D)"
    if not 0.0 < t.eps_max < 1.0:
        return f"key 'eps_max' = {t.eps_max!r} must lie in (0, 1) (the table's last eccentricity ratio)"
    if not (math.isfinite(t.wall_exponent) and t.wall_exponent >= 0.0):
        return f"key 'wall_exponent' = {t.wall_exponent!r} must be a finite number >= 0 (k in H = G (1 - eps)^k)"
    for name in ("n_theta", "n_x"):
        v = getattr(t, name)
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            return f"key 'reynolds.{name}' = {v!r} must be an integer >= 1 (the Reynolds grid it was built on)"
    if not isinstance(t.cavitation, str) or not t.cavitation:
        return f"key 'reynolds.cavitation' = {t.cavitation!r} must be the name of a cavitation model"
    return None


def finite_problem(H: np.ndarray, key: str = "H") -> str | None:
    """The first non-finite entry of a table H (file key ``key``), named, or None."""
    if not np.all(np.isfinite(H)):
        i = tuple(int(k) for k in np.argwhere(~np.isfinite(H))[0])
        return f"key '{key}' has a non-finite entry {key}{list(i)} = {float(H[i])!r}, expected finite numbers"
    return None


def tabulate(params: BearingParams, *, n_eps: int = DEFAULT_N_EPS, n_beta: int = DEFAULT_N_BETA,
             eps_max: float = DEFAULT_EPS_MAX, wall_exponent: float = DEFAULT_WALL_EXPONENT,
             n_theta: int | None = None, n_x: int | None = None, cavitation: str = "reynolds",
             n_phase: int = DEFAULT_N_PHASE, workers: int = 1, progress=None, flows: bool = True,
             client=None, partial=None, done: dict | None = None) -> MapTable:
    """The map of ``params``' L/D from the Reynolds internal on the given grid: one solve per
    table point at r = 1, omega = 1 rad/s, the journal straight below the centre (phi = -90 deg).
    The eps rows are tasks (``parallel.rows.solve_rows``): on the Dask ``client`` when given, else
    on ``workers`` processes; each streamed into ``partial`` as it comes, ``done`` (row -> values)
    not solved again; ``progress(n_done)`` per row. ``flows``: the flow table Q too (one more solve
    per point), else the force alone (a version 1 map)."""
    from functools import partial as bind

    from ...parallel.rows import solve_rows
    from ...physics.solver.reynolds import Reynolds

    params.require_full_bore("a force map", REDUCTION_WHY)
    rey = Reynolds(params, n_theta, n_x, cavitation)
    t0 = time.perf_counter()
    table = MapTable(params.L / params.D, rey.n_theta, rey.n_x, rey.cavitation, eps_max, wall_exponent,
                     np.zeros((n_eps, n_beta, 2)), Q=np.zeros((n_eps, n_beta, 2)) if flows else None)
    task = bind(table_row, params, rey.n_theta, rey.n_x, rey.cavitation, betas=table.beta,
                wall_exponent=wall_exponent, n_phase=n_phase, flows=flows)
    for i, (h, q) in enumerate(solve_rows(task, table.eps, done=done, partial=partial, workers=workers,
                                          client=client, progress=progress)):
        table.H[i] = h
        if flows:
            table.Q[i] = q
    _centre_row(table)
    if flows:  # the centre's side flow: the uniform film turns with the source
        table.Q[0, :, 0] = np.mean(table.Q[0, :, 0])
    table.provenance = {"built_s": round(time.perf_counter() - t0, 3), "solves": (1 + flows) * n_eps * n_beta * n_phase,
                        "n_phase": n_phase,
                        "truth": repr(rey), "date": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    return table


def _centre_row(table: MapTable) -> None:
    """At eps = 0 the film is uniform and the problem turns with the source: G(0, beta) =
    R(beta) g for one vector g (docs/forcemap.md). The continuous force is then independent of
    the attitude phi at the centre, which keeps the Jacobian finite there (its attitude terms
    carry 1/e); the solver's grid breaks this by ~1e-3, so the row is replaced by its
    projection on that form (least squares: g = mean over beta of R(-beta) G(0, beta))."""
    b = table.beta
    c, s = np.cos(b), np.sin(b)
    G = table.H[0]  # (1 - 0)^k = 1
    g = np.array([np.mean(c * G[:, 0] + s * G[:, 1]), np.mean(-s * G[:, 0] + c * G[:, 1])])
    table.H[0, :, 0] = c * g[0] - s * g[1]
    table.H[0, :, 1] = s * g[0] + c * g[1]


def table_row(params, n_theta, n_x, cavitation, eps, betas, wall_exponent, n_phase, rey=None, flows=True):
    """(H, Q) at one eps for every beta (a row's task when ``rey`` is None: a solver of its own, so a
    row's values do not depend on which rows its process solved before). Q from the
    solver's film reports at omega = 1 and 2 rad/s (``film.reduced_flows``; at the centre at
    EPS_MIN, where the line of thickest film has the journal's direction)."""
    if rey is None:
        from ...physics.solver.reynolds import Reynolds

        rey = Reynolds(params, n_theta, n_x, cavitation)
    S = scale(params)
    out, Q = np.zeros((len(betas), 2)), np.zeros((len(betas), 2))
    eps_flow = max(eps, EPS_MIN)
    # the solver's grid is fixed to the bearing: the same (eps, beta) at another attitude
    # differs by its discretisation (up to a few 1e-3 near the wall, docs/forcemap.md);
    # averaging over attitudes spread across one cell tabulates the grid-independent part
    phases = -0.5 * math.pi + (np.arange(n_phase) + 0.5) / n_phase * 2.0 * math.pi / rey.n_theta
    for phi in phases:
        u = np.array([math.cos(phi), math.sin(phi)])
        w = np.array([-math.sin(phi), math.cos(phi)])
        for j, b in enumerate(betas):
            y, z, vy, vz = state_for(eps, b, params, phi)
            F = np.array(rey.force(y, z, vy, vz, 1.0))
            out[j] += (F @ u / S, F @ w / S)
            if flows:
                Q[j] += reduced_flows(params, eps_flow, 1.0, {
                    om: rey.film_report(*state_for(eps_flow, b, params, phi, omega=om), om) for om in (1.0, 2.0)})
    return out / n_phase * (1.0 - eps) ** wall_exponent, Q / n_phase
