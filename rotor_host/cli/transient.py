"""``rotor-host``'s commands on scenes in time: run, compare, the main job, fit, dt-study, waterfall,
limit-cycle, linear-vs-runup and sweep: their options and handlers."""

from __future__ import annotations

from pathlib import Path

from bearing_fmu.io.bundled import bundled_or_file
from bearing_fmu.io.cliargs import (existing_dir, existing_file, float_range, grid, grid_or_default, nonneg_float,
                                    output_dir, output_file, positive_float, positive_int)

from .common import call, internal_choices, module_command, scene_flags, scene_from_args


def _run(args) -> int:
    from ..analyses.report import run_and_report

    return run_and_report(scene_from_args(args), args.out, progress=not args.quiet, plots=not args.no_plots)


def _compare(args) -> int:
    from ..analyses.compare import compare, print_table, reference_and_variants

    scene = scene_from_args(args)
    ref, variants = reference_and_variants(scene, args.out, ref_grid=args.ref_grid, grids=args.grids,
                                           orders=args.orders, maps=args.maps, internals=args.internals)
    rows = compare(scene, ref, variants, Path(args.out), progress=not args.quiet,
                   default_label="Reynolds default grid")
    print(print_table(rows))
    print(f"wrote {Path(args.out)}/compare_{Path(scene.source).stem}.md/.json/.png")
    return 0


def _paper(args) -> int:
    from ..analyses.compare import paper_job

    print(paper_job(args.scenes, args.out, t_end=args.t_end, progress=not args.quiet))
    print(f"tables and plots in {args.out}/ (compare_*.md, compare_*_orbits.png, compare_*_error_vs_time.png)")
    return 0


def _fit(args) -> int:
    from bearing_fmu.cli import recipe_from_args

    from ..analyses import training

    if not args.scenes:
        raise ValueError("--scene: give at least one training scene (rotor_host/bundled/scenes/*.toml)")
    return call(training.command, args, recipe=recipe_from_args(args, "scene"))


def _linear_vs_runup(args) -> int:
    from ..analyses.response import runup

    return call(runup.command, args, scene=scene_from_args(args))


def _sweep(args) -> int:
    from ..analyses import sweep
    from ..analyses.computed_for import scene_line

    scene = scene_from_args(args)
    print(f"computed for: {scene_line(scene)}")
    return call(sweep.command, args, scene=scene)



def add_run(sub) -> None:
    p = sub.add_parser("run", help="run one scene and write results and plots")
    p.add_argument("scene", type=bundled_or_file("scene"), help="scene TOML file, or a bundled scene by name (e.g. paper_22hz)")
    scene_flags(p, tangent=True, checkpoint=True)
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out)")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)


def add_compare(sub) -> None:
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


def add_paper(sub) -> None:
    p = sub.add_parser("paper", help="main job: the paper's 22 Hz and 44 Hz scenes, Reynolds vs map vs Taylor vs "
                                     "linear through the bearing FMUs, error/run-time table and plots")
    from ..bundled import folder

    p.add_argument("--scenes", type=existing_dir, default=str(folder() / "scenes"),
                   help="folder with paper_22hz.toml and paper_44hz.toml (default: the bundled scenes)")
    p.add_argument("--t-end", type=positive_float("s"), help="override the simulated time of both scenes [s]")
    p.add_argument("--out", type=output_dir, default="out/paper", help="output folder (default: out/paper)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_paper)


def add_fit(sub) -> None:
    from bearing_fmu.cli import add_output_arguments, add_recipe_arguments

    p = sub.add_parser("fit", help="fit a bearing's Taylor surrogate to the Reynolds series of scenes (the paper's way) "
                                   "and write its JSON file, report and lambda plots")
    add_recipe_arguments(p, "scene")
    p.add_argument("--cache-dir", type=output_dir, default=None,
                   help="folder caching the Reynolds series (default: series/ beside --output)")
    add_output_arguments(p)
    p.set_defaults(func=_fit)


def add_dt_study(sub) -> None:
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
    p.set_defaults(func=module_command("dt_study"))


def add_waterfall(sub) -> None:
    from ..analyses.waterfall import DEFAULT_WINDOW_S

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
    p.set_defaults(func=module_command("waterfall"))


def add_limit_cycle(sub) -> None:
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
    p.set_defaults(func=module_command("limit_cycle"))



def add_linear_vs_runup(sub) -> None:
    from ..analyses.response.runup import DEFAULT_SCALES

    p = sub.add_parser("linear-vs-runup", help="the linear unbalance response against the same unbalance in a run-up "
                                               "through the nonlinear bearing force, at a small and a large unbalance")
    p.add_argument("scene", type=bundled_or_file("scene"), help="a run-up scene file, or a bundled one by name (e.g. paper_runup_10_60hz)")
    p.add_argument("--scale", type=positive_float(), nargs="+", default=list(DEFAULT_SCALES), metavar="F",
                   help="factors on the scene's unbalance masses, one run each (default "
                        f"{' '.join(f'{f:g}' for f in DEFAULT_SCALES)})")
    p.add_argument("--window-s", type=positive_float("s"), help="the waterfall's window [s] (default 0.25)")
    scene_flags(p)
    p.add_argument("--out", type=output_dir, default="out", help="output folder: linear_vs_runup.json/.md, "
                                                                 "linear_vs_runup_node<N>.png and the runs")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--no-plots", action="store_true", help="write no plots (the tables and json only)")
    p.set_defaults(func=_linear_vs_runup)


def add_sweep(sub) -> None:
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
    scene_flags(p)
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
    p.set_defaults(func=_sweep, own_fixed_costs=True)  # its fixed-cost line names its workers' and cluster's
