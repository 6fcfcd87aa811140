"""What the linear analyses take in, checked before any solve: the rotor file and its static
loads, the speeds (finite, increasing, none beyond what the rotor's material allows) and bearings
that can hold the rotor at all; each refusal a ValueError naming the file, option or key."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...model.rotor import Rotor


def read_rotor(rotor_path, static_loads=()) -> tuple[Rotor, list[tuple[int, float, float]]]:
    """The rotor file and the static loads (node, Fy, Fz) with 1-based nodes, checked against
    its nodes and turned 0-based; ValueError naming the file or the load."""
    rotor_path = Path(rotor_path)
    rotor = Rotor.from_toml(rotor_path)
    loads = []
    for node, fy, fz in static_loads:
        if not 1 <= int(node) <= rotor.n_nodes:
            raise ValueError(f"--static-load {node}:{fy:g}:{fz:g}: node {node} is outside the rotor's nodes "
                             f"1..{rotor.n_nodes} ({rotor_path})")
        loads.append((int(node) - 1, float(fy), float(fz)))
    if not rotor.bearing_nodes:
        raise ValueError(f"{rotor_path}: the rotor has no bearings; a stability analysis needs at least one "
                         "[[bearings]] entry (node, bearing file)")
    return rotor, loads


def check_speeds(speeds_hz) -> list[float]:
    """Finite speeds > 0 Hz in increasing order, or ValueError."""
    speeds = [float(s) for s in speeds_hz]
    if not speeds or any(not (math.isfinite(s) and s > 0.0) for s in speeds) or np.any(np.diff(speeds) <= 0.0):
        raise ValueError(f"speeds {speeds!r}: expected finite speeds > 0 Hz in increasing order")
    return speeds


def check_top_speed(rotor: Rotor, speeds_hz, where: str) -> None:
    """ValueError naming --speeds-hz when the top speed would move the rotor's surface faster
    than sound in its material (``scenes.sanity.surface_speed_refusal``)."""
    from ...scenes.sanity import surface_speed_refusal

    why = surface_speed_refusal(rotor, max(speeds_hz, default=0.0))
    if why is not None:
        raise ValueError(f"{where}: the top speed (--speeds-hz) = {why}")


def refuse_unsupported(rotor: Rotor, f_static, pairs, names, where: str) -> None:
    """RotorNotSupported (bad input, exit code 2) for bearings all at one place, which no speed
    can change (``integrate.equilibrium.placement_refusal``); ``pairs`` the (y, z) DOFs of each
    bearing, ``names`` their names."""
    from ...integrate.equilibrium import RotorNotSupported, placement_refusal

    dofs = np.array([d for pair in pairs for d in pair], dtype=int)
    why = placement_refusal(rotor.rigid_modes(), f_static, dofs, names)
    if why is not None:
        raise RotorNotSupported(f"{where}: {why}")


__all__ = ["read_rotor", "check_speeds", "check_top_speed", "refuse_unsupported"]
