"""The Taylor-surrogate internal: the fitted polynomial of the film force (paper eq. 6),
evaluated by compiled kernels with its analytic Jacobian, and the fitted-domain guard.

``Taylor(surrogate)`` evaluates a :class:`bearing_fmu.surrogates.surrogate.Surrogate` (the model, its
wall factor and shape columns, its file: see there; the basis: :mod:`bearing_fmu.surrogates.basis`)
through the numba kernels of :mod:`bearing_fmu.surrogates.taylor_kernels`. A surrogate without shape
columns never compiles the short-bearing kernel. This module never imports the Reynolds
solver; fitting lives in :mod:`bearing_fmu.fitting`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...physics.solver.film import FilmReport, grooved_report, reduced_report
from ...physics.params import BearingParams
from ...physics.solver.shortbearing import short_bearing_constant
from ...surrogates.film import GROOVED
from ...surrogates.surrogate import NO_FLOWS_WHY, Surrogate, check_params, load_surrogate
from ...surrogates.taylor_kernels import (NOT_FINITE, WRONG_OMEGA, domain_distance_nb, force_jac_shape_si_nb,
                                         force_jac_si_nb, force_nb, force_shape_nb)
from ..base import BearingStateError, check_finite, overflow_error, wall_error
from .nearest import NearestTraining

OMEGA_RTOL = 1e-9  # the same tolerance the linear internal uses for "omega equals the fitted speed"


class Taylor:
    """The Taylor-surrogate internal: ``force`` and ``force_and_jacobian`` from a Surrogate.

    Evaluates everywhere inside the bearing (also outside the fitted domain, returning the
    polynomial value); ``in_domain`` / ``domain_distance`` tell the caller where the fit holds:
    inside its bounds (``bounds_distance``) and near its stored training states
    (``neighbours``); the guard (:mod:`bearing_fmu.internals.taylor.guard`) acts on them.
    Refuses, like Reynolds, with ``BearingStateError``: non-finite inputs (named), the journal
    at or beyond the wall (eccentricity ratio >= 1, where a polynomial's value is no film
    force), and ``omega`` other than the fitted speed (relative tolerance 1e-9).
    ``film_report`` from the file's film fit (format version 2); ``film_flow_why`` says why not
    ('' when it has one: registry.film_flow_of).
    """

    def __init__(self, surrogate: Surrogate, params: BearingParams | None = None, source: str = ""):
        if params is not None:
            check_params(surrogate, params)
        self.surrogate = surrogate
        self.params = surrogate.params
        self.film_flow_why = "" if surrogate.film is not None else NO_FLOWS_WHY.format(source=source or "(in memory)")
        s = surrogate
        self._meta = np.array([s.y0, s.z0, s.omega, s.pos_scale, s.vel_scale, s.force_scale, OMEGA_RTOL,
                               float(max(s.order, 1)), s.wall_power, short_bearing_constant(s.params),
                               float(s.shape_order or 0)])
        # evaluate only the terms kept by either component
        used = s.kept[0] | s.kept[1]
        used[0] = True
        self._exps = np.ascontiguousarray(s.exponents[used])
        self._coef = np.ascontiguousarray(s.coef[:, used])
        if s.shape_order is None:
            self._args = (self._meta, self._exps, self._coef)
            self._kforce, self._kjac = force_nb, force_jac_si_nb
        else:
            self._args = (self._meta, self._exps, self._coef, np.ascontiguousarray(s.shape_exponents),
                          np.ascontiguousarray(s.shape_coef))
            self._kforce, self._kjac = force_shape_nb, force_jac_shape_si_nb
        self._out = np.empty(10)
        self._cr2 = s.params.CR ** 2  # y^2 + z^2 >= CR^2: at or beyond the wall
        # the training states' KD-tree and radius (see ``neighbours``); r_lin evaluates this internal
        self._nearest = None
        if s.neighbours is not None:
            self._nearest = NearestTraining(s, self)
        # where r_lin carries the fit beyond its training states' spacing, the bounds, which only
        # enclose those states, widen by as much (guard.NearestTraining.widening; else unchanged)
        w = 0.0 if self._nearest is None else self._nearest.widening
        d = s.domain
        self._dom = np.array([s.y0, s.z0, s.pos_scale, s.vel_scale, d.ecc_max + w, d.pos_center[0], d.pos_center[1],
                              d.pos_radius + w, d.v_max + w, *(x - w for x in d.box_lo), *(x + w for x in d.box_hi)],
                             float)

    @classmethod
    def from_file(cls, path: str | Path, params: BearingParams | None = None) -> "Taylor":
        return cls(load_surrogate(path, params), source=str(path))

    @property
    def omega(self) -> float:
        return self.surrogate.omega

    def _raise(self, code, y, z, vy, vz, omega):
        """The BearingStateError for a refused call: a kernel's error ``code`` (NOT_FINITE: the
        polynomial overflowed at a huge finite velocity) or, with code 0, the journal at or beyond
        the wall (the plain polynomial's kernel does not check it)."""
        if code == WRONG_OMEGA:
            raise BearingStateError(f"Taylor surrogate was fitted at omega = {self.surrogate.omega:.6g} rad/s; "
                                    f"got omega = {omega:.6g} rad/s")
        check_finite(y, z, vy, vz, omega)  # a non-finite input named; else an overflow, or the journal at the wall
        if code == NOT_FINITE and y * y + z * z < self._cr2:
            raise overflow_error(self.params, y, z, vy, vz, omega, "force (Taylor surrogate)")
        s = self.surrogate
        what = " and ".join(([f"wall factor (1 - eps^2)^-{s.wall_power:g}"] if s.wall_power else [])
                            + (["short-bearing shape columns"] if s.shape_order is not None else []))
        raise wall_error(self.params, y, z, f"; the surrogate's {what} {'are' if s.shape_order is not None else 'is'} "
                                            "undefined there" if what else "")

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] at (y, z) [m], (vy, vz) [m/s], omega [rad/s]."""
        y, z = float(y), float(z)
        fy, fz, code = self._kforce(y, z, float(vy), float(vz), float(omega), *self._args)
        if code or not y * y + z * z < self._cr2:
            self._raise(code, y, z, vy, vz, omega)
        return fy, fz

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,) [N], dF/d(y, z) (2, 2) [N/m], dF/d(vy, vz) (2, 2) [N s/m]), analytic."""
        y, z = float(y), float(z)
        code, F, dF_dq, dF_dv = self._kjac(y, z, float(vy), float(vz), float(omega), *self._args)
        if code or not y * y + z * z < self._cr2:
            self._raise(code, y, z, vy, vz, omega)
        return F, dF_dq, dF_dv

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction and flows of the film (``Reynolds.film_report``'s quantities) as the force map has
        them (``film.reduced_report``): the friction in closed form from this surrogate's force, the
        flows from the file's flow functions J_s, J_i at the state's (eps, beta)
        (``surrogates.film``). A grooved or partial-arc bore's fit: the side flow and the supply edges'
        functions at (eps, phi, beta), assembled as the grooved map's (``film.grooved_report``).
        Refuses what ``force`` refuses; ValueError without a film fit. The fitted domain is the
        force's: the guard (``DomainGuard.film_report``) acts on it."""
        film = self.surrogate.film
        if film is None:
            raise ValueError(f"film_report: {self.film_flow_why}")
        F = self.force(y, z, vy, vz, omega)
        from ..map.forcemap import reduced

        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        eps, phi, a, c = reduced(y, z, vy, vz, omega, self.params.CR)
        if film.kind == GROOVED:
            f = film.values(eps, phi, math.atan2(c, a))[0]
            return grooved_report(self.params, y, z, vy, vz, omega, F, math.hypot(a, c), float(f[0]), f[1:],
                                  film.edges)
        j_s, j_i = film.values(eps, math.atan2(c, a))[0]
        return reduced_report(self.params, y, z, vy, vz, omega, F, eps, math.hypot(a, c), float(j_s), float(j_i))

    # ------------------------------------------------------------------ fitted domain
    def bounds_distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """How far the state lies outside the fitted domain's bounds: the largest relative
        excess (eccentricity / ecc_max - 1, distance to the position-disc centre / radius - 1,
        |v| / v_max - 1, and the bounding-box excess over the box half width), each bound
        widened by ``neighbours.widening`` (0 unless r_lin exceeds the training states' spacing).
        <= 0 inside; e.g. 0.1 means 10 % beyond the nearest violated bound. Compiled, ~0.3 us."""
        return float(domain_distance_nb(float(y), float(z), float(vy), float(vz), self._dom))

    @property
    def neighbours(self):
        """The nearest-neighbour measure of the stored training states and their radius
        (guard.NearestTraining, built with the internal: r_lin takes a few ms); None for a file
        without them (bounds only)."""
        return self._nearest

    def domain_distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """How far the state lies outside the fitted domain, one number: the larger of the
        excess over the bounds (``bounds_distance``) and, when the file stores training states,
        the excess of the distance to the nearest of them over their radius
        (``NearestTraining.distance``: (nn - radius) / the domain's size). <= 0 inside, > 0
        outside; NaN for a non-finite input. One KD-tree query (~10 us); the guard's own
        per-evaluation version skips it inside where it can (``DomainGuard.distance``)."""
        d = self.bounds_distance(y, z, vy, vz)
        near = self.neighbours
        if near is None or d != d:
            return d
        return max(d, near.distance(y, z, vy, vz))

    def in_domain(self, y: float, z: float, vy: float, vz: float) -> bool:
        """True when the state lies inside the fitted domain (see ``domain_distance``)."""
        return self.domain_distance(y, z, vy, vz) <= 1e-12


__all__ = ["Taylor", "OMEGA_RTOL"]
