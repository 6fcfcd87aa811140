"""``bearing-fmu``: the bearing's command line (demo, fit, build)."""

from __future__ import annotations

import argparse
import math
import sys

from .exits import EXIT_CODES, add_debug_flag, run_command


def _demo(args: argparse.Namespace) -> int:
    import numpy as np

    from .params import PAPER_BEARING
    from .reynolds import Reynolds
    from .statics import equilibrium, linearize

    rey = Reynolds(PAPER_BEARING)
    omega = 2 * math.pi * args.speed_hz
    load = (0.0, -args.load)
    y0, z0 = equilibrium(rey, load, omega)
    K, C = linearize(rey, y0, z0, omega)
    eps = math.hypot(y0, z0) / PAPER_BEARING.CR
    att = math.degrees(math.atan2(y0, -z0))
    np.set_printoptions(precision=4)
    print(f"Paper bearing (Table 2: D 31 mm, L 20 mm, CR 90 um, mu 0.05 Pa s), "
          f"Reynolds grid {rey.n_theta} x {rey.n_x}, Swift-Stieber cavitation")
    print(f"speed {args.speed_hz:g} Hz, vertical load {args.load:g} N")
    print(f"equilibrium: y0 = {y0 * 1e6:.3f} um, z0 = {z0 * 1e6:.3f} um, "
          f"eccentricity ratio {eps:.4f}, attitude angle {att:.2f} deg")
    print("stiffness K [N/m] (K_ij = -dF_i/dq_j):")
    print(K)
    print("damping C [N s/m] (C_ij = -dF_i/dqdot_j):")
    print(C)
    return 0


def _build(args: argparse.Namespace) -> int:
    from .build import build_fmu
    from .outputs import ensure_output_file

    ensure_output_file(args.output, "-o/--output")
    path = build_fmu(args.output, surrogate=args.surrogate)
    print(f"wrote {path}")
    return 0


def main(argv: list[str] | None = None) -> int:
    from .cliargs import existing_file, finite_float, output_file, positive_float

    parser = argparse.ArgumentParser(prog="bearing-fmu", description=__doc__, epilog=EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("demo", help="equilibrium and Lund coefficients of the paper bearing")
    p.add_argument("--speed-hz", type=positive_float("Hz"), default=22.0, help="shaft speed [Hz] (default 22)")
    p.add_argument("--load", type=finite_float("N"), default=16.7,
                   help="vertical load on the bearing [N] (default 16.7: half the paper rotor's weight)")
    p.set_defaults(func=_demo)

    from .fitting.cli import add_fit_arguments, run_fit

    p = sub.add_parser("fit", help="fit a Taylor surrogate over a designed domain (or to a time series, --from-npz) "
                                   "and write its JSON file, report and lambda plots; scene-trained fits: "
                                   "rotor-host fit")
    add_fit_arguments(p)
    p.set_defaults(func=run_fit)

    p = sub.add_parser("build", help="write the bearing FMU")
    p.add_argument("-o", "--output", type=output_file, required=True, help="path of the .fmu to write")
    p.add_argument("--surrogate", type=existing_file, action="append", default=None, metavar="FILE",
                   help="surrogate JSON file to bundle in resources/surrogates/ (repeat for several; "
                        "with exactly one, the FMU parameter 'surrogate' defaults to it)")
    p.set_defaults(func=_build)

    add_debug_flag(parser, sub)
    args = parser.parse_args(argv)
    return run_command("bearing-fmu", args)  # exit codes, interrupts, --debug: .exits


if __name__ == "__main__":
    sys.exit(main())
