"""The grooved-bore force map in closed loop: a scene run with the map against the same scene
run with the Reynolds solver called directly (the map's truth grid), orbit RMS and max
difference in % CR at the bearings, and the run times side by side.

    .venv/bin/python benchmarks/groovemap_closed_loop.py SCENE MAP [--t-end S] [--speed-hz F]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.internals.mapfile import load_any_map
from rotor_host.analyses.report import errors_against
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("map")
    ap.add_argument("--t-end", type=float, default=None)
    ap.add_argument("--speed-hz", type=float, default=None)
    args = ap.parse_args()
    table = load_any_map(args.map)
    grid = {"n_theta": table.n_theta, "n_x": table.n_x}
    out = Path(tempfile.mkdtemp())
    runs = {}
    for internal, opts in (("map", {"map": {"map": Path(args.map).resolve()}}), ("reynolds", {"reynolds": grid})):
        scene = load_scene(args.scene)
        kw = {} if args.t_end is None else {"t_end_s": args.t_end}
        if args.speed_hz is not None:
            kw["speed_hz"] = args.speed_hz
        s = scene.with_internal(internal, via="direct", options=opts, **kw)
        t0 = time.perf_counter()
        runs[internal] = run_scene(s, out, stem=internal)
        print(f"{internal}: {runs[internal].meta['status']}, {time.perf_counter() - t0:.1f} s", flush=True)
    err = errors_against(runs["reynolds"].arrays, runs["map"].arrays)
    print(f"{Path(args.scene).stem} (t_end {s.t_end_s:g} s): orbit RMS {err['orbit_rms_pct_cr']:.4f} % CR, max "
          f"{err['orbit_max_pct_cr']:.4f} % CR; " + ", ".join(f"{k} {v:.4g}" for k, v in err.items()
                                                           if k not in ("orbit_rms_pct_cr", "orbit_max_pct_cr")
                                                           and isinstance(v, float)))


if __name__ == "__main__":
    main()
