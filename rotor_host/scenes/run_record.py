"""What a run's record adds to its arrays: the package versions, a fitted internal's domain report,
and the film's peak pressure.

The peak pressure: per bearing, at the recorded state where its journal
came closest to the bore (the largest eccentricity: where the film is thinnest and its pressure, for
a designer's check against the bearing metal's limit, about the highest of the run).

The pressure is the Reynolds field's at that state (``Reynolds.peak_pressure``), for a run whose
internal answers for any state (the Reynolds solver, the force map): one solve per bearing after the run, at the viscosity the film had then (``mu_eff``
of a thermal run, else the bearing's). A state the solver refuses (the journal beyond the bore, a
tilting-pad bearing, which has no single film) gives None, said in ``peak_pressure_note``.
"""

from __future__ import annotations

import functools
import math
import platform

import numpy as np

from bearing_fmu.internals import registry
from bearing_fmu.internals.registry import Context

__all__ = ["domain_report", "package_versions", "peak_pressures"]


def peak_pressures(bearings, arrays: dict, any_state: bool = True) -> dict:
    """{"peak_pressure_Pa", "peak_pressure_deg", "peak_pressure_t_s"}: lists over ``bearings`` (their
    BearingParams, in the order of the run's bearing columns) from the run's ``arrays`` (``y``, ``z``,
    ``vy``, ``vz`` of the recorded nodes, ``eccentricity`` and ``mu_eff`` per bearing, ``speed_hz``,
    ``t``); empty lists before the first record. ``any_state`` False (the run's internal is made about
    one operating point: a Taylor surrogate, the linear model): nothing computed, which the note says
    (the Reynolds solver is not loaded for such a run)."""
    t, ecc = arrays["t"], arrays["eccentricity"]
    out = {"peak_pressure_Pa": [], "peak_pressure_deg": [], "peak_pressure_t_s": []}
    if not t.size:
        return out
    if not any_state:
        out["peak_pressure_note"] = ("not computed: this run's internal answers about one operating point and "
                                     "loads no Reynolds solver; `bearing-fmu demo` gives the peak at a state")
        return out
    from bearing_fmu.physics.solver.reynolds import Reynolds

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


def domain_report(scene, rotor, q: np.ndarray, v: np.ndarray) -> dict:
    """Per bearing: the fraction of recorded states outside the internal's fitted domain and
    the largest distance outside it (``domain_distance`` of an internal with a fitted domain,
    e.g. the Taylor surrogate's: relative excess over its bounds or, with stored training
    states, the distance beyond their radius over the domain's size; <= 0: always inside)."""
    frac, dist = [], []
    for k, params in enumerate(rotor.bearings):
        internal = registry.create(scene.internal, params, scene.internal_options(), Context(omega=scene.omega),
                                   where=str(scene.source))
        d = np.array([internal.domain_distance(*q[i, k], *v[i, k]) for i in range(len(q))])
        frac.append(float(np.mean(d > 1e-12)))
        dist.append(float(d.max()))
    return {"out_of_domain_fraction": frac, "max_domain_excess": dist}


def package_versions() -> dict:
    return dict(_versions())


@functools.cache  # once per process: a sweep's worker runs many scenes (~17 ms each time)
def _versions() -> dict:
    import importlib.metadata as md

    out = {"python": platform.python_version()}
    for pkg in ("bearing-fmu", "numpy", "scipy", "numba", "fmpy", "pythonfmu"):
        try:
            out[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            out[pkg] = None
    return out
