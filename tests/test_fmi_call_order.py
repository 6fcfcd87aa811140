"""The FMI 2.0 calling sequence in both bearing FMUs (issue 22, item 5; docs/fmu.md, "FMI status").

The allowed modes of every call are one table, ``bearing_fmu.fmu.order``; here each FMU is driven
out of order through fmpy's raw ctypes functions and must answer fmi2Error with the table's words,
then go on as if the call had not been made. Calls that would crash a process without the fix
(a second fmi2FreeInstance, a freed FMU state) run in a subprocess, so a regression fails one
test instead of the session. Also: NaN time and direction (native), the host's message for an FMU
that cannot be instantiated, the Taylor domain warning once per excursion, no traceback in a log.
"""

import ctypes
import json
import math
import os
import shutil
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest

import fmpy  # noqa: E402
from fmpy import calloc, free  # noqa: E402
from fmpy.fmi2 import (FMU2Model, FMU2Slave, fmi2CallbackAllocateMemoryTYPE,  # noqa: E402
                       fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

from bearing_fmu.fmu.order import INIT, INSTANTIATED, STEP, TERMINATED, refusal  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING as P  # noqa: E402
from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
OMEGA = 2 * math.pi * 22.0
IN = ("y", "z", "vy", "vz", "omega")
HAS_CC = bool(os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc"))


@pytest.fixture(scope="module")
def native(tmp_path_factory, native_build_cache):
    """A native Taylor FMU (the shipped 22 Hz surrogate): (fmu, extracted folder)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    fmu = native_build_cache(tmp_path_factory.mktemp("order") / "taylor.fmu",
                             lambda target: build_native_fmu(target, "taylor", surrogate=SURROGATE,
                                                             platforms=["linux64"]),
                             [SURROGATE], ("taylor", "linux64"))
    return fmu, fmpy.extract(str(fmu))


@pytest.fixture(params=["python", pytest.param("native", marks=pytest.mark.native)])
def either(request, fmu, unzip):
    """(fmu, folder, kind) of each FMU in turn."""
    if request.param == "python":
        return fmu, unzip, "python"
    return (*request.getfixturevalue("native"), "native")


class Instance:
    """One instance; ``call`` is the raw ctypes call (its fmi2Status), ``messages`` the log."""

    def __init__(self, fmu, unzip, kind="CS"):
        md = fmpy.read_model_description(str(fmu))
        self.vars = {v.name: v for v in md.modelVariables}
        self.messages = []
        self._cb = fmi2CallbackFunctions()  # ctypes callbacks must outlive the instance
        self._cb.logger = fmi2CallbackLoggerTYPE(
            lambda _e, _n, status, _c, msg: self.messages.append((status, msg.decode() if msg else "")))
        self._cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self._cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        cls = FMU2Slave if kind == "CS" else FMU2Model
        ident = (md.coSimulation if kind == "CS" else md.modelExchange).modelIdentifier
        self.fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="order")
        self.fmu.instantiate(callbacks=self._cb, loggingOn=True)
        self.c = ctypes.c_void_p(self.fmu.component)

    def call(self, name, *args) -> int:
        return getattr(self.fmu.dll, f"fmi2{name}")(self.c, *args)

    def set(self, name, value) -> int:
        v = self.vars[name]
        typ, c_type = {"String": ("String", ctypes.c_char_p), "Integer": ("Integer", ctypes.c_int)}.get(
            v.type, ("Real", ctypes.c_double))
        value = value.encode() if typ == "String" else value
        return self.call(f"Set{typ}", (ctypes.c_uint * 1)(v.valueReference), 1, (c_type * 1)(value))

    def get(self, name):
        out = (ctypes.c_double * 1)()
        return self.call("GetReal", (ctypes.c_uint * 1)(self.vars[name].valueReference), 1, out), out[0]

    def inputs(self, state) -> int:
        vrs = (ctypes.c_uint * 5)(*[self.vars[n].valueReference for n in IN])
        return self.call("SetReal", vrs, 5, (ctypes.c_double * 5)(*state))

    def setup(self) -> int:
        return self.call("SetupExperiment", 0, ctypes.c_double(0.0), ctypes.c_double(0.0), 0, ctypes.c_double(0.0))

    def step(self, t, h=1e-4) -> int:
        return self.call("DoStep", ctypes.c_double(t), ctypes.c_double(h), 0)

    def last(self, status=ERROR) -> str:
        return next((m for s, m in reversed(self.messages) if s >= status), "")

    def close(self):
        self.fmu.freeInstance()


def _to(inst, mode, kind):
    """Bring a fresh instance to ``mode`` the legal way (a linear internal in the Python FMU)."""
    if kind == "python":
        assert inst.set("internal", "linear") == OK and inst.set("linear_from", "coefficients") == OK
    if mode == INSTANTIATED:
        return
    assert inst.setup() == OK and inst.call("EnterInitializationMode") == OK
    if mode == INIT:
        return
    assert inst.call("ExitInitializationMode") == OK
    if mode == TERMINATED:
        assert inst.call("Terminate") == OK


_CASES = [  # (mode, call, its arguments)
    (INSTANTIATED, "exitInitializationMode", ()),
    (INSTANTIATED, "doStep", (ctypes.c_double(0.0), ctypes.c_double(1e-4), 0)),
    (INSTANTIATED, "getReal", ((ctypes.c_uint * 1)(5), 1, (ctypes.c_double * 1)())),
    (INSTANTIATED, "terminate", ()),
    (INIT, "enterInitializationMode", ()),
    (INIT, "setupExperiment", (0, ctypes.c_double(0.0), ctypes.c_double(0.0), 0, ctypes.c_double(0.0))),
    (INIT, "doStep", (ctypes.c_double(0.0), ctypes.c_double(1e-4), 0)),
    (STEP, "enterInitializationMode", ()),
    (STEP, "exitInitializationMode", ()),
    (TERMINATED, "doStep", (ctypes.c_double(0.0), ctypes.c_double(1e-4), 0)),
    (TERMINATED, "setReal", ((ctypes.c_uint * 1)(0), 1, (ctypes.c_double * 1)(0.0))),
    (TERMINATED, "terminate", ()),
]


@pytest.mark.parametrize("mode, call, args", _CASES, ids=[f"{c}-in-{m}" for m, c, _a in _CASES])
def test_a_call_out_of_order_is_an_error_naming_it_and_changes_nothing(either, mode, call, args):
    fmu, unzip, kind = either
    inst = Instance(fmu, unzip)
    try:
        _to(inst, mode, kind)
        n = len(inst.messages)
        assert inst.call(call[0].upper() + call[1:], *args) == ERROR
        errors = [m for s, m in inst.messages[n:] if s == ERROR]
        assert len(errors) == 1 and errors[0].endswith(refusal(call, mode)), errors  # the Python FMU: a prefix
        # nothing changed: the legal sequence goes on from where it was
        if mode == INSTANTIATED:
            assert inst.setup() == OK and inst.call("EnterInitializationMode") == OK
        if mode in (INSTANTIATED, INIT):
            assert inst.call("ExitInitializationMode") == OK, inst.last()
        if mode != TERMINATED:
            assert inst.step(0.0) in (OK, DISCARD)  # the start state may be refused (omega = 0), not the call
    finally:
        inst.close()


def test_the_words_are_the_same_in_both_fmus(fmu, unzip, native):
    """Both FMUs word a refusal from the one table: the native message equals fmi_order.refusal."""
    py, nat = Instance(fmu, unzip), Instance(*native)
    try:
        for inst in (py, nat):
            assert inst.call("ExitInitializationMode") == ERROR
        assert py.last() == f"fmi2Error from the Python slave [exitInitializationMode] PyObject_CallMethod {nat.last()}"
        assert nat.last() == ("exitInitializationMode in Instantiated: not allowed there (FMI 2.0: in Initialization "
                              "Mode only); call enterInitializationMode first")
    finally:
        py.close()
        nat.close()


def test_native_model_exchange_refuses_nan_time_and_direction_and_co_simulation_calls(native):
    inst = Instance(*native, kind="ME")
    try:
        assert inst.setup() == OK and inst.call("EnterInitializationMode") == OK
        assert inst.call("SetTime", ctypes.c_double(0.0)) == ERROR  # before Event Mode
        assert "setTime in Initialization Mode: not allowed there" in inst.last()
        assert inst.call("ExitInitializationMode") == OK  # Event Mode
        assert inst.call("SetTime", ctypes.c_double(math.nan)) == ERROR
        assert inst.last() == "setTime: time = nan s must be finite; the instance keeps t = 0 s"
        assert inst.call("SetTime", ctypes.c_double(1e-3)) == OK
        s = load_surrogate(SURROGATE)
        assert inst.inputs((s.y0, s.z0, 0.0, 0.0, s.omega)) == OK
        fy = (ctypes.c_uint * 1)(inst.vars["Fy"].valueReference)
        known = (ctypes.c_uint * 2)(inst.vars["y"].valueReference, inst.vars["vz"].valueReference)
        out = (ctypes.c_double * 1)()
        nan_seed, seed = (ctypes.c_double * 2)(1.0, math.nan), (ctypes.c_double * 2)(1.0, 0.0)
        assert inst.call("GetDirectionalDerivative", fy, 1, known, 2, nan_seed, out) == ERROR
        assert inst.last() == "getDirectionalDerivative: dvKnown[1] = nan (the direction in vz) must be finite"
        assert inst.call("GetDirectionalDerivative", fy, 1, known, 2, seed, out) == OK
        assert math.isfinite(out[0])
        assert inst.step(0.0) == ERROR and inst.last() == "doStep in Event Mode: a Co-Simulation call; this " \
                                                          "instance is a Model Exchange one"
    finally:
        inst.close()


# ----------------------------------------------------------------------------- what crashed a host before

_CHILD = textwrap.dedent("""
    import ctypes, gc, json, sys
    import fmpy
    from fmpy.fmi2 import FMU2Slave
    md = fmpy.read_model_description(sys.argv[1])
    unzip = fmpy.extract(sys.argv[1])
    v = {x.name: x.valueReference for x in md.modelVariables}
    out = {}
    def make():
        f = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="child")
        f.instantiate(loggingOn=False)
        d, c = f.dll, ctypes.c_void_p(f.component)
        if sys.argv[2] == "python":
            for name, value in (("internal", b"linear"), ("linear_from", b"coefficients")):
                d.fmi2SetString(c, (ctypes.c_uint * 1)(v[name]), 1, (ctypes.c_char_p * 1)(value))
        d.fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0)
        d.fmi2EnterInitializationMode(c)
        d.fmi2ExitInitializationMode(c)
        return f, d, c
    keep, d, c = make()  # keeps the library loaded while others are freed
    # an FMU state freed, then used through a copy of its pointer
    s = ctypes.c_void_p()
    out["get"] = d.fmi2GetFMUstate(c, ctypes.byref(s))
    stale = ctypes.c_void_p(s.value)
    out["free"] = d.fmi2FreeFMUstate(c, ctypes.byref(s))
    size = ctypes.c_size_t()
    if sys.argv[2] == "python":  # pythonfmu leaves the master's pointer as it was; the FMU keeps the object
        out["set_stale"] = d.fmi2SetFMUstate(c, stale)
        out["size_stale"] = d.fmi2SerializedFMUstateSize(c, stale, ctypes.byref(size))
        out["free_again"] = d.fmi2FreeFMUstate(c, ctypes.byref(ctypes.c_void_p(stale.value)))
    else:  # the native FMU frees the memory and sets the master's pointer to NULL (a stale copy: undefined)
        out["set_stale"] = d.fmi2SetFMUstate(c, s)
        out["size_stale"] = d.fmi2SerializedFMUstateSize(c, s, ctypes.byref(size))
    gc.collect()
    out["step_after"] = d.fmi2DoStep(c, 0.0, 1e-4, 0)
    # an instance freed twice
    f, d2, c2 = make()
    d2.fmi2FreeInstance(c2)
    d2.fmi2FreeInstance(c2)
    out["freed_twice"] = "survived"
    f2, d3, c3 = make()  # and the next instance works
    out["next_instance_step"] = d3.fmi2DoStep(c3, 0.0, 1e-4, 0)
    d3.fmi2FreeInstance(c3)
    print(json.dumps(out))
""")


def test_a_freed_state_and_a_second_free_are_refused_not_a_crash(either):
    fmu, _unzip, kind = either
    run = subprocess.run([sys.executable, "-c", _CHILD, str(fmu), kind], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=""))
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert (out["get"], out["free"], out["set_stale"], out["size_stale"]) == (OK, OK, ERROR, ERROR), out
    assert out.get("free_again", OK) == OK and out["freed_twice"] == "survived"
    assert out["step_after"] in (OK, DISCARD) and out["next_instance_step"] in (OK, DISCARD), out
    if kind == "native":  # logging is off; the FMU says on stderr what it left alone
        assert "fmi2FreeInstance" in run.stderr and "not a live instance of this FMU (freed already?)" in run.stderr


def test_the_python_fmu_names_a_freed_state(fmu, unzip):
    """In process: the freed state is refused with its reason (the stale-pointer case is the child's)."""
    inst = Instance(fmu, unzip)
    try:
        _to(inst, STEP, "python")
        s = ctypes.c_void_p()
        assert inst.call("GetFMUstate", ctypes.byref(s)) == OK
        stale = ctypes.c_void_p(s.value)
        assert inst.call("FreeFMUstate", ctypes.byref(s)) == OK
        assert inst.call("SetFMUstate", stale) == ERROR
        assert inst.last().endswith("setFMUstate: this FMU state was freed (fmi2FreeFMUstate); the instance keeps "
                                    "its state")
        buf = (ctypes.c_char * 64)()
        assert inst.call("SerializeFMUstate", stale, buf, 64) == ERROR
        assert inst.last().endswith("serializing an FMU state: this FMU state was freed (fmi2FreeFMUstate)")
    finally:
        inst.close()


# ----------------------------------------------------------------------------- the host's message

def _damaged(fmu: Path, out: Path, edit) -> Path:
    with zipfile.ZipFile(fmu) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            zout.writestr(item, edit(item.filename, zin.read(item.filename)))
    return out


def test_the_host_forwards_the_fmus_own_words_when_it_cannot_be_instantiated(native, fmu, tmp_path):
    from rotor_host.coupling.cosim import FMUBearings, FMUError

    guid = fmpy.read_model_description(str(native[0])).guid
    wrong = _damaged(native[0], tmp_path / "wrong_guid.fmu", lambda name, data: data.replace(
        guid.encode(), b"{00000000-0000-0000-0000-000000000000}") if name == "modelDescription.xml" else data)
    with pytest.raises(FMUError) as exc:
        FMUBearings(wrong, [(0, 1)], OMEGA, [{}])
    assert str(exc.value) == ("bearing 1: wrong_guid.fmu could not be instantiated (fmi2Instantiate returned no "
                              f"instance): [error] fmi2Instantiate: the GUID given is not this FMU's ({guid})")
    broken = _damaged(fmu, tmp_path / "broken_slave.fmu", lambda name, data: b'raise ImportError("damaged")\n' + data
                      if name.startswith("resources/") and name.endswith("_slave.py") else data)
    with pytest.raises(FMUError) as exc:
        FMUBearings(broken, [(0, 1)], OMEGA, [{}])
    assert str(exc.value).startswith("bearing 1: broken_slave.fmu could not be instantiated (fmi2Instantiate returned "
                                     "no instance): [fatal] ")
    assert "fmi2Error from the Python slave [ctor] " in str(exc.value)  # pythonfmu's words for a slave it cannot load


# ----------------------------------------------------------------------------- log lines

def _excursions(inst, inside, outside):
    """Steps in, out, out, in, a Newton-like step out (three iterates from one saved state), in,
    out; then terminate. Returns the domain warnings and the terminate line."""
    t = 0.0
    for state in (inside, outside, outside, inside):
        assert inst.inputs(state) == OK and inst.step(t) == OK, inst.last()
        t += 1e-4
    saved = ctypes.c_void_p()
    assert inst.call("GetFMUstate", ctypes.byref(saved)) == OK
    for state in (outside, outside, inside):  # iterates of one step: one excursion begins at most
        assert inst.call("SetFMUstate", saved) == OK
        assert inst.inputs(state) == OK and inst.step(t) == OK
    assert inst.call("FreeFMUstate", ctypes.byref(saved)) == OK
    t += 1e-4
    assert inst.inputs(outside) == OK and inst.step(t) == OK
    assert inst.call("Terminate") == OK
    warned = [m for s, m in inst.messages if s == WARNING and "state outside the surrogate's fitted domain" in m]
    return warned, inst.messages[-1]


def test_the_domain_warning_comes_once_per_excursion_and_is_counted(either):
    fmu, unzip, kind = either
    inst = Instance(fmu, unzip)
    try:
        if kind == "python":  # the session FMU's made-up surrogate: a disc of 0.3 CR about (0.1, -0.4) CR
            assert inst.set("internal", "taylor") == OK
            inside, outside = (0.12 * P.CR, -0.42 * P.CR, 0.0, 0.0, OMEGA), (0.45 * P.CR, -0.4 * P.CR, 0.0, 0.0, OMEGA)
        else:
            s = load_surrogate(SURROGATE)
            inside = (s.y0, s.z0, 0.0, 0.0, s.omega)  # the expansion point: on the training orbits
            outside = (s.y0 + 0.1 * P.CR, s.z0 - 0.1 * P.CR, 0.0, 0.0, s.omega)
        # the centred zero-speed start is refused (wrong speed): it used to spend the one warning
        assert inst.setup() == OK and inst.call("EnterInitializationMode") == OK
        assert inst.call("ExitInitializationMode") == OK
        warned, last = _excursions(inst, inside, outside)
        assert [w.split(":")[0] for w in warned] == ["t = 0.0001 s", "t = 0.0004 s", "t = 0.0005 s"], warned
        assert all("once per excursion" in w for w in warned)
        assert last[0] == WARNING and last[1] == (
            "terminate: the state left the surrogate's fitted domain 3 time(s) in this run (each excursion warned "
            "when it began; the first at t = 0.0001 s, the last at t = 0.0005 s)")
    finally:
        inst.close()


def _linear_at(fmu, unzip, **params) -> Instance:
    inst = Instance(fmu, unzip)
    for name, value in {"internal": "linear", "load_z": -1e7, **params}.items():
        assert inst.set(name, value) == OK
    assert inst.setup() == OK and inst.call("EnterInitializationMode") == OK
    assert inst.call("ExitInitializationMode") == ERROR
    assert not any("Traceback" in m or "\n" in m for _s, m in inst.messages), inst.messages
    return inst


def test_an_impossible_linear_load_on_the_map_is_one_line(fmu, unzip):
    inst = _linear_at(fmu, unzip, linear_from="map")
    try:
        assert "bearing FMU initialisation failed: eccentricity ratio" in inst.last()
    finally:
        inst.close()


@pytest.mark.slow
def test_an_impossible_linear_load_on_reynolds_is_one_line_without_a_traceback(fmu, unzip):
    """The issue's case: Reynolds' equilibrium fails (EquilibriumError, once logged with its traceback)."""
    inst = _linear_at(fmu, unzip, n_theta=16, n_x=2)
    try:
        assert ("bearing FMU initialisation failed: equilibrium: the bearing carries at most ~1.94 kN at 22 Hz at "
                "eccentricity 0.95; asked for 1e+07 N: no static equilibrium inside the clearance") in inst.last()
    finally:
        inst.close()
