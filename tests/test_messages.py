"""Every message names its cause (issue 38, item 6): the bad inputs that were misattributed or
unclear, each refused where the value enters, in one line naming the key, option or file and what
is allowed, exit status 2 from the command line.

Each case is the issue's own reproduction; the expected words come from the input (the key or
option it breaks) and from the limit the code states (the numbers derived below where they are
computed).
"""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import BearingParams
from rotor_host.scenes.scene import SceneError, load_scene
from conftest import run_cli
from tests.test_fmi_status import ERROR, raw  # noqa: F401  (raw: the fixture, a Python FMU's instance)

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"


def _file(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(textwrap.dedent(text))
    return p


# ----------------------------------------------------------------------------- geometry and oil

def test_a_groove_filling_its_arc_is_refused_by_key(tmp_path, capsys):
    """A 179 deg groove centred in a 180 deg arc leaves two films of 0.5 deg: under the 5 deg
    minimum (checked between grooves only before, so `demo` ended with the journal 15 m away).
    A 170 deg groove leaves exactly 5 deg on each side: accepted."""
    with pytest.raises(ValueError, match=r"the film from 269\.5 deg to 270 deg is 0\.5 deg wide: grooves_deg "
                                         r"\(groove_width_deg = 179\) and arc_deg must leave at least 5 deg"):
        Geometry(arc=(math.radians(90), math.radians(270)), grooves=(math.pi,), groove_width=math.radians(179))
    Geometry(arc=(math.radians(90), math.radians(270)), grooves=(math.pi,), groove_width=math.radians(170))
    f = _file(tmp_path, "b.toml", """\
        [bearing]
        D_mm = 31.0
        L_mm = 20.0
        CR_um = 90.0
        mu_Pa_s = 0.05
        [geometry]
        arc_deg = [90.0, 270.0]
        grooves_deg = [180.0]
        groove_width_deg = 179.0
        """)
    code, out, err = run_cli("bearing-fmu", ["demo", "--bearing", str(f)], capsys)
    assert code == 2 and f"{f}: [geometry] the film from 269.5 deg" in err and "Traceback" not in err
    assert "equilibrium" not in out


def test_a_vogel_law_out_of_range_is_refused_by_key(tmp_path, capsys):
    """vogel_b_K = 1e6 gave a bare OverflowError (the law evaluated before any range check). The
    law's largest viscosity is at the range's bottom, 0 C: mu = a exp(b / (273.15 K - c)); within
    1e6 Pa s needs b <= ln(1e6 / a) (273.15 - c) = ln(1e10) 173.15 K = 3986.93 K for a = 1e-4 Pa s,
    c = 100 K."""
    f = _file(tmp_path, "b.toml", """\
        [bearing]
        D_mm = 31.0
        L_mm = 20.0
        CR_um = 90.0
        [oil]
        vogel_a_Pa_s = 1e-4
        vogel_b_K = 1e6
        vogel_c_K = 100
        """)
    b_max = math.log(1e6 / 1e-4) * (273.15 - 100.0)
    with pytest.raises(ValueError, match=rf"vogel_b_K = 1e\+06.*at 0 C, the bottom of its range \(range_C\), above "
                                         rf"1e\+06 Pa s: vogel_b_K at most {b_max:.6g} K"):
        BearingParams.from_toml(f)
    code, _, err = run_cli("bearing-fmu", ["demo", "--bearing", str(f)], capsys)
    assert code == 2 and "[oil] the Vogel law" in err and "OverflowError" not in err
    f.write_text(f.read_text().replace("1e6", "1000"))  # 11 mPa s at 40 C
    assert BearingParams.from_toml(f).oil is not None


# ----------------------------------------------------------------------------- command lines

def test_stability_supply_temperature_is_named_not_the_map(capsys, tmp_path):
    """`stability --internal map --supply-c 1e6`: the supply temperature is the cause (the oil's
    range 0 .. 150 C), not the --map the command chose by default."""
    code, _, err = run_cli("rotor-host", ["stability", str(MODELS / "rotor_paper_vg46.toml"), "--internal", "map",
                                          "--speeds-hz", "20:22:2", "--supply-c", "1e6", "--no-plots", "--out",
                                          str(tmp_path)], capsys)
    assert code == 2 and "--supply-c = 1.00027e+06 K (1e+06 C) is outside the viscosity law's range 0 C .. 150 C" in err
    assert "--map" not in err
    code, _, err = run_cli("rotor-host", ["stability", str(MODELS / "rotor_paper.toml"), "--internal", "map",
                                          "--speeds-hz", "20:22:2", "--supply-c", "40", "--no-plots", "--out",
                                          str(tmp_path)], capsys)
    assert code == 2 and "a supply temperature (given by --supply-c) needs the bearing file's [oil]" in err
    assert "--map" not in err


def test_native_on_a_direct_scene_is_refused(capsys, tmp_path):
    """--native chooses the FMU kind; a via = "direct" scene runs no FMU (it was dropped silently)."""
    scene = MODELS / "scenes" / "heldout_22hz_6g.toml"
    assert load_scene(scene).via == "direct"
    code, _, err = run_cli("rotor-host", ["run", str(scene), "--native", "--out", str(tmp_path), "--quiet"], capsys)
    assert code == 2 and 'runs via = "direct"' in err and "add --via fmu, or leave --native out" in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("value", ["-1e3", "-1000", "-1E+3", "-1000.0"])
def test_a_negative_number_after_an_option(capsys, value):
    """argparse's own test takes -5 and -.5 as numbers but not -1e3 ("expected one argument")."""
    code, out, err = run_cli("bearing-fmu", ["demo", "--load-z", value, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["load_N"] == [0.0, -1000.0]


def test_a_non_finite_negative_is_refused_by_its_type(capsys):
    code, _, err = run_cli("bearing-fmu", ["demo", "--load-z", "-inf"], capsys)
    assert code == 2 and "argument --load-z: expected a finite number N, got '-inf'" in err
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_22hz.toml"), "--dt", "-1e-3"], capsys)
    assert code == 2 and "argument --dt: expected a finite number > 0 s, got '-1e-3'" in err


def test_fit_from_a_text_file(tmp_path, capsys):
    """numpy read a text file as a pickle and said so; the message names the file and the kind."""
    f = _file(tmp_path, "series.npz", "t,y,z\n0,1,2\n")
    code, _, err = run_cli("bearing-fmu", ["fit", "--from-npz", str(f), "-o", str(tmp_path / "s.json")], capsys)
    assert code == 2
    assert f"{f}: not a training time series (.npz with arrays y, z, vy, vz, Fy, Fz): an .npz is a zip archive of " \
           "numpy arrays, this file is text" in err
    assert "pickle" not in err


@pytest.mark.parametrize("flag,given,other", [("map", "surrogates/paper_22hz_16.7N.json", "surrogate"),
                                              ("surrogate", "maps/paper_bearing.json", "map")])
def test_build_with_a_file_of_the_other_option(tmp_path, capsys, flag, given, other):
    """A surrogate given as --map was bundled as a surrogate, and the FMU then said the map was
    missing; each flag takes its own files (their JSON "format")."""
    code, _, err = run_cli("bearing-fmu", ["build", "-o", str(tmp_path / "b.fmu"), f"--{flag}", str(MODELS / given)],
                           capsys)
    assert code == 2 and f"--{flag} {MODELS / given}: the file is a" in err and f"give it with --{other}" in err
    assert not (tmp_path / "b.fmu").exists()


def _run_up(folder: Path) -> Path:
    """A saved run-up: 10 -> 30 Hz over 2 s, node 6 whirling at 1x (tests/test_runup.py's)."""
    from tests.test_runup import _response, _synthetic_run

    return _synthetic_run(folder, 10.0, 30.0, _response(22.4))[0]


def test_waterfall_of_a_truncated_run(tmp_path, capsys):
    npz = _run_up(tmp_path)
    data = npz.read_bytes()
    npz.write_bytes(data[: len(data) // 2])
    code, _, err = run_cli("rotor-host", ["waterfall", str(npz)], capsys)
    assert code == 2 and f"{npz}: not a saved run (.npz of rotor-host run): a damaged or truncated .npz" in err


def test_waterfall_with_nan_speeds(tmp_path, capsys):
    npz = _run_up(tmp_path)
    arrays = dict(np.load(npz))
    arrays["speed_hz"][[100, 200]] = np.nan
    np.savez(npz, **arrays)
    code, _, err = run_cli("rotor-host", ["waterfall", str(npz)], capsys)
    assert code == 2
    assert f"{npz}: array speed_hz holds 2 value(s) that are not finite numbers (first at index 100: nan)" in err
    assert not (tmp_path / "run_waterfall.png").exists()


def test_a_step_too_small_names_dt_and_the_step_limit(tmp_path, capsys):
    """dt_s = 1e-300 over 0.5 s asked for 5e299 steps (numpy: "Maximum allowed dimension
    exceeded"); the limit is 1e8 steps, so dt_s >= 0.5 s / 1e8 = 5e-9 s."""
    scene = _file(tmp_path, "s.toml", f"""\
        rotor = "{(MODELS / 'rotor_paper.toml').as_posix()}"
        internal = "reynolds"
        speed_hz = 22
        [time]
        t_end_s = 0.5
        dt_s = 1e-300
        """)
    with pytest.raises(SceneError, match=r"dt_s = 1e-300 s makes t_end_s = 0\.5 s 5e\+299 steps, more than the "
                                         r"1e\+08 a run may take: dt_s must be at least 5e-09 s"):
        load_scene(scene)
    code, _, err = run_cli("rotor-host", ["run", str(MODELS / "scenes" / "paper_22hz.toml"), "--dt", "1e-9",
                                          "--out", str(tmp_path / "o"), "--quiet"], capsys)
    assert code == 2 and "dt_s = 1e-09 s makes t_end_s" in err and "at least" in err


def test_the_fmu_names_the_parameter_whose_file_is_missing(raw):  # noqa: F811
    """The Python FMU (tests/test_fmi_status.py's, a surrogate and a map bundled) asked for a map
    it does not hold: "map file ... --map FILE" (it said "surrogate file" for every option)."""
    r = raw()
    st = r.initialise(internal="map", map="missing.json")
    assert st["exit"] == ERROR
    assert any("map file 'missing.json' not found in the FMU resources folder surrogates/ (bundled: paper_22hz.json, "
               "paper_map.json); build the FMU with `bearing-fmu build --map FILE`" in m for m in r.errors()), r.messages
