"""The stability command's inputs beyond the rotor: the internal's options from the command line's
file flags and grid, and the supply temperature against every bearing's oil (shared by the
response analyses)."""

from __future__ import annotations

from pathlib import Path

from bearing_fmu.internals import registry

from ...bundled import folder

PAPER_MAP = folder() / "maps" / "paper_bearing.json"  # the bundled map of the paper bearing

DEFAULT_FILES = {"map": PAPER_MAP}  # a file option left out: the paper bearing's (its L/D)


def internal_options(internal: str, files: dict | None = None, grid=None) -> dict:
    """The internal's options from the command line's ``--<file option> FILE`` flags (``files``:
    option -> path; a required one left out: ``DEFAULT_FILES``) and ``--grid`` (n_theta, n_x),
    refused by option name when the internal does not read them."""
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
