"""The options several ``rotor-host`` commands share (a scene's overrides, the internals' file flags,
the linearised rotor's options) and how a command hands its parsed values to the package."""

from __future__ import annotations

import inspect
from pathlib import Path

from bearing_fmu.io.cliargs import existing_file, finite_float, grid, node_load, output_dir, positive_float, unbalance
from bearing_fmu.io.bundled import bundled_or_file  # a file, or a bundled one by name (both command lines)


# ----------------------------------------------------------------------------- shared options

def internal_choices() -> tuple[str, ...]:
    """Every registered internal (also those a plug-in registered before the parser is made)."""
    from bearing_fmu.internals.registry import names

    return names()


def file_flags(p, what: str = "over the scene's", defaults: dict | None = None, note: str = "",
                only=None) -> None:
    """One ``--<option> FILE`` flag per file option of the registry (--surrogate, --map, ...);
    ``defaults``: option -> its default file, named in that option's help (none: ``what`` the scene's);
    ``only``: the internals the command takes (their options only)."""
    from ..bundled import KINDS
    from ..scenes.overrides import file_options

    for internal, option in file_options():
        if only is not None and internal not in only:
            continue
        if defaults is None:
            where = f"{what} [{internal}] {option}"
        elif option in defaults:
            where = f"default: {Path(defaults[option]).stem}, bundled{note}"
        else:
            where = "no default: needed with --internal " + internal
        p.add_argument(f"--{option}", type=bundled_or_file(option) if option in KINDS else existing_file, metavar="FILE",
                       help=f"the {internal} internal's {option} file ({where})")


def bearing_swap(text: str) -> tuple[str, str]:
    """An argparse type: ``FILE`` (every bearing) or ``NAME=FILE`` (the [[bearings]] entry of that
    name or 1-based node); FILE a bearing file or a bundled bearing by name."""
    from ..scenes.overrides import ALL_BEARINGS

    which, sep, file = text.rpartition("=")
    return (which if sep and which else ALL_BEARINGS), bundled_or_file("bearing")(file)


def file_args(args) -> dict:
    from ..scenes.overrides import file_options

    return {o: getattr(args, o) for _, o in file_options() if getattr(args, o, None) is not None}


def scene_flags(p, *, tangent: bool = False, checkpoint: bool = False) -> None:
    """The options that change a scene (``SceneOverrides``)."""
    from ..integrate.forces import NEWTON_TANGENTS

    p.add_argument("--internal", choices=internal_choices(), help="override the scene's internal")
    p.add_argument("--via", choices=("fmu", "direct"), help="the bearings via bearing FMUs through fmpy, or via internals in-process")
    p.add_argument("--native", action="store_true",
                   help="through native bearing FMUs (the internal compiled to C, no Python in the FMU; built with "
                        "the C compiler): the scene key fmu_kind = \"native\"")
    file_flags(p)
    p.add_argument("--bearing", type=bearing_swap, action="append", default=[], metavar="[NAME=]FILE",
                   help="a bearing file (or a bundled bearing by name, e.g. bearing_paper_2groove) in place of the "
                        "rotor file's: FILE for every bearing, NAME=FILE for the [[bearings]] entry of that name or "
                        "1-based node (repeat for several); the rotor file with it is written to the output folder")
    p.add_argument("--supply-c", type=finite_float("C"), metavar="C",
                   help="oil supply temperature [C] over the scene's supply_temperature_C: every bearing at its "
                        "film's effective temperature (each needs an [oil] table covering it; docs/thermal.md)")
    p.add_argument("--t-end", type=positive_float("s"), help="override the end time [s]")
    p.add_argument("--dt", type=positive_float("s"), help="override the time step [s]")
    if tangent:
        p.add_argument("--tangent", choices=NEWTON_TANGENTS,
                       help="Newton tangent of the bearing forces (default: the scene's, normally 'bearing': "
                            "the FMUs' own stiffness and damping outputs; 'frozen': those at the static "
                            "equilibrium; 'fd': finite differences; 'linear': the rotor's without bearings)")
    if checkpoint:
        p.add_argument("--checkpoint-s", type=positive_float("s"),
                       help="write the partial result every this many seconds of wall time (default: the "
                            "scene's [record] checkpoint_s, 60)")


def scene_from_args(args):
    """The scene file of ``args.scene`` with the command line's changes (``SceneOverrides``)."""
    from ..scenes.overrides import SceneOverrides, load_with_overrides

    ov = SceneOverrides(internal=getattr(args, "internal", None), via=getattr(args, "via", None),
                        native=getattr(args, "native", False), t_end_s=getattr(args, "t_end", None),
                        dt_s=getattr(args, "dt", None), newton_tangent=getattr(args, "tangent", None),
                        checkpoint_s=getattr(args, "checkpoint_s", None), files=file_args(args),
                        supply_c=getattr(args, "supply_c", None), bearings=dict(getattr(args, "bearing", None) or ()),
                        folder=getattr(args, "out", None))
    return load_with_overrides(args.scene, ov)


def call(fn, args, **values):
    """``fn`` with its keyword parameters taken from ``values``, else from ``args`` by name."""
    kw = {}
    for name in inspect.signature(fn).parameters:
        if name in values:
            kw[name] = values[name]
        elif hasattr(args, name):
            kw[name] = getattr(args, name)
    return fn(**kw)


# ----------------------------------------------------------------------------- commands


def module_command(module: str):
    """The handler of a command whose options are the parameters of ``analyses.<module>.command``."""
    def handler(args) -> int:
        import importlib

        return call(importlib.import_module(f"rotor_host.analyses.{module}").command, args)

    return handler




def linear_rotor_flags(p) -> None:
    """The options of a command on the linearised rotor: internal, its files and grid, static loads, oil."""
    from bearing_fmu.internals.registry import having

    from ..analyses.linear.inputs import DEFAULT_FILES

    p.add_argument("--internal", choices=having(any_state=True), default="reynolds",
                   help="bearing internal, one valid at every speed and load: " + ", ".join(having(any_state=True))
                        + " (default reynolds)")
    file_flags(p, defaults=DEFAULT_FILES, note=", the paper bearing's", only=having(any_state=True))
    p.add_argument("--grid", type=grid, metavar="NxM", help="Reynolds grid n_theta x n_x (default: the solver's)")
    p.add_argument("--static-load", type=node_load, nargs="+", action="extend", default=[], metavar="NODE:FY:FZ",
                   help="static point loads [N] on 1-based nodes, besides the weight")
    p.add_argument("--supply-c", type=finite_float("C"), default=None, metavar="C",
                   help="oil supply temperature [C]: each bearing at its film's effective temperature per speed")


def rotor_argument(p, what: str = "rotor TOML file, or a bundled rotor by name (e.g. rotor_paper)") -> None:
    """The rotor file a command on the linearised rotor reads (or a bundled rotor by name)."""
    p.add_argument("rotor", type=bundled_or_file("rotor"), help=what)


def unbalance_option(p, what: str = "an unbalance on a 1-based node; repeat for several") -> None:
    """The unbalances (required, repeatable) of a response."""
    p.add_argument("--unbalance", type=unbalance, action="append", required=True,
                   metavar="NODE:MASS_G:RADIUS_MM[:PHASE_DEG]", help=what)


def gas_density_option(p) -> None:
    """API 617's average gas density for its Level I screening chart."""
    p.add_argument("--gas-density-kg-m3", type=positive_float("kg/m^3"), metavar="RHO",
                   help="average gas density (suction and discharge) [kg/m^3] for API 617's screening chart when "
                        "2 <= Q_0 / Q_A <= 10")


def output_options(p, what: str, *, default: str | None = "out") -> None:
    """``--out`` (``what`` it holds; required when ``default`` is None) and ``--no-plots``."""
    p.add_argument("--out", type=output_dir, required=default is None, default=default, help=what)
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")

