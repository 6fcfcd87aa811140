"""Order study of the scene-trained Taylor surrogate: held-out force NRMSE for orders 1..7.

For each shipped surrogate (rotor_host/bundled/surrogates/paper_*hz_16.7N.json), the fit it records in its
provenance (its recipe: `rotor-host fit --scene ...` with its options) is repeated at every order, and
the NRMSE is printed on the held-out blocks of the training series and on the series of the
held-out scene at the same speed (another unbalance: another trajectory), with the
evaluation time per call. Checks the paper's claim that order 5 is
the lowest order that fits the instability case.

    .venv/bin/python benchmarks/order_study.py [--orders 1 2 3 4 5 6 7] [--cache out/series]
        [--surrogates rotor_host/bundled/surrogates/paper_22hz_16.7N.json ...] [--closed-loop]

With --closed-loop each order's surrogate also runs the paper scene in closed loop (called
directly) against one Reynolds run: what a user swapping the surrogate in would see.
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

from bearing_fmu.surrogates.surrogate import load_surrogate
from rotor_host.analyses.compare import envelope_error, late_max_eccentricity
from rotor_host.analyses.report import errors_against, markdown_table
from rotor_host.analyses.training import refit, training_scenes
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SURROGATES = [ROOT / "rotor_host" / "bundled" / "surrogates" / f"paper_{f}hz_16.7N.json" for f in (22, 44)]


def time_per_call(surrogate, n: int = 20000) -> float:
    from bearing_fmu.internals.taylor import Taylor

    t = Taylor(surrogate)
    y, z, om = surrogate.y0, surrogate.z0, surrogate.omega
    t.force(y, z, 0.0, 0.0, om)
    t0 = time.perf_counter()
    for _ in range(n):
        t.force(y, z, 0.0, 0.0, om)
    return (time.perf_counter() - t0) / n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--orders", type=int, nargs="+", default=list(range(1, 8)))
    ap.add_argument("--cache", default=str(ROOT / "out" / "series"), help="folder caching the Reynolds series")
    ap.add_argument("--surrogates", nargs="+", default=[str(p) for p in SURROGATES])
    ap.add_argument("--closed-loop", action="store_true",
                    help="also run the first training scene (the paper scene) with each order's surrogate, "
                         "called directly, against one Reynolds run of it: orbit and envelope errors")
    args = ap.parse_args()
    for path in args.surrogates:
        rows = []
        base = load_surrogate(path)
        name = base.provenance.get("training_source", "?")
        held = None
        ref = scene = None
        if args.closed_loop:
            scene = load_scene(training_scenes(path)[0][0])
            ref = run_scene(scene.with_internal("reynolds", via="direct"), None).arrays
        for order in args.orders:
            with tempfile.TemporaryDirectory() as tmp:
                fitted = refit(path, order, Path(tmp) / "s.json", cache_dir=args.cache, log=lambda *_: None)
                sur = load_surrogate(fitted)
                closed = closed_loop(scene, fitted, ref) if args.closed_loop else {}
            e = sur.errors
            held, other = next(iter(e.get("other_scenes", {"-": {"nrmse": {"Fy": float("nan"),
                                                                         "Fz": float("nan")}}}).items()))
            rows.append({
                "order": order, "terms": len(sur.exponents),
                "kept": f"{int(sur.kept[0].sum())}/{int(sur.kept[1].sum())}",
                "blocks_y": 100 * e["test_nrmse"]["Fy"], "blocks_z": 100 * e["test_nrmse"]["Fz"],
                "other_y": 100 * other["nrmse"]["Fy"], "other_z": 100 * other["nrmse"]["Fz"],
                "us": 1e6 * time_per_call(sur), **closed,
            })
        print(f"\norder study, {Path(path).name} (training: {name} as recorded in the file; held out: "
              f"every 5th block of 2 revolutions, and the series of {held}); {platform.machine()}, "
              f"Python {platform.python_version()}")
        print(markdown_table(rows, [
            ("order", "order", "d"), ("terms", "terms", "d"), ("kept", "kept Fy/Fz", ""),
            ("blocks_y", "held-out blocks NRMSE Fy [%]", ".3f"), ("blocks_z", "Fz [%]", ".3f"),
            ("other_y", f"{held} NRMSE Fy [%]", ".2f"), ("other_z", "Fz [%]", ".2f"),
            ("us", "force call [us]", ".2f"),
        ] + ([("status", f"closed loop, {scene.name}", ""), ("orbit", "orbit RMS [% CR]", ".2f"),
              ("envelope", "envelope RMS [% CR]", ".2f"), ("late", "late max ecc.", ".3f")]
             if args.closed_loop else [])))


def closed_loop(scene, surrogate_path, ref) -> dict:
    """Run ``scene`` with the surrogate (called directly) and measure it against ``ref``."""
    run = run_scene(scene.with_internal("taylor", via="direct", options={"taylor": {"surrogate": Path(surrogate_path)}}), None)
    m = run.meta
    status = m["status"] if m["status"] == "ok" else f"{m['status']} at t = {m['t_reached_s']:.3f} s"
    err = errors_against(ref, run.arrays)
    return {"status": status, "orbit": err["orbit_rms_pct_cr"],
            "envelope": envelope_error(ref, run.arrays, scene.speed_hz),
            "late": late_max_eccentricity(run.arrays)}


if __name__ == "__main__":
    main()
