"""The Python FMU's bore and oil parameters and its thermal ports (bearing_fmu/fmu/ports.py).

The thermal outputs are checked against the heat balance solved on the Reynolds solver run at the
viscosity the FMU reports (physics/thermal.py's temperature_rise: P / (rho c_p (Q - Qs / 2)),
Shigley's balance), and against physics.thermal.effective_temperature at a static equilibrium;
the lag against its closed form (a first-order lag with the film's residence time)."""

import math
from pathlib import Path

import pytest
from fmpy.fmi1 import FMICallException

from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.oil import Oil
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.thermal import residence_time_s, temperature_rise

OMEGA = 2 * math.pi * 44.0
STATE = (12e-6, -45e-6, 0.0, 0.0, OMEGA)
T_SUPPLY = 313.15
VG46 = Oil.grade("ISO VG 46")  # the FMU's Walther defaults are ISO VG 46's two points (physics/oil.py)
THERMAL = {"thermal": True, "oil_law": "walther", "mu": VG46.mu(T_SUPPLY)}
BEARING = BearingParams(D=PAPER_BEARING.D, L=PAPER_BEARING.L, CR=PAPER_BEARING.CR, mu=VG46.mu(T_SUPPLY))


def _refusal(fmu, unzip, **params) -> str:
    """The log of an initialisation with ``params``, which must be refused (fmi2Error)."""
    from tests.conftest import logging_slave

    inst, log, names = logging_slave(fmu, unzip)
    try:
        for k, v in params.items():
            {"Real": inst.setReal, "Integer": inst.setInteger, "Boolean": inst.setBoolean,
             "String": inst.setString}[names[k].type]([names[k].valueReference], [v])
        inst.setupExperiment(startTime=0.0)
        inst.enterInitializationMode()
        with pytest.raises(FMICallException):
            inst.exitInitializationMode()
    finally:
        inst.freeInstance()
    return " ".join(log)


@pytest.mark.slow
def test_unconnected_supply_temperature_leaves_the_force_unchanged(fmu_instance):
    """thermal = false (the default): whatever T_supply holds, the force is the Reynolds solver's at mu
    exactly, mu_eff = mu, T_eff = T_supply, and the thermal outputs are not computed (0)."""
    from bearing_fmu.physics.solver.reynolds import Reynolds

    want = Reynolds(BEARING).force(*STATE)
    for T in (T_SUPPLY, 380.0):
        inst = fmu_instance(mu=BEARING.mu, oil_law="walther", T_supply=T)
        try:
            out = inst.step(1e-4, *STATE)
            assert (out["Fy"], out["Fz"]) == want
            assert (inst.get("T_eff"), inst.get("mu_eff"), inst.get("P_loss"), inst.get("Q_side")) == (T, BEARING.mu, 0, 0)
        finally:
            inst.close()


def test_thermal_outputs_are_the_heat_balance_of_the_film(fmu_instance):
    """In Initialization Mode T_eff is quasi-static: T_eff = T_supply + k P / (rho c_p (Q - Qs / 2)) with
    P, Q, Qs of the Reynolds solver run at mu(T_eff) itself; the force is that solver's at mu_eff."""
    from bearing_fmu.physics.solver.reynolds import Reynolds

    inst = fmu_instance(**THERMAL, **dict(zip(("y", "z", "vy", "vz", "omega"), STATE)), T_supply=T_SUPPLY)
    try:
        T, mu_eff = inst.get("T_eff"), inst.get("mu_eff")
        hot = Reynolds(BEARING.with_viscosity(mu_eff))
        rep = hot.film_report(*STATE)
        assert mu_eff == pytest.approx(VG46.mu(T), rel=1e-12)
        assert T == pytest.approx(T_SUPPLY + 0.5 * temperature_rise(rep, VG46), abs=1e-8)
        assert T > T_SUPPLY + 0.5  # it does heat: the check above is not 0 = 0
        assert inst.get("P_loss") == pytest.approx(rep.friction_power_W, rel=1e-10)
        assert inst.get("Q_side") == pytest.approx(rep.side_flow_m3_s, rel=1e-10)
        assert (inst.get("Fy"), inst.get("Fz")) == pytest.approx(hot.force(*STATE), rel=1e-10)
    finally:
        inst.close()


def test_T_eff_lags_by_the_residence_time_and_is_part_of_the_fmu_state(fmu_instance):
    """From the quasi-static T_eff at one speed, the speed doubles: T_eff moves toward the new balance
    as a first-order lag with the film's residence time V / Q (one step: within the implicit step's
    error of exp(-dt / tau)); a restored FMU state brings T_eff back."""
    from bearing_fmu.physics.solver.reynolds import Reynolds

    slow = (*STATE[:4], OMEGA / 2)
    inst = fmu_instance(**THERMAL, **dict(zip(("y", "z", "vy", "vz", "omega"), slow)), T_supply=T_SUPPLY)
    try:
        T0 = inst.get("T_eff")
        saved = inst.fmu.getFMUstate()
        rep = Reynolds(BEARING).film_report(*STATE)
        tau = residence_time_s(BEARING, rep)
        dt = 0.2 * tau
        inst.step(dt, *STATE)
        T1 = inst.get("T_eff")
        # the balance at the new speed, at T1's viscosity (the implicit step's target)
        target = T_SUPPLY + 0.5 * temperature_rise(Reynolds(BEARING.with_viscosity(VG46.mu(T1))).film_report(*STATE),
                                                   VG46)
        assert T1 == pytest.approx(target + (T0 - target) * math.exp(-dt / tau), abs=1e-8)
        assert T0 < T1 < target
        for _ in range(60):  # 12 residence times: the lag has settled on the quasi-static value
            inst.step(dt, *STATE)
        T = inst.get("T_eff")
        fresh = fmu_instance(**THERMAL, **dict(zip(("y", "z", "vy", "vz", "omega"), STATE)), T_supply=T_SUPPLY)
        assert T == pytest.approx(fresh.get("T_eff"), abs=1e-4)
        fresh.close()
        inst.fmu.setFMUstate(saved)
        assert inst.get("T_eff") == T0
        inst.fmu.freeFMUstate(saved)
    finally:
        inst.close()


@pytest.mark.parametrize("params, words", [
    ({"thermal": True, "internal": "linear", "oil_law": "walther"}, ("thermal = true", "internal = 'linear'")),
    ({"thermal": True}, ("thermal = true needs the oil's viscosity law", "oil_law")),
    ({"internal": "map", "groove_count": 2, "groove_1": math.pi / 2, "groove_2": 1.5 * math.pi},
     ("models only the full 360 deg circular bore", "2 axial grooves")),  # a full-bore map (its file says)
    ({"lobes": 2, "preload": 0.5, "internal": "taylor"}, ("fitted for the bore 'full 360 deg circular bore'", "2 lobes")),
    ({"groove_count": 2, "groove_1": 0.1, "groove_2": 0.2}, ("geometry parameters", "overlap")),
])
def test_refused_by_name(fmu, unzip, params, words):
    log = _refusal(fmu, unzip, **params)
    for w in words:
        assert w in log


@pytest.mark.slow
def test_geometry_parameters_reach_the_solver(fmu_instance):
    """Two axial grooves and a lemon bore set as parameters give the Reynolds solver of that bore."""
    from bearing_fmu.physics.solver.reynolds import Reynolds

    cases = [({"groove_count": 2, "groove_1": math.pi / 2, "groove_2": 1.5 * math.pi, "supply_pressure": 5e4},
              Geometry(grooves=(math.pi / 2, 1.5 * math.pi), supply_pressure=5e4)),
             ({"lobes": 2, "preload": 0.5, "n_theta": 64}, Geometry(lobes=2, preload=0.5)),
             ({"partial_arc": True, "arc_start": 0.5 * math.pi, "arc_end": 1.5 * math.pi}, Geometry(arc=(0.5 * math.pi, 1.5 * math.pi)))]
    for params, geometry in cases:
        inst = fmu_instance(**params)
        try:
            out = inst.step(1e-4, *STATE)
            grid = {"n_theta": params["n_theta"]} if "n_theta" in params else {}
            want = Reynolds(BearingParams(**PAPER_BEARING.as_dict(), geometry=geometry), **grid).force(*STATE)
            assert (out["Fy"], out["Fz"]) == want
        finally:
            inst.close()


@pytest.mark.slow
def test_build_with_a_bearing_makes_its_bore_and_oil_the_defaults(tmp_path, code_cache):
    """`bearing-fmu build --bearing FILE`: the file's [geometry] and [oil] are the parameters' start values
    (model description and resources), a master that sets nothing gets that bore's force, and the FMU
    validates."""
    import fmpy
    from fmpy.validation import validate_fmu

    from bearing_fmu.cli import main
    from bearing_fmu.physics.solver.reynolds import Reynolds

    models = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    grooved = tmp_path / "grooved.fmu"
    assert main(["build", "--bearing", str(models / "bearing_paper_2groove.toml"), "-o", str(grooved)]) == 0
    assert validate_fmu(str(grooved)) == []
    starts = {v.name: v.start for v in fmpy.read_model_description(str(grooved)).modelVariables}
    assert (starts["groove_count"], float(starts["groove_1"]), float(starts["groove_2"])) == ("2", math.pi / 2, 1.5 * math.pi)
    state = {"y": 1e-5, "z": -4e-5, "omega": OMEGA}
    res = fmpy.simulate_fmu(str(grooved), stop_time=1e-3, output_interval=1e-3, output=["Fy", "Fz"], start_values=state)
    want = Reynolds(BearingParams.from_toml(models / "bearing_paper_2groove.toml")).force(1e-5, -4e-5, 0.0, 0.0, OMEGA)
    assert (res["Fy"][-1], res["Fz"][-1]) == want

    oily = tmp_path / "oily.fmu"
    assert main(["build", "--bearing", str(models / "bearing_paper_vg46.toml"), "-o", str(oily)]) == 0
    assert validate_fmu(str(oily)) == []
    v = {x.name: x for x in fmpy.read_model_description(str(oily)).modelVariables}
    assert (v["oil_law"].start, v["oil_law_enum"].start, v["thermal"].start) == ("walther", "2", "false")
    oil = BearingParams.from_toml(models / "bearing_paper_vg46.toml").oil
    two = Oil.walther(float(v["oil_nu_1"].start) * 1e6, float(v["oil_T_1"].start),
                      float(v["oil_nu_2"].start) * 1e6, float(v["oil_T_2"].start))
    for T in (300.0, 350.0, 420.0):  # the law through the two points the build wrote is the file's
        assert two.mu(T) == pytest.approx(oil.mu(T), rel=1e-12)
    # thermal on with nothing else set: the built-in law; its enumeration set to 1 (none) counts too
    res = fmpy.simulate_fmu(str(oily), stop_time=1e-3, output_interval=1e-3, output=["T_eff"],
                            start_values={**state, "thermal": True})
    assert res["T_eff"][-1] > 313.15 + 0.5
    with pytest.raises(Exception):
        fmpy.simulate_fmu(str(oily), stop_time=1e-3, start_values={**state, "thermal": True, "oil_law_enum": 1})


def test_a_supply_temperature_outside_the_oil_law_discards_by_name(fmu_instance):
    """T_supply beyond the law's range (oil_T_max, 150 C by default): the step is discarded naming it, the
    outputs keep their last values; a serialized FMU state brings T_eff back."""
    inst = fmu_instance(**THERMAL, **dict(zip(("y", "z", "vy", "vz", "omega"), STATE)), T_supply=T_SUPPLY)
    try:
        T0 = inst.get("T_eff")
        blob = inst.fmu.serializeFMUstate(inst.fmu.getFMUstate())
        inst.set("T_supply", 500.0)
        with pytest.raises(FMICallException):
            inst.step(1e-4, *STATE)
        assert ("thermal model: T_supply = 500 K (226.85 C) is outside the viscosity law's range 0 C .. 150 C (the "
                "parameters oil_T_min .. oil_T_max)") in inst.messages[-1]
        assert inst.get("T_eff") == T0
        inst.set("T_supply", 350.0)
        inst.step(1e-3, *STATE)
        assert inst.get("T_eff") > T0 + 1.0  # a hotter supply heats the film over the step
        inst.fmu.setFMUstate(inst.fmu.deSerializeFMUstate(blob))
        assert inst.get("T_eff") == T0
    finally:
        inst.close()
