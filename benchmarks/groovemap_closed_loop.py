"""The grooved-bore force map in closed loop: a scene run with the map against the same scene
run with the Reynolds solver called directly (the map's truth grid), orbit RMS and max
difference in % CR at the bearings, and the run times side by side.

    .venv/bin/python benchmarks/groovemap_closed_loop.py SCENE MAP [MAP ...] [--t-end S] [--speed-hz F]

Several maps (of one truth grid) are each compared with one Reynolds run.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.internals.map.mapfile import load_any_map
from rotor_host.analyses.report import errors_against
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("maps", nargs="+")
    ap.add_argument("--t-end", type=float, default=None)
    ap.add_argument("--speed-hz", type=float, default=None)
    args = ap.parse_args()
    table = load_any_map(args.maps[0])
    grid = {"n_theta": table.n_theta, "n_x": table.n_x}
    out = Path(tempfile.mkdtemp())
    kw = {} if args.t_end is None else {"t_end_s": args.t_end}
    if args.speed_hz is not None:
        kw["speed_hz"] = args.speed_hz
    scene = load_scene(args.scene)

    def run(internal, opts, stem):
        t0 = time.perf_counter()
        r = run_scene(scene.with_internal(internal, via="direct", options=opts, **kw), out, stem=stem)
        return r, time.perf_counter() - t0

    rey, t_rey = run("reynolds", {"reynolds": grid}, "reynolds")
    print(f"{Path(args.scene).stem} at {kw.get('speed_hz', scene.speed_hz)} Hz, t_end {kw.get('t_end_s', scene.t_end_s)} "
          f"s: Reynolds {table.n_theta} x {table.n_x} {rey.meta['status']} in {t_rey:.1f} s")
    for path in args.maps:
        fmap, t_map = run("map", {"map": {"map": Path(path).resolve()}}, "map")
        err = errors_against(rey.arrays, fmap.arrays)
        print(f"  {Path(path).name}: {fmap.meta['status']} in {t_map:.1f} s; orbit RMS {err['orbit_rms_pct_cr']:.4f} % CR, "
              f"max {err['orbit_max_pct_cr']:.4f} % CR, force NRMSE {err['force_nrmse_pct']:.4f} %", flush=True)


if __name__ == "__main__":
    main()
