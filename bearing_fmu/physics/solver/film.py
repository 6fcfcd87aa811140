"""Friction and oil flow of the film: what a thermal model starts from (docs/thermal.md).

Computed from a converged pressure field (``Reynolds.film_report``), outside the solver's hot
force loop; the friction of the full bore also in closed form from the force alone
(``full_bore_friction``), so every internal (map, Taylor, linear) has it.

Shear on the journal (DESIGN.md: the surface moves toward increasing theta at U = omega R)
------------------------------------------------------------------------------------------
The film's velocity u(n) = U (1 - n/h) + (1/(2 mu)) dp/ds (n^2 - n h) across the gap (n = 0 on
the journal, s = R theta) drags the journal against its motion with

    tau = mu U / h + (h / 2) dp/ds            (Couette + Poiseuille)

so the drag torque T = R int int tau R dtheta dx and the friction force T / R. Raimondi & Boyd
(1958) shear the whole circumference as a full film, the cavitated (Swift-Stieber) region
included: their friction variable (r/c) f is reproduced only that way (at h0/c = 0.1, L/D = 1:
Couette over the full circle 0.851 plus the pressure part eps sin(phi) / 2 = 0.200 gives 1.051,
their table 1.05; shearing only the pressurised film gives about half). This module does the
same: a film rupture zone whose striations carry a fraction h_film / h of the gap would shear
less (Couette term times that fraction); the difference is in docs/thermal.md's limits.

Full bore, in closed form (any internal):
    Couette   T_c = 2 pi mu omega R^3 L / (CR sqrt(1 - eps^2))      (int_0^2pi dtheta / h exactly)
    Poiseuille T_p = (R / 2) int int h dp/dtheta dtheta dx = (y Fz - z Fy) / 2
                     (by parts, dh/dtheta = y cos + z sin; F the film force on the journal)
The Couette part scales with omega alone (and mu, and the eccentricity), the pressure part with
the journal's offset r and the force: what the force map and the Taylor surrogate hold already.
The friction power is P = T omega - F . v (the journal's surface work less the work the film
does on the moving journal centre; v = 0 at a static equilibrium).

Flow (cell-face fluxes of the finite-volume discretisation, so they balance to round-off)
-----------------------------------------------------------------------------------------
    circumferential, per unit length:  q = omega R h / 2 - h^3 / (12 mu R) dp/dtheta
    axial, per unit circumference:      q_x = - h^3 / (12 mu) dp/dx
Side flow: the axial flow out of both ends of every film cell (the end gradient is the solver's
own second-order one, (9 p0 - p1) / (3 dx)). Inflow: the oil entering the film, through every
line where it enters: from every cell with a prescribed pressure (a groove, the ambient outside an
arc) into the film next to it, where positive (the grooves' and the arc's leading edges); in a
preloaded lobed bore, across each lobe's own line of thickest film (``lobe_feed_faces``: each lobe
converges and cavitates on its own, so one line for all of them let the side flow reach 4x the
inflow); in the full bore the circumferential flow across its line of thickest film, interpolated
between the two faces around it: Raimondi & Boyd's full bearing is fed there. Where no cell
cavitates, the net flow in through those lines is the side flow to round-off
(tests/test_flow_balance.py); Swift-Stieber's film reforms a little upstream of a thickest line, so
there Qs may exceed Q by a few per cent (Raimondi & Boyd's plain full bore: 1.3 % at h0/c = 0.03).
A flow that is NaN, infinite or negative is a ``FlowError`` (``check_flows``), never a report.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .lands import axial_stencil, film_length, groove_inflow, has_lands
from ..params import BearingParams

__all__ = ["FilmReport", "FlowError", "assemble_report", "cavitated_relief", "require_full_shear", "shear_option", "check_flows", "at_viscosity", "edge_flows", "face_fluxes", "field_report",
           "film_couette_integral", "flow_field", "flow_scale", "full_bore_friction", "grooved_report", "lobe_feed_faces", "reduced_flows",
           "reduced_report", "side_flow", "supply_edges", "supply_functions"]


@dataclass(frozen=True)
class FilmReport:
    """Friction and flow of the film at one state (SI).

    friction_torque_Nm  : drag torque on the journal, opposing the rotation [N m]
    friction_force_N    : the drag at the journal surface, torque / R [N]
    friction_power_W    : power the film dissipates, T omega - F . v [W]
    friction_coefficient: friction force / the film force's magnitude (nan when it is 0) [-]
    couette_torque_Nm, pressure_torque_Nm : the two parts of the torque [N m]
    inflow_m3_s         : oil entering the film (see the module docstring) [m^3/s]
    side_flow_m3_s      : axial flow out of both ends [m^3/s]
    load_N              : magnitude of the film force [N]
    """

    friction_torque_Nm: float
    friction_force_N: float
    friction_power_W: float
    friction_coefficient: float
    couette_torque_Nm: float
    pressure_torque_Nm: float
    inflow_m3_s: float
    side_flow_m3_s: float
    load_N: float

    def as_dict(self) -> dict[str, float]:
        return {k: float(v) for k, v in asdict(self).items()}


def assemble_report(params: BearingParams, tc: float, tp: float, F, v, omega: float, q_in: float,
                    q_s: float) -> FilmReport:
    """The report from its parts: Couette and pressure torques [N m], the film force F and the
    journal velocity v [N, m/s] at omega [rad/s], inflow and side flow [m^3/s] (``check_flows``)."""
    check_flows(q_in, q_s, "film report")
    t = tc + tp
    w = float(math.hypot(F[0], F[1]))
    ff = abs(t) / params.R
    power = t * omega - (F[0] * v[0] + F[1] * v[1])
    return FilmReport(friction_torque_Nm=t, friction_force_N=ff, friction_power_W=power,
                      friction_coefficient=ff / w if w > 0.0 else math.nan, couette_torque_Nm=tc,
                      pressure_torque_Nm=tp, inflow_m3_s=q_in, side_flow_m3_s=q_s, load_N=w)


def at_viscosity(report: FilmReport, factor: float) -> FilmReport:
    """The report of the same state at the viscosity ``factor`` times the report's: the pressure, the
    shear, the force and the friction scale with mu, the flows (pressure / mu) and the friction
    coefficient do not (what an internal's report gives at an effective viscosity, docs/thermal.md)."""
    f = float(factor)
    return FilmReport(**{k: v * f if k.startswith(("friction_torque", "friction_force", "friction_power", "couette",
                                                   "pressure", "load")) else v
                         for k, v in report.as_dict().items()})


def full_bore_friction(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float,
                       F) -> tuple[float, float, float]:
    """(Couette torque, pressure torque, friction power) [N m, N m, W] of the full 360 deg bore in
    closed form (module docstring), from the journal state (y, z [m], vy, vz [m/s], omega [rad/s])
    and the film force F = (Fy, Fz) [N] of any internal at that state."""
    params.require_full_bore("full_bore_friction", "its Couette integral is the circular film's")
    require_full_shear(params, "full_bore_friction")
    eps = math.hypot(y, z) / params.CR
    if not eps < 1.0:
        raise ValueError(f"full_bore_friction: eccentricity ratio {eps:.6g} >= 1 (the journal touches the bore)")
    tc = 2.0 * math.pi * params.mu * omega * params.R ** 3 * params.L / (params.CR * math.sqrt(1.0 - eps * eps))
    tp = 0.5 * (y * float(F[1]) - z * float(F[0]))
    power = (tc + tp) * omega - (float(F[0]) * vy + float(F[1]) * vz)
    return tc, tp, power


def _cells(n: int, grid):
    """(width, centre, right, fixed, supply, dist, face_h0, centre_h0) of the n cells (``grid`` a
    ``thetagrid.ThetaGrid``, None: the full bore's uniform cells)."""
    if grid is None:
        w = np.full(n, 2.0 * math.pi / n)
        centre = np.arange(n) * w[0]
        return w, centre, centre + 0.5 * w, np.zeros(n, dtype=bool), np.zeros(n), w.copy(), np.ones(n), np.ones(n)
    return (grid.width, grid.centre, grid.right, grid.fixed.astype(bool), grid.supply, grid.dist, grid.face_film,
            grid.centre_film)


def _faces(params: BearingParams, y: float, z: float, p_half: np.ndarray, cells):
    """(p, hf, dp): the pressure with the prescribed cells' own along the whole length, the film at
    every right face [m] and dp/dtheta across it [Pa/rad]."""
    _w, _centre, right, fixed, psup, dist, face_h0, _ = cells
    nxt = np.roll(np.arange(fixed.shape[0]), -1)
    hf = params.CR * face_h0 + y * np.sin(right) - z * np.cos(right)
    p = np.where(fixed[:, None], psup[:, None], p_half)
    safe = np.where(dist > 0.0, dist, 1.0)
    return p, hf, (p[nxt] - p) / safe[:, None]


def _end_flows(params: BearingParams, y: float, z: float, p_half: np.ndarray, dx: float, cells) -> np.ndarray:
    """The axial flow [m^3/s] out of one end of every cell (0 for a prescribed one), with the solver's
    own second-order end gradient."""
    w, centre, fixed, centre_h0 = cells[0], cells[1], cells[3], cells[7]
    hc = params.CR * centre_h0 + y * np.sin(centre) - z * np.cos(centre)
    if p_half.shape[1] == 1:
        grad_end = 8.0 * p_half[:, 0] / (3.0 * dx)
    else:
        grad_end = (9.0 * p_half[:, 0] - p_half[:, 1]) / (3.0 * dx)
    return np.where(fixed, 0.0, hc ** 3 / (12.0 * params.mu) * grad_end * params.R * w)


def side_flow(params: BearingParams, y: float, z: float, p_half: np.ndarray, dx: float, grid=None) -> float:
    """The axial flow [m^3/s] out of both ends of every film cell (the arguments as ``field_report``'s):
    the end gradient the solver's own second-order one."""
    return float(np.sum(_end_flows(params, y, z, p_half, dx, _cells(p_half.shape[0], grid)))) * 2.0


def flow_field(params: BearingParams, y: float, z: float, omega: float, p_half: np.ndarray, dx: float,
               grid=None) -> tuple[np.ndarray, np.ndarray]:
    """The flows of a converged field cell by cell (the arguments as ``field_report``'s): the
    circumferential flux across every right face over the whole length [m^3/s] (toward increasing
    theta) and the axial flow out of both ends of every cell [m^3/s] (0 for a prescribed one); what
    ``field_report`` sums into the inflow and the side flow, so a stretch of film whose every node is
    pressurised balances: the flux into it less the flux out of it is its side flow (squeeze aside)."""
    cells = _cells(p_half.shape[0], grid)
    _p, hf, dp = _faces(params, y, z, p_half, cells)
    couette, pressure = face_fluxes(params, omega, hf, dp, dx)
    return couette - pressure, 2.0 * _end_flows(params, y, z, p_half, dx, cells)


def field_report(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float, F,
                 p_half: np.ndarray, dx: float, grid=None) -> FilmReport:
    """The film report from a converged pressure field (``Reynolds.film_report`` calls it).

    p_half : (n_theta, m) [Pa], the half length x < 0, column 0 at the end (the solver's order)
    dx     : axial cell length [m]
    grid   : the bore's ``thetagrid.ThetaGrid`` (None: the full bore's uniform cells)
    """
    mu, R, CR = params.mu, params.R, params.CR
    n, m = p_half.shape
    F = (float(F[0]), float(F[1]))
    v = (float(vy), float(vz))
    cells = _cells(n, grid)
    w, centre, right, fixed = cells[:4]
    nxt = np.roll(np.arange(n), -1)
    hc = CR * cells[7] + y * np.sin(centre) - z * np.cos(centre)
    p, hf, dp = _faces(params, y, z, p_half, cells)
    # axial weights of the half length (both halves: x 2): the solver's quadrature for p, plain
    # cell lengths for the fluxes through the faces
    lands = has_lands(params)  # a circumferential groove: p_half is one land (physics.solver.lands)
    qw = axial_stencil(m, dx, lands)[2]
    film_face = ~(fixed & fixed[nxt])                    # faces with film on at least one side
    # --- friction: Couette over the film (as a full film), pressure part summed over the faces
    if grid is None or grid.geometry.is_circle:  # the lands' film is the circular one (the groove shears none)
        eps = math.hypot(y, z) / CR
        tc = 2.0 * math.pi * mu * omega * R ** 3 * film_length(params) / (CR * math.sqrt(1.0 - eps * eps))
        tp = 0.5 * (y * F[1] - z * F[0])
    else:
        g = grid.geometry
        lobe = g.lobe_of(centre)
        left = grid.left
        h_l = CR * g.base_film(left, lobe) + y * np.sin(left) - z * np.cos(left)
        h_r = CR * g.base_film(right, lobe) + y * np.sin(right) - z * np.cos(right)
        inv_h = w / 6.0 * (1.0 / h_l + 4.0 / hc + 1.0 / h_r)   # Simpson over each cell
        tc = mu * omega * R ** 3 * params.L * float(np.sum(np.where(fixed, 0.0, inv_h)))
        # (R / 2) int h dp/dtheta dtheta over the film: h_f (p_next - p) per face, both halves
        jump = (p[nxt] - p) @ (2.0 * qw)
        tp = 0.5 * R * float(np.sum(np.where(film_face, hf * jump, 0.0)))
    tc -= cavitated_relief(params, y, z, omega, p_half, dx, cells, hf)
    q_side = side_flow(params, y, z, p_half, dx, grid)
    # --- inflow: circumferential face fluxes over the whole length (both halves)
    couette, pressure = face_fluxes(params, omega, hf, dp, dx)
    flux = couette - pressure
    q_in = 0.0
    if fixed.any():
        faces, sign = supply_edges(fixed)
        q_in = float(np.sum(np.maximum(flux[faces[sign > 0]], 0.0)) + np.sum(np.maximum(-flux[faces[sign < 0]], 0.0)))
    feeds = lobe_feed_faces(grid, hf) if grid is not None and grid.geometry.lobes > 1 and grid.geometry.preload > 0.0 else []
    for face in feeds:                                                  # each lobe's own feed line
        q_in += abs(float(flux[face]))
    if lands:
        # the groove is the lands' only supply: in a steady state it delivers what leaves by the ends (where the
        # film cavitates, Swift-Stieber's film reforms with oil that in the bearing comes from the groove through
        # the cavitated zone; where none cavitates, the flow across the groove's edges, ``groove_inflow``, is the
        # side flow to round-off: tests/test_circumferential_groove.py)
        q_in = q_side
    elif not (fixed.any() or feeds):
        k = int(np.argmax(hf))                                          # the thickest face
        t_max = math.atan2(y, -z) if (y or z) else float(right[k])      # (sin, -cos) along (y, z)
        # the two faces around the thickest line and the linear weight between them
        d = np.mod(t_max - right + math.pi, 2.0 * math.pi) - math.pi    # angle from each face
        a = int(np.argmin(np.where(d >= 0.0, d, np.inf)))               # the face just before it
        b = int(nxt[a])
        span = float(np.mod(right[b] - right[a], 2.0 * math.pi)) or 1.0
        s = float(d[a]) / span
        q_in = abs(float((1.0 - s) * flux[a] + s * flux[b]))
    return assemble_report(params, tc, tp, F, v, omega, q_in, q_side)


def shear_option(params: BearingParams):
    """The bearing's [oil] cavitated_shear: "full" (also without an [oil] table), "striated" or a fraction."""
    return "full" if params.oil is None else params.oil.cavitated_shear


def require_full_shear(params: BearingParams, what: str) -> None:
    """ValueError unless the cavitated film shears as a full film: ``what`` (a closed form from the force
    alone) does not know where the film cavitates."""
    if shear_option(params) != "full":
        raise ValueError(f"{what}: [oil] cavitated_shear = {params.oil.cavitated_shear!r} needs the film's pressure "
                         "field to tell the cavitated cells: the Reynolds internal computes it (or write 'full')")


def cavitated_relief(params: BearingParams, y: float, z: float, omega: float, p_half: np.ndarray, dx: float, cells,
                     hf: np.ndarray) -> float:
    """The Couette torque [N m] the cavitated cells do not exert when the film there is striated
    (``[oil] cavitated_shear``; 0 for "full"): mu omega R^3 sum (1 - f) width 2 dx / h over the cavitated
    nodes (p = 0, not prescribed), f the sheared fraction of the gap: the given number, or for "striated"
    h_r / h (capped at 1), h_r the film at the face where the node's run of cavitated cells begins along
    theta (where the film ruptured, or a supply edge): the striations carry on the Couette flow omega R h_r / 2
    of the film there (Dowson & Taylor 1979's film fraction in the Swift-Stieber rupture zone). A row
    cavitated all round keeps its full shear (no rupture to take h_r from)."""
    option = shear_option(params)
    if option == "full":
        return 0.0
    w, centre, fixed = cells[0], cells[1], cells[3]
    hc = params.CR * cells[7] + y * np.sin(centre) - z * np.cos(centre)
    cav = (p_half <= 0.0) & ~fixed[:, None]
    if option == "striated":
        frac = np.ones(p_half.shape)
        h_left = np.roll(hf, 1)  # the film at every cell's left face
        n = cav.shape[0]
        for j in range(cav.shape[1]):
            row = cav[:, j]
            if row.all() or not row.any():
                continue
            k0 = int(np.flatnonzero(~row)[0])  # start the walk at a cell that does not cavitate
            h_r = 0.0
            for s in range(1, n + 1):
                i = (k0 + s) % n
                if row[i]:
                    if not row[i - 1]:
                        h_r = h_left[i]
                    frac[i, j] = min(1.0, h_r / hc[i])
    else:
        frac = np.full(p_half.shape, float(option))
    lost = np.where(cav, 1.0 - frac, 0.0) @ np.full(p_half.shape[1], 2.0 * dx)
    return params.mu * omega * params.R ** 3 * float(np.sum(lost * w / hc))


def face_fluxes(params: BearingParams, omega: float, hf: np.ndarray, dp: np.ndarray, dx: float):
    """(Couette, pressure) parts [m^3/s] of the circumferential flux across every right face over the
    whole length, the flux their difference: omega R h L / 2 and h^3 / (12 mu R) int dp/dtheta dx
    (``dp`` (n_theta, m) across the faces of the half length, cells ``dx`` long)."""
    along = dp @ (2.0 * np.full(dp.shape[1], dx))
    return (omega * params.R * hf / 2.0) * film_length(params), hf ** 3 / (12.0 * params.mu * params.R) * along


def supply_edges(fixed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(faces, signs) of the supply edges of a bore's cells (``fixed``: prescribed pressure): the
    right faces between a prescribed cell and a film cell, in face order; sign +1 where the film is
    on the face's right (the flux enters it as it is), -1 on its left (it enters as -flux)."""
    nxt = np.roll(np.arange(fixed.shape[0]), -1)
    into_next, into_prev = fixed & ~fixed[nxt], ~fixed & fixed[nxt]
    faces = np.flatnonzero(into_next | into_prev)
    return faces, np.where(into_next[faces], 1.0, -1.0)


def lobe_feed_faces(grid, hf: np.ndarray) -> list[int]:
    """The faces where oil enters the lobes of a preloaded bore that no supply edge feeds, in face
    order: the lines of locally thickest film ``hf`` [m] (thicker than the next face, not thinner
    than the one before, film on both sides), where each lobe's own converging film starts, as the
    full bore's at its thickest line. A lobe whose film a groove or an arc edge feeds takes its oil
    there (``supply_edges``); a lobe the journal's eccentricity leaves without a thickest line of its
    own passes the oil on without one (the film converges on through it)."""
    g = grid.geometry
    fixed = grid.fixed.astype(bool)
    n = fixed.shape[0]
    nxt, prev = np.roll(np.arange(n), -1), np.roll(np.arange(n), 1)
    lobe = g.lobe_of(grid.centre)
    fed = np.zeros(g.lobes, dtype=bool)
    if fixed.any():
        faces, sign = supply_edges(fixed)
        fed[lobe[np.where(sign > 0, nxt[faces], faces)]] = True
    peak = ~fixed & ~fixed[nxt] & (hf > hf[nxt]) & (hf >= hf[prev]) & ~fed[lobe]
    return [int(i) for i in np.flatnonzero(peak)]


class FlowError(ValueError):
    """A film report whose flows are not a flow: NaN, infinite or negative (named, never printed)."""


def check_flows(q_in: float, q_side: float, where: str) -> None:
    """FlowError unless the inflow and the side flow [m^3/s] are finite and >= 0: a film that
    dissipates with such flows has no heat balance, and a printed NaN reads as a result."""
    for name, q in (("inflow", q_in), ("side flow", q_side)):
        if not (math.isfinite(q) and q >= 0.0):
            raise FlowError(f"{where}: the {name} is {q!r} m^3/s (a flow is finite and >= 0): the film's "
                            "pressure field or state is not physical here")


def edge_flows(params: BearingParams, y: float, z: float, p_half: np.ndarray, dx: float, grid) -> dict:
    """The parts of a grooved or partial-arc bore's flows that scale with the pressure field alone
    (``Reynolds.supply_flows`` calls it; the field as ``field_report`` takes it): ``side_flow`` [m^3/s]
    and, per supply edge (``supply_edges`` order), ``theta`` [rad], ``sign`` and ``pressure`` [m^3/s],
    the pressure part of the flux into the film there, so that the edge's inflow is
    max(sign omega R L h_e / 2 + pressure, 0), h_e = CR + y sin(theta) - z cos(theta)."""
    _p, hf, dp = _faces(params, y, z, p_half, _cells(p_half.shape[0], grid))
    _couette, pressure = face_fluxes(params, 0.0, hf, dp, dx)
    fixed = grid.fixed.astype(bool)
    faces, sign = supply_edges(fixed)
    return {"side_flow": side_flow(params, y, z, p_half, dx, grid), "theta": grid.right[faces], "sign": sign,
            "pressure": -sign * pressure[faces]}


def supply_functions(params: BearingParams, flows: dict, r: float) -> tuple[float, np.ndarray]:
    """(J_s, P_e per supply edge) of a grooved or partial-arc bore at a state of source r [1/s] from its
    ``edge_flows`` there (no supply pressure: the field scales with r): J_s = Q_s / (r Q0), P_e = -(the
    pressure part of edge e's flux into the film) / (r Q0), so that edge's flux is sign_e omega Q0 h_e /
    (2 CR) - r Q0 P_e (``grooved_report``; what the grooved map tabulates at r = 1)."""
    rq0 = r * flow_scale(params)
    return flows["side_flow"] / rq0, -np.asarray(flows["pressure"], float) / rq0


def film_couette_integral(geometry, eps: float, phi: float) -> float:
    """int dtheta / (1 + eps sin(theta - phi)) over the film of a bore without lobes (its segments
    without a prescribed pressure) in closed form: the Couette torque is mu omega R^3 L / CR times it.
    With u = theta - phi - pi/2, int_0^u dt / (1 + e cos t) = (u + 2 atan2((k - 1) sin u, (1 + k) +
    (1 - k) cos u)) / sqrt(1 - e^2), k = sqrt((1 - e) / (1 + e)), continuous in u (2 pi / sqrt(1 - e^2)
    over the full circle)."""
    root = math.sqrt(1.0 - eps * eps)
    k = math.sqrt((1.0 - eps) / (1.0 + eps))

    def prim(theta):
        u = theta - phi - 0.5 * math.pi
        return (u + 2.0 * math.atan2((k - 1.0) * math.sin(u), (1.0 + k) + (1.0 - k) * math.cos(u))) / root

    if geometry.is_full_bore:
        return 2.0 * math.pi / root
    segs, fixed, _supply = geometry.segments()
    return sum(prim(b) - prim(a) for (a, b), f in zip(segs, fixed) if not f)


def grooved_report(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float, F,
                   r: float, j_s: float, p_e, edges) -> FilmReport:
    """The film report of a grooved or partial-arc bore from the grooved map's force F and flow
    functions at the state's (eps, phi, beta): the Couette torque over the film in closed form
    (``film_couette_integral``), the pressure torque (y Fz - z Fy) / 2 (by parts: the grooves and the
    ambient hold p = 0 at the film's edges), the side flow r Q0 J_s, and the inflow the sum over the
    supply edges ``edges`` ((theta [rad], sign), ``Geometry.supply_edges``) of
    max(sign omega Q0 h_e / (2 CR) - r Q0 P_e, 0), h_e = CR + y sin(theta) - z cos(theta)
    (docs/forcemap.md, "Grooved bores: the flows")."""
    require_full_shear(params, "grooved_report")
    eps = float(np.hypot(y, z)) / params.CR  # libm's, as forcemap.reduced (the native C map's too)
    if not eps < 1.0:
        raise ValueError(f"grooved_report: eccentricity ratio {eps:.6g} >= 1 (the journal touches the bore)")
    phi = math.atan2(z, y)
    tc = params.mu * omega * params.R ** 3 * params.L / params.CR * film_couette_integral(params.geometry, eps, phi)
    tp = 0.5 * (y * float(F[1]) - z * float(F[0]))
    q0 = flow_scale(params)
    q_in = 0.0
    for (theta, sign), p in zip(edges, p_e):
        h = params.CR + y * math.sin(theta) - z * math.cos(theta)
        q_in += max(sign * omega * q0 * h / (2.0 * params.CR) - r * q0 * float(p), 0.0)
    return assemble_report(params, tc, tp, F, (vy, vz), omega, q_in, r * q0 * j_s)


# ------------------------------------------------------------------ the force map's reduction
# (docs/forcemap.md, "The flows"): with the pressure p = 6 mu r (R / CR)^2 Pi(psi, x; eps, beta) and
# h = CR (1 + eps cos psi), both flows are Q0 = R L CR times a function of the map's coordinates:
#     side flow  Q_s = r Q0 J_s(eps, beta)
#     inflow     Q   = | omega Q0 (1 + eps) / 2 - r Q0 J_i(eps, beta) |   (across the thickest line)

def flow_scale(params: BearingParams) -> float:
    """Q0 = R L CR [m^3]: the map's flow per unit omega or r [1/s]."""
    return params.R * params.L * params.CR


def reduced_flows(params: BearingParams, eps: float, r: float,
                  at_omega: dict[float, FilmReport]) -> tuple[float, float]:
    """(J_s, J_i) of a full-bore state from the Reynolds reports at two speeds ``at_omega`` {omega:
    report} with equal (eps, beta, r) (the same pressure field): the side flow gives J_s; the inflow
    is |omega Q0 (1 + eps) / 2 - r Q0 J_i|, whose sign each report loses, so J_i is the value both
    reports agree on: the pair of signs whose difference is the Couette part's. The solver's own
    Couette part (interpolated between two faces) is solved for with it, so J_i holds the pressure
    part alone and the map adds the exact Couette part."""
    q0 = flow_scale(params)
    (w1, rep1), (w2, rep2) = sorted(at_omega.items())
    couette = 0.5 * q0 * (1.0 + eps)  # per unit omega
    q1, q2 = rep1.inflow_m3_s, rep2.inflow_m3_s
    s1, s2 = min(((a * q1, b * q2) for a in (1.0, -1.0) for b in (1.0, -1.0)),
                 key=lambda p: abs((p[1] - p[0]) - (w2 - w1) * couette))
    c_solver = (s2 - s1) / (w2 - w1)
    j_i = (w1 * c_solver - s1) / (r * q0)
    return 0.5 * (rep1.side_flow_m3_s + rep2.side_flow_m3_s) / (r * q0), j_i


def reduced_report(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float, F,
                   eps: float, r: float, j_s: float, j_i: float) -> FilmReport:
    """The film report of the full bore from the map's force F and its flow functions (J_s, J_i) at
    (eps, beta): the friction in closed form (``full_bore_friction``), the flows by the reduction."""
    tc, tp, _power = full_bore_friction(params, y, z, vy, vz, omega, F)
    q0 = flow_scale(params)
    q_in = abs(omega * q0 * 0.5 * (1.0 + eps) - r * q0 * j_i)
    return assemble_report(params, tc, tp, F, (vy, vz), omega, q_in, r * q0 * j_s)


def _vertex(t0: float, t1: float, t2: float, p0: float, p1: float, p2: float) -> tuple[float, float]:
    """(t, p) of the parabola's vertex through three points (t1 the middle one, p1 >= p0, p2), or the
    middle point itself when the three are collinear."""
    a0, a2 = t0 - t1, t2 - t1
    den = a0 * a2 * (a0 - a2)
    c2 = ((p0 - p1) * a2 - (p2 - p1) * a0) / den  # p(t) = p1 + c1 (t - t1) + c2 (t - t1)^2
    if not c2 < 0.0:
        return t1, p1
    c1 = ((p2 - p1) * a0 * a0 - (p0 - p1) * a2 * a2) / den
    s = min(max(-c1 / (2.0 * c2), a0), a2)  # the vertex, kept between the neighbours
    return t1 + s, p1 + c1 * s + c2 * s * s


def peak_pressure(theta: np.ndarray, x: np.ndarray, p: np.ndarray) -> tuple[float, float]:
    """(p_peak [Pa], theta_peak [rad]) of a film's pressure field ``p`` (n_theta, n_x) at cell centres
    ``theta`` (periodic, ascending) and ``x`` (symmetric about the mid-plane x = 0).

    The largest cell value refined by the parabola through it and its two neighbours, around the
    circumference at its axial row, and along x by the even parabola p(x) = A - B x^2 through the two
    rows nearest the mid-plane (the aligned film's pressure is even in x and peaks at x = 0, between
    cell centres): the cell value alone lies O(dtheta^2 + dx^2) below the field's maximum. 0 at
    theta of the largest cell for a film without pressure."""
    n = len(theta)
    i, j = np.unravel_index(int(np.argmax(p)), p.shape)
    if not p[i, j] > 0.0:
        return 0.0, float(theta[i])
    m = p.shape[1] // 2
    rows = p[:, m] if p.shape[1] % 2 else None
    if rows is None and m >= 2:  # even n_x: no centre on the mid-plane; A from the two rows nearest it
        x1, x2 = abs(x[m]), abs(x[m + 1])
        rows = (p[:, m] * x2 * x2 - p[:, m + 1] * x1 * x1) / (x2 * x2 - x1 * x1)
        rows = np.where(rows >= p[:, m], rows, p[:, m])  # a profile that is not concave: the cell value
    elif rows is None:
        rows = p[:, j]
    i = int(np.argmax(rows))
    two_pi = 2.0 * math.pi
    t0, t2 = theta[i - 1] - (two_pi if i == 0 else 0.0), theta[(i + 1) % n] + (two_pi if i == n - 1 else 0.0)
    t, pk = _vertex(float(t0), float(theta[i]), float(t2), float(rows[i - 1]), float(rows[i]),
                    float(rows[(i + 1) % n]))
    return float(pk), float(t % two_pi)
