"""``bearing-fmu fit``: fit a Taylor surrogate of one bearing over a designed domain (or to a
co-simulation time series) and write its file, report and lambda plots.

The options are generated from the FitRecipe fields (the model's and the designed domain's).
Scene-trained fitting runs a rotor and is the host's command, ``rotor-host fit``; its options
given here are refused with a pointer to it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..io.exits import note_kept
from ..io.outputs import ensure_output_file, ensure_writable, savez
from .fit import FitResult, fit_condition, save_fit
from .recipe import add_recipe_arguments, option_name, recipe_fields, recipe_from_args
from .report import format_report, plot_lambda

SCENE_FIT = "rotor-host fit --scene SCENE [--scene ...] [--test-scene SCENE] [--bearing-number N] ..."


class _Moved(argparse.Action):
    """An option of scene-trained fitting, which moved to ``rotor-host fit``."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error(f"{option_string}: scene-trained fitting is the host's command now (the bearing side never "
                     f"runs a rotor): {SCENE_FIT}")


def add_output_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """The options of both fit commands that are not fit settings: output, plots, note."""
    from ..io.cliargs import output_dir, output_file

    parser.add_argument("--plots", type=output_dir, default=None, help="directory for the lambda plots")
    parser.add_argument("--note", default=None, help="free text stored in the file's provenance")
    parser.add_argument("-o", "--output", type=output_file, required=True, help="surrogate JSON file to write")
    return parser


def add_fit_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Arguments of ``bearing-fmu fit``."""
    add_recipe_arguments(parser, "designed")
    moved = [option_name(f) for f in recipe_fields("scene") if f.metadata["group"] == "scene"] + ["--cache-dir"]
    for flag in moved:
        parser.add_argument(flag, nargs="*", action=_Moved, default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    from ..io.cliargs import existing_file

    parser.add_argument("--bearing", type=existing_file, default=None, metavar="FILE",
                        help="bearing TOML file to fit (default: the paper bearing, Table 2); its name and geometry "
                             "go into the report and the surrogate file")
    return add_output_arguments(parser)


def run_fit(args: argparse.Namespace) -> int:
    check_outputs(args)
    recipe = recipe_from_args(args, "designed")
    from ..physics.params import PAPER_BEARING, BearingParams

    params = BearingParams.from_toml(args.bearing) if args.bearing else PAPER_BEARING
    try:
        res = fit_condition(recipe, params=params)
    except KeyboardInterrupt as exc:
        if getattr(exc, "samples", None) is not None and len(exc.samples[0]):
            path = keep_samples(exc.samples, Path(args.output))
            note_kept(exc, f"{path} ({len(exc.samples[0])} samples of the truth; fit them with --from-npz "
                                f"{path})")
        raise
    res.surrogate.provenance["bearing"] = str(args.bearing) if args.bearing else "paper bearing (Table 2)"
    return write_fit(res, args.output, plots=args.plots, note=args.note)


def check_outputs(args) -> None:
    """The output file and plot folder can be written: checked before the fit's work."""
    ensure_output_file(args.output, "-o/--output")
    if args.plots:
        ensure_writable(args.plots, "--plots")


def keep_samples(samples, output: Path) -> Path:
    """The truth's samples of an interrupted fit, as an npz that ``--from-npz`` reads."""
    states, forces = samples
    path = output.with_name(f"{output.stem}_samples_interrupted.npz")
    savez(path, **{k: states[:, i] for i, k in enumerate(("y", "z", "vy", "vz"))},
          Fy=forces[:, 0], Fz=forces[:, 1])
    return path


def write_fit(res: FitResult, output, *, plots=None, note: str | None = None) -> int:
    """Write the surrogate file (with ``note`` in its provenance), print the report, write the
    lambda plots into the folder ``plots``."""
    if note:
        res.surrogate.provenance["note"] = note
    path = save_fit(res, output)
    print(format_report(res))
    print(f"wrote {path}")
    if plots:
        written = plot_lambda(res, plots, Path(output).stem)
        for p in written:
            print(f"wrote {p}")
        if not written:  # say why rather than write nothing without a word
            print(f"no lambda plots in {plots}: lambda was fixed (--lambda), so there was no search to plot; "
                  "leave --lambda out to choose it by cross-validation and plot the search")
    return 0


__all__ = ["add_fit_arguments", "add_output_arguments", "check_outputs", "keep_samples", "run_fit", "write_fit"]
