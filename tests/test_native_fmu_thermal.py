"""The native Reynolds and map FMUs' thermal ports (docs/thermal.md, docs/fmu.md) against the Python FMU's.

Expected values: the Python FMU (bearing_fmu/fmu/slave.py, its thermal model in Python:
physics/thermal.py film_temperature through fmu/ports.py thermal_state) at the same parameters
(the native FMU's starts: the ISO VG 46 paper bearing of models/bearing_paper_vg46.toml, a
32 x 4 grid) over the same short Co-Simulation run: T_eff, mu_eff, P_loss, Q_side and the force
with its tangent within 1e-12 relative (round-off: the C film report and oil law equal Python's to
about 1e-16, tests/test_native_film.py, tests/test_native_thermal.py). The native FMU's own
contract: T_eff is part of the FMU state (a restored state steps the same), a supply temperature
outside the oil's range refuses the step (Discard); in Model Exchange T_eff is the continuous
state, its derivative the heat balance's rate (Python's formula at the state set).

The native map FMU (its film report in C from the map file's flow table, c/internal_map.c) the
same way against the Python FMU with the same map (the session's coarse contract map, tests/
conftest.py map_file), over a run whose T_supply ramps, and against the Python map internal's
film_report (ForceMap.film_report); a map file without flow tables (version 1) refuses thermal.
"""

import math
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Slave

from bearing_fmu.physics.params import BearingParams

ROOT = Path(__file__).resolve().parents[1]
VG46 = ROOT / "models" / "bearing_paper_vg46.toml"
GRID = {"n_theta": 32, "n_x": 4}
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "T_eff", "mu_eff", "P_loss", "Q_side", "Kyy", "Kzy", "Cyy", "Czz")
T_SUPPLY = 318.15  # 45 C
RTOL = 1e-12


@pytest.fixture(scope="module")
def thermal_on(tmp_path_factory, native_build_cache):
    """The native Reynolds FMU (FMI 2.0) of the VG 46 bearing starting with thermal = true."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    params = BearingParams.from_toml(VG46)
    return native_build_cache(tmp_path_factory.mktemp("thermal_on") / "reynolds_vg46_on.fmu",
                              lambda target: build_native_fmu(target, "reynolds", bearing=params, options=GRID,
                                                              compiler="cc", thermal=True),
                              [VG46], ("thermal on", "reynolds", tuple(GRID.items())))


def by_version(folder, native_build_cache, internal, inputs, **kw) -> dict:
    """FMI version (2, 3) -> (the native FMU of ``internal`` for the VG 46 bearing, built with ``kw``
    and cached on ``inputs``, its model description)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    params = BearingParams.from_toml(VG46)
    out = {}
    for version in (2, 3):
        def build(target, version=version):
            return build_native_fmu(target, internal, bearing=params, fmi_version=version, compiler="cc", **kw)
        path = native_build_cache(folder / f"{internal}_vg46_fmi{version}.fmu", build, [VG46, *inputs],
                                  ("thermal", internal, version, tuple(sorted((k, str(v)) for k, v in kw.items()))))
        out[version] = (path, fmpy.read_model_description(str(path)))
    return out


@pytest.fixture(scope="module")
def native3(tmp_path_factory, native_build_cache):
    """FMI version -> (the native Reynolds FMU of the VG 46 bearing, its model description)."""
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


def trajectory(n=12):
    """The journal on a widening, speeding spiral: the load and the friction change every step."""
    CR, out = 90e-6, []
    for k in range(n):
        a, e, w = 0.3 * k, 0.5 + 0.02 * k, 300.0 + 20.0 * k
        out.append((e * CR * math.sin(a), -e * CR * math.cos(a), 0.01 * w * CR * math.cos(a),
                    0.01 * w * CR * math.sin(a), w))
    return out


class Run:
    """One Co-Simulation instance through fmpy (FMI 2.0 or 3.0) with the thermal model on."""

    def __init__(self, path, md, reals: dict, strings: dict | None = None, kind="CS", thermal=True, log=None):
        self.md, self.v3 = md, md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        unzip = fmpy.extract(str(path))
        if self.v3:
            self.f = FMU3Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                               instanceName="thermal")
        else:
            cls, ident = ((FMU2Slave, md.coSimulation.modelIdentifier) if kind == "CS" else
                          (FMU2Model, md.modelExchange.modelIdentifier))
            self.f = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="thermal")
        if log is None:
            self.f.instantiate()
        else:  # FMI 2.0: every log line into the list log
            from test_native_several import callbacks

            self._cb = callbacks(log)
            self.f.instantiate(callbacks=self._cb, loggingOn=True)
        if self.v3:
            self.f.enterInitializationMode(startTime=0.0)
        else:
            self.f.setupExperiment(startTime=0.0)
            self.f.enterInitializationMode()
        self.f.setBoolean([self.vr["thermal"]], [thermal])
        for k, v in (strings or {}).items():
            self.f.setString([self.vr[k]], [v])
        self.set(reals)
        self.t = 0.0

    def set(self, values: dict):
        ids, vals = [self.vr[k] for k in values], [float(v) for v in values.values()]
        (self.f.setFloat64 if self.v3 else self.f.setReal)(ids, vals)

    def get(self, names=OUT) -> np.ndarray:
        ids = [self.vr[k] for k in names]
        return np.array((self.f.getFloat64 if self.v3 else self.f.getReal)(ids))

    def step(self, state, h):
        self.set(dict(zip(IN, state)))
        self.f.doStep(self.t, h)
        self.t += h

    def close(self):
        self.f.terminate()
        self.f.freeInstance()


def parameters(md) -> dict:
    """The native FMU's bearing and oil parameters (its starts), for the Python FMU too."""
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type in ("Real", "Float64") and (v.name in ("D", "L", "CR", "mu")
                                                                   or v.name.startswith("oil_"))}


def run(fmu, md, h=1e-3, python=False, native_md=None, map_name=None, ramp=0.0, internal=None):
    """The outputs OUT over the trajectory, Co-Simulation; ``python``: the Python FMU with the
    Reynolds internal on GRID, or with ``map_name`` the map internal; T_supply rises by ``ramp`` [K]
    per step; ``internal``: the one a native FMU of several sets."""
    states = trajectory()
    reals = {**parameters(native_md or md), "T_supply": T_SUPPLY, **dict(zip(IN, states[0]))}
    strings = ({"internal": "map", "map": map_name} if map_name else {"internal": "reynolds"}) if python else None
    r = Run(fmu, md, reals, {**strings, "oil_law": "walther"} if python else {"internal": internal} if internal else None)
    try:
        if python and not map_name:
            ints = [r.vr["n_theta"], r.vr["n_x"]]
            r.f.setInteger(ints, [GRID["n_theta"], GRID["n_x"]])
        r.f.exitInitializationMode()
        rows = [r.get()]
        for k, s in enumerate(states[1:], 1):
            r.set({"T_supply": T_SUPPLY + ramp * k})
            r.step(s, h)
            rows.append(r.get())
        return np.array(rows)
    finally:
        r.close()


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_equals_the_python_fmu(native3, fmu, version):
    path, md = native3[version]
    got = run(path, md)
    want = run(fmu, fmpy.read_model_description(str(fmu)), python=True, native_md=md)
    scale = np.max(np.abs(want), axis=0)  # each output against its largest value over the run
    assert np.max(np.abs(got - want) / scale) <= RTOL
    T = got[:, OUT.index("T_eff")]
    assert np.all(T > T_SUPPLY) and np.ptp(T) > 0.1  # the film runs hot, and its temperature moves


RAMP = 2.0  # K per step: T_supply 45 -> 67 C over the run


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_map_equals_the_python_fmu(map3, fmu, map_file, version):
    """The native map FMU with thermal on over a Co-Simulation run whose T_supply ramps 45 -> 67 C:
    T_eff, mu_eff, P_loss, Q_side, the force and its tangent equal the Python FMU's with the same map
    within RTOL = 1e-12 of each output's largest value (round-off: the C film report is
    ForceMap.film_report's operations in the same order, the oil law and heat balance the ones the
    Reynolds comparison above checks; measured: every output the same bits). And the Python map
    internal's film_report at each state (its own force at the file's mu): P_loss its friction power
    times mu_eff / mu, Q_side its side flow, within 1e-13 relative (measured: 2.2e-16 and 0)."""
    from bearing_fmu.internals.forcemap import ForceMap

    path, md = map3[version]
    got = run(path, md, ramp=RAMP)
    want = run(fmu, fmpy.read_model_description(str(fmu)), python=True, native_md=md, map_name=map_file.name,
               ramp=RAMP)
    scale = np.max(np.abs(want), axis=0)
    assert np.max(np.abs(got - want) / scale) <= RTOL
    p = parameters(md)
    internal = ForceMap.from_file(map_file, BearingParams(D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"]))
    col = {n: OUT.index(n) for n in OUT}
    for state, row in zip(trajectory(), got):
        rep = internal.film_report(*state)
        assert row[col["P_loss"]] == pytest.approx(rep.friction_power_W * row[col["mu_eff"]] / p["mu"], rel=1e-13)
        assert row[col["Q_side"]] == pytest.approx(rep.side_flow_m3_s, rel=1e-13) and rep.side_flow_m3_s > 0.0
    T = got[:, col["T_eff"]]
    assert T[0] > T_SUPPLY and np.all(np.diff(T) > 0.0) and T[-1] - T[0] > 5.0  # hot, lagging the rising supply


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_map_model_exchange_state_and_derivative(map3, map_file, version):
    """Model Exchange of the native map FMU: as test_model_exchange_state_and_derivative, the rate
    and the force against the Python map internal's film report and force (within 1e-12)."""
    from bearing_fmu.internals.forcemap import ForceMap

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
    # every native internal with the film's flows has its film report in C (the scene checks only the capability)
    from bearing_fmu.fmu.native.portgen import C_FILM_REPORT
    from bearing_fmu.internals import registry

    assert set(registry.having(film_flow=True, native=True)) <= set(C_FILM_REPORT)


@pytest.mark.slow
def test_several_internals_with_thermal(map3, native3, map_file, tmp_path_factory, native_build_cache):
    """An FMU of several internals (reynolds and map, c/bn_parts.c) runs the thermal model of the
    internal set: over the CS run with T_supply ramped, internal = 'map' gives the native map FMU's
    bits, internal = 'reynolds' the native Reynolds FMU's (one C film report each, dispatched). With
    a map file without flow tables (version 1) in it, thermal = true is refused at initialisation
    for internal = 'map', naming the internal and the file, and runs for internal = 'reynolds'."""
    import json

    folder = tmp_path_factory.mktemp("several_thermal")
    both = by_version(folder, native_build_cache, "reynolds,map", [map_file], map=map_file, options=GRID)[2]
    for internal, single in (("map", map3[2]), ("reynolds", native3[2])):
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
def test_fmpy_validates_the_thermal_fmus(native3):
    from fmpy.validation import validate_fmu

    for version, (path, md) in native3.items():
        assert validate_fmu(str(path)) == [], version
        names = {v.name for v in md.modelVariables}
        assert {"thermal", "T_supply", "T_eff", "oil_nu_1", "oil_rise_factor"} <= names and "oil_law" not in names


@pytest.mark.slow
def test_t_eff_is_part_of_the_fmu_state(native3):
    path, md = native3[2]
    states = trajectory()
    r = Run(path, md, {"T_supply": T_SUPPLY, **dict(zip(IN, states[0]))})
    try:
        r.f.exitInitializationMode()
        for s in states[1:5]:
            r.step(s, 1e-3)
        blob = r.f.serializeFMUstate(r.f.getFMUstate())
        before = r.get()
        r.step(states[5], 1e-3)
        after = r.get()
        assert after[OUT.index("T_eff")] != before[OUT.index("T_eff")]
        r.f.setFMUstate(r.f.deSerializeFMUstate(blob))
        r.t -= 1e-3
        assert np.array_equal(r.get(), before)
        r.step(states[5], 1e-3)
        assert np.array_equal(r.get(), after)  # the same lag from the same T_eff
        # a supply temperature outside the oil's range (0 .. 150 C): the step is refused
        r.set({"T_supply": 450.0})
        with pytest.raises(FMICallException, match="discard"):
            r.f.doStep(r.t, 1e-3)
    finally:
        r.close()


def reynolds_on_grid(params):
    from bearing_fmu.physics.reynolds import Reynolds

    return Reynolds(params, GRID["n_theta"], GRID["n_x"])


def python_rate(md, state, T, internal=reynolds_on_grid):
    """(der(T_eff) [K/s], mu(T) [Pa s], the force at T [N]) by Python: the film report of
    ``internal(params)`` (the Reynolds solver on GRID, or the map) at the FMU's mu (physics/film.py),
    the oil of the FMU's parameters (fmu/ports.oil_of), the lag's rate dT/dt = (T*(T) - T) / t_res
    (physics/thermal.py, "At a fixed journal state")."""
    from types import SimpleNamespace

    from bearing_fmu.fmu import ports
    from bearing_fmu.physics.thermal import residence_time_s

    p = parameters(md)
    oil = ports.oil_of(SimpleNamespace(**p), "walther")
    params = BearingParams(D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"])
    rey = internal(params)
    F = rey.force(*state)
    rep = rey.film_report(*state)
    gain = oil.rise_factor * rep.friction_power_W / params.mu / (
        oil.density * oil.heat_capacity * (rep.inflow_m3_s - 0.5 * rep.side_flow_m3_s))
    mu = oil.mu(T)
    return (T_SUPPLY + gain * mu - T) / residence_time_s(params, rep), mu, np.array(F) * mu / params.mu


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_model_exchange_state_and_derivative(native3, version):
    """Model Exchange: T_eff is the one continuous state, starting at the quasi-static film
    temperature (the Co-Simulation start: der(T_eff) ~ 0 there), its derivative the heat balance's
    rate at the state as set, the force and mu_eff at that temperature (Python's within 1e-12; measured:
    der(T_eff) and mu_eff the same bits, the force within 2.2e-16)."""
    model_exchange_check(*native3[version], version, reynolds_on_grid)


def model_exchange_check(path, md, version, internal):
    """test_model_exchange_state_and_derivative's checks of the FMU ``path`` against ``internal``."""
    from fmpy.fmi3 import FMU3Model

    vr = {v.name: v.valueReference for v in md.modelVariables}
    state = trajectory()[3]
    unzip = fmpy.extract(str(path))
    if version == 3:
        f = FMU3Model(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.modelExchange.modelIdentifier,
                      instanceName="me")
        f.instantiate()
        f.enterInitializationMode()
        setr, getr = f.setFloat64, f.getFloat64
    else:
        f = FMU2Model(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.modelExchange.modelIdentifier,
                      instanceName="me")
        f.instantiate()
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        setr, getr = f.setReal, f.getReal
    try:
        f.setBoolean([vr["thermal"]], [True])
        setr([vr[n] for n in (*IN, "T_supply")], [*state, T_SUPPLY])
        f.exitInitializationMode()
        if version == 3:
            assert f.getNumberOfContinuousStates() == 1
        import ctypes

        buf = np.zeros(1)
        ptr = buf.ctypes.data_as(ctypes.POINTER(ctypes.c_double))
        f.getContinuousStates(ptr, 1)
        T0 = float(buf[0])
        cs = Run(path, md, {"T_supply": T_SUPPLY, **dict(zip(IN, state))})  # Co-Simulation's start
        cs.f.exitInitializationMode()
        assert T0 == cs.get(["T_eff"])[0] and T0 > T_SUPPLY
        cs.close()
        f.enterContinuousTimeMode()
        for T in (T0, T0 + 5.0, T0 - 2.0):
            buf[0] = T
            f.setContinuousStates(ptr, 1)
            (f.getContinuousStateDerivatives if version == 3 else f.getDerivatives)(ptr, 1)
            der = float(buf[0])
            want_der, want_mu, want_F = python_rate(md, state, T, internal)
            got = getr([vr[n] for n in ("der(T_eff)", "mu_eff", "T_eff", "Fy", "Fz")])
            assert got[0] == der and got[2] == T
            assert der == pytest.approx(want_der, rel=1e-12, abs=1e-9)  # the same bits, measured
            assert got[1] == pytest.approx(want_mu, rel=1e-12)
            assert got[3:] == pytest.approx(want_F, rel=1e-12)
        assert abs(python_rate(md, state, T0, internal)[0]) < 1e-6  # the start is the fixed point
        assert python_rate(md, state, T0 + 5.0, internal)[0] < 0.0  # hotter than the balance: it cools
    finally:
        f.terminate()
        f.freeInstance()


@pytest.mark.slow
@pytest.mark.parametrize("interface", ["me", "cs"])
@pytest.mark.parametrize("which", ["thermal_on", "map_thermal_on"])
def test_compliance_checker_with_thermal_on(which, interface, tmp_path, request):
    """The FMU Compliance Checker (../shared/tools/fmu-compliance-checker, an empty environment)
    simulates the thermal FMU (Reynolds; the map) with an input signal that ramps T_supply 40 -> 60 C
    while the journal circles: 0 warnings and 0 errors from the FMU and the checker; T_eff moves
    (ME: the state)."""
    import os
    import subprocess

    thermal_on = request.getfixturevalue(which)
    checker = next((p for p in (ROOT.parent / "shared", ROOT.parent.parent / "shared", Path("/work/shared"))
                    if (p / "tools" / "fmu-compliance-checker" / "fmuCheck.linux64").is_file()), None)
    if checker is None:
        if os.environ.get("CI"):
            raise AssertionError("the FMU Compliance Checker is not in ../shared/tools/fmu-compliance-checker/")
        pytest.skip("the FMU Compliance Checker (../shared/tools/fmu-compliance-checker/) is not here")
    md = fmpy.read_model_description(str(thermal_on))
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("omega", "CR")}
    rows = ["time,y,z,vy,vz,omega,T_supply"]
    for k in range(11):
        t, r, w = 1e-3 * k, 0.3 * start["CR"], start["omega"]
        rows.append(f"{t!r},{r * math.cos(w * t)!r},{-r * math.sin(w * t) - 0.3 * start['CR']!r},"
                    f"{-r * w * math.sin(w * t)!r},{-r * w * math.cos(w * t)!r},{w!r},{313.15 + 2.0 * k!r}")
    (tmp_path / "in.csv").write_text("\n".join(rows) + "\n")
    log = tmp_path / "check.log"
    done = subprocess.run(["env", "-i", str(checker / "tools" / "fmu-compliance-checker" / "fmuCheck.linux64"),
                           "-h", "1e-4", "-s", "0.01", "-k", interface, "-i", str(tmp_path / "in.csv"), "-o",
                           str(tmp_path / "out.csv"), "-e", str(log), str(thermal_on)],
                          capture_output=True, text=True, timeout=300, check=False)
    text = log.read_text()
    summary = text[text.index("FMU check summary:"):]
    assert done.returncode == 0, summary
    assert "FMU reported:\n\t0 warning(s) and error(s)" in summary, summary
    assert "0 Warning(s)" in summary and "0 Error(s)" in summary, summary
    rows = (tmp_path / "out.csv").read_text().splitlines()
    head = [h.strip('"') for h in rows[0].split(",")]
    T = np.array([float(r.split(",")[head.index("T_eff")]) for r in rows[1:]])
    assert len(rows) >= 100 and T[-1] - T[0] > 0.5


@pytest.mark.slow
def test_model_exchange_thermal_off_t_eff_is_a_known(native3):
    """thermal = false in Model Exchange: T_eff is the state, holding its start (T_supply at
    initialisation; der(T_eff) = 0); its directional derivatives along T_eff as a known: itself 1,
    der(T_eff) and the force 0; along T_supply: T_eff 0 (the state does not follow it)."""
    path, md = native3[2]
    vr = {v.name: v.valueReference for v in md.modelVariables}
    r = Run(path, md, {"T_supply": T_SUPPLY, **dict(zip(IN, trajectory()[3]))}, kind="ME", thermal=False)
    try:
        r.f.exitInitializationMode()
        r.f.enterContinuousTimeMode()
        assert list(r.get(["T_eff", "der(T_eff)"])) == [T_SUPPLY, 0.0]
        unknowns = [vr[n] for n in ("T_eff", "der(T_eff)", "Fy")]
        assert r.f.getDirectionalDerivative(unknowns, [vr["T_eff"]], [1.0]) == [1.0, 0.0, 0.0]
        assert r.f.getDirectionalDerivative(unknowns, [vr["T_supply"]], [1.0]) == [0.0, 0.0, 0.0]
    finally:
        r.close()
