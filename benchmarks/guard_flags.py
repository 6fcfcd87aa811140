"""How many states of Reynolds trajectories the domain guard of each shipped surrogate flags.

For every surrogate in rotor_host/bundled/surrogates/ and every scene in rotor_host/bundled/scenes/ that names it
(``[taylor] surrogate``), the scene's Reynolds series of bearing 1 (rotor_host.analyses.training.
scene_series, cached in --cache-dir) is passed state by state through the surrogate's domain
distance (``Taylor.domain_distance``: bounds and nearest training state) and counted:
flagged (d > 0, out_of_domain), by which part (bounds, nearest-neighbour), and refused under
the default domain_limit 0.5 (d > 0.5). For a training scene the rows are split into the
blocks the fit held out and the rest. The 22 Hz state (0, -0.5 CR, 0, 0) is evaluated too.

    python benchmarks/guard_flags.py --cache-dir ../cache-guard [--markdown]
"""
from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

LIMIT = 0.5  # the default domain_limit


def serving_scenes(surrogate: Path) -> list[Path]:
    """The scenes of rotor_host/bundled/scenes/ whose [taylor] surrogate is this file."""
    out = []
    for p in sorted((ROOT / "rotor_host" / "bundled" / "scenes").glob("*.toml")):
        data = tomllib.loads(p.read_text())
        name = (data.get("taylor") or {}).get("surrogate") or data.get("surrogate")
        if name and (p.parent / name).resolve() == surrogate.resolve():
            out.append(p)
    return out


def count(tay, states) -> dict:
    """Flag counts of the guard over raw states (M, 4)."""
    b = np.array([tay.bounds_distance(*x) for x in states])
    d = np.array([tay.domain_distance(*x) for x in states])
    near = tay.neighbours
    nn = np.full(len(states), -np.inf) if near is None else np.array([near.distance(*x) for x in states])
    flagged = d > 1e-12
    return {"n": len(states), "flagged": int(flagged.sum()), "bounds": int((b > 1e-12).sum()),
            "nn": int((nn > 1e-12).sum()), "nn_only": int(((nn > 1e-12) & ~(b > 1e-12)).sum()),
            "refused": int((d > LIMIT).sum()), "max_d": float(d.max()) if len(d) else float("nan")}


def main(argv=None) -> int:
    from bearing_fmu.fitting import recipe_of
    from bearing_fmu.internals.taylor import Taylor
    from bearing_fmu.surrogates.surrogate import load_surrogate
    from rotor_host.analyses.training import holdout_mask, scene_series
    from rotor_host.scenes.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache-dir", type=Path, required=True, help="folder of the scenes' Reynolds series (reused)")
    ap.add_argument("--markdown", action="store_true", help="print a markdown table")
    args = ap.parse_args(argv)
    rows = []
    for f in sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("*.json")):
        sur = load_surrogate(f)
        tay = Taylor(sur)
        recipe = recipe_of(sur, f)
        train = {Path(p).resolve() for p in recipe.scenes}
        for sc_path in serving_scenes(f):
            sc = load_scene(sc_path)
            t, states, _, _ = scene_series(sc, 1, args.cache_dir / f"{sc_path.stem}_b1_series.npz")
            if sc_path.resolve() in train:
                held = holdout_mask(t[::recipe.stride], sc.speed_hz)
                mask = np.zeros(len(t), bool)
                mask[::recipe.stride] = held
                parts = {"training scene, held-out blocks": states[mask], "training scene, the rest": states[~mask]}
            else:
                role = "test scene of the fit" if sc_path.resolve() in {Path(p).resolve() for p in
                                                                        recipe.test_scenes} else "never used"
                parts = {f"held out ({role})": states}
            for what, st in parts.items():
                rows.append({"surrogate": f.name, "scene": sc_path.stem, "rows": what, **count(tay, st)})
        if f.name.startswith("paper_22hz"):
            rows.append({"surrogate": f.name, "scene": "(0, -0.5 CR, 0, 0)", "rows": "single state",
                         **count(tay, np.array([[0.0, -0.5 * sur.params.CR, 0.0, 0.0]]))})
    if args.markdown:
        print("| surrogate | scene | rows | states | flagged | by bounds | by nearest neighbour | "
              "by nearest neighbour only | refused (d > 0.5) | largest d |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            pct = f"{r['flagged']} ({100 * r['flagged'] / r['n']:.2g} %)" if r["flagged"] else "0"
            print(f"| {r['surrogate']} | {r['scene']} | {r['rows']} | {r['n']} | {pct} | {r['bounds']} | "
                  f"{r['nn']} | {r['nn_only']} | {r['refused']} | {r['max_d']:.3g} |")
    else:
        for r in rows:
            print(r)
    return 0


if __name__ == "__main__":
    sys.exit(main())
