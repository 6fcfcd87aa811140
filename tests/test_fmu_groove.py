"""The Python FMU carries a circumferential (360 deg) feed groove (``ports.GROOVE_ROWS``: the parameter
``circumferential_groove`` [m], fed at ``supply_pressure`` [Pa], as the bearing file's
``circumferential_groove_mm`` with ``supply_pressure_kPa``).

Expected values: the Python Reynolds internal built directly on the bearing file's bore (the FMU must
build the same lands: force, Jacobian, peak pressure to round-off), and ``ports.port_defaults`` the
bearing's own keys; the thermal model's oil leaves at the full rise as ``params.groove_problem``
demands (compared with ``physics.thermal.film_temperature`` of the direct route)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.fmu.ports import port_defaults
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

D, L, CR, MU, WIDTH, PS = 0.040, 0.045, 42e-6, 0.02, 0.005, 200e3  # tests/test_circumferential_groove.py's
GRID = {"n_theta": 32, "n_x": 8}
OMEGA = 2.0 * math.pi * 46.67
GROOVED = BearingParams(D=D, L=L, CR=CR, mu=MU, geometry=Geometry(circumferential_groove=WIDTH, supply_pressure=PS))


def states():
    rng = np.random.default_rng(7)
    for _ in range(4):
        e, a = rng.uniform(0.2, 0.8), rng.uniform(-math.pi, math.pi)
        v = rng.normal(0.0, 0.1, 2) * OMEGA * CR
        yield e * CR * math.cos(a), e * CR * math.sin(a), v[0], v[1], OMEGA


def test_port_defaults_carry_the_groove():
    """The bearing's groove width [m] and supply pressure [Pa] become the FMU's parameters."""
    got = port_defaults(GROOVED)
    assert got["circumferential_groove"] == WIDTH and got["supply_pressure"] == PS and got["groove_count"] == 0


def test_fmu_force_jacobian_and_peak_are_the_internals(fmu_instance):
    """The FMU built with the bearing's port defaults computes the lands' film: force, K, C and the peak
    pressure [Pa] and angle equal the Reynolds internal's on the same bore to round-off."""
    direct = Reynolds(GROOVED, GRID["n_theta"], GRID["n_x"])
    inst = fmu_instance(internal="reynolds", D=D, L=L, CR=CR, mu=MU, **GRID, **port_defaults(GROOVED))
    try:
        for state in states():
            out = inst.step(1e-4, *state)
            F, dq, dv = direct.force_and_jacobian(*state)
            K, C = -dq, -dv
            want = [F[0], F[1], K[0, 0], K[0, 1], K[1, 0], K[1, 1], C[0, 0], C[0, 1], C[1, 0], C[1, 1]]
            got = [out[n] for n in ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")]
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.max(np.abs(want)))
            peak = direct.peak_pressure(*state)
            assert peak[0] >= PS  # the groove's own pressure at least (Reynolds.peak_pressure)
            assert inst.get("peak_pressure") == pytest.approx(peak[0], rel=1e-12)
            assert inst.get("peak_pressure_angle") == pytest.approx(peak[1], abs=1e-12)
    finally:
        inst.close()


def test_thermal_groove_leaves_at_the_full_rise(fmu_instance):
    """thermal = true on the grooved bore: the FMU's oil is the parameters' with all the lands' oil leaving at
    the full rise (outflow_rise 'full', which a grooved bearing file must say: params.groove_problem), so its
    quasi-static T_eff and mu_eff at the inputs of Initialization Mode are the direct route's
    film_temperature of that bearing, and not the half rise's."""
    from dataclasses import replace

    from bearing_fmu.physics.oil import KELVIN, Oil
    from bearing_fmu.physics.thermal import film_temperature

    oil = Oil.walther(46.0, 40.0 + KELVIN, 6.8, 100.0 + KELVIN, outflow_rise="full", name="VG 46")
    T_s = 45.0 + KELVIN
    params = replace(GROOVED, mu=oil.mu(T_s), oil=oil)
    state = (0.3 * CR, -0.5 * CR, 0.0, 0.0, OMEGA)
    inst = fmu_instance(internal="reynolds", D=D, L=L, CR=CR, mu=params.mu, **GRID, **port_defaults(params),
                        thermal=True, T_supply=T_s, **dict(zip(("y", "z", "vy", "vz", "omega"), state)))
    try:
        report = Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*state)
        T, mu_eff, _tau = film_temperature(params, report, oil, T_s, None, 0.0)
        half = film_temperature(params, report, replace(oil, outflow_rise="half"), T_s, None, 0.0)[0]
        assert T - T_s > 1.0 and abs(half - T) > 0.05 * (T - T_s)  # the full rise is what is checked
        assert inst.get("T_eff") == pytest.approx(T, rel=1e-9)
        assert inst.get("mu_eff") == pytest.approx(mu_eff, rel=1e-9)
    finally:
        inst.close()


def test_pads_with_a_groove_refused_by_name():
    """Tilting pads have no circumferential groove: the parameter to set back is named."""
    from types import SimpleNamespace

    from bearing_fmu.fmu import ports

    values = {r[0]: r[4] for r in ports.GEOMETRY_ROWS + ports.PAD_ROWS + ports.GROOVE_ROWS}
    v = SimpleNamespace(**{**values, **port_defaults(GROOVED)})
    v.pads, v.pivot_1, v.pivot_2, v.pivot_3 = 3, 0.0, 2.0, 4.0
    with pytest.raises(ValueError, match="circumferential_groove = 0.005"):
        ports.geometry_of(v)
