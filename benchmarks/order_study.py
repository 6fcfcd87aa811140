"""Order study of the scene-trained Taylor surrogate: held-out force NRMSE for orders 1..7.

For each shipped surrogate (models/surrogates/paper_*hz_16.7N.json), the fit it records in its
provenance (`bearing-fmu fit --scene ...` with its options) is repeated at every order, and
the NRMSE is printed on the held-out blocks of the training series and on the series of the
held-out scene at the same speed (another unbalance: another trajectory), with the
evaluation time per call. Checks the paper's claim that order 5 is
the lowest order that fits the instability case.

    .venv/bin/python benchmarks/order_study.py [--orders 1 2 3 4 5 6 7] [--cache out/series]
        [--surrogates models/surrogates/paper_22hz_16.7N.json ...]
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

from rotor_host.report import markdown_table
from bearing_fmu.taylor import load_surrogate
from rotor_host.training import refit

ROOT = Path(__file__).resolve().parents[1]
SURROGATES = [ROOT / "models" / "surrogates" / f"paper_{f}hz_16.7N.json" for f in (22, 44)]


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
    ap.add_argument("--surrogates", nargs="+", default=[str(p) for p in SURROGATES])
    args = ap.parse_args()
    for path in args.surrogates:
        rows = []
        base = load_surrogate(path)
        name = base.provenance.get("training_source", "?")
        held = None
        for order in args.orders:
            with tempfile.TemporaryDirectory() as tmp:
                sur = load_surrogate(refit(path, order, Path(tmp) / "s.json", cache_dir=args.cache,
                                           log=lambda *_: None))
            e = sur.errors
            held, other = next(iter(e.get("other_scenes", {"-": {"nrmse": {"Fy": float("nan"),
                                                                         "Fz": float("nan")}}}).items()))
            rows.append({
                "order": order, "terms": len(sur.exponents),
                "kept": f"{int(sur.kept[0].sum())}/{int(sur.kept[1].sum())}",
                "blocks_y": 100 * e["test_nrmse"]["Fy"], "blocks_z": 100 * e["test_nrmse"]["Fz"],
                "other_y": 100 * other["nrmse"]["Fy"], "other_z": 100 * other["nrmse"]["Fz"],
                "us": 1e6 * time_per_call(sur),
            })
        print(f"\norder study, {Path(path).name} (training: {name} as recorded in the file; held out: "
              f"every 5th block of 2 revolutions, and the series of {held}); {platform.machine()}, "
              f"Python {platform.python_version()}")
        print(markdown_table(rows, [
            ("order", "order", "d"), ("terms", "terms", "d"), ("kept", "kept Fy/Fz", ""),
            ("blocks_y", "held-out blocks NRMSE Fy [%]", ".3f"), ("blocks_z", "Fz [%]", ".3f"),
            ("other_y", f"{held} NRMSE Fy [%]", ".2f"), ("other_z", "Fz [%]", ".2f"),
            ("us", "force call [us]", ".2f"),
        ]))


if __name__ == "__main__":
    main()
