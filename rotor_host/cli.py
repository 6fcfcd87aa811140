"""``rotor-host``: run scenes, compare internals, run the paper's main job, fit scene-trained surrogates,
find a rotor's stability threshold (Campbell diagram), sweep a scene over speeds or unbalances on Dask."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from bearing_fmu.io.exits import EXIT_CODES, add_debug_flag, note_kept, run_command
from bearing_fmu.io.outputs import ensure_writable, write_text


def _scene_from_args(args):
    from .scenes.scene import load_scene

    scene = load_scene(args.scene)
    changes = {}
    for flag, key in (("via", "via"), ("t_end", "t_end_s"), ("dt", "dt_s"), ("tangent", "newton_tangent"),
                      ("checkpoint_s", "checkpoint_s")):
        if getattr(args, flag, None) is not None:  # 0 is a value (refused by its type), not "unset"
            changes[key] = getattr(args, flag)
    if getattr(args, "native", False):
        changes["fmu_kind"] = "native"
    options = {}
    for internal, option in _file_options():  # --surrogate FILE, --map FILE, ...
        if getattr(args, option, None) is not None:
            options.setdefault(internal, {})[option] = Path(getattr(args, option)).resolve()
    internal = getattr(args, "internal", None)
    if changes or options or internal:
        scene = scene.with_internal(internal or scene.internal, options=options, **changes)
    return scene


def _file_options() -> list[tuple[str, str]]:
    """(internal, option) of every file option in the registry: each is a command-line flag."""
    from bearing_fmu.internals.registry import REGISTRY

    return [(spec.name, o.name) for spec in REGISTRY.values() for o in spec.options if o.file]


def _add_file_flags(p) -> None:
    from bearing_fmu.io.cliargs import existing_file

    for internal, option in _file_options():
        p.add_argument(f"--{option}", type=existing_file, metavar="FILE",
                       help=f"the {internal} internal's {option} file (over the scene's [{internal}] {option})")


def _internal_choices():
    from bearing_fmu.internals.registry import names

    return names()


def _run(args) -> int:
    from .analyses.report import plot_runs
    from .scenes.run import run_scene

    scene = _scene_from_args(args)
    out = Path(args.out)
    run = run_scene(scene, out, progress=not args.quiet)
    m = run.meta
    via = f"{scene.via}, native" if scene.via == "fmu" and scene.fmu_kind == "native" else scene.via
    print(f"{scene.name} [{scene.internal} via {via}]: {m['status']}, {m['steps']} steps to "
          f"t = {m['t_reached_s']:.4g} s in {m['wall_time_s']:.1f} s "
          f"(setup {m['setup_time_s']:.1f} s), {m['newton_mean_evaluations_per_step']:.2f} force "
          f"evaluations per step, {m['step_cuts']} step cuts")
    print(f"max eccentricity ratio per bearing: {', '.join(f'{e:.3f}' for e in m['max_eccentricity'])}"
          + ("  (the orbit crossed the clearance circle)" if m["crossed_clearance"] else ""))
    if m["status"] != "ok":
        print(f"stopped: {m['message']}")
    if scene.speed_profile is not None and not args.no_plots and run.arrays["t"].size > 1:
        from .analyses.waterfall import default_nodes, plot_waterfall, spectra, summary

        try:
            nodes = default_nodes(run.arrays)
            png = plot_waterfall(run.arrays, out / f"{run.npz.stem}_waterfall.png", nodes=nodes,
                                 title=f"{scene.description or scene.name}: {scene.speed_profile.describe()}")
            for n in nodes:
                s = summary(spectra(run.arrays, n))
                whirl = (f"whirl from {s['whirl_onset_hz']:.1f} Hz at {s['whirl_hz']:.1f} Hz "
                         f"({s['whirl_ratio']:.2f}x)" if s["whirl_onset_hz"] else "no subsynchronous whirl")
                print(f"node {n}: resonance at {s['resonance_hz']:.1f} Hz; {whirl}")
            print(f"wrote {png}")
        except ValueError as exc:  # a run too short for a spectrum: say so, keep the run
            print(f"no waterfall: {exc}")
    if not args.no_plots and run.arrays["t"].size > 1:
        png = plot_runs({scene.internal: run.arrays}, out / f"{run.npz.stem}.png", title=scene.description,
                        history=True)
        print(f"wrote {run.npz}, {run.json}, {png}")
    else:
        print(f"wrote {run.npz}, {run.json}")
    return 0 if m["status"] == "ok" else 1


def _grid_options(grid) -> dict:
    """Reynolds grid (n_theta, n_x) as variant options; None = the solver's default."""
    n_theta, n_x = grid if grid else (0, 0)
    return {"reynolds": {"n_theta": n_theta, "n_x": n_x}}


def _grid_label(grid) -> str:
    return f"Reynolds {grid[0]}x{grid[1]}" if grid else "Reynolds default grid"


def _reference_and_variants(args, scene):
    from .analyses.compare import Variant

    ref_grid = args.ref_grid  # (n_theta, n_x), or None: the default grid (parsed by cliargs.grid_or_default)
    ref = Variant(_grid_label(ref_grid), "reynolds", _grid_options(ref_grid))
    variants = []
    if ref_grid:
        variants.append(Variant(_grid_label(None), "reynolds", _grid_options(None)))
    for grid in args.grids or []:
        variants.append(Variant(_grid_label(grid), "reynolds", _grid_options(grid)))
    variants += _map_variants(args.maps if args.maps is not None else _scene_map(scene))
    from bearing_fmu.surrogates.surrogate import load_surrogate

    for order, path in _surrogates(args, scene):
        variants.append(Variant(f"Taylor {load_surrogate(path).recipe}", "taylor", {"taylor": {"surrogate": path}},
                                order=order))
    variants.append(Variant("linear", "linear", _grid_options(None)))
    return ref, variants


def _scene_map(scene) -> list[Path]:
    """The scene's force map as the one map variant, if it names one."""
    value = scene.options.get("map", {}).get("map")
    return [Path(value)] if value else []


def _map_variants(paths) -> list:
    """One compare variant per force map file, labelled with its resolution and truth grid."""
    from bearing_fmu.internals.forcemap import load_map

    from .analyses.compare import Variant

    out = []
    for path in paths:
        t = load_map(path)
        out.append(Variant(f"map {t.n_eps}x{t.n_beta} (Reynolds {t.n_theta}x{t.n_x})", "map",
                           {"map": {"map": Path(path).resolve()}}))
    return out


def _surrogates(args, scene):
    """(order, file) per requested order: the scene's surrogate for its own order, others
    fitted on the same declared domain into the output folder."""
    from bearing_fmu.surrogates.surrogate import load_surrogate

    from .scenes.scene import required_file

    if not args.orders:  # `--orders` with nothing: no Taylor variant, no surrogate needed
        return []
    # read once: its order here, its recipe for the refits
    base = load_surrogate(required_file(scene, "taylor", "surrogate"))
    out = []
    for order in args.orders:
        if order == base.order:
            out.append((order, scene.surrogate))
            continue
        path = Path(args.out) / "surrogates" / f"{scene.surrogate.stem}_order{order}.json"
        if not path.is_file():
            from .analyses.training import refit

            refit(scene.surrogate, order, path, cache_dir=Path(args.out) / "series", surrogate=base)
        out.append((order, path))
    return out


def _compare(args) -> int:
    from .analyses.compare import compare, print_table

    scene = _scene_from_args(args)
    ref, variants = _reference_and_variants(args, scene)
    rows = compare(scene, ref, variants, Path(args.out), progress=not args.quiet,
                   default_label="Reynolds default grid")
    print(print_table(rows))
    print(f"wrote {Path(args.out)}/compare_{Path(scene.source).stem}.md/.json/.png")
    return 0


PAPER_SCENES = ("paper_22hz.toml", "paper_44hz.toml")


def _paper(args) -> int:
    """The main job: the paper's 22 Hz and 44 Hz scenes, Reynolds (default grid) against the
    force map, the bundled Taylor surrogate of each scene and the linear model, all through the
    bearing FMUs."""
    scenes_dir = Path(args.scenes)
    out = ensure_writable(args.out)
    summary = []
    try:
        _paper_scenes(args, scenes_dir, out, summary)
    except KeyboardInterrupt as exc:
        if summary:  # the scenes that finished; compare wrote the interrupted scene's rows
            write_text(out / "paper_summary.md", "\n".join(summary) + "\n**interrupted: the scenes above finished**\n")
            note_kept(exc, f"{out / 'paper_summary.md'} ({len(summary)} finished scene(s))")
        raise
    text = "\n".join(summary)
    write_text(out / "paper_summary.md", text)
    print(text)
    print(f"tables and plots in {out}/ (compare_*.md, compare_*_orbits.png, compare_*_error_vs_time.png)")
    return 0


def _paper_scenes(args, scenes_dir: Path, out: Path, summary: list) -> None:
    from bearing_fmu.surrogates.surrogate import load_surrogate

    from .analyses.compare import Variant, compare, print_table
    from .scenes.scene import load_scene, required_file

    for name in PAPER_SCENES:
        scene = load_scene(scenes_dir / name)
        if args.t_end is not None:  # checked like the file's own value (a whole number of steps)
            scene = scene.with_internal(scene.internal, t_end_s=args.t_end)
        # 22 Hz: order 5; 44 Hz: order 7 with wall factor and shape columns
        sur = load_surrogate(required_file(scene, "taylor", "surrogate"))
        ref = Variant("Reynolds default grid", "reynolds")
        variants = [*_map_variants(_scene_map(scene)), Variant(f"Taylor {sur.recipe}", "taylor", order=sur.order),
                    Variant("linear", "linear")]
        rows = compare(scene, ref, variants, out, progress=not args.quiet, default_label=ref.label)
        summary.append(f"## {scene.description}\n\n{print_table(rows)}\n")


def main(argv: list[str] | None = None) -> int:
    from bearing_fmu.io.cliargs import (existing_dir, existing_file, grid, grid_or_default, output_dir,
                                        positive_float, positive_int)

    from .integrate.forces import NEWTON_TANGENTS

    parser = argparse.ArgumentParser(prog="rotor-host", description=__doc__, epilog=EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("run", help="run one scene and write results and plots")
    p.add_argument("scene", type=existing_file, help="scene TOML file (models/scenes/*.toml)")
    p.add_argument("--internal", choices=_internal_choices(), help="override the scene's internal")
    p.add_argument("--via", choices=("fmu", "direct"), help="bearing FMUs through fmpy, or internals in-process")
    p.add_argument("--native", action="store_true",
                   help="through native bearing FMUs (the internal compiled to C, no Python in the FMU: linear, map, "
                        "taylor; built with the C compiler): the scene key fmu_kind = \"native\"")
    _add_file_flags(p)
    p.add_argument("--t-end", type=positive_float("s"), help="override the end time [s]")
    p.add_argument("--dt", type=positive_float("s"), help="override the time step [s]")
    p.add_argument("--tangent", choices=NEWTON_TANGENTS,
                   help="Newton tangent of the bearing forces (default: the scene's, normally 'bearing': "
                        "the FMUs' own stiffness and damping outputs; 'frozen': those at the static "
                        "equilibrium; 'fd': finite differences; 'linear': the rotor's without bearings)")
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out)")
    p.add_argument("--checkpoint-s", type=positive_float("s"),
                   help="write the partial result every this many seconds of wall time (default: the scene's "
                        "[record] checkpoint_s, 60)")
    p.add_argument("--no-plots", action="store_true")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)

    p = sub.add_parser("compare", help="error against run time of Reynolds grids, Taylor orders and the linear model")
    p.add_argument("scene", type=existing_file, help="scene TOML file")
    p.add_argument("--via", choices=("fmu", "direct"), help="bearing FMUs through fmpy (scene default) or in-process")
    p.add_argument("--ref-grid", type=grid_or_default, default="256x32", metavar="NxM",
                   help="reference Reynolds grid n_theta x n_x (default 256x32; '' = the default grid is the "
                        "reference)")
    p.add_argument("--grids", nargs="*", type=grid, default=[(64, 8)], metavar="NxM",
                   help="coarser Reynolds grids to compare (default 64x8)")
    p.add_argument("--orders", nargs="*", type=positive_int(), default=[1, 3, 5, 7],
                   help="Taylor orders (default 1 3 5 7)")
    p.add_argument("--maps", nargs="*", type=existing_file, default=None, metavar="FILE",
                   help="force map files to compare, e.g. several resolutions (default: the scene's [map] map; "
                        "'--maps' with none: no map variant)")
    p.add_argument("--t-end", type=positive_float("s"), help="override the end time [s]")
    p.add_argument("--dt", type=positive_float("s"), help="override the time step [s]")
    p.add_argument("--out", type=output_dir, default="out", help="output folder (default: out)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_compare)

    p = sub.add_parser("paper", help="main job: the paper's 22 Hz and 44 Hz scenes, Reynolds vs map vs Taylor vs "
                                     "linear through the bearing FMUs, error/run-time table and plots")
    p.add_argument("--scenes", type=existing_dir,
                   default=str(Path(__file__).resolve().parents[1] / "models" / "scenes"),
                   help="folder with paper_22hz.toml and paper_44hz.toml")
    p.add_argument("--t-end", type=positive_float("s"), help="override the simulated time of both scenes [s]")
    p.add_argument("--out", type=output_dir, default="out/paper", help="output folder (default: out/paper)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_paper)

    from .analyses import training

    p = sub.add_parser("fit", help="fit a bearing's Taylor surrogate to the Reynolds series of scenes (the paper's way) "
                                   "and write its JSON file, report and lambda plots")
    training.add_arguments(p)
    p.set_defaults(func=training.run)

    from .analyses import dt_study

    p = sub.add_parser("dt-study", help="halve dt until the bearing orbit changes by less than 1 %% CR")
    dt_study.add_arguments(p)
    p.set_defaults(func=dt_study.run)

    from .analyses import waterfall

    p = sub.add_parser("waterfall", help="response spectra against speed of a run-up or coast-down run "
                                         "(a scene with [speed_profile]), with 1x and 0.5x lines and orbits")
    waterfall.add_arguments(p)
    p.set_defaults(func=waterfall.run)

    from .analyses import limit_cycle

    p = sub.add_parser("limit-cycle", help="envelope of the bearing eccentricity: does the whirl settle and hold?")
    limit_cycle.add_arguments(p)
    p.set_defaults(func=limit_cycle.run)

    from .analyses import stability

    p = sub.add_parser("stability", help="Campbell diagram and stability threshold: equilibrium, linearised "
                                         "bearings and damped modes at each speed of a range")
    stability.add_arguments(p)
    p.set_defaults(func=stability.run)

    from .analyses import sweep

    p = sub.add_parser("sweep", help="run a scene at many speeds or unbalances in parallel on Dask: summary table "
                                     "and bifurcation diagram")
    sweep.add_arguments(p)
    p.set_defaults(func=sweep.run)

    add_debug_flag(parser, sub)
    args = parser.parse_args(argv)
    return run_command("rotor-host", args)  # exit codes, interrupts, --debug: bearing_fmu.io.exits


if __name__ == "__main__":
    sys.exit(main())
