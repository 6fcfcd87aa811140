"""The shipped grooved and lemon-bore bearings through the commands (issue 25, item 4): demo, a
scene run with the Reynolds internal in-process, stability, the grooved bore's force map and
Taylor surrogates (their files record the bore; tests/test_groovemap.py, tests/test_geometry_maps_commands.py);
and what does not take them yet, refused by name before any work: the bearing FMUs (but the
native map FMU of a grooved map), a force map of a lobed bore without grooves over its lobe boundaries."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from conftest import run_cli

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
GROOVED = MODELS / "bearing_paper_2groove.toml"
LEMON = MODELS / "bearing_paper_lemon.toml"


def test_shipped_bearings_are_the_paper_bearing_with_their_bore():
    g, lemon = BearingParams.from_toml(GROOVED), BearingParams.from_toml(LEMON)
    for p in (g, lemon):
        assert (p.D, p.L, p.CR, p.mu) == (PAPER_BEARING.D, PAPER_BEARING.L, PAPER_BEARING.CR, PAPER_BEARING.mu)
    assert g.geometry.grooves == (math.radians(90), math.radians(270)) and g.geometry.lobes == 1
    assert lemon.geometry.lobes == 2 and lemon.geometry.preload == 0.5
    assert lemon.geometry.pad_clearance(lemon.CR) == pytest.approx(180e-6)


@pytest.mark.parametrize("path, words", [(GROOVED, "bore: 2 axial grooves at 90, 270 deg"),
                                         (LEMON, "2 lobes, preload 0.5, offset 0.5, first lobe centred at 0 deg; "
                                                 "pad clearance 180 um")])
def test_demo_takes_the_bore(path, words, capsys):
    code, out, err = run_cli("bearing-fmu", ["demo", "--bearing", str(path)], capsys)
    assert code == 0, err
    assert words in out and "equilibrium:" in out and "minimum film" in out


@pytest.mark.parametrize("scene", ["paper_2groove_22hz", "paper_lemon_22hz"])
def test_scene_runs_with_reynolds_in_process(scene, tmp_path, capsys):
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / f"{scene}.toml"), "--internal", "reynolds",
                                         "--via", "direct", "--t-end", "0.01", "--out", str(tmp_path), "--no-plots",
                                         "--quiet"], capsys)
    assert code == 0, err
    res = json.loads((tmp_path / f"{scene}_reynolds.json").read_text())
    assert res["status"] == "ok" and res["t_reached_s"] == pytest.approx(0.01)
    npz = np.load(tmp_path / f"{scene}_reynolds.npz")
    assert np.all(np.isfinite(npz["t"])) and npz["t"][-1] == pytest.approx(0.01)


@pytest.mark.slow
def test_scene_through_the_python_fmu_takes_the_bore(tmp_path, capsys):
    """The grooved scene through the Python FMU (the bore as its parameters) equals the in-process run."""
    runs = {}
    for via in ("direct", "fmu"):
        code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--via", via,
                                             "--t-end", "0.002", "--out", str(tmp_path / via), "--quiet"], capsys)
        assert code == 0, err
        runs[via] = np.load(next((tmp_path / via).glob("*.npz")))
    for key in ("y", "z", "Fy", "Fz"):
        assert np.max(np.abs(runs["fmu"][key] - runs["direct"][key])) <= 1e-9 * np.max(np.abs(runs["direct"][key]))


@pytest.mark.parametrize("internal", ["linear", "taylor"])
def test_scene_through_the_native_fmu_is_refused_before_any_build(tmp_path, capsys, monkeypatch, internal):
    monkeypatch.setenv("BEARING_FMU_BUILD_CACHE", str(tmp_path / "fmus"))  # where a build would go
    # the native Reynolds FMU has the bore compiled in and the native map FMU its map's bore (both
    # run: test_grooved_scene_through_the_native_map_fmu); the native linear and Taylor FMUs have
    # neither. The message names this internal's native FMU, not "the native FMU" (issue 38: the
    # native Reynolds FMU takes any bore)
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--via", "fmu",
                                         "--native", "--internal", internal, "--surrogate", "paper_22hz_16.7N",
                                         "--t-end", "0.01", "--out", str(tmp_path), "--quiet"], capsys)
    assert code == 2
    assert (f"fmu_kind = 'native': the native {internal} FMU models only the full 360 deg circular bore (its "
            "parameters are D, L, CR and mu), not bearing 1 (node 3)'s 2 axial grooves at 90, 270 deg") in err
    assert "with --native use internal = 'reynolds' (the bore compiled in) or 'map' (a map of this bore)" in err
    assert "leave --native out" in err and "via = 'direct'" in err
    assert not list(tmp_path.rglob("*.fmu"))


@pytest.mark.slow
@pytest.mark.native
def test_grooved_scene_through_the_native_map_fmu(tmp_path, capsys):
    """The grooved scene's 3-D map compiled into a native FMU (its bore checked against the
    bearing's at build) gives the in-process map run's orbit: the same table, spline and
    Jacobian in C (tests/test_groovemap.py: the native map equals the Python one bit for bit)."""
    runs = {}
    for via in ("direct", "fmu"):
        code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--via", via,
                                             "--internal", "map", "--t-end", "0.005", "--out", str(tmp_path / via),
                                             "--quiet"] + (["--native"] if via == "fmu" else []), capsys)
        assert code == 0, err
        runs[via] = np.load(next((tmp_path / via).glob("*.npz")))
    for key in ("y", "z", "Fy", "Fz"):
        assert np.max(np.abs(runs["fmu"][key] - runs["direct"][key])) <= 1e-9 * np.max(np.abs(runs["direct"][key]))


def test_stability_takes_the_grooved_rotor(tmp_path, capsys):
    code, out, err = run_cli("rotor-host", ["stability", str(MODELS / "rotor_paper_2groove.toml"), "--speeds-hz",
                                         "38:46:4", "--internal", "reynolds", "--out", str(tmp_path), "--no-plots"],
                          capsys)
    assert code == 0, err
    assert "threshold" in out


def test_map_and_taylor_internals_take_the_bore_their_file_records(tmp_path):
    """The map and Taylor files record the bore they were made for; the internals take a
    grooved bearing with its own file and refuse a file made for another bore, by name."""
    g = BearingParams.from_toml(GROOVED)
    assert all(registry.get(n).can.any_geometry for n in ("map", "taylor", "reynolds", "linear"))
    with pytest.raises(ValueError, match=r"models only the full 360 deg circular bore \(a version 1 map's reduction "
                                         r".*builds a 3-D map for grooves and partial arcs\), not this bearing's 2 axial"):
        registry.create("map", g, {"map": str(MODELS / "maps" / "paper_bearing.json")})
    with pytest.raises(ValueError, match=r"fitted for the bore 'full 360 deg circular bore', but used with '2 axial "
                                         r"grooves at 90, 270 deg"):
        registry.create("taylor", g, {"surrogate": str(MODELS / "surrogates" / "paper_22hz_16.7N.json")})
    # the linear internal made from Reynolds takes the bore; made from a full-bore map, it refuses it
    lin = registry.create("linear", g, {"load_z": -16.7, "omega_lin": 2 * math.pi * 22.0, "n_theta": 64, "n_x": 8})
    assert np.all(np.isfinite(lin.K))
    with pytest.raises(ValueError, match="models only the full 360 deg circular bore"):
        registry.create("linear", g, {"linear_from": "map", "map": str(MODELS / "maps" / "paper_bearing.json")})


@pytest.mark.slow
def test_the_grooved_map_serves_the_internals_and_the_linear_model():
    """The shipped grooved map: the map internal for the grooved bearing, and the linear model
    linearised on it, whose stiffness is within 1 % of Reynolds' (at the map's truth grid)."""
    g = BearingParams.from_toml(GROOVED)
    path = MODELS / "maps" / "paper_2groove.json"
    fmap = registry.create("map", g, {"map": str(path)})
    assert "2 axial grooves" in repr(fmap)
    opts = {"load_z": -16.7, "omega_lin": 2 * math.pi * 22.0}
    on_map = registry.create("linear", g, {**opts, "linear_from": "map", "map": str(path)})
    on_rey = registry.create("linear", g, opts)
    assert np.abs(on_map.K - on_rey.K).max() < 0.01 * np.abs(on_rey.K).max()
    assert np.abs(on_map.C - on_rey.C).max() < 0.01 * np.abs(on_rey.C).max()


def test_fmu_builds_refuse_the_bore_by_name(tmp_path, capsys):
    # the Python FMU takes the bore as parameters (tests/test_fmu_ports.py); the native one refuses it
    from bearing_fmu.fmu.native.build import build_native_fmu

    with pytest.raises(ValueError, match=r"the native bearing FMU \(.*\) models only the full 360 deg circular bore"):
        build_native_fmu(tmp_path / "n.fmu", "linear", bearing=BearingParams.from_toml(GROOVED))
    # a lobed bore without grooves over its lobe boundaries: no exact lobe sum (the lemon's map is built,
    # tests/test_lobemap.py)
    ungrooved = tmp_path / "lemon_ungrooved.toml"
    ungrooved.write_text("\n".join(line for line in LEMON.read_text().splitlines() if not line.startswith("groove")))
    code, _, err = run_cli("bearing-fmu", ["map", "--bearing", str(ungrooved), "-o", str(tmp_path / "m.json"),
                                          "--quiet"], capsys)
    assert code == 2 and "[geometry] lobes = 2 with 0 groove(s) in grooves_deg" in err
    assert not (tmp_path / "m.json").exists()
