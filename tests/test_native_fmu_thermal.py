"""The native Reynolds and map FMUs' thermal ports (docs/thermal.md, docs/fmu.md) against the Python FMU's.

Expected values: the Python FMU (bearing_fmu/fmu/slave.py, its thermal model in Python:
physics/thermal.py film_temperature through fmu/ports.py thermal_state) at the same parameters
(the native FMU's starts: the ISO VG 46 paper bearing of rotor_host/bundled/bearing_paper_vg46.toml, a
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
from conftest import compliance_checker

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from bearing_fmu.physics.params import BearingParams

ROOT = Path(__file__).resolve().parents[1]
VG46 = ROOT / "rotor_host" / "bundled" / "bearing_paper_vg46.toml"
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
            cls, ident = ((FMU3Slave, md.coSimulation.modelIdentifier) if kind == "CS" else
                          (FMU3Model, md.modelExchange.modelIdentifier))
            self.f = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="thermal")
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

    def dd(self, unknowns, knowns, seed) -> np.ndarray:
        return np.array(self.f.getDirectionalDerivative([self.vr[k] for k in unknowns], [self.vr[k] for k in knowns],
                                                        list(seed)))

    def save(self):
        return self.f.getFMUState() if self.v3 else self.f.getFMUstate()

    def restore(self, state):
        (self.f.setFMUState if self.v3 else self.f.setFMUstate)(state)

    def set_state(self, T):
        """Model Exchange: the continuous state T_eff."""
        import ctypes

        buf = np.array([float(T)])
        self.f.setContinuousStates(buf.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), 1)

    def close(self):
        self.f.terminate()
        self.f.freeInstance()


def parameters(md) -> dict:
    """The native FMU's bearing and oil parameters (its starts), for the Python FMU too."""
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type in ("Real", "Float64") and (v.name in ("D", "L", "CR", "mu")
                                                                   or v.name.startswith("oil_"))}


def run(fmu, md, h=1e-3, python=False, native_md=None, map_name=None, ramp=0.0, internal=None, states=None,
        strings=None):
    """The outputs OUT over the trajectory (or ``states``), Co-Simulation; ``python``: the Python FMU
    with the Reynolds internal on GRID, with ``map_name`` the map internal, or the String parameters
    ``strings``; T_supply rises by ``ramp`` [K] per step; ``internal``: the one a native FMU of
    several sets."""
    states = states or trajectory()
    reals = {**parameters(native_md or md), "T_supply": T_SUPPLY, **dict(zip(IN, states[0]))}
    strings = (strings or ({"internal": "map", "map": map_name} if map_name else {"internal": "reynolds"})
               if python else None)
    r = Run(fmu, md, reals, {**strings, "oil_law": "walther"} if python else {"internal": internal} if internal else None)
    try:
        if python and (strings["internal"] == "reynolds" or strings.get("domain_action") == "fallback"):
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


def check_reports(got, states, internal, mu, rel, rise):
    """The rows ``got`` (OUT over ``states``, thermal on) against ``internal``'s film_report at each
    state (its own force at mu): P_loss its friction power times mu_eff / mu, Q_side its side flow
    (> 0), within ``rel``; T_eff above the supply, rising by more than ``rise`` [K] over the run."""
    col = {n: OUT.index(n) for n in OUT}
    for state, row in zip(states, got):
        rep = internal.film_report(*state)
        assert row[col["P_loss"]] == pytest.approx(rep.friction_power_W * row[col["mu_eff"]] / mu, rel=rel)
        assert row[col["Q_side"]] == pytest.approx(rep.side_flow_m3_s, rel=rel) and rep.side_flow_m3_s > 0.0
    T = got[:, col["T_eff"]]
    assert T[0] > T_SUPPLY and np.all(np.diff(T) > 0.0) and T[-1] - T[0] > rise  # hot, lagging a rising supply


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
    from bearing_fmu.physics.solver.reynolds import Reynolds

    return Reynolds(params, GRID["n_theta"], GRID["n_x"])


def python_rate(md, state, T, internal=reynolds_on_grid):
    """(der(T_eff) [K/s], mu(T) [Pa s], the force at T [N]) by Python: the film report of
    ``internal(params)`` (the Reynolds solver on GRID, or the map) at the FMU's mu (physics/solver/film.py),
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


def model_exchange_check(path, md, version, internal, state=None):
    """test_model_exchange_state_and_derivative's checks of the FMU ``path`` against ``internal`` at
    ``state`` (default: the trajectory's fourth)."""
    vr = {v.name: v.valueReference for v in md.modelVariables}
    state = state or trajectory()[3]
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
def test_compliance_checker_with_thermal_on(thermal_on, interface, tmp_path):
    """The FMU Compliance Checker (conftest.compliance_checker(), an empty environment)
    simulates the thermal FMU with an input signal that ramps T_supply 40 -> 60 C while the journal
    circles: 0 warnings and 0 errors from the FMU and the checker; T_eff moves (ME: the state)."""
    compliance_check(thermal_on, interface, tmp_path)


def compliance_check(thermal_on, interface, tmp_path, orbit=(0.0, -0.3, 0.3)):
    """test_compliance_checker_with_thermal_on's run and checks of the FMU ``thermal_on``: the journal
    circles about (orbit[0], orbit[1]) CR with the radius orbit[2] CR at the start omega."""
    import subprocess

    checker = compliance_checker()
    md = fmpy.read_model_description(str(thermal_on))
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("omega", "CR")}
    rows = ["time,y,z,vy,vz,omega,T_supply"]
    for k in range(11):
        t, w = 1e-3 * k, start["omega"]
        y0, z0, r = (c * start["CR"] for c in orbit)
        rows.append(f"{t!r},{y0 + r * math.cos(w * t)!r},{-r * math.sin(w * t) + z0!r},"
                    f"{-r * w * math.sin(w * t)!r},{-r * w * math.cos(w * t)!r},{w!r},{313.15 + 2.0 * k!r}")
    (tmp_path / "in.csv").write_text("\n".join(rows) + "\n")
    log = tmp_path / "check.log"
    done = subprocess.run(["env", "-i", str(checker),
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


# directional derivatives with thermal = true (docs/thermal.md, "Directional derivatives")
DD_IN = (*IN, "T_supply")
DD_OUT = ("Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz", "P_loss",
          "Q_side", "T_eff", "mu_eff")
DD_RTOL = 1e-6  # measured: within 2.2e-8 of the differences (FMI 2.0 and 3.0, ME and CS)


def dd_state():
    """A loaded, whirling journal at 40 Hz (eccentricity 0.58), the supply at 45 C; each input's scale."""
    CR, w = 90e-6, 2 * math.pi * 40.0
    return (0.3 * CR, -0.5 * CR, 0.05 * w * CR, -0.08 * w * CR, w, T_SUPPLY), (CR, CR, w * CR, w * CR, w, 1.0)


def central(r: Run, outs, name, x, h, evaluate) -> np.ndarray:
    """Central differences of the outputs ``outs`` along input ``name`` (a step h) or, for "T_eff",
    Model Exchange's state; ``evaluate()`` makes the outputs at the inputs set (a get, or a step)."""
    rows = []
    for sign in (1, -1):
        if name == "T_eff":
            r.set_state(x + sign * h)
        else:
            r.set({name: x + sign * h})
        rows.append(evaluate())
    if name == "T_eff":
        r.set_state(x)
    else:
        r.set({name: x})
    return (rows[0] - rows[1]) / (2 * h)


def assert_close(got, want, floor, what):
    """Each derivative within DD_RTOL of the difference, or of ``floor`` (the size of the same
    derivative where the film temperature follows the inputs: what the differences' own errors, the
    heat balance's root to 1e-10 K and a step's lag, are small against)."""
    tol = DD_RTOL * (np.abs(want) + np.abs(floor)) + 1e-12 * np.max(np.abs(want))
    assert np.all(np.abs(got - want) <= tol), (what, got, want)


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("kind", ["ME", "CS"])
def test_directional_derivatives_with_thermal_on(native3, version, kind):
    """Every Real output (the thermal ones and der(T_eff) too) along every input, thermal = true,
    against central differences of the FMU's own outputs (a step of 1e-5 of each input's scale;
    T_eff 1e-3 K): in Initialization Mode, where T_eff is the heat balance's root (the outputs read
    there); after it in Model Exchange, where T_eff is the state (the outputs read after setting
    the inputs or the state); in Co-Simulation, where T_eff is the step's internal state, held (the
    outputs of a step of 1e-9 s from one FMU state: its lag moves T_eff by (1 - exp(-dt / t_res)) ~
    3e-8 of the quasi-static change, below the tolerance). Tolerance DD_RTOL (1e-6; measured 2.2e-8:
    the differences' truncation and the 1e-10 K root). Independent: in Initialization Mode
    dT_eff/dT_supply = 1 / (1 - g dmu/dT) lies in (0, 1) (a hotter supply thins the oil, which
    dissipates less) and der(T_eff) is stationary (the root makes T* - T vanish to first order);
    FMI 3.0's adjoint derivative is the directional ones' transpose."""
    path, md = native3[version]
    x, scale = dd_state()
    r = Run(path, md, dict(zip(DD_IN, x)), kind=kind)
    outs = DD_OUT + (("der(T_eff)",) if kind == "ME" else ())
    try:
        quasi = {}
        for j, name in enumerate(DD_IN):
            got = r.dd(outs, [name], [1.0])
            want = central(r, outs, name, x[j], 1e-5 * scale[j], lambda: r.get(outs))
            quasi[name] = got
            if kind == "ME":  # der(T_eff): the differences see the root's 1e-10 K only
                assert abs(got[-1]) <= 1e-6 * abs(want[-1]) + 1e-3
                got, want = got[:-1], want[:-1]
            assert_close(got, want, 0.0, ("initialization", name))
        assert 0.5 < quasi["T_supply"][DD_OUT.index("T_eff")] < 1.0
        r.f.exitInitializationMode()
        T0 = r.get(["T_eff"])[0]
        if kind == "ME":
            r.f.enterContinuousTimeMode()
            T0 += 3.0  # off the heat balance's root: der(T_eff) < 0, and t_res's change counts
            r.set_state(T0)
            rate = {}
            for j, name in enumerate((*DD_IN, "T_eff")):
                got = r.dd(outs, [name], [1.0])
                x0, h = (T0, 1e-3) if name == "T_eff" else (x[j], 1e-5 * scale[j])
                want = central(r, outs, name, x0, h, lambda: r.get(outs))
                assert_close(got, want, 0.0, ("model exchange", name))
                rate[name] = got[-1]
                if name != "T_eff":  # at the state, der(T_eff) moves; in Initialization Mode it did not
                    assert abs(quasi[name][-1]) <= 1e-9 * abs(got[-1])
            assert rate["T_eff"] < 0.0 and rate["T_supply"] > 0.0  # a stable lag, fed by the supply
        else:
            saved = r.save()
            for j, name in enumerate(DD_IN):
                got = r.dd(outs, [name], [1.0])
                rows = []
                for sign in (1, -1):  # a step from the same FMU state (inputs, T_eff) at the inputs moved
                    r.restore(saved)
                    r.set({**dict(zip(DD_IN, x)), name: x[j] + sign * 1e-5 * scale[j]})
                    r.f.doStep(r.t, 1e-9)
                    rows.append(r.get(outs))
                r.restore(saved)
                want = (rows[0] - rows[1]) / (2e-5 * scale[j])
                assert_close(got, want, quasi[name], ("co-simulation", name))
                assert got[DD_OUT.index("T_eff")] == 0.0  # held between steps
        if version == 3:  # the adjoint: sum_i seed_i dU_i/dk for each known k
            knowns = (*DD_IN, "T_eff") if kind == "ME" else DD_IN
            seed = np.linspace(-1.0, 2.0, len(outs))
            adjoint = np.array(r.f.getAdjointDerivative([r.vr[k] for k in outs], [r.vr[k] for k in knowns],
                                                        list(seed), len(knowns)))
            rows = np.array([r.dd(outs, [k], [1.0]) for k in knowns])
            assert adjoint == pytest.approx(rows @ seed, rel=1e-12)
    finally:
        r.close()


@pytest.mark.slow
def test_parameter_derivatives_with_thermal_on(native3):
    """Initialization Mode, thermal = true: the outputs along the Real parameters (the bearing, the
    oil: the FMU differences its outputs with a step of 1e-6 of each value) against central
    differences of the outputs read with a step 100 times larger (1e-4 of each value): within 1e-5
    (the two steps' truncation errors and the 1e-10 K root). Independent: along mu nothing moves
    (every force is mu_eff / mu times one proportional to mu, the heat balance sees the friction
    power over mu); the rise factor k heats the film, so T_eff grows along it, mu_eff falls."""
    path, md = native3[2]
    x, _scale = dd_state()
    r = Run(path, md, dict(zip(DD_IN, x)), kind="ME")
    outs = (*DD_OUT, "der(T_eff)")
    try:
        p = {k: r.get([k])[0] for k in ("D", "L", "CR", "mu", "oil_nu_1", "oil_T_2", "oil_heat_capacity",
                                            "oil_rise_factor")}
        base = r.get(outs)
        for name, value in p.items():
            got = r.dd(outs, [name], [1.0])
            want = central(r, outs, name, value, 1e-4 * value, lambda: r.get(outs))
            if name == "mu":
                assert np.all(np.abs(got) <= 1e-7 * np.abs(base) / value), got
                continue
            tol = 1e-5 * np.abs(want) + 1e-9 * np.abs(base) / value
            assert np.all(np.abs(got[:-1] - want[:-1]) <= tol[:-1]), (name, got, want)
        k = r.dd(["T_eff", "mu_eff"], ["oil_rise_factor"], [1.0])
        assert k[0] > 0.0 and k[1] < 0.0
    finally:
        r.f.freeInstance()  # in Initialization Mode: nothing to terminate


@pytest.mark.slow
def test_declared_dependencies_are_the_computed_ones(native3):
    """After initialisation each Real output's dependencies as declared (the FMI 2.0 and 3.0 model
    descriptions, fmi3GetVariableDependencies) are exactly the knowns along which its directional
    derivative is not 0 in Model Exchange or Co-Simulation, thermal = true or false (the damping along
    the velocities and the speed aside: below): none left out, none always 0. So T_supply reaches the force, P_loss and Q_side only through the state T_eff
    (no direct feedthrough: an oil circuit making T_supply from P_loss is no algebraic loop)."""
    x, _scale = dd_state()
    declared = {}
    for version, (path, md) in native3.items():
        deps = {u.variable.name: sorted(d.name for d in u.dependencies) for u in (*md.outputs, *md.derivatives)}
        deps.pop("out_of_domain")
        for name in ("peak_pressure", "peak_pressure_angle"):  # the force's (test_native_peak.py); no derivative
            assert deps.pop(name) == deps["Fy"], (version, name)
        assert declared in ({}, deps), version
        declared = deps
    path, md = native3[3]
    r = Run(path, md, dict(zip(DD_IN, x)))
    try:
        import ctypes

        names = {v.valueReference: v.name for v in md.modelVariables}
        for name, deps in declared.items():  # raw: fmpy 0.3's getNumberOfVariableDependencies passes a type
            n = ctypes.c_size_t()
            r.f.fmi3GetNumberOfVariableDependencies(r.f.component, r.vr[name], ctypes.byref(n))
            got = (ctypes.c_uint * n.value)()
            r.f.fmi3GetVariableDependencies(r.f.component, r.vr[name], (ctypes.c_size_t * n.value)(), got,
                                            (ctypes.c_size_t * n.value)(), (ctypes.c_int * n.value)(), n.value)
            assert sorted(names[k] for k in got) == deps, name
    finally:
        r.f.freeInstance()
    assert declared["Fy"] == sorted((*IN, "T_eff")) and declared["Q_side"] == sorted(IN)
    found = {name: set() for name in declared}
    for kind in ("ME", "CS"):
        for thermal in (True, False):
            path, md = native3[2]
            r = Run(path, md, dict(zip(DD_IN, x)), kind=kind, thermal=thermal)
            try:
                r.f.exitInitializationMode()
                knowns = DD_IN
                if kind == "ME":
                    r.f.enterContinuousTimeMode()
                    r.set_state(r.get(["T_eff"])[0] + 3.0)  # off the root: der(T_eff) moves along everything
                    knowns += ("T_eff",)
                outs = [n for n in declared if kind == "ME" or n != "der(T_eff)"]
                for k in knowns:
                    for name, value in zip(outs, r.dd(outs, [k], [1.0])):
                        if value != 0.0:
                            found[name].add(k)
            finally:
                r.close()
    # the Reynolds film's force is linear in the velocities and the speed while its cavitated zone
    # stays: the damping C = -dF/dv moves with them only where that zone changes, in steps (its
    # derivative 0 between); the declarations are the interface's, for every internal
    steps = {name: {"vy", "vz", "omega"} for name in ("Cyy", "Cyz", "Czy", "Czz")}
    assert {name: sorted(ks | steps.get(name, set())) for name, ks in found.items()} == declared
