"""What a report, a figure or a command's summary names as its inputs: the rotor file, each
bearing's file, bore and oil, the internal (and its options and files) and the supply
temperature, in one line (``title_line``; a scene's: ``scene_line``) for a figure's title and
stdout, and in a list (``bearing_lines``) for a markdown report. Every command that reports
on a rotor (run, stability, waterfall, sweep, response, ucs, level1, api-report) says it with
these, so a plain and a grooved bore never give identical-looking reports."""

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


def oil_words(rotor, T_supply_K: float | None = None) -> str:
    """The bearings' oil: its name (or the isoviscous viscosity) and the supply temperature."""
    oils = sorted({p.oil.name if p.oil is not None else f"isoviscous mu {p.mu:.3g} Pa s" for p in rotor.bearings})
    supply = (f", supply {T_supply_K - 273.15:g} C" if T_supply_K is not None
              else " (no supply temperature: at the bearing files' mu)" if any(p.oil is not None for p in rotor.bearings)
              else "")
    return "oil " + ", ".join(oils) + supply


def title_line(rotor, rotor_file, internal: str, options: dict | None, T_supply_K: float | None = None) -> str:
    """One line for a figure and stdout: rotor file, bearing files and bores, oil and supply
    temperature, internal with its options and files."""
    files = bearing_files(rotor_file)
    each = [(Path(files[k]).name if k < len(files) else "?", p.geometry.describe()) for k, p in enumerate(rotor.bearings)]
    if len(set(each)) == 1:  # every bearing alike: said once
        bearings = f"bearing {each[0][0]} ({each[0][1]})"
    else:  # which bearing is which, by node
        bearings = "bearings " + ", ".join(f"at node {n + 1} {f} ({b})" for n, (f, b) in zip(rotor.bearing_nodes, each))
    rotor_words = f"rotor {rotor.name} ({Path(rotor_file).name})" if rotor.name else f"rotor {Path(rotor_file).name}"
    return (f"{rotor_words}; {bearings}; "
            f"{oil_words(rotor, T_supply_K)}; internal {internal_words(internal, options)}")


def scene_line(scene, rotor=None) -> str:
    """``title_line`` of a scene (``rotor``: the scene's Rotor when the caller has read it)."""
    if rotor is None:
        from ..model.rotor import Rotor

        rotor = Rotor.from_toml(scene.rotor_path)
    return title_line(rotor, scene.rotor_path, scene.internal, scene.internal_options(), scene.supply_temperature_K)


def run_inputs(npz) -> str:
    """The inputs line a run's json record beside its .npz keeps (``analyses.computed_for``); '' for a
    run without one (recorded before it was kept, or the json gone)."""
    import json

    try:
        return str(json.loads(Path(npz).with_suffix(".json").read_text()).get("inputs", ""))
    except (OSError, ValueError, AttributeError):
        return ""


def wrapped(line: str, width: int = 120) -> str:
    """A long inputs line broken into lines of at most ``width`` characters (a figure's title)."""
    import textwrap

    return "\n".join(textwrap.wrap(line, width))


__all__ = ["bearing_files", "bearing_lines", "internal_words", "oil_words", "title_line", "scene_line", "run_inputs", "wrapped"]
