"""``rotor-host``: run scenes, compare internals, run the paper's main job, fit scene-trained surrogates,
find a rotor's stability threshold (Campbell diagram), sweep a scene over speeds or unbalances on Dask.

Every option of every command is parsed here, and nowhere else: each command hands plain values
(or a ``SceneOverrides``) to a function of the package (``rotor_host.analyses.*.command``,
``report.run_and_report``, ``compare.compare``), which a script may call the same way."""

from __future__ import annotations

import argparse
import inspect
import sys
from pathlib import Path

from bearing_fmu.io.cliargs import (existing_dir, existing_file, finite_float, float_range, grid,
                                    grid_or_default, int_at_least, interval, node_load, nonneg_float, number,
                                    output_dir, output_file, positive_float, positive_int, unbalance)
from bearing_fmu.cli import Parser, add_debug_flag
from bearing_fmu.io.exits import EXIT_CODES, run_command
from bearing_fmu.internals.warmup import announce_compiling



from bearing_fmu.io.bundled import bundled_or_file  # a file, or a bundled one by name (both command lines)


# ----------------------------------------------------------------------------- shared options

def internal_choices() -> tuple[str, ...]:
    """Every registered internal (also those a plug-in registered before the parser is made)."""
    from bearing_fmu.internals.registry import names

    return names()


def _file_flags(p, what: str = "over the scene's", defaults: dict | None = None, note: str = "",
                only=None) -> None:
    """One ``--<option> FILE`` flag per file option of the registry (--surrogate, --map, ...);
    ``defaults``: option -> its default file, named in that option's help (none: ``what`` the scene's);
    ``only``: the internals the command takes (their options only)."""
    from .bundled import KINDS
    from .scenes.overrides import file_options

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
    from .scenes.overrides import ALL_BEARINGS

    which, sep, file = text.rpartition("=")
    return (which if sep and which else ALL_BEARINGS), bundled_or_file("bearing")(file)


def _files(args) -> dict:
    from .scenes.overrides import file_options

    return {o: getattr(args, o) for _, o in file_options() if getattr(args, o, None) is not None}


def _scene_flags(p, *, tangent: bool = False, checkpoint: bool = False) -> None:
    """The options that change a scene (``SceneOverrides``)."""
    from .integrate.forces import NEWTON_TANGENTS

    p.add_argument("--internal", choices=internal_choices(), help="override the scene's internal")
    p.add_argument("--via", choices=("fmu", "direct"), help="the bearings via bearing FMUs through fmpy, or via internals in-process")
    p.add_argument("--native", action="store_true",
                   help="through native bearing FMUs (the internal compiled to C, no Python in the FMU; built with "
                        "the C compiler): the scene key fmu_kind = \"native\"")
    _file_flags(p)
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
    from .scenes.overrides import SceneOverrides, load_with_overrides

    ov = SceneOverrides(internal=getattr(args, "internal", None), via=getattr(args, "via", None),
                        native=getattr(args, "native", False), t_end_s=getattr(args, "t_end", None),
                        dt_s=getattr(args, "dt", None), newton_tangent=getattr(args, "tangent", None),
                        checkpoint_s=getattr(args, "checkpoint_s", None), files=_files(args),
                        supply_c=getattr(args, "supply_c", None), bearings=dict(getattr(args, "bearing", None) or ()),
                        folder=getattr(args, "out", None))
    return load_with_overrides(args.scene, ov)


def _call(fn, args, **values):
    """``fn`` with its keyword parameters taken from ``values``, else from ``args`` by name."""
    kw = {}
    for name in inspect.signature(fn).parameters:
        if name in values:
            kw[name] = values[name]
        elif hasattr(args, name):
            kw[name] = getattr(args, name)
    return fn(**kw)


# ----------------------------------------------------------------------------- commands

def _run(args) -> int:
    from .analyses.report import run_and_report

    return run_and_report(scene_from_args(args), args.out, progress=not args.quiet, plots=not args.no_plots)


def _compare(args) -> int:
    from .analyses.compare import compare, print_table, reference_and_variants

    scene = scene_from_args(args)
    ref, variants = reference_and_variants(scene, args.out, ref_grid=args.ref_grid, grids=args.grids,
                                           orders=args.orders, maps=args.maps, internals=args.internals)
    rows = compare(scene, ref, variants, Path(args.out), progress=not args.quiet,
                   default_label="Reynolds default grid")
    print(print_table(rows))
    print(f"wrote {Path(args.out)}/compare_{Path(scene.source).stem}.md/.json/.png")
    return 0


def _paper(args) -> int:
    from .analyses.compare import paper_job

    print(paper_job(args.scenes, args.out, t_end=args.t_end, progress=not args.quiet))
    print(f"tables and plots in {args.out}/ (compare_*.md, compare_*_orbits.png, compare_*_error_vs_time.png)")
    return 0


def _fit(args) -> int:
    from bearing_fmu.cli import recipe_from_args

    from .analyses import training

    if not args.scenes:
        raise ValueError("--scene: give at least one training scene (rotor_host/bundled/scenes/*.toml)")
    return _call(training.command, args, recipe=recipe_from_args(args, "scene"))


def _stability(args) -> int:
    from .analyses.linear import stability

    return _call(stability.command, args, rotor_file=args.rotor, data_files=_files(args))


def _response(args) -> int:
    from .analyses.response import unbalance

    return _call(unbalance.command, args, rotor_file=args.rotor, data_files=_files(args))


def _ucs(args) -> int:
    from .analyses.response import ucs

    return _call(ucs.command, args, rotor_file=args.rotor, data_files=_files(args))


def _level1(args) -> int:
    from .analyses.response import level1

    return _call(level1.command, args, rotor_file=args.rotor, data_files=_files(args))


def _api_report(args) -> int:
    from .analyses.response import api_report

    return _call(api_report.command, args, rotor_file=args.rotor, data_files=_files(args))


def _linear_vs_runup(args) -> int:
    from .analyses.response import runup

    return _call(runup.command, args, scene=scene_from_args(args))


def _sweep(args) -> int:
    from .analyses import sweep
    from .analyses.computed_for import scene_line

    scene = scene_from_args(args)
    print(f"computed for: {scene_line(scene)}")
    return _call(sweep.command, args, scene=scene)


def _module_command(module: str):
    """The handler of a command whose options are the parameters of ``analyses.<module>.command``."""
    def handler(args) -> int:
        import importlib

        return _call(importlib.import_module(f".analyses.{module}", __package__).command, args)

    return handler


# ----------------------------------------------------------------------------- the parser

def _add_run(sub) -> None:
    p = sub.add_parser("run", help="run one scene and write results and plots")
    p.add_argument("scene", type=bundled_or_file("scene"), help="scene TOML file, or a bundled scene by name (e.g. paper_22hz)")
    _scene_flags(p, tangent=True, checkpoint=True)
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out)")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)


def _add_compare(sub) -> None:
    p = sub.add_parser("compare", help="error against run time of Reynolds grids, Taylor orders and the linear model")
    p.add_argument("scene", type=bundled_or_file("scene"), help="scene TOML file, or a bundled scene by name (e.g. paper_22hz)")
    p.add_argument("--via", choices=("fmu", "direct"), help="the bearings via FMUs through fmpy (the scene's default) or via internals in-process")
    p.add_argument("--ref-grid", type=grid_or_default, default="256x32", metavar="NxM",
                   help="reference Reynolds grid n_theta x n_x (default 256x32; '' = the default grid is the "
                        "reference)")
    p.add_argument("--grids", nargs="*", type=grid, default=[(64, 8)], metavar="NxM",
                   help="coarser Reynolds grids to compare (default 64x8)")
    p.add_argument("--orders", nargs="*", type=positive_int(), default=[1, 3, 5, 7],
                   help="Taylor orders (default 1 3 5 7)")
    p.add_argument("--maps", nargs="*", type=bundled_or_file("map"), default=None, metavar="FILE",
                   help="force map files to compare, e.g. several resolutions (default: the scene's [map] map; "
                        "'--maps' with none: no map variant)")
    p.add_argument("--internals", nargs="+", choices=internal_choices(), default=None, metavar="NAME",
                   help="instead of the grids, orders and maps: one variant per named internal, with the scene's "
                        f"options for it (any of {', '.join(internal_choices())})")
    p.add_argument("--t-end", type=positive_float("s"), help="override the end time [s]")
    p.add_argument("--dt", type=positive_float("s"), help="override the time step [s]")
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_compare)


def _add_paper(sub) -> None:
    p = sub.add_parser("paper", help="main job: the paper's 22 Hz and 44 Hz scenes, Reynolds vs map vs Taylor vs "
                                     "linear through the bearing FMUs, error/run-time table and plots")
    from .bundled import folder

    p.add_argument("--scenes", type=existing_dir, default=str(folder() / "scenes"),
                   help="folder with paper_22hz.toml and paper_44hz.toml (default: the bundled scenes)")
    p.add_argument("--t-end", type=positive_float("s"), help="override the simulated time of both scenes [s]")
    p.add_argument("--out", type=output_dir, default="out/paper", help="output folder (default: out/paper)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_paper)


def _add_fit(sub) -> None:
    from bearing_fmu.cli import add_output_arguments, add_recipe_arguments

    p = sub.add_parser("fit", help="fit a bearing's Taylor surrogate to the Reynolds series of scenes (the paper's way) "
                                   "and write its JSON file, report and lambda plots")
    add_recipe_arguments(p, "scene")
    p.add_argument("--cache-dir", type=output_dir, default=None,
                   help="folder caching the Reynolds series (default: series/ beside --output)")
    add_output_arguments(p)
    p.set_defaults(func=_fit)


def _add_dt_study(sub) -> None:
    p = sub.add_parser("dt-study", help="halve dt until the bearing orbit changes by less than 1 %% CR")
    p.add_argument("scene", type=bundled_or_file("scene"), help="scene TOML file, or a bundled scene by name (e.g. paper_22hz)")
    p.add_argument("--internal", choices=internal_choices(), default="reynolds",
                   help="the bearing internal (default reynolds)")
    p.add_argument("--dt", type=positive_float("s"), help="first time step [s] (default: the scene's)")
    p.add_argument("--t-end", type=positive_float("s"), help="simulated time [s] (default: the scene's)")
    p.add_argument("--halvings", type=positive_int(), default=3,
                   help="at most this many halvings, at least 1 (default 3)")
    p.add_argument("--tol", type=positive_float("% CR"), default=1.0,
                   help="orbit change that counts as converged [%% CR] (default 1)")
    p.add_argument("--out", type=output_dir, default="out",
                   help="output folder for dtstudy_<scene>_<internal>.md/.json")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_module_command("dt_study"))


def _add_waterfall(sub) -> None:
    from .analyses.waterfall import DEFAULT_WINDOW_S

    p = sub.add_parser("waterfall", help="response spectra against speed of a run-up or coast-down run "
                                         "(a scene with [speed_profile]), with 1x and 0.5x lines and orbits")
    p.add_argument("run", type=existing_file, help="a run's .npz (rotor-host run of a scene with a [speed_profile])")
    p.add_argument("--nodes", nargs="+", type=positive_int(), default=None,
                   help="recorded nodes to show (default: the first bearing and the recorded node with the "
                        "largest whirl)")
    p.add_argument("--window-s", type=positive_float("s"), default=DEFAULT_WINDOW_S,
                   help=f"spectrum window [s] (default {DEFAULT_WINDOW_S}; resolution 1/window)")
    p.add_argument("--orbits-at-hz", nargs="*", type=positive_float("Hz"), default=None,
                   help="speeds whose orbits are drawn, inside the run's speeds (default: start, 1x peak, end)")
    p.add_argument("-o", "--output", type=output_file, default=None,
                   help="PNG to write (default: beside the run, _waterfall.png)")
    p.set_defaults(func=_module_command("waterfall"))


def _add_limit_cycle(sub) -> None:
    p = sub.add_parser("limit-cycle", help="envelope of the bearing eccentricity: does the whirl settle and hold?")
    p.add_argument("source", type=bundled_or_file("scene"), help="scene TOML file or bundled scene (run it, called directly) or a saved run "
                   ".npz (then give --speed-hz)")
    p.add_argument("--internal", choices=internal_choices(), default="reynolds",
                   help="the bearing internal (default reynolds)")
    p.add_argument("--dt", type=positive_float("s"), help="time step [s] (default: the scene's)")
    p.add_argument("--t-end", type=positive_float("s"), help="simulated time [s] (default: the scene's)")
    p.add_argument("--speed-hz", type=positive_float("Hz"), help="shaft speed for a .npz source [Hz]")
    p.add_argument("--revs", type=positive_int(), default=2, help="window length in shaft revolutions (default 2: "
                   "one period of a half-speed whirl)")
    p.add_argument("--tol", type=positive_float("% CR"), default=1.0,
                   help="settling band half-width [%% CR] (default 1)")
    p.add_argument("--hold", type=nonneg_float("s"), default=1.0, help="the limit cycle counts as held when settled "
                   "this long before the end, without a trend across the band [s] (default 1; exit status 1 "
                   "otherwise)")
    p.add_argument("--rel-tol", type=positive_float("%"), default=10.0,
                   help="largest trend of the whirl's size over the last half of the run, in %% of that size, for "
                        "a held limit cycle (default 10): a whirl dying away slowly inside the band is not one")
    p.add_argument("--out", type=output_dir, default="out", help="output folder for limitcycle_<name>.md/.json/.png")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_module_command("limit_cycle"))


def _add_stability(sub) -> None:
    from bearing_fmu.internals.registry import having

    from .analyses.linear.modal import RANK_UP_TO
    from .analyses.linear.stability import DEFAULT_FILES, DEFAULT_MODES

    p = sub.add_parser("stability", help="Campbell diagram and stability threshold: equilibrium, linearised "
                                         "bearings and damped modes at each speed of a range")
    p.add_argument("rotor", type=bundled_or_file("rotor"), help="rotor TOML file, or a bundled rotor by name (e.g. rotor_paper)")
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz], both ends included (e.g. 10:70:1)")
    p.add_argument("--internal", choices=having(any_state=True), default="reynolds",
                   help="bearing internal, one valid at every speed and load: " + ", ".join(having(any_state=True))
                        + " (default reynolds)")
    _file_flags(p, defaults=DEFAULT_FILES, note=", the paper bearing's; build one with `bearing-fmu map`",
                only=having(any_state=True))
    p.add_argument("--grid", type=grid, metavar="NxM", help="Reynolds grid n_theta x n_x (default: the solver's, "
                                                           "128x16)")
    p.add_argument("--static-load", type=node_load, nargs="+", action="extend", default=[], metavar="NODE:FY:FZ",
                   help="static point loads [N] on 1-based nodes, besides the weight (applied as in a scene)")
    p.add_argument("--modes", type=positive_int(), default=DEFAULT_MODES,
                   help=f"lowest modes shown in the Campbell diagram and the json (default {DEFAULT_MODES}; the "
                        "threshold and the critical speeds look at every mode)")
    p.add_argument("--rank-up-to", type=number("x the top speed", 1.0), default=RANK_UP_TO, metavar="MULTIPLE",
                   help=f"rank the least stable mode among the modes up to this multiple of the top speed (default "
                        f"{RANK_UP_TO:g}: every whirl and every mode a 1x or 2x force drives; the modes above are "
                        "reported in one line)")
    p.add_argument("--supply-c", type=finite_float("C"), default=None, metavar="C",
                   help="oil supply temperature [C]: every bearing (each needs an [oil] table) at the viscosity of its "
                        "film's effective temperature at each speed (docs/thermal.md); default: isoviscous bearings")
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out) for "
                   "stability_<rotor>_<internal>.md/.json and _campbell/_logdec/_mode.png")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_stability)


def _linear_rotor_flags(p) -> None:
    """The options of a command on the linearised rotor: internal, its files and grid, static loads, oil."""
    from bearing_fmu.internals.registry import having

    from .analyses.linear.stability import DEFAULT_FILES

    p.add_argument("--internal", choices=having(any_state=True), default="reynolds",
                   help="bearing internal, one valid at every speed and load: " + ", ".join(having(any_state=True))
                        + " (default reynolds)")
    _file_flags(p, defaults=DEFAULT_FILES, note=", the paper bearing's", only=having(any_state=True))
    p.add_argument("--grid", type=grid, metavar="NxM", help="Reynolds grid n_theta x n_x (default: the solver's)")
    p.add_argument("--static-load", type=node_load, nargs="+", action="extend", default=[], metavar="NODE:FY:FZ",
                   help="static point loads [N] on 1-based nodes, besides the weight")
    p.add_argument("--supply-c", type=finite_float("C"), default=None, metavar="C",
                   help="oil supply temperature [C]: each bearing at its film's effective temperature per speed")


def _add_response(sub) -> None:
    p = sub.add_parser("response", help="unbalance response of the linearised rotor: Bode and polar plots, peaks "
                                        "with their amplification factor and API separation margins")
    p.add_argument("rotor", type=bundled_or_file("rotor"), help="rotor TOML file, or a bundled rotor by name (e.g. rotor_paper)")
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz], both ends included; every one is computed and kept")
    p.add_argument("--unbalance", type=unbalance, action="append", required=True,
                   metavar="NODE:MASS_G:RADIUS_MM[:PHASE_DEG]",
                   help="an unbalance on a 1-based node (phase from +y toward +z, default 0); repeat for several")
    p.add_argument("--operating-hz", type=interval("Hz"), metavar="MIN:MAX",
                   help="operating speed range [Hz]: separation margins and API 617's required margins")
    p.add_argument("--probe", type=positive_int(), nargs="+", metavar="NODE",
                   help="probe nodes (1-based) for the peaks and plots (default: the bearings' and disks' nodes)")
    _linear_rotor_flags(p)
    p.add_argument("--out", type=output_dir, required=True,
                   help="output folder: response.json, response.md, bode_node<N>.png, polar_node<N>.png")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_response)


def _add_ucs(sub) -> None:
    from .analyses.response.ucs import DEFAULT_CRITICALS, DEFAULT_POINTS, DEFAULT_SPEEDS_HZ, DEFAULT_STIFFNESS

    p = sub.add_parser("ucs", help="undamped critical speed map against support stiffness, the bearings' stiffness "
                                   "at speed overlaid, the mode shapes of the first criticals")
    p.add_argument("rotor", type=bundled_or_file("rotor"), help="rotor TOML file, or a bundled rotor by name (e.g. rotor_paper)")
    p.add_argument("--stiffness-n-m", type=interval("N/m"), default=DEFAULT_STIFFNESS, metavar="MIN:MAX",
                   help=f"support stiffness range [N/m] (default {DEFAULT_STIFFNESS[0]:g}:{DEFAULT_STIFFNESS[1]:g})")
    p.add_argument("--points", type=int_at_least(2), default=DEFAULT_POINTS,
                   help=f"stiffness values, log-spaced (default {DEFAULT_POINTS})")
    p.add_argument("--criticals", type=positive_int(), default=DEFAULT_CRITICALS,
                   help=f"lowest forward criticals drawn (default {DEFAULT_CRITICALS})")
    a, b, step = DEFAULT_SPEEDS_HZ
    p.add_argument("--speeds-hz", type=float_range("Hz"), metavar="START:STOP:STEP",
                   help=f"speeds of the bearings' stiffness overlay (default {a:g}:{b:g}:{step:g})")
    _linear_rotor_flags(p)
    p.add_argument("--out", type=output_dir, default="out", help="output folder: ucs.json, ucs.md, ucs_map.png, "
                                                                 "ucs_modes.png")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_ucs)


def _add_level1(sub) -> None:
    from .analyses.response.level1 import DEFAULT_POINTS

    p = sub.add_parser("level1", help="API 617 Level I stability: log decrement of the first forward mode against "
                                      "the stages' cross-coupling, Q_A, Q_0 and the verdict")
    p.add_argument("rotor", type=bundled_or_file("rotor"), help="rotor TOML file with a [[stages]] table (or a bundled rotor by name)")
    p.add_argument("--operating-hz", type=interval("Hz"), required=True, metavar="MIN:MAX",
                   help="operating speed range [Hz]; the check runs at the maximum continuous speed MAX")
    p.add_argument("--points", type=int_at_least(2), default=DEFAULT_POINTS,
                   help=f"cross-coupling values drawn (default {DEFAULT_POINTS})")
    p.add_argument("--gas-density-kg-m3", type=positive_float("kg/m^3"), metavar="RHO",
                   help="average gas density (suction and discharge) [kg/m^3] for API 617's screening chart when "
                        "2 <= Q_0 / Q_A <= 10")
    _linear_rotor_flags(p)
    p.add_argument("--out", type=output_dir, default="out", help="output folder: level1.json, level1.md, level1.png")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_level1)


def _add_api_report(sub) -> None:
    p = sub.add_parser("api-report", help="one markdown report: Campbell diagram and threshold, unbalance response "
                                          "with AF and API margins, critical speed map, API 617 Level I")
    p.add_argument("rotor", type=bundled_or_file("rotor"), help="rotor TOML file, or a bundled rotor by name (e.g. rotor_paper)")
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz] of the Campbell diagram and the response, both ends included")
    p.add_argument("--unbalance", type=unbalance, action="append", required=True,
                   metavar="NODE:MASS_G:RADIUS_MM[:PHASE_DEG]", help="an unbalance on a 1-based node; repeat for several")
    p.add_argument("--operating-hz", type=interval("Hz"), required=True, metavar="MIN:MAX",
                   help="operating speed range [Hz] (margins; Level I at MAX)")
    p.add_argument("--probe", type=positive_int(), nargs="+", metavar="NODE",
                   help="probe nodes (default: the bearings' and disks' nodes)")
    p.add_argument("--gas-density-kg-m3", type=positive_float("kg/m^3"), metavar="RHO",
                   help="average gas density (suction and discharge) [kg/m^3] for API 617's screening chart when "
                        "2 <= Q_0 / Q_A <= 10")
    _linear_rotor_flags(p)
    p.add_argument("--out", type=output_dir, required=True, help="output folder: api_report.md, its json and figures")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_api_report)


def _add_linear_vs_runup(sub) -> None:
    from .analyses.response.runup import DEFAULT_SCALES

    p = sub.add_parser("linear-vs-runup", help="the linear unbalance response against the same unbalance in a run-up "
                                               "through the nonlinear bearing force, at a small and a large unbalance")
    p.add_argument("scene", type=bundled_or_file("scene"), help="a run-up scene file, or a bundled one by name (e.g. paper_runup_10_60hz)")
    p.add_argument("--scale", type=positive_float(), nargs="+", default=list(DEFAULT_SCALES), metavar="F",
                   help="factors on the scene's unbalance masses, one run each (default "
                        f"{' '.join(f'{f:g}' for f in DEFAULT_SCALES)})")
    p.add_argument("--window-s", type=positive_float("s"), help="the waterfall's window [s] (default 0.25)")
    _scene_flags(p)
    p.add_argument("--out", type=output_dir, default="out", help="output folder: linear_vs_runup.json/.md, "
                                                                 "linear_vs_runup_node<N>.png and the runs")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_linear_vs_runup)


def _add_sweep(sub) -> None:
    from bearing_fmu.parallel.cluster import scheduler_address

    p = sub.add_parser("sweep", help="run a scene at many speeds or unbalances in parallel on Dask: summary table "
                                     "and bifurcation diagram")
    p.add_argument("scene", type=bundled_or_file("scene"), help="scene TOML file, or a bundled scene by name (e.g. paper_22hz)")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--speeds-hz", nargs="+", type=float_range("Hz", 0.0), metavar="F|START:STOP:STEP",
                      help="shaft speeds [Hz]: numbers and ranges, e.g. 10:60:2.5 (both ends included)")
    what.add_argument("--unbalance-g", nargs="+", type=float_range("g", 0.0, exclusive_minimum=False),
                      metavar="M|START:STOP:STEP",
                      help="masses [g] of the scene's first [[unbalance]] (at its radius and the scene's speed)")
    _scene_flags(p)
    p.add_argument("--settle-s", type=nonneg_float("s"),
                   help="the transient ends here: the summary and diagram use t >= this [s] (default: half the run)")
    p.add_argument("--scheduler", type=scheduler_address, metavar="ADDRESS",
                   help="a running Dask scheduler (e.g. tcp://10.0.0.5:8786, or its scheduler file) whose workers run "
                        "the sweep; default: one left running for later commands (DASK_SCHEDULER_ADDRESS or the "
                        "scheduler file in the user's cache: docs/sweep.md), else this machine")
    p.add_argument("--workers", type=positive_int(), help="worker processes on this machine (default: the cores)")
    p.add_argument("--execution", choices=("auto", "inline", "pool", "cluster"), default="auto",
                   help="execution: where the runs run: auto (default: a running cluster, else this process for one worker, "
                        "else a pool of warm processes), inline (this process), pool, cluster (a Dask LocalCluster "
                        "started for the sweep, or --scheduler's)")
    p.add_argument("--out", type=output_dir, default="out/sweep", help="output folder (default: out/sweep)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_sweep)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="rotor-host", description=__doc__, epilog=EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    for add in (_add_run, _add_compare, _add_paper, _add_fit, _add_dt_study, _add_waterfall, _add_limit_cycle,
                _add_stability, _add_sweep, _add_response, _add_ucs,
                _add_level1, _add_api_report, _add_linear_vs_runup):
        add(sub)
    add_debug_flag(parser, sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    announce_compiling()  # an installation's first compilation of a kernel: one line on stderr
    return run_command("rotor-host", args)  # exit codes, interrupts, --debug: bearing_fmu.io.exits


if __name__ == "__main__":
    sys.exit(main())
