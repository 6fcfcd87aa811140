"""Add the nearest-neighbour guard's training states (key ``neighbours``) to surrogate files
written before it, leaving every other byte of the file as it was (coefficients included).

The training states are regenerated from the file's own recipe (``provenance``: ``recipe``
or the older ``fit_call``): the file is refitted the way it was fitted (scene-trained:
``rotor_host.analyses.training.fit_scene``, which reruns the training scenes with Reynolds, or reads
their series from ``--cache-dir``; designed-domain: ``fit_condition``), and only the refit's
``neighbours`` are written into the file. The refit's coefficients, training-row count and
domain are compared with the file's and printed: they agree to round-off when the training
states are the ones the file was fitted to (the Reynolds series differ from the stored fit's
at round-off level between machines).

    python benchmarks/add_neighbours.py rotor_host/bundled/surrogates/*.json --cache-dir ../cache-guard

Files that already have the key are left alone unless ``--force``.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's packages


def regenerate(path: Path, cache_dir: Path):
    """The refit of the file at ``path`` from its recipe (a FitResult)."""
    from bearing_fmu.fitting import fit_condition, recipe_of
    from bearing_fmu.surrogates.surrogate import load_surrogate

    sur = load_surrogate(path)
    recipe = recipe_of(sur, path)
    if recipe.kind == "scene":
        from rotor_host.analyses.training import fit_scene

        return sur, fit_scene(recipe, cache_dir=cache_dir, log=lambda m: print("  " + m, flush=True))
    return sur, fit_condition(recipe, params=sur.params, bias_variance=False)


def compare(old, new) -> dict:
    """How close the refit is to the file: coefficients, training rows, domain."""
    scale = float(np.max(np.abs(old.coef)))
    out = {
        "coef_max_rel_diff": float(np.max(np.abs(new.coef - old.coef)) / scale),
        "n_train_file": old.errors.get("n_train"), "n_train_refit": new.errors.get("n_train"),
        "domain_max_abs_diff": float(np.max(np.abs(np.subtract(
            [old.domain.ecc_max, old.domain.pos_radius, old.domain.v_max, *old.domain.box_lo, *old.domain.box_hi],
            [new.domain.ecc_max, new.domain.pos_radius, new.domain.v_max, *new.domain.box_lo, *new.domain.box_hi])))),
    }
    if old.shape_coef is not None:
        out["shape_coef_max_rel_diff"] = float(np.max(np.abs(new.shape_coef - old.shape_coef))
                                               / np.max(np.abs(old.shape_coef)))
    return out


def add(path: Path, cache_dir: Path, force: bool) -> dict | None:
    from bearing_fmu.surrogates.surrogate import load_surrogate, surrogate_json

    data = json.loads(path.read_text())
    if "neighbours" in data and not force:
        print(f"{path}: has neighbours already (--force to replace)")
        return None
    t0 = time.perf_counter()
    old, res = regenerate(path, cache_dir)
    nb = res.surrogate.neighbours
    data.pop("neighbours", None)
    data["neighbours"] = nb.to_dict()
    path.write_text(surrogate_json(data))
    back = load_surrogate(path)
    if not (np.array_equal(back.coef, old.coef) and np.array_equal(back.kept, old.kept)
            and (old.shape_coef is None or np.array_equal(back.shape_coef, old.shape_coef))):
        raise RuntimeError(f"{path}: coefficients changed on writing; restore it from git")
    row = {"file": str(path), **compare(old, res.surrogate), "n_points": len(nb.points), "radius": nb.radius,
           "covering_radius": nb.info["covering_radius"], "cv_distance": nb.info["cv_distance"],
           "other_scenes": res.surrogate.errors.get("other_scenes"), "seconds": round(time.perf_counter() - t0, 1)}
    print(json.dumps(row, indent=1), flush=True)
    return row


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("files", nargs="+", type=Path)
    p.add_argument("--cache-dir", type=Path, required=True, help="folder of the scenes' Reynolds series (reused)")
    p.add_argument("--force", action="store_true", help="replace existing neighbours")
    args = p.parse_args(argv)
    for f in args.files:
        add(f, args.cache_dir, args.force)
    return 0


if __name__ == "__main__":
    sys.exit(main())
