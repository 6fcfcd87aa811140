"""``rotor-host``'s commands on the linearised rotor: stability (Campbell diagram), unbalance response,
undamped critical speed map, API 617 Level I and the API report: their options and handlers."""

from __future__ import annotations

from bearing_fmu.io.cliargs import (finite_float, float_range, grid, int_at_least, interval, node_load, number,
                                    positive_int)

from .common import (call, file_args, file_flags, gas_density_option, linear_rotor_flags, output_options,
                     rotor_argument, unbalance_option)


def _stability(args) -> int:
    from ..analyses.linear import stability

    return call(stability.command, args, rotor_file=args.rotor, data_files=file_args(args))


def _response(args) -> int:
    from ..analyses.response import unbalance

    return call(unbalance.command, args, rotor_file=args.rotor, data_files=file_args(args))


def _ucs(args) -> int:
    from ..analyses.response import ucs

    return call(ucs.command, args, rotor_file=args.rotor, data_files=file_args(args))


def _level1(args) -> int:
    from ..analyses.response import level1

    return call(level1.command, args, rotor_file=args.rotor, data_files=file_args(args))


def _api_report(args) -> int:
    from ..analyses.response import api_report

    return call(api_report.command, args, rotor_file=args.rotor, data_files=file_args(args))



def add_stability(sub) -> None:
    from bearing_fmu.internals.registry import having

    from ..analyses.linear.modal import RANK_UP_TO
    from ..analyses.linear.inputs import DEFAULT_FILES
    from ..analyses.linear.stability_result import DEFAULT_MODES

    p = sub.add_parser("stability", help="Campbell diagram and stability threshold: equilibrium, linearised "
                                         "bearings and damped modes at each speed of a range")
    rotor_argument(p)
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz], both ends included (e.g. 10:70:1)")
    p.add_argument("--internal", choices=having(any_state=True), default="reynolds",
                   help="bearing internal, one valid at every speed and load: " + ", ".join(having(any_state=True))
                        + " (default reynolds)")
    file_flags(p, defaults=DEFAULT_FILES, note=", the paper bearing's; build one with `bearing-fmu map`",
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
    output_options(p, "output folder (default: out) for "
                   "stability_<rotor>_<internal>.md/.json and _campbell/_logdec/_mode.png")
    p.set_defaults(func=_stability)


def add_response(sub) -> None:
    p = sub.add_parser("response", help="unbalance response of the linearised rotor: Bode and polar plots, peaks "
                                        "with their amplification factor and API separation margins")
    rotor_argument(p)
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz], both ends included; every one is computed and kept")
    unbalance_option(p, "an unbalance on a 1-based node (phase from +y toward +z, default 0); repeat for several")
    p.add_argument("--operating-hz", type=interval("Hz"), metavar="MIN:MAX",
                   help="operating speed range [Hz]: separation margins and API 617's required margins")
    p.add_argument("--probe", type=positive_int(), nargs="+", metavar="NODE",
                   help="probe nodes (1-based) for the peaks and plots (default: the bearings' and disks' nodes)")
    linear_rotor_flags(p)
    output_options(p, "output folder: response.json, response.md, bode_node<N>.png, polar_node<N>.png", default=None)
    p.set_defaults(func=_response)


def add_ucs(sub) -> None:
    from ..analyses.response.ucs import DEFAULT_CRITICALS, DEFAULT_POINTS, DEFAULT_SPEEDS_HZ, DEFAULT_STIFFNESS

    p = sub.add_parser("ucs", help="undamped critical speed map against support stiffness, the bearings' stiffness "
                                   "at speed overlaid, the mode shapes of the first criticals")
    rotor_argument(p)
    p.add_argument("--stiffness-n-m", type=interval("N/m"), default=DEFAULT_STIFFNESS, metavar="MIN:MAX",
                   help=f"support stiffness range [N/m] (default {DEFAULT_STIFFNESS[0]:g}:{DEFAULT_STIFFNESS[1]:g})")
    p.add_argument("--points", type=int_at_least(2), default=DEFAULT_POINTS,
                   help=f"stiffness values, log-spaced (default {DEFAULT_POINTS})")
    p.add_argument("--criticals", type=positive_int(), default=DEFAULT_CRITICALS,
                   help=f"lowest forward criticals drawn (default {DEFAULT_CRITICALS})")
    a, b, step = DEFAULT_SPEEDS_HZ
    p.add_argument("--speeds-hz", type=float_range("Hz"), metavar="START:STOP:STEP",
                   help=f"speeds of the bearings' stiffness overlay (default {a:g}:{b:g}:{step:g})")
    linear_rotor_flags(p)
    output_options(p, "output folder: ucs.json, ucs.md, ucs_map.png, "
                                                                 "ucs_modes.png")
    p.set_defaults(func=_ucs)


def add_level1(sub) -> None:
    from ..analyses.response.level1 import DEFAULT_POINTS

    p = sub.add_parser("level1", help="API 617 Level I stability: log decrement of the first forward mode against "
                                      "the stages' cross-coupling, Q_A, Q_0 and the verdict")
    rotor_argument(p, "rotor TOML file with a [[stages]] table (or a bundled rotor by name)")
    p.add_argument("--operating-hz", type=interval("Hz"), required=True, metavar="MIN:MAX",
                   help="operating speed range [Hz]; the check runs at the maximum continuous speed MAX")
    p.add_argument("--points", type=int_at_least(2), default=DEFAULT_POINTS,
                   help=f"cross-coupling values drawn (default {DEFAULT_POINTS})")
    gas_density_option(p)
    linear_rotor_flags(p)
    output_options(p, "output folder: level1.json, level1.md, level1.png")
    p.set_defaults(func=_level1)


def add_api_report(sub) -> None:
    p = sub.add_parser("api-report", help="one markdown report: Campbell diagram and threshold, unbalance response "
                                          "with AF and API margins, critical speed map, API 617 Level I")
    rotor_argument(p)
    p.add_argument("--speeds-hz", type=float_range("Hz"), required=True, metavar="START:STOP:STEP",
                   help="shaft speeds [Hz] of the Campbell diagram and the response, both ends included")
    unbalance_option(p)
    p.add_argument("--operating-hz", type=interval("Hz"), required=True, metavar="MIN:MAX",
                   help="operating speed range [Hz] (margins; Level I at MAX)")
    p.add_argument("--probe", type=positive_int(), nargs="+", metavar="NODE",
                   help="probe nodes (default: the bearings' and disks' nodes)")
    gas_density_option(p)
    linear_rotor_flags(p)
    output_options(p, "output folder: api_report.md, its json and figures", default=None)
    p.set_defaults(func=_api_report)
