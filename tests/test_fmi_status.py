"""FMI statuses of the bearing FMU as any master sees them (docs/fmu.md, "FMI status").

Every call goes through the raw ctypes function of fmpy's FMU2Slave (as rotor_host/coupling/cosim.py
calls them), so the test sees the exact fmi2Status: 0 OK, 1 Warning, 2 Discard, 3 Error.
The expected statuses and messages are the table in docs/fmu.md; the expected forces come from
the linear internal's formula F = F0 - K (q - q0) - C v written out here, not from the FMU.
``fmpy.simulate_fmu`` runs in a subprocess where what it prints to stderr is the point.
"""

import ctypes
import json
import math
import os
import subprocess
import sys
import textwrap

import pytest

import fmpy  # noqa: E402
from fmpy import calloc, free  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,  # noqa: E402
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

from bearing_fmu.internals.registry import names as internal_names  # noqa: E402

OK, DISCARD, ERROR = 0, 2, 3
FMI2_TERMINATED = 3  # fmi2StatusKind fmi2Terminated
OMEGA = 2 * math.pi * 22.0
# the linear internal from coefficients: no Reynolds, no numba, an exact formula to compare with
LIN = dict(y0=1e-5, z0=-4e-5, Fy0=0.5, Fz0=16.7, Kyy=2e5, Kyz=3e4, Kzy=-1e4, Kzz=4e5, Cyy=300.0, Cyz=20.0,
           Czy=-10.0, Czz=500.0)
LINEAR = {"internal": "linear", "linear_from": "coefficients", "omega_lin": OMEGA,
          **{f"lin_{k}": v for k, v in LIN.items()}}
STATE = (2e-5, -3e-5, 1e-3, -2e-3, OMEGA)


def linear_force(y, z, vy, vz):
    """F = F0 - K (q - q0) - C v with LIN's coefficients (bearing_fmu/internals/linear/linear.py's definition)."""
    dy, dz = y - LIN["y0"], z - LIN["z0"]
    fy = LIN["Fy0"] - LIN["Kyy"] * dy - LIN["Kyz"] * dz - LIN["Cyy"] * vy - LIN["Cyz"] * vz
    fz = LIN["Fz0"] - LIN["Kzy"] * dy - LIN["Kzz"] * dz - LIN["Czy"] * vy - LIN["Czz"] * vz
    return fy, fz


class Raw:
    """One instance of the bearing FMU; ``call`` makes the raw ctypes call and returns its status."""

    _ARRAY = {"Real": ctypes.c_double, "Integer": ctypes.c_int, "Boolean": ctypes.c_int, "String": ctypes.c_char_p}

    def __init__(self, fmu, unzip, logging=True, name="status"):
        md = fmpy.read_model_description(str(fmu))
        self.vars = {v.name: v for v in md.modelVariables}
        self.messages = []
        self._cb = fmi2CallbackFunctions()  # ctypes callbacks must outlive the instance
        self._cb.logger = fmi2CallbackLoggerTYPE(
            lambda _e, _n, status, _c, msg: self.messages.append((status, msg.decode() if msg else "")))
        self._cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self._cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                             instanceName=name)
        self.fmu.instantiate(callbacks=self._cb, loggingOn=logging)

    def call(self, fname, *args) -> int:
        return getattr(self.fmu.dll, fname)(self.fmu.component, *args)

    def set_vr(self, typ, vr, value) -> int:
        value = value.encode() if typ == "String" else value
        return self.call(f"fmi2Set{typ}", (ctypes.c_uint * 1)(vr), 1, (self._ARRAY[typ] * 1)(value))

    def get_vr(self, typ, vr):
        out = (self._ARRAY[typ] * 1)()
        status = self.call(f"fmi2Get{typ}", (ctypes.c_uint * 1)(vr), 1, out)
        return status, (out[0].decode() if typ == "String" and out[0] else out[0])

    def set(self, name, value) -> int:
        v = self.vars[name]
        return self.set_vr(v.type, v.valueReference, value)

    def get(self, name):
        v = self.vars[name]
        return self.get_vr(v.type, v.valueReference)

    def setup_and_enter(self) -> None:
        assert self.call("fmi2SetupExperiment", 0, 0.0, 0.0, 0, 0.0) == OK
        assert self.call("fmi2EnterInitializationMode") == OK

    def initialise(self, **params) -> dict:
        """Set the parameters, enter and exit initialisation: statuses of each call."""
        statuses = {name: self.set(name, value) for name, value in params.items()}
        self.setup_and_enter()
        statuses["exit"] = self.call("fmi2ExitInitializationMode")
        return statuses

    def step(self, t, h, state=None) -> int:
        for name, value in zip(("y", "z", "vy", "vz", "omega"), state or ()):
            assert self.set(name, value) == OK
        return self.call("fmi2DoStep", t, h, 0)

    def terminated(self) -> int:
        flag = ctypes.c_int(-1)
        assert self.call("fmi2GetBooleanStatus", FMI2_TERMINATED, ctypes.byref(flag)) == OK
        return flag.value

    def errors(self, since=0):
        return [m for s, m in self.messages[since:] if s == ERROR]

    def close(self) -> None:
        # FMI 2.0 terminates an initialised instance only (else fmi2Error): free it either way
        assert self.call("fmi2Terminate") in (OK, ERROR)
        self.fmu.freeInstance()


@pytest.fixture
def raw(fmu, unzip):
    """raw(logging=True): a fresh instance, terminated and freed after the test."""
    made = []

    def make(**kw):
        made.append(Raw(fmu, unzip, **kw))
        return made[-1]

    yield make
    for r in made:
        r.close()


# ----------------------------------------------------------------------------- 1. invalid parameters

@pytest.mark.parametrize("params, refused_by, expected", [
    ({"D": -1.0}, "D", "D = -1.0 m must be finite and > 0"),
    ({"mu": 0.0}, "mu", "mu = 0.0 Pa.s must be finite and > 0"),
    ({"internal": "magic"}, "internal", f"unknown internal 'magic'; choose one of {', '.join(internal_names())}"),
    ({"n_theta": 3}, "n_theta", "n_theta = 3 must be an integer >= 8 and <= 100000"),
    ({"internal": "linear", "linear_from": "guess"}, "linear_from", "unknown linear_from 'guess'"),
    # valid one by one, refused together (BearingParams) or only where the file is looked for
    ({"CR": 0.02}, None, "BearingParams.CR = 20 mm is outside the physical range"),  # its range depends on D
    ({"internal": "taylor", "surrogate": "missing.json"}, None,
     "surrogate file 'missing.json' not found in the FMU resources folder surrogates/ (bundled: paper_22hz.json, "
     "paper_map.json)"),
])
def test_invalid_parameter_is_an_error_in_its_setter_and_the_initialisation(raw, params, refused_by, expected):
    r = raw()
    st = r.initialise(**params)
    for name in params:  # a value that cannot be valid is refused where it is set, and not stored
        assert st[name] == (ERROR if name == refused_by else OK), (name, r.messages)
    assert st["exit"] == ERROR  # and the initialisation fails too: a master that ignored the setter learns here
    assert any(expected in m for m in r.errors()), r.messages
    if refused_by in ("D", "mu"):
        assert r.get(refused_by) == (OK, {"D": 0.031, "mu": 0.05}[refused_by])  # kept its start value
    # the instance stays usable: getters answer, doStep is refused naming the reason, terminate/free work
    assert r.get("CR")[0] == OK
    n = len(r.messages)
    assert r.step(0.0, 1e-4) == ERROR
    assert any("step to t = 0.0001 s refused: bearing FMU initialisation failed" in m and expected in m
               for m in r.errors(n)), r.messages[n:]


def test_a_refused_parameter_set_again_validly_initialises(raw):
    r = raw()
    assert r.set("D", -1.0) == ERROR
    assert r.set("D", 0.04) == OK  # the refusal is withdrawn by a valid value
    st = r.initialise(**LINEAR)
    assert set(st.values()) == {OK}, r.messages
    assert r.get("D") == (OK, 0.04)


_SIMULATE = textwrap.dedent("""
    import json, sys, warnings
    import fmpy
    out = {}
    for key, start in json.loads(sys.argv[2]).items():
        try:
            res = fmpy.simulate_fmu(sys.argv[1], start_values=start, stop_time=1e-3, output_interval=1e-4,
                                    output=["Fy", "Fz"])
            out[key] = {"rows": len(res), "Fz": [float(x) for x in res["Fz"]]}
        except Exception as exc:
            out[key] = {"raised": type(exc).__name__, "message": str(exc)}
    print(json.dumps(out))
""")


def _simulate(fmu, cases: dict) -> tuple[dict, str]:
    run = subprocess.run([sys.executable, "-c", _SIMULATE, str(fmu), json.dumps(cases)], capture_output=True,
                         text=True, timeout=120, env=dict(os.environ, PYTHONPATH=""))
    assert run.returncode == 0, run.stderr[-3000:]
    assert "Traceback" not in run.stderr, run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1]), run.stderr


@pytest.mark.slow
def test_simulate_fmu_without_logging_raises_and_prints_the_reason(fmu):
    cases = {"D": {"D": -1.0}, "mu": {"mu": 0.0}, "internal": {"internal": "magic"},
             "surrogate": {"internal": "taylor", "surrogate": "missing.json"},
             "good": {"internal": "linear", "linear_from": "coefficients", "omega_lin": 0.0, "lin_Fz0": 16.7}}
    out, err = _simulate(fmu, cases)
    # refused in the setter fmpy calls for the start value, or at exitInitializationMode
    assert out["D"] == {"raised": "FMICallException", "message": "fmi2SetReal failed with status 3 (error)."}
    assert out["mu"]["message"] == "fmi2SetReal failed with status 3 (error)."
    assert out["internal"]["message"] == "fmi2SetString failed with status 3 (error)."
    assert out["surrogate"]["message"] == "fmi2ExitInitializationMode failed with status 3 (error)."
    # logging is off (simulate_fmu's default): each instance prints its first error to stderr
    lines = [ln for ln in err.splitlines() if ln.startswith("bearing FMU")]
    assert lines == [
        "bearing FMU 'BearingFMU' [error]: setReal: D = -1.0 m must be finite and > 0; D keeps 0.031",
        "bearing FMU 'BearingFMU' [error]: setReal: mu = 0.0 Pa.s must be finite and > 0; mu keeps 0.05",
        f"bearing FMU 'BearingFMU' [error]: setString: unknown internal 'magic'; choose one of "
        f"{', '.join(internal_names())}; internal keeps 'reynolds'",
        "bearing FMU 'BearingFMU' [error]: bearing FMU initialisation failed: surrogate file 'missing.json' not "
        "found in the FMU resources folder surrogates/ (bundled: paper_22hz.json, paper_map.json); build the FMU with "
        "`bearing-fmu build --surrogate FILE`"], err
    assert err.count("logging is off") == 4  # the hint, once per instance
    # a good run: every row, and nothing printed
    assert out["good"]["rows"] == 11 and set(out["good"]["Fz"]) == {16.7}


# ----------------------------------------------------------------------------- 2. unknown value references

@pytest.mark.parametrize("direction", ["get", "set"])
@pytest.mark.parametrize("typ, vr, what", [
    ("Real", 9999, "value reference 9999 is not a Real variable of this FMU"),
    ("Integer", 9999, "value reference 9999 is not a Integer variable of this FMU"),
    ("Boolean", 9999, "value reference 9999 is not a Boolean variable of this FMU"),
    ("String", 9999, "value reference 9999 is not a String variable of this FMU"),
    ("Real", "internal", "is not a Real variable"),  # a String variable through the Real call
])
def test_unknown_value_reference_is_an_error(raw, direction, typ, vr, what):
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    vr = r.vars[vr].valueReference if isinstance(vr, str) else vr
    n = len(r.messages)
    status = r.get_vr(typ, vr)[0] if direction == "get" else r.set_vr(typ, vr, {"Real": 1.0, "String": "x"}.get(typ, 1))
    assert status == ERROR
    assert any(f"{direction}{typ}: " in m and what in m for m in r.errors(n)), r.messages[n:]
    assert r.step(0.0, 1e-4, STATE) == OK  # still usable
    assert r.get("Fy") == (OK, linear_force(*STATE[:4])[0])


# ----------------------------------------------------------------------------- 3. doStep arguments

@pytest.mark.parametrize("t, h, expected", [
    (0.0, 0.0, "doStep: communicationStepSize = 0.0 s must be finite and > 0"),
    (0.0, -1e-4, "doStep: communicationStepSize = -0.0001 s must be finite and > 0"),
    (0.0, math.inf, "doStep: communicationStepSize = inf s must be finite and > 0"),
    (0.0, math.nan, "doStep: communicationStepSize = nan s must be finite and > 0"),
    (math.nan, 1e-4, "doStep: currentCommunicationPoint = nan s must be finite"),
    (-math.inf, 1e-4, "doStep: currentCommunicationPoint = -inf s must be finite"),
    (1.7e308, 1e308, "doStep: currentCommunicationPoint + communicationStepSize = 1.7e+308 + 1e+308 s is not finite"),
])
def test_bad_step_size_or_time_is_an_error_naming_it(raw, t, h, expected):
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    assert r.step(0.0, 1e-4, STATE) == OK
    before = r.get("Fy")
    n = len(r.messages)
    assert r.step(t, h, (0.0, 0.0, 0.0, 0.0, OMEGA)) == ERROR
    assert any(expected in m for m in r.errors(n)), r.messages[n:]
    assert r.get("Fy") == before  # nothing computed
    assert r.terminated() == 0  # refused, not discarded
    assert r.step(1e-4, 1e-4) == OK  # and the next good step works


# ----------------------------------------------------------------------------- 4. refused setters

@pytest.mark.parametrize("when, name, value, expected", [
    ("step", "D", 0.05, "setReal: parameter D is fixed after initialisation (variability fixed); it keeps 0.031"),
    ("step", "internal", "reynolds", "setString: parameter internal is fixed after initialisation"),
    ("step", "Fy", 1.0, "setReal: Fy is an output and cannot be set"),
    ("init", "n_x", 3, "setInteger: n_x = 3 must be an even integer >= 2 and <= 100000"),
    ("init", "cavitation", "foo", "setString: unknown cavitation 'foo'; choose one of reynolds, gumbel"),
    ("init", "domain_limit", -1.0, "setReal: domain_limit = -1.0 must be a finite number > 0"),
    ("init", "out_of_domain", 1, "setBoolean: out_of_domain is an output and cannot be set"),
])
def test_refused_setter_is_an_error(raw, when, name, value, expected):
    r = raw()
    if when == "step":
        assert set(r.initialise(**LINEAR).values()) == {OK}
    else:
        for key, v in LINEAR.items():  # reading an output in Initialization Mode evaluates the internal
            assert r.set(key, v) == OK
        r.setup_and_enter()
    old = r.get(name)
    n = len(r.messages)
    assert r.set(name, value) == ERROR
    assert any(expected in m for m in r.errors(n)), r.messages[n:]
    assert r.get(name) == old  # not stored


@pytest.mark.parametrize("name, value", [("y", math.nan), ("omega", math.inf), ("T_supply", -math.inf)])
def test_non_finite_input_is_refused_at_set_real_and_the_value_kept(raw, name, value):
    """A non-finite input is refused by fmi2SetReal (fmi2Error naming it), not taken for the next
    step; the input keeps its value and the step goes on with it (docs/fmu.md, "FMI status")."""
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    for n_, v in zip(("y", "z", "vy", "vz", "omega"), STATE):
        assert r.set(n_, v) == OK
    status, old = r.get(name)
    assert status == OK and math.isfinite(old)
    n = len(r.messages)
    assert r.set(name, value) == ERROR
    assert any(f"input {name} = {value!r} is not finite; it keeps {old!r}" in m for m in r.errors(n)), r.messages[n:]
    assert r.get(name) == (OK, old)
    assert r.step(0.0, 1e-4) == OK  # at the kept inputs
    assert r.get("Fy") == (OK, linear_force(*STATE[:4])[0])


def test_outputs_in_initialization_mode_follow_the_inputs(raw):
    r = raw()
    for name, value in LINEAR.items():
        assert r.set(name, value) == OK
    r.setup_and_enter()
    for state in (STATE, (-1e-5, -5e-5, 0.0, 3e-3, OMEGA)):
        for name, value in zip(("y", "z", "vy", "vz", "omega"), state):
            assert r.set(name, value) == OK
        got = (r.get("Fy"), r.get("Fz"))
        assert got == ((OK, linear_force(*state[:4])[0]), (OK, linear_force(*state[:4])[1]))
        assert r.get("eccentricity") == (OK, math.hypot(*state[:2]) / 90e-6)
        assert r.get("Kyz") == (OK, LIN["Kyz"])  # the tangent too (Lund sign: K as given)
    # a parameter set in Initialization Mode counts as well (the internal is rebuilt)
    assert r.set("lin_Fz0", 20.0) == OK
    assert r.get("Fz") == (OK, linear_force(*state[:4])[1] + 20.0 - LIN["Fz0"])
    # a state the internal refuses: the read is refused, naming the input
    assert r.set("omega", 1.0) == OK
    n = len(r.messages)
    assert r.get("Fy")[0] == ERROR
    assert any("getReal Fy in Initialization Mode: the outputs cannot be computed at the inputs set: linear "
               "internal was linearised at omega = 138.23 rad/s; got omega = 1 rad/s" in m for m in r.errors(n))
    assert r.set("omega", OMEGA) == OK
    assert r.call("fmi2ExitInitializationMode") == OK
    assert r.get("Fz") == (OK, linear_force(*state[:4])[1] + 20.0 - LIN["Fz0"])  # at the start time


def test_initialization_mode_outputs_equal_a_reynolds_step(fmu_instance, raw):
    """The Reynolds internal in Initialization Mode gives the force a doStep gives at that state."""
    stepped = fmu_instance(n_theta=32, n_x=4)
    try:
        out = stepped.step(1e-4, *STATE)
    finally:
        stepped.close()
    r = raw()
    assert r.set("n_theta", 32) == OK and r.set("n_x", 4) == OK
    r.setup_and_enter()
    for name, value in zip(("y", "z", "vy", "vz", "omega"), STATE):
        assert r.set(name, value) == OK
    assert (r.get("Fy"), r.get("Fz")) == ((OK, out["Fy"]), (OK, out["Fz"]))


# ----------------------------------------------------------------------------- 6. no terminated after a discard

@pytest.mark.parametrize("recover", ["restore", "good step"])
@pytest.mark.parametrize("refused", ["faster", "slower"])
def test_discard_then_recovery_is_not_terminated(raw, recover, refused):
    """A refused state (a speed outside the linear model's domain, its one speed omega_lin) is
    fmi2Discard without fmi2Terminated (the patched binary's step-terminated):
    a retry with another state succeeds. Read through fmpy's FMU2Slave.getBooleanStatus too."""
    from fmpy.fmi2 import fmi2Terminated

    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    assert r.step(0.0, 1e-4, STATE) == OK and r.terminated() == 0
    saved = ctypes.c_void_p()
    assert r.call("fmi2GetFMUstate", ctypes.byref(saved)) == OK
    bad = (*STATE[:4], (1.5 if refused == "faster" else 0.5) * OMEGA)
    n = len(r.messages)
    assert r.step(1e-4, 1e-4, bad) == DISCARD
    assert [s for s, _m in r.messages[n:]] == [DISCARD]  # the reason, logged as a discard
    assert r.terminated() == 0 and r.fmu.getBooleanStatus(fmi2Terminated) is False  # the master may go on
    # the same inputs again, unchanged (a master that retries forever, fmpy's simulate_fmu): an error
    assert r.call("fmi2DoStep", 1e-4, 5e-5, 0) == ERROR and "unchanged" in r.errors(n)[-1]
    if recover == "restore":
        assert r.call("fmi2SetFMUstate", saved) == OK
        assert r.terminated() == 0
    assert r.step(1e-4, 1e-4, STATE) == OK
    assert r.terminated() == 0
    assert r.get("Fy") == (OK, linear_force(*STATE[:4])[0])
    assert r.call("fmi2FreeFMUstate", ctypes.byref(saved)) == OK


def test_bad_state_restore_is_an_error_and_changes_nothing(raw):
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    assert r.step(0.0, 1e-4, STATE) == OK
    blob = b'["something else", 0.0, []]'
    state = ctypes.c_void_p()
    buf = (ctypes.c_char * len(blob)).from_buffer_copy(blob)
    n = len(r.messages)
    assert r.call("fmi2DeSerializeFMUstate", buf, len(blob), ctypes.byref(state)) == ERROR
    assert any("its checksum does not match its contents" in m for m in r.errors(n)), r.messages[n:]
    assert r.get("Fy") == (OK, linear_force(*STATE[:4])[0])
    # more damaged states: tests/test_fmu_refusals.py


# ----------------------------------------------------------------------------- 7. messages reach a master without a logger

_ECHO = textwrap.dedent("""
    import ctypes, json, math, sys
    import fmpy
    from fmpy.fmi2 import FMU2Slave
    md = fmpy.read_model_description(sys.argv[1])
    v = {x.name: x.valueReference for x in md.modelVariables}
    unzip = fmpy.extract(sys.argv[1])
    statuses = []
    # a name longer than 15 bytes: pythonfmu's std::string keeps it on the heap (the short one
    # 'BearingFMU' in test_simulate_fmu_... sits in the string object itself)
    for name, logging in (("quiet_instance_of_the_bearing", False), ("logged", True), ("switched", False)):
        f = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=name)
        f.instantiate(loggingOn=logging)
        if name == "switched":
            f.setDebugLogging(True, [])  # turned on after instantiation: nothing printed from here on
        d, c = f.dll, f.component
        def set_(n, x):
            return d.fmi2SetReal(c, (ctypes.c_uint * 1)(v[n]), 1, (ctypes.c_double * 1)(x))
        f.setString([v["internal"]], ["linear"]); f.setString([v["linear_from"]], ["coefficients"])
        f.setupExperiment(startTime=0.0); f.enterInitializationMode()
        statuses.append(d.fmi2ExitInitializationMode(c))        # omega 0 != omega_lin: warning, OK
        set_("omega", 2 * math.pi * 22.0)
        statuses.append(d.fmi2DoStep(c, 0.0, 1e-4, 0))           # OK
        set_("omega", 3 * math.pi * 22.0)
        statuses.append(d.fmi2DoStep(c, 1e-4, 1e-4, 0))          # discard
        set_("omega", 4 * math.pi * 22.0)                        # another refused state (the same again: an error)
        statuses.append(d.fmi2DoStep(c, 1e-4, 1e-4, 0))          # discard again: not printed again
        statuses.append(d.fmi2DoStep(c, 1e-4, 0.0, 0))           # error
        statuses.append(d.fmi2DoStep(c, 1e-4, -1.0, 0))          # error again: not printed again
        f.terminate(); f.freeInstance()
    print(json.dumps(statuses))
""")


def test_without_logging_the_first_warning_discard_and_error_reach_stderr(fmu):
    run = subprocess.run([sys.executable, "-c", _ECHO, str(fmu)], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=""))
    assert run.returncode == 0, run.stderr[-3000:]
    statuses = json.loads(run.stdout.strip().splitlines()[-1])
    assert statuses == [OK, OK, DISCARD, DISCARD, ERROR, ERROR] * 3
    lines = [ln for ln in run.stderr.splitlines() if ln.strip()]
    hint = ("  (logging is off, so this FMU instance prints its first warning, discard and error here; instantiate "
            "it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to receive every message)")
    assert lines == [
        "bearing FMU 'quiet_instance_of_the_bearing' [warning]: outputs at the start time left at their start values: linear internal was "
        "linearised at omega = 138.23 rad/s; got omega = 0 rad/s",
        hint,
        "bearing FMU 'quiet_instance_of_the_bearing' [discard]: linear internal was linearised at omega = 138.23 rad/s; "
        "got omega = 207.345 rad/s at t = 0.0002 s",
        "bearing FMU 'quiet_instance_of_the_bearing' [error]: doStep: communicationStepSize = 0.0 s must be finite and > 0 "
        "(currentCommunicationPoint = 0.0001 s)",
    ], run.stderr  # 'logged' and 'switched' deliver to the logger (fmpy's default prints nothing here)


# ----------------------------------------------------------------------------- the patched binary itself

def test_status_patches_are_all_or_nothing_and_idempotent():
    """Each patch checks the code it changes; on a binary with none of that code nothing
    is written and the slave keeps pythonfmu's statuses (it never raises)."""
    from pathlib import Path

    import pythonfmu

    from bearing_fmu.fmu import resources as fmu_resources
    from bearing_fmu.fmu.binary import _HANDLE, STATUS_PATCHES, _Elf, patch_pythonfmu_binary, status_patched

    assert fmu_resources.STATUS_PATCHES == STATUS_PATCHES  # what the slave looks for is what the build applies

    original = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64"
                / "libpythonfmu-export.so").read_bytes()
    patched, notes = patch_pythonfmu_binary(original)
    assert set(notes.values()) == {"patched"} and status_patched(notes)
    # every changed byte lies in the functions and the text the patches name (fmu_binary.py)
    elf = _Elf(original)
    places = [(elf.offset(sym.value), elf.offset(sym.value) + sym.size) for sym in map(elf.symbol, (
        "_ZN12_GLOBAL__N_115onLibraryUnloadEv", _HANDLE, "fmi2DoStep", "fmi2SetFMUstate", "fmi2FreeInstance"))]
    text = original.find(b"Fatal py exception encountered: ")
    places.append((text, text + 32))
    changed = [k for k, (a, b) in enumerate(zip(original, patched)) if a != b]
    assert len(patched) == len(original) and changed
    assert all(any(lo <= k < hi for lo, hi in places) for k in changed)
    assert {next(i for i, (lo, hi) in enumerate(places) if lo <= k < hi) for k in changed} == set(range(6))
    again, notes2 = patch_pythonfmu_binary(patched)
    assert again == patched and set(notes2.values()) == {"already patched"}
    # fmi2DoStep's code changed (another pythonfmu build): no status patch at all
    at = original.find(bytes.fromhex("84c07530f20f101424c6430801"))
    other = original[:at] + b"\x90" + original[at + 1:]
    out, notes3 = patch_pythonfmu_binary(other)
    assert not status_patched(notes3) and notes3["exit-unload"] == notes3["free-once"] == "patched"
    assert all(notes3[n].startswith("left as is") for n in STATUS_PATCHES)
    moved = [k for k, (a, b) in enumerate(zip(other, out)) if a != b]  # only the exit fix and free-once
    assert moved and all(places[0][0] <= k < places[0][1] or places[4][0] <= k < places[4][1] for k in moved)


def test_an_fmu_without_the_status_patches_never_raises(fmu, tmp_path):
    """pythonfmu as is (the notes file says the patches are missing): a refused call is logged
    with status Error and returns fmi2OK, and the instance is not released (no crash)."""
    import zipfile

    legacy = tmp_path / "legacy.fmu"
    with zipfile.ZipFile(fmu) as zin, zipfile.ZipFile(legacy, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "resources/pythonfmu_patches.json":
                data = json.dumps({"linux64": {"keep-instance": "left as is: test"}}).encode()
            zout.writestr(item, data)
    r = Raw(legacy, fmpy.extract(str(legacy)))
    try:
        assert r.get_vr("Real", 9999)[0] == OK
        assert any("getReal: value reference 9999 is not a Real variable" in m for m in r.errors())
        assert r.set("D", -1.0) == OK and r.initialise()["exit"] == OK
        assert any("bearing FMU initialisation failed: D = -1.0 m must be finite and > 0" in m for m in r.errors())
        assert r.step(0.0, 1e-4) == DISCARD  # as before the patches: the step is discarded with the reason
    finally:
        r.close()


def test_fmpy_wrappers_raise_with_the_status(fmu_instance):
    """fmpy's checking wrappers (FMU2Slave.doStep, getReal, ...) raise FMICallException with
    the status: an error is never mistaken for a discard."""
    inst = fmu_instance(**LINEAR)
    try:
        with pytest.raises(FMICallException) as exc:
            inst.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=-1.0)
        assert exc.value.status == ERROR
        with pytest.raises(FMICallException) as exc:
            inst.fmu.getReal([9999])
        assert exc.value.status == ERROR
        assert inst.step(1e-4, *STATE)["Fy"] == linear_force(*STATE[:4])[0]
    finally:
        inst.close()
