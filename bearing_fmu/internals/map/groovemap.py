"""The force map of a grooved or partial-arc bore: F = S r G(eps, phi, beta), a 3-D table.

A groove or an arc leaves the film circular, h = CR (1 + eps cos psi) with psi measured from the
line of centres, and leaves the right-hand side -6 mu CR r sin(psi - beta) of the full bore
(docs/forcemap.md). What it adds is a boundary fixed in the bearing: in the journal's
coordinates the grooves sit at theta_g - phi, so the problem depends on the attitude phi too.
With the grooves at ambient pressure the complementarity problem stays positively homogeneous
in its right-hand side, hence

    F = S r (G_r(eps, phi, beta) u + G_t(eps, phi, beta) w),    S = mu R L (R / CR)^2,

periodic in phi with the bore's own symmetry (pi for two opposite grooves, 2 pi for an arc).
A supply pressure p_s over the grooves adds a source independent of r: with cavitation the
force is then not p_s Q(eps, phi) + S r G (checked in docs/studies/2026-11-26-geometry-maps.md,
by 2-4x), so such a bearing is refused by name. Lobed bores are refused too: their film depends
on the position in two coordinates and on the direction of (omega, A, B), a 4-D table
(docs/forcemap.md, "Grooved bores").

The flows (docs/forcemap.md, "Grooved bores: the flows"): the side flow reduces as the force,
Q_s = r Q0 J_s(eps, phi, beta), Q0 = R L CR. The inflow is the oil entering the film at the
supply edges (a groove's two sides, an arc's ends), each the positive part of the signed flux
into the film there. At fixed (eps, phi, beta) that flux is linear in omega and r: its Couette
part sign_e omega Q0 h_e / (2 CR), h_e the film at the edge (closed form), minus r Q0 P_e(eps, phi,
beta), its pressure part. So the table holds P_e per edge and the positive part is taken after
the sum, at run time: exact, whatever the sign of each edge's flux. The friction needs no table
(the Couette torque over the film in closed form, the pressure torque from the force).

The file (format ``bearing-fmu-force-map``, version 2; version 4 with the flow table Q =
(J_s, P_1 .. P_E) and the edges) holds the tables only: the tensor cubic splines (not-a-knot in s,
periodic in phi and beta) are fitted when it is loaded, by one collocation solve per axis in
numpy, so the file stays about half the size and cannot disagree with its splines.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...io.schema import find_non_finite
from ...physics.solver.film import FilmReport, grooved_report, supply_functions
from ...physics.bore.geometry import Geometry
from ...physics.params import BearingParams
from .forcemap import ForceMap
from .tablefile import array_key, bspline_matrix, number_key
from .tables import EPS_MIN, FORMAT, LD_RTOL, TableAxes, finite_problem, header_problem, reduced, scale, state_for

VERSION = 2  # the force table alone (read still: such a map has no film flows)
FLOW_VERSION = 4  # with the flow table Q and the supply edges
NO_FLOWS_WHY = ("the grooved map file {source} has no flow tables (format version 2, built before they were added): "
                "rebuild it with `bearing-fmu map --bearing FILE -o MAP` to get the film's inflow and side flow")
# the convergence study (docs/studies/2026-11-26-geometry-maps.md): against the solver at random
# states 48 x 24 x 48 is as good, but the paper rotor's 10 Hz orbit needs 64 x 32 x 64 (0.012 ->
# 0.003 % CR); averaging attitudes only biases the table (the solver's grid is fixed to the grooves)
DEFAULT_N_EPS = 64
DEFAULT_PHI_PER_PI = 32  # attitude points per 180 deg (5.6 deg apart): n_phi = this x period / pi
DEFAULT_N_BETA = 64
DEFAULT_N_PHASE = 1  # attitudes per table point, spread over one Reynolds cell (averaged)
DEFAULT_EPS_MAX = 0.99
GEOMETRY_RTOL = 1e-9  # [rad] a map serves bearings whose grooves and arc equal its own to this
DIGITS = 8  # significant digits of H in the file (1e-8; the interpolation error is ~1e-5)

LOBES_WHY = ("a lobed bore's film depends on the journal position in two coordinates and on the direction "
             "of (omega, omega y - 2 vz, omega z + 2 vy): a 4-D table (1.3 million points, about 35 MB and 2.7 "
             "million Reynolds solves at the grooved map's resolution, docs/forcemap.md); use the Reynolds or "
             "Taylor internal")
SUPPLY_WHY = ("a supply pressure adds a film source independent of the journal's motion and, with "
              "cavitation, the force is not the sum of the two parts (docs/forcemap.md): the map needs "
              "supply_pressure_kPa = 0; use the Reynolds or Taylor internal")


def map_geometry_problem(geometry: Geometry) -> str | None:
    """Why no force map serves this bore (a phrase), or None."""
    if geometry.circumferential_groove:
        return (f"circumferential_groove_mm = {geometry.circumferential_groove * 1e3:g}: the lands' field is not the "
                "grooved map's (its edges are axial, its film fed along theta); use the Reynolds internal")
    if geometry.lobes > 1:
        return f"lobes = {geometry.lobes}: {LOBES_WHY}"
    if geometry.supply_pressure > 0.0:
        return f"supply_pressure_kPa = {geometry.supply_pressure / 1e3:g}: {SUPPLY_WHY}"
    return None


def symmetry_period(geometry: Geometry) -> float:
    """The smallest rotation 2 pi / k [rad] that maps the bore's grooves (and arc) onto
    themselves: G is periodic in phi with it (two opposite grooves: pi; an arc: 2 pi)."""
    g = np.array(geometry.grooves)
    if geometry.arc is not None or len(g) < 2:
        return 2.0 * math.pi
    for k in range(len(g), 1, -1):
        if len(g) % k:
            continue
        turned = np.sort(np.mod(g + 2.0 * math.pi / k, 2.0 * math.pi))
        d = np.abs(turned - g)
        if np.all(np.minimum(d, 2.0 * math.pi - d) < GEOMETRY_RTOL):
            return 2.0 * math.pi / k
    return 2.0 * math.pi


def geometry_record(geometry: Geometry) -> dict:
    """The bore as the file records it (degrees)."""
    return {"grooves_deg": [math.degrees(x) for x in geometry.grooves],
            "groove_width_deg": math.degrees(geometry.groove_width),
            "arc_deg": None if geometry.arc is None else [math.degrees(x) for x in geometry.arc]}


def geometry_from_record(rec) -> Geometry:
    if not isinstance(rec, dict) or set(rec) != {"grooves_deg", "groove_width_deg", "arc_deg"}:
        raise ValueError(f"key 'geometry' = {rec!r:.80} must be an object {{grooves_deg, groove_width_deg, arc_deg}}")
    arc = rec["arc_deg"]
    g = Geometry(grooves=tuple(math.radians(float(x)) for x in rec["grooves_deg"]),
                 groove_width=math.radians(float(rec["groove_width_deg"])),
                 arc=None if arc is None else (math.radians(float(arc[0])), math.radians(float(arc[1]))))
    if g.is_full_bore:
        raise ValueError("key 'geometry' describes the full bore: a version 1 map serves it")
    return g


def same_bore(a: Geometry, b: Geometry) -> bool:
    """Grooves, their width and the arc equal to GEOMETRY_RTOL (no lobes, no supply pressure)."""
    if len(a.grooves) != len(b.grooves) or (a.arc is None) != (b.arc is None) or a.lobes != b.lobes:
        return False
    if a.supply_pressure != b.supply_pressure:
        return False
    pairs = list(zip(a.grooves, b.grooves)) + ([] if a.arc is None else list(zip(a.arc, b.arc)))
    pairs.append((a.groove_width, b.groove_width) if a.grooves else (0.0, 0.0))
    return all(abs(math.remainder(x - y, 2.0 * math.pi)) < GEOMETRY_RTOL for x, y in pairs)


# ------------------------------------------------------------------------------ the spline

def not_a_knot_knots(x: np.ndarray) -> np.ndarray:
    """Knots of the not-a-knot cubic interpolant on points x (len(x) coefficients)."""
    return np.concatenate([[x[0]] * 4, x[2:-2], [x[-1]] * 4])


def periodic_knots(x0: float, period: float, n: int) -> np.ndarray:
    """Uniform knots x0 + (j - 3) h, j = 0 .. n + 6 (h = period / n): n + 3 coefficients, the
    last three equal to the first three; the kernels fold the argument into [t[3], t[n + 3])."""
    return x0 + (np.arange(n + 7) - 3.0) * (period / n)


def fit_axis(values: np.ndarray, axis: int, t: np.ndarray, x: np.ndarray, periodic: bool) -> np.ndarray:
    """Coefficients along one axis: the collocation system B c = values (B from the knots t at
    the points x); periodic: the wrapped basis folded onto n unknowns, then the three repeated."""
    n = len(x)
    B = bspline_matrix(t, x, n + 3 if periodic else n)
    if periodic:
        B = B[:, :n] + np.pad(B[:, n:], ((0, 0), (0, n - 3)))
    v = np.moveaxis(values, axis, 0)
    c = np.linalg.solve(B, v.reshape(n, -1)).reshape(v.shape)
    if periodic:
        c = np.concatenate([c, c[:3]], axis=0)
    return np.moveaxis(c, 0, axis)


@dataclass
class GroovedMapTable(TableAxes):
    """G tabulated on s_i = i s_max / (n_eps - 1), s = -ln(1 - eps), phi_j = j P / n_phi (P the
    bore's symmetry period) and beta_k = -pi + k 2 pi / n_beta; H has shape (n_eps, n_phi,
    n_beta, 2) (radial, tangential). No wall factor: the s axis follows the wall growth."""

    L_over_D: float
    n_theta: int
    n_x: int
    cavitation: str
    eps_max: float
    geometry: Geometry
    H: np.ndarray
    provenance: dict = field(default_factory=dict)
    coefficients: tuple | None = field(default=None, repr=False)
    Q: np.ndarray | None = None  # (n_eps, n_phi, n_beta, 1 + E): (J_s, P_1 .. P_E), the module docstring; or None
    flow_coefficients: tuple | None = field(default=None, repr=False)  # ``flow_spline``

    wall_exponent = 0.0  # read like a version 1 table's

    def __post_init__(self):
        self.H = np.asarray(self.H, float)
        self.Q = None if self.Q is None else np.asarray(self.Q, float)
        problem = self.problem()
        if problem:
            raise ValueError(f"force map table: {problem}")

    def problem(self) -> str | None:
        problem = header_problem(self)
        if problem:
            return problem
        why = map_geometry_problem(self.geometry)
        if why:
            return f"key 'geometry': {why}"
        if self.H.ndim != 4 or self.H.shape[3] != 2 or min(self.H.shape[:3]) < 4:
            return f"key 'H' has shape {self.H.shape}, expected (n_eps >= 4, n_phi >= 4, n_beta >= 4, 2)"
        want = (*self.H.shape[:3], 1 + len(self.edges))
        if self.Q is not None and self.Q.shape != want:
            return (f"key 'Q' has shape {self.Q.shape}, expected {want} (side flow and one per supply edge of the "
                    f"bore, {len(self.edges)})")
        return finite_problem(self.H) or (None if self.Q is None else finite_problem(self.Q, "Q"))

    n_eps = property(lambda self: self.H.shape[0])
    n_phi = property(lambda self: self.H.shape[1])
    n_beta = property(lambda self: self.H.shape[2])
    period = property(lambda self: symmetry_period(self.geometry))
    edges = property(lambda self: self.geometry.supply_edges())  # (theta [rad], sign) in the order of Q's P_e

    @property
    def phi(self) -> np.ndarray:
        return self.period * np.arange(self.n_phi) / self.n_phi

    def knots(self):
        return (not_a_knot_knots(self.s), periodic_knots(0.0, self.period, self.n_phi),
                periodic_knots(-math.pi, 2.0 * math.pi, self.n_beta))

    def spline(self):
        """(ts, tp, tb, C): knots in s, phi, beta and coefficients C (n_eps, n_phi + 3, n_beta + 3, 2)."""
        if self.coefficients is None:
            self.coefficients = self.fit_spline(self.H)
        return self.coefficients

    def flow_spline(self):
        """(ts, tp, tb, C) of the flow table Q over one period in phi, as ``spline`` of H, but its last
        three coefficients in phi are the next period's: the first three with the edges renumbered
        (``flow_images``). Fitted over the whole turn (``unrolled_flows``), whose periods' coefficients
        are each other's renumbered to round-off, and kept for the first period only: ``flow_components``
        reads the others by renumbering (None without flow tables)."""
        if self.flow_coefficients is None and self.Q is not None:
            images = self.flow_images()
            ts, _, tb, C = self.fit_spline(self.unrolled_flows(), len(images))
            C = np.concatenate([C[:, :self.n_phi], C[:, :3][..., images[1 % len(images)]]], axis=1)
            self.flow_coefficients = (ts, self.knots()[1], tb, np.ascontiguousarray(C))
        return self.flow_coefficients

    def flow_images(self) -> np.ndarray:
        """(k, 1 + E) indices, k = 2 pi / period: row j the component of Q that each of (J_s, P_1 .. P_E)
        takes j periods on. The side flow repeats with the bore's period, an edge's P_e does not: turned
        by j periods, the journal sees the edge that lies j periods behind, P_e(phi + j P) = P_e'(phi),
        theta_e' = theta_e - j P. A spline periodic over one period would join P_e to itself across the
        period's end (docs/studies/2026-11-26-groove-flows.md: 0.29 of the inflow at one of 300 states)."""
        theta = np.array([t for t, _ in self.edges])
        sign = np.array([sg for _, sg in self.edges])
        rows = []
        for j in range(round(2.0 * math.pi / self.period)):
            d = np.abs(np.remainder(theta[None, :] - (theta[:, None] - j * self.period) + math.pi, 2.0 * math.pi)
                       - math.pi)  # d[e, e']: edge e' against the place of e turned back by j periods
            d[sign[:, None] != sign[None, :]] = math.inf
            rows.append(np.r_[0, 1 + np.argmin(d, axis=1)])
        return np.array(rows)

    def unrolled_flows(self) -> np.ndarray:
        """Q over phi in [0, 2 pi) (n_eps, k n_phi, n_beta, 1 + E): block j renumbered by ``flow_images``."""
        return np.concatenate([self.Q[..., img] for img in self.flow_images()], axis=1)

    def fit_spline(self, values, turns: int = 1):
        """The spline of a table on the map's axes (``turns`` periods in phi: ``unrolled_flows``)."""
        ts, tp, tb = self.knots()
        n_phi = self.n_phi * turns
        tp = periodic_knots(0.0, self.period * turns, n_phi)
        C = fit_axis(values, 0, ts, self.s, False)
        C = fit_axis(C, 1, tp, self.period * turns * np.arange(n_phi) / n_phi, True)
        C = fit_axis(C, 2, tb, self.beta, True)
        return ts, tp, tb, np.ascontiguousarray(C)

    def to_dict(self) -> dict:
        flows = {} if self.Q is None else {
            "flow_meaning": ("Q[i][j][k] = (J_s, P_1 .. P_E), the last index fastest: side flow r R L CR J_s; "
                             "inflow sum over the supply edges e of max(sign_e omega R L h_e / 2 - r R L CR P_e, 0), "
                             "h_e = CR + eps CR sin(theta_e - phi) the film at the edge; flow_edges_deg[e] = (theta_e, "
                             "sign_e); Q over phi in one period P of the bore, P_e(phi + j P) = P_e'(phi) with "
                             "theta_e' = theta_e - j P (the spline is fitted over the whole turn)"),
            "flow_edges_deg": [[math.degrees(t), sg] for t, sg in self.edges],
            "Q": [float(f"{v:.{DIGITS}g}") for v in self.Q.ravel()]}
        return {"format": FORMAT, "version": VERSION if self.Q is None else FLOW_VERSION, "L_over_D": self.L_over_D,
                "reynolds": {"n_theta": self.n_theta, "n_x": self.n_x, "cavitation": self.cavitation},
                "eps_max": self.eps_max, "geometry": geometry_record(self.geometry),
                "n_eps": self.n_eps, "n_phi": self.n_phi, "n_beta": self.n_beta,
                "grid": ("s = -ln(1 - eps) uniform on [0, -ln(1 - eps_max)]; phi = j P / n_phi, P the bore's "
                         "symmetry period (2 pi / k for k equally spaced grooves, else 2 pi); beta = -pi + k 2 pi / n_beta"),
                "meaning": ("H[i][j][k] = (G_r, G_t); F = mu R L (R/CR)^2 r (G_r u + G_t w), phi the journal's "
                            "attitude atan2(z, y); spline: cubic, not-a-knot in s, periodic in phi and beta, fitted "
                            "on loading"),
                "H": [float(f"{v:.{DIGITS}g}") for v in self.H.ravel()],
                "provenance": self.provenance, **flows}


def flow_components(spline, images, s: float, phi: float, beta: float, work: np.ndarray) -> np.ndarray:
    """(J_s, P_1 .. P_E) and their derivatives (as ``map_kernels.spline3``'s out) at (s, phi, beta), any
    phi: ``spline`` (``flow_spline``) at phi folded into its period, then renumbered by the row of
    ``images`` (``flow_images``) for the periods folded away; ``work``: (1 + E, 4). The fold twice, so
    that the kernel's own fold leaves it (a first fold may round to the period's end: that is 0)."""
    from .kernels import spline3

    ts, tp, tb, C = spline
    t3, period = float(tp[3]), float(tp[C.shape[1]] - tp[3])
    p = t3 + ((t3 + ((phi - t3) % period)) - t3) % period
    spline3(ts, tp, tb, C, s, p, beta, work)
    return work[images[math.floor((phi - p) / period + 0.5) % len(images)]]


# ------------------------------------------------------------------------------ building

def default_n_phi(geometry: Geometry) -> int:
    """Table points in phi over one symmetry period at the studied spacing (32 per 180 deg: 32
    for two opposite grooves, 64 for an arc, 21 for three grooves)."""
    return max(8, round(DEFAULT_PHI_PER_PI * symmetry_period(geometry) / math.pi))


def tabulate_grooved(params: BearingParams, *, n_eps: int = DEFAULT_N_EPS, n_phi: int | None = None,
                     n_beta: int = DEFAULT_N_BETA, eps_max: float = DEFAULT_EPS_MAX, n_theta: int | None = None,
                     n_x: int | None = None, cavitation: str = "reynolds", n_phase: int = DEFAULT_N_PHASE,
                     workers: int = 1, progress=None, flows: bool = True, client=None, partial=None,
                     done: dict | None = None) -> GroovedMapTable:
    """The 3-D map of ``params``' grooved or partial-arc bore from the Reynolds internal: one
    solve per table point and phase at r = 1, omega = 1 rad/s; the eps rows are tasks, run as
    ``tables.tabulate`` runs them (``client``, ``workers``, ``partial``, ``done``, ``progress``).
    ``flows``: the flow table Q too, from the same solves' fields (else the force alone, version 2)."""
    from functools import partial as bind

    from ...parallel.rows import solve_rows
    from ...physics.solver.reynolds import Reynolds

    why = map_geometry_problem(params.geometry)
    if why:
        raise ValueError(f"no force map for this bearing's bore ({params.geometry.describe()}): {why}")
    rey = Reynolds(params, n_theta, n_x, cavitation)
    n_phi = n_phi or default_n_phi(params.geometry)
    t0 = time.perf_counter()
    n_q = 1 + len(params.geometry.supply_edges())
    Q = np.zeros((n_eps, n_phi, n_beta, n_q)) if flows else None
    table = GroovedMapTable(params.L / params.D, rey.n_theta, rey.n_x, rey.cavitation, eps_max, params.geometry,
                            np.zeros((n_eps, n_phi, n_beta, 2)), Q=Q)
    task = bind(grooved_row, params, rey.n_theta, rey.n_x, rey.cavitation, phis=table.phi, betas=table.beta,
                n_phase=n_phase, flows=flows)
    for i, (h, q) in enumerate(solve_rows(task, table.eps, done=done, partial=partial, workers=workers,
                                          client=client, progress=progress)):
        table.H[i] = h
        if flows:
            table.Q[i] = q
    table.provenance = {"built_s": round(time.perf_counter() - t0, 3),
                        "solves": n_eps * n_phi * n_beta * n_phase, "n_phase": n_phase,
                        "truth": repr(rey), "bore": params.geometry.describe(),
                        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    return table


def grooved_row(params, n_theta, n_x, cavitation, eps, phis, betas, n_phase, rey=None, flows=True, *, r=1.0,
                per=None):
    """(G, Q) at one eps for every (phi, beta) (a row's task when ``rey`` is None; Q None
    without ``flows``). Each point averages n_phase attitudes spread symmetrically over one nominal
    cell about phi: the solver's cell-scale scatter partly cancels, the grooves' own effect is kept
    to O(cell^2). Q from the same solve's field (``Reynolds.supply_flows``, r = 1): J_s = Q_s / Q0,
    P_e = -(the pressure part of edge e's flux into the film) / Q0. ``r`` [1/s] the states' velocity scale
    and ``per`` [N] what the force is divided by (default S; the fed map's row: W at its r,
    ``supplymap.supplied_row``), the flows then by (per / S) Q0."""
    if rey is None:
        from ...physics.solver.reynolds import Reynolds

        rey = Reynolds(params, n_theta, n_x, cavitation)
    S = scale(params)
    per = S if per is None else per
    cell = 2.0 * math.pi / rey.n_theta
    offsets = ((np.arange(n_phase) + 0.5) / n_phase - 0.5) * cell
    out = np.zeros((len(phis), len(betas), 2))
    Q = np.zeros((len(phis), len(betas), 1 + len(params.geometry.supply_edges()))) if flows else None
    for i, phi0 in enumerate(phis):
        for phi in phi0 + offsets:
            u = np.array([math.cos(phi), math.sin(phi)])
            w = np.array([-math.sin(phi), math.cos(phi)])
            for k, b in enumerate(betas):
                state = state_for(eps, b, params, phi, 1.0, r)
                F = np.array(rey.force(*state, 1.0))
                out[i, k] += (F @ u / per, F @ w / per)
                if flows:
                    j_s, p_e = supply_functions(params, rey.supply_flows(*state, 1.0), per / S)  # the force's field
                    Q[i, k, 0] += j_s
                    Q[i, k, 1:] += p_e
    return out / n_phase, (None if Q is None else Q / n_phase)


# ------------------------------------------------------------------------------- files

GROOVED_KEYS = ("format", "version", "L_over_D", "reynolds", "eps_max", "geometry", "n_eps", "n_phi", "n_beta",
                "grid", "meaning", "H", "provenance")
FLOW_KEYS = ("flow_meaning", "flow_edges_deg", "Q")  # and these in a version 4 file


def save_grooved_map(table: GroovedMapTable, path) -> Path:
    from ...io.outputs import write_text

    return write_text(path, json.dumps(table.to_dict(), indent=None, allow_nan=False, separators=(",", ":")) + "\n")


def grooved_from_data(path: Path, data: dict) -> GroovedMapTable:
    """A version 2 or 4 map from the file's parsed JSON ``data``; every key checked, one line naming
    the file and the key."""
    flows = data.get("version") == FLOW_VERSION
    unknown = sorted(set(data) - set(GROOVED_KEYS + (FLOW_KEYS if flows else ())))
    if unknown:
        raise ValueError(f"force map file {path}: unknown key(s) {', '.join(unknown)}; allowed: "
                         f"{', '.join(GROOVED_KEYS + (FLOW_KEYS if flows else ()))}")
    try:
        rey = data["reynolds"]
        if not isinstance(rey, dict) or set(rey) != {"n_theta", "n_x", "cavitation"}:
            raise ValueError(f"key 'reynolds' = {rey!r:.60} must be an object {{n_theta, n_x, cavitation}}")
        bad = find_non_finite({k: v for k, v in data.items() if k not in ("H", "Q")})
        if bad is not None:
            raise ValueError(f"key {bad!r} is not a finite number (NaN, Infinity or beyond the float range)")
        shape = []
        for k in ("n_eps", "n_phi", "n_beta"):
            v = data[k]
            if isinstance(v, bool) or not isinstance(v, int) or v < 4:
                raise ValueError(f"key {k!r} = {v!r:.40} must be an integer >= 4")
            shape.append(v)
        H = array_key(data, "H")
        if H.shape != (shape[0] * shape[1] * shape[2] * 2,):
            raise ValueError(f"key 'H' has {H.size} numbers, n_eps x n_phi x n_beta x 2 = {math.prod(shape) * 2}")
        try:
            geometry = geometry_from_record(data["geometry"])
        except (TypeError, ValueError, IndexError) as exc:
            raise ValueError(f"key 'geometry': {exc}") from None
        Q = None
        if flows:
            edges = geometry.supply_edges()
            Q = array_key(data, "Q")
            if Q.shape != (math.prod(shape) * (1 + len(edges)),):
                raise ValueError(f"key 'Q' has {Q.size} numbers, n_eps x n_phi x n_beta x (1 + {len(edges)} supply "
                                 f"edges) = {math.prod(shape) * (1 + len(edges))}")
            Q = Q.reshape(*shape, 1 + len(edges))
            rec = data["flow_edges_deg"]
            if not (isinstance(rec, list) and len(rec) == len(edges) and all(
                    isinstance(x, list) and len(x) == 2 and isinstance(x[0], (int, float)) and x[1] == sg
                    and abs(math.remainder(math.radians(x[0]) - t, 2 * math.pi)) < GEOMETRY_RTOL
                    for x, (t, sg) in zip(rec, edges))):
                raise ValueError(f"key 'flow_edges_deg' = {rec!r:.80} must list the bore's supply edges [theta_deg, "
                                 f"sign] in order: {[[round(math.degrees(t), 9), sg] for t, sg in edges]}")
        table = GroovedMapTable(number_key(data, "L_over_D"), rey["n_theta"], rey["n_x"], rey["cavitation"],
                                number_key(data, "eps_max"), geometry, H.reshape(*shape, 2),
                                data.get("provenance", {}), Q=Q)
    except KeyError as exc:
        raise ValueError(f"force map file {path}: missing key {exc.args[0]!r}") from None
    except ValueError as exc:
        raise ValueError(f"force map file {path}: {str(exc).removeprefix('force map table: ')}") from None
    if not isinstance(table.provenance, dict):
        raise ValueError(f"force map file {path}: key 'provenance' must be an object, got {table.provenance!r:.60}")
    return table


# ---------------------------------------------------------------------------- internal

class GroovedForceMap(ForceMap):
    """The map internal for a grooved or partial-arc bore: ``force`` and ``force_and_jacobian``
    (analytic, from the 3-D spline's derivatives; ForceMap's, with this kernel) for a bearing whose
    L/D and bore equal the table's; states at or beyond eps_max are refused."""

    # not ForceMap.__init__, which refuses every bore but the full circle
    def __init__(self, params: BearingParams, table: GroovedMapTable, source: str = ""):
        where = f"force map{' ' + source if source else ''}"
        if not same_bore(params.geometry, table.geometry):
            raise ValueError(f"{where} is for the bore '{table.geometry.describe()}', the bearing has "
                             f"'{params.geometry.describe()}': build a map for it with "
                             "`bearing-fmu map --bearing FILE -o MAP`")
        ld = params.L / params.D
        if not abs(ld - table.L_over_D) <= LD_RTOL * table.L_over_D:
            raise ValueError(f"{where} is for L/D = {table.L_over_D:.6g}, the bearing has L/D = {ld:.6g} (L = "
                             f"{params.L:g} m, D = {params.D:g} m): build a map for it with "
                             "`bearing-fmu map --bearing FILE -o MAP`")
        self.params, self.table, self.source = params, table, source
        ts, tp, tb, C = table.spline()
        self._F = np.zeros(2)
        self._J = np.zeros((2, 4))
        from .kernels import map3_force

        self._kernel = map3_force
        self._args = (ts, tp, tb, C, EPS_MIN, scale(params), float(params.CR))
        self._eps_max = float(table.eps_max)
        # the film's flows (registry capability film_flow, per file): '' when the file has them
        self.film_flow_why = "" if table.Q is not None else NO_FLOWS_WHY.format(source=source or "(in memory)")
        self._edges = table.edges  # the flow spline is fitted at the first film report (0.2 s for a shipped map)
        self._Jq = None if table.Q is None else np.zeros((table.Q.shape[3], 4))
        self._images = None if table.Q is None else table.flow_images()

    def compiled_force(self):
        """None: no compiled kernel of the 3-D map yet (a host calls ``force_and_jacobian``); not
        the full bore's, which a ForceMap may offer and which would read this table wrongly."""
        return None

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction (closed form, from the force) and flows (the file's flow table, the inflow summed
        over the supply edges) of the film, as ``Reynolds.film_report`` (``film.grooved_report``;
        docs/forcemap.md, "Grooved bores: the flows"); ValueError without the table."""
        if self.table.Q is None:
            raise ValueError(f"film_report: {self.film_flow_why}")
        F = self.force(y, z, vy, vz, omega)
        eps, phi, a, c = reduced(float(y), float(z), float(vy), float(vz), float(omega), self.params.CR)
        q = flow_components(self.table.flow_spline(), self._images, -math.log1p(-max(eps, EPS_MIN)), phi,
                            math.atan2(c, a), self._Jq)
        return grooved_report(self.params, float(y), float(z), float(vy), float(vz), float(omega), F,
                              float(np.hypot(a, c)), float(q[0, 0]), q[1:, 0], self._edges)

    @classmethod
    def from_file(cls, path, params: BearingParams) -> "GroovedForceMap":
        data = json.loads(Path(path).read_text())
        return cls(params, grooved_from_data(Path(path), data), source=str(path))

    def __repr__(self) -> str:
        t = self.table
        return (f"GroovedForceMap(L/D {t.L_over_D:.4g}, {t.geometry.describe()}, {t.n_eps} x {t.n_phi} x "
                f"{t.n_beta}, eps <= {t.eps_max:g}, Reynolds {t.n_theta} x {t.n_x} {t.cavitation})")
