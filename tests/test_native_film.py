"""The native FMU's film report (bearing_fmu/fmu/native/c/reynolds_film.c) against the Python
one (physics/solver/film.py field_report through ``Reynolds.film_report``), state by state.

The expected values are Python's own at the same state, grid, cavitation model and bore: the
Couette and pressure torque, the friction power, the inflow and the side flow within 1e-12
relative (the brief's tolerance; only the order of the sums differs), each against its own
magnitude, or against the Couette torque's (times omega for the power) where a part cancels to
near zero. The states: tests/test_native_reynolds.py's random ones (closure 0.05-0.97, any
attitude, velocities up to omega CR).
"""


import numpy as np
import pytest

from tests.test_native_reynolds import BORES, PAPER, both, lib, random_states  # noqa: F401  (lib: the fixture)

RTOL = 1e-12


def worst_report_difference(params, py, c, states) -> float:
    worst = 0.0
    for s in states:
        r = py.film_report(*s)
        want = np.array([r.couette_torque_Nm, r.pressure_torque_Nm, r.friction_power_W, r.inflow_m3_s,
                         r.side_flow_m3_s])
        got = c.film_report(*s)
        torque = abs(r.couette_torque_Nm)
        flow = s[4] * params.R * params.CR * params.L  # the Couette inflow's scale (omega R CR L)
        scale = np.maximum(np.abs(want), [torque, torque, torque * abs(s[4]), flow, flow])
        worst = max(worst, float(np.max(np.abs(got - want) / scale)))
    return worst


@pytest.mark.slow
@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
@pytest.mark.parametrize("bore", list(BORES))
def test_film_report_every_bore(lib, bore, cavitation):  # noqa: F811
    params, py, c = both(lib, BORES[bore], (32, 4), cavitation)
    assert worst_report_difference(params, py, c, random_states(params, 25, 3)) <= RTOL


@pytest.mark.parametrize("grid", [(16, 2), (64, 8)])
def test_film_report_grids(lib, grid):  # noqa: F811
    """One axial cell per half (its own end gradient and quadrature) and a finer grid."""
    for bore in ("full", "grooves with supply"):
        params, py, c = both(lib, BORES[bore], grid, "reynolds")
        assert worst_report_difference(params, py, c, random_states(params, 10, 4)) <= RTOL


def test_film_report_centred_journal(lib):  # noqa: F811
    """At the centre (y = z = 0) the inflow line is the thickest face's, not the attitude's."""
    for bore in ("full", "three lobes"):
        params, py, c = both(lib, BORES[bore], (32, 4), "reynolds")
        assert worst_report_difference(params, py, c, [(0.0, 0.0, 0.0, 0.0, 300.0)]) <= RTOL
