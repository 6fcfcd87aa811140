"""The force map of a lobed bore whose lobes are separated by ambient grooves: the sum over its lobes
of one partial-arc map, exact (docs/forcemap.md, "Lobed bores").

The lobes (``physics.bore.geometry``'s derivation)
---------------------------------------------
Lobe k of N spans 360/N deg from its leading edge theta_lead,k = lobe_angle + (k - 1/2) 360/N; its
film is h = C_pad - (e - O_k) . u(theta), u(theta) = (-sin theta, cos theta), the film of a
*circular* bore of clearance C_pad = CR / (1 - m) whose centre O_k = -d u(theta_p,k) lies d = C_pad
- CR = m C_pad from the bearing's centre, against the lobe's preload point theta_p,k =
theta_lead,k + lobe_offset 360/N. Lobe k is lobe 0 turned by alpha_k = k 360/N: theta_p,k =
theta_p,0 + alpha_k, O_k = Rot(alpha_k) O_0, and u(theta + alpha) = Rot(alpha) u(theta) for the
rotation Rot of the (y, z) plane. So at theta = theta' + alpha_k the film of lobe k with the journal
at e is the film of lobe 0 at theta' with the journal at Rot(-alpha_k) e:

    h_k(theta; e) = C_pad - (Rot(-alpha_k) e - O_0) . u(theta') = h_0(theta'; Rot(-alpha_k) e).

Why the sum is exact
--------------------
With one ambient groove (supply pressure 0) over every lobe boundary, each lobe's film is one
stretch of one lobe's circle, [a, b] = [theta_lead,0 + delta + w/2, theta_lead,0 + 360/N + delta -
w/2] for lobe 0 (w the groove width, delta the groove centres' offset from the boundaries, the same
for every groove), bounded by p = 0 on both sides: a groove's cells are Dirichlet cells of the
Reynolds solver, so the lobes' complementarity problems share no unknown and decouple exactly. Each
is the problem of the partial arc [a, b] of clearance C_pad with the journal at e' = Rot(-alpha_k) e
- O_0 from the arc's centre, its velocity turned the same way: the grooved bores' 3-D map F = S r
G(eps, phi, beta) (``groovemap``, exact for a circular film with ambient edges), built once with CR
= C_pad, gives every lobe's force, turned back by Rot(alpha_k):

    F(e, v) = sum_k Rot(alpha_k) F_arc(Rot(-alpha_k) e - O_0, Rot(-alpha_k) v),
    dF/dq   = sum_k Rot(alpha_k) dF_arc/dq' Rot(-alpha_k)   (and dF/dv alike: the shift is a constant).

The friction torques, the side flows and the inflows of the lobes add (the lemon's inflow is the oil
entering its film at the grooves' edges, each lobe's own pair). The Reynolds solver of the lobed bore
puts a face on every groove edge and lobe boundary and spreads its film cells evenly over the N equal
film stretches; the map's truth is the arc solver with as many film cells on [a, b]
(``map_params``), so the two solve the same discrete problem (to round-off,
tests/test_lobemap.py) and the map reproduces the lobed Reynolds internal to its interpolation
error. Not covered: lobes without a groove over every boundary (the lobes' films then connect: no
exact reduction, and the 4-D table of docs/forcemap.md stays a design), a supply pressure in the
grooves (not superposable under cavitation: issue 35 item 3), grooves that are not the same for every
lobe, and journal positions beyond eps_max of C_pad from any lobe's centre (for the lemon with m =
0.5: |e| up to CR vertically and 1.7 CR sideways).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...physics.solver.film import FilmReport, assemble_report
from ...physics.bore.geometry import Geometry
from ...physics.params import BearingParams
from ..base import BearingStateError, check_finite

TWO_PI = 2.0 * math.pi
_TOL = 1e-9  # [rad] groove offsets equal to this

NOT_EXACT_WHY = ("the lobe reduction (the sum of one partial-arc map per lobe, docs/forcemap.md) is exact only "
                 "when an ambient groove lies over every lobe boundary, the same for every lobe; without them the "
                 "lobes' films connect and the map would be a 4-D table (not built); use the Reynolds or Taylor "
                 "internal")


def lobed_problem(geometry: Geometry) -> str | None:
    """Why no lobe map serves this lobed bore (a phrase naming the keys), or None (also None for a bore
    without lobes: the other maps' checks apply)."""
    if geometry.lobes < 2:
        return None
    n = geometry.lobes
    if geometry.supply_pressure > 0.0:
        return (f"supply_pressure_kPa = {geometry.supply_pressure / 1e3:g}: a supply pressure adds a film source "
                "independent of the journal's motion and, with cavitation, the force is not the sum of the two "
                "parts (docs/forcemap.md); use the Reynolds or Taylor internal")
    if geometry.arc is not None:
        return f"lobes = {n} with arc_deg: {NOT_EXACT_WHY}"
    if len(geometry.grooves) != n:
        return f"lobes = {n} with {len(geometry.grooves)} groove(s) in grooves_deg (one per lobe boundary needed): " \
               f"{NOT_EXACT_WHY}"
    w = geometry.groove_width
    offsets = []
    for b in geometry.lobe_boundaries():
        d = [math.remainder(g - b, TWO_PI) for g in geometry.grooves]
        k = int(np.argmin(np.abs(d)))
        if not abs(d[k]) < 0.5 * w - _TOL:
            return (f"lobes = {n}: the lobe boundary at {math.degrees(b) % 360:.6g} deg lies in no groove of "
                    f"grooves_deg: {NOT_EXACT_WHY}")
        offsets.append(d[k])
    if max(offsets) - min(offsets) > _TOL:
        return (f"lobes = {n}: the grooves sit at different offsets from their lobe boundaries "
                f"({', '.join(f'{math.degrees(o):.4g}' for o in offsets)} deg), so the lobes are not one arc "
                f"turned: {NOT_EXACT_WHY}")
    return None


def map_problem(geometry: Geometry) -> str | None:
    """Why no force map serves this bore (a phrase), or None: a lobed bore's ``lobed_problem``, fed
    grooves' ``supplymap.supply_problem`` (their 4-D map), any other bore's
    ``groovemap.map_geometry_problem``."""
    from .groovemap import map_geometry_problem
    from .supplymap import supply_problem

    if geometry.lobes > 1:
        return lobed_problem(geometry)
    return supply_problem(geometry) if geometry.supply_pressure > 0.0 else map_geometry_problem(geometry)


def lobe_arc(params: BearingParams) -> BearingParams:
    """The circular partial arc lobe 0 of ``params``' lobed bore is: clearance C_pad [m], arc [a, b]
    (module docstring), in the bearing's own frame."""
    g = params.geometry
    why = lobed_problem(g) if g.lobes > 1 else f"lobes = {g.lobes}: not a lobed bore"
    if why:
        raise ValueError(f"no lobe map for this bore ({g.describe()}): {why}")
    step = TWO_PI / g.lobes
    lead = g.lobe_angle - 0.5 * step
    delta = math.remainder(g.grooves[int(np.argmin([abs(math.remainder(x - lead, TWO_PI)) for x in g.grooves]))]
                           - lead, TWO_PI)
    a = lead + delta + 0.5 * g.groove_width
    return replace(params, CR=g.pad_clearance(params.CR), geometry=Geometry(arc=(a, a + step - g.groove_width)))


def lobe_cells(params: BearingParams, n_theta: int) -> int:
    """Film cells on each lobe of the lobed bore's Reynolds grid of ``n_theta`` cells; ValueError when the
    lobes get unequal counts (then no one arc grid matches every lobe's cells)."""
    grid = params.geometry.theta_grid(n_theta)
    counts = np.bincount(params.geometry.lobe_of(grid.centre[~grid.fixed]), minlength=params.geometry.lobes)
    if np.any(counts != counts[0]):
        n_fixed = int(grid.fixed.sum())
        raise ValueError(f"n_theta = {n_theta}: the Reynolds grid of this lobed bore gives its lobes "
                         f"{', '.join(map(str, counts))} film cells; its lobe map needs them equal (n_theta - "
                         f"{n_fixed} divisible by {params.geometry.lobes})")
    return int(counts[0])


def map_params(params: BearingParams, grid=None) -> tuple[BearingParams, tuple]:
    """(the bearing whose map is built, its Reynolds grid (n_theta, n_x)) for ``params`` and the Reynolds
    grid asked for (None: the solver's defaults): a lobed bore's lobe arc (``lobe_arc``) with as many
    cells on the arc as the lobed grid has on each lobe, plus the arc's one ambient cell; any other
    bearing as given."""
    if params.geometry.lobes < 2:
        return params, grid
    from ...physics.solver.reynolds import DEFAULT_N_THETA, DEFAULT_N_X

    n_theta, n_x = grid or (None, None)
    arc = lobe_arc(params)
    cells = lobe_cells(params, n_theta or DEFAULT_N_THETA)
    return arc, (cells + len(arc.geometry.segments()[0]) - 1, n_x or DEFAULT_N_X)


class LobedForceMap:
    """The map internal for a lobed bore with ambient grooves over its lobe boundaries: the force, its
    analytic Jacobian and the film report, summed over the lobes from one partial-arc map ``table``
    (a ``GroovedMapTable`` of ``lobe_arc(params)``; module docstring). A state farther than the table's
    eps_max of C_pad from any lobe's centre is refused."""

    def __init__(self, params: BearingParams, table, source: str = ""):
        from .groovemap import GroovedForceMap
        from .kernels import lobes_force
        from .tables import EPS_MIN, scale

        g = params.geometry
        why = lobed_problem(g) if g.lobes > 1 else f"lobes = {g.lobes}: not a lobed bore"
        if why:
            raise ValueError(f"force map{' ' + source if source else ''}: no lobe map serves this bore "
                             f"({g.describe()}): {why}")
        self.params, self.source, self.table = params, source, table
        self.arc = lobe_arc(params)
        try:
            self.map = GroovedForceMap(self.arc, table, source)
        except ValueError as exc:
            raise ValueError(f"{exc} (the lobed bearing's lobe is the partial arc "
                             f"'{self.arc.geometry.describe()}', C_pad = {self.arc.CR:g} m)") from None
        tp0 = float(g.preload_points()[0])
        d = self.arc.CR - params.CR  # [m] from the bearing's centre to lobe 0's, against its preload point
        self._centre0 = np.ascontiguousarray(-d * np.array([-math.sin(tp0), math.cos(tp0)]))  # O_0 [m]
        # (cos, sin) alpha_k per lobe: Rot(alpha_k) turns lobe 0 onto lobe k (the native map reads them as they are)
        self.turns = np.array([[math.cos(a), math.sin(a)] for a in TWO_PI * np.arange(g.lobes) / g.lobes])
        self._eps_max = float(table.eps_max)
        self.film_flow_why = self.map.film_flow_why
        ts, tp, tb, C = table.spline()
        self._kernel = lobes_force
        self._args = (ts, tp, tb, C, EPS_MIN, scale(self.arc), float(self.arc.CR), self._eps_max, self._centre0,
                      self.turns)
        self._F, self._J = np.zeros(2), np.zeros((2, 4))

    def compiled_force(self):
        """Its force and Jacobian as a compiled kernel (``internals.compiled``): ``kernels.lobes_force``,
        the same function ``force_and_jacobian`` calls, so the same numbers."""
        from ..compiled import CompiledForce
        from .kernels import lobes_kernel, pack_lobes

        return CompiledForce(lobes_kernel(), pack_lobes(*self._args))

    def lobe_states(self, y, z, vy, vz):
        """Per lobe k: (y', z', vy', vz') [m, m/s] of the journal in the arc map's frame, Rot(-alpha_k) e - O_0
        and Rot(-alpha_k) v (in ``kernels.lobes_force``'s operations); refused (``BearingStateError``) beyond
        eps_max of C_pad from a lobe's centre."""
        o0, o1 = self._centre0
        out = []
        for k, (c, s) in enumerate(self.turns):
            yk, zk = c * y + s * z - o0, -s * y + c * z - o1
            eps = math.hypot(yk, zk) / self.arc.CR
            if not eps < self._eps_max:
                why = "at or beyond the lobe's circle" if eps >= 1.0 else "beyond the force map's last point"
                raise BearingStateError(
                    f"the journal (y = {y:.4g} m, z = {z:.4g} m) is {eps:.4g} C_pad from the centre of lobe {k} "
                    f"({why}; C_pad = {self.arc.CR:.4g} m; the lobe map covers < {self._eps_max:g} C_pad from "
                    "every lobe's centre)")
            out.append((float(yk), float(zk), float(c * vy + s * vz), float(-s * vy + c * vz)))
        return out

    def _states(self, y, z, vy, vz, omega):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        check_finite(y, z, vy, vz, omega)
        return self.lobe_states(y, z, vy, vz), omega

    def _run(self, y, z, vy, vz, omega, want_jac):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        eps = self._kernel(*self._args, y, z, vy, vz, omega, want_jac, self._F, self._J)
        if not eps < self._eps_max or not math.isfinite(y + z + vy + vz + omega):
            self._states(y, z, vy, vz, omega)  # names a non-finite input or the lobe beyond the map
            for (yk, zk, vyk, vzk) in self.lobe_states(y, z, vy, vz):  # else the arc map's own refusal (overflow)
                self.map.force(yk, zk, vyk, vzk, omega)
            raise BearingStateError(f"lobe map: no finite force at y = {y!r}, z = {z!r}, vy = {vy!r}, vz = {vz!r}, "
                                    f"omega = {omega!r}")

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N]: the lobes' forces turned back and summed (``kernels.lobes_force``)."""
        self._run(y, z, vy, vz, omega, False)
        return float(self._F[0]), float(self._F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF/dq (2, 2), dF/dv (2, 2)) [N, N/m, N s/m], each lobe's map Jacobian turned back."""
        self._run(y, z, vy, vz, omega, True)
        return self._F.copy(), self._J[:, :2].copy(), self._J[:, 2:].copy()

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction and flows of the film: each lobe's report from the arc map (``GroovedForceMap.
        film_report``: Couette torque in closed form, pressure torque from the lobe's force about its
        own offset journal, inflow over its two groove edges, side flow), torques and flows summed;
        ValueError without the flow tables."""
        states, omega = self._states(y, z, vy, vz, omega)
        tc = tp = q_in = q_s = 0.0
        for s in states:
            rep = self.map.film_report(*s, omega)
            tc += rep.couette_torque_Nm
            tp += rep.pressure_torque_Nm
            q_in += rep.inflow_m3_s
            q_s += rep.side_flow_m3_s
        F = self.force(y, z, vy, vz, omega)
        return assemble_report(self.params, tc, tp, F, (float(vy), float(vz)), omega, q_in, q_s)

    def __repr__(self) -> str:
        return f"LobedForceMap({self.params.geometry.lobes} lobes, each {self.map!r}, C_pad {self.arc.CR:g} m)"


__all__ = ["LobedForceMap", "lobed_problem", "map_problem", "lobe_arc", "lobe_cells", "map_params", "NOT_EXACT_WHY"]
