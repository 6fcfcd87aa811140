"""The truth of a fit (bearing_fmu.fitting.truth): the Reynolds solver, or a force map for the
designed, tube and held-out samples (``truth_map``), its checks, its record in the surrogate
file and the report, and the refit from the stored recipe.

The fits here are small (order 2-3, a few hundred samples) on the session's coarse map
(tests/conftest.py: Reynolds 32 x 4, table 12 x 16), whose statics are Reynolds 32 x 4.
"""

import argparse
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu import fitting as F
from bearing_fmu.cli import main as bearing_fmu
from bearing_fmu.cli import add_fit_arguments, run_fit
from bearing_fmu.fitting import FitRecipe
from bearing_fmu.internals.map.forcemap import ForceMap
from bearing_fmu.internals.map.tablefile import load_map, save_map
from bearing_fmu.internals.map.tables import scale, tabulate
from bearing_fmu.physics.params import PAPER_BEARING as P
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.surrogates.surrogate import load_surrogate

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
OMEGA = 2 * math.pi * 22.0
# a small designed fit at the paper's 22 Hz under half the rotor weight (the README's domain)
SMALL = dict(speed_hz=22.0, load_z=-16.7, ecc_max=0.6, v_max=0.4, order=2, n_train=150, n_test=60, prune=False)


def _design(internal, sur, r: FitRecipe, seed: int, n: int):
    """The designed samples of recipe ``r`` about the surrogate's expansion point from ``internal``."""
    states, forces, _ = F.designed_samples(internal, sur.y0, sur.z0, sur.omega, r.ecc_max, r.v_max, n, seed,
                                           radius=r.radius)
    return states, forces


def test_map_truth_draws_training_and_held_out_samples_from_the_map(map_file):
    r = FitRecipe(**SMALL, truth_map=str(map_file))
    res = F.fit_condition(r, bias_variance=False)
    s = res.surrogate
    m = ForceMap.from_file(map_file, P)
    # the stored errors are of the map's forces: recomputed here from the map at the same design
    # (training seed, held-out seed + 1000; FitRecipe's seed), they agree to round-off
    st, fm = _design(m, s, r, r.seed, r.n_train)
    ts, tm = _design(m, s, r, r.seed + 1000, r.n_test)
    np.testing.assert_allclose(F.nrmse(s.predict(st), fm), [s.errors["train_nrmse"][c] for c in F.COMPONENTS],
                               rtol=1e-9)
    np.testing.assert_allclose(F.nrmse(s.predict(ts), tm), [s.errors["test_nrmse"][c] for c in F.COMPONENTS],
                               rtol=1e-9)
    # ... and not Reynolds': the same states' Reynolds 32 x 4 forces differ from the map's (the
    # coarse table's own error, well above round-off), so they give another NRMSE
    statics = F.make_reynolds(P, (32, 4))
    tr = F.sample_forces(statics, ts, OMEGA)
    assert np.max(np.abs(tr - tm)) > 1e-6 * np.max(np.abs(tr))
    assert not np.allclose(F.nrmse(s.predict(ts), tr), [s.errors["test_nrmse"][c] for c in F.COMPONENTS],
                           rtol=1e-9)
    # the statics stay Reynolds on the map's grid: the expansion point is Reynolds 32 x 4's equilibrium
    y0, z0 = F.expansion_point(statics, (0.0, -16.7), OMEGA)
    assert math.hypot(s.y0 - y0, s.z0 - z0) < 1e-9 * P.CR
    assert res.report["sampling_seconds"] > 0 and res.report["total_seconds"] >= res.report["fit_seconds"]


def test_paper_map_samples_are_within_its_accuracy_of_reynolds():
    # the shipped map (96 x 96 from Reynolds 128 x 16) against Reynolds 128 x 16 at the README's
    # designed samples (22 Hz, ecc <= 0.6, |v| <= 0.4 omega CR). Measured 2026-11-24 on 200
    # samples: NRMSE 7.4e-5 (Fy) / 3.9e-5 (Fz), largest error 7.2e-4 of max(|F|, S omega);
    # docs/forcemap.md gives the map's accuracy over the whole table. Bounds: 4x margin.
    truth = F.fit_truth(FitRecipe(truth_map=str(PAPER_MAP)), P)
    assert isinstance(truth.samples, ForceMap)
    assert (truth.statics.n_theta, truth.statics.n_x, truth.statics.cavitation) == (128, 16, "reynolds")
    y0, z0 = F.expansion_point(truth.statics, (0.0, -16.7), OMEGA)
    st, fm, _ = F.designed_samples(truth.samples, y0, z0, OMEGA, 0.6, 0.4, 200, 1001)
    fr = F.sample_forces(truth.statics, st, OMEGA)
    assert np.all(F.nrmse(fm, fr) < 3e-4)
    ref = np.maximum(np.linalg.norm(fr, axis=1), scale(P) * OMEGA)
    assert np.max(np.linalg.norm(fm - fr, axis=1) / ref) < 3e-3


def test_report_and_file_name_the_truth(tmp_path, map_file, capsys):
    parser = add_fit_arguments(argparse.ArgumentParser())
    common = ["--speed-hz", "22", "--load-z", "-16.7", "--ecc-max", "0.6", "--v-max", "0.4", "--order", "2",
              "--n-train", "150", "--n-test", "60", "--no-prune"]
    out = tmp_path / "m.json"
    assert run_fit(parser.parse_args([*common, "--truth-map", str(map_file), "-o", str(out)])) == 0
    text = capsys.readouterr().out
    # the conftest map: Reynolds 32 x 4 tabulated on 12 x 16 points
    assert f"truth: force map 12x16 from Reynolds 32x4 ({map_file}); equilibrium and anchor: Reynolds 32x4" in text
    assert "the truth's samples" in text and "whole fit" in text
    prov = load_surrogate(out).provenance
    assert prov["truth"] == "force map" and prov["truth_n_theta"] == 32 and prov["truth_n_x"] == 4
    m = prov["truth_map"]
    table = load_map(map_file)
    assert m["file"] == map_file.name and (m["n_eps"], m["n_beta"]) == (12, 16)
    assert m["reynolds"] == {"n_theta": 32, "n_x": 4, "cavitation": "reynolds"}
    assert m["provenance"] == table.provenance and len(m["sha256"]) == 16
    assert Path(out.parent / prov["recipe"]["truth_map"]).resolve() == Path(map_file).resolve()
    # the line comes from the file alone too (no path given: the stored file name)
    assert F.truth_line(prov).startswith(f"truth: force map 12x16 from Reynolds 32x4 ({map_file.name})")
    # the default truth says so as well, and records no map
    out2 = tmp_path / "r.json"
    assert run_fit(parser.parse_args([*common, "--grid", "32", "4", "-o", str(out2)])) == 0
    assert "truth: Reynolds 32x4\n" in capsys.readouterr().out
    prov2 = load_surrogate(out2).provenance
    assert prov2["truth"] == "Reynolds" and "truth_map" not in prov2 and prov2["recipe"]["truth_map"] is None


def _other_ld_map(folder: Path) -> Path:
    """A (tiny) map of a bearing with L/D = 0.8 instead of the paper's 0.645."""
    other = BearingParams(D=P.D, L=0.8 * P.D, CR=P.CR, mu=P.mu)
    return save_map(tabulate(other, n_theta=16, n_x=4, n_eps=4, n_beta=8, n_phase=1), folder / "ld08.json")


def test_a_map_of_another_bearing_is_refused_by_name(tmp_path, capsys, monkeypatch):
    path = _other_ld_map(tmp_path)

    def no_solver(*_a, **_k):
        raise AssertionError("the Reynolds solver was built before the map was checked")

    monkeypatch.setattr("bearing_fmu.fitting.truth.make_reynolds", no_solver)
    with pytest.raises(ValueError, match=r"^fit: truth_map: force map .*ld08\.json is for L/D = 0\.8, the bearing "
                                         r"has L/D = 0\.645161"):
        F.fit_condition(FitRecipe(**SMALL, truth_map=str(path)))
    # on the command line: exit 2 and one line, before any Reynolds work
    code = bearing_fmu(["fit", "--truth-map", str(path), "-o", str(tmp_path / "s.json")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "ld08.json is for L/D = 0.8" in err and "Traceback" not in err


def test_a_map_of_another_grid_or_too_short_is_refused(tmp_path, map_file, capsys):
    # samples from a 32 x 4 map and statics from Reynolds 32 x 8 would be two truths
    with pytest.raises(ValueError, match=r"truth_map .*paper_map\.json is tabulated from Reynolds 32x4, the fit's "
                                         r"Reynolds truth .* is Reynolds 32x8.*leave --grid out"):
        F.fit_condition(FitRecipe(**SMALL, truth_map=str(map_file), grid=(32, 8)))
    # the map ends at eps 0.99 (forcemap.DEFAULT_EPS_MAX): a design reaching it is refused up front
    with pytest.raises(ValueError, match=r"ecc_max = 0\.995 reaches the truth map's last point, eccentricity 0\.99"):
        F.fit_condition(FitRecipe(**{**SMALL, "ecc_max": 0.995}, truth_map=str(map_file)))
    missing = tmp_path / "gone.json"
    with pytest.raises(FileNotFoundError, match=r"^fit: truth_map: force map file .*gone\.json not found$"):
        F.fit_condition(FitRecipe(**SMALL, truth_map=str(missing)))


def test_refit_from_the_stored_recipe_uses_the_map_again(tmp_path, map_file):
    # the surrogate and its map move together (the recipe stores the map relative to the file)
    (tmp_path / "maps").mkdir()
    local_map = shutil.copy(map_file, tmp_path / "maps" / "m.json")
    res = F.fit_condition(FitRecipe(**{**SMALL, "order": 3, "n_train": 250}, truth_map=local_map))
    out = F.save_fit(res, tmp_path / "sur" / "s.json")
    assert load_surrogate(out).provenance["recipe"]["truth_map"] == "../maps/m.json"
    (tmp_path / "moved").mkdir()
    shutil.move(tmp_path / "sur", tmp_path / "moved" / "sur")
    shutil.move(tmp_path / "maps", tmp_path / "moved" / "maps")
    s = load_surrogate(tmp_path / "moved" / "sur" / "s.json")
    # the refit at the same order draws the same samples from the same map: the same fit exactly
    again = load_surrogate(F.refit_order(tmp_path / "moved" / "sur" / "s.json", 3, tmp_path / "again.json"))
    assert again.coef.tolist() == s.coef.tolist() and again.errors == s.errors
    assert again.provenance["truth"] == "force map"
    assert again.provenance["truth_map"] == s.provenance["truth_map"]
    # at another order: still the map (its errors are of the map's forces, recomputed here)
    o2 = load_surrogate(F.refit_order(tmp_path / "moved" / "sur" / "s.json", 2, tmp_path / "o2.json"))
    m = ForceMap.from_file(map_file, P)
    r = F.recipe_of(o2, tmp_path / "o2.json")
    ts, tm = _design(m, o2, r, r.seed + 1000, r.n_test)
    np.testing.assert_allclose(F.nrmse(o2.predict(ts), tm), [o2.errors["test_nrmse"][c] for c in F.COMPONENTS],
                               rtol=1e-9)
    # a refit whose map is gone says which setting names it
    (tmp_path / "moved" / "maps" / "m.json").unlink()
    with pytest.raises(FileNotFoundError, match=r"fit: truth_map: force map file .*m\.json not found"):
        F.refit_order(tmp_path / "moved" / "sur" / "s.json", 2, tmp_path / "o3.json")


# ----------------------------------------------------------------------------- scene-trained fits

def _scene(paper_scene, n_x: int) -> Path:
    # the paper's 22 Hz scene, 30 ms on a coarse grid 32 x n_x (tests/test_training.py's, shorter)
    return paper_scene(name=f"s{n_x}", t_end=0.03, grid=(32, n_x))


def test_scene_fit_draws_its_tube_from_the_map_and_refits_with_it(tmp_path, paper_scene, map_file, capsys,
                                                                   monkeypatch):
    from rotor_host.analyses.training import refit
    from rotor_host.cli import main as rotor_host

    drawn = []  # (internal, states, forces) of each tube_samples call of the fits below

    def spy(internal, *args, **kw):
        states, forces = tube_samples(internal, *args, **kw)
        drawn.append((internal, states, forces))
        return states, forces

    tube_samples = F.tube_samples
    monkeypatch.setattr(F, "tube_samples", spy)
    scene = _scene(paper_scene, 4)  # the conftest map's grid
    out = tmp_path / "s.json"
    assert rotor_host(["fit", "--scene", str(scene), "--order", "2", "--designed", "120", "--designed-tube", "0.02",
                       "--no-prune", "--truth-map", str(map_file), "--cache-dir", str(tmp_path / "series"),
                       "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert (f"truth: force map 12x16 from Reynolds 32x4 ({map_file}) for the designed samples; series, equilibrium "
            "and anchor: Reynolds 32x4") in text
    s = load_surrogate(out)
    assert s.provenance["truth"] == "force map" and s.provenance["truth_map"]["file"] == map_file.name
    # the tube's forces are the map's (a map read afresh, same states: equal to the last bit) ...
    (internal, states, forces), = drawn
    assert isinstance(internal, ForceMap)
    m = ForceMap.from_file(map_file, P)
    np.testing.assert_array_equal(forces, [m.force(*row, s.omega) for row in states])
    # ... within the coarse map's accuracy of Reynolds 32 x 4 (12 x 16 points, one attitude: a
    # contract map; measured 2026-11-24 on this tube: error / |F| median 2.6e-2, max 6.5e-2; bounds
    # 3x) and not Reynolds' own (the accurate map's figures: test_paper_map_samples_...)
    fr = F.sample_forces(F.make_reynolds(P, (32, 4)), states, s.omega)
    rel = np.linalg.norm(forces - fr, axis=1) / np.linalg.norm(fr, axis=1)
    assert np.median(rel) < 0.08 and rel.max() < 0.2 and np.median(rel) > 1e-6
    # the refit at another order from the stored recipe draws from the map again
    again = load_surrogate(refit(out, 3, tmp_path / "o3.json", cache_dir=tmp_path / "series", log=lambda *_: None))
    assert len(drawn) == 2 and isinstance(drawn[1][0], ForceMap)
    np.testing.assert_array_equal(drawn[1][2], forces)  # same seed, same series: the same tube
    assert again.order == 3 and again.provenance["truth_map"] == s.provenance["truth_map"]


def test_scene_fit_refuses_a_map_of_another_grid_before_running(tmp_path, paper_scene, map_file):
    from rotor_host.analyses.training import fit_scene

    scene = _scene(paper_scene, 8)  # Reynolds 32 x 8, the map is 32 x 4
    with pytest.raises(ValueError, match=r"paper_map\.json is tabulated from Reynolds 32x4.* is Reynolds 32x8.*"
                                         r"build a map on the scenes' Reynolds grid"):
        fit_scene(FitRecipe(scenes=[scene], designed=50, truth_map=str(map_file)), cache_dir=tmp_path / "series",
                  log=lambda *_: None)
    assert not (tmp_path / "series").exists()  # refused before the scene ran


def test_fit_takes_the_users_bearing_and_says_why_it_draws_no_plots(tmp_path, capsys):
    # `bearing-fmu fit --bearing FILE`: the surrogate belongs to that bearing (its file says so
    # and the host refuses it on another), the report names it; --plots with a fixed --lambda
    # says why there is nothing to plot
    from bearing_fmu.cli import main
    from bearing_fmu.physics.params import BearingParams
    from bearing_fmu.surrogates.surrogate import load_surrogate

    f = tmp_path / "b.toml"
    f.write_text("[bearing]\nD_mm = 40.0\nL_mm = 20.0\nCR_um = 60.0\nmu_Pa_s = 0.02\n")
    out = tmp_path / "s.json"
    assert main(["fit", "--bearing", str(f), "--speed-hz", "50", "--load-z", "-32.7", "--order", "2",
                 "--n-train", "200", "--n-test", "100", "--grid", "32", "4", "--lambda", "1e-8",
                 "--plots", str(tmp_path / "plots"), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"bearing: {f}: D 40 mm, L 20 mm, CR 60 um, mu 0.02 Pa s" in text
    assert "no lambda plots" in text and "--lambda" in text
    sur = load_surrogate(out)
    assert sur.params == BearingParams.from_toml(f) and sur.provenance["bearing"] == str(f)
