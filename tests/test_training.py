"""Scene-trained surrogates (rotor_host.analyses.training): the paper's way of fitting, end to end on a
short, coarse scene, and the refit from the stored fit call in another folder."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.fitting import FitRecipe, nrmse
from bearing_fmu.surrogates.surrogate import load_surrogate
from rotor_host.analyses.training import fit_scene, holdout_mask, refit, scene_series
from rotor_host.cli import main as rotor_host
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def training_scene(paper_scene):
    """training_scene(folder, name, mass_g, **overrides): the paper's 22 Hz scene (tests/conftest.py
    ``paper_scene``), 40 ms on a coarse 32 x 8 grid, mass_g grams on the disk: cheap but the same
    physics; the overrides as paper_scene's."""
    return lambda folder, name, mass_g, **kw: paper_scene(**{"folder": folder, "name": name, "t_end": 0.04,
                                                             "grid": (32, 8), "unbalance_g": mass_g, **kw})


def _as_fit_call(d: dict) -> dict:
    """A surrogate file's content as written before FitRecipe: the scene fit's settings in
    provenance["fit_call"] (the bearing number as "bearing"; no order, no k_folds)."""
    r = d["provenance"].pop("recipe")
    call = {"scenes": r["scenes"], "bearing": r["bearing_number"], "stride": r["stride"],
            "test_scenes": r["test_scenes"]}
    call.update({k: r[k] for k in ("lam", "prune", "prune_tol", "anchor", "designed", "designed_ecc_max",
                                   "designed_v_max", "designed_weight", "designed_tube", "ecc_weight", "wall_power",
                                   "shape_order", "seed")})
    d["provenance"]["fit_call"] = call
    return d


def test_holdout_blocks_are_every_fifth():
    # 10 s at 10 Hz: blocks of 2 revolutions = 0.2 s, every 5th held out: [0.8, 1.0), [1.8, 2.0), ...
    t = np.arange(0, 10.0, 1e-3)
    held = holdout_mask(t, 10.0)
    expect = np.floor(t / 0.2 + 1e-9).astype(int) % 5 == 4
    assert np.mean(held != expect) < 1e-3  # only round-off at block edges may differ
    assert abs(held.mean() - 0.2) < 1e-3
    # a 1 s series has 10 revolutions: blocks shrink to 0.4 revolutions so there are 25 of them
    t = np.arange(0, 1.0, 1e-3)
    held = holdout_mask(t, 10.0)
    assert abs(held.mean() - 0.2) < 0.01 and held[(t > 0.161) & (t < 0.199)].all() and not held[t < 0.159].any()


@pytest.mark.slow  # a fit, a figure or a process end to end (about 1 s): the full suite's, out of the quick loop
def test_scene_fit_holds_out_and_refits_elsewhere(tmp_path, training_scene):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    train = training_scene(scenes, "train", 8.5)
    other = training_scene(scenes, "other", 6.0)
    res = fit_scene(FitRecipe(scenes=[train], order=3, test_scenes=[other], designed=200, prune=False),
                    cache_dir=tmp_path / "series", log=lambda *_: None)
    s = res.surrogate
    # the held-out blocks are states the fit never saw; the check below recomputes their error
    t, states, forces, _ = scene_series(load_scene(train), cache=tmp_path / "series" / "train_b1_series.npz")
    t, states, forces = t[::2], states[::2], forces[::2]
    held = holdout_mask(t, 22.0)
    assert 0 < held.sum() < len(t)
    err = nrmse(s.predict(states[held]), forces[held])
    assert np.allclose(err, [s.errors["test_nrmse"][c] for c in ("Fy", "Fz")], rtol=1e-9)
    # order 3 on 40 ms near the equilibrium: measured 2.0 % (Fy) and 0.5 % (Fz) on 2026-11-23
    assert err.max() < 0.05
    assert "other.toml" in s.errors["other_scenes"]

    # written through the CLI path: scene paths relative to the file, so the pair of folders can move
    from bearing_fmu.fitting import save_fit

    out = tmp_path / "surrogates" / "s.json"
    save_fit(res, out)
    call = json.loads(out.read_text())["provenance"]["recipe"]
    assert call["scenes"] == ["../scenes/train.toml"] and call["test_scenes"] == ["../scenes/other.toml"]
    moved = tmp_path / "moved"
    shutil.copytree(tmp_path / "scenes", moved / "scenes")
    shutil.copytree(tmp_path / "surrogates", moved / "surrogates")
    shutil.rmtree(tmp_path / "scenes")
    r = refit(moved / "surrogates" / "s.json", 2, moved / "surrogates" / "s2.json",
              cache_dir=tmp_path / "series2", log=lambda *_: None)
    assert load_surrogate(r).order == 2


def test_refit_names_a_missing_scene(tmp_path):
    src = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
    copy = tmp_path / "s.json"
    shutil.copy(src, copy)  # its fit call points at ../scenes/paper_22hz.toml, absent here
    with pytest.raises(FileNotFoundError, match="paper_22hz.toml"):
        refit(copy, 3, tmp_path / "o.json", log=lambda *_: None)


@pytest.mark.parametrize("name", ["paper_22hz_16.7N", "paper_44hz_16.7N", "paper_10hz_500N", "paper_20hz_800N"])
def test_shipped_fit_calls_point_at_bundled_scenes(name):
    path = ROOT / "rotor_host" / "bundled" / "surrogates" / f"{name}.json"
    call = load_surrogate(path).provenance["fit_call"]
    for p in [*call.get("scenes", [call.get("scene")]), *call["test_scenes"]]:
        assert not Path(p).is_absolute() and (path.parent / p).is_file()


@pytest.mark.slow  # a fit, a figure or a process end to end (about 1 s): the full suite's, out of the quick loop
def test_several_training_scenes(tmp_path, training_scene):
    # two unbalances at the same speed and load trained together: both series' held-out blocks
    # are scored, the fit recipe names both scenes, the CLI takes --scene twice and a refit
    # (also from a file of the older single-scene fit-call form) uses the same data
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    a, b, other = (training_scene(scenes, name, g) for name, g in (("a", 8.5), ("b", 3.0), ("other", 6.0)))
    cache = tmp_path / "series"
    out = tmp_path / "surrogates" / "s.json"
    args = ["fit", "--scene", str(a), "--scene", str(b), "--test-scene", str(other), "--order", "3",
            "--designed", "200", "--designed-tube", "0.02", "--ecc-weight", "1",
            "--no-prune", "--cache-dir", str(cache), "-o", str(out)]
    assert rotor_host(args) == 0
    s = load_surrogate(out)
    call = s.provenance["recipe"]
    assert call["scenes"] == ["../scenes/a.toml", "../scenes/b.toml"]
    assert call["designed_tube"] == 0.02 and call["ecc_weight"] == 1.0
    held = []
    for name in ("a", "b"):
        t, st, fo, _ = scene_series(load_scene(scenes / f"{name}.toml"), cache=cache / f"{name}_b1_series.npz")
        t, st, fo = t[::2], st[::2], fo[::2]
        m = holdout_mask(t, 22.0)
        held.append((st[m], fo[m]))
    st_h, fo_h = np.vstack([h[0] for h in held]), np.vstack([h[1] for h in held])
    assert s.errors["n_test"] == len(st_h)
    err = nrmse(s.predict(st_h), fo_h)
    assert np.allclose(err, [s.errors["test_nrmse"][c] for c in ("Fy", "Fz")], rtol=1e-9)
    assert err.max() < 0.05 and "other.toml" in s.errors["other_scenes"]

    r = load_surrogate(refit(out, 3, tmp_path / "surrogates" / "r.json", cache_dir=cache, log=lambda *_: None))
    assert r.provenance["recipe"]["scenes"] == call["scenes"]
    np.testing.assert_allclose(r.coef, s.coef, rtol=1e-9, atol=1e-12)  # same data, seed and weights
    # a file written before several scenes were possible names one "scene"
    d = _as_fit_call(json.loads(out.read_text()))
    d["provenance"]["fit_call"].pop("scenes")
    d["provenance"]["fit_call"]["scene"] = "../scenes/a.toml"
    old = tmp_path / "surrogates" / "old.json"
    old.write_text(json.dumps(d))
    o = load_surrogate(refit(old, 2, tmp_path / "surrogates" / "o.json", cache_dir=cache, log=lambda *_: None))
    assert o.order == 2 and o.provenance["recipe"]["scenes"] == ["../scenes/a.toml"]


def test_host_fit_needs_a_scene(capsys):
    assert rotor_host(["fit", "--order", "3", "-o", "s.json"]) == 2
    assert "--scene" in capsys.readouterr().err


def test_compare_refits_a_scene_surrogate_at_other_orders(tmp_path, training_scene):
    # `rotor-host compare --orders`: the scene's surrogate for its own order, the others refitted
    # from its recipe into the output folder (once: a second call finds them there)
    from rotor_host.analyses.compare import surrogates_at_orders

    scenes = tmp_path / "scenes"
    scenes.mkdir()
    a = training_scene(scenes, "a", 8.5)
    sur = tmp_path / "surrogates" / "a.json"
    assert rotor_host(["fit", "--scene", str(a), "--order", "3", "--designed", "0", "--no-prune",
                       "--cache-dir", str(tmp_path / "out" / "series"), "-o", str(sur)]) == 0
    scene = load_scene(a).with_internal("taylor", via="direct", options={"taylor": {"surrogate": sur}})
    got = surrogates_at_orders(scene, [2, 3], tmp_path / "out")
    assert [o for o, _ in got] == [2, 3] and got[1][1] == sur
    r = load_surrogate(got[0][1])
    assert r.order == 2 and r.provenance["recipe"]["scenes"] == ["../../scenes/a.toml"]
    assert surrogates_at_orders(scene, [2, 3], tmp_path / "out") == got


def test_training_scenes_must_share_speed_and_load(tmp_path, training_scene):
    a = training_scene(tmp_path, "a", 8.5)
    heavy = training_scene(tmp_path, "heavy", 8.5, static_loads=[{"node": 3, "Fz_N": -50.0}])
    with pytest.raises(ValueError, match="load"):
        fit_scene(FitRecipe(scenes=[a, heavy], order=2, designed=0, prune=False), cache_dir=tmp_path / "series",
                  log=lambda *_: None)
    fast = training_scene(tmp_path, "fast", 8.5, speed_hz=30.0)
    with pytest.raises(ValueError, match="speed"):
        fit_scene(FitRecipe(scenes=[a, fast], order=2, designed=0, prune=False), cache_dir=tmp_path / "series",
                  log=lambda *_: None)
    with pytest.raises(ValueError, match="ecc_weight"):
        fit_scene(FitRecipe(scenes=[a], order=2, designed=0, ecc_weight=-1.0), cache_dir=tmp_path / "series",
                  log=lambda *_: None)


def test_wall_power_is_recorded_and_refitted(tmp_path, training_scene):
    # --wall-power P: the polynomial fits F (1 - eps^2)^P, the file says so, the fit recipe stores
    # it and a refit repeats it (same data, same coefficients)
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    a = training_scene(scenes, "a", 8.5)
    cache = tmp_path / "series"
    out = tmp_path / "surrogates" / "w.json"
    args = ["fit", "--scene", str(a), "--order", "3", "--designed", "0", "--wall-power", "1.5", "--no-prune",
            "--cache-dir", str(cache), "-o", str(out)]
    assert rotor_host(args) == 0
    s = load_surrogate(out)
    assert s.wall_power == 1.5 and s.provenance["recipe"]["wall_power"] == 1.5
    t, st, fo, _ = scene_series(load_scene(a), cache=cache / "a_b1_series.npz")
    t, st, fo = t[::2], st[::2], fo[::2]
    m = holdout_mask(t, 22.0)
    err = nrmse(s.predict(st[m]), fo[m])
    assert np.allclose(err, [s.errors["test_nrmse"][c] for c in ("Fy", "Fz")], rtol=1e-9)
    assert err.max() < 0.05
    r = load_surrogate(refit(out, 3, tmp_path / "surrogates" / "r.json", cache_dir=cache, log=lambda *_: None))
    assert r.wall_power == 1.5
    np.testing.assert_allclose(r.coef, s.coef, rtol=1e-9, atol=1e-12)
    # a fit call without the key (older files) refits with the plain polynomial
    d = _as_fit_call(json.loads(out.read_text()))
    d["provenance"]["fit_call"].pop("wall_power")
    old = tmp_path / "surrogates" / "old.json"
    old.write_text(json.dumps(d))
    o = load_surrogate(refit(old, 3, tmp_path / "surrogates" / "o.json", cache_dir=cache, log=lambda *_: None))
    assert o.wall_power == 0.0


def test_series_forces_are_the_bearings_own(tmp_path, training_scene):
    # a scene recording a node before the first bearing (node 1, as the 10 Hz scenes do) and an
    # unbalance near one end, so the two bearings carry different forces: the series must pair
    # each state with the force of the same bearing -- the truth evaluated at the series states
    # gives the series forces back (the forces are recorded per bearing, the states per node)
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from rotor_host.analyses.training import _bearing_params

    p = training_scene(tmp_path, "asym", 8.5, unbalance_node=1, record={"nodes": [1, 3, 6, 9]}, t_end=0.01)
    sc = load_scene(p)
    for bearing in (1, 2):
        t, st, fo, _ = scene_series(sc, bearing, cache=tmp_path / f"b{bearing}.npz")
        truth = Reynolds(_bearing_params(sc, bearing), n_theta=32, n_x=8)
        for i in (len(t) // 2, len(t) - 1):
            np.testing.assert_allclose(truth.force(*st[i], sc.omega), fo[i], rtol=1e-6, atol=1e-6)
    t1, _, f1, _ = scene_series(sc, 1, cache=tmp_path / "b1.npz")
    t2, _, f2, _ = scene_series(sc, 2, cache=tmp_path / "b2.npz")
    assert np.max(np.abs(f1 - f2)) > 1e-3 * np.max(np.abs(f1))  # the bearings differ, so the check has teeth


def test_a_tilting_pad_scene_is_refused_by_name_before_any_run(tmp_path, capsys):
    """The Taylor surrogate maps the journal's state to the force; a tilting-pad force depends on
    the pads' tilts too: `rotor-host fit` on the five-pad scene says so and exits 2, before any
    Reynolds series is computed (no series folder)."""
    scene = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_5pad_lbp_44hz.toml"
    assert rotor_host(["fit", "--scene", str(scene), "-o", str(tmp_path / "fit.json")]) == 2
    err = capsys.readouterr().err
    assert "has tilting pads" in err and "tilting_pad internal" in err and "Traceback" not in err
    assert not (tmp_path / "series").exists()
