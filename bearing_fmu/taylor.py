"""The Taylor-surrogate internal: the fitted polynomial of the film force (paper eq. 6),
evaluated by compiled kernels with its analytic Jacobian, and the fitted-domain guard.

``Taylor(surrogate)`` evaluates a :class:`bearing_fmu.surrogate.Surrogate` (the model, its
wall factor and shape columns, its file: see there; the basis: :mod:`bearing_fmu.basis`)
through the numba kernels of :mod:`bearing_fmu._taylor_kernels`. A surrogate without shape
columns never compiles the short-bearing kernel. This module never imports the Reynolds
solver; fitting lives in :mod:`bearing_fmu.fitting`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ._taylor_kernels import (
    _AT_WALL,
    _BAD_OMEGA,
    _BAD_VY,
    _BAD_VZ,
    _BAD_Y,
    _BAD_Z,
    _WRONG_OMEGA,
    _domain_distance_nb,
    _force_jac_shape_si_nb,
    _force_jac_si_nb,
    _force_nb,
    _force_shape_nb,
)
from .internals import BearingStateError
from .params import BearingParams
from .shortbearing import short_bearing_constant
from .surrogate import Surrogate, check_params, load_surrogate

OMEGA_RTOL = 1e-9  # the same tolerance the linear internal uses for "omega equals the fitted speed"

_VAR_OF_CODE = {_BAD_Y: "y", _BAD_Z: "z", _BAD_VY: "vy", _BAD_VZ: "vz", _BAD_OMEGA: "omega"}


class Taylor:
    """The Taylor-surrogate internal: ``force`` and ``force_and_jacobian`` from a Surrogate.

    Evaluates everywhere (also outside the fitted domain, returning the polynomial value);
    ``in_domain`` / ``domain_distance`` tell the caller where the fit holds. Inputs must be
    finite and ``omega`` must equal the fitted speed (relative tolerance 1e-9).
    """

    def __init__(self, surrogate: Surrogate, params: BearingParams | None = None):
        if params is not None:
            check_params(surrogate, params)
        self.surrogate = surrogate
        self.params = surrogate.params
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
            self._kforce, self._kjac = _force_nb, _force_jac_si_nb
        else:
            self._args = (self._meta, self._exps, self._coef, np.ascontiguousarray(s.shape_exponents),
                          np.ascontiguousarray(s.shape_coef))
            self._kforce, self._kjac = _force_shape_nb, _force_jac_shape_si_nb
        self._out = np.empty(10)
        d = s.domain
        self._dom = np.array([s.y0, s.z0, s.pos_scale, s.vel_scale, d.ecc_max, d.pos_center[0], d.pos_center[1],
                              d.pos_radius, d.v_max, *d.box_lo, *d.box_hi], float)

    @classmethod
    def from_file(cls, path: str | Path, params: BearingParams | None = None) -> "Taylor":
        return cls(load_surrogate(path, params))

    @property
    def omega(self) -> float:
        return self.surrogate.omega

    def _raise(self, code, y, z, vy, vz, omega):
        if code == _AT_WALL:
            ecc = math.hypot(y, z) / self.params.CR
            s = self.surrogate
            what = " and ".join(([f"wall factor (1 - eps^2)^-{s.wall_power:g}"] if s.wall_power else [])
                                + (["short-bearing shape columns"] if s.shape_order is not None else []))
            verb = "are" if s.shape_order is not None else "is"
            raise BearingStateError(
                f"eccentricity ratio {ecc:.4g} >= 1: the journal (y = {y:.4g} m, z = {z:.4g} m) is at or beyond "
                f"the bearing wall; the surrogate's {what} {verb} undefined there"
            )
        if code == _WRONG_OMEGA:
            raise BearingStateError(
                f"Taylor surrogate was fitted at omega = {self.surrogate.omega:.6g} rad/s; got omega = {omega:.6g} rad/s"
            )
        name = _VAR_OF_CODE[code]
        value = {"y": y, "z": z, "vy": vy, "vz": vz, "omega": omega}[name]
        raise BearingStateError(f"bearing input {name} = {value!r} is not finite")

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        fy, fz, code = self._kforce(float(y), float(z), float(vy), float(vz), float(omega), *self._args)
        if code:
            self._raise(code, y, z, vy, vz, omega)
        return fy, fz

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        code, F, dF_dq, dF_dv = self._kjac(float(y), float(z), float(vy), float(vz), float(omega), *self._args)
        if code:
            self._raise(code, y, z, vy, vz, omega)
        return F, dF_dq, dF_dv

    # ------------------------------------------------------------------ guard
    def domain_distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """How far the state lies outside the fitted domain: the largest relative excess over
        its bounds (eccentricity / ecc_max - 1, distance to the position-disc centre / radius
        - 1, |v| / v_max - 1, and the bounding-box excess over the box half width). <= 0
        inside; e.g. 0.1 means 10 % beyond the nearest violated bound."""
        return float(_domain_distance_nb(float(y), float(z), float(vy), float(vz), self._dom))

    def in_domain(self, y: float, z: float, vy: float, vz: float) -> bool:
        """True when the state lies inside the fitted domain (see ``domain_distance``)."""
        return self.domain_distance(y, z, vy, vz) <= 1e-12


__all__ = ["Taylor", "OMEGA_RTOL"]
