"""Scene-trained Taylor surrogates: the paper's way (section 3).

A Reynolds co-simulation of a scene, transient included, gives the time series
(y, z, vy, vz, Fy, Fz) of one bearing; the surrogate is fitted to it around that bearing's
static equilibrium. The series is cut into blocks of a few shaft revolutions and every fifth
block is held out, so the reported error is measured on states the fit never saw, spread
over the whole run (a held-out tail would be an extrapolation along a growing orbit). A
second scene (``test_scenes``) adds held-out data from another trajectory: a surrogate that
only works on its own training orbit is not worth shipping.

The series is computed with the internal called directly (identical to the FMU run to
round-off, see tests/test_cosim.py) and cached as ``<name>_series.npz`` beside the output,
so refitting at another order does not rerun the scene.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from .scene import Scene, load_scene, run_scene

HOLDOUT_EVERY = 5  # every 5th block is held out
BLOCK_REVS = 2.0  # block length in shaft revolutions


def scene_series(scene: Scene, bearing: int = 1, cache: Path | None = None, log=print):
    """Reynolds time series of bearing number ``bearing`` (1-based, in rotor order) of the scene:
    (t (M,), states (M, 4) [m, m/s], forces (M, 2) [N], load (2,) [N]). Cached in ``cache``
    (an .npz path) when given: a cached series of the same scene, grid and span is reused."""
    rey = scene.with_internal("reynolds", via="direct")
    key = np.array([rey.speed_hz, rey.t_end_s, rey.dt_s, rey.n_theta or 0, rey.n_x or 0, bearing], float)
    if cache is not None and Path(cache).is_file():
        d = np.load(cache)
        if "key" in d.files and d["key"].shape == key.shape and np.allclose(d["key"], key):
            return d["t"], d["states"], d["forces"], d["load"]
    log(f"running {scene.name} with the Reynolds internal for {rey.t_end_s:g} s to record the training series ...")
    run = run_scene(rey, None, progress=False)
    if run.meta["status"] != "ok":
        raise RuntimeError(f"{scene.source}: the Reynolds training run failed: {run.meta['message']}")
    a = run.arrays
    nodes = list(a["nodes"])
    bnodes = list(a["bearing_nodes"])
    if not 1 <= bearing <= len(bnodes):
        raise ValueError(f"bearing = {bearing}: the rotor has bearings 1..{len(bnodes)}")
    c = nodes.index(bnodes[bearing - 1])
    states = np.column_stack([a[k][:, c] for k in ("y", "z", "vy", "vz")])
    forces = np.column_stack([a["Fy"][:, c], a["Fz"][:, c]])
    load = np.array(run.meta["bearing_loads_N"][bearing - 1], float)
    if cache is not None:
        Path(cache).parent.mkdir(parents=True, exist_ok=True)
        np.savez(cache, key=key, t=a["t"], states=states, forces=forces, load=load)
    return a["t"], states, forces, load


def holdout_mask(t: np.ndarray, speed_hz: float, every: int = HOLDOUT_EVERY, revs: float = BLOCK_REVS):
    """True for the samples held out: every ``every``-th block of ``revs`` shaft revolutions
    (shorter blocks on a short series, so that it has at least 5 * ``every`` blocks)."""
    t = np.asarray(t)
    span_revs = (t[-1] - t[0]) * speed_hz if len(t) else 0.0
    revs = min(revs, span_revs / (5 * every)) if span_revs > 0 else revs
    block = np.floor((t - t[0]) * speed_hz / revs).astype(int)
    return block % every == every - 1


DESIGNED = 2000  # designed samples added over the domain the series spans


def fit_scene(scene_path, order: int = 5, *, bearing: int = 1, test_scenes=(), stride: int = 2,
              cache_dir=None, lam="cv", prune: bool = True, prune_tol: float = 0.05, anchor: bool = True,
              designed: int = DESIGNED, designed_ecc_max: float | None = None,
              designed_v_max: float | None = None, seed: int = 1, log=print):
    """Fit a Taylor surrogate to the Reynolds series of a scene. Returns the FitResult with
    the held-out block errors in ``surrogate.errors["test_*"]`` and, per test scene, its
    NRMSE in ``surrogate.errors["other_scenes"]``."""
    from bearing_fmu import fit as F
    from bearing_fmu.reynolds import Reynolds

    scene = load_scene(scene_path)
    cache_dir = Path(cache_dir) if cache_dir is not None else None

    def cached(sc):
        return None if cache_dir is None else cache_dir / f"{Path(sc.source).stem}_b{bearing}_series.npz"

    t, states, forces, load = scene_series(scene, bearing, cached(scene), log)
    t, states, forces = t[::stride], states[::stride], forces[::stride]
    params = _bearing_params(scene, bearing)
    truth = Reynolds(params, n_theta=scene.n_theta, n_x=scene.n_x)
    omega = scene.omega
    y0, z0 = F.expansion_point(truth, tuple(load), omega)
    held = holdout_mask(t, scene.speed_hz)
    train = ~held
    domain = F.domain_from_data(states[train], y0, z0, params, omega)
    s_fit, f_fit = states[train], forces[train]
    if designed:
        # A fit to one orbit alone is exact on it and wild off it (the series spans a thin set
        # of the 4-D state space: cond(X) ~ 1e10), and a rotor run with the surrogate leaves
        # that orbit at once. Reynolds forces at states spread over the domain the orbit spans
        # make the fit hold between orbits too.
        # Near the wall the film force grows without bound; a polynomial cannot follow it
        # there and the designed samples then spoil the fit everywhere: designed_ecc_max and
        # designed_v_max keep them to the inner part of the domain (the series covers the rest).
        ecc_d = min(domain.ecc_max, designed_ecc_max or domain.ecc_max)
        v_d = min(domain.v_max, designed_v_max or domain.v_max)
        s_d, f_d, _ = F.designed_samples(truth, y0, z0, omega, ecc_d, v_d, designed, seed,
                                         radius=domain.pos_radius)
        s_fit, f_fit = np.vstack([s_fit, s_d]), np.vstack([f_fit, f_d])
    anc = F.truth_jacobian(truth, y0, z0, omega) if anchor else None
    prov = {"truth": "Reynolds", "truth_n_theta": truth.n_theta, "truth_n_x": truth.n_x,
            "truth_cavitation": truth.cavitation,
            "training_source": f"scene {Path(scene.source).name}",
            "scene_t_end_s": scene.t_end_s, "scene_dt_s": scene.dt_s, "bearing": bearing, "stride": stride,
            "designed_samples": designed, "designed_seed": seed, "designed_ecc_max": designed_ecc_max,
            "designed_v_max": designed_v_max,
            "held_out": f"every {HOLDOUT_EVERY}th block of (at most) {BLOCK_REVS:g} revolutions of the series",
            "fit_call": {"scene": str(Path(scene.source).resolve()), "bearing": bearing, "stride": stride,
                         "test_scenes": [str(Path(p).resolve()) for p in test_scenes], "lam": lam,
                         "prune": prune, "prune_tol": prune_tol, "anchor": anchor, "designed": designed,
                         "designed_ecc_max": designed_ecc_max, "designed_v_max": designed_v_max, "seed": seed}}
    res = F.fit_surrogate(s_fit, f_fit, params, omega, y0, z0, order, domain=domain,
                          lam=lam, blocked=True, prune=prune, prune_tol=prune_tol, load=tuple(load),
                          test=(states[held], forces[held]), provenance=prov, anchor=anc)
    others = {}
    for p in test_scenes:
        other = load_scene(p)
        if not math.isclose(other.speed_hz, scene.speed_hz, rel_tol=1e-12):
            raise ValueError(f"test scene {p}: speed {other.speed_hz} Hz differs from the training scene's "
                             f"{scene.speed_hz} Hz; a surrogate holds at one speed")
        _, s2, f2, _ = scene_series(other, bearing, cached(other), log)
        pred = res.surrogate.predict(s2[::stride])
        err = F.nrmse(pred, f2[::stride])
        tay_dist = _domain_fraction(res.surrogate, s2[::stride])
        others[Path(other.source).name] = {"nrmse": dict(zip(F.COMPONENTS, err.tolist())),
                                           "out_of_domain_fraction": tay_dist}
    if others:
        res.surrogate.errors["other_scenes"] = others
        res.report["errors"]["other_scenes"] = others
    eq = math.hypot(y0, z0) / params.CR
    res.report.update({"speed_hz": scene.speed_hz, "load": list(load), "equilibrium": [y0, z0], "eps0": eq,
                       "domain": domain.to_dict()})
    return res


def _bearing_params(scene: Scene, bearing: int):
    from .rotor import Rotor

    rotor = Rotor.from_toml(scene.rotor_path)
    return rotor.bearings[bearing - 1]


def _domain_fraction(surrogate, states) -> float:
    from bearing_fmu.taylor import Taylor

    tay = Taylor(surrogate)
    return float(np.mean([tay.domain_distance(*s) > 1e-12 for s in states]))


def refit(surrogate_path, order: int, out_path, cache_dir=None, log=print):
    """The surrogate of ``surrogate_path`` refitted at another order from the same data (the
    call stored in its provenance): for order studies. Writes and returns ``out_path``."""
    from bearing_fmu.fit import refit_order
    from bearing_fmu.taylor import load_surrogate, save_surrogate

    base = load_surrogate(surrogate_path)
    call = base.provenance.get("fit_call")
    if call is None or "scene" not in call:
        return refit_order(surrogate_path, order, out_path)
    here = Path(surrogate_path).resolve().parent
    scene = _locate(call["scene"], here, surrogate_path)
    tests = [_locate(p, here, surrogate_path) for p in call.get("test_scenes", ())]
    res = fit_scene(scene, order, bearing=call["bearing"], test_scenes=tests,
                    stride=call["stride"], cache_dir=cache_dir, lam=call["lam"], prune=call["prune"],
                    prune_tol=call["prune_tol"], anchor=call["anchor"], designed=call.get("designed", 0),
                    designed_ecc_max=call.get("designed_ecc_max"), designed_v_max=call.get("designed_v_max"),
                    seed=call.get("seed", 1), log=log)
    portable_fit_call(res.surrogate, out_path)
    return save_surrogate(res.surrogate, out_path)


def portable_fit_call(surrogate, out_path) -> None:
    """Store the scene paths of ``provenance["fit_call"]`` relative to the folder of the file
    the surrogate is written to, so a refit works in another clone or checkout."""
    call = surrogate.provenance.get("fit_call") or {}
    if "scene" not in call:
        return
    folder = Path(out_path).resolve().parent

    def rel(p):
        return Path(os.path.relpath(Path(p).resolve(), folder)).as_posix()

    call["scene"] = rel(call["scene"])
    call["test_scenes"] = [rel(p) for p in call.get("test_scenes", ())]


def _locate(path, folder: Path, surrogate_path) -> Path:
    p = Path(path)
    p = p if p.is_absolute() else folder / p
    if not p.is_file():
        raise FileNotFoundError(f"{surrogate_path}: its fit call names the scene {path}, which is not at {p}; "
                                "refit it with `bearing-fmu fit --scene ...`")
    return p


__all__ = ["scene_series", "holdout_mask", "fit_scene", "refit", "portable_fit_call"]
