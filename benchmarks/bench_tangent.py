"""Newton tangent of the bearing forces: the FMUs' own stiffness and damping against fixed ones.

Runs paper scenes through the bearing FMUs with each ``newton_tangent`` (rotor_host.scenes.scene):
``bearing`` (the FMU's K, C outputs at every iterate: exact Newton), ``frozen`` (those at the
static equilibrium, fixed: Lund's coefficients), ``fd`` (finite differences by the
integrator, refreshed when Newton slows; the FMUs skip their Jacobian) and ``linear`` (the
rotor's tangent without bearings, fixed). Prints force evaluations per step, step cuts,
integration time, and the orbit difference from the exact-Newton run (it should be at the
Newton tolerance when both complete).

    .venv/bin/python benchmarks/bench_tangent.py [--t-end 0.05] [--internals taylor reynolds]
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import warnings
from pathlib import Path

from bench_cosim import cpu

from rotor_host.analyses.report import errors_against, markdown_table
from rotor_host.integrate.forces import NEWTON_TANGENTS
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("paper_22hz.toml", "paper_10hz_500N.toml")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.05, help="simulated time per run [s]")
    ap.add_argument("--internals", nargs="+", default=["taylor", "reynolds"])
    ap.add_argument("--skip", nargs="*", default=["reynolds:linear"],
                    help="internal:tangent pairs not to run (Reynolds with the linear tangent takes "
                         "minutes: ~170x the evaluations)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # out-of-domain warnings of wandering iterates
        for name in SCENES:
            base = load_scene(ROOT / "rotor_host" / "bundled" / "scenes" / name)
            base.t_end_s = args.t_end
            for internal in args.internals:
                ref = None
                for tangent in NEWTON_TANGENTS:
                    if f"{internal}:{tangent}" in args.skip:
                        continue
                    run = run_scene(base.with_internal(internal, via="fmu", newton_tangent=tangent), work_dir=Path(tmp))
                    m = run.meta
                    if tangent == "bearing":
                        ref = run.arrays
                    diff = errors_against(ref, run.arrays)["orbit_max_pct_cr"]
                    rows.append({
                        "scene": base.name, "internal": internal, "tangent": tangent,
                        "status": m["status"] if m["status"] == "ok" else f"failed at {m['t_reached_s']:.4f} s",
                        "evals": m["newton_mean_evaluations_per_step"], "cuts": m["step_cuts"],
                        "time": m["integration_time_s"], "diff": diff,
                    })
                    print(f"{base.name} {internal} {tangent}: {rows[-1]['status']}, {rows[-1]['evals']:.2f} "
                          f"evaluations/step, {m['step_cuts']} cuts, {m['integration_time_s']:.2f} s", flush=True)
    for r in rows:
        base_t = next(x["time"] for x in rows if x["scene"] == r["scene"] and x["internal"] == r["internal"]
                      and x["tangent"] == "bearing")
        r["rel"] = r["time"] / base_t
    print(f"\nbench_tangent: {args.t_end} s of each scene through the bearing FMUs, dt = 1e-4 s; {cpu()}, "
          f"{platform.machine()}, Python {platform.python_version()}")
    print(markdown_table(rows, [
        ("scene", "scene", ""), ("internal", "internal", ""), ("tangent", "Newton tangent", ""),
        ("status", "status", ""), ("evals", "evaluations/step", ".2f"), ("cuts", "step cuts", "d"),
        ("time", "integration [s]", ".2f"), ("rel", "time / exact", ".1f"),
        ("diff", "orbit max diff. from exact [% CR]", ".2g"),
    ]))


if __name__ == "__main__":
    main()
