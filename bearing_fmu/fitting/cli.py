"""``bearing-fmu fit``: fit a Taylor surrogate of one bearing and write its file, report and plots."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..surrogate import save_surrogate
from .fit import FitResult, fit_condition
from .report import format_report, plot_lambda


def add_fit_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Arguments of ``bearing-fmu fit``."""
    parser.add_argument("--load-y", type=float, default=0.0, help="static load on the journal, y [N] (default 0)")
    parser.add_argument("--load-z", type=float, default=-16.7,
                        help="static load on the journal, z [N] (default -16.7: half the paper rotor's weight)")
    parser.add_argument("--speed-hz", type=float, default=22.0, help="shaft speed [Hz] (default 22)")
    parser.add_argument("--order", type=int, default=5, help="Taylor order (default 5; 1 = linear)")
    parser.add_argument("--ecc-max", type=float, default=0.7, help="eccentricity bound of the design (default 0.7)")
    parser.add_argument("--v-max", type=float, default=0.5, help="velocity bound in units of omega*CR (default 0.5)")
    parser.add_argument("--radius", type=float, default=None,
                        help="position disc radius about the equilibrium in CR (default: the whole disc ecc <= ecc-max)")
    parser.add_argument("--n-train", type=int, default=3000, help="training samples (default 3000)")
    parser.add_argument("--n-test", type=int, default=1500, help="held-out samples (default 1500)")
    parser.add_argument("--seed", type=int, default=1, help="design seed (held-out uses seed + 1000)")
    parser.add_argument("--grid", type=int, nargs=2, metavar=("N_THETA", "N_X"), default=None,
                        help="Reynolds grid (default: the solver's default)")
    parser.add_argument("--lambda", dest="lam", default="cv", help="'cv' (line search, default) or a fixed value")
    parser.add_argument("--k-folds", type=int, default=5, help="cross-validation folds (default 5)")
    parser.add_argument("--no-prune", action="store_true", help="keep all terms")
    parser.add_argument("--no-anchor", action="store_true",
                        help="regress the constant and order-1 terms too (default: fixed to the Reynolds force and "
                             "derivatives at the equilibrium)")
    parser.add_argument("--prune-tol", type=float, default=0.05,
                        help="allowed relative increase of the CV RMS error by pruning (default 0.05)")
    parser.add_argument("--from-npz", default=None, help="train on a co-simulation time series (y, z, vy, vz, Fy, Fz)")
    parser.add_argument("--scene", action="append", default=None, metavar="SCENE",
                        help="train on the Reynolds time series of this scene (models/scenes/*.toml), the paper's "
                             "way; its speed and bearing load replace --speed-hz/--load-*. Repeatable: several "
                             "scenes (other unbalances, same speed and load) are fitted together")
    parser.add_argument("--test-scene", action="append", default=[], metavar="SCENE",
                        help="with --scene: another scene at the same speed whose series is held out (repeatable)")
    parser.add_argument("--bearing", type=int, default=1, help="with --scene: which bearing's series (default 1)")
    parser.add_argument("--stride", type=int, default=2, help="with --scene: use every stride-th step (default 2)")
    parser.add_argument("--designed", type=int, default=2000,
                        help="with --scene: Reynolds samples added over the domain the series spans (default 2000; "
                             "0 = the series only, the paper's way, which holds on the training orbit only)")
    parser.add_argument("--designed-ecc-max", type=float, default=None,
                        help="with --scene: eccentricity bound of the designed samples (default: the series')")
    parser.add_argument("--designed-v-max", type=float, default=None,
                        help="with --scene: velocity bound of the designed samples in omega*CR (default: the series')")
    parser.add_argument("--designed-weight", type=float, default=1.0,
                        help="with --scene: weight of a designed row against a series row in the least-squares "
                             "fit (default 1)")
    parser.add_argument("--designed-tube", type=float, default=None,
                        help="with --scene: draw the designed samples in a tube of this radius (CR and omega*CR "
                             "units) about the training series' states instead of over the discs they span")
    parser.add_argument("--ecc-weight", type=float, default=0.0, metavar="P",
                        help="with --scene: weigh each row by (1 - eccentricity^2)^P, so the rows near the wall "
                             "(forces without bound) do not dominate the fit (default 0: equal weights)")
    parser.add_argument("--wall-power", type=float, default=0.0, metavar="P",
                        help="fit the polynomial to F * (1 - eccentricity^2)^P and evaluate F = polynomial / "
                             "(1 - eccentricity^2)^P, so it can follow the force's growth near the wall "
                             "(default 0: the plain polynomial)")
    parser.add_argument("--shape-order", type=int, default=None, metavar="R",
                        help="add the short-bearing shape columns S_y m_j, S_z m_j (S: the closed-form short-bearing "
                             "force, m_j: monomials of order <= R) to the regression, so the surrogate carries the "
                             "film's growth at the wall and its dependence on the squeeze direction "
                             "(default: none; docs/taylor.md)")
    parser.add_argument("--cache-dir", default=None,
                        help="with --scene: folder caching the Reynolds series (default: beside --output)")
    parser.add_argument("--plots", default=None, help="directory for the lambda plots")
    parser.add_argument("--note", default=None, help="free text stored in the file's provenance")
    parser.add_argument("-o", "--output", required=True, help="surrogate JSON file to write")
    return parser


def run_fit(args: argparse.Namespace) -> int:
    lam = args.lam if args.lam == "cv" else float(args.lam)
    grid = tuple(args.grid) if args.grid else None
    if args.order < 1:
        raise ValueError(f"--order {args.order}: the Taylor order must be >= 1")
    if args.shape_order is not None and args.shape_order < 0:
        raise ValueError(f"--shape-order {args.shape_order}: must be >= 0 (omit it for no shape columns)")
    if getattr(args, "scene", None):
        from rotor_host.training import fit_scene

        cache = Path(args.cache_dir) if args.cache_dir else Path(args.output).resolve().parent / "series"
        scenes = args.scene if len(args.scene) > 1 else args.scene[0]
        res = fit_scene(scenes, args.order, bearing=args.bearing, test_scenes=args.test_scene,
                        stride=args.stride, cache_dir=cache, lam=lam, prune=not args.no_prune,
                        prune_tol=args.prune_tol, anchor=not args.no_anchor, designed=args.designed,
                        designed_ecc_max=args.designed_ecc_max, designed_v_max=args.designed_v_max,
                        designed_weight=args.designed_weight, designed_tube=args.designed_tube,
                        ecc_weight=args.ecc_weight, wall_power=args.wall_power, shape_order=args.shape_order,
                        seed=args.seed)
    else:
        res = _fit_designed(args, lam, grid)
    return _write_fit(res, args)


def _fit_designed(args, lam, grid) -> FitResult:
    return fit_condition(
        (args.load_y, args.load_z), args.speed_hz, args.order, ecc_max=args.ecc_max, v_max=args.v_max,
        radius=args.radius, n_train=args.n_train, n_test=args.n_test, seed=args.seed, grid=grid,
        npz=args.from_npz, lam=lam, k_folds=args.k_folds, prune=not args.no_prune, prune_tol=args.prune_tol,
        anchor=not args.no_anchor, wall_power=args.wall_power, shape_order=args.shape_order,
    )


def _write_fit(res: FitResult, args) -> int:
    if getattr(args, "note", None):
        res.surrogate.provenance["note"] = args.note
    if getattr(args, "scene", None):
        from rotor_host.training import portable_fit_call

        portable_fit_call(res.surrogate, args.output)
    path = save_surrogate(res.surrogate, args.output)
    print(format_report(res))
    print(f"wrote {path}")
    if args.plots:
        for p in plot_lambda(res, args.plots, Path(args.output).stem):
            print(f"wrote {p}")
    return 0


__all__ = ["add_fit_arguments", "run_fit"]
