"""Scene-trained Taylor surrogates: the paper's way (section 3).

A Reynolds co-simulation of a scene, transient included, gives the time series
(y, z, vy, vz, Fy, Fz) of one bearing; the surrogate is fitted to it around that bearing's
static equilibrium. The series is cut into blocks of a few shaft revolutions and every fifth
block is held out, so the reported error is measured on states the fit never saw, spread
over the whole run (a held-out tail would be an extrapolation along a growing orbit). A
second scene (``test_scenes``) adds held-out data from another trajectory: a surrogate that
only works on its own training orbit is not worth shipping. Several training scenes (other
unbalances at the same speed and load, models/scenes/train_*.toml) can be fitted together.

The series is computed with the internal called directly (identical to the FMU run to
round-off, see tests/test_cosim.py) and cached as ``<name>_series.npz`` beside the output,
so refitting at another order does not rerun the scene.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from bearing_fmu import internals as registry

from .scene import Scene, load_scene, run_scene

SERIES_VERSION = 2  # cache format of scene_series (see there)
HOLDOUT_EVERY = 5  # every 5th block is held out
BLOCK_REVS = 2.0  # block length in shaft revolutions


def scene_series(scene: Scene, bearing: int = 1, cache: Path | None = None, log=print):
    """Reynolds time series of bearing number ``bearing`` (1-based, in rotor order) of the scene:
    (t (M,), states (M, 4) [m, m/s], forces (M, 2) [N], load (2,) [N]). Cached in ``cache``
    (an .npz path) when given: a cached series of the same scene, grid and span is reused."""
    rey = scene.with_internal("reynolds", via="direct")
    # the last entry versions the cache: series cached before forces were taken from the
    # bearing's own column (SERIES_VERSION 2) paired another bearing's force with this one's
    # state whenever the scene also records a node before the bearing, and are recomputed
    grid = rey.internal_options()
    key = np.array([rey.speed_hz, rey.t_end_s, rey.dt_s, grid.get("n_theta", 0), grid.get("n_x", 0), bearing,
                    SERIES_VERSION], float)
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
    c = nodes.index(bnodes[bearing - 1])  # positions and velocities: one column per recorded node
    states = np.column_stack([a[k][:, c] for k in ("y", "z", "vy", "vz")])
    # forces: one column per bearing (not per recorded node)
    forces = np.column_stack([a["Fy"][:, bearing - 1], a["Fz"][:, bearing - 1]])
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
              designed_v_max: float | None = None, designed_weight: float = 1.0,
              designed_tube: float | None = None, ecc_weight: float = 0.0, wall_power: float = 0.0,
              shape_order: int | None = None, seed: int = 1, log=print):
    """Fit a Taylor surrogate to the Reynolds series of a scene, or of several scenes
    (``scene_path`` a list) at the same speed and bearing load: other unbalances give other
    trajectories, so the fit sees more of the state space the rotor can reach. Every fifth
    block of each series is held out. Returns the FitResult with the held-out block errors
    (all training scenes together) in ``surrogate.errors["test_*"]`` and, per test scene, its
    NRMSE in ``surrogate.errors["other_scenes"]``.

    ``designed`` Reynolds samples are added: over the discs the series span (bounded by
    ``designed_ecc_max``, ``designed_v_max``), or with ``designed_tube`` (scaled units: CR and
    omega CR) in a tube of that radius about the recorded training states. Each designed row
    weighs ``designed_weight`` against a series row (1 = equal) in the least-squares fit.

    ``ecc_weight`` = p > 0 weighs every row by (1 - eps^2)^p (eps: its eccentricity ratio):
    near the wall the film force grows without bound and a polynomial cannot follow it; with
    equal weights those rows dominate the least squares and spoil the fit where the journal
    spends its transient (44 Hz: the growth of the whirl, whose phase then drifts).

    ``wall_power`` = p > 0 fits the polynomial to F (1 - eps^2)^p and evaluates
    F = P(u) / (1 - eps^2)^p (the wall factor, see :mod:`bearing_fmu.surrogate`).

    ``shape_order`` = r adds the short-bearing shape columns of order r (see
    :func:`bearing_fmu.fitting.fit_surrogate`); None = the polynomial alone."""
    from bearing_fmu import fitting as F
    from bearing_fmu.reynolds import Reynolds

    paths = [scene_path] if isinstance(scene_path, (str, os.PathLike)) else list(scene_path)
    if not paths:
        raise ValueError("fit_scene: no training scene given")
    if not (ecc_weight >= 0 and math.isfinite(ecc_weight)):
        raise ValueError(f"fit_scene: ecc_weight = {ecc_weight!r} must be finite and >= 0")
    if designed_weight < 0 or not math.isfinite(designed_weight):
        raise ValueError(f"fit_scene: designed_weight = {designed_weight!r} must be finite and >= 0")
    scenes = [load_scene(p) for p in paths]
    scene = scenes[0]
    cache_dir = Path(cache_dir) if cache_dir is not None else None

    def cached(sc):
        return None if cache_dir is None else cache_dir / f"{Path(sc.source).stem}_b{bearing}_series.npz"

    def check_speed(other, what):
        if not math.isclose(other.speed_hz, scene.speed_hz, rel_tol=1e-12):
            raise ValueError(f"{what} {other.source}: speed {other.speed_hz} Hz differs from the training scene's "
                             f"{scene.speed_hz} Hz; a surrogate holds at one speed")

    tr_states, tr_forces, ho_states, ho_forces = [], [], [], []
    load = None
    for sc in scenes:
        check_speed(sc, "training scene")
        t, states, forces, ld = scene_series(sc, bearing, cached(sc), log)
        if load is None:
            load = ld
        elif not np.allclose(ld, load, rtol=1e-9, atol=1e-9 * max(1.0, float(np.max(np.abs(load))))):
            raise ValueError(f"training scene {sc.source}: bearing {bearing} carries {ld.tolist()} N, the first "
                             f"training scene's carries {load.tolist()} N; a surrogate holds at one load")
        t, states, forces = t[::stride], states[::stride], forces[::stride]
        held = holdout_mask(t, sc.speed_hz)
        tr_states.append(states[~held])
        tr_forces.append(forces[~held])
        ho_states.append(states[held])
        ho_forces.append(forces[held])
    s_train, f_train = np.vstack(tr_states), np.vstack(tr_forces)
    params = _bearing_params(scene, bearing)
    truth = Reynolds.from_options(params, registry.get("reynolds").check_options(scene.internal_options("reynolds")))
    omega = scene.omega
    y0, z0 = F.expansion_point(truth, tuple(load), omega)
    domain = F.domain_from_data(s_train, y0, z0, params, omega)
    s_fit, f_fit = s_train, f_train
    weights = None
    if designed:
        # A fit to one orbit alone is exact on it and wild off it (the series spans a thin set
        # of the 4-D state space: cond(X) ~ 1e10), and a rotor run with the surrogate leaves
        # that orbit at once. Reynolds forces at states spread over the domain the orbit spans
        # make the fit hold between orbits too.
        # Near the wall the film force grows without bound; a polynomial cannot follow it
        # there and the designed samples then spoil the fit everywhere: designed_ecc_max and
        # designed_v_max keep them to the inner part of the domain (the series covers the rest).
        ecc_d = min(domain.ecc_max, designed_ecc_max or domain.ecc_max)
        if designed_tube:
            s_d, f_d = F.tube_samples(truth, s_train, y0, z0, omega, designed_tube, designed, seed, ecc_max=ecc_d)
        else:
            v_d = min(domain.v_max, designed_v_max or domain.v_max)
            s_d, f_d, _ = F.designed_samples(truth, y0, z0, omega, ecc_d, v_d, designed, seed,
                                             radius=domain.pos_radius)
        s_fit, f_fit = np.vstack([s_fit, s_d]), np.vstack([f_fit, f_d])
        if designed_weight != 1.0:
            weights = np.concatenate([np.ones(len(s_train)), np.full(len(s_d), float(designed_weight))])
    if ecc_weight:
        ecc = np.hypot(s_fit[:, 0], s_fit[:, 1]) / params.CR
        w_ecc = np.clip(1.0 - ecc**2, 0.0, None) ** ecc_weight
        weights = w_ecc if weights is None else weights * w_ecc
    anc = F.truth_jacobian(truth, y0, z0, omega) if anchor else None
    names = ", ".join(Path(sc.source).name for sc in scenes)
    prov = {"truth": "Reynolds", "truth_n_theta": truth.n_theta, "truth_n_x": truth.n_x,
            "truth_cavitation": truth.cavitation,
            "training_source": f"scene{'s' if len(scenes) > 1 else ''} {names}",
            "scene_t_end_s": [sc.t_end_s for sc in scenes] if len(scenes) > 1 else scene.t_end_s,
            "scene_dt_s": scene.dt_s, "bearing": bearing, "stride": stride,
            "designed_samples": designed, "designed_seed": seed, "designed_ecc_max": designed_ecc_max,
            "designed_v_max": designed_v_max, "designed_weight": designed_weight, "designed_tube": designed_tube,
            "ecc_weight": ecc_weight, "wall_power": wall_power, "shape_order": shape_order,
            "held_out": f"every {HOLDOUT_EVERY}th block of (at most) {BLOCK_REVS:g} revolutions of each series",
            "fit_call": {"scenes": [str(Path(sc.source).resolve()) for sc in scenes], "bearing": bearing,
                         "stride": stride, "test_scenes": [str(Path(p).resolve()) for p in test_scenes],
                         "lam": lam, "prune": prune, "prune_tol": prune_tol, "anchor": anchor,
                         "designed": designed, "designed_ecc_max": designed_ecc_max,
                         "designed_v_max": designed_v_max, "designed_weight": designed_weight,
                         "designed_tube": designed_tube, "ecc_weight": ecc_weight, "wall_power": wall_power,
                         "shape_order": shape_order, "seed": seed}}
    res = F.fit_surrogate(s_fit, f_fit, params, omega, y0, z0, order, domain=domain,
                          lam=lam, blocked=True, prune=prune, prune_tol=prune_tol, load=tuple(load),
                          test=(np.vstack(ho_states), np.vstack(ho_forces)), provenance=prov, anchor=anc,
                          weights=weights, wall_power=wall_power, shape_order=shape_order)
    others = {}
    for p in test_scenes:
        other = load_scene(p)
        check_speed(other, "test scene")
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
    from bearing_fmu.fitting import refit_order
    from bearing_fmu.surrogate import load_surrogate, save_surrogate

    base = load_surrogate(surrogate_path)
    call = base.provenance.get("fit_call")
    if call is None or not ("scene" in call or "scenes" in call):
        return refit_order(surrogate_path, order, out_path)
    scenes, tests = training_scenes(surrogate_path)
    res = fit_scene(scenes if len(scenes) > 1 else scenes[0], order, bearing=call["bearing"], test_scenes=tests,
                    stride=call["stride"], cache_dir=cache_dir, lam=call["lam"], prune=call["prune"],
                    prune_tol=call["prune_tol"], anchor=call["anchor"], designed=call.get("designed", 0),
                    designed_ecc_max=call.get("designed_ecc_max"), designed_v_max=call.get("designed_v_max"),
                    designed_weight=call.get("designed_weight", 1.0), designed_tube=call.get("designed_tube"),
                    ecc_weight=call.get("ecc_weight", 0.0), wall_power=call.get("wall_power", 0.0),
                    shape_order=call.get("shape_order"), seed=call.get("seed", 1), log=log)
    portable_fit_call(res.surrogate, out_path)
    return save_surrogate(res.surrogate, out_path)


def training_scenes(surrogate_path) -> tuple[list[Path], list[Path]]:
    """(training scenes, held-out test scenes) of a scene-trained surrogate file, as paths
    (its fit call stores them relative to the file); ([], []) for a designed-domain fit."""
    from bearing_fmu.surrogate import load_surrogate

    call = load_surrogate(surrogate_path).provenance.get("fit_call") or {}
    if "scene" not in call and "scenes" not in call:
        return [], []
    here = Path(surrogate_path).resolve().parent
    return ([_locate(p, here, surrogate_path) for p in _call_scenes(call)],
            [_locate(p, here, surrogate_path) for p in call.get("test_scenes", ())])


def _call_scenes(call: dict) -> list:
    """The training scenes of a fit call: ``scenes`` (a list), or ``scene`` (files written
    before several training scenes were possible)."""
    if "scenes" in call:
        return list(call["scenes"])
    return [call["scene"]]


def portable_fit_call(surrogate, out_path) -> None:
    """Store the scene paths of ``provenance["fit_call"]`` relative to the folder of the file
    the surrogate is written to, so a refit works in another clone or checkout."""
    call = surrogate.provenance.get("fit_call") or {}
    if "scene" not in call and "scenes" not in call:
        return
    folder = Path(out_path).resolve().parent

    def rel(p):
        return Path(os.path.relpath(Path(p).resolve(), folder)).as_posix()

    for key in ("scene", "scenes"):
        if key in call:
            call[key] = [rel(p) for p in call[key]] if key == "scenes" else rel(call[key])
    call["test_scenes"] = [rel(p) for p in call.get("test_scenes", ())]


def _locate(path, folder: Path, surrogate_path) -> Path:
    p = Path(path)
    p = p if p.is_absolute() else folder / p
    if not p.is_file():
        raise FileNotFoundError(f"{surrogate_path}: its fit call names the scene {path}, which is not at {p}; "
                                "refit it with `bearing-fmu fit --scene ...`")
    return p


__all__ = ["scene_series", "holdout_mask", "fit_scene", "refit", "portable_fit_call", "training_scenes"]
