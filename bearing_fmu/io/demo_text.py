"""The text ``bearing-fmu demo`` prints: an operating point's record (``physics.operating`` for the
fixed bores, ``internals.tilting_pad.operating`` for tilting pads) as the lines a designer reads,
with the conventions each figure needs (axes, signs, whose definitions)."""

from __future__ import annotations

import numpy as np

from ..physics.oil import KELVIN


def print_operating_point(rec: dict, params, load: tuple[float, float], speed_hz: float, *, name: str,
                          model: str) -> None:
    """A fixed bore's record: geometry, equilibrium, peak pressure, Sommerfeld number, K and C (and
    dimensionless), friction, flows and the thermal figures. ``model`` names what computed it."""
    with np.printoptions(precision=4):
        K, C = np.array(rec["K_N_m"]), np.array(rec["C_N_s_m"])
        print(f"{name}: D {params.D * 1e3:g} mm, L {params.L * 1e3:g} mm (L/D {params.L / params.D:.3g}), "
              f"CR {params.CR * 1e6:g} um, mu {rec['mu_Pa_s']:.4g} Pa s; {model}")
        geo = params.geometry
        if not geo.is_full_bore:  # the record's: a feed line placed at this equilibrium
            print(f"bore: {rec['bore']}" + (f"; pad clearance {geo.pad_clearance(params.CR) * 1e6:.4g} um"
                                            if geo.preload > 0 else ""))
        print(f"speed {speed_hz:g} Hz, static load (Wy, Wz) = ({load[0]:g}, {load[1]:g}) N")
        att = rec["attitude_deg"] if rec["attitude_deg"] is not None else 0.0
        print(f"equilibrium: y0 = {rec['y0_m'] * 1e6:.3f} um, z0 = {rec['z0_m'] * 1e6:.3f} um, eccentricity ratio "
              f"{rec['eccentricity']:.4f}, attitude angle {att:.2f} deg, minimum film {rec['h_min_m'] * 1e6:.3f} um")
        print(f"film pressure: peak {rec['peak_pressure_Pa'] / 1e6:.4g} MPa at theta = {rec['peak_pressure_deg']:.2f} deg "
              f"(minimum film at {rec['min_film_deg']:.2f} deg; theta 0 at the top, turning with the shaft)"
              + (f"; unit load W / (L D) = {rec['unit_load_Pa'] / 1e6:.4g} MPa, ratio {rec['unit_load_Pa'] / rec['peak_pressure_Pa']:.4g}"
                 if rec["peak_pressure_Pa"] > 0.0 else ""))
        W = float(np.hypot(*load))
        if W > 0.0:
            print(f"Sommerfeld number S = (mu N L D / W) (R / C)^2 = {rec['sommerfeld']:.4g} (Raimondi and Boyd's; "
                  f"N = {speed_hz:g} rev/s, W = {W:g} N, R = D / 2, C = CR)")
        print("stiffness K [N/m] (K_ij = -dF_i/dq_j; axes y horizontal, z vertical up):")
        print(K)
        if W > 0.0:
            print("dimensionless stiffness K CR / W:")
            print(np.array(rec["K_dimensionless"]))
        print("damping C [N s/m] (C_ij = -dF_i/dqdot_j):")
        print(C)
        if W > 0.0:
            print("dimensionless damping C omega CR / W:")
            print(np.array(rec["C_dimensionless"]))
            if load[0] == 0.0 and load[1] < 0.0:
                print("(a table with x along the load and y along the rotation reads K_xx = K_zz, K_yy = K_yy, "
                      "K_xy = -K_zy, K_yx = -K_yz here, the same for C)")
        else:
            print("no load: no Sommerfeld number, no dimensionless coefficients (both divide by the load)")
        f = rec["friction_coefficient"]
        print(f"friction: torque {rec['friction_torque_Nm']:.4g} N m, power {rec['friction_power_W']:.4g} W"
              + (f", coefficient f = {f:.4g} ((R / C) f = {f * params.R / params.CR:.4g})" if f is not None else "")
              + " (the cavitated film sheared as full film, as Raimondi and Boyd)")
        q, qs = rec["inflow_m3_s"], rec["side_flow_m3_s"]
        print(f"oil flow: inflow Q = {q * 6e4:.4g} L/min (Q / (R C N L) = {rec['flow_variable']:.4g}), side flow "
              f"Qs = {qs * 6e4:.4g} L/min (Qs / Q = {qs / q:.3f})")
        if rec["T_eff_K"] is not None:
            print(f"thermal: {rec['oil']}; supply {rec['T_supply_K'] - KELVIN:.4g} C, film rise dT = "
                  f"{rec['temperature_rise_K']:.3g} K, effective temperature T_eff = {rec['T_eff_K'] - KELVIN:.4g} C, "
                  f"mu_eff = {rec['mu_eff_Pa_s']:.4g} Pa s (the point above is at mu_eff)")
        else:
            print(f"thermal: no [oil] table, isoviscous at mu; with rho c_p of a mineral oil the film would rise by "
                  f"dT = {rec['temperature_rise_K']:.3g} K (docs/thermal.md)")


def print_tilting_pads(rec: dict, params, load: tuple[float, float], speed_hz: float, *, name: str) -> None:
    """A tilting-pad bearing's record: the fixed bores' figures (K, C synchronously reduced) with
    each pad's rotation, load and pivot deflection."""
    with np.printoptions(precision=4):
        pads = rec["pads"]
        print(f"{name}: D {params.D * 1e3:g} mm, L {params.L * 1e3:g} mm, CR {params.CR * 1e6:g} um "
              f"(pad clearance {pads['pad_clearance_m'] * 1e6:.4g} um), mu {params.mu:.4g} Pa s")
        print(f"bore: {params.geometry.describe()}")
        print(f"speed {speed_hz:g} Hz, static load (Wy, Wz) = ({load[0]:g}, {load[1]:g}) N")
        att = rec["attitude_deg"] if rec["attitude_deg"] is not None else 0.0
        print(f"equilibrium: y0 = {rec['y0_m'] * 1e6:.3f} um, z0 = {rec['z0_m'] * 1e6:.3f} um, eccentricity ratio "
              f"{rec['eccentricity']:.4f}, attitude angle {att:.2f} deg, minimum film {rec['h_min_m'] * 1e6:.3f} um")
        for k, piv in enumerate(pads["pivots_deg"]):
            print(f"  pad at {piv:7.2f} deg: rotation {pads['rotation_rad'][k] * 1e3:+.5f} mrad, load "
                  f"{pads['load_N'][k]:.4g} N" + (f", pivot deflection {pads['pivot_deflection_m'][k] * 1e6:.4g} um"
                                                 if "pivot_deflection_m" in pads else ""))
        print("stiffness K [N/m] and damping C [N s/m], reduced at the running speed (synchronous):")
        print(np.array(rec["K_N_m"]))
        print(np.array(rec["C_N_s_m"]))
        if rec["K_dimensionless"] is not None:
            print("dimensionless K CR / W and C omega CR / W:")
            print(np.array(rec["K_dimensionless"]))
            print(np.array(rec["C_dimensionless"]))
        film = ("isoviscous" if rec["T_eff_K"] is None else
                f"oil {rec['oil']}: supply {rec['T_supply_K'] - KELVIN:.4g} C, effective temperature {rec['T_eff_C']:.4g} C, "
                f"mu_eff {rec['mu_eff_Pa_s']:.4g} Pa s")
        print(f"friction: power {rec['friction_power_W']:.4g} W; oil flow: inflow {rec['inflow_m3_s'] * 6e4:.4g} L/min, "
              f"side flow {rec['side_flow_m3_s'] * 6e4:.4g} L/min, temperature rise {rec['temperature_rise_K']:.4g} K "
              f"({film}; the full (2 + N) coefficients: --json)")
