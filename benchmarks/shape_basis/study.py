"""Held-out errors (and optionally the closed loop) of one shape-column recipe against the
plain polynomial of the same order and wall power.

    .venv/bin/python benchmarks/shape_basis/study.py 44hz [--n 7 --p 1.25 --r 3 --lam 0]
        [--closed-loop]

Cases (sbasis.CASES): 10hz (10 Hz 500 N), 20hz (20 Hz 800 N), 44hz. Held-out measures as in
bearing-fmu fit: every 5th block of 2 revolutions of each training series, and the whole series
of a scene never trained on. The closed loop runs the paper scene, called directly, against its
Reynolds run (saved once in out/shape_basis/ref); in pure Python a 6 s 44 Hz run takes ~2 min.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from closedloop import fmt as fmt_loop  # noqa: E402
from closedloop import run_with  # noqa: E402
from sbasis import CASES, AugInternal, Case, evaluate, fit, fmt  # noqa: E402

# the study's best recipe per case (docs/taylor.md, "Short-bearing shape columns")
BEST = {"10hz": dict(n=5, p=1.0, r=2, lam=1e-8), "20hz": dict(n=3, p=0.5, r=2, lam=1e-4),
        "44hz": dict(n=7, p=1.25, r=3, lam=0.0)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", choices=sorted(CASES))
    ap.add_argument("--n", type=int, help="polynomial order")
    ap.add_argument("--p", type=float, help="wall power")
    ap.add_argument("--r", type=int, help="order of the monomials multiplying the shape columns")
    ap.add_argument("--lam", help="ridge lambda, or cv")
    ap.add_argument("--closed-loop", action="store_true")
    args = ap.parse_args()
    rec = dict(BEST[args.case])
    for k in ("n", "p", "r"):
        if getattr(args, k) is not None:
            rec[k] = getattr(args, k)
    if args.lam is not None:
        rec["lam"] = args.lam if args.lam == "cv" else float(args.lam)
    case = Case(args.case)
    models = {}
    for label, r in (("plain polynomial", None), ("with shape columns", rec["r"])):
        m, info = fit(case, rec["n"], r, rec["p"], rec["lam"])
        models[label] = m
        print(f"{args.case} order {rec['n']}, wall {rec['p']}, r {r}, lambda {rec['lam']} "
              f"(cond {info['cond']:.1e}): {fmt(evaluate(case, m))}  [NRMSE in % Fy / Fz]", flush=True)
    if args.closed_loop:
        scene = CASES[args.case]["train"][0]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for label, m in models.items():
                out = run_with(scene, lambda params, load, m=m: AugInternal(m, params))
                print(f"closed loop {scene}, {label}: {fmt_loop(out)}", flush=True)


if __name__ == "__main__":
    main()
