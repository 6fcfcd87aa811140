"""Any internal at another viscosity: its force times mu_eff / mu (docs/thermal.md).

At a fixed state the film force of the Reynolds equation is proportional to the viscosity (the
source 6 mu omega dh/dtheta + 12 mu dh/dt and the pressure both scale with mu), so every internal
that models that film (Reynolds, linear, the force map, the Taylor surrogate) gives the force at
the effective viscosity exactly when its force and Jacobian are multiplied by mu_eff / mu. The
factor can change between calls (a stability sweep sets it per speed); nothing else changes, so a
surrogate's domain and a map's table stay valid.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ViscosityScaled"]


class ViscosityScaled:
    """``inner`` (an internal) with its force scaled to viscosity ``mu_eff`` [Pa s]; ``params`` is
    the inner bearing at mu_eff (``BearingParams.with_viscosity``). ``force_and_jacobian`` exists
    when the inner internal has it; ``domain_distance`` and other attributes are the inner's."""

    def __init__(self, inner, mu_eff: float | None = None):
        self.inner = inner
        self.mu_ref = float(inner.params.mu)
        self.set_viscosity(self.mu_ref if mu_eff is None else mu_eff)
        if getattr(inner, "force_and_jacobian", None) is not None:
            self.force_and_jacobian = self._force_and_jacobian

    def set_viscosity(self, mu_eff: float) -> None:
        """Use viscosity mu_eff [Pa s] from the next call on."""
        mu_eff = float(mu_eff)
        if not (math.isfinite(mu_eff) and mu_eff > 0.0):
            raise ValueError(f"ViscosityScaled: mu_eff = {mu_eff!r} Pa s must be finite and > 0")
        self.mu_eff = mu_eff
        self.factor = mu_eff / self.mu_ref
        self.params = self.inner.params.with_viscosity(mu_eff)

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        fy, fz = self.inner.force(y, z, vy, vz, omega)
        return self.factor * fy, self.factor * fz

    def _force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        F, dq, dv = self.inner.force_and_jacobian(y, z, vy, vz, omega)
        f = self.factor
        return f * np.asarray(F, float), f * np.asarray(dq, float), f * np.asarray(dv, float)

    def __getattr__(self, name):  # domain_distance, counts, ... of the inner internal
        if name in ("inner", "force_and_jacobian"):
            raise AttributeError(name)
        return getattr(self.inner, name)

    def __repr__(self) -> str:
        return f"ViscosityScaled({self.inner!r}, mu_eff={self.mu_eff!r})"
