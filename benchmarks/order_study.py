"""Order study of the scene-trained Taylor surrogate: held-out force NRMSE for orders 1..7.

For each scene, the surrogate is fitted (as `bearing-fmu fit --scene`) at every order to the
Reynolds series of the scene, and its NRMSE is printed on the held-out blocks of that series
and on the series of a held-out scene at the same speed (another unbalance: another
trajectory), with the evaluation time per call. Checks the paper's claim that order 5 is
the lowest order that fits the instability case.

    .venv/bin/python benchmarks/order_study.py [--orders 1 2 3 4 5 6 7] [--cache out/series]
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

from rotor_host.report import markdown_table
from rotor_host.training import fit_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "paper_22hz.toml": "heldout_22hz_6g.toml",
    "paper_44hz.toml": "heldout_44hz_4g.toml",
}


def time_per_call(surrogate, n: int = 20000) -> float:
    from bearing_fmu.taylor import Taylor

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
    ap.add_argument("--scenes", nargs="+", default=list(SCENES))
    args = ap.parse_args()
    for name in args.scenes:
        rows = []
        held = ROOT / "models" / "scenes" / SCENES[name]
        for order in args.orders:
            res = fit_scene(ROOT / "models" / "scenes" / name, order, test_scenes=[held], cache_dir=args.cache,
                            log=lambda *_: None)
            e = res.surrogate.errors
            other = next(iter(e["other_scenes"].values()))
            rows.append({
                "order": order, "terms": res.report["n_terms"],
                "kept": f"{res.report['kept']['Fy']}/{res.report['kept']['Fz']}",
                "blocks_y": 100 * e["test_nrmse"]["Fy"], "blocks_z": 100 * e["test_nrmse"]["Fz"],
                "other_y": 100 * other["nrmse"]["Fy"], "other_z": 100 * other["nrmse"]["Fz"],
                "us": 1e6 * time_per_call(res.surrogate),
            })
        print(f"\norder study, {name} (training: its Reynolds series; held out: every 5th block of 2 "
              f"revolutions, and the series of {held.name}); {platform.machine()}, Python {platform.python_version()}")
        print(markdown_table(rows, [
            ("order", "order", "d"), ("terms", "terms", "d"), ("kept", "kept Fy/Fz", ""),
            ("blocks_y", "held-out blocks NRMSE Fy [%]", ".3f"), ("blocks_z", "Fz [%]", ".3f"),
            ("other_y", f"{held.stem} NRMSE Fy [%]", ".2f"), ("other_z", "Fz [%]", ".2f"),
            ("us", "force call [us]", ".2f"),
        ]))


if __name__ == "__main__":
    main()
