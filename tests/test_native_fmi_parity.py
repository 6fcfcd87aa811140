"""The native FMU's FMI 2.0 and FMI 3.0 binaries answer alike (issue 32, item 3).

Both FMI layers are a check and one call into the same model layer (c/bearing_calls.c); here the
two binaries of one build are driven through ctypes with the same sequences, and every call must
return the same status in both: each call in each mode (where the two standards' calling
sequences, ``order.ALLOWED`` and ``fmi3.ALLOWED3``, agree; where they differ, each refuses as its
own table says), and each refusal of docs/fmu.md's "FMI status" table (a parameter refused alone
or together, a fixed parameter, an output set, an unknown value reference, a bad step, a refused
state at initialisation, in a step and in Model Exchange, a retried discarded step, a non-finite
time or direction, a foreign FMU state, a wrong number of continuous states), whose expected
status the table gives. And the C beneath: every file a unit of its own, no two calling each other.
"""

import ctypes
import math
import shutil
import subprocess
from pathlib import Path

import pytest

import fmpy
from fmpy.fmi2 import (FMU2Model, FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2EventInfo)
from fmpy.fmi3 import FMU3Model, FMU3Slave

from bearing_fmu.fmu.native.fmi3 import ALLOWED3
from bearing_fmu.fmu.order import ALLOWED
from bearing_fmu.physics.params import PAPER_BEARING as P

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
IN = ("y", "z", "vy", "vz", "omega")
OMEGA = 2 * math.pi * 22.0
GOOD = (0.2 * P.CR, -0.4 * P.CR, 0.0, 0.0, OMEGA)  # inside the map (eccentricity ratio 0.45)
WALL = (1.2 * P.CR, 0.0, 0.0, 0.0, OMEGA)  # beyond the bearing wall: refused by the internal

pytestmark = pytest.mark.slow  # two native builds, driven call by call


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    """version -> (fmu, extracted folder) of one map FMU built for FMI 2.0 and for FMI 3.0."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder = tmp_path_factory.mktemp("parity")
    out = {}
    for version in (2, 3):
        path = build_native_fmu(folder / f"map{version}.fmu", "map", map=PAPER_MAP, compiler="cc",
                                fmi_version=version)
        out[version] = (path, fmpy.extract(str(path)))
    return out


class Driver:
    """One instance of either binary, the same operations on both; each returns the worst status
    of the FMI calls it makes, every log line kept."""

    def __init__(self, built, version, kind):
        path, unzip = built
        md = fmpy.read_model_description(str(path))
        self.version, self.kind = version, kind
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.time_vr = self.vr.get("time", 0)  # FMI 3.0's independent variable
        self.messages = []
        ident = (md.coSimulation or md.modelExchange).modelIdentifier
        if version == 2:
            self._cb = fmi2CallbackFunctions()
            self._cb.logger = fmi2CallbackLoggerTYPE(lambda _e, _n, s, _c, msg: self.messages.append((s, msg.decode())))
            self._cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
            self._cb.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy.free)
            cls = FMU2Slave if kind == "CS" else FMU2Model
            self.fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="parity")
            self.fmu.instantiate(callbacks=self._cb, loggingOn=True)
            self._f = lambda name: getattr(self.fmu.dll, f"fmi2{name}")
        else:
            cls = FMU3Slave if kind == "CS" else FMU3Model
            self.fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="parity")
            self.fmu.instantiate(loggingOn=True, logMessage=lambda _e, s, _c, msg: self.messages.append(
                (s, msg.decode())))
            self._f = lambda name: self.fmu._functions[f"fmi3{name}"]
        self.c = ctypes.c_void_p(self.fmu.component)

    def call(self, fmi2_name, fmi3_name, *args):
        name = fmi2_name[0].upper() + fmi2_name[1:] if self.version == 2 else fmi3_name
        return self._f(name)(self.c, *args)

    def _vrs(self, names):
        return (ctypes.c_uint * len(names))(*[self.vr[n] if isinstance(n, str) else n for n in names])

    # ------------------------------------------------------------------ the operations

    def enter(self, start=0.0):
        if self.version == 2:
            s = self.call("setupExperiment", "", 0, ctypes.c_double(0.0), ctypes.c_double(start), 0,
                          ctypes.c_double(0.0))
            return s if s == ERROR else max(s, self.call("enterInitializationMode", ""))
        return self.call("", "EnterInitializationMode", False, ctypes.c_double(0.0), ctypes.c_double(start), False,
                         ctypes.c_double(0.0))

    def exit(self):
        return self.call("exitInitializationMode", "ExitInitializationMode")

    def terminate(self):
        return self.call("terminate", "Terminate")

    def reset(self):
        return self.call("reset", "Reset")

    def set_reals(self, names, values):
        n = len(names)
        extra = (n,) if self.version == 3 else ()
        return self.call("setReal", "SetFloat64", self._vrs(names), n, (ctypes.c_double * n)(*values), *extra)

    def get_reals(self, names):
        n = len(names)
        out = (ctypes.c_double * n)()
        extra = (n,) if self.version == 3 else ()
        return self.call("getReal", "GetFloat64", self._vrs(names), n, out, *extra)

    def inputs(self, state):
        return self.set_reals(IN, state)

    def now(self) -> float:
        """The instance's time: where its last step ended (a step must start there)."""
        t = ctypes.c_double()
        if self.version == 2:
            status = self.call("getRealStatus", "", 2, ctypes.byref(t))  # fmi2LastSuccessfulTime
            return t.value if status == 0 else 0.0  # (refused before initialisation)
        out = (ctypes.c_double * 1)()
        status = self.call("", "GetFloat64", (ctypes.c_uint * 1)(self.time_vr), 1, out, 1)
        return out[0] if status == 0 else 0.0

    def step(self, t=None, h=1e-4):
        t = self.now() if t is None else t
        if self.version == 2:
            return self.call("doStep", "", ctypes.c_double(t), ctypes.c_double(h), 0)
        flags, last = [ctypes.c_bool() for _ in range(3)], ctypes.c_double()
        return self.call("", "DoStep", ctypes.c_double(t), ctypes.c_double(h), True,
                         *(ctypes.byref(b) for b in flags), ctypes.byref(last))

    def enter_event(self):
        return self.call("enterEventMode", "EnterEventMode")

    def enter_ct(self):
        return self.call("enterContinuousTimeMode", "EnterContinuousTimeMode")

    def discrete(self):
        if self.version == 2:
            return self.call("newDiscreteStates", "", ctypes.byref(fmi2EventInfo()))
        flags = [ctypes.c_bool() for _ in range(5)]
        return self.call("", "UpdateDiscreteStates", *(ctypes.byref(b) for b in flags),
                         ctypes.byref(ctypes.c_double()))

    def completed(self):
        if self.version == 2:
            a, b = ctypes.c_int(), ctypes.c_int()
        else:
            a, b = ctypes.c_bool(), ctypes.c_bool()
        return self.call("completedIntegratorStep", "CompletedIntegratorStep", 1, ctypes.byref(a), ctypes.byref(b))

    def set_time(self, t):
        return self.call("setTime", "SetTime", ctypes.c_double(t))

    def derivative(self, unknowns, knowns, seed):
        out = (ctypes.c_double * len(unknowns))()
        seeds = (ctypes.c_double * len(seed))(*seed)
        if self.version == 2:
            return self.call("getDirectionalDerivative", "", self._vrs(unknowns), len(unknowns), self._vrs(knowns),
                             len(knowns), seeds, out)
        return self.call("", "GetDirectionalDerivative", self._vrs(unknowns), len(unknowns), self._vrs(knowns),
                         len(knowns), seeds, len(seed), out, len(unknowns))

    def get_state(self):
        state = ctypes.c_void_p()
        s = self.call("getFMUstate", "GetFMUState", ctypes.byref(state))
        if state.value:
            self.call("freeFMUstate", "FreeFMUState", ctypes.byref(state))
        return s

    def foreign_state(self):
        self._foreign = ctypes.create_string_buffer(4096)  # zeros: no tag, no build id
        return self.call("setFMUstate", "SetFMUState", ctypes.cast(self._foreign, ctypes.c_void_p))

    def states(self, n=0):
        return self.call("getContinuousStates", "GetContinuousStates", (ctypes.c_double * 2)(), n)

    def nominals(self, n=0):
        return self.call("getNominalsOfContinuousStates", "GetNominalsOfContinuousStates", (ctypes.c_double * 2)(), n)

    def close(self):
        self.fmu.freeInstance()


# ----------------------------------------------------------------------------- the calling sequence

# operation -> (the FMI 2.0 call in order.ALLOWED, the FMI 3.0 function in ALLOWED3, how to call it)
OPERATIONS = {
    "enter": ("enterInitializationMode", "EnterInitializationMode", lambda d: d.enter()),
    "exit": ("exitInitializationMode", "ExitInitializationMode", lambda d: d.exit()),
    "terminate": ("terminate", "Terminate", lambda d: d.terminate()),
    "reset": ("reset", "Reset", lambda d: d.reset()),
    "set input": ("setReal", "SetFloat64", lambda d: d.inputs(GOOD)),
    "get output": ("getReal", "GetFloat64", lambda d: d.get_reals(["Fy"])),
    "step": ("doStep", "DoStep", lambda d: d.step()),
    "enter event": ("enterEventMode", "EnterEventMode", lambda d: d.enter_event()),
    "enter continuous": ("enterContinuousTimeMode", "EnterContinuousTimeMode", lambda d: d.enter_ct()),
    "discrete states": ("newDiscreteStates", "UpdateDiscreteStates", lambda d: d.discrete()),
    "completed step": ("completedIntegratorStep", "CompletedIntegratorStep", lambda d: d.completed()),
    "set time": ("setTime", "SetTime", lambda d: d.set_time(1e-3)),
    "derivative": ("getDirectionalDerivative", "GetDirectionalDerivative",
                   lambda d: d.derivative(["Fy"], ["y"], [1.0])),
    "FMU state": ("getFMUstate", "GetFMUState", lambda d: d.get_state()),
    "continuous states": ("getContinuousStates", "GetContinuousStates", lambda d: d.states()),
    "nominals": ("getNominalsOfContinuousStates", "GetNominalsOfContinuousStates", lambda d: d.nominals()),
}
MODES = {"CS": ("Instantiated", "Initialization Mode", "Step Mode", "Terminated"),
         "ME": ("Instantiated", "Initialization Mode", "Event Mode", "Continuous-Time Mode", "Terminated")}


def drive(d: Driver, mode: str) -> None:
    """Bring a fresh instance to ``mode`` by allowed calls, at inputs the map evaluates."""
    assert d.inputs(GOOD) == OK
    if mode == "Instantiated":
        return
    assert d.enter() == OK
    if mode == "Initialization Mode":
        return
    assert d.exit() == OK
    if mode == "Continuous-Time Mode":
        assert d.enter_ct() == OK
    if mode == "Terminated":
        assert d.terminate() == OK


@pytest.mark.parametrize("kind", ["CS", "ME"])
def test_each_call_in_each_mode_answers_alike(builds, kind):
    compared = differ = 0
    for op, (c2, c3, run) in OPERATIONS.items():
        for mode in MODES[kind]:
            status = {}
            for version in (2, 3):
                d = Driver(builds[version], version, kind)
                try:
                    drive(d, mode)
                    status[version] = run(d)
                finally:
                    d.close()
            in2, in3 = mode in ALLOWED[c2], mode in ALLOWED3[c3]
            if in2 == in3:  # the standards agree on the calling sequence: the same answer
                compared += 1
                assert status[2] == status[3], (kind, op, mode, status)
            else:  # each refuses as its own standard says
                differ += 1
                for version, allowed in ((2, in2), (3, in3)):
                    if not allowed:
                        assert status[version] == ERROR, (kind, op, mode, version, status)
    assert compared > 3 * differ  # most of the table is shared by the two standards


# ----------------------------------------------------------------------------- the refusals

def _refused_start_state(d):
    return [d.inputs(WALL), d.enter(), d.get_reals(["Fy"]), d.exit(), d.step(), d.step(), d.inputs(GOOD), d.step()]


def _refused_parameter(d):
    return [d.set_reals(["D"], [-1.0]), d.enter(), d.exit(), d.set_reals(["D"], [P.D]), d.exit(), d.step()]


def _parameters_not_together(d):
    return [d.set_reals(["CR"], [P.D]), d.enter(), d.exit(), d.set_reals(["CR"], [P.CR]), d.exit()]


def _bad_values(d):
    return [d.set_reals([9999], [1.0]), d.get_reals([9999]), d.set_reals(["Fy"], [1.0]), d.inputs(GOOD), d.enter(),
            d.exit(), d.set_reals(["D"], [P.D]), d.inputs(GOOD), d.step(0.0, 0.0), d.step(float("nan")),
            d.step(0.0, float("inf")), d.step()]


def _refused_step(d):
    return [d.inputs(GOOD), d.enter(), d.exit(), d.step(), d.inputs(WALL), d.step(1e-4), d.step(1e-4),
            d.inputs(GOOD), d.step(1e-4)]


def _derivatives(d):
    return [d.inputs(GOOD), d.enter(), d.exit(), d.derivative(["Fy"], ["y"], [float("nan")]),
            d.derivative(["y"], ["y"], [1.0]), d.derivative(["Fy", "Kyy"], ["y", "omega"], [1.0, 2.0]),
            d.inputs(WALL), d.derivative(["Fy"], ["y"], [1.0])]


def _fmu_states(d):
    return [d.get_state(), d.foreign_state(), d.enter(), d.exit(), d.get_state(), d.foreign_state()]


def _model_exchange(d):
    return [d.inputs(WALL), d.enter(), d.exit(), d.enter_ct(), d.set_time(float("nan")), d.set_time(1e-3),
            d.get_reals(["Fy"]), d.completed(), d.enter_event(), d.discrete(), d.enter_ct(), d.inputs(GOOD),
            d.get_reals(["Fy"]), d.completed(), d.states(1), d.nominals(2), d.states(0), d.terminate()]


# sequence -> (interface, the statuses docs/fmu.md's "FMI status" table gives)
CASES = {
    "a refused start state": (_refused_start_state, "CS",
                              [OK, OK, ERROR, WARNING, DISCARD, ERROR, OK, OK]),
    "a parameter refused alone": (_refused_parameter, "CS", [ERROR, OK, ERROR, OK, OK, OK]),
    "parameters refused together": (_parameters_not_together, "CS", [OK, OK, ERROR, OK, OK]),
    "bad values and steps": (_bad_values, "CS",
                             [ERROR, ERROR, ERROR, OK, OK, OK, ERROR, OK, ERROR, ERROR, ERROR, OK]),
    "a refused step": (_refused_step, "CS", [OK, OK, OK, OK, OK, DISCARD, ERROR, OK, OK]),
    "derivatives": (_derivatives, "CS", [OK, OK, OK, ERROR, ERROR, OK, OK, DISCARD]),
    "FMU states": (_fmu_states, "CS", [OK, ERROR, OK, OK, OK, ERROR]),
    "Model Exchange": (_model_exchange, "ME",
                       [OK, OK, WARNING, OK, ERROR, OK, DISCARD, OK, OK, OK, OK, OK, OK, OK, ERROR, ERROR, OK, OK]),
}


@pytest.mark.parametrize("case", list(CASES))
def test_each_refusal_answers_alike(builds, case):
    sequence, kind, expected = CASES[case]
    got = {}
    for version in (2, 3):
        d = Driver(builds[version], version, kind)
        try:
            got[version] = sequence(d)
            if ERROR in got[version]:  # an error is logged with the reason in both
                assert any(s == ERROR for s, _m in d.messages)
        finally:
            d.close()
    assert got[2] == got[3] == expected, got


# ----------------------------------------------------------------------------- the C units

SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"


@pytest.mark.skipif(not (shutil.which("gcc") or shutil.which("cc")) or not shutil.which("nm"),
                    reason="needs the system C compiler and nm")
def test_every_c_file_is_a_unit_and_no_two_call_each_other(tmp_path):
    """Every staged .c file is compiled as a unit of its own (none included by another), compiles
    alone with its headers, and the units' calls (read from the objects' symbols) have no pair
    calling each other: the FMI layer calls the model layer, the model layer the internals."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.compile import fmi_headers

    fmu = build_native_fmu(tmp_path / "all.fmu", "taylor,reynolds,map,linear", surrogate=SURROGATE, map=PAPER_MAP,
                           compiler="cc")
    unzip = Path(fmpy.extract(str(fmu)))
    md = fmpy.read_model_description(str(fmu))
    listed = list(md.buildConfigurations[0].sourceFileSets[0].sourceFiles)
    assert sorted(p.name for p in (unzip / "sources").glob("*.c")) == sorted(listed)
    cc = shutil.which("gcc") or shutil.which("cc")
    defined, used = {}, {}
    for name in listed:
        obj = tmp_path / f"{name}.o"
        done = subprocess.run([cc, "-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", "-I",
                               str(unzip / "sources"), "-I", str(fmi_headers()), str(unzip / "sources" / name), "-o",
                               str(obj)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr[-2000:]
        rows = [line.split() for line in subprocess.run(["nm", str(obj)], capture_output=True,
                                                        text=True).stdout.splitlines()]
        defined[name] = {r[2] for r in rows if len(r) == 3 and r[1] in "TDRB"}
        used[name] = {r[1] for r in rows if len(r) == 2 and r[0] == "U"}
    calls = {a: {b for b in listed if b != a and used[a] & defined[b]} for a in listed}
    assert calls["fmi2_bearing.c"] and "fmi2_bearing.c" not in set().union(*calls.values())  # the top layer
    both = sorted({tuple(sorted((a, b))) for a in listed for b in calls[a] if a in calls[b]})
    assert not both, f"C files calling each other: {both}"
