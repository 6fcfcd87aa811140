"""The map internal of the full bore: ``ForceMap`` evaluates a ``MapTable`` (``tables``) with
the compiled spline kernels (``kernels``): the force, its analytic Jacobian and the film's flows,
for a bearing whose L/D equals the table's. The reduction behind it: ``tables``' docstring and
docs/forcemap.md.
"""

from __future__ import annotations

import math

import numpy as np

from ...physics.solver.film import FilmReport, reduced_report
from ...physics.params import BearingParams
from ..base import BearingStateError, check_finite, overflow_error
from .tablefile import load_map
from .tables import EPS_MIN, LD_RTOL, NO_FLOWS_WHY, REDUCTION_WHY, MapTable, reduced, scale

class ForceMap:
    """The map internal: ``force`` and ``force_and_jacobian`` (analytic, from the spline's
    derivatives) for a bearing whose L/D equals the table's. States at or beyond the table's
    last eccentricity (eps_max) are refused like Reynolds refuses the wall."""

    # no flow tables unless __init__ finds them (the grooved map, a subclass, sets its own)
    film_flow_why, _flow = "the map has no flow tables (docs/forcemap.md)", None

    def __init__(self, params: BearingParams, table: MapTable, source: str = ""):
        params.require_full_bore(f"the force map{' ' + source if source else ''}", REDUCTION_WHY)
        ld = params.L / params.D
        if not abs(ld - table.L_over_D) <= LD_RTOL * table.L_over_D:  # NaN is refused, not let through
            raise ValueError(f"force map{' ' + source if source else ''} is for L/D = {table.L_over_D:.6g}, the "
                             f"bearing has L/D = {ld:.6g} (L = {params.L:g} m, D = {params.D:g} m): build a map for "
                             "it with `bearing-fmu map --bearing FILE -o MAP`")
        self.params, self.table, self.source = params, table, source
        self._ts, self._tb, self._C = table.spline()
        self._ns, self._nb = self._C.shape[0], self._C.shape[1]
        self._scale = scale(params)
        self._F = np.zeros(2)
        self._J = np.zeros((2, 4))
        from .kernels import map_force  # numba, compiled (or loaded from its cache) here

        self._kernel = map_force
        self._args = (self._ts, self._tb, self._C, self._ns, self._nb, float(table.wall_exponent), EPS_MIN,
                      self._scale, float(params.CR))
        self._eps_max = float(table.eps_max)
        # the film's flows (registry capability film_flow, per file): '' when the file has them
        self.film_flow_why = "" if table.Q is not None else NO_FLOWS_WHY.format(source=source or "(in memory)")
        self._flow, self._Jq = table.flow_spline(), np.zeros((2, 3))

    @classmethod
    def from_file(cls, path, params: BearingParams) -> "ForceMap":
        return cls(params, load_map(path), source=str(path))

    @classmethod
    def from_options(cls, params: BearingParams, options, context) -> "ForceMap":
        """From the registry's checked options (``internals.REGISTRY["map"]``)."""
        if not options["map"]:
            raise ValueError("internal 'map' needs the option map (a force map JSON file)")
        return cls.from_file(context.path(options["map"]), params)

    def __repr__(self) -> str:
        t = self.table
        return (f"ForceMap(L/D {t.L_over_D:.4g}, {t.n_eps} x {t.n_beta}, eps <= {t.eps_max:g}, Reynolds "
                f"{t.n_theta} x {t.n_x} {t.cavitation})")

    def _run(self, y, z, vy, vz, omega, want_jac):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        # the kernel returns eps (NaN when its result is not finite); a non-finite input, a state
        # beyond the table or an overflow is checked after it (one call on the good path) and
        # refused before anything is used
        eps = self._kernel(*self._args, y, z, vy, vz, omega, want_jac, self._F, self._J)
        if not eps < self._eps_max or not math.isfinite(vy + vz + omega):
            self._refuse(y, z, vy, vz, omega, want_jac)

    def _refuse(self, y, z, vy, vz, omega, want_jac):
        refuse_state(self.params, self._eps_max, y, z, vy, vz, omega, want_jac)

    def compiled_force(self):
        """Its force and Jacobian as a compiled kernel (``internals.compiled``)."""
        from ..compiled import CompiledForce
        from .kernels import map_kernel, pack

        return CompiledForce(map_kernel(), pack(*self._args[:3], *self._args[5:], self._eps_max))

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N]."""
        self._run(y, z, vy, vz, omega, False)
        return float(self._F[0]), float(self._F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF/dq (2, 2), dF/dv (2, 2)) [N, N/m, N s/m]."""
        self._run(y, z, vy, vz, omega, True)
        return self._F.copy(), self._J[:, :2].copy(), self._J[:, 2:].copy()

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction (closed form, from the force) and flows (the file's flow table) of the film, as
        ``Reynolds.film_report`` (docs/forcemap.md, "The flows"); ValueError without the table."""
        if self._flow is None:
            raise ValueError(f"film_report: {self.film_flow_why}")
        from .kernels import spline2

        F = self.force(y, z, vy, vz, omega)
        eps, _phi, a, c = reduced(float(y), float(z), float(vy), float(vz), float(omega), self.params.CR)
        e = max(eps, EPS_MIN)  # as the table's centre row (and the force) have it
        spline2(*self._flow, self._ns, self._nb, -math.log1p(-e), math.atan2(c, a), self._Jq)
        return reduced_report(self.params, float(y), float(z), float(vy), float(vz), float(omega), F, eps,
                              math.hypot(a, c), float(self._Jq[0, 0]), float(self._Jq[1, 0]))


def refuse_state(params: BearingParams, eps_max: float, y, z, vy, vz, omega, want_jac) -> None:
    """Raise the error of a state a map cannot answer (the map kernels returned eps >= eps_max,
    NaN, or took a non-finite velocity): a non-finite input, the wall, beyond the table, or a
    force that overflows, each by name."""
    check_finite(y, z, vy, vz, omega)
    eps = math.hypot(y, z) / params.CR  # as the kernel has it (which returns NaN on overflow)
    if eps < eps_max:  # finite inputs inside the table: the force overflowed
        # F = S r G is linear in r ~ |v| / CR: beyond the float range no finite value is the
        # model's answer, so the state is refused by name rather than returned as inf or NaN
        raise overflow_error(params, y, z, vy, vz, omega, "force and its Jacobian" if want_jac else "force")
    CR = params.CR
    why = "at or beyond the bearing wall" if eps >= 1.0 else "beyond the force map's last point"
    raise BearingStateError(
        f"eccentricity ratio {eps:.4g} >= {1.0 if eps >= 1.0 else eps_max:g}: the journal "
        f"(y = {y:.4g} m, z = {z:.4g} m) is {why} (CR = {CR:.4g} m; the map covers eps < {eps_max:g})")
