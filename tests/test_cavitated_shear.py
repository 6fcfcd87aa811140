"""``[oil] cavitated_shear``: the cavitated film sheared as a full film (Raimondi & Boyd, the default), as
striations carrying the Couette flow of the film where it ruptured (the fraction h_rupture / h of the gap),
or as a fixed fraction (physics/solver/film.py, ``cavitated_relief``).

The closed form it is checked against: with Gumbel's (half-Sommerfeld) condition, the full-Sommerfeld
pressure of a circular bore of any L/D is antisymmetric about the line of centres, so the film cavitates
exactly over the diverging half, from h_min (theta' = pi from the thickest film) to h_max, in every axial
row, and ruptures at h_min = c (1 - eps). The Couette torque is mu omega R^3 L / c times
int dtheta / H over the full half plus int (H_r / H) dtheta / H over the cavitated half, H = 1 + eps cos:
int_0^pi dtheta / H = pi / sqrt(1 - eps^2) and int_0^pi dtheta / H^2 = pi / (1 - eps^2)^(3/2), so
striated / full = (1 + (1 - eps) / (1 - eps^2)) / 2 = (2 + eps) / (2 (1 + eps)), and with a fixed
fraction f: (1 + f) / 2.
"""

from __future__ import annotations

import math

import pytest

from bearing_fmu.physics.solver.film import full_bore_friction
from bearing_fmu.physics.oil import Oil
from bearing_fmu.physics.params import BearingFileError, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

D, L, CR, MU, OMEGA = 0.1, 0.05, 100e-6, 0.02, 100.0


def couette(shear, eps, grid=(256, 16), cavitation="gumbel") -> float:
    p = BearingParams(D=D, L=L, CR=CR, mu=MU, oil=Oil.grade("ISO VG 32", cavitated_shear=shear))
    return Reynolds(p, *grid, cavitation=cavitation).film_report(0.4 * eps * CR, -math.sqrt(0.84) * eps * CR, 0.0,
                                                                  0.0, OMEGA).couette_torque_Nm


@pytest.mark.parametrize("eps", [0.3, 0.8])
def test_striated_against_the_half_sommerfeld_closed_form(eps):
    full = couette("full", eps)
    assert full == pytest.approx(2 * math.pi * MU * OMEGA * (D / 2) ** 3 * L / (CR * math.sqrt(1 - eps * eps)),
                                 rel=1e-12)  # the full film's closed form, as before
    assert couette("striated", eps) / full == pytest.approx((2 + eps) / (2 * (1 + eps)), rel=1e-3)
    assert couette(0.25, eps) / full == pytest.approx((1 + 0.25) / 2, rel=5e-3)  # first order: the boundary cell
    assert couette(1.0, eps) == full


def test_swift_stieber_striated_shears_less_than_full_more_than_none():
    full, striated, none = (couette(s, 0.7, (128, 16), "reynolds") for s in ("full", "striated", 0.0))
    assert none < striated < full


def test_friction_power_and_the_pressure_torque():
    p_full = BearingParams(D=D, L=L, CR=CR, mu=MU, oil=Oil.grade("ISO VG 32"))
    p_str = BearingParams(D=D, L=L, CR=CR, mu=MU, oil=Oil.grade("ISO VG 32", cavitated_shear="striated"))
    state = (0.3 * CR, -0.5 * CR, 0.0, 0.0, OMEGA)
    a, b = Reynolds(p_full).film_report(*state), Reynolds(p_str).film_report(*state)
    assert b.pressure_torque_Nm == a.pressure_torque_Nm  # the pressure part is the field's, unchanged
    assert a.friction_power_W - b.friction_power_W == pytest.approx(
        (a.couette_torque_Nm - b.couette_torque_Nm) * OMEGA, rel=1e-12)


def test_closed_forms_from_the_force_refuse_it():
    p = BearingParams(D=D, L=L, CR=CR, mu=MU, oil=Oil.grade("ISO VG 32", cavitated_shear="striated"))
    with pytest.raises(ValueError, match="cavitated_shear = 'striated' needs the film's pressure field"):
        full_bore_friction(p, 1e-5, -3e-5, 0.0, 0.0, OMEGA, (10.0, 100.0))


@pytest.mark.parametrize("value, ok", [("'striated'", "striated"), ("0.4", 0.4), ("1", 1.0), ("'full'", "full"),
                                       ("1.5", None), ("'half'", None), ("true", None)])
def test_the_key(tmp_path, value, ok):
    f = tmp_path / "b.toml"
    f.write_text(f"[bearing]\nD_mm = 100\nL_mm = 50\nCR_um = 100\n\n[oil]\ngrade = 'ISO VG 32'\n"
                 f"cavitated_shear = {value}\n")
    if ok is None:
        with pytest.raises(BearingFileError, match="cavitated_shear"):
            BearingParams.from_toml(f)
    else:
        assert BearingParams.from_toml(f).oil.cavitated_shear == ok


def test_fmu_ports_refuse_it_by_name():
    from bearing_fmu.fmu.ports import port_defaults

    p = BearingParams(D=D, L=L, CR=CR, mu=MU, oil=Oil.grade("ISO VG 32", cavitated_shear=0.5))
    with pytest.raises(ValueError, match="cavitated_shear = 0.5"):
        port_defaults(p)
