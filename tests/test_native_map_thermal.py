"""The native map FMU's thermal ports (docs/thermal.md, docs/fmu.md): its film report in C from the
map file's flow table (c/internal_map.c, a port of ForceMap.film_report), against the Python FMU
with the same map (the session's coarse contract map, tests/conftest.py map_file) over a run whose
T_supply ramps, against the Python map internal's film_report, in Model Exchange, under the FMU
Compliance Checker; a map file without flow tables (version 1) refuses thermal by name; an FMU of
several internals (reynolds, map) runs the thermal model of the internal set. The helpers and the
Reynolds FMU's own comparisons: tests/test_native_fmu_thermal.py.
"""

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402

from bearing_fmu.physics.params import BearingParams  # noqa: E402

from test_native_fmu_thermal import (GRID, IN, RTOL, T_SUPPLY, VG46, Run, by_version,  # noqa: E402
                                     check_reports, compliance_check, model_exchange_check, parameters, run,
                                     trajectory)


@pytest.fixture(scope="module")
def rey3(tmp_path_factory, native_build_cache):
    """FMI version -> (the native Reynolds FMU of the VG 46 bearing, its model description): the one
    tests/test_native_fmu_thermal.py compares with Python (the same build, from the cache)."""
    return by_version(tmp_path_factory.mktemp("native_thermal"), native_build_cache, "reynolds", [], options=GRID)


@pytest.fixture(scope="module")
def map3(tmp_path_factory, native_build_cache, map_file):
    """FMI version -> (the native map FMU of the VG 46 bearing on the session's contract map, with its
    flow table: version 3, starting with thermal = true, its model description)."""
    return by_version(tmp_path_factory.mktemp("native_map_thermal"), native_build_cache, "map", [map_file],
                      map=map_file, thermal=True)


@pytest.fixture(scope="module")
def map_thermal_on(map3):
    """The native map FMU (FMI 2.0) of the VG 46 bearing starting with thermal = true."""
    return map3[2][0]


RAMP = 2.0  # K per step: T_supply 45 -> 67 C over the run


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_map_equals_the_python_fmu(map3, fmu, map_file, version):
    """The native map FMU with thermal on over a Co-Simulation run whose T_supply ramps 45 -> 67 C:
    T_eff, mu_eff, P_loss, Q_side, the force and its tangent equal the Python FMU's with the same map
    within RTOL = 1e-12 of each output's largest value (round-off: the C film report is
    ForceMap.film_report's operations in the same order, the oil law and heat balance the ones the
    Reynolds comparison checks, tests/test_native_fmu_thermal.py; measured: every output the same bits). And the Python map
    internal's film_report at each state (its own force at the file's mu): P_loss its friction power
    times mu_eff / mu, Q_side its side flow, within 1e-13 relative (measured: 2.2e-16 and 0)."""
    from bearing_fmu.internals.map.forcemap import ForceMap

    check_against_python(*map3[version], fmu, map_file.name, lambda params: ForceMap.from_file(map_file, params))


def check_against_python(path, md, python_fmu, map_name, internal, rise_K=5.0):
    """test_map_equals_the_python_fmu's run and checks of the native FMU ``path`` against the Python
    FMU ``python_fmu`` with the map ``map_name`` and the map internal ``internal(params)``; T_eff
    rises by more than ``rise_K`` over the run."""
    got = run(path, md, ramp=RAMP)
    want = run(python_fmu, fmpy.read_model_description(str(python_fmu)), python=True, native_md=md,
               map_name=map_name, ramp=RAMP)
    scale = np.max(np.abs(want), axis=0)
    assert np.max(np.abs(got - want) / scale) <= RTOL
    p = parameters(md)
    internal = internal(BearingParams(D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"]))
    check_reports(got, trajectory(), internal, p["mu"], 1e-13, rise_K)


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_map_model_exchange_state_and_derivative(map3, map_file, version):
    """Model Exchange of the native map FMU: as test_native_fmu_thermal.py's
    test_model_exchange_state_and_derivative, the rate and the force against the Python map
    internal's film report and force (within 1e-12)."""
    from bearing_fmu.internals.map.forcemap import ForceMap

    model_exchange_check(*map3[version], version, lambda params: ForceMap.from_file(map_file, params))


def test_a_map_without_flow_tables_refuses_thermal(map_file, tmp_path):
    """A version 1 map file (the force alone): a native map FMU starting with thermal = true is
    refused before anything is compiled, naming why (the Python map's film_flow_why, as for a grooved
    bore's map: test_native_fmu.py); without thermal its thermal parameter says why it stays false."""
    import json

    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.codegen import native_model

    data = json.loads(map_file.read_text())
    for key in ("Q", "flow_spline", "flow_meaning"):
        data.pop(key)
    old = tmp_path / "v1.json"
    old.write_text(json.dumps({**data, "version": 1}))
    params = BearingParams.from_toml(VG46)
    with pytest.raises(ValueError, match=r"thermal = true needs the film's flows and the bearing's oil law: the "
                                         r"map file .*v1.json has no flow tables \(format version 1"):
        build_native_fmu(tmp_path / "x.fmu", "map", map=old, bearing=params, compiler="cc", thermal=True)
    model = native_model("map", params, map=old)
    thermal = next(v for v in model.variables if v.name == "thermal")
    assert "not in this native FMU (the map file" in thermal.description and "#define BN_FILM_FLOW 0" in model.config_h
    assert "der(T_eff)" not in {v.name for v in model.variables}


@pytest.mark.slow
def test_several_internals_with_thermal(map3, rey3, map_file, tmp_path_factory, native_build_cache):
    """An FMU of several internals (reynolds and map, c/bn_parts.c) runs the thermal model of the
    internal set: over the CS run with T_supply ramped, internal = 'map' gives the native map FMU's
    bits, internal = 'reynolds' the native Reynolds FMU's (one C film report each, dispatched). With
    a map file without flow tables (version 1) in it, thermal = true is refused at initialisation
    for internal = 'map', naming the internal and the file, and runs for internal = 'reynolds'."""
    import json

    folder = tmp_path_factory.mktemp("several_thermal")
    both = by_version(folder, native_build_cache, "reynolds,map", [map_file], map=map_file, options=GRID)[2]
    for internal, single in (("map", map3[2]), ("reynolds", rey3[2])):
        want = run(*single, ramp=RAMP)
        assert np.array_equal(run(*both, ramp=RAMP, internal=internal), want), internal
    data = json.loads(map_file.read_text())
    for key in ("Q", "flow_spline", "flow_meaning"):
        data.pop(key)
    old = folder / "v1.json"
    old.write_text(json.dumps({**data, "version": 1}))
    path, md = by_version(folder, native_build_cache, "reynolds,map", [old], map=old, options=GRID)[2]
    state = dict(zip(IN, trajectory()[3]))
    log = []
    r = Run(path, md, {"T_supply": T_SUPPLY, **state}, {"internal": "map"}, log=log)
    with pytest.raises(FMICallException):
        r.f.exitInitializationMode()
    r.f.freeInstance()  # refused initialisation: no terminate
    assert ("thermal = true needs the film's friction and flows, which internal = 'map' does not have (the map "
            "file") in log[-1] and "v1.json has no flow tables (format version 1" in log[-1]
    r = Run(path, md, {"T_supply": T_SUPPLY, **state}, {"internal": "reynolds"})
    r.f.exitInitializationMode()
    assert r.get(["T_eff"])[0] > T_SUPPLY
    r.close()


@pytest.mark.slow
@pytest.mark.parametrize("interface", ["me", "cs"])
def test_compliance_checker_with_thermal_on(map_thermal_on, interface, tmp_path):
    """The FMU Compliance Checker on the native map FMU with thermal on, T_supply ramped 40 -> 60 C
    in its input file while the journal circles (test_native_fmu_thermal.py's run): 0 warnings and
    0 errors from the FMU and the checker; T_eff moves (ME: the state)."""
    compliance_check(map_thermal_on, interface, tmp_path)
