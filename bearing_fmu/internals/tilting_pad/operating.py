"""A tilting-pad bearing at one operating point: the journal's static equilibrium under a load with
the massless pads in moment equilibrium, the full (2 + N) x (2 + N) coefficients, the journal's
K and C reduced at the running speed (synchronous), the pads' tilts and loads, friction and flows
summed over the pads (what ``bearing-fmu demo`` prints and writes with --json; the keys the fixed
bores' record has keep their meaning: ``physics.operating``).

Not there yet: the effective temperature of an [oil] table (the record is isoviscous at mu and,
as for an isoviscous fixed bore, gives the film's temperature rise with a mineral oil's rho c_p).
"""

from __future__ import annotations

import math

import numpy as np

from ...physics.oil import DEFAULT_DENSITY, DEFAULT_HEAT_CAPACITY
from ...physics.params import BearingParams
from ...physics.statics import EquilibriumError, dimensionless_coefficients, sommerfeld_number
from ..base import BearingStateError
from .tilting_pad import TiltingPad

NEWTON_MAX = 80


def journal_equilibrium(bearing: TiltingPad, load, omega: float, rtol: float = 1e-9) -> tuple[float, float]:
    """(y0, z0) [m] where the film force of the pads (in moment equilibrium) balances ``load`` =
    (Wy, Wz) [N]: Newton with the quasi-static Jacobian from 0.2 C_bearing along the load, each step
    halved until every pad's film stays open and the residual falls."""
    load = np.asarray(load, float)
    w = float(np.hypot(*load))
    if w == 0.0:
        return 0.0, 0.0
    # from 0.2 C_bearing along the load: a centred journal on unpreloaded pads has no film force and
    # no stiffness to start Newton from
    q = 0.2 * bearing.params.CR * load / w

    def residual(x):
        return np.asarray(bearing.force(x[0], x[1], 0.0, 0.0, omega)) + load

    r = residual(q)
    for _ in range(NEWTON_MAX):
        rn = float(np.hypot(*r))
        if rn <= rtol * w:
            return float(q[0]), float(q[1])
        _, dq, _ = bearing.force_and_jacobian(q[0], q[1], 0.0, 0.0, omega)
        try:
            step = -np.linalg.solve(dq, r)
        except np.linalg.LinAlgError:
            break
        alpha = 1.0
        while alpha > 1e-8:
            trial = q + alpha * step
            try:
                r_trial = residual(trial)
            except BearingStateError:
                alpha *= 0.5
                continue
            if float(np.hypot(*r_trial)) < (1.0 - 1e-4 * alpha) * rn:
                break
            alpha *= 0.5
        else:
            break
        q, r = trial, r_trial
    raise EquilibriumError(f"equilibrium: the tilting pads ({bearing.pads.pads.describe()}) found no static "
                           f"equilibrium under the load {load.tolist()} N at omega = {omega:.4g} rad/s (residual "
                           f"{np.hypot(*r):.3g} N at y = {q[0]:.4g} m, z = {q[1]:.4g} m)",
                           bearing="tilting pads", load_N=w, capacity_N=math.nan, speed_hz=omega / (2 * math.pi))


def operating_point(params: BearingParams, load, speed_hz: float, n_theta: int | None = None,
                    n_x: int | None = None) -> dict:
    """The record of the tilting-pad bearing ``params`` under the static ``load`` = (Wy, Wz) [N] at
    ``speed_hz`` [Hz] (> 0); pad grid n_theta cells per pad x n_x (None: the solver's defaults)."""
    if not (math.isfinite(speed_hz) and speed_hz > 0.0):
        raise ValueError(f"operating point: speed_hz = {speed_hz!r} must be a finite number > 0")
    load = (float(load[0]), float(load[1]))
    omega = 2.0 * math.pi * speed_hz
    W = math.hypot(*load)
    bearing = TiltingPad(params, n_theta, n_x)
    y0, z0 = journal_equilibrium(bearing, load, omega)
    co = bearing.coefficients(y0, z0, omega)
    sol, pads = co["solution"], bearing.pads
    reps = [pads.solvers[k].film_report(*pads.frame_state(k, (y0, z0), (0.0, 0.0), sol.delta[k], 0.0), omega)
            for k in range(pads.n)]
    power = sum(r.friction_power_W for r in reps)
    torque = sum(r.friction_torque_Nm for r in reps)
    inflow = sum(r.inflow_m3_s for r in reps)
    side = sum(r.side_flow_m3_s for r in reps)
    carried = inflow - 0.5 * side
    rise = power / (DEFAULT_DENSITY * DEFAULT_HEAT_CAPACITY * carried) if carried > 0.0 else math.nan
    h_min = min(pads.solvers[k].params.geometry.min_film(*pads.frame_state(k, (y0, z0), (0.0, 0.0), sol.delta[k],
                                                                          0.0)[:2], params.CR) for k in range(pads.n))
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
        "T_supply_K": None, "T_eff_K": None, "mu_eff_Pa_s": params.mu, "oil": None,
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
            "full_coordinates": ["y [m]", "z [m]"] + [f"delta_{k + 1} [rad]" for k in range(pads.n)],
        },
    }
    if W > 0.0:
        Kd, Cd = dimensionless_coefficients(params, W, omega, co["K"], co["C"])
        rec["K_dimensionless"], rec["C_dimensionless"] = np.asarray(Kd).tolist(), np.asarray(Cd).tolist()
    else:
        rec["K_dimensionless"] = rec["C_dimensionless"] = None
    return rec


__all__ = ["journal_equilibrium", "operating_point"]
