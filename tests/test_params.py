"""BearingParams refuses bad values with a message naming the field and the value."""

import math
from pathlib import Path

import pytest

from bearing_fmu.physics.params import PAPER_BEARING, BearingParams


def test_paper_bearing_is_table_2():
    # Table 2 of the paper: D 31 mm, L 20 mm, CR 90 um, mu 50 mPa s
    assert PAPER_BEARING == BearingParams(D=31e-3, L=20e-3, CR=90e-6, mu=50e-3)
    assert PAPER_BEARING.R == pytest.approx(15.5e-3)


@pytest.mark.parametrize("field", ["D", "L", "CR", "mu"])
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "abc", None])
def test_rejects_bad_values(field, bad):
    kw = dict(D=0.031, L=0.02, CR=90e-6, mu=0.05)
    kw[field] = bad
    with pytest.raises(ValueError, match=rf"BearingParams\.{field}"):
        BearingParams(**kw)


def test_clearance_must_be_below_radius():
    with pytest.raises(ValueError, match="CR"):
        BearingParams(D=0.031, L=0.02, CR=0.02, mu=0.05)


def test_from_mapping_units_and_key_errors():
    p = BearingParams.from_mapping({"D_mm": 31, "L_mm": 20, "CR_um": 90, "mu_Pa_s": 0.05})
    assert p == PAPER_BEARING
    with pytest.raises(KeyError, match="CR_um"):
        BearingParams.from_mapping({"D_mm": 31, "L_mm": 20, "mu_Pa_s": 0.05})
    with pytest.raises(KeyError, match="D_m\\b"):
        BearingParams.from_mapping({"D_m": 31, "D_mm": 31, "L_mm": 20, "CR_um": 90, "mu_Pa_s": 0.05})
    with pytest.raises(ValueError, match="L_mm"):
        BearingParams.from_mapping({"D_mm": 31, "L_mm": "twenty", "CR_um": 90, "mu_Pa_s": 0.05})


# Each parameter just outside its physical range (bearing_fmu.physics.params: D 1 mm .. 5 m, L/D 0.05 .. 5,
# CR/R 1e-5 .. 0.05, mu 1e-5 .. 10 Pa s; L and CR at the paper's D = 31 mm, R = 15.5 mm), and
# the non-finite values: each refused with the parameter, its value with unit and the range.
RANGE_WORDS = {"D": "1 mm .. 5 m", "L": "L/D 0.05 .. 5", "CR": "CR/R 1e-05 .. 0.05", "mu": "1e-05 .. 10 Pa s"}
OUTSIDE = [
    ("D", 0.9e-3, "900 um"), ("D", 5.5, "5.5 m"),
    ("L", 0.04 * 0.031, "1.24 mm"), ("L", 6 * 0.031, "186 mm"),
    ("CR", 0.9e-5 * 0.0155, "139.5 nm"), ("CR", 0.06 * 0.0155, "930 um"), ("CR", 1e-300, "1e-300 m"),
    ("mu", 0.9e-5, "9e-06 Pa s"), ("mu", 11.0, "11 Pa s"),
]


@pytest.mark.parametrize("field, value, shown", OUTSIDE + [
    (f, v, f"{v!r} {'Pa s' if f == 'mu' else 'm'}") for f in ("D", "L", "CR", "mu")
    for v in (math.nan, math.inf, -math.inf)])
def test_rejects_values_outside_the_physical_range(field, value, shown):
    kw = dict(D=0.031, L=0.02, CR=90e-6, mu=0.05)
    kw[field] = value
    with pytest.raises(ValueError) as ei:
        BearingParams(**kw)
    msg = str(ei.value)
    assert msg.startswith(f"BearingParams.{field} ") and shown in msg and RANGE_WORDS[field] in msg, msg


def test_range_edges_are_inside():
    # the bounds themselves are allowed (the ranges are closed)
    for D in (1e-3, 5.0):
        for ld in (0.05, 5.0):
            for cr in (1e-5, 0.05):
                BearingParams(D=D, L=ld * D, CR=cr * (D / 2), mu=0.05)
    BearingParams(D=0.031, L=0.02, CR=90e-6, mu=1e-5)
    BearingParams(D=0.031, L=0.02, CR=90e-6, mu=10.0)


def test_bearing_file_range_names_the_key_and_the_file():
    good = {"D_mm": 31, "L_mm": 20, "CR_um": 90, "mu_Pa_s": 0.05}
    with pytest.raises(ValueError, match=r"^b\.toml: CR_um = 2000: CR = 2 mm is outside the physical range .*CR/R 1e-05 "
                                         r"\.\. 0\.05"):
        BearingParams.from_mapping({**good, "CR_um": 2000}, where="b.toml")
    with pytest.raises(ValueError, match=r"^b\.toml: mu_Pa_s = 1e-09: mu = 1e-09 Pa s is outside .*1e-05 \.\. 10 Pa s"):
        BearingParams.from_mapping({**good, "mu_Pa_s": 1e-9}, where="b.toml")


def test_shipped_bearings_are_inside_the_ranges():
    # every bearing shipped in rotor_host/bundled/ goes through BearingParams: the bearing files, the rotors'
    # bearings and the bearing each surrogate was fitted for
    from bearing_fmu.surrogates.surrogate import load_surrogate
    from rotor_host.model.rotor import Rotor

    models = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    files = sorted(models.glob("bearing*.toml"))
    assert files and all(BearingParams.from_toml(f) for f in files)
    for f in sorted(models.glob("rotor*.toml")):
        assert Rotor.from_toml(f).bearings
    for f in sorted((models / "surrogates").glob("*.json")):
        assert isinstance(load_surrogate(f).params, BearingParams)


def test_a_table_beside_bearing_is_refused_not_ignored(tmp_path):
    # a table this code does not read would leave the bearing computed without it; [geometry] and
    # [oil] are read (tests/test_geometry.py, tests/test_oil.py); the shipped files still load
    f = tmp_path / "b.toml"
    f.write_text("[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\nmu_Pa_s = 0.05\n\n[cooling]\nflow = 0.1\n")
    with pytest.raises(ValueError, match=r"b.toml: unknown table\(s\) \[cooling\]; allowed: \[bearing\], \[geometry\], "
                                         r"\[oil\]$"):
        BearingParams.from_toml(f)
    models = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    assert BearingParams.from_toml(models / "bearing_paper.toml") == PAPER_BEARING
    BearingParams.from_toml(models / "bearing_friswell.toml")
