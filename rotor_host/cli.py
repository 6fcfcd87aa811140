"""``rotor-host``: run scenes, compare internals, run the paper's main job."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _scene_from_args(args):
    from .scene import load_scene

    scene = load_scene(args.scene)
    changes = {}
    if getattr(args, "internal", None):
        changes["internal"] = args.internal
    if getattr(args, "via", None):
        changes["via"] = args.via
    if getattr(args, "t_end", None):
        changes["t_end_s"] = args.t_end
    if getattr(args, "dt", None):
        changes["dt_s"] = args.dt
    if getattr(args, "surrogate", None):
        changes["surrogate"] = Path(args.surrogate).resolve()
    if changes:
        scene = scene.with_internal(changes.pop("internal", scene.internal), **changes)
    return scene


def _run(args) -> int:
    from .report import plot_runs
    from .scene import run_scene

    scene = _scene_from_args(args)
    out = Path(args.out)
    run = run_scene(scene, out, progress=not args.quiet)
    m = run.meta
    print(f"{scene.name} [{scene.internal} via {scene.via}]: {m['status']}, {m['steps']} steps to "
          f"t = {m['t_reached_s']:.4g} s in {m['wall_time_s']:.1f} s "
          f"(setup {m['setup_time_s']:.1f} s), {m['newton_mean_evaluations_per_step']:.2f} force "
          f"evaluations per step, {m['step_cuts']} step cuts")
    print(f"max eccentricity ratio per bearing: {', '.join(f'{e:.3f}' for e in m['max_eccentricity'])}"
          + ("  (the orbit crossed the clearance circle)" if m["crossed_clearance"] else ""))
    if m["status"] != "ok":
        print(f"stopped: {m['message']}")
    if not args.no_plots:
        disk = 6 if 6 in run.arrays["nodes"] else None
        png = plot_runs({scene.internal: run.arrays}, out / f"{run.npz.stem}.png", title=scene.description,
                        disk_node=disk, history=True)
        print(f"wrote {run.npz}, {run.json}, {png}")
    else:
        print(f"wrote {run.npz}, {run.json}")
    return 0 if m["status"] == "ok" else 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rotor-host", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("run", help="run one scene and write results and plots")
    p.add_argument("scene", help="scene TOML file (models/scenes/*.toml)")
    p.add_argument("--internal", choices=("reynolds", "taylor", "linear"), help="override the scene's internal")
    p.add_argument("--via", choices=("fmu", "direct"), help="bearing FMUs through fmpy, or internals in-process")
    p.add_argument("--surrogate", help="surrogate JSON (taylor)")
    p.add_argument("--t-end", type=float, help="override the end time [s]")
    p.add_argument("--dt", type=float, help="override the time step [s]")
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument("--no-plots", action="store_true")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)

    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, KeyError, FileNotFoundError, RuntimeError) as exc:
        print(f"rotor-host {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
