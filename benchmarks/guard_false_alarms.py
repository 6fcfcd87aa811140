"""Is the domain guard right when it warns? False-alarm and miss rates against Reynolds.

For each machine, a surrogate and states it is evaluated at, with Reynolds' force at each:

* the held-out runs: every state of bearing 1's Reynolds series (``rotor_host.analyses.training.
  scene_series``, run called directly, cached in --cache-dir) of each scene that names the
  surrogate without having trained it (its fit's test scenes and scenes never used);
* off-orbit states, seeded: ``box`` uniform in the fitted domain's box in u, ``beyond``
  uniform in that box widened to twice its half-widths about its centre and outside the box,
  ``near`` a random held-out-run state moved in a random direction of u by a distance drawn
  log-uniformly from [0.002, 0.5] (in CR, omega CR); eccentricity < 0.97 in all three.

A second table gives per machine the guard's radii and, for comparison with r_lin, the distance
from the stored training states at which the median error along 60 random rays reaches 5 %.

The surrogate's error at a state: e = |F_taylor - F_reynolds| / max(|F_reynolds|, |W|), W the
bearing's static load (the file's ``load``); accurate when e < TOL (5 %). The guard's verdict:
out of domain when ``Taylor.domain_distance`` > 0 (the guard's own test, at every call).

* false-alarm rate = flagged accurate states / accurate states,
* miss rate        = inaccurate states inside / inaccurate states.

Machines: the four shipped surrogates (rotor_host/bundled/surrogates/) with their scenes, and the Friswell
rotor (rotor_host/bundled/rotor_friswell.toml) at 25 Hz, for which this script writes scenes of other
unbalances into --work-dir and fits a surrogate (``rotor_host.analyses.training.fit_scene``) on one of
them, the scene's default recipe without designed samples or pruning (~1 s beside the series;
the series take ~15 s each, the 44 Hz held-out one ~1 min).

    python benchmarks/guard_false_alarms.py --cache-dir /tmp/gcache --work-dir /tmp/gwork [--markdown]
"""
from __future__ import annotations

import argparse
import math
import sys
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

TOL = 0.05  # accurate: error below 5 % of max(|F_reynolds|, |load|)
N_OFF = 600  # off-orbit states per kind and surrogate
ECC_MAX = 0.97  # off-orbit states stay off the wall
LIMIT = 0.5  # the default domain_limit: refused beyond it
RAY_STEPS = 0.003 * 2.0 ** (np.arange(16) / 2)  # error_crossing: distances in u, 0.003-0.54
SHIPPED = ("paper_22hz_16.7N.json", "paper_44hz_16.7N.json", "paper_20hz_800N.json", "paper_10hz_500N.json")

# Friswell rotor at 25 Hz: (scene, unbalance node, mass [kg], phase [deg]); 100 mm radius, 1 s
FRISWELL_TRAIN = ("fr25_train_10g", 3, 0.010, 0.0)
FRISWELL_HELD = (("fr25_heldout_15g", 3, 0.015, 120.0), ("fr25_heldout_20g", 3, 0.020, 240.0),
                 ("fr25_heldout_5g", 3, 0.005, 180.0), ("fr25_heldout_node5", 5, 0.010, 90.0))


def friswell_scene(folder: Path, name, node, mass, phase) -> Path:
    """A 1 s scene of the Friswell rotor at 25 Hz with one unbalance (100 mm radius)."""
    path = folder / f"{name}.toml"
    path.write_text(f'name = "{name}"\nrotor = "{ROOT / "rotor_host" / "bundled" / "rotor_friswell.toml"}"\ninternal = "reynolds"\n'
                    f'via = "direct"\nspeed_hz = 25.0\n[time]\nt_end_s = 1.0\ndt_s = 1e-4\n[[unbalance]]\n'
                    f'node = {node}\nmass_kg = {mass}\nradius_mm = 100.0\nphase_deg = {phase}\n[record]\n'
                    f'nodes = [3, 5]\n[taylor]\nsurrogate = "friswell_25hz.json"\n')
    return path


def fit(recipe, out: Path, cache: Path) -> Path:
    from bearing_fmu.fitting import save_fit
    from rotor_host.analyses.training import fit_scene

    return save_fit(fit_scene(recipe, cache_dir=cache, log=lambda m: print("  " + m, file=sys.stderr)), out)


def serving_scenes(surrogate: Path) -> list[Path]:
    """The scenes of rotor_host/bundled/scenes/ whose [taylor] surrogate is this file."""
    out = []
    for p in sorted((ROOT / "rotor_host" / "bundled" / "scenes").glob("*.toml")):
        name = (tomllib.loads(p.read_text()).get("taylor") or {}).get("surrogate")
        if name and (p.parent / name).resolve() == surrogate.resolve():
            out.append(p)
    return out


def cases(args) -> list[tuple[str, Path, list[tuple[Path, int]]]]:
    """(machine, surrogate file, [(held-out scene, bearing number)]) for every machine."""
    from bearing_fmu.fitting import FitRecipe, recipe_of
    from bearing_fmu.surrogates.surrogate import load_surrogate

    out = []
    for name in SHIPPED:
        f = ROOT / "rotor_host" / "bundled" / "surrogates" / name
        recipe = recipe_of(load_surrogate(f), f)
        train = {Path(p).resolve() for p in recipe.scenes}
        held = [(p, 1) for p in serving_scenes(f) if p.resolve() not in train]
        out.append((name.removesuffix(".json"), f, held))
    folder = args.work_dir / "friswell"
    folder.mkdir(parents=True, exist_ok=True)
    train = friswell_scene(folder, *FRISWELL_TRAIN)
    held = [friswell_scene(folder, *h) for h in FRISWELL_HELD]
    recipe = FitRecipe(scenes=(str(train),), test_scenes=(str(held[0]),), designed=0, prune=False)
    f = fit(recipe, folder / "friswell_25hz.json", args.cache_dir)
    out.append(("friswell 25 Hz", f, [(p, 1) for p in held] + [(held[0], 2)]))
    return out


def reynolds_for(scene_path: Path, bearing: int):
    """The scene's Reynolds internal (its grid and options) for bearing number ``bearing``."""
    from bearing_fmu import internals as registry
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from rotor_host.model.rotor import Rotor
    from rotor_host.scenes.scene import load_scene

    sc = load_scene(scene_path)
    params = Rotor.from_toml(sc.rotor_path).bearings[bearing - 1]
    return Reynolds.from_options(params, registry.get("reynolds").check_options(sc.internal_options("reynolds")))


def off_orbit(sur, held_states: np.ndarray, rng) -> dict[str, np.ndarray]:
    """Raw off-orbit states (see the module doc), N_OFF of each kind."""
    d = sur.domain
    lo, hi = np.array(d.box_lo), np.array(d.box_hi)
    c, h = 0.5 * (lo + hi), 0.5 * (hi - lo)
    scale = np.array([sur.pos_scale, sur.pos_scale, sur.vel_scale, sur.vel_scale])
    shift = np.array([sur.y0, sur.z0, 0.0, 0.0])
    u_held = sur.scaled(held_states)

    def draw(kind, n):
        if kind == "box":
            return c + h * rng.uniform(-1, 1, (n, 4))
        if kind == "beyond":
            u = c + 2 * h * rng.uniform(-1, 1, (n, 4))
            return u[np.any(np.abs(u - c) > h, axis=1)]
        v = rng.normal(size=(n, 4))
        v /= np.linalg.norm(v, axis=1)[:, None]
        return u_held[rng.integers(len(u_held), size=n)] + v * np.exp(rng.uniform(math.log(2e-3), math.log(0.5), (n, 1)))

    out = {}
    for kind in ("box", "beyond", "near"):
        got = np.empty((0, 4))
        while len(got) < N_OFF:
            raw = draw(kind, 4 * N_OFF) * scale + shift
            raw = raw[np.hypot(raw[:, 0], raw[:, 1]) < ECC_MAX * sur.params.CR]
            got = np.vstack([got, raw])
        out[kind] = got[:N_OFF]
    return out


def truth_at(rey, omega, states, cache: Path | None) -> np.ndarray:
    if cache is not None and cache.is_file():
        d = np.load(cache)
        if d["states"].shape == states.shape and np.array_equal(d["states"], states):
            return d["forces"]
    forces = np.array([rey.force(*s, omega) for s in states])
    if cache is not None:
        np.savez(cache, states=states, forces=forces)
    return forces


def verdict(tay, states, forces, load) -> dict:
    """Counts of the guard's verdict against the surrogate's error at each state."""
    from bearing_fmu.internals.taylor.guard import DomainGuard
    from bearing_fmu.internals import BearingStateError

    ft = np.array([tay.force(*s, tay.omega) for s in states])
    err = np.hypot(*(ft - forces).T) / np.maximum(np.hypot(*forces.T), load)
    d = np.array([tay.domain_distance(*s) for s in states])
    flag = ~(d <= 1e-12)
    acc = err < TOL
    g = DomainGuard(tay, "warn", LIMIT, on_warn=lambda m: None)  # what a run under the default limit refuses
    refused = 0
    for s in states:
        try:
            g.force(*s, tay.omega)
        except BearingStateError:
            refused += 1
    return {"n": len(states), "acc": int(acc.sum()), "flag": int(flag.sum()), "fa": int((flag & acc).sum()),
            "inacc": int((~acc).sum()), "miss": int((~flag & ~acc).sum()), "refused": refused,
            "err": err, "d": d}


def error_crossing(tay, rey, load, rng, n_rays: int = 60) -> float:
    """The distance in u from the stored training states at which the median of Reynolds'
    disagreement with the fit, along n_rays random rays (random stored state, isotropic random
    direction of u), reaches TOL: what r_lin estimates without the truth. Log-log interpolated
    between RAY_STEPS (inf if never reached there); rays are dropped at eccentricity >= ECC_MAX."""
    sur = tay.surrogate
    scale = np.array([sur.pos_scale, sur.pos_scale, sur.vel_scale, sur.vel_scale])
    pts = sur.neighbours.points[rng.integers(len(sur.neighbours.points), size=n_rays)]
    v = rng.normal(size=(n_rays, 4))
    v /= np.linalg.norm(v, axis=1)[:, None]
    med = []
    for r in RAY_STEPS:
        raw = (pts + r * v) * scale + [sur.y0, sur.z0, 0.0, 0.0]
        raw = raw[np.hypot(raw[:, 0], raw[:, 1]) < ECC_MAX * sur.params.CR]
        fr = np.array([rey.force(*x, sur.omega) for x in raw])
        ft = np.array([tay.force(*x, sur.omega) for x in raw])
        med.append(np.median(np.hypot(*(ft - fr).T) / np.maximum(np.hypot(*fr.T), load)))
    med = np.array(med)
    if not np.any(med >= TOL):
        return math.inf
    j = int(np.argmax(med >= TOL))
    if j == 0:
        return float(RAY_STEPS[0])
    t = math.log(TOL / med[j - 1]) / math.log(med[j] / med[j - 1])
    return float(RAY_STEPS[j - 1] * (RAY_STEPS[j] / RAY_STEPS[j - 1]) ** t)


def rate(k: int, n: int) -> str:
    return "-" if n == 0 else f"{100 * k / n:.3g} % ({k}/{n})"


def main(argv=None) -> int:
    from bearing_fmu.internals.taylor.nearest import linear_radius
    from bearing_fmu.surrogates.surrogate import load_surrogate
    from bearing_fmu.internals.taylor import Taylor
    from rotor_host.scenes.scene import load_scene
    from rotor_host.analyses.training import scene_series

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache-dir", type=Path, required=True, help="Reynolds series and forces (reused)")
    ap.add_argument("--work-dir", type=Path, required=True, help="the Friswell scenes and its fit")
    ap.add_argument("--markdown", action="store_true", help="print a markdown table")
    ap.add_argument("--save", type=Path, help="write every state's error and domain distance (npz)")
    args = ap.parse_args(argv)
    args.cache_dir.mkdir(parents=True, exist_ok=True)
    args.work_dir.mkdir(parents=True, exist_ok=True)
    rows, radii = [], []
    for machine, f, held in cases(args):
        sur = load_surrogate(f)
        tay = Taylor(sur)
        load = math.hypot(*sur.load)
        near = tay.neighbours
        rey = reynolds_for(held[0][0], 1)
        radii.append((machine, near.cv_radius, linear_radius(tay, sur.neighbours.points), near.radius, near.size,
                      error_crossing(tay, rey, load, np.random.default_rng(5))))
        all_held = []
        for scene_path, bearing in held:
            sc = load_scene(scene_path)
            _, states, forces, _ = scene_series(sc, bearing, args.cache_dir / f"{scene_path.stem}_b{bearing}_series.npz",
                                                log=lambda m: print("  " + m, file=sys.stderr))
            if bearing == 1:
                all_held.append(states)
            what = f"{scene_path.stem}" + (f" (bearing {bearing})" if bearing != 1 else "")
            rows.append({"machine": machine, "states": what, **verdict(tay, states, forces, load)})
        rng = np.random.default_rng(22)
        for kind, states in off_orbit(sur, np.vstack(all_held), rng).items():
            forces = truth_at(rey, sur.omega, states, args.cache_dir / f"off_{f.stem}_{kind}.npz")
            rows.append({"machine": machine, "states": f"off-orbit: {kind}", **verdict(tay, states, forces, load)})
        print(f"{machine}: done", file=sys.stderr, flush=True)
    if args.save:
        np.savez(args.save, **{f"{r['machine']}|{r['states']}|{k}": r[k] for r in rows for k in ("err", "d")})
    if args.markdown:
        print("| machine | states | n | accurate (e < 5 %) | flagged | false alarms (flagged / accurate) | "
              "misses (inside / inaccurate) | refused (d > 0.5) |")
        print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        if args.markdown:
            print(f"| {r['machine']} | {r['states']} | {r['n']} | {r['acc']} | {r['flag']} | {rate(r['fa'], r['acc'])} | "
                  f"{rate(r['miss'], r['inacc'])} | {r['refused']} |")
        else:
            print({k: v for k, v in r.items() if k not in ("err", "d")})
    print("\n| machine | r_cv (stored spacing) | r_lin (fit checked) | radius | size | Reynolds' median error "
          "reaches 5 % at |\n|---|---|---|---|---|---|")
    for r in radii:
        print("| " + " | ".join([r[0]] + [f"{x:.3g}" for x in r[1:]]) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
