"""Scene-trained Taylor surrogates: the paper's way (section 3).

A Reynolds co-simulation of a scene, transient included, gives the time series
(y, z, vy, vz, Fy, Fz) of one bearing; the surrogate is fitted to it around that bearing's
static equilibrium. The series is cut into blocks of a few shaft revolutions and every fifth
block is held out, so the reported error is measured on states the fit never saw, spread
over the whole run (a held-out tail would be an extrapolation along a growing orbit). A
second scene (``test_scenes``) adds held-out data from another trajectory: a surrogate that
only works on its own training orbit is not worth shipping. Several training scenes (other
unbalances at the same speed and load, rotor_host/bundled/scenes/train_*.toml) can be fitted together.

The series is computed with the internal called directly (identical to the FMU run to
round-off, see tests/test_cosim.py) and cached as ``<name>_b<bearing>_series.npz`` in a folder
beside the output, so refitting at another order does not rerun the scene.

The settings of a fit are a :class:`bearing_fmu.fitting.FitRecipe` (its scene-training
part: scenes, test scenes, bearing number, stride, designed samples, row weights), stored in
the surrogate file; ``refit`` reads it back. The command is ``rotor-host fit`` (``add_arguments``,
``run``); ``bearing-fmu fit`` keeps the designed-domain fit of one bearing.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from bearing_fmu.fitting.recipe import FitRecipe, recipe_of
from bearing_fmu.internals import registry
from bearing_fmu.io.outputs import savez

from ..scenes.run import run_scene
from ..scenes.scene import Scene, load_scene

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
        # atomic: an interrupted fit keeps every finished series and never a half-written one
        savez(cache, key=key, t=a["t"], states=states, forces=forces, load=load)
    return a["t"], states, forces, load


def holdout_mask(t: np.ndarray, speed_hz: float, every: int = HOLDOUT_EVERY, revs: float = BLOCK_REVS):
    """True for the samples held out: every ``every``-th block of ``revs`` shaft revolutions
    (shorter blocks on a short series, so that it has at least 5 * ``every`` blocks)."""
    t = np.asarray(t)
    span_revs = (t[-1] - t[0]) * speed_hz if len(t) else 0.0
    revs = min(revs, span_revs / (5 * every)) if span_revs > 0 else revs
    block = np.floor((t - t[0]) * speed_hz / revs).astype(int)
    return block % every == every - 1


def fit_scene(recipe: FitRecipe, *, cache_dir=None, log=print):
    """Fit a Taylor surrogate to the Reynolds series of the scene-trained ``recipe``: its
    ``scenes`` at the same speed and bearing load (other unbalances give other trajectories,
    so the fit sees more of the state space the rotor can reach), bearing number
    ``recipe.bearing_number``, every ``stride``-th step. Every fifth block of each series is
    held out. Returns the FitResult with the held-out block errors (all training scenes
    together) in ``surrogate.errors["test_*"]`` and, per test scene (``test_scenes``), its
    NRMSE in ``surrogate.errors["other_scenes"]``. Series are cached in ``cache_dir``.

    ``designed`` Reynolds samples are added: over the discs the series span (bounded by
    ``designed_ecc_max``, ``designed_v_max``), or with ``designed_tube`` (scaled units: CR and
    omega CR) in a tube of that radius about the recorded training states. Each designed row
    weighs ``designed_weight`` against a series row (1 = equal) in the least-squares fit.

    ``ecc_weight`` = p > 0 weighs every row by (1 - eps^2)^p (eps: its eccentricity ratio):
    near the wall the film force grows without bound and a polynomial cannot follow it; with
    equal weights those rows dominate the least squares and spoil the fit where the journal
    spends its transient (44 Hz: the growth of the whirl, whose phase then drifts).

    The model settings (order, lambda, pruning, wall factor ``wall_power``, short-bearing shape
    columns ``shape_order``): see :class:`bearing_fmu.fitting.FitRecipe` and
    :func:`bearing_fmu.fitting.fit_surrogate`.

    ``truth_map``: the designed (or tube) samples come from that force map instead of Reynolds
    (bearing_fmu.fitting.truth); the series, the equilibrium and the anchor stay Reynolds. The
    map is checked before any scene runs."""
    from bearing_fmu import fitting as F
    from bearing_fmu.fitting.truth import fit_truth
    from bearing_fmu.physics.solver.reynolds import Reynolds

    if recipe.kind != "scene":
        raise ValueError("fit_scene: the recipe names no training scene (scenes)")
    r = recipe
    bearing = r.bearing_number
    scenes = [load_scene(p) for p in r.scenes]
    scene = scenes[0]
    params = _bearing_params(scene, bearing)  # before any run: a bearing number the rotor lacks is named now
    if params.geometry.pads is not None:
        raise ValueError(f"{scene.source}: bearing {bearing} has tilting pads: a Taylor surrogate's inputs are the "
                         "journal's (y, z, vy, vz), and the pads' force also depends on the pads' own tilts and "
                         "their history; run it with the tilting_pad internal or the pads' force map (`bearing-fmu "
                         "map --bearing FILE`; docs/geometry.md, Tilting pads)")
    truth = Reynolds.from_options(params, registry.get("reynolds").check_options(scene.internal_options("reynolds")))
    # before any run too: a map that does not serve this bearing or grid is named now
    samples_truth = fit_truth(r, params, truth, grid_hint="build a map on the scenes' Reynolds grid "
                                                          "(`bearing-fmu map --grid N_THETAxN_X`)")
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
        t, states, forces = t[::r.stride], states[::r.stride], forces[::r.stride]
        held = holdout_mask(t, sc.speed_hz)
        tr_states.append(states[~held])
        tr_forces.append(forces[~held])
        ho_states.append(states[held])
        ho_forces.append(forces[held])
    s_train, f_train = np.vstack(tr_states), np.vstack(tr_forces)
    omega = scene.omega
    y0, z0 = F.expansion_point(truth, tuple(load), omega)
    domain = F.domain_from_data(s_train, y0, z0, params, omega)
    s_fit, f_fit = s_train, f_train
    weights = None
    t_samples = 0.0
    if r.designed:
        # A fit to one orbit alone is exact on it and wild off it (the series spans a thin set
        # of the 4-D state space: cond(X) ~ 1e10), and a rotor run with the surrogate leaves
        # that orbit at once. Reynolds forces at states spread over the domain the orbit spans
        # make the fit hold between orbits too.
        # Near the wall the film force grows without bound; a polynomial cannot follow it
        # there and the designed samples then spoil the fit everywhere: designed_ecc_max and
        # designed_v_max keep them to the inner part of the domain (the series covers the rest).
        ecc_d = min(domain.ecc_max, r.designed_ecc_max or domain.ecc_max)
        samples_truth.check_reach(ecc_d, "the designed samples' eccentricity bound (designed_ecc_max, else the "
                                         "series' largest)")
        if not r.designed_tube:
            from scipy.stats import qmc  # noqa: F401 -- the design's sampler, imported before the clock

        t0 = time.perf_counter()
        if r.designed_tube:
            s_d, f_d = F.tube_samples(samples_truth.samples, s_train, y0, z0, omega, r.designed_tube, r.designed,
                                      r.seed, ecc_max=ecc_d)
        else:
            v_d = min(domain.v_max, r.designed_v_max or domain.v_max)
            s_d, f_d, _ = F.designed_samples(samples_truth.samples, y0, z0, omega, ecc_d, v_d, r.designed, r.seed,
                                             radius=domain.pos_radius)
        t_samples = time.perf_counter() - t0
        s_fit, f_fit = np.vstack([s_fit, s_d]), np.vstack([f_fit, f_d])
        if r.designed_weight != 1.0:
            weights = np.concatenate([np.ones(len(s_train)), np.full(len(s_d), float(r.designed_weight))])
    if r.ecc_weight:
        ecc = np.hypot(s_fit[:, 0], s_fit[:, 1]) / params.CR
        w_ecc = np.clip(1.0 - ecc**2, 0.0, None) ** r.ecc_weight
        weights = w_ecc if weights is None else weights * w_ecc
    anc = F.truth_jacobian(truth, y0, z0, omega) if r.anchor else None
    names = ", ".join(Path(sc.source).name for sc in scenes)
    prov = {**samples_truth.provenance(),
            "training_source": f"scene{'s' if len(scenes) > 1 else ''} {names}",
            "scene_t_end_s": [sc.t_end_s for sc in scenes] if len(scenes) > 1 else scene.t_end_s,
            "scene_dt_s": scene.dt_s,
            "held_out": f"every {HOLDOUT_EVERY}th block of (at most) {BLOCK_REVS:g} revolutions of each series"}
    res = F.fit_surrogate(s_fit, f_fit, params, omega, y0, z0, r, domain=domain, anchor=anc, weights=weights,
                          blocked=True, test=(np.vstack(ho_states), np.vstack(ho_forces)), load=tuple(load),
                          provenance=prov)
    # the film's flows from the same truth (the series' Reynolds, or the map) at the training states
    F.attach_film(res, samples_truth, s_fit, test_states=np.vstack(ho_states), seed=r.seed, log=log)
    others = {}
    for p in r.test_scenes:
        other = load_scene(p)
        check_speed(other, "test scene")
        _, s2, f2, _ = scene_series(other, bearing, cached(other), log)
        pred = res.surrogate.predict(s2[::r.stride])
        err = F.nrmse(pred, f2[::r.stride])
        tay_dist = _domain_fraction(res.surrogate, s2[::r.stride])
        others[Path(other.source).name] = {"nrmse": dict(zip(F.COMPONENTS, err.tolist())),
                                           "out_of_domain_fraction": tay_dist}
    if others:
        res.surrogate.errors["other_scenes"] = others
        res.report["errors"]["other_scenes"] = others
    eq = math.hypot(y0, z0) / params.CR
    res.report.update({"speed_hz": scene.speed_hz, "load": list(load), "equilibrium": [y0, z0], "eps0": eq,
                       "domain": domain.to_dict(), "sampling_seconds": t_samples})
    return res


def _bearing_params(scene: Scene, bearing: int):
    """The BearingParams of bearing number ``bearing`` (1-based) of the scene's rotor."""
    from ..model.rotor import Rotor

    rotor = Rotor.from_toml(scene.rotor_path)
    if not 1 <= bearing <= len(rotor.bearings):
        raise ValueError(f"--bearing-number {bearing}: the rotor of {scene.source} has bearings "
                         f"1..{len(rotor.bearings)}")
    return rotor.bearings[bearing - 1]


def _domain_fraction(surrogate, states) -> float:
    from bearing_fmu.internals.taylor import Taylor

    tay = Taylor(surrogate)
    return float(np.mean([tay.domain_distance(*s) > 1e-12 for s in states]))


# ----------------------------------------------------------------------------- refit

def refit(surrogate_path, order: int, out_path, cache_dir=None, log=print, *, surrogate=None) -> Path:
    """The surrogate of ``surrogate_path`` refitted at another order from the same data (its
    recipe, read once): for order studies. Scene-trained files rerun (or read from
    ``cache_dir``) their scenes' series; designed-domain files their design. Writes and
    returns ``out_path``. ``surrogate``: the file's content if the caller has read it already."""
    from bearing_fmu.fitting import refit_order, save_fit
    from bearing_fmu.surrogates.surrogate import load_surrogate

    sur = load_surrogate(surrogate_path) if surrogate is None else surrogate
    recipe = recipe_of(sur, surrogate_path)
    if recipe.kind != "scene":
        return refit_order(surrogate_path, order, out_path, surrogate=sur)
    _scenes_present(recipe, surrogate_path)
    return save_fit(fit_scene(recipe.with_order(order), cache_dir=cache_dir, log=log), out_path)


def training_scenes(surrogate_path) -> tuple[list[Path], list[Path]]:
    """(training scenes, held-out test scenes) of a scene-trained surrogate file, as paths
    (its recipe stores them relative to the file); ([], []) for a designed-domain fit."""
    from bearing_fmu.surrogates.surrogate import load_surrogate

    recipe = recipe_of(load_surrogate(surrogate_path), surrogate_path)
    if recipe.kind != "scene":
        return [], []
    _scenes_present(recipe, surrogate_path)
    return [Path(p) for p in recipe.scenes], [Path(p) for p in recipe.test_scenes]


def _scenes_present(recipe: FitRecipe, surrogate_path) -> None:
    for p in (*recipe.scenes, *recipe.test_scenes):
        if not Path(p).is_file():
            raise FileNotFoundError(f"{surrogate_path}: its fit recipe names the scene {p}, which is not there; "
                                    "fit it again with `rotor-host fit --scene ...`")


# ----------------------------------------------------------------------------- rotor-host fit

def command(*, recipe: FitRecipe, output, cache_dir=None, plots=None, note: str | None = None) -> int:
    """``rotor-host fit``: fit ``recipe`` to the Reynolds series of its scenes (cached in
    ``cache_dir``, default series/ beside ``output``), write the file ``output`` (scene paths
    relative to it), print the report, write the lambda plots into the folder ``plots``."""
    from bearing_fmu.fitting.output import check_outputs, write_fit

    if not recipe.scenes:
        raise ValueError("--scene: give at least one training scene (rotor_host/bundled/scenes/*.toml)")
    check_outputs(output, plots)
    cache = Path(cache_dir) if cache_dir else Path(output).resolve().parent / "series"
    res = fit_scene(recipe, cache_dir=cache)
    scene = load_scene(recipe.scenes[0])
    res.surrogate.provenance["bearing"] = f"bearing {recipe.bearing_number} of {scene.rotor_path.name}"
    return write_fit(res, output, plots=plots, note=note)


__all__ = ["scene_series", "holdout_mask", "fit_scene", "refit", "training_scenes", "command"]
