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

__all__ = ["ViscosityScaled", "LaggedThermal"]


class ViscosityScaled:
    """``inner`` (an internal) with its force scaled to viscosity ``mu_eff`` [Pa s]; ``params`` is
    the inner bearing at mu_eff (``BearingParams.with_viscosity``). ``force_and_jacobian`` exists
    when the inner internal has it; ``domain_distance`` and other attributes are the inner's."""

    def __init__(self, inner, mu_eff: float | None = None):
        why = getattr(inner, "viscosity_scaling_why", "")  # an internal whose force is not mu times one function
        if why:
            raise ValueError(why)
        self.inner = inner
        self.mu_ref = float(inner.params.mu)
        self.set_viscosity(self.mu_ref if mu_eff is None else mu_eff)
        if getattr(inner, "force_and_jacobian", None) is not None:
            self.force_and_jacobian = self._force_and_jacobian
        # what answers in N (or N/m, N s/m) at the inner's viscosity is scaled too, never handed on raw
        for name in ("journal_equilibrium", "reduced_coefficients", "full_coefficients"):
            if getattr(inner, name, None) is not None:
                setattr(self, name, getattr(self, "_" + name))

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

    def _journal_equilibrium(self, load, omega: float, **kw) -> tuple[float, float]:
        # the force is factor times the inner's: the inner's equilibrium under the load / factor
        return self.inner.journal_equilibrium((load[0] / self.factor, load[1] / self.factor), omega, **kw)

    def _reduced_coefficients(self, y: float, z: float, omega: float, whirl: float) -> tuple:
        if getattr(self.inner, "reduce", None) is not None:  # pads with inertia: -whirl^2 I does not scale
            K, C, _ = self._full_coefficients(y, z, omega)
            return self.inner.reduce(K, C, whirl)
        K, C = self.inner.reduced_coefficients(y, z, omega, whirl)
        return self.factor * np.asarray(K), self.factor * np.asarray(C)

    def _full_coefficients(self, y: float, z: float, omega: float) -> tuple:
        K, C, inertia = self.inner.full_coefficients(y, z, omega)  # the pads' inertia does not scale
        return self.factor * np.asarray(K), self.factor * np.asarray(C), inertia

    def __getattr__(self, name):  # domain_distance, counts, ... of the inner internal
        # not the inner's compiled force, coefficients or equilibrium: at the inner's viscosity, unscaled
        if name in ("inner", "force_and_jacobian", "compiled_force", "journal_equilibrium", "reduced_coefficients",
                    "full_coefficients"):
            raise AttributeError(name)
        return getattr(self.inner, name)

    def __repr__(self) -> str:
        return f"ViscosityScaled({self.inner!r}, mu_eff={self.mu_eff!r})"


class LaggedThermal(ViscosityScaled):
    """``inner`` (an internal with ``film_report``: ``Capabilities.film_flow``) at the viscosity of its
    film's temperature, which lags the film's heat balance by the residence time
    (``physics.thermal.film_temperature``): the bearing FMU's thermal model (``fmu/ports.py``)
    in-process, for runs whose speed or load changes (docs/thermal.md).

    oil, T_supply_K : the oil law and its supply temperature [K]
    ``start(y, z, vy, vz, omega)`` sets the temperature quasi-statically at a state (the FMU's
    Initialization Mode); ``begin_step(dt)`` [s] then makes every evaluation lag from the committed
    temperature over dt (0: held, the static evaluations), ``accept_step`` commits the last one.
    ``thermal_record()``: what the last evaluation had, as the FMU's thermal outputs have it (a
    run records it at its recorded times)."""

    def __init__(self, inner, oil, T_supply_K: float):
        if getattr(inner, "film_report", None) is None:
            raise ValueError(f"LaggedThermal: {type(inner).__name__} has no film_report (the film's flows)")
        super().__init__(inner)
        self.oil, self.T_supply = oil, float(T_supply_K)
        self.T = self.T_trial = oil.check_temperature(T_supply_K, "T_supply")
        self.dt = 0.0
        self.report = None  # the film report of the last evaluation, at the inner's viscosity

    def _at(self, state, lagged: bool = True) -> None:
        from ..physics.thermal import film_temperature
        from .registry import BearingStateError

        self.report = report = self.inner.film_report(*state)
        try:
            self.T_trial, mu, _ = film_temperature(self.inner.params, report, self.oil, self.T_supply,
                                                   self.T if lagged else None, self.dt)
        except ValueError as exc:  # the oil's range left: a state this film cannot take
            raise BearingStateError(f"thermal model: {exc}") from None
        self.set_viscosity(mu)

    def start(self, y: float, z: float, vy: float, vz: float, omega: float) -> float:
        """The quasi-static temperature [K] at this state, committed."""
        self._at((y, z, vy, vz, omega), lagged=False)
        self.T = self.T_trial
        return self.T

    def begin_step(self, dt: float) -> None:
        self.dt = float(dt)
        if getattr(self.inner, "begin_step", None) is not None:  # an internal with states of its own (pads)
            self.inner.begin_step(dt)

    def thermal_record(self) -> tuple[float, float, float, float, float]:
        """(T_eff [K], mu_eff [Pa s], friction power P_loss [W], side flow Q_side [m^3/s], inflow Q_in
        [m^3/s]) of the last evaluation (the FMU's P_loss: the report's power times mu_eff / mu)."""
        r = self.report
        return self.T_trial, self.mu_eff, r.friction_power_W * self.factor, r.side_flow_m3_s, r.inflow_m3_s

    def accept_step(self) -> None:
        self.T = self.T_trial
        if getattr(self.inner, "accept_step", None) is not None:
            self.inner.accept_step()

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        f = self.inner.force(y, z, vy, vz, omega)  # refuses the wall before the film report is made
        self._at((y, z, vy, vz, omega))
        return self.factor * f[0], self.factor * f[1]

    def _force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        F, dq, dv = self.inner.force_and_jacobian(y, z, vy, vz, omega)
        self._at((y, z, vy, vz, omega))
        f = self.factor
        return f * np.asarray(F, float), f * np.asarray(dq, float), f * np.asarray(dv, float)
