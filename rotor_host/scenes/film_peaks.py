"""The film's peak pressure in a run's record: per bearing, at the recorded state where its journal
came closest to the bore (the largest eccentricity: where the film is thinnest and its pressure, for
a designer's check against the bearing metal's limit, about the highest of the run).

The pressure is the Reynolds field's at that state (``Reynolds.peak_pressure``), whichever internal
ran the scene: one solve per bearing after the run, at the viscosity the film had then (``mu_eff``
of a thermal run, else the bearing's). A state the solver refuses (the journal beyond the bore, a
tilting-pad bearing, which has no single film) gives None, said in ``peak_pressure_note``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["peak_pressures"]


def peak_pressures(bearings, arrays: dict) -> dict:
    """{"peak_pressure_Pa", "peak_pressure_deg", "peak_pressure_t_s"}: lists over ``bearings`` (their
    BearingParams, in the order of the run's bearing columns) from the run's ``arrays`` (``y``, ``z``,
    ``vy``, ``vz`` of the recorded nodes, ``eccentricity`` and ``mu_eff`` per bearing, ``speed_hz``,
    ``t``); empty lists before the first record."""
    from bearing_fmu.physics.reynolds import Reynolds

    t, ecc = arrays["t"], arrays["eccentricity"]
    out = {"peak_pressure_Pa": [], "peak_pressure_deg": [], "peak_pressure_t_s": []}
    if not t.size:
        return out
    cols = {int(n): i for i, n in enumerate(arrays["nodes"])}
    notes = []
    for k, (params, node) in enumerate(zip(bearings, arrays["bearing_nodes"])):
        i, c = int(np.argmax(ecc[:, k])), cols[int(node)]
        state = tuple(float(arrays[a][i, c]) for a in ("y", "z", "vy", "vz"))
        if "mu_eff" in arrays:
            params = params.with_viscosity(float(arrays["mu_eff"][i, k]))
        omega = 2.0 * math.pi * float(arrays["speed_hz"][i])
        try:
            if params.geometry.pads is not None:
                raise ValueError("a tilting-pad bearing: each pad has its own film")
            p, th = Reynolds(params).peak_pressure(*state, omega)
        except ValueError as exc:
            notes.append(f"bearing {k + 1}: {exc}")
            p = th = None
        out["peak_pressure_Pa"].append(p)
        out["peak_pressure_deg"].append(None if th is None else math.degrees(th))
        out["peak_pressure_t_s"].append(float(t[i]))
    if notes:
        out["peak_pressure_note"] = "; ".join(notes)
    return out
