"""Every [oil] heat balance in the Python FMU (docs/thermal.md, docs/fmu.md): its parameters
``oil_outflow_share`` s (0.5: the side flow at half the rise, 0: all the oil at the full rise),
``oil_ambient_loss`` h A [W/K] and ``oil_T_ambient`` [K] (0: the supply temperature), their starts a
bearing file's ``outflow_rise``, ``ambient_W_K``, ``ambient_C`` (``ports.port_defaults``).

Expected values: ``physics.thermal.film_temperature`` of the direct route at the same journal state
(quasi-static at the inputs of Initialization Mode, lagged over a step), to 1e-10; and, independent of
the code, the energy balance written here from the FMU's outputs: P_loss = rho c_p (Q - s Q_side) dT +
h A (T_eff - T_amb) with dT = (T_eff - T_supply) / k and the inflow Q of the film (the flows do not depend
on mu: physics/thermal.py), closing to 1e-9 of P_loss.
"""

from __future__ import annotations

from dataclasses import replace

import pytest

from bearing_fmu.fmu import ports
from bearing_fmu.physics.oil import KELVIN, Oil
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.thermal import film_temperature

PAPER = dict(D=0.031, L=0.02, CR=90e-6)  # paper Table 2
GRID = {"n_theta": 32, "n_x": 4}
IN = ("y", "z", "vy", "vz", "omega")
T_S = 45.0 + KELVIN
STATE = (2e-5, -6e-5, 1e-4, -2e-4, 600.0)
# the full rise; a housing losing 2 W/K to 20 C air (below the supply); a loss to the supply temperature
# (no ambient_C: oil_T_ambient 0) at another k; the full rise with a loss
BALANCES = {"full": dict(outflow_rise="full"),
            "ambient": dict(ambient_W_K=2.0, T_ambient=20.0 + KELVIN),
            "ambient at supply": dict(ambient_W_K=2.0, rise_factor=0.7),
            "full with ambient": dict(outflow_rise="full", ambient_W_K=0.5, T_ambient=30.0 + KELVIN)}


def bearing(balance: dict, **geometry) -> BearingParams:
    oil = replace(Oil.grade("ISO VG 46"), **balance)
    return BearingParams(**PAPER, mu=oil.mu(oil.T_supply), oil=oil, **geometry)


def energy_residual(out: dict, params: BearingParams, inflow: float, T_s: float) -> float:
    """P_loss - rho c_p (Q - s Q_side) dT - h A (T_eff - T_amb) over P_loss, from the FMU's outputs ``out``
    and the bearing file's [oil] (s: 1/2 for 'half', 0 for 'full'; T_amb: ambient_C, else the supply)."""
    oil = params.oil
    s = {"half": 0.5, "full": 0.0}[oil.outflow_rise]
    T_amb = T_s if oil.T_ambient is None else oil.T_ambient
    dT = (out["T_eff"] - T_s) / oil.rise_factor
    carried = oil.density * oil.heat_capacity * (inflow - s * out["Q_side"]) * dT
    return (out["P_loss"] - carried - oil.ambient_W_K * (out["T_eff"] - T_amb)) / out["P_loss"]


def test_port_defaults_carry_every_balance():
    """A bearing file's outflow_rise, ambient_W_K and ambient_C become the FMU's parameters (no refusal)."""
    got = ports.port_defaults(bearing(BALANCES["full with ambient"]))
    assert (got["oil_outflow_share"], got["oil_ambient_loss"], got["oil_T_ambient"]) == (0.0, 0.5, 30.0 + KELVIN)
    got = ports.port_defaults(bearing(BALANCES["ambient at supply"]))
    assert (got["oil_outflow_share"], got["oil_ambient_loss"], got["oil_T_ambient"]) == (0.5, 2.0, 0.0)
    assert got["oil_rise_factor"] == 0.7


def test_outflow_share_takes_the_two_balances_only():
    assert ports.check_value("oil_outflow_share", 0.0) == 0.0 and ports.check_value("oil_outflow_share", 0.5) == 0.5
    with pytest.raises(ValueError, match="oil_outflow_share = 0.3 must be 0.5 .* or 0"):
        ports.check_value("oil_outflow_share", 0.3)
    with pytest.raises(ValueError, match="oil_ambient_loss = -1.0 must be finite"):
        ports.check_value("oil_ambient_loss", -1.0)


@pytest.mark.parametrize("name", list(BALANCES))
def test_fmu_film_temperature_is_the_direct_routes(fmu_instance, name):
    """thermal = true with the balance's parameters (a bearing file's port defaults): the quasi-static
    T_eff and mu_eff at the inputs of Initialization Mode equal film_temperature's (1e-10), the energy
    balance closes at the outputs (1e-9), and a lagged step equals film_temperature's lag from there."""
    params = bearing(BALANCES[name])
    inst = fmu_instance(internal="reynolds", **PAPER, mu=params.mu, **GRID, **ports.port_defaults(params),
                        thermal=True, T_supply=T_S, **dict(zip(IN, STATE)))
    try:
        rey = Reynolds(params, GRID["n_theta"], GRID["n_x"])
        report = rey.film_report(*STATE)
        T, mu_eff, _tau = film_temperature(params, report, params.oil, T_S)
        out = {n: inst.get(n) for n in ("T_eff", "mu_eff", "P_loss", "Q_side")}
        assert out["T_eff"] == pytest.approx(T, rel=1e-10) and out["mu_eff"] == pytest.approx(mu_eff, rel=1e-10)
        assert abs(energy_residual(out, params, report.inflow_m3_s, T_S)) <= 1e-9
        default = film_temperature(params, report, replace(params.oil, outflow_rise="half", ambient_W_K=0.0,
                                                           rise_factor=0.5), T_S)[0]
        assert abs(T - default) > 0.05 * abs(default - T_S)  # another balance than the default: what is checked
        state = (3e-5, -5e-5, 0.0, 0.0, 650.0)
        inst.step(2e-3, *state)
        want = film_temperature(params, rey.film_report(*state), params.oil, T_S, out["T_eff"], 2e-3)
        assert inst.get("T_eff") == pytest.approx(want[0], rel=1e-10)
        assert inst.get("mu_eff") == pytest.approx(want[1], rel=1e-10) and want[0] != out["T_eff"]
    finally:
        inst.close()


def test_ambient_at_the_supply_follows_the_input(fmu_instance):
    """oil_T_ambient = 0 (a file without ambient_C): the ambient is the input T_supply, whatever the file's
    supply_C; at a supply 10 K above it the FMU's balance is film_temperature's with T_ambient None."""
    params = bearing(BALANCES["ambient at supply"])
    T_s = params.oil.T_supply + 10.0
    inst = fmu_instance(internal="reynolds", **PAPER, mu=params.mu, **GRID, **ports.port_defaults(params),
                        thermal=True, T_supply=T_s, **dict(zip(IN, STATE)))
    try:
        report = Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*STATE)
        T = film_temperature(params, report, params.oil, T_s)[0]
        fixed = film_temperature(params, report, replace(params.oil, T_ambient=params.oil.T_supply), T_s)[0]
        assert inst.get("T_eff") == pytest.approx(T, rel=1e-10) and abs(fixed - T) > 1e-3
        out = {n: inst.get(n) for n in ("T_eff", "P_loss", "Q_side")}
        assert abs(energy_residual(out, params, report.inflow_m3_s, T_s)) <= 1e-9
    finally:
        inst.close()


def test_fmu_refuses_another_outflow_share_by_name(fmu, unzip):
    """oil_outflow_share = 0.3 (neither balance): the FMU's setter refuses it (fmi2Error), naming the two values."""
    from fmpy.fmi1 import FMICallException

    from tests.conftest import logging_slave

    inst, log, names = logging_slave(fmu, unzip)
    vr = {n: v.valueReference for n, v in names.items()}
    try:
        with pytest.raises(FMICallException):
            inst.setReal([vr["oil_outflow_share"]], [0.3])
    finally:
        inst.freeInstance()
    text = " ".join(log)
    assert "oil_outflow_share = 0.3 must be 0.5" in text and "or 0" in text, text
