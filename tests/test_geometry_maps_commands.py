"""Every command family with a grooved bearing (issue 25 item 4): map, fit, run (and a run-up),
stability and sweep through the grooved bore's force map and Taylor surrogate; and the shipped
grooved map in closed loop against the Reynolds solver it was built from (the reference: the
same scene, the Reynolds internal at the map's truth grid, called directly)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.params import BearingParams
from conftest import run_cli

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"
GROOVED = MODELS / "bearing_paper_2groove.toml"
PAPER_MAP = MODELS / "maps" / "paper_2groove.json"
FRISWELL_MAP = MODELS / "maps" / "friswell_2groove.json"


@pytest.mark.slow
def test_the_shipped_grooved_maps_are_for_their_bearings():
    from bearing_fmu.internals.map.mapfile import load_any_map, open_map

    for path, bearing in ((PAPER_MAP, GROOVED), (FRISWELL_MAP, MODELS / "bearing_friswell_2groove.toml")):
        t = load_any_map(path)
        assert t.H.shape == (64, 32, 64, 2) and (t.n_theta, t.n_x) == (128, 16)
        assert t.Q.shape == (64, 32, 64, 5)  # the flow tables: side flow and the four groove edges
        assert t.provenance["bearing_file"] == str(bearing.relative_to(ROOT))
        open_map(path, BearingParams.from_toml(bearing))
        assert path.stat().st_size < 9e6


@pytest.mark.slow
def test_the_native_map_build_of_a_grooved_map_needs_its_bearing(tmp_path, capsys):
    # the native map FMU takes the grooved map with its bearing file (tests/test_native_fmu.py), not without
    code, _, err = run_cli("bearing-fmu", ["build", "--native", "--internal", "map", "--map",
                                          str(PAPER_MAP), "-o", str(tmp_path / "n.fmu")],
                        capsys)
    assert code == 2 and "give the bearing file with --bearing" in err and not (tmp_path / "n.fmu").exists()


@pytest.mark.slow
def test_map_command_writes_a_grooved_map_that_runs_a_scene(tmp_path, capsys):
    out = tmp_path / "m.json"
    code, text, err = run_cli("bearing-fmu", ["map", "--bearing", str(GROOVED), "-o", str(out), "--resolution", "8x8",
                                           "--phi-points", "4", "--grid", "32x4", "--phases", "1", "--quiet"], capsys)
    assert code == 0, err
    assert "8 x 4 x 8 points (eps x phi over 180 deg x beta)" in text and "2 axial grooves" in text
    assert json.loads(out.read_text())["version"] == 4  # with the flow tables
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--internal", "map",
                                       "--map", str(out), "--t-end", "0.005", "--out", str(tmp_path), "--no-plots",
                                       "--quiet"], capsys)
    assert code == 0, err
    assert json.loads((tmp_path / "paper_2groove_22hz_map.json").read_text())["status"] == "ok"
    # --phi-points is for a grooved bore only
    code, _, err = run_cli("bearing-fmu", ["map", "-o", str(tmp_path / "n.json"), "--phi-points", "8"], capsys)
    assert code == 2 and "--phi-points is for a grooved or partial-arc bore" in err


@pytest.mark.slow
def test_fit_takes_a_grooved_bearing_and_its_surrogate_runs_the_scene(tmp_path, capsys):
    sur = tmp_path / "s.json"
    code, _, err = run_cli("bearing-fmu", ["fit", "--bearing", str(GROOVED), "--order", "2", "--n-train", "80",
                                        "--n-test", "20", "--grid", "32", "4", "-o", str(sur)], capsys)
    assert code == 0, err
    assert json.loads(sur.read_text())["geometry"]["grooves_deg"] == [90.0, 270.0]
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--internal",
                                       "taylor", "--surrogate", str(sur), "--t-end", "0.002", "--out", str(tmp_path),
                                       "--no-plots", "--quiet"], capsys)
    assert code == 0, err
    # the full-bore scene refuses it, by name
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_22hz.toml"), "--internal", "taylor",
                                       "--via", "direct", "--surrogate", str(sur), "--t-end", "0.002", "--out",
                                       str(tmp_path), "--no-plots", "--quiet"], capsys)
    assert code == 2 and "fitted for the bore '2 axial grooves" in err


@pytest.mark.slow
def test_run_up_stability_and_sweep_take_the_grooved_map(tmp_path, capsys):
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_2groove_runup_10_60hz.toml"), "--t-end",
                                       "0.01", "--out", str(tmp_path), "--no-plots", "--quiet"], capsys)
    assert code == 0, err
    res = json.loads((tmp_path / "paper_2groove_runup_10_60hz_map.json").read_text())
    assert res["status"] == "ok"
    code, out, err = run_cli("rotor-host", ["stability", str(MODELS / "rotor_paper_2groove.toml"), "--speeds-hz",
                                         "40:44:2", "--internal", "map", "--map", str(PAPER_MAP), "--out",
                                         str(tmp_path), "--no-plots"], capsys)
    assert code == 0, err
    threshold = float(out.split("\nthreshold ")[1].split(" Hz")[0])
    assert threshold == pytest.approx(42.35, abs=0.15)  # Reynolds 128 x 16: 42.35 Hz (docs/geometry.md)
    code, _, err = run_cli("rotor-host", ["sweep", str(MODELS / "scenes" / "paper_2groove_22hz.toml"), "--speeds-hz",
                                       "20", "30", "--internal", "map", "--t-end", "0.005", "--workers", "1", "--out",
                                       str(tmp_path / "sweep"), "--quiet"], capsys)
    assert code == 0, err


@pytest.mark.slow
def test_the_grooved_map_orbit_follows_reynolds(tmp_path):
    """The paper rotor on two-groove bearings at 22 Hz, 0.05 s from the static equilibrium: the
    shipped map's orbit against Reynolds 128 x 16 (its truth grid) within 0.01 % CR RMS
    (measured 2026-11-26: docs/studies/2026-11-26-geometry-maps.md)."""
    from rotor_host.analyses.report import errors_against
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(MODELS / "scenes" / "paper_2groove_22hz.toml")
    rey = run_scene(scene.with_internal("reynolds", via="direct", t_end_s=0.05), tmp_path, stem="rey")
    fmap = run_scene(scene.with_internal("map", via="direct", t_end_s=0.05), tmp_path, stem="map")
    assert rey.ok and fmap.ok
    err = errors_against(rey.arrays, fmap.arrays)
    assert err["orbit_rms_pct_cr"] < 0.01, err
    bearings = [list(rey.arrays["nodes"]).index(n) for n in rey.arrays["bearing_nodes"]]
    assert np.ptp(rey.arrays["z"][:, bearings], axis=0).min() > 0.02 * BearingParams.from_toml(GROOVED).CR
    assert math.isfinite(err["orbit_max_pct_cr"])


@pytest.mark.slow
def test_the_python_fmu_runs_the_grooved_map_like_the_direct_call(tmp_path):
    """The Python FMU takes the bore as parameters (from the scene's bearing): with the grooved
    map it gives the in-process map run (the same kernel), to 1e-9 of each array's largest value."""
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(MODELS / "scenes" / "paper_2groove_22hz.toml")
    direct = run_scene(scene.with_internal("map", via="direct", t_end_s=0.005), tmp_path, stem="direct")
    cosim = run_scene(scene.with_internal("map", via="fmu", t_end_s=0.005), tmp_path, stem="fmu")
    assert direct.ok and cosim.ok, (direct.meta["message"], cosim.meta["message"])
    for key in ("y", "z", "Fy", "Fz"):
        a, b = direct.arrays[key], cosim.arrays[key]
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-9 * np.abs(a).max(), err_msg=key)
