"""Every [oil] heat balance in the native FMU (docs/thermal.md, docs/fmu.md): the outflow share s
(``oil_outflow_share``: 0.5 half rise, 0 full rise), the housing's loss h A (``oil_ambient_loss``) to
the ambient ``oil_T_ambient`` (0: the supply temperature), in c/oil_thermal.c (ot_balance_terms,
ot_film_temperature, ot_film_rate) and the native FMUs' thermal ports; and the native Reynolds FMU's
thermal model on a circumferential groove (all the lands' oil at the full rise).

Expected values: ``physics.thermal.film_temperature`` and ``heat_balance_rise`` (Python) at the same
film report (quasi-static and lagged: the C solve is a port with scipy's brentq iterates, so 1e-12;
the FMU's against Python to 1e-10), the Python FMU at the same parameters, an energy balance written
here from the FMU's outputs alone (P = rho c_p (Q - s Qs) dT + h A (T_eff - T_amb), the inflow Q from
the film, which does not depend on mu), central differences of the outputs for the directional
derivatives.
"""

import math
from dataclasses import replace
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

VG46 = Oil.grade("ISO VG 46")
T_S = 45.0 + KELVIN
# the balances besides the default: the full rise; a housing losing 2 W/K to 20 C air (below the supply);
# the loss to an ambient at the supply temperature (T_ambient None: oil_T_ambient 0); both together
BALANCES = {"full": dict(outflow_rise="full"),
            "ambient": dict(ambient_W_K=2.0, T_ambient=20.0 + KELVIN),
            "ambient at supply": dict(ambient_W_K=2.0, rise_factor=0.7),
            "full with ambient": dict(outflow_rise="full", ambient_W_K=0.5, T_ambient=30.0 + KELVIN)}


def oil_values(oil) -> dict:
    """The FMU's oil parameters of the paper bearing with ``oil`` (ports.port_defaults; the rows' defaults
    where the law sets none)."""
    rows = ports.OIL_ROWS + ports.BALANCE_ROWS
    return {**{r[0]: r[4] for r in rows}, **ports.port_defaults(BearingParams(**PAPER, oil=oil))}


@pytest.mark.parametrize("name", list(BALANCES))
def test_c_film_temperature_equals_python(lib, name):  # noqa: F811
    """ot_film_temperature with the balance's parameters against physics.thermal.film_temperature at one
    film report: quasi-static and lagged from below and above over short and long steps, to 1e-12."""
    values = oil_values(replace(VG46, **BALANCES[name]))
    oil = ports.oil_of(SimpleNamespace(**values), values["oil_law"])  # the parameters carry the balance
    for key, value in BALANCES[name].items():
        assert getattr(oil, key) == value, key
    c = NativeOil(lib, values)
    params = BearingParams(**PAPER, oil=oil)
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 1e-4, -2e-4, 600.0)
    for T_old, dt in [(None, 0.0)] + [(T_S + d, dt) for d in (-8.0, 30.0) for dt in (1e-4, 1e-2, 1.0)]:
        want = film_temperature(params, report, oil, T_S, T_old, dt)
        got = c.film_temperature(params, report, T_S, T_old, dt)
        assert got == pytest.approx(want, rel=1e-12, abs=0.0), (T_old, dt)
    half = film_temperature(params, report, VG46, T_S)[0]
    assert abs(want[0] - half) > 0.05 * (half - T_S)  # another balance than the default, solved


def test_c_film_cooled_below_its_range_is_refused(lib):  # noqa: F811
    """A housing loss so large that the film would run below the oil's range: both refuse (C by name)."""
    oil = replace(VG46, ambient_W_K=1e4, T_ambient=-60.0 + KELVIN)
    params = BearingParams(**PAPER, oil=oil)
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 0.0, 0.0, 600.0)
    with pytest.raises(ValueError, match="below the oil's range"):
        film_temperature(params, report, oil, T_S)
    with pytest.raises(ValueError, match="below the oil.s range.*oil_ambient_loss"):
        NativeOil(lib, oil_values(oil)).film_temperature(params, report, T_S)


def test_c_outflow_share_other_than_half_or_none_refused(lib):  # noqa: F811
    values = oil_values(VG46)
    with pytest.raises(ValueError, match="oil_outflow_share = 0.25 must be 0.5 .* or 0"):
        NativeOil(lib, {**values, "oil_outflow_share": 0.25})
    with pytest.raises(ValueError, match="oil_ambient_loss = -1"):
        NativeOil(lib, {**values, "oil_ambient_loss": -1.0})
