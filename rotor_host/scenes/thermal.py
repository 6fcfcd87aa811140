"""A scene's oil supply temperature in a run: each bearing's film at its effective temperature
(docs/thermal.md) at the start, the internal that follows it, and what the run records of it.

``scene_thermal`` solves each bearing's heat balance at the scene's speed and static load (the
run's json ``thermal`` entry, ``thermal_meta``); ``thermal_internal`` makes the internal that runs
at the film's temperature in-process (``LaggedThermal``, or held at the start's viscosity). A run
whose film temperature lags (in-process or through the FMUs' thermal ports) records per bearing,
at every recorded time, the arrays of ``THERMAL_ARRAYS`` (``thermal_arrays``) and, in the json's
``thermal`` entry, their start, end and largest value (``with_history``). ``thermal_lines`` says
it in words (``rotor-host run``), ``settled_thermal`` and ``compared_thermal`` give a sweep's and
a compare's row their values.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the run's (and a sweep's, which reads only the arrays) imports stay light
    from .scene import Scene

# the run's thermal arrays (npz, one column per bearing of ``bearing_nodes``): name (as the bearing
# FMU's output), the json key of its start / end / max (unit in the name), unit, meaning
THERMAL_ARRAYS = (
    ("T_eff", "T_eff_K", "K", "effective film temperature: the heat balance lagged by the film's residence time"),
    ("mu_eff", "mu_eff_Pa_s", "Pa s", "the viscosity the film force is computed at: the oil's at T_eff"),
    ("P_loss", "P_loss_W", "W", "friction power of the film at mu_eff"),
    ("Q_side", "Q_side_m3_s", "m3/s", "oil flow out of both ends of the film"),
    ("Q_in", "Q_in_m3_s", "m3/s", "oil flow into the film (in-process runs only: the FMUs have no inflow output)"),
)


def thermal_arrays_table() -> str:
    """``THERMAL_ARRAYS`` as the markdown table of docs/file-formats.md."""
    rows = ["| array | unit | meaning |", "|---|---|---|"]
    rows += [f"| `{name}` | {unit} | {meaning} |" for name, _key, unit, meaning in THERMAL_ARRAYS]
    return "\n".join(rows)


# ------------------------------------------------------------------------------- the start

def scene_thermal(scene: Scene, rotor, loads: np.ndarray) -> list | None:
    """Each bearing's film at its effective temperature (``physics.thermal.ThermalState``) at the
    scene's speed under its static load, with the scene's supply temperature; None without one.
    A bearing without a film temperature there is an EquilibriumError naming it."""
    if scene.supply_temperature_K is None:
        return None
    from bearing_fmu.physics.statics import EquilibriumError
    from bearing_fmu.physics.thermal import ThermalError, effective_temperature

    from bearing_fmu.internals import registry

    spec = registry.get(scene.internal)
    out = []
    for k, (p, w) in enumerate(zip(rotor.bearings, loads)):
        name = f"bearing {k + 1} (node {rotor.bearing_nodes[k] + 1})"
        load = (float(w[0]), float(w[1]))
        # the scene's own internal where the Reynolds solver cannot take the bore (tilting pads)
        own = (spec.create(p, scene.internal_options(), registry.Context(load=load, omega=scene.omega),
                           where=f"{scene.source}: {name}") if spec.can.pads else None)
        try:
            out.append(effective_temperature(p, load, scene.omega, scene.supply_temperature_K, name=name,
                                             internal=own))
        except ThermalError as exc:
            raise EquilibriumError(str(exc), bearing=name) from None
    return out


def thermal_meta(states) -> list[dict]:
    """The run's json entry of ``scene_thermal``: per bearing T_eff, mu_eff and the film's friction and flows."""
    return [{"T_supply_K": st.T_supply_K, "T_eff_K": st.T_eff_K, "dT_K": st.dT_K, "mu_eff_Pa_s": st.mu_eff_Pa_s,
             "P_loss_W": st.report.friction_power_W, "inflow_m3_s": st.report.inflow_m3_s,
             "side_flow_m3_s": st.report.side_flow_m3_s, "friction_coefficient": st.report.friction_coefficient}
            for st in states]


def thermal_internal(scene: Scene, internal, params, state):
    """One bearing's internal at its film's temperature: lagging the heat balance by the residence
    time from the quasi-static value at its static equilibrium (``LaggedThermal``, the FMU's model)
    when the internal has the film's flows, else held at the static equilibrium's mu_eff (exact for
    one speed: F ~ mu; ``scene.py`` refuses a run-up for an internal without them by capability, and
    here one whose file lacks them, e.g. a map file without flow tables)."""
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.scaled import LaggedThermal, ViscosityScaled

    from .scene import SceneError

    inertia = getattr(getattr(params.geometry, "pads", None), "inertia", 0.0)
    if inertia:  # its force at another viscosity is not the force times the ratio: the pads' dynamics change
        raise SceneError(f"{scene.source}: supply_temperature_C with tilting pads of inertia "
                         f"(pad_inertia_kg_m2 = {inertia:g}): the pads' motion at the film's temperature is not "
                         "modelled yet; massless pads (pad_inertia_kg_m2 = 0) or an isoviscous bearing")
    why = registry.film_flow_of(registry.get(scene.internal), internal)
    if why:
        if scene.speed_profile is not None:
            raise SceneError(f"{scene.source}: supply_temperature_C with a [speed_profile] needs the film's flows: "
                             f"{why}")
        return ViscosityScaled(internal, state.mu_eff_Pa_s)
    lagged = LaggedThermal(internal, params.oil, state.T_supply_K)
    lagged.start(state.y_m, state.z_m, 0.0, 0.0, scene.omega)
    return lagged


# ------------------------------------------------------------------------------- over time

def thermal_arrays(extra, fields, n_times: int, n_bearings: int) -> dict:
    """The run's thermal arrays (n_times, n_bearings) by name from the integrator's records
    ``extra`` ((n_times, n_bearings, len(fields)): ``BearingSet.thermal_record`` at each recorded
    time; None or empty before the integration started)."""
    x = np.zeros((0, n_bearings, len(fields))) if extra is None or not np.size(extra) else np.asarray(extra, float)
    if x.shape != (n_times, n_bearings, len(fields)):
        raise ValueError(f"thermal records of shape {x.shape}, expected {(n_times, n_bearings, len(fields))}")
    return {name: x[:, :, j] for j, name in enumerate(fields)}


def with_history(entries: list[dict], arrays: dict) -> list[dict]:
    """The json ``thermal`` entries (one per bearing) with ``over_time``: the start, end and largest
    value of each thermal array the run has (none before its first record)."""
    keys = [(name, key) for name, key, *_ in THERMAL_ARRAYS if name in arrays]
    out = []
    for k, entry in enumerate(entries):
        over = {}
        for name, key in keys:
            v = np.asarray(arrays[name])[:, k]
            if v.size:
                over[key] = {"start": float(v[0]), "end": float(v[-1]), "max": float(v.max())}
        out.append({**entry, "over_time": over})
    return out


def thermal_lines(arrays: dict) -> list[str]:
    """One line per bearing: T_eff and P_loss from the start to the end of the run (and the speeds
    there when it changes), their largest values; [] for a run without the thermal arrays."""
    if "T_eff" not in arrays or not np.size(arrays["T_eff"]):
        return []
    speed = np.asarray(arrays["speed_hz"], float)
    at = ("" if speed[-1] == speed[0] else f" from {speed[0]:.1f} to {speed[-1]:.1f} Hz")
    T, P = np.asarray(arrays["T_eff"]) - 273.15, np.asarray(arrays["P_loss"])
    return [f"bearing {k + 1} (node {int(n)}) oil{at}: T_eff {T[0, k]:.2f} -> {T[-1, k]:.2f} C (max "
            f"{T[:, k].max():.2f} C), friction power {P[0, k]:.3g} -> {P[-1, k]:.3g} W (max {P[:, k].max():.3g} W)"
            for k, n in enumerate(np.asarray(arrays["bearing_nodes"]).ravel())]


def settled_thermal(arrays: dict, window) -> list[dict]:
    """Per bearing the mean T_eff [K] and friction power [W] over the recorded times ``window`` (a
    boolean mask: a sweep's settled part); [] for a run without the thermal arrays."""
    if "T_eff" not in arrays:
        return []
    T, P = np.asarray(arrays["T_eff"], float)[window], np.asarray(arrays["P_loss"], float)[window]
    return [{"T_eff_K": float(T[:, k].mean()), "P_loss_W": float(P[:, k].mean())} for k in range(T.shape[1])]


def compared_thermal(ref: dict, run: dict) -> dict:
    """A compare row's thermal part for ``run`` against the reference run ``ref`` (their arrays):
    the hottest bearing's T_eff at the end [C], the bearings' friction power at the end [W] and the
    largest |T_eff - T_eff of the reference| [K] over the times both reached; {} without T_eff."""
    if not np.size(run.get("T_eff", ())):
        return {}
    T, T_ref = np.asarray(run["T_eff"], float), np.asarray(ref.get("T_eff", np.zeros((0, 1))), float)
    n = min(len(T), len(T_ref))
    return {"T_eff_end_C": float(T[-1].max()) - 273.15, "P_loss_end_W": float(np.asarray(run["P_loss"])[-1].sum()),
            "T_eff_error_K": float(np.abs(T[:n] - T_ref[:n]).max()) if n else None}


__all__ = ["THERMAL_ARRAYS", "thermal_arrays_table", "scene_thermal", "thermal_meta", "thermal_internal",
           "thermal_arrays", "with_history", "thermal_lines", "settled_thermal", "compared_thermal"]
