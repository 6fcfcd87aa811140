"""What the linear analyses take in, checked before any solve: the rotor file and its static
loads, the speeds (finite, increasing, none beyond what the rotor's material allows) and bearings
that can hold the rotor at all, the internal's options from the command line's file flags and grid,
and the supply temperature against every bearing's oil; each refusal a ValueError naming the file,
option or key."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from bearing_fmu.internals import registry

from ...bundled import folder
from ...model.rotor import Rotor

PAPER_MAP = folder() / "maps" / "paper_bearing.json"  # the bundled map of the paper bearing

DEFAULT_FILES = {"map": PAPER_MAP}  # a file option left out: the paper bearing's (its L/D)


def internal_options(internal: str, files: dict | None = None, grid=None, bearings=()) -> dict:
    """The internal's options from the command line's ``--<file option> FILE`` flags (``files``:
    option -> path; a required one left out: the map store's for ``bearings`` when it has one,
    named on stderr, else ``DEFAULT_FILES``) and ``--grid`` (n_theta, n_x), refused by option name
    when the internal does not read them."""
    spec = registry.get(internal)
    own = {o.name: o for o in spec.all_options()}
    out = {}
    for option, path in (files or {}).items():
        if path is None:
            continue
        if option not in own:
            owners = [n for n, other in registry.REGISTRY.items() if option in {o.name for o in other.file_options()}]
            raise ValueError(f"--{option} {path} is for --internal {' or '.join(owners) or '(none)'} (the internal "
                             f"is {spec.name})")
        out[option] = str(Path(path).resolve())
    for o in spec.file_options():
        if o.required and o.name not in out and bearings:
            from bearing_fmu.internals.map.store import stored_file

            path, line = stored_file(o.file_format, bearings)
            if path is not None:
                print(f"--{o.name} not given: {line}", file=sys.stderr)
                out[o.name] = str(path)
        if o.required and o.name not in out:
            if o.name not in DEFAULT_FILES:
                raise ValueError(f"--{o.name}: the {spec.name} internal needs its {o.name} file")
            out[o.name] = str(DEFAULT_FILES[o.name])
    if grid is not None:
        if "n_theta" not in own:
            raise ValueError(f"--grid sets the Reynolds grid; with --internal {spec.name} there is none to set (a "
                             "map's grid is its own: build a map on another grid with `bearing-fmu map`)")
        out.update(n_theta=grid[0], n_x=grid[1])
    return out


def check_supply(rotor, T_supply_K: float, where: str, what: str) -> None:
    """ValueError naming ``what`` (the supply temperature's source) unless every bearing of the rotor
    has an [oil] table whose range holds ``T_supply_K`` [K]."""
    for k, (p, n) in enumerate(zip(rotor.bearings, rotor.bearing_nodes)):
        name = f"bearing {k + 1} (node {n + 1})"
        if p.oil is None:
            given = f" (given by {what})" if what.startswith("--") else ""
            raise ValueError(f"{where}: {name}: a supply temperature{given} needs the bearing file's [oil] table "
                             f"(its viscosity law); this bearing is isoviscous at {p.mu:g} Pa s")
        p.oil.check_temperature(T_supply_K, what)


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
