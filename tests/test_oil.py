"""The oil's viscosity law (physics/oil.py) and the bearing file's [oil] table."""

from __future__ import annotations

import math

import pytest

from bearing_fmu.physics.oil import GRADES, KELVIN, Oil
from bearing_fmu.physics.params import PAPER_BEARING, BearingFileError, BearingParams

C = KELVIN


def test_walther_passes_through_its_points_and_falls():
    """Through both points exactly (ASTM D341's equation inverted), monotonic between, and the
    ISO VG 32 preset has 32 cSt at 40 C (ISO 3448 mid-point) and 5.4 cSt at 100 C."""
    oil = Oil.walther(100.0, 40 + C, 11.0, 100 + C)
    assert oil.nu(40 + C) * 1e6 == pytest.approx(100.0, rel=1e-12)
    assert oil.nu(100 + C) * 1e6 == pytest.approx(11.0, rel=1e-12)
    mus = [oil.mu(t + C) for t in range(0, 151, 5)]
    assert all(a > b for a, b in zip(mus, mus[1:]))
    vg32 = Oil.grade("ISO VG 32")
    assert vg32.nu(40 + C) * 1e6 == pytest.approx(32.0, rel=1e-12)
    assert vg32.nu(100 + C) * 1e6 == pytest.approx(5.4, rel=1e-12)
    assert vg32.mu(40 + C) == pytest.approx(32e-6 * 861.0, rel=1e-12)  # rho nu, Shigley's 861 kg/m^3
    assert set(GRADES) == {"ISO VG 32", "ISO VG 46", "SAE 30"}


def test_sae30_is_shigleys_fit():
    """Shigley's Mechanical Engineering Design, Table 12-1 (Seireg & Dandage): SAE 30,
    mu = 0.0141 exp(1360 / (T_F + 95)) micro-reyn; its solutions manual, problem 12-20: 15.2 mPa s
    at 79 C."""
    oil = Oil.grade("SAE 30")
    assert oil.mu(79 + C) * 1e3 == pytest.approx(15.2, abs=0.05)
    T_F = 150.0
    assert oil.mu((T_F - 32) / 1.8 + C) == pytest.approx(0.0141e-6 * 6894.757 * math.exp(1360 / (T_F + 95)),
                                                         rel=1e-12)


def test_walther_against_an_independent_point():
    """ASTM D341's straight line in log log (nu + 0.7) vs log T, checked at a third temperature
    computed by hand from the two points (not by the code's coefficients): 32 cSt at 40 C and 5.4
    cSt at 100 C give at 70 C: w = w40 + (w100 - w40) (log 343.15 - log 313.15) / (log 373.15 - log 313.15)."""
    w40 = math.log10(math.log10(32.7))
    w100 = math.log10(math.log10(6.1))
    s = (math.log10(343.15) - math.log10(313.15)) / (math.log10(373.15) - math.log10(313.15))
    nu70 = 10 ** (10 ** (w40 + s * (w100 - w40))) - 0.7
    assert Oil.grade("ISO VG 32").nu(70 + C) * 1e6 == pytest.approx(nu70, rel=1e-10)
    assert 10.0 < nu70 < 13.0  # a VG 32 turbine oil has about 11 cSt at 70 C


def test_vogel():
    oil = Oil.vogel(5e-5, 900.0, 160.0)
    assert oil.mu(80 + C) == pytest.approx(5e-5 * math.exp(900.0 / (80 + C - 160.0)), rel=1e-14)


@pytest.mark.parametrize("make, match", [
    (lambda: Oil.walther(10.0, 40 + C, 20.0, 100 + C), "must fall as the temperature rises"),
    (lambda: Oil.walther(-3.0, 40 + C, 2.5, 100 + C), r"must be > 0 cSt"),
    (lambda: Oil.walther(30.0, 40 + C, 30.0, 40 + C), "two temperatures must differ"),
    (lambda: Oil.walther(10.0, 40 + C, 1.5, 100 + C), "below the 2 cSt"),
    (lambda: Oil.walther(5.0, 40 + C, 2.1, 100 + C), r"at 150 C, the top of its range .* lower the range's top"),
    (lambda: Oil.vogel(-1e-4, 900.0, 160.0), "needs a > 0, b > 0, c >= 0"),
    (lambda: Oil.vogel(1e-4, 900.0, 300.0), "diverges at T = c = 300 K"),
    (lambda: Oil.grade("SAE 40"), "unknown grade 'SAE 40'"),
    (lambda: Oil.grade("ISO VG 32", T_supply=200 + C), r"supply_C = 200 C is outside its range 0 C .. 150 C"),
])
def test_refused_by_name(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_temperature_outside_the_range_is_refused():
    oil = Oil.grade("ISO VG 46")
    with pytest.raises(ValueError, match=r"T = 473.15 K \(200 C\) is outside the viscosity law's range 0 C .. 150 C "
                                         r"\(the bearing file's \[oil\] range_C\)"):
        oil.mu(200 + C)
    with pytest.raises(ValueError, match="T_eff = nan"):
        oil.check_temperature(math.nan, "T_eff")


def _write(tmp_path, text, name="b.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


BEARING = '[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\n'


def test_bearing_file_with_oil(tmp_path):
    p = _write(tmp_path, BEARING + '[oil]\ngrade = "ISO VG 32"\nsupply_C = 50.0\n')
    b = BearingParams.from_toml(p)
    assert b.oil is not None and b.oil.T_supply == 50 + C
    assert b.mu == b.oil.mu(50 + C)
    assert b.with_viscosity(0.01).mu == 0.01 and b.with_viscosity(0.01).oil == b.oil
    p = _write(tmp_path, BEARING + '[oil]\nnu_cSt = [68.0, 8.6]\ntemperatures_C = [40.0, 100.0]\n'
               'density_kg_m3 = 870.0\nrange_C = [-10.0, 120.0]\n', "c.toml")
    b = BearingParams.from_toml(p)
    assert b.mu == pytest.approx(68e-6 * 870.0, rel=1e-12)  # supply_C defaults to 40 C
    assert b.oil.T_min == -10 + C and b.oil.density == 870.0


def test_no_oil_is_todays_bearing_bit_for_bit():
    b = BearingParams.from_toml("rotor_host/bundled/bearing_paper.toml")
    assert b == PAPER_BEARING and b.oil is None and repr(b) == repr(PAPER_BEARING)


@pytest.mark.parametrize("text, match", [
    (BEARING + 'mu_Pa_s = 0.05\n[oil]\ngrade = "ISO VG 32"\n', r"\[bearing\] mu_Pa_s = 0.05 and an \[oil\] table both"),
    (BEARING, r"\[bearing\]: missing key\(s\) mu_Pa_s"),
    (BEARING + '[oil]\nsupply_C = 40.0\n', r"\[oil\] give exactly one viscosity law.*\(none given\)"),
    (BEARING + '[oil]\ngrade = "ISO VG 32"\nvogel_a_Pa_s = 1e-4\nvogel_b_K = 900.0\nvogel_c_K = 160.0\n',
     r"\[oil\] give exactly one viscosity law.*given: grade; vogel"),
    (BEARING + '[oil]\nnu_cSt = [32.0, 5.4]\n', r"\[oil\] nu_cSt needs temperatures_C"),
    (BEARING + '[oil]\nvogel_a_Pa_s = 1e-4\nvogel_b_K = 900.0\n', r"\[oil\] the Vogel law needs .*missing: vogel_c_K"),
    (BEARING + '[oil]\nnu_cSt = [-32.0, 5.4]\ntemperatures_C = [40.0, 100.0]\n',
     r"\[oil\] nu_cSt = \[-32.0, 5.4\]: entry 1 = -32.0 must be a finite number > 0"),
    (BEARING + '[oil]\nnu_cSt = [5.4, 32.0]\ntemperatures_C = [40.0, 100.0]\n',
     r"\[oil\] the viscosity must fall as the temperature rises"),
    (BEARING + '[oil]\ngrade = "ISO VG 32"\nsupply_C = 180.0\n', r"\[oil\] supply_C = 180 C is outside its range"),
    (BEARING + '[oil]\ngrade = "ISO VG 32"\nrange_C = [100.0, 20.0]\n', r"\[oil\] range_C = \[100, 20\] must have low < high"),
    (BEARING + '[oil]\ngrade = "ISO VG 100"\n', r"\[oil\] grade = 'ISO VG 100'; choose one of ISO VG 32, ISO VG 46, SAE 30"),
    (BEARING + '[oill]\ngrade = "ISO VG 32"\n', r"unknown table\(s\) \[oill\] \(did you mean \[oil\]\?\)"),
])
def test_bad_oil_table_is_refused_naming_file_and_key(tmp_path, text, match):
    p = _write(tmp_path, text)
    with pytest.raises(BearingFileError, match=rf"{p}: .*{match}" if not match.startswith("unknown") else match):
        BearingParams.from_toml(p)


def test_presets_are_records_whose_fields_are_the_oil_tables_keys(tmp_path):
    """Each preset (PRESETS) is a named record whose data fields are keys of the [oil] table: the
    table that writes them out gives the same oil, bit for bit, as the table naming the grade; and
    each says where its numbers come from."""
    import dataclasses

    from bearing_fmu.physics.oil import OIL_KEYS, PRESETS, OilPreset

    keys = {k.name for k in OIL_KEYS}
    assert [p.name for p in PRESETS] == list(GRADES) and all(GRADES[p.name] is p for p in PRESETS)
    for i, p in enumerate(PRESETS):
        assert isinstance(p, OilPreset) and len(p.source) > 40
        with pytest.raises(dataclasses.FrozenInstanceError):
            p.name = "x"
        data = {f.name: getattr(p, f.name) for f in dataclasses.fields(p) if f.name not in ("name", "source")}
        data = {k: v for k, v in data.items() if v is not None}
        assert set(data) <= keys, f"{p.name}: {set(data) - keys} are no [oil] keys"
        lines = [f"{k} = {list(v) if isinstance(v, tuple) else repr(v)}" for k, v in data.items()]
        by_keys = BearingParams.from_toml(_write(tmp_path, BEARING + "[oil]\n" + "\n".join(lines) + "\n",
                                                 f"k{i}.toml"))
        by_name = BearingParams.from_toml(_write(tmp_path, BEARING + f'[oil]\ngrade = "{p.name}"\n',
                                                 f"g{i}.toml"))
        assert by_keys.oil.coefficients == by_name.oil.coefficients and by_keys.mu == by_name.mu
