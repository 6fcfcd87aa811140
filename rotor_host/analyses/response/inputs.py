"""What a figure or a report of the linearised rotor names as its inputs: the rotor file, each
bearing's file, bore and oil, the internal (and its options) and the supply temperature, in
one line for a figure's title and in a list for a markdown report."""

from __future__ import annotations

from pathlib import Path

from bearing_fmu.io.schema import read_toml


def bearing_files(rotor_file) -> list[str]:
    """The ``bearing`` file of each [[bearings]] entry of the rotor file, as written there."""
    data = read_toml(Path(rotor_file), "rotor file", ValueError)
    return [str(b.get("bearing", "?")) for b in data.get("bearings", [])]


def bearing_lines(rotor, rotor_file) -> list[str]:
    """One line per bearing: node, file, D, L, CR, bore and oil."""
    files = bearing_files(rotor_file)
    out = []
    for k, (node, p) in enumerate(zip(rotor.bearing_nodes, rotor.bearings)):
        oil = p.oil.describe() if p.oil is not None else f"isoviscous mu = {p.mu:.4g} Pa s"
        out.append(f"bearing {k + 1} at node {node + 1}: {files[k] if k < len(files) else '?'} (D {p.D * 1e3:g} mm, "
                   f"L {p.L * 1e3:g} mm, CR {p.CR * 1e6:g} um; bore: {p.geometry.describe()}; oil: {oil})")
    return out


def internal_words(internal: str, options: dict | None) -> str:
    """The internal with the options that choose its answer (grid, map file)."""
    opts = dict(options or {})
    parts = [f"{k} {Path(v).name if isinstance(v, str) else v}" for k, v in opts.items()]
    return internal + (f" ({', '.join(parts)})" if parts else "")


def title_line(rotor, rotor_file, internal: str, options: dict | None, T_supply_K: float | None = None) -> str:
    """One line for a figure: rotor file, bearing files and bores, oil, internal."""
    files = sorted(set(bearing_files(rotor_file)))
    bores = sorted({p.geometry.describe() for p in rotor.bearings})
    if T_supply_K is not None:
        oil = f"oil supply {T_supply_K - 273.15:g} C"
    else:
        oil = "oil " + ", ".join(sorted({f"mu {p.mu:.3g} Pa s" for p in rotor.bearings}))
    return (f"{Path(rotor_file).name}; bearings {', '.join(files)} ({'; '.join(bores)}); {oil}; "
            f"internal {internal_words(internal, options)}")


__all__ = ["bearing_files", "bearing_lines", "internal_words", "title_line"]
