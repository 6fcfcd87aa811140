"""The native FMU's oil laws and film temperature (bearing_fmu/fmu/native/c/oil_thermal.c)
against Python's (physics/oil.py through fmu/ports.oil_of, physics/thermal.py film_temperature).

The expected values are Python's own for the same FMU oil parameters (ports.port_defaults of a
bearing with that [oil]: the presets ISO VG 32, ISO VG 46 by Walther, SAE 30 by Vogel, and a
Walther law through a data sheet's two points) and the same film report (the Python Reynolds
solver's at a loaded state of the paper bearing): mu(T) over the oil's range within 1e-13
relative (pow and exp of the C library against Python's), the film temperature, its viscosity
and the residence time within 1e-12 relative (the brief's; Brent's iterates are scipy's),
quasi-static and lagged over steps from 1e-4 s to 1 s, from above and below the balance.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from bearing_fmu.fmu import ports
from bearing_fmu.fmu.native.solver_lib import NativeOil
from bearing_fmu.physics.oil import KELVIN, Oil
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.thermal import film_temperature
from tests.test_native_reynolds import PAPER, lib  # noqa: F401  (lib: the fixture)

OILS = {"ISO VG 32": Oil.grade("ISO VG 32"), "ISO VG 46": Oil.grade("ISO VG 46"), "SAE 30": Oil.grade("SAE 30"),
        "data sheet": Oil.walther(68.0, 40.0 + KELVIN, 8.6, 100.0 + KELVIN, T_min=260.0, T_max=420.0)}


def oil_values(oil) -> dict:
    """The FMU's oil parameters of a bearing with ``oil`` (the rows' defaults where the law sets none)."""
    return {**{r[0]: r[4] for r in ports.OIL_ROWS}, **ports.port_defaults(BearingParams(**PAPER, oil=oil))}


def both_oils(lib, oil):  # noqa: F811
    values = oil_values(oil)
    return ports.oil_of(SimpleNamespace(**values), values["oil_law"]), NativeOil(lib, values)


@pytest.mark.parametrize("name", list(OILS))
def test_viscosity_law(lib, name):  # noqa: F811
    py, c = both_oils(lib, OILS[name])
    for T in np.linspace(py.T_min, py.T_max, 41):
        assert c.mu(T) == pytest.approx(py.mu(T), rel=1e-13, abs=0.0)


@pytest.mark.parametrize("name", [n if n == "ISO VG 46" else pytest.param(n, marks=pytest.mark.slow) for n in OILS])
def test_film_temperature(lib, name):  # noqa: F811
    py, c = both_oils(lib, OILS[name])
    params = BearingParams(**PAPER, oil=OILS[name])
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 1e-4, -2e-4, 600.0)
    T_s = 40.0 + KELVIN
    cases = [(None, 0.0)] + [(T_old, dt) for T_old in (T_s - 3.0, T_s + 30.0) for dt in (1e-4, 1e-2, 1.0)]
    for T_old, dt in cases:
        want = film_temperature(params, report, py, T_s, T_old, dt)
        got = c.film_temperature(params, report, T_s, T_old, dt)
        assert got == pytest.approx(want, rel=1e-12, abs=0.0), (T_old, dt)
    assert want[0] > T_s  # the film runs hot: the balance was solved, not skipped


def test_range_left_is_an_error(lib):  # noqa: F811
    """Python's ThermalError and C's refusal at the same supply temperature outside the range."""
    py, c = both_oils(lib, OILS["ISO VG 46"])
    params = BearingParams(**PAPER, oil=OILS["ISO VG 46"])
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 0.0, 0.0, 600.0)
    with pytest.raises(ValueError, match="T_supply"):
        film_temperature(params, report, py, py.T_max + 1.0)
    with pytest.raises(ValueError, match="T_supply = .* outside the viscosity law's range"):
        c.film_temperature(params, report, py.T_max + 1.0)


def test_bad_oil_parameters(lib):  # noqa: F811
    values = oil_values(OILS["ISO VG 46"])
    with pytest.raises(ValueError, match="must fall as the temperature rises"):
        NativeOil(lib, {**values, "oil_nu_2": values["oil_nu_1"] * 2.0})
    with pytest.raises(ValueError, match="Vogel law diverges"):
        NativeOil(lib, {**values, "oil_law": "vogel", "oil_vogel_c": values["oil_T_min"] + 1.0})
    assert math.isfinite(NativeOil(lib, values).mu(330.0))
