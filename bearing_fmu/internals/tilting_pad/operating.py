"""A tilting-pad bearing at one operating point: the journal's static equilibrium under a load with
the massless pads in moment equilibrium, the full (2 + N) x (2 + N) coefficients, the journal's
K and C reduced at the running speed (synchronous), the pads' tilts and loads, friction and flows
summed over the pads (what ``bearing-fmu demo`` prints and writes with --json; the keys the fixed
bores' record has keep their meaning: ``physics.operating``).

With an [oil] table the point is at the film's effective temperature, as for the fixed bores
(``physics.thermal.effective_temperature`` with this bearing's film report: the pads' friction and
flows summed, every pad fed at its leading edge; one temperature for the whole film, the pads'
hot-oil carry-over between pads not modelled). Massless pads in moment equilibrium take a tilt that
does not depend on mu (every moment scales with it), so the force at a fixed journal state is
exactly mu times a function of the state, as for a fixed bore, and the point at mu_eff is exact.
Without an [oil] table the record is isoviscous at mu and gives the film's temperature rise with
a mineral oil's rho c_p.
"""

from __future__ import annotations

import math

import numpy as np

from ...physics.oil import DEFAULT_DENSITY, DEFAULT_HEAT_CAPACITY, KELVIN
from ...physics.params import BearingParams
from ...physics.statics import dimensionless_coefficients, sommerfeld_number
from ...physics.thermal import effective_temperature, heat_balance_rise
from .tilting_pad import TiltingPad, viscosity_scaling_why

def operating_point(params: BearingParams, load, speed_hz: float, n_theta: int | None = None,
                    n_x: int | None = None, T_supply_K: float | None = None) -> dict:
    """The record of the tilting-pad bearing ``params`` under the static ``load`` = (Wy, Wz) [N] at
    ``speed_hz`` [Hz] (> 0); pad grid n_theta cells per pad x n_x (None: the solver's defaults); with
    an [oil] table at the film's effective temperature, oil supplied at ``T_supply_K`` [K] (default:
    the file's supply_C)."""
    if not (math.isfinite(speed_hz) and speed_hz > 0.0):
        raise ValueError(f"operating point: speed_hz = {speed_hz!r} must be a finite number > 0")
    load = (float(load[0]), float(load[1]))
    omega = 2.0 * math.pi * speed_hz
    W = math.hypot(*load)
    oil, thermal = params.oil, None
    if oil is not None and viscosity_scaling_why(params.geometry.pads):
        raise ValueError(viscosity_scaling_why(params.geometry.pads))
    if oil is not None:
        thermal = effective_temperature(params, load, omega, T_supply_K, internal=TiltingPad(params, n_theta, n_x),
                                        name="the tilting pads")
        params = params.with_viscosity(thermal.mu_eff_Pa_s)
    elif T_supply_K is not None:
        raise ValueError("operating point: a supply temperature needs the bearing's [oil] table (its viscosity law); "
                         f"this bearing is isoviscous at {params.mu:g} Pa s")
    bearing = TiltingPad(params, n_theta, n_x)
    y0, z0 = bearing.journal_equilibrium(load, omega, start=None if thermal is None else (thermal.y_m, thermal.z_m))
    co = bearing.coefficients(y0, z0, omega)
    sol, pads = co["solution"], bearing.pads
    rep = bearing.film_report(y0, z0, 0.0, 0.0, omega)
    power, torque, inflow, side = rep.friction_power_W, rep.friction_torque_Nm, rep.inflow_m3_s, rep.side_flow_m3_s
    rise = thermal.dT_K if thermal is not None else heat_balance_rise(rep, DEFAULT_DENSITY * DEFAULT_HEAT_CAPACITY)
    radial = sol.u if sol.u is not None else np.zeros(pads.n)  # flexible pivots: each pad's own displacement
    h_min = min(pads.solvers[k].params.geometry.min_film(*pads.frame_state(k, (y0, z0), (0.0, 0.0), sol.delta[k],
                                                                          0.0, radial[k])[:2], params.CR)
                for k in range(pads.n))
    rec = {
        "speed_hz": speed_hz, "load_N": list(load), "y0_m": y0, "z0_m": z0,
        "eccentricity": math.hypot(y0, z0) / params.CR,
        "attitude_deg": (math.degrees(math.atan2(load[0] * z0 - load[1] * y0, load[0] * y0 + load[1] * z0))
                         if W > 0.0 else None),
        "h_min_m": h_min, "mu_Pa_s": params.mu,
        "sommerfeld": sommerfeld_number(params, W, speed_hz) if W > 0.0 else None,
        "friction_coefficient": torque / params.R / W if W > 0.0 else None,
        "friction_torque_Nm": torque, "friction_power_W": power, "inflow_m3_s": inflow, "side_flow_m3_s": side,
        "flow_variable": inflow / (params.R * params.CR * speed_hz * params.L), "temperature_rise_K": rise,
        "T_supply_K": thermal.T_supply_K if thermal else None, "T_eff_K": thermal.T_eff_K if thermal else None,
        "mu_eff_Pa_s": params.mu, "oil": oil.describe() if oil is not None else None,
        "K_N_m": co["K"].tolist(), "C_N_s_m": co["C"].tolist(),
        "whirl_rad_s": omega,
        "pads": {
            "pivots_deg": [math.degrees(p) for p in pads.pads.pivots],
            "rotation_rad": sol.delta.tolist(),
            "load_N": [float(np.hypot(*f)) for f in sol.pad_F],
            "force_N": sol.pad_F.tolist(),
            "moment_N_m": sol.M.tolist(),
            "pad_clearance_m": pads.pads.pad_clearance(params.CR),
            "K_full": co["K_full"].tolist(), "C_full": co["C_full"].tolist(),
            "full_coordinates": pads.coordinate_names(),
        },
    }
    if sol.u is not None:  # flexible pivots: each pad's radial displacement, its pivot's load = k_p u
        rec["pads"]["pivot_stiffness_N_m"] = pads.kp
        rec["pads"]["pivot_deflection_m"] = sol.u.tolist()
        rec["pads"]["pivot_load_N"] = sol.pivot_loads(pads.s).tolist()
    if W > 0.0:
        Kd, Cd = dimensionless_coefficients(params, W, omega, co["K"], co["C"])
        rec["K_dimensionless"], rec["C_dimensionless"] = np.asarray(Kd).tolist(), np.asarray(Cd).tolist()
    else:
        rec["K_dimensionless"] = rec["C_dimensionless"] = None
    if thermal is not None:
        rec["T_eff_C"] = thermal.T_eff_K - KELVIN
    return rec


__all__ = ["operating_point"]
