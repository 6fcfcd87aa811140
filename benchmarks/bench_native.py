"""Native bearing FMUs (bearing_fmu/native): what one doStep costs, and what the rotor host pays.

1. C host: bearing_fmu/fmu/native/c/example_host.c, compiled here, started with an empty
   environment, loads each native FMU's binary and times doStep at states moving on a small
   circle around the surrogate's expansion point (the map and linear: the 22 Hz one), and one
   conformant iteration (restore the state saved at the step's start, set the inputs, doStep,
   get the 11 outputs). Best of --repeat runs of 200 000 calls.
2. Rotor host: a paper scene (default paper_22hz) for --t-end s with each internal called
   in-process (direct), through the Python FMU and through the native FMU (fmpy, the
   conformant iteration of rotor_host/coupling/cosim.py); integration time only, best of --repeat. The
   step split (bearing evaluations, the per-step FMU state bookkeeping, the integrator) is
   bench_cosim.StepSplit's. Reynolds runs through the Python FMU (it has no native FMU) for
   the Reynolds/Taylor and Reynolds/map ratios of the same run.

    .venv/bin/python benchmarks/bench_native.py [--t-end 0.1] [--repeat 2] [--scene FILE]
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_cosim import StepSplit, cpu  # noqa: E402

from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402
from rotor_host.analyses.report import markdown_table  # noqa: E402
from rotor_host.scenes.run import run_scene  # noqa: E402
from rotor_host.scenes.scene import load_scene

SURROGATES = ROOT / "rotor_host" / "bundled" / "surrogates"
MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"


def c_host_costs(tmp: Path, repeat: int, n: int = 200_000) -> list[dict]:
    import fmpy

    from bearing_fmu.fmu.native.build import C_DIR, build_native_fmu, find_compiler, fmi_headers

    exe = tmp / "example_host"
    subprocess.run([find_compiler(), "-O2", str(C_DIR / "example_host.c"), "-I", str(fmi_headers()), "-o", str(exe),
                    "-ldl", "-lm"], check=True)
    s22 = load_surrogate(SURROGATES / "paper_22hz_16.7N.json")
    cases = []
    for name in ("paper_44hz_16.7N", "paper_22hz_16.7N"):
        s = load_surrogate(SURROGATES / f"{name}.json")
        cases.append((f"taylor {name} ({s.recipe}, {s.neighbours.points.shape[0] if s.neighbours else 0} "
                      "training states)", "taylor", {"surrogate": SURROGATES / f"{name}.json"},
                      (s.y0, s.z0, 0.0, 0.0, s.omega)))
    cases.append(("map paper_bearing (96 x 96)", "map", {"map": MAP}, (s22.y0, s22.z0, 0.0, 0.0, s22.omega)))
    cases.append(("linear", "linear", {"options": {"linear_from": "map", "map": str(MAP)}},
                  (s22.y0, s22.z0, 0.0, 0.0, 2 * 3.141592653589793 * 22.0)))
    rows = []
    for label, internal, kw, state in cases:
        fmu = build_native_fmu(tmp / f"{internal}_{len(rows)}.fmu", internal, **kw)
        unzip = Path(fmpy.extract(str(fmu)))
        binary = next((unzip / "binaries").rglob("*.so"))
        guid = fmpy.read_model_description(str(fmu)).guid
        best = None
        for _ in range(repeat):
            out = subprocess.run([str(exe), str(binary), guid, *(repr(float(x)) for x in state), str(n)], env={},
                                 capture_output=True, text=True, check=True).stdout
            line = next(l for l in out.splitlines() if l.startswith("doStep_us"))
            f = line.split()
            step, it, refused = float(f[1]), float(f[3]), int(f[5])
            if best is None or step < best["step"]:
                best = {"case": label, "step": step, "iteration": it, "refused": refused}
        rows.append(best)
    return rows


def host_costs(scene_file: Path, t_end: float, repeat: int, tmp: Path) -> tuple[list[dict], list[dict], dict]:
    base = load_scene(scene_file)
    base = base.with_internal(base.internal, t_end_s=t_end)
    kinds = [("direct", "direct", "python"), ("Python FMU", "fmu", "python"), ("native FMU", "fmu", "native")]
    rows, splits, best_of = [], [], {}
    for internal in ("taylor", "map", "linear", "reynolds"):
        times = {}
        for label, via, kind in kinds:
            if internal == "reynolds" and kind == "native":
                continue
            s = base.with_internal(internal, via=via, fmu_kind=kind)
            best = None
            for _ in range(repeat):
                with StepSplit() as split:
                    run = run_scene(s, work_dir=tmp)
                m = dict(run.meta, split=dict(split.acc))
                if best is None or m["integration_time_s"] < best["integration_time_s"]:
                    best = m
            times[label] = best
            best_of[(internal, label)] = best
            steps = best["steps"]
            ev, st = best["split"]["evaluate"], best["split"]["step"]
            splits.append({"internal": internal, "via": label, "us_step": 1e6 * best["integration_time_s"] / steps,
                           "eval": 1e6 * ev / steps, "step": 1e6 * st / steps,
                           "host": 1e6 * (best["integration_time_s"] - ev - st) / steps,
                           "per_eval": 1e6 * ev / max(best["force_evaluations"] * 2, 1)})
        d = times["direct"]["integration_time_s"]
        rows.append({"internal": internal, "evals": times["direct"]["newton_mean_evaluations_per_step"],
                     "direct": d, "python": times["Python FMU"]["integration_time_s"],
                     "native": times.get("native FMU", {}).get("integration_time_s", float("nan")),
                     "r_python": times["Python FMU"]["integration_time_s"] / d,
                     "r_native": times.get("native FMU", {}).get("integration_time_s", float("nan")) / d})
    rey = best_of[("reynolds", "Python FMU")]["integration_time_s"]
    ratios = {f"Reynolds (Python FMU) / {i} ({label})": rey / best_of[(i, label)]["integration_time_s"]
              for i in ("taylor", "map") for label in ("native FMU", "Python FMU", "direct")}
    ratios["Reynolds / taylor, both direct"] = (best_of[("reynolds", "direct")]["integration_time_s"]
                                                / best_of[("taylor", "direct")]["integration_time_s"])
    ratios["Reynolds / map, both direct"] = (best_of[("reynolds", "direct")]["integration_time_s"]
                                             / best_of[("map", "direct")]["integration_time_s"])
    return rows, splits, ratios


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.1, help="simulated time of each rotor run [s]")
    ap.add_argument("--repeat", type=int, default=2, help="runs per case, the fastest counts")
    ap.add_argument("--scene", type=Path, default=ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml")
    ap.add_argument("--skip-host", action="store_true", help="only the C host")
    args = ap.parse_args()
    print(f"bench_native: {cpu()}, {platform.machine()}, Python {platform.python_version()}")
    with tempfile.TemporaryDirectory() as tmp:
        rows = c_host_costs(Path(tmp), max(args.repeat, 3))
        print("\nC host (example_host.c, empty environment), best of runs of 200 000 calls [us]:")
        print(markdown_table(rows, [("case", "native FMU", ""), ("step", "doStep + getReal", ".3f"),
                                    ("iteration", "conformant iteration", ".3f"), ("refused", "refused", "d")]))
        if args.skip_host:
            return
        rows, splits, ratios = host_costs(args.scene, args.t_end, args.repeat, Path(tmp))
    print(f"\nRotor host: {args.scene.name}, {args.t_end} s at its dt; integration time [s], best of {args.repeat}:")
    print(markdown_table(rows, [
        ("internal", "internal", ""), ("evals", "evaluations/step", ".2f"), ("direct", "direct", ".3f"),
        ("python", "Python FMU", ".3f"), ("native", "native FMU", ".3f"), ("r_python", "Python FMU / direct", ".2f"),
        ("r_native", "native FMU / direct", ".2f")]))
    print("\nWhere a step goes [us per step; per bearing evaluation in the last column]:")
    print(markdown_table(splits, [
        ("internal", "internal", ""), ("via", "via", ""), ("us_step", "step", ".1f"),
        ("eval", "bearing evaluations", ".1f"), ("step", "bearing begin/accept", ".1f"),
        ("host", "integrator (the rest)", ".1f"), ("per_eval", "one bearing evaluation", ".1f")]))
    print("\nScene ratios (integration time):")
    for k, v in ratios.items():
        print(f"- {k}: {v:.1f}x")


if __name__ == "__main__":
    main()
