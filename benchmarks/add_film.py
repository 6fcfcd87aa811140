"""Add the film fit (key ``film``: the film's side flow and inflow, bearing_fmu/fitting/flows.py) to
surrogate files fitted before it (format version 1), leaving every other key of the file as it was
(the force's coefficients included, checked on writing); the file becomes version 2.

The film is fitted to the Reynolds solver's film reports (the grid and cavitation model the file's
provenance names) at the training states the file stores for its domain guard (``neighbours``: a
compact subset of the states the force was fitted to), 80 % of them (seeded) for the fit, the other
20 % held out for the recorded errors. A file without stored training states is refused (fit it
again with `bearing-fmu fit` or `rotor-host fit`, which fit the film from all their training states).

    python benchmarks/add_film.py rotor_host/bundled/surrogates/paper_44hz_16.7N.json -o out/paper_44hz_film.json

Without -o the file is rewritten in place.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's packages


def add(path: Path, out: Path, seed: int = 0) -> dict:
    from bearing_fmu.fitting.flows import fit_film
    from bearing_fmu.fitting.truth import make_reynolds
    from bearing_fmu.surrogates.surrogate import FILM_VERSION, load_surrogate, surrogate_json

    sur = load_surrogate(path)
    if sur.neighbours is None:
        raise SystemExit(f"{path}: stores no training states (key 'neighbours'); fit it again instead")
    prov = sur.provenance
    grid = (prov.get("truth_n_theta"), prov.get("truth_n_x"))
    rey = make_reynolds(sur.params, None if None in grid else grid, prov.get("truth_cavitation") or "reynolds")
    u = np.asarray(sur.neighbours.points, float)
    states = np.column_stack([sur.y0 + u[:, 0] * sur.pos_scale, sur.z0 + u[:, 1] * sur.pos_scale,
                              u[:, 2] * sur.vel_scale, u[:, 3] * sur.vel_scale])
    held = np.random.default_rng(seed).uniform(size=len(states)) < 0.2
    t0 = time.perf_counter()
    film = fit_film(rey, states[~held], sur.omega, test_states=states[held], seed=seed)
    film.errors["training_states"] = "the file's stored training states (neighbours), 80 %; held out: the other 20 %"
    data = json.loads(path.read_text())
    data["version"], data["film"] = FILM_VERSION, film.to_dict()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(surrogate_json(data))
    back = load_surrogate(out)
    if not (np.array_equal(back.coef, sur.coef) and np.array_equal(back.kept, sur.kept)
            and (sur.shape_coef is None or np.array_equal(back.shape_coef, sur.shape_coef))):
        raise RuntimeError(f"{out}: the force's coefficients changed on writing")
    row = {"file": str(path), "out": str(out), **film.errors, "seconds": round(time.perf_counter() - t0, 1)}
    print(json.dumps(row, indent=1), flush=True)
    return row


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("file", type=Path)
    p.add_argument("-o", "--output", type=Path, default=None, help="where to write (default: in place)")
    p.add_argument("--seed", type=int, default=0, help="seed of the held-out split and the CV folds")
    args = p.parse_args(argv)
    add(args.file, args.output or args.file, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
