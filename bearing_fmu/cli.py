"""``bearing-fmu``: the bearing's command line (demo, fit, build, map). Every option of these commands
is parsed here (the fit options generated from the FitRecipe fields); ``rotor-host fit`` takes
the recipe options from here too."""

from __future__ import annotations

import argparse
import sys

from .internals.warmup import announce_compiling
from .io.exits import EXIT_CODES, run_command

SCENE_FIT = "rotor-host fit --scene SCENE [--scene ...] [--test-scene SCENE] [--bearing-number N] ..."


def add_debug_flag(parser, subparsers=None) -> None:
    """``--debug`` before or after the subcommand (a subparser's own default must not
    overwrite the main parser's value, hence SUPPRESS there); both command lines use it."""
    help_ = "show the Python traceback of an error"
    parser.add_argument("--debug", action="store_true", help=help_)
    for p in (subparsers.choices.values() if subparsers is not None else ()):
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=help_)


# ----------------------------------------------------------------------------- fit options

def add_recipe_arguments(parser: argparse.ArgumentParser, group: str) -> argparse.ArgumentParser:
    """Options for the FitRecipe fields of ``group`` ('designed': ``bearing-fmu fit``, 'scene':
    ``rotor-host fit``) and the shared ones, generated from the fields."""
    from .fitting.recipe import command_line_options

    for flag, kw in command_line_options(group):
        parser.add_argument(flag, **kw)
    return parser


def recipe_from_args(args: argparse.Namespace, group: str):
    """The FitRecipe of parsed options; a value outside its range is refused naming the option."""
    from .fitting.recipe import recipe_from_values

    return recipe_from_values(vars(args), group)


def add_output_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """The options of both fit commands that are not fit settings: output, plots, note."""
    from .io.cliargs import output_dir, output_file

    parser.add_argument("--plots", type=output_dir, default=None, help="directory for the lambda plots")
    parser.add_argument("--note", default=None, help="free text stored in the file's provenance")
    parser.add_argument("-o", "--output", type=output_file, required=True, help="surrogate JSON file to write")
    return parser


class _Moved(argparse.Action):
    """An option of scene-trained fitting, which moved to ``rotor-host fit``."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error(f"{option_string}: scene-trained fitting is the host's command now (the bearing side never "
                     f"runs a rotor): {SCENE_FIT}")


def add_fit_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Arguments of ``bearing-fmu fit``."""
    from .fitting.recipe import option_name, recipe_fields
    from .io.bundled import bundled_or_file

    add_recipe_arguments(parser, "designed")
    moved = [option_name(f) for f in recipe_fields("scene") if f.metadata["group"] == "scene"] + ["--cache-dir"]
    for flag in moved:
        parser.add_argument(flag, nargs="*", action=_Moved, default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    parser.add_argument("--bearing", type=bundled_or_file("bearing"), default=None, metavar="FILE",
                        help="bearing TOML file, or a bundled bearing by name, to fit (default: the paper bearing, Table 2); its name and geometry "
                             "go into the report and the surrogate file")
    return add_output_arguments(parser)


def run_fit(args: argparse.Namespace) -> int:
    """``bearing-fmu fit`` of parsed options."""
    from .fitting.output import check_outputs, fit_designed

    check_outputs(args.output, args.plots)  # before the recipe: a bad output is named first
    return fit_designed(recipe_from_args(args, "designed"), output=args.output, bearing=args.bearing,
                        plots=args.plots, note=args.note)


# ----------------------------------------------------------------------------- commands


def _demo(args: argparse.Namespace) -> int:
    """Equilibrium, attitude, minimum film, Lund coefficients, friction, oil flow and the effective
    temperature of a bearing (the paper's by default) under a static load at one speed, from the
    Reynolds solver (``physics.operating.operating_point``); --json: the same record as JSON."""
    import json

    from .io.demo_text import print_operating_point
    from .physics.oil import KELVIN
    from .physics.operating import operating_point
    from .physics.params import PAPER_BEARING, BearingParams
    from .physics.solver.reynolds import DEFAULT_N_THETA, DEFAULT_N_X

    if args.bearing_file:  # the positional form: `bearing-fmu demo bearing_paper`
        if args.bearing:
            raise ValueError(f"give the bearing once: {args.bearing_file} or --bearing {args.bearing}")
        args.bearing = args.bearing_file
    params = BearingParams.from_toml(args.bearing) if args.bearing else PAPER_BEARING
    load = (args.load_y, -args.load if args.load is not None else args.load_z)
    if params.geometry.pads is not None:
        return _demo_pads(args, params, load)
    supply = None if args.supply_c is None else args.supply_c + KELVIN
    internal = _demo_internal(args, params, load)
    rec = operating_point(params, load, args.speed_hz, supply, internal=internal)
    if args.json:
        rec = {"bearing": str(args.bearing) if args.bearing else "paper Table 2", "internal": args.internal, **rec}
        print(json.dumps(rec, indent=2))
        return 0
    name = (f"{args.bearing}" if args.bearing else "Paper bearing (Table 2)")
    model = (f"Reynolds grid {DEFAULT_N_THETA} x {DEFAULT_N_X}, Swift-Stieber cavitation" if internal is None
             else f"internal {args.internal} ({args.surrogate or args.map or 'its defaults'})")
    print_operating_point(rec, params, load, args.speed_hz, name=name, model=model)
    return 0


def _demo_pads(args: argparse.Namespace, params, load) -> int:
    """demo of a tilting-pad bearing (``internals.tilting_pad.operating``): the record of the fixed
    bores (synchronously reduced K, C) with the pads' tilts, loads and full coefficients."""
    import json

    from .internals.tilting_pad.operating import operating_point
    from .io.demo_text import print_tilting_pads
    from .physics.oil import KELVIN

    for flag, value in (("--internal", args.internal != "reynolds"), ("--surrogate", args.surrogate),
                        ("--map", args.map)):
        if value:
            raise ValueError(f"{flag}: a tilting-pad bearing is computed by the tilting_pad internal (every pad by the "
                             "Reynolds solver); leave {flag} out".replace("{flag}", flag))
    rec = operating_point(params, load, args.speed_hz,
                          T_supply_K=None if args.supply_c is None else args.supply_c + KELVIN)
    if args.json:
        print(json.dumps({"bearing": str(args.bearing), "internal": "tilting_pad", **rec}, indent=2))
        return 0
    print_tilting_pads(rec, params, load, args.speed_hz, name=str(args.bearing))
    return 0


def _demo_internal(args: argparse.Namespace, params, load):
    """The internal of ``demo --internal NAME`` (None: the Reynolds solver on its default grid), its
    data file from --surrogate or --map; refused by name when it has no film report."""
    import math

    from .internals import registry

    if args.internal == "reynolds" and not (args.surrogate or args.map):
        return None
    spec = registry.get(args.internal)
    names = {o.name for o in spec.all_options()}
    options = {k: v for k, v in (("surrogate", args.surrogate), ("map", args.map)) if v}
    for key in set(options) - names:
        raise ValueError(f"--{key}: the {args.internal} internal takes no {key} file")
    internal = spec.create(params, options, registry.Context(load=load, omega=2.0 * math.pi * args.speed_hz),
                           where=f"--internal {args.internal}")
    why = registry.film_flow_of(spec, internal)
    if why:
        raise ValueError(f"--internal {args.internal}: demo reports the film's friction and flows, which it does not "
                         f"have ({why})")
    return internal


def _check_file_flags(given: dict) -> None:
    """Each file given to --surrogate or --map is a file of that option (its JSON "format"), else a
    ValueError naming the flag, the file and the flag that takes it (the FMU would bundle it under the
    option its content says and report the other option missing at run time)."""
    from .internals.registry import option_for_file

    for flag, files in given.items():
        for f in files:
            try:
                option = option_for_file(f)
            except ValueError as exc:
                raise ValueError(f"--{flag} {f}: {str(exc).removeprefix(f'{f}: ')}") from None
            if option.name != flag:
                raise ValueError(f"--{flag} {f}: the file is a {option.file_format} file, read by the option "
                                 f"{option.name}, not {flag}: give it with --{option.name}")


def _build(args: argparse.Namespace) -> int:
    from .fmu.build import build_fmu
    from .io.outputs import ensure_output_file

    _check_file_flags({"surrogate": args.surrogate or [], "map": args.map or []})
    if args.native:
        return _build_native(args)
    for flag, value in (("--internal", args.internal), ("--cmake", args.cmake or None),
                        ("--platforms", args.platforms), ("--compiler", args.compiler), ("--speed-hz", args.speed_hz)):
        if value is not None:
            raise ValueError(f"{flag} is an option of the native FMU: add --native (the Python FMU chooses its "
                             "internal by its parameter 'internal')")
    if args.fmi == 3:
        raise ValueError("--fmi 3 is an option of the native FMU: add --native (the Python FMU is FMI 2.0, as "
                         "pythonfmu writes it)")
    ensure_output_file(args.output, "-o/--output")
    bearing = None
    if args.bearing:
        from .physics.params import BearingParams

        bearing = BearingParams.from_toml(args.bearing)
    path = build_fmu(args.output, surrogate=[*(args.surrogate or []), *(args.map or [])] or None,
                     bearing=bearing, bearing_source=args.bearing or "")
    if bearing is not None:
        print(f"the FMU's default bearing: {args.bearing} (D {bearing.D * 1e3:g} mm, L {bearing.L * 1e3:g} mm, "
              f"CR {bearing.CR * 1e6:g} um, mu {bearing.mu:g} Pa s)")
    print(f"wrote {path}")
    return 0


def _build_native(args: argparse.Namespace) -> int:
    """``bearing-fmu build --native``: the internal compiled to C, one data file compiled in."""
    from .fmu.native.build import build_native_fmu
    from .io.outputs import ensure_output_file
    from .internals import registry
    from .physics.params import BearingParams

    given = {"surrogate": args.surrogate or [], "map": args.map or []}  # the build's file flags
    owners = {o.name: spec.name for spec in registry.REGISTRY.values() for o in spec.file_options()}
    native = registry.having(native=True)
    flags = [name for name, files in given.items() if files]
    internal = args.internal or (owners.get(flags[0]) if len(flags) == 1 else None)
    if internal is None:
        raise ValueError(f"--native needs --internal {'|'.join(native)} ("
                         + ", ".join(f"{owners[f]} with --{f} FILE" for f in given if f in owners) + ")")
    specs = [registry.get(p) for p in internal.split(",")]
    readable = {o.name for spec in specs for o in spec.all_options() if o.file}
    # a flag's file read by an option of another name (the tilting pads' pad_map takes a --map file): by its format
    formats = {o.name: o.file_format for spec in registry.REGISTRY.values() for o in spec.file_options()}
    renamed = {flag: o.name for flag in given for spec in specs for o in spec.file_options()
               if flag not in readable and o.name != flag and o.file_format == formats.get(flag)}
    readable |= set(renamed)
    bearing = BearingParams.from_toml(args.bearing) if args.bearing else None
    for o in (o for spec in specs for o in spec.file_options()):
        if o.required and not given.get(o.name):
            # a file the store keeps (a force map): the one built for this bearing, as run and stability take it
            from .internals.map.store import stored_file
            from .physics.params import PAPER_BEARING

            found, line = stored_file(o.file_format, [bearing or PAPER_BEARING])
            if found is None:
                raise ValueError(f"--native --internal {internal} needs --{o.name} FILE"
                                 + (f": {line}" if line else ""))
            print(f"--{o.name} not given: {line}")
            given[o.name] = [str(found)]
    for name, files in given.items():
        if len(files) > 1:
            raise ValueError("--native compiles one data file in: give --surrogate or --map once")
        if files and name not in readable:
            raise ValueError(f"--native --internal {internal} takes no --{name} (it reads "
                             f"{', '.join('--' + r for r in sorted(readable & set(given))) or 'no data file'})")
    options = {renamed.pop(flag): given.pop(flag)[0] for flag in list(renamed) if given[flag]}
    surrogates, maps = given.get("surrogate"), given.get("map")
    ensure_output_file(args.output, "-o/--output")
    path = build_native_fmu(args.output, internal, surrogate=surrogates[0] if surrogates else None,
                            map=maps[0] if maps else None, options=options or None, bearing=bearing,
                            bearing_source=args.bearing or "",
                            compiler=args.compiler or ("cmake" if args.cmake else None),
                            platforms=args.platforms.split(",") if args.platforms else None,
                            speed_hz=args.speed_hz, fmi_version=args.fmi)
    import zipfile

    folders = sorted({n.split("/")[1] for n in zipfile.ZipFile(path).namelist() if n.startswith("binaries/")})
    kind = f"{internal} internal{'s' if ',' in internal else ''}"
    print(f"wrote {path} (native FMU, FMI {args.fmi}.0, {kind}, Model Exchange and Co-Simulation, no Python; "
          f"binaries: {', '.join(folders)})")
    return 0


def _map(args: argparse.Namespace) -> int:
    """``bearing-fmu map``: tabulate the force map of a bearing's L/D (and bore) into the map store
    and, with -o, a file (``internals.map.build``)."""
    from .internals.map.build import command

    return command(bearing=args.bearing, output=args.output, resolution=args.resolution, n_phi=args.phi_points,
                   grid=args.grid, cavitation=args.cavitation, eps_max=args.eps_max, phases=args.phases,
                   workers=args.workers, scheduler=args.scheduler, quiet=args.quiet, rebuild=args.rebuild)


def _map_scheduler(text: str) -> str:
    """--scheduler of ``map``: ``local`` or a Dask scheduler's address."""
    from .parallel.cluster import scheduler_address

    try:
        return "local" if text.strip() == "local" else scheduler_address(text)
    except argparse.ArgumentTypeError:
        raise ValueError(text) from None


def _native_choices() -> tuple[str, ...]:
    from .internals.registry import having

    return having(native=True)


def _native_internal(text: str) -> str:
    """--internal of a native FMU: one internal, or several comma-separated (each once)."""
    names = [t.strip().lower() for t in str(text).split(",") if t.strip()]
    allowed = _native_choices()
    if not names or any(n not in allowed for n in names) or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"{text!r}: one of {', '.join(allowed)}, or several comma-separated, each "
                                         "once (an FMU switching among them by its parameter internal)")
    return ",".join(names)


def _internals_help(names, default: str | None = None) -> str:
    """The internals ``names`` as a help text lists them: each with "(default)" and the file flags
    of its file options ("taylor (--surrogate)"), from the registry (a new internal is listed)."""
    from .internals import registry

    out = []
    for name in names:
        flags = [f"--{o.name}" for o in registry.get(name).options if o.file]
        out.append(name + (" (default)" if name == default else "") + (f" ({', '.join(flags)})" if flags else ""))
    return ", ".join(out)


def _film_internal(text: str) -> str:
    """--internal of demo: a registered internal with the film's flows (``Capabilities.film_flow``)."""
    from .internals import registry

    allowed = registry.having(film_flow=True)
    if str(text).strip().lower() not in allowed:
        raise argparse.ArgumentTypeError(f"{text!r}: one of {', '.join(allowed)} (the internals with a film report)")
    return str(text).strip().lower()


def _resolution(text: str) -> tuple[int, int]:
    n_eps, n_beta = (int(v) for v in text.lower().split("x"))
    if not (4 <= n_eps <= 2000 and 8 <= n_beta <= 4000):
        raise ValueError(text)
    return n_eps, n_beta


class Parser(argparse.ArgumentParser):
    """An ArgumentParser (and, through ``add_subparsers``, every sub-command's) that takes any
    negative number after an option as its value (``--load-z -1e3``; ``--load-z -inf`` is then
    refused by the option's type, by name). No option of these commands looks like a negative
    number, the one case where argparse must tell the two apart."""

    def __init__(self, *args, **kwargs):
        from .io.cliargs import NEGATIVE_NUMBER

        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER  # argparse's test for it (Python 3.8 .. 3.13)


def main(argv: list[str] | None = None) -> int:
    from .internals.registry import having
    from .io.bundled import bundled_or_file
    from .io.cliargs import finite_float, output_file, platform_list, positive_float

    parser = Parser(prog="bearing-fmu", description=__doc__, epilog=EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("demo", help="equilibrium, attitude, minimum film and Lund coefficients of a bearing "
                                    "(the paper's by default) under a static load")
    p.add_argument("bearing_file", nargs="?", type=bundled_or_file("bearing"), metavar="BEARING",
                   help="bearing TOML file, or a bundled bearing by name (e.g. bearing_paper_2groove; default: the "
                        "paper bearing)")
    p.add_argument("--bearing", type=bundled_or_file("bearing"), metavar="FILE",
                   help="the same as the BEARING argument (the older form)")
    p.add_argument("--speed-hz", type=positive_float("Hz"), default=22.0, help="shaft speed [Hz] (default 22)")
    p.add_argument("--load-z", type=finite_float("N"), default=-16.7,
                   help="static load on the journal, vertical [N] (weight is negative; default -16.7: half the "
                        "paper rotor's weight)")
    p.add_argument("--load-y", type=finite_float("N"), default=0.0, help="static load, horizontal [N] (default 0)")
    p.add_argument("--load", type=finite_float("N"), default=None,
                   help="downward load magnitude [N], the same as --load-z -LOAD (the older form)")
    p.add_argument("--supply-c", type=finite_float("C"), default=None,
                   help="oil supply temperature [C] (default: the bearing file's [oil] supply_C; needs an [oil] table)")
    p.add_argument("--internal", type=_film_internal, default="reynolds",
                   help="the bearing internal with a film report: "
                        + _internals_help(having(film_flow=True), "reynolds"))
    p.add_argument("--surrogate", type=bundled_or_file("surrogate"), default=None, metavar="FILE",
                   help="--internal taylor: the surrogate file or a bundled one by name (its film fit gives the flows)")
    p.add_argument("--map", type=bundled_or_file("map"), default=None, metavar="FILE",
                   help="--internal map: the force map file or a bundled one by name (with its flow tables)")
    p.add_argument("--json", action="store_true",
                   help="print the record as JSON (eccentricity, attitude, h_min, peak pressure, Sommerfeld, friction, flows, T_eff, "
                        "mu_eff, K and C dimensional and dimensionless; SI, keys carry their unit)")
    p.set_defaults(func=_demo)

    p = sub.add_parser("fit", help="fit a Taylor surrogate over a designed domain (or to a time series, --from-npz) "
                                   "and write its JSON file, report and lambda plots; scene-trained fits: "
                                   "rotor-host fit")
    add_fit_arguments(p)
    p.set_defaults(func=run_fit)

    p = sub.add_parser("build", help="write the bearing FMU")
    p.add_argument("-o", "--output", type=output_file, required=True, help="path of the .fmu to write")
    p.add_argument("--surrogate", type=bundled_or_file("surrogate"), action="append", default=None, metavar="FILE",
                   help="surrogate JSON file (or a bundled one by name) to bundle in resources/surrogates/ (repeat for several; "
                        "with exactly one, the FMU parameter 'surrogate' defaults to it)")
    p.add_argument("--bearing", type=bundled_or_file("bearing"), default=None, metavar="FILE",
                   help="bearing TOML file (or a bundled bearing by name) whose D, L, CR, mu become the FMU's defaults (default: the paper "
                        "bearing's; --native taylor: the surrogate's); a master that sets no parameters gets this "
                        "bearing's force")
    p.add_argument("--map", type=bundled_or_file("map"), action="append", default=None, metavar="FILE",
                   help="force map JSON file (or a bundled one by name) to bundle beside the surrogates (repeat for several; with exactly "
                        "one, the FMU parameter 'map' defaults to it)")
    p.add_argument("--native", action="store_true",
                   help="a native FMU: the internal compiled to C (Model Exchange and Co-Simulation, no Python at run "
                        "time; needs a C compiler now): " + ", ".join(_native_choices()) + ", or several in one FMU")
    p.add_argument("--internal", type=_native_internal, default=None,
                   help="--native: the internal, " + " | ".join(_native_choices()) + ", or several comma-separated "
                        "(one FMU, the parameter internal chooses; taylor,reynolds: domain_action = fallback) "
                        "(default: taylor with --surrogate, map with --map)")
    p.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                   help="--native: the FMI version of the FMU, 2 (2.0, default) or 3 (3.0: binaries per platform "
                        "tuple, sources/buildDescription.xml)")
    p.add_argument("--platforms", type=platform_list, default=None, metavar="all|linux64,win64,darwin64",
                   help="--native: the binaries to compile (default all: linux64 against glibc 2.17, win64, darwin64 "
                        "universal x86_64 + arm64, with zig from the ziglang package, on any machine)")
    p.add_argument("--compiler", choices=("zig", "cc", "cmake"), default=None,
                   help="--native: zig (default, every platform), cc (the system C compiler: $CC, cc, gcc or clang) or "
                        "cmake (fmpy's CMake project, as `fmpy compile` does); cc and cmake build this machine's "
                        "platform only")
    p.add_argument("--cmake", action="store_true", help="--native: the same as --compiler cmake")
    p.add_argument("--speed-hz", type=positive_float("Hz"), default=None, metavar="HZ",
                   help="--native map or linear: the start value of the input omega [Hz] (default: the linear model's "
                        "speed; map: 22 Hz); taylor: the surrogate's speed, always")
    p.set_defaults(func=_build)

    from .internals.map import groovemap as gm
    from .internals.map.tables import DEFAULT_EPS_MAX, DEFAULT_N_BETA, DEFAULT_N_EPS, DEFAULT_N_PHASE
    from .io.cliargs import grid, int_at_least, number, typed

    p = sub.add_parser("map", help="tabulate the force map of a bearing's L/D from the Reynolds solver "
                                   "(docs/forcemap.md) into the map store and write its JSON file")
    p.add_argument("--bearing", type=bundled_or_file("bearing"), metavar="FILE",
                   help="bearing TOML file or a bundled bearing by name (default: the paper bearing); the map "
                   "serves every bearing of the same L/D")
    p.add_argument("-o", "--output", type=output_file, default=None,
                   help="map JSON file to write (the map goes into the map store too, where commands that need a "
                        "map of this bearing find it)")
    p.add_argument("--resolution", type=typed("N_EPSxN_BETA, n_eps 4..2000 and n_beta 8..4000 (e.g. 96x96)",
                                               _resolution), default=None, metavar="N_EPSxN_BETA",
                   help=f"table points in -ln(1 - eps) x beta (default {DEFAULT_N_EPS}x{DEFAULT_N_BETA}; grooved or "
                        f"partial-arc bore {gm.DEFAULT_N_EPS}x{gm.DEFAULT_N_BETA})")
    p.add_argument("--phi-points", type=int_at_least(4), default=None, metavar="N",
                   help="grooved or partial-arc bore: table points in the journal's attitude over one period of the "
                        f"bore's symmetry (default {gm.DEFAULT_PHI_PER_PI} per 180 deg: {gm.DEFAULT_PHI_PER_PI} for two "
                        f"opposite grooves, {2 * gm.DEFAULT_PHI_PER_PI} for an arc)")
    p.add_argument("--grid", type=grid, default=None, metavar="N_THETAxN_X",
                   help="Reynolds grid of the truth (default: the solver's default)")
    p.add_argument("--cavitation", choices=("reynolds", "gumbel"), default="reynolds",
                   help="the film's cavitation condition: reynolds (Swift-Stieber, default) or gumbel (half-Sommerfeld)")
    p.add_argument("--eps-max", type=number("", 0.5, 0.999), default=DEFAULT_EPS_MAX,
                   help=f"last tabulated eccentricity ratio; the map refuses states beyond (default {DEFAULT_EPS_MAX})")
    p.add_argument("--phases", type=int_at_least(1), default=None,
                   help=f"attitudes per point averaged over one Reynolds cell (default {DEFAULT_N_PHASE}; grooved "
                        f"{gm.DEFAULT_N_PHASE})")
    p.add_argument("--workers", type=int_at_least(1), default=None,
                   help="local processes (default: the cores, for tables of 16 rows and more)")
    p.add_argument("--scheduler", type=typed("local or a Dask scheduler address such as tcp://10.0.0.5:8786", str,
                                             _map_scheduler), default=None, metavar="ADDRESS",
                   help="a running Dask scheduler (e.g. tcp://10.0.0.5:8786) whose workers solve the table's rows, or "
                        "'local' for a local Dask cluster of --workers processes; default: a local process pool. "
                        "An interrupted build resumes from the rows kept in MAP.partial")
    p.add_argument("--rebuild", action="store_true", help="rebuild the map even if the map store has it")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_map)

    add_debug_flag(parser, sub)
    args = parser.parse_args(argv)
    announce_compiling()  # a kernel not in numba's cache yet: one line on stderr (never on --json's stdout)
    return run_command("bearing-fmu", args)  # exit codes, interrupts, --debug: .exits


if __name__ == "__main__":
    sys.exit(main())
