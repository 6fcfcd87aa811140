"""One bearing at one operating point: equilibrium, Lund coefficients, friction, flow and the
effective temperature, as one record (what ``bearing-fmu demo`` prints and writes with --json).

With an [oil] table the point is computed at the film's effective temperature (``thermal``): the
equilibrium, K and C and the friction at mu_eff. Without one the bearing is isoviscous at mu; the
record still gives the film's temperature rise with the default oil's rho c_p (``oil``), and
T_eff is None (no supply temperature is known).
"""

from __future__ import annotations

import math

import numpy as np

from .oil import DEFAULT_DENSITY, DEFAULT_HEAT_CAPACITY, KELVIN
from .bore.feed import place_feed
from .solver.film import at_viscosity
from .params import BearingParams
from .solver.reynolds import Reynolds
from .statics import dimensionless_coefficients, equilibrium, linearize, sommerfeld_number
from .thermal import effective_temperature, heat_balance_rise

__all__ = ["operating_point"]


def _attitude_deg(load, y0: float, z0: float) -> float:
    """The angle from the load's direction to the journal's displacement [deg] (positive: turned from
    +y toward +z, the sense of positive omega)."""
    return math.degrees(math.atan2(load[0] * z0 - load[1] * y0, load[0] * y0 + load[1] * z0))


def operating_point(params: BearingParams, load, speed_hz: float, T_supply_K: float | None = None,
                    internal=None) -> dict:
    """The record of the bearing under the static ``load`` = (Wy, Wz) [N] at ``speed_hz`` [Hz]
    (> 0), oil supplied at ``T_supply_K`` [K] (default: the bearing file's supply_C; refused without
    an [oil] table). Keys carry their unit; K, C are 2 x 2 lists (K_ij = -dF_i/dq_j, axes y, z); angles
    (``min_film_deg``, ``peak_pressure_deg``) are the bore's theta (docs/conventions.md: 0 at the top,
    increasing with the rotation); the peak pressure is the Reynolds field's at the point, whichever
    internal found the point.
    ``internal``: another internal with a film report (a map, a Taylor surrogate with its film fit)
    at the viscosity ``params.mu`` in place of the Reynolds solver, scaled to mu_eff exactly (F ~ mu)."""
    if not (math.isfinite(speed_hz) and speed_hz > 0.0):
        raise ValueError(f"operating point: speed_hz = {speed_hz!r} must be a finite number > 0")
    load = (float(load[0]), float(load[1]))
    omega = 2.0 * math.pi * speed_hz
    W = math.hypot(*load)
    oil = params.oil
    # a feed along the line of thickest film: placed at the isothermal equilibrium (as a run places it)
    params = place_feed(params, load, omega, name="operating point")
    thermal = None
    if oil is not None:
        thermal = effective_temperature(params, load, omega, T_supply_K, internal=internal)
        params = params.with_viscosity(thermal.mu_eff_Pa_s)
    elif T_supply_K is not None:
        raise ValueError("operating point: a supply temperature needs the bearing's [oil] table (its viscosity law); "
                         f"this bearing is isoviscous at {params.mu:g} Pa s")
    start = None if thermal is None else (thermal.y_m, thermal.z_m)
    if internal is None:
        rey, f = Reynolds(params), 1.0
    else:  # the internal at mu_eff: its force times f, so its equilibrium under the load / f
        rey, f = internal, params.mu / internal.params.mu
    y0, z0 = equilibrium(rey, (load[0] / f, load[1] / f), omega, start=start)
    K, C = (f * np.asarray(a) for a in linearize(rey, y0, z0, omega))
    rep = at_viscosity(rey.film_report(y0, z0, 0.0, 0.0, omega), f)
    eps = math.hypot(y0, z0) / params.CR
    geo = params.geometry
    h_min, th_min = geo.min_film_at(y0, z0, params.CR)
    if geo.is_full_bore:
        h_min = params.CR * (1.0 - eps)
    # the peak from the Reynolds field at the point (an internal without a field: one solve here)
    p_peak, th_peak = (rey if internal is None else Reynolds(params)).peak_pressure(y0, z0, 0.0, 0.0, omega)
    rho_c = (oil.density * oil.heat_capacity) if oil is not None else DEFAULT_DENSITY * DEFAULT_HEAT_CAPACITY
    rise = thermal.dT_K if thermal is not None else heat_balance_rise(rep, rho_c)
    rec = {
        "speed_hz": speed_hz, "load_N": list(load), "y0_m": y0, "z0_m": z0,
        "eccentricity": eps, "attitude_deg": _attitude_deg(load, y0, z0) if W > 0.0 else None,
        "h_min_m": h_min, "min_film_deg": math.degrees(th_min), "peak_pressure_Pa": p_peak,
        "peak_pressure_deg": math.degrees(th_peak),
        "unit_load_Pa": W / (params.L * params.D), "mu_Pa_s": params.mu,
        "sommerfeld": sommerfeld_number(params, W, speed_hz) if W > 0.0 else None,
        "friction_coefficient": rep.friction_coefficient if W > 0.0 else None,
        "friction_torque_Nm": rep.friction_torque_Nm, "friction_power_W": rep.friction_power_W,
        "inflow_m3_s": rep.inflow_m3_s, "side_flow_m3_s": rep.side_flow_m3_s,
        "flow_variable": rep.inflow_m3_s / (params.R * params.CR * speed_hz * params.L),
        "temperature_rise_K": rise,
        "T_supply_K": thermal.T_supply_K if thermal else None, "T_eff_K": thermal.T_eff_K if thermal else None,
        "mu_eff_Pa_s": params.mu, "oil": oil.describe() if oil is not None else None,
        "K_N_m": np.asarray(K).tolist(), "C_N_s_m": np.asarray(C).tolist(), "bore": geo.describe(),
    }
    if geo.feed == "thickest":
        rec["feed_deg"] = math.degrees(geo.grooves[0])
    if W > 0.0:
        Kd, Cd = dimensionless_coefficients(params, W, omega, K, C)
        rec["K_dimensionless"], rec["C_dimensionless"] = np.asarray(Kd).tolist(), np.asarray(Cd).tolist()
    else:
        rec["K_dimensionless"] = rec["C_dimensionless"] = None
    if thermal is not None:
        rec["T_eff_C"] = thermal.T_eff_K - KELVIN
    return rec
