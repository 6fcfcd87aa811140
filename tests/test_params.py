"""BearingParams refuses bad values with a message naming the field and the value."""

import math

import pytest

from bearing_fmu.params import PAPER_BEARING, BearingParams


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
