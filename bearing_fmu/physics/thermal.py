"""The film's effective temperature and viscosity (docs/thermal.md).

Heat balance (Raimondi & Boyd 1958, part III; Shigley's Mechanical Engineering Design, ch. 12,
"temperature rise"): the oil enters the film at T_supply with the inflow Q; the side flow Qs leaves
along the way at, on average, half the rise, the rest (Q - Qs) at the full rise dT; the friction
power P goes into the oil (adiabatic: none conducted into journal or bush):

    P = rho c_p [Qs dT / 2 + (Q - Qs) dT] = rho c_p (Q - Qs / 2) dT
    T_eff = T_supply + k dT,   k = 1/2 (the mean of inlet and outlet: Shigley's T_av = T_1 + dT / 2)
    mu_eff = mu(T_eff)

With P and Q from the film at its static equilibrium under the load (``physics.solver.film``), at the
viscosity mu_eff itself: T = T_supply + k dT(mu(T)) is solved for T by bracketing (Brent). The
residual r(T) = T_supply + k dT(mu(T)) - T is >= 0 at T_supply (dT >= 0); a hotter, thinner oil
dissipates less, so r(T_supply + k dT(T_supply)) <= 0 and that brackets the root (else the bracket
grows up to the oil's range, and no root there is an error naming it).

Quasi-static, not a state of the time integration: the oil in the film is renewed every
t_res = V / Q (film volume over inflow; ``residence_time_s``), about 1-2 revolutions (the paper
bearing at 50 Hz: 0.03 s), so the adiabatic film temperature settles within a few revolutions of
a change of speed or load (a run-up takes seconds), while over one whirl or unbalance cycle (one to
two revolutions) it cannot follow the orbit and sees its mean: the static equilibrium. The bush and
journal, whose heat capacity this model leaves out, are slower still (minutes), which only smooths
more. So T_eff is computed at the static equilibrium of each speed and load, not per time step.

The film force is proportional to mu at a fixed state, so every internal (Reynolds, linear, the
force map, the Taylor surrogate) is exact under mu_eff: its force scaled by mu_eff / mu.

At a fixed journal state (an FMU, which does not know the static load: ``film_temperature``)
-----------------------------------------------------------------------------------------
The friction power is proportional to mu at a fixed state (Couette torque, the force's torque and
F . v all are), the flows do not depend on it (the pressure-driven part h^3 dp / (12 mu) holds
p / mu). So one film report at the reference viscosity mu_ref serves every temperature:
P(T) = P_ref mu(T) / mu_ref, and the heat balance's target T*(T) = T_supply + k dT(mu(T)) is
a scalar function. The quasi-static temperature at the state solves T = T*(T) (at a static
equilibrium the same fixed point as ``effective_temperature``'s); the lagged one follows it with
the residence time t_res as a first-order lag, dT/dt = (T*(T) - T) / t_res, stepped over dt
exactly for a target held at the step's end: T_new = T*(T_new) + (T_old - T*(T_new)) exp(-dt / t_res),
an implicit step (stable for any dt; its steady state is the quasi-static fixed point).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from .solver.film import FilmReport, at_viscosity
from .oil import KELVIN, Oil
from .params import BearingParams
from .solver.reynolds import Reynolds
from .statics import EquilibriumError, equilibrium

__all__ = ["ThermalError", "ThermalState", "heat_balance_rise", "temperature_rise", "effective_temperature", "residence_time_s",
           "film_temperature"]


class ThermalError(ValueError):
    """No effective temperature: outside the oil's range, or no equilibrium at some viscosity."""


@dataclass(frozen=True)
class ThermalState:
    """The film at its effective temperature (SI, K).

    T_supply_K, T_eff_K : supply and effective temperature [K]
    dT_K        : the film's temperature rise, outlet over inlet [K]
    mu_eff_Pa_s : the viscosity at T_eff [Pa s]
    y_m, z_m    : the journal's static equilibrium at mu_eff [m]
    report      : friction and flow there (``physics.solver.film.FilmReport``)
    evaluations : film solutions the root search took
    """

    T_supply_K: float
    T_eff_K: float
    dT_K: float
    mu_eff_Pa_s: float
    y_m: float
    z_m: float
    report: FilmReport
    evaluations: int


def temperature_rise(report: FilmReport, oil: Oil, T_supply_K: float | None = None) -> float:
    """dT [K] of the oil's heat balance (module docstring: P = rho c_p (Q - s Qs) dT + h A (T_eff - T_amb),
    s = ``oil.outflow_share``, h A = ``oil.ambient_W_K``, T_eff = T_supply + k dT); 0 without friction power."""
    T_s = oil.T_supply if T_supply_K is None else T_supply_K
    T_amb = T_s if oil.T_ambient is None else oil.T_ambient
    return heat_balance_rise(report, oil.density * oil.heat_capacity, share=oil.outflow_share,
                             loss_W_K=oil.ambient_W_K, excess_K=T_s - T_amb, k=oil.rise_factor)


def heat_balance_rise(report: FilmReport, rho_c: float, *, share: float = 0.5, loss_W_K: float = 0.0,
                      excess_K: float = 0.0, k: float = 0.5) -> float:
    """dT [K] = (P - hA x) / (rho_c (Q - s Qs) + k hA), rho_c = rho c_p [J/(m^3 K)], s = ``share``, hA =
    ``loss_W_K`` [W/K] the heat lost per kelvin of T_eff = T_supply + k dT above the ambient, x =
    ``excess_K`` the supply's excess over the ambient [K]: P = rho_c (Q - s Qs) dT + hA (T_eff - T_amb).
    0 without friction power. ThermalError when the film dissipates and carries no oil away (no heat
    balance: never a NaN)."""
    power = report.friction_power_W
    if not power > 0.0:
        return 0.0
    carried = report.inflow_m3_s - share * report.side_flow_m3_s
    if not carried > 0.0:
        raise ThermalError(f"temperature rise: the film carries no oil away (inflow {report.inflow_m3_s:.4g} m^3/s, "
                           f"side flow {report.side_flow_m3_s:.4g} m^3/s) while it dissipates {power:.4g} W")
    return (power - loss_W_K * excess_K) / (rho_c * carried + k * loss_W_K)


def residence_time_s(params: BearingParams, report: FilmReport) -> float:
    """How long the oil stays in the film [s]: the mean film volume 2 pi R CR L over the inflow."""
    return 2.0 * math.pi * params.R * params.CR * params.L / report.inflow_m3_s


def effective_temperature(params: BearingParams, load, omega: float, T_supply_K: float | None = None, *,
                          n_theta: int | None = None, n_x: int | None = None, tol_K: float = 1e-3,
                          name: str = "the bearing", internal=None) -> ThermalState:
    """The effective temperature of the bearing's film under the static ``load`` = (Wy, Wz) [N] at
    ``omega`` [rad/s], oil supplied at ``T_supply_K`` [K] (default: the bearing file's supply_C),
    converged to ``tol_K``; the Reynolds solver on an n_theta x n_x grid (default: its own).
    ThermalError when the bearing has no [oil], at omega = 0, or when no root lies in the oil's range.
    ``internal``: another internal with a film report (``Capabilities.film_flow``) at the viscosity
    ``params.mu``, in place of the solver: F ~ mu at a state, so at mu(T) its equilibrium is the one
    under the load times mu / mu(T) and its report is ``film.at_viscosity``'s (exact)."""
    oil = params.oil
    if oil is None:
        raise ThermalError(f"effective temperature of {name}: the bearing has no [oil] table (a viscosity law); "
                           f"it is isoviscous at {params.mu:g} Pa s")
    if not (math.isfinite(omega) and omega != 0.0):
        raise ThermalError(f"effective temperature of {name}: omega = {omega!r} rad/s: a film without rotation "
                           "dissipates nothing; give a speed")
    T_s = oil.check_temperature(oil.T_supply if T_supply_K is None else T_supply_K, "T_supply")
    k = oil.rise_factor
    seen: dict[float, tuple] = {}
    start = [None]

    def film(T: float):
        if T in seen:
            return seen[T]
        mu = oil.mu(T)
        f = 1.0 if internal is None else mu / internal.params.mu
        try:
            rey = Reynolds(params.with_viscosity(mu), n_theta, n_x) if internal is None else internal
            y, z = equilibrium(rey, (load[0] / f, load[1] / f), omega, start=start[0], name=name)
        except (EquilibriumError, ValueError) as exc:
            raise ThermalError(f"effective temperature of {name}: at T = {T - KELVIN:.4g} C (mu = {mu:.4g} Pa s): "
                               f"{exc}") from None
        start[0] = (y, z)
        rep = at_viscosity(rey.film_report(y, z, 0.0, 0.0, omega), f)
        seen[T] = (mu, y, z, rep, temperature_rise(rep, oil, T_s))
        return seen[T]

    def residual(T: float) -> float:
        return T_s + k * film(T)[4] - T

    r0 = residual(T_s)
    if abs(r0) <= tol_K:
        T_eff = T_s
    elif r0 < 0.0:  # a housing losing more than the film makes at T_supply: the film runs below it
        lo = T_s
        while residual(lo) < 0.0:
            if lo <= oil.T_min:
                raise ThermalError(f"effective temperature of {name}: below the oil's range ({oil.name}: from "
                                   f"{oil.T_min - KELVIN:.4g} C): the heat lost to the ambient (ambient_W_K, "
                                   "ambient_C) cools the film further; lower ambient_W_K or raise ambient_C")
            lo = max(lo - 2.0 * (T_s - lo) - abs(r0), oil.T_min)
        T_eff = brentq(residual, lo, T_s, xtol=tol_K, rtol=1e-12) if residual(lo) > 0.0 else lo
    else:
        lo, hi = T_s, min(T_s + r0, oil.T_max)
        while residual(hi) > 0.0:
            if hi >= oil.T_max:
                raise ThermalError(f"effective temperature of {name}: above the oil's range ({oil.name}: up to "
                                   f"{oil.T_max - KELVIN:.4g} C): at {oil.T_max - KELVIN:.4g} C the film would still "
                                   f"heat to {T_s + k * film(hi)[4] - KELVIN:.4g} C; widen [oil] range_C or cool "
                                   "the supply")
            lo, hi = hi, min(hi + 2.0 * (hi - T_s), oil.T_max)
        T_eff = brentq(residual, lo, hi, xtol=tol_K, rtol=1e-12) if residual(hi) < 0.0 else hi
    mu, y, z, rep, dT = film(T_eff)
    return ThermalState(T_supply_K=T_s, T_eff_K=float(T_eff), dT_K=dT, mu_eff_Pa_s=mu, y_m=y, z_m=z, report=rep,
                        evaluations=len(seen))


def film_temperature(params: BearingParams, report: FilmReport, oil: Oil, T_supply_K: float,
                     T_old_K: float | None = None, dt_s: float = 0.0) -> tuple[float, float, float]:
    """(T [K], mu(T) [Pa s], residence time [s]) of the film at one journal state (module
    docstring, "At a fixed journal state"): ``report`` the film there at the viscosity
    ``params.mu``; quasi-static when ``T_old_K`` is None, else lagged from T_old_K over ``dt_s``.
    A film that takes in no oil (no rotation) keeps T_old_K (quasi-static: T_supply). ThermalError
    outside the oil's range, or when it dissipates power with no oil carried away."""
    T_s = oil.check_temperature(T_supply_K, "T_supply")
    q_in = report.inflow_m3_s
    tau = residence_time_s(params, report) if q_in > 0.0 else math.inf
    lagged = T_old_K is not None
    a = math.exp(-dt_s / tau) if lagged else 0.0
    if lagged:
        T_old = oil.check_temperature(T_old_K, "the film temperature (T_eff)")
    else:
        T_old = T_s
    per_mu = report.friction_power_W / params.mu  # P / mu [W / (Pa s)] at this state
    if per_mu <= 0.0 or a == 1.0:
        T = T_old if lagged else T_s
        return T, oil.mu(T), tau
    carried = q_in - oil.outflow_share * report.side_flow_m3_s
    if not carried > 0.0:
        raise ThermalError(f"film temperature: the film carries no oil away (inflow {q_in:.4g} m^3/s, side flow "
                           f"{report.side_flow_m3_s:.4g} m^3/s) while it dissipates {report.friction_power_W:.4g} W")
    # T* = T_s + k dT, dT = (P - hA x) / (rho c (Q - s Qs) + k hA), P = per_mu mu(T) (``heat_balance_rise``)
    den = oil.density * oil.heat_capacity * carried + oil.rise_factor * oil.ambient_W_K
    gain = oil.rise_factor * per_mu / den  # k dT / mu [K / (Pa s)] of the friction power
    excess = T_s - (T_s if oil.T_ambient is None else oil.T_ambient)
    shift = -oil.rise_factor * oil.ambient_W_K * excess / den  # [K]: the loss at T_supply

    def g(T: float) -> float:  # decreasing in T: the target falls as the oil thins
        return (1.0 - a) * (T_s + shift + gain * oil.mu(T)) + a * T_old - T

    lo = max(min(T_old, T_s + min(shift, 0.0)), oil.T_min)
    hi = min(max(T_old, T_s + max(shift, 0.0) + gain * oil.mu(lo)), oil.T_max)
    if g(lo) < 0.0:  # only with a heat loss (shift < 0) can the target lie below the range
        raise ThermalError(f"film temperature: below the oil's range ({oil.name}: from {oil.T_min - KELVIN:.4g} C): "
                           "the heat lost to the ambient (ambient_W_K, ambient_C) cools the film further")
    if g(hi) > 0.0:
        raise ThermalError(f"film temperature: above the oil's range ({oil.name}: up to {oil.T_max - KELVIN:.4g} C): "
                           f"the heat balance at {oil.T_max - KELVIN:.4g} C still heats the film (dissipation "
                           f"{report.friction_power_W * oil.mu(hi) / params.mu:.4g} W); cool the supply or widen the "
                           "oil's range")
    g_lo = g(lo)
    T = lo if g_lo <= 0.0 else (hi if g(hi) == 0.0 else brentq(g, lo, hi, xtol=1e-10, rtol=1e-15))
    return float(T), oil.mu(T), tau
