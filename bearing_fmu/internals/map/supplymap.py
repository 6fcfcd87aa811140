"""The force map of a grooved or partial-arc bore whose grooves are fed at a supply pressure p_s > 0:
a 4-D table, exact by homogeneity as the ambient grooves' 3-D map (``groovemap``) is.

The derivation. In the journal's frame the film is h = CR (1 + eps cos psi) and Reynolds' right-hand
side is -6 mu CR r sin(psi - beta) (docs/forcemap.md). With x = R X and h = CR H the equation reads
(CR^3 / R^2) div_(theta, X)(H^3 grad p) = -6 mu CR r sin(psi - beta), so with the pressure scale k r,
k = mu (R / CR)^2 [Pa s], p = k r P(psi, X) where div(H^3 grad P) = -6 sin(psi - beta) on the
bore of the given L/D whose only data are (eps, phi, beta) and the grooves' value p_s / (k r). The
cavitation problem (p >= 0, complementary to the Reynolds residual) is a linear complementarity
problem whose right-hand side is linear in (r, p_s) jointly (the film source, the grooves'
Dirichlet values): its solution is positively homogeneous of degree 1 in (k r, p_s) together,
p(lambda r, lambda p_s) = lambda p(r, p_s) for lambda > 0, though not superposable (the cavitated
set depends on the ratio). Dividing by k r + p_s instead of k r keeps the table bounded at both ends:

    F = W (G_r(eps, phi, beta, u) u_ + G_t(eps, phi, beta, u) w_),    W = S r + R L p_s,
    u = R L p_s / W = sigma / (1 + sigma) in [0, 1],   sigma = p_s / (k r),

with S = mu R L (R / CR)^2 = k R L the 3-D map's scale (so W = R L (k r + p_s)), u_, w_ the unit
vectors along and across the line of centres and the grooves' own cells' force (p_s over their
area) included, as the solver has it. u = 0 (p_s / r -> 0) is the 3-D map exactly (W = S r); u = 1
is the journal at rest (r = 0): F = R L p_s G(eps, phi, ., 1), the still journal's supply force,
the same for every beta (its table row is one value). Near u = 1, G = (1 - t) Q + t (cos beta A +
sin beta B) + O(t^2) with t = 1 - u = S r / W, so the force is smooth in (a, c) through r = 0 and
the kernel's (a, c) derivatives (``supplykernels``: G_beta / (1 - u)) stay finite. D, CR, mu and p_s
enter only through W and u: the table serves every bearing of its L/D and bore at any p_s > 0.

The table: G on the 3-D map's axes (s = -ln(1 - eps), phi over the bore's symmetry period, beta)
times u_l = 1 - (1 - l / (n_sup - 1))^2 (crowded toward rest, where G turns fastest: ``U_GRADING``);
the rows are (eps, u) pairs, each the n_phi x n_beta solves at the r
that gives u with the bearing's own p_s (r = R L p_s (1 - u) / (S u); u = 0: p_s = 0 and r = 1);
the spline is cubic, not-a-knot in s and u, periodic in phi and beta; at the nodes the map is the
solver's answer. The flows reduce the same way with W / S in place of r: side flow (W / S) Q0 J_s,
the pressure part of edge e's flux (W / S) Q0 P_e (groovemap's docstring); the friction adds to the
3-D map's pressure torque the fed edges' boundary term (``fed_edge_torque``).

The file: format ``bearing-fmu-force-map`` version 6 (force), 7 (with the flow table); the bore's
geometry with the p_s it was built at (any p_s > 0 is served).
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...physics.bore.geometry import Geometry
from ...physics.params import BearingParams
from ...physics.solver.film import FilmReport, assemble_report, grooved_report
from . import groovemap as gm
from .tablefile import number_key
from .tables import EPS_MIN, LD_RTOL, finite_problem, header_problem, reduced, scale

VERSION, FLOW_VERSION = 6, 7  # (5 is left unread: an old test names it as the unknown version)
# points in u = sigma / (1 + sigma) on [0, 1]: the error against Reynolds falls from 9 to 13 and stays from 13
# to 17, where the other axes' error is left (docs/forcemap.md, "Fed grooves: the 4-D map")
DEFAULT_N_SUP = 13
# G bends in u where the motion's suction starts to cavitate the supply field, which moves with (eps, beta)
# over the whole axis and is steepest near rest (eps = 0.7: G_r moves by 0.3 between 1 - u = 0.04 and 0.001),
# so the nodes crowd toward u = 1; grading 2 did a little better than 3 at 13 points (the study)
U_GRADING = 2.0
KEYS = tuple(k for k in gm.GROOVED_KEYS) + ("n_sup", "u_grading", "supply_pressure_kPa")


def u_nodes(n: int, grading: float = U_GRADING) -> np.ndarray:
    """The table's u: 1 - (1 - l / (n - 1))^grading, l = 0 .. n - 1, clustered toward u = 1 (rest)."""
    return 1.0 - (1.0 - np.arange(n) / (n - 1)) ** grading


def supply_problem(geometry: Geometry) -> str | None:
    """Why no fed-groove map serves this bore (a phrase), or None: the 3-D map's conditions but for
    the supply pressure, which must be > 0 (ambient grooves have the 3-D map)."""
    if not geometry.supply_pressure > 0.0:
        return "supply_pressure_kPa = 0: ambient grooves have the 3-D map (groovemap), not the fed-groove map"
    return gm.map_geometry_problem(dataclasses.replace(geometry, supply_pressure=0.0))


def ambient(geometry: Geometry) -> Geometry:
    return dataclasses.replace(geometry, supply_pressure=0.0)


def supply_force(params: BearingParams) -> float:
    """R L p_s [N]: the force scale of the grooves' supply pressure (W = S r + this)."""
    return params.R * params.L * params.geometry.supply_pressure


@dataclass
class SupplyMapTable(gm.GroovedMapTable):
    """G on (s, phi, beta) as ``GroovedMapTable`` times u (``u_nodes`` of ``u_grading``, kept in the file);
    H (n_eps, n_phi, n_beta, n_sup, 2), Q None or (n_eps, n_phi, n_beta, n_sup, 1 + E); F = (S r + R L p_s)
    (G_r u_ + G_t w_)."""

    u_grading: float = U_GRADING

    def problem(self) -> str | None:
        problem = header_problem(self)
        if problem:
            return problem
        why = supply_problem(self.geometry)
        if why:
            return f"key 'geometry': {why}"
        if not (isinstance(self.u_grading, (int, float)) and 1.0 <= self.u_grading <= 4.0):
            return f"key 'u_grading' = {self.u_grading!r:.40} must be a number in 1 .. 4"
        if self.H.ndim != 5 or self.H.shape[4] != 2 or min(self.H.shape[:4]) < 4:
            return f"key 'H' has shape {self.H.shape}, expected (n_eps, n_phi, n_beta, n_sup, 2), each n >= 4"
        want = (*self.H.shape[:4], 1 + len(self.edges))
        if self.Q is not None and self.Q.shape != want:
            return f"key 'Q' has shape {self.Q.shape}, expected {want}"
        return finite_problem(self.H) or (None if self.Q is None else finite_problem(self.Q, "Q"))

    n_sup = property(lambda self: self.H.shape[3])

    @property
    def u(self) -> np.ndarray:
        return u_nodes(self.n_sup, self.u_grading)

    def fit_spline(self, values, turns: int = 1):
        """(ts, tp, tb, tu, C): the 3-D map's fit along (s, phi, beta), then not-a-knot along u."""
        ts, tp, tb, C = super().fit_spline(values, turns)
        tu = gm.not_a_knot_knots(self.u)
        return ts, tp, tb, tu, np.ascontiguousarray(gm.fit_axis(C, 3, tu, self.u, False))

    def flow_spline(self):
        """As ``GroovedMapTable.flow_spline``, with the u axis (None without flow tables)."""
        if self.flow_coefficients is None and self.Q is not None:
            images = self.flow_images()
            ts, _, tb, tu, C = self.fit_spline(self.unrolled_flows(), len(images))
            C = np.concatenate([C[:, :self.n_phi], C[:, :3][..., images[1 % len(images)]]], axis=1)
            self.flow_coefficients = (ts, self.knots()[1], tb, tu, np.ascontiguousarray(C))
        return self.flow_coefficients

    def to_dict(self) -> dict:
        d = gm.GroovedMapTable.to_dict(self)  # its H and Q flattened the same way (C order), its keys
        d.update(version=VERSION if self.Q is None else FLOW_VERSION, n_sup=self.n_sup, u_grading=self.u_grading,
                 supply_pressure_kPa=self.geometry.supply_pressure / 1e3,
                 grid=d["grid"] + ("; u_l = 1 - (1 - l / (n_sup - 1))^u_grading on [0, 1], u = R L p_s / (S r + "
                                   "R L p_s)"),
                 meaning=("H[i][j][k][l] = (G_r, G_t); F = (S r + R L p_s) (G_r u + G_t w), S = mu R L (R/CR)^2, "
                          "u = R L p_s / (S r + R L p_s), phi the journal's attitude atan2(z, y); the table serves any "
                          "p_s > 0 (supply_pressure_kPa: the one it was built at); spline: cubic, not-a-knot in s "
                          "and u, periodic in phi and beta, fitted on loading"))
        if self.Q is not None:
            d["flow_meaning"] = d["flow_meaning"].replace("r R L CR J_s", "(W / S) R L CR J_s").replace(
                "r R L CR P_e", "(W / S) R L CR P_e") + "; W = S r + R L p_s, one more axis u"
        return d


def save_supply_map(table: SupplyMapTable, path) -> Path:
    return gm.save_grooved_map(table, path)


def supply_from_data(path: Path, data: dict) -> SupplyMapTable:
    """A version 6 or 7 map from the file's parsed JSON ``data``: the 3-D reader's checks on its keys,
    with the u axis and the supply pressure."""
    flows = data.get("version") == FLOW_VERSION
    allowed = KEYS + (gm.FLOW_KEYS if flows else ())
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise ValueError(f"force map file {path}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}")
    try:
        n_sup = data["n_sup"]
        if isinstance(n_sup, bool) or not isinstance(n_sup, int) or n_sup < 4:
            raise ValueError(f"key 'n_sup' = {n_sup!r:.40} must be an integer >= 4")
        p_s = number_key(data, "supply_pressure_kPa") * 1e3
        grading = number_key(data, "u_grading")
        dims = [data[k] for k in ("n_eps", "n_phi", "n_beta")]
        if all(isinstance(v, int) and not isinstance(v, bool) for v in dims) and isinstance(data["H"], list) \
                and len(data["H"]) != math.prod(dims) * n_sup * 2:
            raise ValueError(f"key 'H' has {len(data['H'])} numbers, n_eps x n_phi x n_beta x n_sup x 2 = "
                             f"{math.prod(dims) * n_sup * 2}")
        if not p_s > 0.0:
            raise ValueError(f"key 'supply_pressure_kPa' = {p_s / 1e3!r} must be > 0 (ambient grooves have the "
                             "3-D map)")
        # the 3-D reader on the same keys with the u axis folded into beta's: its checks of every key
        d3 = {k: v for k, v in data.items() if k not in ("n_sup", "u_grading", "supply_pressure_kPa")}
        d3.update(version=gm.FLOW_VERSION if flows else gm.VERSION, n_beta=data["n_beta"] * n_sup)
    except KeyError as exc:
        raise ValueError(f"force map file {path}: missing key {exc.args[0]!r}") from None
    except ValueError as exc:
        raise ValueError(f"force map file {path}: {exc}") from None
    t3 = gm.grooved_from_data(path, d3)
    shape = (t3.n_eps, t3.n_phi, data["n_beta"], n_sup)
    try:
        return SupplyMapTable(t3.L_over_D, t3.n_theta, t3.n_x, t3.cavitation, t3.eps_max,
                              dataclasses.replace(t3.geometry, supply_pressure=p_s), t3.H.reshape(*shape, 2),
                              t3.provenance, Q=None if t3.Q is None else t3.Q.reshape(*shape, -1), u_grading=grading)
    except ValueError as exc:
        raise ValueError(f"force map file {path}: {str(exc).removeprefix('force map table: ')}") from None


# ------------------------------------------------------------------------------ building

def tabulate_supplied(params: BearingParams, *, n_eps: int = gm.DEFAULT_N_EPS, n_phi: int | None = None,
                      n_beta: int = gm.DEFAULT_N_BETA, n_sup: int = DEFAULT_N_SUP, u_grading: float = U_GRADING,
                      eps_max: float = gm.DEFAULT_EPS_MAX,
                      n_theta: int | None = None, n_x: int | None = None, cavitation: str = "reynolds",
                      n_phase: int = gm.DEFAULT_N_PHASE, workers: int = 1, progress=None, flows: bool = True,
                      client=None, partial=None, done: dict | None = None) -> SupplyMapTable:
    """The 4-D map of ``params``' fed grooves from the Reynolds internal; its rows the (eps, u) pairs
    (row i n_sup + l), run as ``groovemap.tabulate_grooved`` runs its eps rows."""
    from functools import partial as bind

    from ...parallel.rows import solve_rows
    from ...physics.solver.reynolds import Reynolds

    why = supply_problem(params.geometry)
    if why:
        raise ValueError(f"no fed-groove force map for this bearing's bore ({params.geometry.describe()}): {why}")
    rey = Reynolds(params, n_theta, n_x, cavitation)
    n_phi = n_phi or gm.default_n_phi(params.geometry)
    t0 = time.perf_counter()
    n_q = 1 + len(params.geometry.supply_edges())
    table = SupplyMapTable(params.L / params.D, rey.n_theta, rey.n_x, rey.cavitation, eps_max, params.geometry,
                           np.zeros((n_eps, n_phi, n_beta, n_sup, 2)),
                           Q=np.zeros((n_eps, n_phi, n_beta, n_sup, n_q)) if flows else None, u_grading=u_grading)
    task = bind(supplied_row, params, rey.n_theta, rey.n_x, rey.cavitation, phis=table.phi, betas=table.beta,
                n_phase=n_phase, flows=flows)
    rows = [(e, u) for e in table.eps for u in table.u]
    for k, (h, q) in enumerate(solve_rows(task, rows, done=done, partial=partial, workers=workers, client=client,
                                          progress=progress)):
        i, l = divmod(k, n_sup)
        table.H[i, :, :, l] = h
        if flows:
            table.Q[i, :, :, l] = q
    table.provenance = {"built_s": round(time.perf_counter() - t0, 3),
                        "solves": n_eps * n_phi * n_beta * n_sup * n_phase, "n_phase": n_phase,
                        "truth": repr(rey), "bore": params.geometry.describe(),
                        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    return table


def row_state(params: BearingParams, u: float) -> tuple[BearingParams, float, float]:
    """(the bearing the row solves, its r [1/s], W [N]) for the table's u: the bearing's own p_s at
    r = R L p_s (1 - u) / (S u); u = 0 at ambient grooves and r = 1 (W = S r); u = 1 at rest (W = R L p_s)."""
    S, P = scale(params), supply_force(params)
    if u <= 0.0:
        return dataclasses.replace(params, geometry=ambient(params.geometry)), 1.0, S
    return params, (P * (1.0 - u) / (S * u) if u < 1.0 else 0.0), P / u


def supplied_row(params, n_theta, n_x, cavitation, x, phis, betas, n_phase, flows=True):
    """(G, Q) at one (eps, u) = ``x`` for every (phi, beta): ``groovemap.grooved_row`` of the row's
    bearing at ``row_state``'s r, divided by W (the flows by (W / S) Q0)."""
    eps, u = x
    bearing, r, W = row_state(params, u)
    return gm.grooved_row(bearing, n_theta, n_x, cavitation, eps, phis, betas, n_phase, flows=flows, r=r, per=W)


# ---------------------------------------------------------------------------- internal

def fed_edge_torque(params: BearingParams, y: float, z: float) -> float:
    """The fed edges' share of the film's pressure torque [N m]: (R / 2) int h dp/dtheta over the film,
    by parts, gains -(R L / 2) sum_e sign_e h_e p_e over the supply edges whose groove holds p_e = p_s
    (the 3-D map's grooved_report has p = 0 there); h_e = CR + y sin(theta_e) - z cos(theta_e)."""
    g = params.geometry
    total = 0.0
    for theta, sign in g.supply_edges():
        inside = theta - 1e-9 * sign  # the prescribed side of the edge
        if any(math.remainder(inside - 0.5 * (a + b), 2.0 * math.pi) ** 2 < (0.5 * (b - a)) ** 2
               for a, b in g.groove_edges()):
            total += sign * (params.CR + y * math.sin(theta) - z * math.cos(theta))
    return -0.5 * params.R * params.L * g.supply_pressure * total


def flow_components4(spline, images, s: float, phi: float, beta: float, u: float, work: np.ndarray) -> np.ndarray:
    """``groovemap.flow_components`` with the u axis (``supplykernels.spline4``)."""
    from .supplykernels import spline4

    ts, tp, tb, tu, C = spline
    t3, period = float(tp[3]), float(tp[C.shape[1]] - tp[3])
    p = t3 + ((t3 + ((phi - t3) % period)) - t3) % period
    spline4(ts, tp, tb, tu, C, s, p, beta, u, work)
    return work[images[math.floor((phi - p) / period + 0.5) % len(images)]]


class SupplyForceMap(gm.GroovedForceMap):
    """The map internal for fed grooves: ``force`` and ``force_and_jacobian`` (analytic, from the 4-D
    spline's derivatives, ``supplykernels.map4_force``) and the film report, for a bearing whose L/D
    and bore equal the table's, at any p_s > 0."""

    def __init__(self, params: BearingParams, table: SupplyMapTable, source: str = ""):
        where = f"force map{' ' + source if source else ''}"
        if not params.geometry.supply_pressure > 0.0:
            raise ValueError(f"{where} is for fed grooves (supply_pressure_kPa > 0), the bearing's are at ambient "
                             "pressure: its map is the 3-D one, `bearing-fmu map --bearing FILE -o MAP`")
        if not gm.same_bore(ambient(params.geometry), ambient(table.geometry)):
            raise ValueError(f"{where} is for the bore '{table.geometry.describe()}', the bearing has "
                             f"'{params.geometry.describe()}': build a map for it with "
                             "`bearing-fmu map --bearing FILE -o MAP`")
        ld = params.L / params.D
        if not abs(ld - table.L_over_D) <= LD_RTOL * table.L_over_D:
            raise ValueError(f"{where} is for L/D = {table.L_over_D:.6g}, the bearing has L/D = {ld:.6g} (L = "
                             f"{params.L:g} m, D = {params.D:g} m): build a map for it with "
                             "`bearing-fmu map --bearing FILE -o MAP`")
        self.params, self.table, self.source = params, table, source
        ts, tp, tb, tu, C = table.spline()
        from .supplykernels import map4_force

        self._F, self._J = np.zeros(2), np.zeros((2, 4))
        self._kernel = map4_force
        self._args = (ts, tp, tb, tu, C, EPS_MIN, scale(params), float(params.CR), supply_force(params))
        self._eps_max = float(table.eps_max)
        self.film_flow_why = "" if table.Q is not None else (
            f"the fed-groove map {source or '(in memory)'} has no flow tables (format version 6): rebuild it with "
            "`bearing-fmu map --bearing FILE -o MAP`")
        self._edges = params.geometry.supply_edges()
        self._Jq = None if table.Q is None else np.zeros((table.Q.shape[4], 5))
        self._images = None if table.Q is None else table.flow_images()

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """As ``GroovedForceMap.film_report`` with W / S for r (the module docstring) and the fed edges'
        pressure torque (``fed_edge_torque``)."""
        if self.table.Q is None:
            raise ValueError(f"film_report: {self.film_flow_why}")
        F = self.force(y, z, vy, vz, omega)
        eps, phi, a, c = reduced(float(y), float(z), float(vy), float(vz), float(omega), self.params.CR)
        r = float(np.hypot(a, c))
        S = scale(self.params)
        W = S * r + supply_force(self.params)
        q = flow_components4(self.table.flow_spline(), self._images, -math.log1p(-max(eps, EPS_MIN)), phi,
                             math.atan2(c, a) if r > 0.0 else 0.0, supply_force(self.params) / W, self._Jq)
        rep = grooved_report(self.params, float(y), float(z), float(vy), float(vz), float(omega), F, W / S,
                             float(q[0, 0]), q[1:, 0], self._edges)
        return assemble_report(self.params, rep.couette_torque_Nm,
                               rep.pressure_torque_Nm + fed_edge_torque(self.params, float(y), float(z)), F,
                               (float(vy), float(vz)), float(omega), rep.inflow_m3_s, rep.side_flow_m3_s)

    @classmethod
    def from_file(cls, path, params: BearingParams) -> "SupplyForceMap":
        return cls(params, supply_from_data(Path(path), json.loads(Path(path).read_text())), source=str(path))

    def __repr__(self) -> str:
        t = self.table
        return (f"SupplyForceMap(L/D {t.L_over_D:.4g}, {t.geometry.describe()}, {t.n_eps} x {t.n_phi} x {t.n_beta} x "
                f"{t.n_sup}, eps <= {t.eps_max:g}, Reynolds {t.n_theta} x {t.n_x} {t.cavitation})")
