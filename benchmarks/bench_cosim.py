"""Host with bearing FMUs vs the same internal called directly, measured side by side.

Runs the paper's 22 Hz scene (models/scenes/paper_22hz.toml) for a short span with each
internal, once through the FMUs (fmpy, conformant state-restore iterations) and once
in-process, and prints the run-time ratio FMU / direct and the FMI overhead per bearing
evaluation. Integration time only (setup: FMU build, load, numba cache, equilibrium apart).

    .venv/bin/python benchmarks/bench_cosim.py [--t-end 0.2]
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import tempfile
from pathlib import Path

from rotor_host.report import markdown_table
from rotor_host.scene import load_scene, run_scene

ROOT = Path(__file__).resolve().parents[1]


def cpu() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        return next(line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name"))
    except Exception:  # noqa: BLE001
        return platform.processor() or "unknown CPU"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.2)
    ap.add_argument("--repeat", type=int, default=2, help="runs per case, the fastest counts")
    args = ap.parse_args()
    base = load_scene(ROOT / "models" / "scenes" / "paper_22hz.toml")
    base.t_end_s = args.t_end
    internals = ["reynolds", "linear"]
    if base.surrogate and base.surrogate.is_file():
        internals.append("taylor")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for internal in internals:
            times = {}
            for via in ("direct", "fmu"):
                s = base.with_internal(internal, via=via)
                best = None
                for _ in range(args.repeat):
                    run = run_scene(s, work_dir=Path(tmp))
                    m = run.meta
                    if best is None or m["integration_time_s"] < best["integration_time_s"]:
                        best = m
                times[via] = best
            d, f = times["direct"], times["fmu"]
            evals = f["force_evaluations"] * 2  # two bearings
            rows.append({
                "internal": internal, "steps": f["steps"], "evals": f["newton_mean_evaluations_per_step"],
                "direct": d["integration_time_s"], "fmu": f["integration_time_s"],
                "ratio": f["integration_time_s"] / d["integration_time_s"],
                "overhead_us": 1e6 * (f["integration_time_s"] - d["integration_time_s"]) / evals,
                "us_step": 1e6 * f["integration_time_s"] / f["steps"],
            })
    print(f"bench_cosim: paper_22hz, {args.t_end} s simulated at dt = {base.dt_s} s; {cpu()}, "
          f"{platform.machine()}, Python {platform.python_version()}")
    print(markdown_table(rows, [
        ("internal", "internal", ""), ("steps", "steps", "d"), ("evals", "evaluations/step", ".2f"),
        ("direct", "direct [s]", ".3f"), ("fmu", "FMU [s]", ".3f"), ("ratio", "FMU / direct", ".2f"),
        ("overhead_us", "FMI overhead per bearing evaluation [us]", ".1f"), ("us_step", "FMU us/step", ".0f"),
    ]))


if __name__ == "__main__":
    main()
