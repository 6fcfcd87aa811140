"""FitRecipe: every fit setting once -- its checks, its record in the surrogate file, the
command-line options generated from it, and the fit calls of files written before it."""

import argparse
import dataclasses
import json
import math
import re
from pathlib import Path

import pytest

from bearing_fmu.fitting import FitRecipe, recipe_of
from bearing_fmu.cli import add_fit_arguments, add_recipe_arguments, recipe_from_args
from bearing_fmu.fitting.recipe import GROUPS, recipe_fields
from bearing_fmu.surrogates.surrogate import load_surrogate

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("*.json"))


def test_every_field_says_its_meaning_group_and_range():
    for f in dataclasses.fields(FitRecipe):
        assert f.metadata["group"] in GROUPS, f.name
        assert len(f.metadata["help"]) > 10, f.name
        assert f.metadata["allowed"].text(), f.name
    FitRecipe()  # the defaults are allowed


@pytest.mark.parametrize("name,bad", [
    ("order", 0), ("order", 2.0), ("order", True), ("lam", "best"), ("lam", -1e-3), ("lam", math.nan),
    ("k_folds", 1), ("prune", 1), ("prune_tol", -0.1), ("wall_power", math.inf), ("shape_order", -1),
    ("shape_order", "2"), ("seed", -1), ("speed_hz", 0.0), ("load_z", math.nan), ("ecc_max", 1.0),
    ("ecc_max", 0.0), ("v_max", -1.0), ("radius", 0.0), ("n_train", 0), ("grid", (32,)), ("grid", (32, 0)),
    ("bearing_number", 0), ("stride", 0), ("designed", -1), ("designed_ecc_max", 1.2), ("designed_v_max", 0.0),
    ("designed_weight", -1.0), ("designed_tube", 0.0), ("ecc_weight", -1.0), ("truth_map", 3),
])
def test_a_value_out_of_range_is_refused_naming_field_and_range(name, bad):
    f = {f.name: f for f in dataclasses.fields(FitRecipe)}[name]
    kw = {name: bad, **({"scenes": ("a.toml",)} if f.metadata["group"] == "scene" else {})}
    with pytest.raises(ValueError, match=rf"^fit: {name} = .* must be {re.escape(f.metadata['allowed'].text())}$"):
        FitRecipe(**kw)


def test_settings_of_the_other_kind_are_refused():
    with pytest.raises(ValueError, match="speed_hz = 30.0 must be left at its default"):
        FitRecipe(scenes=("a.toml",), speed_hz=30.0)
    with pytest.raises(ValueError, match="test_scenes"):
        FitRecipe(test_scenes=("b.toml",))  # no training scene: a designed recipe
    assert FitRecipe(scenes=["a.toml"]).kind == "scene" and FitRecipe().kind == "designed"


def test_round_trip_with_paths_relative_to_the_file(tmp_path):
    (tmp_path / "scenes").mkdir()
    r = FitRecipe(scenes=(tmp_path / "scenes" / "a.toml",), test_scenes=[str(tmp_path / "scenes" / "b.toml")],
                  order=4, lam=1e-6, designed=0, designed_tube=0.02, wall_power=1.25, shape_order=2)
    d = r.to_dict(relative_to=tmp_path / "surrogates")
    assert d["scenes"] == ["../scenes/a.toml"] and d["test_scenes"] == ["../scenes/b.toml"]
    assert "speed_hz" not in d and d["order"] == 4  # only the model settings and those of its kind
    back = FitRecipe.from_dict(json.loads(json.dumps(d)), folder=tmp_path / "surrogates")
    assert back == r
    designed = FitRecipe(grid=(32, 8), radius=0.1, from_npz=str(tmp_path / "ts.npz"))
    d = designed.to_dict(relative_to=tmp_path)
    assert d["grid"] == [32, 8] and d["from_npz"] == "ts.npz" and "scenes" not in d
    assert FitRecipe.from_dict(d, folder=tmp_path) == designed
    with pytest.raises(ValueError, match="unknown setting.*bearing"):
        FitRecipe.from_dict({"bearing": 1})


def test_truth_map_is_stored_relative_to_the_file_for_both_kinds(tmp_path):
    # a shared setting (group "truth"): both kinds store it, relative to the surrogate's folder
    for r in (FitRecipe(truth_map=str(tmp_path / "maps" / "m.json")),
              FitRecipe(scenes=(str(tmp_path / "a.toml"),), truth_map=tmp_path / "maps" / "m.json")):
        d = r.to_dict(relative_to=tmp_path / "surrogates")
        assert d["truth_map"] == "../maps/m.json"
        assert FitRecipe.from_dict(json.loads(json.dumps(d)), folder=tmp_path / "surrogates") == r
    assert FitRecipe().to_dict()["truth_map"] is None  # absent: the Reynolds solver
    assert FitRecipe.from_dict({}).truth_map is None  # files written before the setting: Reynolds


def test_a_truth_map_that_would_serve_no_sample_is_refused():
    with pytest.raises(ValueError, match=r"^fit: truth_map = 'm.json' must be None \(from_npz gives the training "
                                         r"forces"):
        FitRecipe(truth_map="m.json", from_npz="ts.npz")
    with pytest.raises(ValueError, match=r"^fit: truth_map = 'm.json' must be None \(designed = 0: the fit draws "
                                         r"no designed samples"):
        FitRecipe(scenes=("a.toml",), designed=0, truth_map="m.json")
    assert FitRecipe(scenes=("a.toml",), designed=10, truth_map="m.json").truth_map == "m.json"
    # on the command line: the option, "left out" and why
    args = add_recipe_arguments(argparse.ArgumentParser(), "scene").parse_args(
        ["--scene", __file__, "--designed", "0", "--truth-map", __file__])
    with pytest.raises(ValueError, match=r"^--truth-map .*test_recipe\.py: must be left out \(designed = 0: the fit "
                                         r"draws no designed samples"):
        recipe_from_args(args, "scene")


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_fit_calls_read_into_a_recipe(path):
    # files written before FitRecipe store provenance["fit_call"]: read in one place
    sur = load_surrogate(path)
    call = sur.provenance["fit_call"]
    r = recipe_of(sur, path)
    assert r.kind == "scene" and r.order == sur.order
    assert [Path(p) for p in r.scenes] == [(path.parent / p).resolve() for p in call["scenes"]]
    assert [Path(p) for p in r.test_scenes] == [(path.parent / p).resolve() for p in call["test_scenes"]]
    assert r.bearing_number == call["bearing"] and r.stride == call["stride"]
    for key in ("lam", "prune", "prune_tol", "anchor", "designed", "designed_tube", "ecc_weight", "seed"):
        assert getattr(r, key) == call[key], key
    assert r.wall_power == call.get("wall_power", 0.0) and r.shape_order == call.get("shape_order")


def test_designed_fit_call_reads_into_a_recipe():
    call = {"load": [0.0, -16.7], "speed_hz": 22.0, "ecc_max": 0.9, "v_max": 0.1, "radius": 0.1, "n_train": 300,
            "n_test": 100, "seed": 1, "grid": [32, 8], "npz": None, "anchor": True, "lam": "cv", "k_folds": 5,
            "prune": True, "prune_tol": 0.05, "wall_power": 0.0, "shape_order": None}
    r = FitRecipe.from_fit_call(call)
    assert r == FitRecipe(load_z=-16.7, ecc_max=0.9, v_max=0.1, radius=0.1, n_train=300, n_test=100, grid=(32, 8))
    with pytest.raises(ValueError, match="neither scenes nor a speed"):
        FitRecipe.from_fit_call({"order": 3})


@pytest.mark.parametrize("group", ["designed", "scene"])
def test_options_are_generated_from_the_fields(group):
    p = add_recipe_arguments(argparse.ArgumentParser(), group)
    options = {a.dest: a for a in p._actions if a.dest != "help"}
    assert set(options) == {f.name for f in recipe_fields(group)}
    for f in recipe_fields(group):
        text = f.metadata["flag_help"] or f.metadata["help"]  # a true/false setting: the option that flips it
        assert text[:20].replace("%", "%%") in options[f.name].help
    scene = __file__  # --scene takes an existing file
    args = p.parse_args(["--scene", scene] if group == "scene" else [])
    expect = FitRecipe(scenes=(scene,)) if group == "scene" else FitRecipe()
    assert recipe_from_args(args, group) == expect  # the defaults are the recipe's
    # argparse refuses these by their type (tests/test_bad_inputs.py); values set otherwise are refused here
    for flag, dest, bad, match in (("--order", "order", 0, r"--order 0: must be an integer >= 1"),
                                   ("--shape-order", "shape_order", -1, r"--shape-order -1: must be an integer >= 0")):
        with pytest.raises(SystemExit):
            p.parse_args([flag, str(bad)])
        with pytest.raises(ValueError, match=match):
            recipe_from_args(argparse.Namespace(**{**vars(args), dest: bad}), group)


def test_bearing_fit_points_scene_training_to_the_host(capsys):
    from bearing_fmu.cli import main

    for argv in (["fit", "--scene", "x.toml", "-o", "s.json"], ["fit", "--scene", "x.toml"],
                 ["fit", "--test-scene", "y.toml", "-o", "s.json"], ["fit", "--cache-dir", "c", "-o", "s.json"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 2
        err = capsys.readouterr().err
        assert "rotor-host fit --scene" in err and "Traceback" not in err
    parser = add_fit_arguments(argparse.ArgumentParser())
    assert "--scene" not in parser.format_help()  # hidden: only there to point the way
