"""The FMI 3.0 native FMU (bearing_fmu/fmu/native/fmi3.py, c/fmi3_*.c): the FMI 2.0 FMU's model
over FMI 3.0.

Expected values come from the FMI 2.0 native FMU of the same internal and data (built in the
same session: tests/test_native_fmu.py checks that one against the Python internals), from the
Python internals, from finite differences of the FMU's own outputs, and from the FMI 3.0.2
standard (ALLOWED3 is its calling sequence; fmpy's schemas and validation). Each FMU is built
once per session: map (through the command line), taylor (paper_22hz_16.7N), linear.
"""

import ctypes
import math
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

import fmpy  # noqa: E402
from fmpy.fmi2 import FMU2Model, FMU2Slave  # noqa: E402
from fmpy.fmi3 import (  # noqa: E402
    FMU3Model,
    FMU3Slave,
    fmi3ClockUpdateCallback,
    fmi3IntermediateUpdateCallback,
    fmi3LockPreemptionCallback,
    fmi3LogMessageCallback,
    fmi3UnlockPreemptionCallback,
)

from bearing_fmu.fmu.native.fmi3 import ALLOWED3, VR_TIME  # noqa: E402
from bearing_fmu.internals import registry  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING  # noqa: E402
from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")
KINDS = ("map", "taylor", "linear", "reynolds")
REYNOLDS_GRID = {"n_theta": 32, "n_x": 8}  # the native Reynolds FMU's start values: a small grid

pytestmark = [pytest.mark.slow,  # six FMI 3.0 and FMI 2.0 builds compiled and driven: end to end, in CI (the whole suite)
              pytest.mark.filterwarnings("ignore:state outside the surrogate's fitted domain")]


# ----------------------------------------------------------------------------- the FMUs

@pytest.fixture(scope="session")
def fmus(tmp_path_factory):
    """internal -> {"fmu2", "fmu3": (path, unzipped dir), "py": the Python internal, "params"}."""
    from bearing_fmu.cli import main
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder = tmp_path_factory.mktemp("fmi3")
    lin = {"linear_from": "map", "map": str(PAPER_MAP)}
    builds = {"map": ({"map": PAPER_MAP}, PAPER_BEARING,
                      registry.create("map", PAPER_BEARING, {"map": str(PAPER_MAP)})),
              "taylor": ({"surrogate": SURROGATE}, load_surrogate(SURROGATE).params,
                         registry.create("taylor", load_surrogate(SURROGATE).params, {"surrogate": str(SURROGATE)})),
              "linear": ({"options": lin}, PAPER_BEARING, registry.create("linear", PAPER_BEARING, lin)),
              "reynolds": ({"options": REYNOLDS_GRID}, PAPER_BEARING,
                           registry.create("reynolds", PAPER_BEARING, REYNOLDS_GRID))}
    out = {}
    for internal, (kw, params, py) in builds.items():
        paths = {}
        for version in (2, 3):
            path = folder / f"{internal}_fmi{version}.fmu"
            if internal == "map" and version == 3:  # the command line's --fmi 3
                assert main(["build", "--native", "--fmi", "3", "--map", str(PAPER_MAP), "--compiler", "cc",
                             "-o", str(path)]) == 0
            else:  # this machine's binary (the cross-compiled ones: test_native_platforms.py)
                build_native_fmu(path, internal, fmi_version=version, compiler="cc", **kw)
            paths[f"fmu{version}"] = (path, fmpy.extract(str(path)))
        out[internal] = {**paths, "py": py, "params": params}
    return out


class Raw3:
    """One FMI 3.0 instance through fmpy's ctypes functions, without its status checks: the exact
    fmi3Status of every call, and every log line (status, category, message)."""

    _C = {"Float64": ctypes.c_double, "Boolean": ctypes.c_bool, "Int64": ctypes.c_int64, "String": ctypes.c_char_p}

    def __init__(self, built, kind="CS", logging=True, name="fmi3"):
        path, unzip = built
        md = fmpy.read_model_description(str(path))
        self.vars = {v.name: v for v in md.modelVariables}
        self.messages = []
        cls = FMU3Slave if kind == "CS" else FMU3Model
        ident = (md.coSimulation or md.modelExchange).modelIdentifier
        self.fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName=name)
        self.fmu.instantiate(loggingOn=logging, logMessage=self._log)
        self.f = self.fmu._functions

    def _log(self, _env, status, category, message):
        self.messages.append((status, (category or b"").decode(), message.decode() if message else ""))

    def call(self, fname, *args) -> int:
        return self.f[fname](self.fmu.component, *args)

    def vrs(self, names):
        return (ctypes.c_uint * len(names))(*[self.vars[n].valueReference for n in names])

    def get(self, names, typ="Float64"):
        buf = (self._C[typ] * len(names))()
        status = self.call(f"fmi3Get{typ}", self.vrs(names), len(names), buf, len(names))
        return status, list(buf)

    def set(self, names, values, typ="Float64") -> int:
        values = [v.encode() if isinstance(v, str) else v for v in values]
        return self.call(f"fmi3Set{typ}", self.vrs(names), len(names), (self._C[typ] * len(names))(*values),
                         len(names))

    def enter(self, start=0.0, stop=None) -> int:
        return self.call("fmi3EnterInitializationMode", False, 0.0, start, stop is not None, stop or 0.0)

    def init(self) -> int:
        assert self.enter() == OK
        return self.call("fmi3ExitInitializationMode")

    def now(self) -> float:
        """The instance's time (the independent variable): where its last step ended."""
        status, (t,) = self.get(["time"])
        return t if status == OK else 0.0

    def step(self, t=None, h=1e-4):
        t = self.now() if t is None else t
        flags = [ctypes.c_bool() for _ in range(3)]
        last = ctypes.c_double()
        status = self.call("fmi3DoStep", t, h, True, *(ctypes.byref(b) for b in flags), ctypes.byref(last))
        return status, [b.value for b in flags], last.value

    def derivative(self, unknowns, knowns, seed, adjoint=False):
        n = len(knowns) if adjoint else len(unknowns)
        out = (ctypes.c_double * n)()
        name = "fmi3GetAdjointDerivative" if adjoint else "fmi3GetDirectionalDerivative"
        status = self.call(name, self.vrs(unknowns), len(unknowns), self.vrs(knowns), len(knowns),
                           (ctypes.c_double * len(seed))(*seed), len(seed), out, n)
        return status, np.array(out[:])

    def last(self, status=None) -> str:
        msgs = [m for s, _c, m in self.messages if status is None or s == status]
        return msgs[-1] if msgs else ""

    def close(self):
        self.fmu.freeInstance()


def open2(built, kind="CS"):
    """The FMI 2.0 FMU initialised through fmpy (Model Exchange: in Continuous-Time Mode)."""
    path, unzip = built
    md = fmpy.read_model_description(str(path))
    cls = FMU2Slave if kind == "CS" else FMU2Model
    fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="fmi2")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    if kind == "ME":
        fmu.enterContinuousTimeMode()
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def states(internal, py, params, n=12, seed=0):
    """Journal states (y, z, vy, vz, omega) where the internal evaluates: the map anywhere to eps
    0.9 at any speed and velocity; the surrogate at its training states, moved across its domain's
    edge; the linear model about its point at its speed."""
    rng = np.random.default_rng(seed)
    if internal in ("map", "reynolds"):
        out = []
        for _ in range(n):
            e, a, w = rng.uniform(0, 0.9), rng.uniform(-math.pi, math.pi), rng.uniform(20, 400)
            v = rng.normal(0, 0.3, 2) * w * params.CR
            out.append((e * params.CR * math.cos(a), e * params.CR * math.sin(a), v[0], v[1], w))
        return out
    if internal == "taylor":
        s = py.taylor.surrogate
        pts = s.neighbours.points[rng.choice(len(s.neighbours.points), n)] + rng.normal(0, 0.02, (n, 4))
        return [(s.y0 + p[0] * s.pos_scale, s.z0 + p[1] * s.pos_scale, p[2] * s.vel_scale, p[3] * s.vel_scale,
                 s.omega) for p in pts]
    q = rng.normal(0, 0.2, (n, 4))
    return [(py.y0 + p[0] * params.CR, py.z0 + p[1] * params.CR, p[2] * 0.01, p[3] * 0.01, py.omega0) for p in q]


# ----------------------------------------------------------------------------- the FMU files

def test_fmpy_validates_each_fmi3_fmu(fmus):
    from fmpy.validation import validate_fmu

    for internal, f in fmus.items():
        assert validate_fmu(str(f["fmu3"][0])) == [], internal  # modelDescription.xml and buildDescription.xml


def test_archive_binary_and_instantiation_token(fmus):
    path, unzip = fmus["taylor"]["fmu3"]
    md = fmpy.read_model_description(str(path))
    ident = md.coSimulation.modelIdentifier
    names = zipfile.ZipFile(path).namelist()
    for f in ("sources/buildDescription.xml", "sources/fmi3_bearing.c", "sources/fmi3_config.h",
              "sources/internal_taylor.c", "sources/model_data.h", "documentation/index.html",
              f"binaries/x86_64-linux/{ident}.so", "resources/build_info.json"):
        assert f in names
    assert not any(n.startswith("binaries/linux64") for n in names)
    assert md.fmiVersion == "3.0" and md.modelExchange.modelIdentifier == ident
    xml = zipfile.ZipFile(path).read("modelDescription.xml").decode()
    for flag in ("canGetAndSetFMUState", "canSerializeFMUState", "providesDirectionalDerivatives",
                 "providesAdjointDerivatives", "providesPerElementDependencies"):
        assert xml.count(f'{flag}="true"') == 2, flag  # both interfaces
    assert 'needsCompletedIntegratorStep="true"' in xml  # out_of_domain's step events (a fitted domain)
    assert 'needsCompletedIntegratorStep="false"' in zipfile.ZipFile(fmus["map"]["fmu3"][0]).read(
        "modelDescription.xml").decode()
    config = Path(unzip, "sources", "fmi3_config.h").read_text()
    assert f'#define BN3_TOKEN "{md.guid}"' in config
    assert len({fmpy.read_model_description(str(f["fmu3"][0])).guid for f in fmus.values()}) == len(fmus)
    build = fmpy.read_model_description(str(path)).buildConfigurations[0]
    assert build.sourceFileSets[0].language == "C99"
    assert [(d.name, d.value) for d in build.sourceFileSets[0].preprocessorDefinitions] == [("BN_FMI_VERSION", "3")]
    page = Path(unzip, "documentation", "index.html").read_text()
    assert "FMI 3.0, instantiation token" in page and "fmi3GetAdjointDerivative" in page
    assert all(f"<tr><td>{v.name}</td>" in page for v in md.modelVariables)


def test_binary_exports_the_fmi3_functions_only(fmus):
    """Every function of fmi3Functions.h (an importer may look up any), nothing else; it needs the
    C library and libm only (no Python at run time)."""
    assert shutil.which("nm") and shutil.which("readelf"), "binutils (nm, readelf): .ci/run installs them"
    header = (Path(fmpy.__file__).parent / "c-code" / "fmi3Functions.h").read_text()
    want = set(re.findall(r"FMI3_Export fmi3\w+TYPE\s+(fmi3\w+);", header))
    unzip = fmus["map"]["fmu3"][1]
    so = next(Path(unzip, "binaries", "x86_64-linux").glob("*.so"))
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True, check=True).stdout
    have = {line.split()[-1] for line in out.splitlines() if line.strip()}
    assert len(want) == 75 and have == want
    dynamic = subprocess.run(["readelf", "-d", str(so)], capture_output=True, text=True, check=True).stdout
    assert set(re.findall(r"\(NEEDED\)\s+Shared library: \[(.+?)\]", dynamic)) <= {"libc.so.6", "libm.so.6"}


def test_same_variables_as_the_fmi2_fmu(fmus):
    """The FMI 2.0 FMU's variables with their value references, causality, variability, start,
    units, display units and bounds; Real as Float64; the independent variable time; the outputs'
    dependencies as fmi3GetVariableDependencies gives them."""
    types = {"Real": "Float64", "Boolean": "Boolean", "String": "String", "Enumeration": "Enumeration",
             "Integer": "Int64"}
    for internal, f in fmus.items():
        v2 = {v.name: v for v in fmpy.read_model_description(str(f["fmu2"][0])).modelVariables}
        md3 = fmpy.read_model_description(str(f["fmu3"][0]))
        v3 = {v.name: v for v in md3.modelVariables}
        time = v3.pop("time")
        assert (time.causality, time.variability, time.valueReference, time.start) == ("independent", "continuous",
                                                                                       VR_TIME, None)
        assert set(v3) == set(v2), internal
        for name, a in v2.items():
            b = v3[name]
            assert b.type == types[a.type], (internal, name)
            assert (b.valueReference, b.causality, b.variability, b.unit, b.displayUnit, b.min, b.max, b.nominal) == \
                   (a.valueReference, a.causality, a.variability, a.unit, a.displayUnit, a.min, a.max, a.nominal), name
            assert str(b.start) == str(a.start) if a.causality != "output" else b.start is None, (internal, name)
            if a.type == "Enumeration":
                assert [(i.name, i.value) for i in b.declaredType.items] == \
                       [(i.name, i.value) for i in a.declaredType.items]
        assert {u.name: [d.name for d in u.displayUnits] for u in md3.unitDefinitions} == \
               {u.name: [d.name for d in u.displayUnits]
                for u in fmpy.read_model_description(str(f["fmu2"][0])).unitDefinitions}
        # the model description's (fmi3.output_dependencies) and the binary's (fmi3_modes.c) agree
        outputs = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md3.outputs}
        assert set(outputs) == {n for n, v in v2.items() if v.causality == "output"}
        assert outputs["Fy"] == sorted(IN) and outputs["h_min"] == ["y", "z"]
        assert outputs["out_of_domain"] == (["vy", "vz", "y", "z"] if internal == "taylor" else [])
        # the peak pressure: the Reynolds internal's field, as its force; none (always 0) without a field
        assert outputs["peak_pressure"] == outputs["peak_pressure_angle"] == (sorted(IN) if internal == "reynolds"
                                                                              else [])
        raw = Raw3(f["fmu3"])
        try:
            for name, deps in outputs.items():
                n = ctypes.c_size_t()
                assert raw.call("fmi3GetNumberOfVariableDependencies", v3[name].valueReference, ctypes.byref(n)) == OK
                idx = (ctypes.c_size_t * n.value)()
                ind = (ctypes.c_uint * n.value)()
                kinds = (ctypes.c_int * n.value)()
                assert raw.call("fmi3GetVariableDependencies", v3[name].valueReference, idx,
                                ind, (ctypes.c_size_t * n.value)(), kinds, n.value) == OK
                assert sorted(next(k for k, v in v3.items() if v.valueReference == r) for r in ind) == deps, name
                assert set(kinds) <= {5}  # fmi3Dependent
        finally:
            raw.close()


# ----------------------------------------------------------------------------- equal to FMI 2.0

@pytest.mark.parametrize("internal", KINDS)
def test_forces_equal_the_fmi2_fmus_bit_for_bit(fmus, internal):
    """Co-Simulation and Model Exchange, every Float64 output and out_of_domain, at the same inputs."""
    f = fmus[internal]
    sts = states(internal, f["py"], f["params"])
    for kind in ("CS", "ME"):
        fmu2, vr = open2(f["fmu2"], kind)
        raw = Raw3(f["fmu3"], kind)
        try:
            assert raw.init() == OK
            if kind == "ME":
                assert raw.call("fmi3EnterContinuousTimeMode") == OK
            for k, st in enumerate(sts):
                fmu2.setReal([vr[n] for n in IN], list(st))
                assert raw.set(IN, st) == OK
                if kind == "CS":
                    fmu2.doStep(1e-4 * k, 1e-4)
                    assert raw.step(1e-4 * k)[0] == OK, raw.last()
                want = fmu2.getReal([vr[n] for n in OUT])
                status, got = raw.get(OUT)
                assert status == OK
                assert got == want, (internal, kind, st)  # the same bits
                if kind == "CS":  # in ME out_of_domain changes at events only (test below)
                    assert raw.get(["out_of_domain"], "Boolean")[1] == [bool(fmu2.getBoolean([vr["out_of_domain"]])[0])]
        finally:
            fmu2.terminate()
            fmu2.freeInstance()
            raw.close()


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
@pytest.mark.parametrize("internal", KINDS)
def test_fmpy_simulates_it_like_the_fmi2_fmu(fmus, internal, fmi_type):
    f = fmus[internal]
    a, b = states(internal, f["py"], f["params"], n=2, seed=4)
    table = np.array([(0.0, *a), (0.005, *a), (0.005, *b), (0.01, *b)],
                     dtype=[("time", float)] + [(n, float) for n in IN])
    res = {v: fmpy.simulate_fmu(str(f[f"fmu{v}"][0]), fmi_type=fmi_type, stop_time=0.01, output_interval=1e-3,
                                input=table, output=["Fy", "Fz", "Kyy", "Czz"]) for v in (2, 3)}
    assert len(res[3]) == len(res[2]) >= 11  # Model Exchange records the input's step at 5 ms as an event
    for name in ("time", "Fy", "Fz", "Kyy", "Czz"):
        assert np.array_equal(res[3][name], res[2][name]), name
    want = np.array(f["py"].force(*a))
    assert np.allclose([res[3]["Fy"][2], res[3]["Fz"][2]], want, rtol=1e-12, atol=1e-12 * np.max(np.abs(want)))


# ----------------------------------------------------------------------------- derivatives

def _scale(params, st):
    w = max(abs(st[4]), 1.0)
    return np.array([params.CR, params.CR, params.CR * w, params.CR * w, w])


@pytest.mark.parametrize("internal", KINDS)
def test_directional_and_adjoint_derivatives(fmus, internal):
    """Fy, Fz along each input: the FMI 2.0 FMU's directional derivative (the same bits) and the K, C
    outputs; eccentricity, h_min: analytic; K.., C..: finite differences of the FMU's own K, C
    outputs (another step); the adjoint derivatives: the rows of the same Jacobian."""
    f = fmus[internal]
    params = f["params"]
    fmu2, vr = open2(f["fmu2"], "ME")
    raw = Raw3(f["fmu3"], "ME")
    try:
        assert raw.init() == OK and raw.call("fmi3EnterContinuousTimeMode") == OK
        for st in states(internal, f["py"], params, n=3, seed=7):
            raw.set(IN, st)
            fmu2.setReal([vr[n] for n in IN], list(st))
            out = np.array(raw.get(OUT)[1])
            cols = []
            for j, name in enumerate(IN):
                status, d = raw.derivative(OUT, [name], [1.0])
                assert status == OK, raw.last()
                cols.append(d)
                d2 = fmu2.getDirectionalDerivative([vr["Fy"], vr["Fz"]], [vr[name]], [1.0])
                assert list(d[:2]) == d2, (internal, name)
                if j < 4:  # K = -dF/dq, C = -dF/dv: the outputs' bits
                    k = {0: (4, 6), 1: (5, 7), 2: (8, 10), 3: (9, 11)}[j]
                    assert list(d[:2]) == [-out[k[0]], -out[k[1]]]
                e = math.hypot(st[0], st[1])
                decc = st[j] / (e * params.CR) if j < 2 else 0.0
                assert d[2] == pytest.approx(decc, rel=1e-14) and d[3] == pytest.approx(-params.CR * decc, rel=1e-14)
            J = np.array(cols).T  # (12 outputs, 5 inputs)
            # K, C along each input: central differences of the K, C outputs, a step 30 times the FMU's
            h = 3e-5 * _scale(params, st)
            for j in range(5):
                if internal not in ("map", "reynolds") and j == 4:
                    assert np.all(J[4:, 4] == 0.0)  # a model of one speed: its K, C do not move with it
                    continue
                plus, minus = list(st), list(st)
                plus[j] += h[j]
                minus[j] -= h[j]
                raw.set(IN, plus)
                kp = np.array(raw.get(OUT)[1][4:])
                raw.set(IN, minus)
                km = np.array(raw.get(OUT)[1][4:])
                fd = (kp - km) / (2 * h[j])
                size = np.max(np.abs(J[4:, :4] * _scale(params, st)[:4])) / _scale(params, st)[j]
                assert np.allclose(J[4:, j], fd, rtol=0, atol=1e-5 * size + 1e-300), (internal, IN[j], J[4:, j], fd)
            raw.set(IN, st)
            if internal == "linear":
                assert np.all(J[4:] == 0.0)
            # adjoint: a unit seed gives a row, bit for bit; any seed w gives w^T J
            for i in range(len(OUT)):
                status, row = raw.derivative([OUT[i]], IN, [1.0], adjoint=True)
                assert status == OK and np.array_equal(row, J[i]), OUT[i]
            w = np.linspace(-1.0, 2.0, len(OUT))
            status, wj = raw.derivative(OUT, IN, w, adjoint=True)
            assert status == OK and np.allclose(wj, w @ J, rtol=1e-12, atol=1e-12 * np.max(np.abs(w @ J)))
            # directional along a combined seed: J v
            v = np.array([0.3, -0.2, 0.5, 0.1, 0.0 if internal != "map" else 0.7])
            status, jv = raw.derivative(["Fy", "Fz", "eccentricity"], list(IN), v)
            assert status == OK and np.allclose(jv, J[:3] @ v, rtol=1e-12, atol=1e-9 * np.max(np.abs(J[:3] @ v)))
        # refused: a parameter as known after initialisation, a Boolean as unknown, seed and sensitivity sizes
        assert raw.derivative(["Fy"], ["D"], [1.0])[0] == ERROR and "known D" in raw.last()
        assert "in Initialization Mode only" in raw.last()
        assert raw.derivative(["Fy"], ["time"], [1.0])[0] == ERROR and "no output depends on time" in raw.last()
        assert raw.derivative(["out_of_domain"], ["y"], [1.0])[0] == ERROR and "not a Float64 output" in raw.last()
        out = (ctypes.c_double * 1)()
        assert raw.call("fmi3GetDirectionalDerivative", raw.vrs(["Fy"]), 1, raw.vrs(["y", "z"]), 2,
                        (ctypes.c_double * 1)(1.0), 1, out, 1) == ERROR and "nSeed = 1" in raw.last()
        assert raw.derivative(["Fy"], ["y"], [float("nan")])[0] == ERROR and "seed[0]" in raw.last()
    finally:
        fmu2.terminate()
        fmu2.freeInstance()
        raw.close()


def test_derivatives_in_initialization_mode_and_without_the_tangent(fmus):
    f = fmus["map"]
    st = states("map", f["py"], f["params"], n=1, seed=11)[0]
    raw = Raw3(f["fmu3"])
    try:
        assert raw.set(["compute_tangent"], [False], "Boolean") == OK
        assert raw.derivative(["Fy"], ["y"], [1.0])[0] == ERROR and "Instantiated" in raw.last()
        assert raw.enter() == OK and raw.set(IN, st) == OK
        status, d = raw.derivative(["Fy", "Kyy"], ["y"], [1.0])
        _f, dq, _dv = f["py"].force_and_jacobian(*st)
        assert status == OK and d[0] == dq[0][0] and d[1] == 0.0  # K is 0 without the tangent: so is its derivative
    finally:
        raw.close()


# the Float64 parameters whose derivatives are checked against differences of the outputs: the
# map's bearing moves only with its L/D (LD_RTOL 1e-9: D alone is refused), so D and L go
# together; a surrogate refuses any bearing but its own (its CR: analytic, below)
PARAMETER_DIRECTIONS = {"map": (("D", "L"), ("CR",), ("mu",)),
                        "taylor": (("domain_limit",),),
                        "linear": (("lin_Kyy",), ("lin_Czy",), ("lin_y0",), ("lin_Fz0",), ("CR",), ("D", "L")),
                        # Reynolds: any bearing; D or L alone changes L/D (bn_shape_derivative)
                        "reynolds": (("D",), ("L",), ("D", "L"), ("CR",), ("mu",))}


@pytest.mark.parametrize("internal", KINDS)
def test_parameter_derivatives_in_initialization_mode(fmus, internal):
    """Directional and adjoint derivatives along the Float64 parameters in Initialization Mode
    (their InitialUnknown dependencies), against central differences of the FMU's own outputs
    computed in Initialization Mode at the parameters moved by +-1e-6 of their values: the map's
    D, L, CR, mu (F = S P(q/CR, v/CR, omega), S = mu L D^3 / 8 CR^2: D alone is 3 F / D), the
    Taylor model's (its bearing compiled in: 0 for the force; eccentricity and h_min follow CR),
    the linear model's coefficients. The same bits as the FMI 2.0 FMU's; an adjoint's unit seed
    gives the directional derivative's bits. After initialisation a parameter is no known."""
    f = fmus[internal]
    st = states(internal, f["py"], f["params"], n=1, seed=13)[0]
    raw = Raw3(f["fmu3"])
    md2 = fmpy.read_model_description(str(f["fmu2"][0]))
    fmu2 = FMU2Slave(guid=md2.guid, unzipDirectory=f["fmu2"][1], modelIdentifier=md2.coSimulation.modelIdentifier,
                     instanceName="fmi2")
    vr2 = {v.name: v.valueReference for v in md2.modelVariables}
    try:
        fmu2.instantiate()
        fmu2.setupExperiment(startTime=0.0)
        fmu2.enterInitializationMode()
        fmu2.setReal([vr2[n] for n in IN], list(st))
        assert raw.enter() == OK and raw.set(IN, st) == OK
        start = {k: float(v.start) for k, v in raw.vars.items() if v.causality == "parameter" and v.type == "Float64"}

        def outputs_at(values):
            assert raw.set(list(values), list(values.values())) == OK, raw.last()
            status, out = raw.get(OUT)
            assert status == OK, raw.last()
            return np.array(out)

        base = outputs_at(start)
        for names in PARAMETER_DIRECTIONS[internal]:
            seed = [start[n] for n in names]  # d/ds of the outputs at p (1 + s)
            status, got = raw.derivative(OUT, list(names), seed)
            assert status == OK, raw.last()
            h = 1e-6
            up = outputs_at({**start, **{n: start[n] * (1 + h) for n in names}})
            down = outputs_at({**start, **{n: start[n] * (1 - h) for n in names}})
            outputs_at(start)
            want = (up - down) / (2 * h)
            assert np.allclose(got, want, rtol=1e-5, atol=1e-6 * np.abs(want).max() + 1e-300), (names, got, want)
            assert got.tolist() == fmu2.getDirectionalDerivative([vr2[n] for n in OUT], [vr2[n] for n in names], seed)
            # the adjoint's unit seeds: the bits of the directional derivatives along each known alone
            unit = np.array([raw.derivative(OUT, [n], [1.0])[1] for n in names]).T  # (outputs, knowns)
            for i, name in enumerate(OUT):
                status, row = raw.derivative([name], list(names), [1.0], adjoint=True)
                assert status == OK and np.array_equal(row, unit[i]), (name, row, unit[i])
            assert np.allclose(unit @ np.array(seed), got, rtol=1e-12, atol=1e-12 * np.abs(got).max() + 1e-300)
        if internal == "map":
            status, got = raw.derivative(["Fy", "Fz", "Kyy"], ["D"], [1.0])
            assert status == OK and np.allclose(got, 3 * base[[0, 1, 4]] / start["D"], rtol=1e-14)
        if internal == "taylor":
            status, got = raw.derivative(["Fy", "Fz", "Kyy", "eccentricity", "h_min"], ["CR"], [1.0])
            assert status == OK and np.array_equal(got[:3], np.zeros(3))
            assert got[3] == pytest.approx(-base[2] / start["CR"], rel=1e-14) and got[4] == pytest.approx(1.0, rel=1e-14)
        assert raw.call("fmi3ExitInitializationMode") == OK
        assert raw.derivative(["Fy"], ["mu"], [1.0])[0] == ERROR and "Initialization Mode only" in raw.last()
        assert raw.derivative(["Fy"], ["mu"], [1.0], adjoint=True)[0] == ERROR
    finally:
        fmu2.freeInstance()
        raw.close()


# ----------------------------------------------------------------------------- FMU state

def test_fmu_state_get_set_serialize(fmus):
    f = fmus["map"]
    a, b = states("map", f["py"], f["params"], n=2, seed=3)
    raw = Raw3(f["fmu3"])
    try:
        assert raw.init() == OK
        raw.set(IN, a)
        assert raw.step(0.0)[0] == OK
        at_a = raw.get(OUT)[1]
        state = ctypes.c_void_p()
        assert raw.call("fmi3GetFMUState", ctypes.byref(state)) == OK and state.value
        raw.set(IN, b)
        assert raw.step(1e-4)[0] == OK and raw.get(OUT)[1] != at_a
        assert raw.call("fmi3SetFMUState", state) == OK
        assert raw.get(OUT)[1] == at_a and raw.get(["time"])[1] == [1e-4]  # outputs and time of the state
        size = ctypes.c_size_t()
        # the serialised state holds the pads' block too (12 pads at most): about 1.4 kB
        assert raw.call("fmi3SerializedFMUStateSize", state, ctypes.byref(size)) == OK and 0 < size.value < 2000
        buf = (ctypes.c_uint8 * size.value)()
        assert raw.call("fmi3SerializeFMUState", state, buf, size.value) == OK
        copy = ctypes.c_void_p()
        assert raw.call("fmi3DeserializeFMUState", buf, size.value, ctypes.byref(copy)) == OK
        raw.set(IN, b)
        assert raw.step(1e-4)[0] == OK
        assert raw.call("fmi3SetFMUState", copy) == OK and raw.get(OUT)[1] == at_a
        bad = (ctypes.c_uint8 * size.value)(*bytes(size.value))
        assert raw.call("fmi3DeserializeFMUState", bad, size.value, ctypes.byref(copy)) == ERROR
        assert "not a serialised" in raw.last()
        for s in (state, copy):
            assert raw.call("fmi3FreeFMUState", ctypes.byref(s)) == OK and s.value is None
        assert raw.call("fmi3SetFMUState", state) == ERROR and "not a bearing-native3/1 state" in raw.last()
    finally:
        raw.close()


def test_a_state_of_another_build_is_refused(fmus):
    one, other = Raw3(fmus["map"]["fmu3"]), Raw3(fmus["linear"]["fmu3"])
    try:
        state = ctypes.c_void_p()
        assert one.call("fmi3GetFMUState", ctypes.byref(state)) == OK
        assert other.call("fmi3SetFMUState", state) == ERROR and "not a bearing-native3/1 state" in other.last()
        assert one.call("fmi3FreeFMUState", ctypes.byref(state)) == OK
    finally:
        one.close()
        other.close()


# ----------------------------------------------------------------------------- calling sequence

_MODES = {"ME": ("Instantiated", "Initialization Mode", "Event Mode", "Continuous-Time Mode", "Terminated"),
          "CS": ("Instantiated", "Initialization Mode", "Step Mode", "Terminated")}
_CALLS = ("ExitInitializationMode", "EnterEventMode", "Terminate", "EnterContinuousTimeMode", "EnterStepMode",
          "EvaluateDiscreteStates", "EnterInitializationMode", "Reset")


def _drive(raw, kind, mode):
    """Bring a fresh instance to ``mode`` by allowed calls only."""
    if mode == "Instantiated":
        return
    assert raw.enter() == OK
    if mode == "Initialization Mode":
        return
    assert raw.call("fmi3ExitInitializationMode") == OK
    if mode == "Continuous-Time Mode":
        assert raw.call("fmi3EnterContinuousTimeMode") == OK
    if mode == "Terminated":
        assert raw.call("fmi3Terminate") == OK


@pytest.mark.parametrize("kind", ["ME", "CS"])
def test_calling_sequence_is_the_fmi3_state_machine(fmus, kind):
    """Each mode-changing call in each mode: fmi3OK where ALLOWED3 (the FMI 3.0.2 state machine)
    allows it for this interface, else fmi3Error naming the call and the mode, nothing changed."""
    me_only = {"EnterEventMode", "EnterContinuousTimeMode", "EvaluateDiscreteStates"}
    # fmi3EnterStepMode: never (a Co-Simulation function, and Co-Simulation here has no Event Mode)
    for mode in _MODES[kind]:
        for call in _CALLS:
            raw = Raw3(fmus["map"]["fmu3"], kind)
            try:
                _drive(raw, kind, mode)
                args = (False, 0.0, 0.0, False, 0.0) if call == "EnterInitializationMode" else ()
                allowed = mode in ALLOWED3[call] and not (kind == "CS" and call in me_only) and call != "EnterStepMode"
                status = raw.call(f"fmi3{call}", *args)
                assert status == (OK if allowed else ERROR), (kind, mode, call, raw.last())
                if not allowed:
                    assert raw.last(ERROR).startswith(f"fmi3{call} in {mode}"), raw.last()
                    # nothing changed: what the mode allows still works
                    if mode == "Instantiated":
                        assert raw.enter() == OK
                    elif mode == "Initialization Mode":
                        assert raw.call("fmi3ExitInitializationMode") == OK
            finally:
                raw.close()


def test_refused_calls_name_the_call_and_what_to_do(fmus):
    me, cs = Raw3(fmus["map"]["fmu3"], "ME"), Raw3(fmus["map"]["fmu3"], "CS")
    try:
        assert cs.step()[0] == ERROR
        assert "fmi3DoStep in Instantiated: not allowed there (FMI 3.0: in Step Mode only); initialise it" in cs.last()
        assert cs.get(["Fy"])[0] == ERROR and "initial = calculated" in cs.last()
        assert cs.get(["y", "D", "time"]) == (OK, [0.0, PAPER_BEARING.D, 0.0])  # start values
        assert cs.call("fmi3Terminate") == ERROR and "nothing to terminate" in cs.last()
        assert cs.init() == OK
        assert cs.call("fmi3SetTime", 0.1) == ERROR and "a Model Exchange function" in cs.last()
        assert cs.call("fmi3EnterEventMode") == ERROR and "hasEventMode is false" in cs.last()
        assert cs.call("fmi3EnterStepMode") == ERROR and "no Event Mode in Co-Simulation" in cs.last()
        assert cs.set(["D"], [0.03]) == ERROR and "parameter D is fixed after initialisation" in cs.last()
        assert cs.set(["Fy"], [1.0]) == ERROR and "Fy is an output" in cs.last()
        assert cs.set(["time"], [1.0]) == ERROR and "independent variable" in cs.last()
        assert cs.call("fmi3GetInt32", cs.vrs(["D"]), 1, (ctypes.c_int32 * 1)(), 1) == ERROR
        assert "not an Int32 variable" in cs.last() and "fmi3GetInt64" in cs.last()
        assert cs.call("fmi3GetFloat32", cs.vrs([]), 0, (ctypes.c_float * 1)(), 0) == OK  # nothing asked
        assert cs.call("fmi3EnterConfigurationMode") == ERROR and "no structural parameters" in cs.last()
        assert cs.call("fmi3GetOutputDerivatives", cs.vrs(["Fy"]), 1, (ctypes.c_int32 * 1)(1),
                       (ctypes.c_double * 1)(), 1) == ERROR and "maxOutputDerivativeOrder is 0" in cs.last()
        assert cs.step(0.0, 0.0)[0] == ERROR and "communicationStepSize = 0 s" in cs.last()
        assert cs.step(0.0)[0] == OK  # usable after every refusal
        assert me.init() == OK
        assert me.step()[0] == ERROR and "a Co-Simulation function; this instance is a Model Exchange one" in me.last()
        assert me.call("fmi3CompletedIntegratorStep", True, ctypes.byref(ctypes.c_bool()),
                       ctypes.byref(ctypes.c_bool())) == ERROR
        assert "call fmi3EnterContinuousTimeMode first" in me.last()
        assert me.call("fmi3SetTime", 1e-3) == ERROR and "not allowed there" in me.last()
        assert me.call("fmi3EnterContinuousTimeMode") == OK and me.call("fmi3SetTime", 1e-3) == OK
        assert me.set(["compute_tangent"], [False], "Boolean") == ERROR  # Continuous-Time Mode: continuous inputs only
        n = ctypes.c_size_t(7)
        assert me.call("fmi3GetNumberOfContinuousStates", ctypes.byref(n)) == OK and n.value == 0
        assert me.call("fmi3GetContinuousStates", (ctypes.c_double * 1)(), 1) == ERROR
    finally:
        me.close()
        cs.close()


def test_stop_time_is_kept_in_co_simulation(fmus):
    raw = Raw3(fmus["map"]["fmu3"])
    try:
        assert raw.enter(0.0, 1e-3) == OK and raw.call("fmi3ExitInitializationMode") == OK
        assert raw.step(0.0, 1e-3)[0] == OK
        assert raw.step(1e-3, 1e-4)[0] == ERROR and "beyond the stopTime" in raw.last()
    finally:
        raw.close()


# ----------------------------------------------------------------------------- statuses

def test_a_refused_state_discards_and_the_instance_goes_on(fmus):
    """fmi3Discard with the instance as before the step (outputs, time) and terminateSimulation
    false: the importer may restore a state, or set other inputs, and step again."""
    f = fmus["map"]
    good = states("map", f["py"], f["params"], n=1, seed=5)[0]
    raw = Raw3(f["fmu3"])
    try:
        assert raw.init() == OK
        raw.set(IN, good)
        assert raw.step(0.0) == (OK, [False, False, False], 1e-4)
        before = raw.get(OUT)[1]
        raw.set(IN, (1.2 * PAPER_BEARING.CR, 0.0, 0.0, 0.0, 100.0))  # beyond the wall
        status, (event, terminate, early), last = raw.step(1e-4)
        assert (status, event, terminate, early, last) == (DISCARD, False, False, False, 1e-4)
        assert "eccentricity ratio 1.2 >= " in raw.last(DISCARD)
        assert raw.get(OUT)[1] == before and raw.get(["time"])[1] == [1e-4]
        raw.set(IN, good)
        assert raw.step(1e-4)[0] == OK and raw.get(["time"])[1] == [2e-4]
    finally:
        raw.close()


def test_out_of_domain_changes_at_events_only_in_model_exchange(fmus):
    """A discrete output: in Continuous-Time Mode it keeps its value of the last event, and
    fmi3CompletedIntegratorStep asks for an event where the state crossed the domain's edge; in
    Event Mode it takes the new value. The force follows the state all along."""
    f = fmus["taylor"]
    s = f["py"].taylor.surrogate
    raw = Raw3(f["fmu3"], "ME")
    try:
        assert raw.init() == OK and raw.call("fmi3EnterContinuousTimeMode") == OK
        crossed = False
        for k in range(1, 40):
            st = (s.y0 + 0.02 * k * s.pos_scale, s.z0, 0.0, 0.0, s.omega)
            assert raw.call("fmi3SetTime", ctypes.c_double(1e-3 * k)) == OK and raw.set(IN, st) == OK
            status, (fy,) = raw.get(["Fy"])
            assert status == OK and fy == pytest.approx(f["py"].force(*st)[0], rel=1e-9)
            assert raw.get(["out_of_domain"], "Boolean") == (OK, [False])
            event, terminate = ctypes.c_bool(), ctypes.c_bool()
            assert raw.call("fmi3CompletedIntegratorStep", True, ctypes.byref(event), ctypes.byref(terminate)) == OK
            assert not terminate.value
            if event.value:
                crossed = True
                break
        assert crossed and f["py"].domain_distance(*st[:4]) > 0  # outside, by the Python guard too
        assert raw.call("fmi3EnterEventMode") == OK
        assert raw.get(["out_of_domain"], "Boolean") == (OK, [True])
        flags = [ctypes.c_bool(True) for _ in range(5)]
        assert raw.call("fmi3UpdateDiscreteStates", *(ctypes.byref(b) for b in flags),
                        ctypes.byref(ctypes.c_double())) == OK and not any(b.value for b in flags)
        assert raw.call("fmi3EnterContinuousTimeMode") == OK
        assert raw.get(["out_of_domain"], "Boolean") == (OK, [True])
        assert len([m for st_, _c, m in raw.messages if st_ == WARNING]) == 1  # warned once, when the excursion began
    finally:
        raw.close()


def test_errors_reach_the_logger_even_with_logging_off(fmus, capfd):
    """FMI 3.0: an error is always given to the logger; a warning or discard only when its category
    is on (the first of each printed to stderr when logging is off)."""
    f = fmus["map"]
    raw = Raw3(f["fmu3"], logging=False, name="quiet")
    try:
        assert raw.set(["D"], [-1.0]) == ERROR
        said = "fmi3SetFloat64: D = -1 m must be finite and > 0; D keeps 0.031"
        assert raw.messages == [(ERROR, "logStatusError", said)]
        assert raw.set(["D"], [PAPER_BEARING.D]) == OK
        raw.set(IN, (2 * PAPER_BEARING.CR, 0.0, 0.0, 0.0, 100.0))
        assert raw.init() == WARNING  # outputs left at their start values: a warning (as FMI 2.0's), not logged
        assert len(raw.messages) == 1
        assert "bearing FMU 'quiet' [warning]: outputs at the start time left" in capfd.readouterr().err
        cats = (ctypes.c_char_p * 1)(b"logStatusDiscard")
        assert raw.call("fmi3SetDebugLogging", True, 1, cats) == OK
        assert raw.step()[0] == DISCARD and raw.messages[-1][:2] == (DISCARD, "logStatusDiscard")
        raw.set(IN, states("map", f["py"], f["params"], n=1)[0])
        assert raw.step()[0] == OK
        assert raw.call("fmi3Terminate") == OK and len(raw.messages) == 2  # no warning category: not logged
        bad = (ctypes.c_char_p * 1)(b"logEverything")
        assert raw.call("fmi3SetDebugLogging", True, 1, bad) == ERROR and "unknown log category" in raw.last()
    finally:
        raw.close()


def test_instantiation_refusals(fmus):
    path, unzip = fmus["map"]["fmu3"]
    md = fmpy.read_model_description(str(path))
    seen = []
    log = fmi3LogMessageCallback(lambda _e, status, _c, msg: seen.append((status, msg.decode())))
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="x")
    f = fmu._functions
    none = (ctypes.c_uint * 0)()
    args = (b"x", md.guid.encode(), b"", False, True)
    no_update = fmi3IntermediateUpdateCallback()
    assert not f["fmi3InstantiateCoSimulation"](*args, True, False, none, 0, None, log, no_update)
    assert "eventModeUsed is true" in seen[-1][1] and seen[-1][0] == ERROR
    assert not f["fmi3InstantiateModelExchange"](b"x", b"{another build}", b"", False, True, None, log)
    assert "instantiationToken given is not this FMU's" in seen[-1][1]
    assert not f["fmi3InstantiateScheduledExecution"](b"x", md.guid.encode(), b"", False, True, None, log,
                                                       fmi3ClockUpdateCallback(), fmi3LockPreemptionCallback(),
                                                       fmi3UnlockPreemptionCallback())
    assert "no Scheduled Execution" in seen[-1][1]
    inst = f["fmi3InstantiateCoSimulation"](*args, False, True, none, 0, None, log, no_update)
    assert inst
    f["fmi3FreeInstance"](inst)
    fmu.freeLibrary()


def test_enumerations_and_strings_choose_as_in_fmi2(fmus):
    raw = Raw3(fmus["taylor"]["fmu3"])
    try:
        assert raw.get(["internal_enum", "domain_action_enum"], "Int64") == (OK, [3, 1])
        assert raw.set(["internal_enum"], [4], "Int64") == ERROR and "internal = 'map'" in raw.last()
        assert raw.set(["domain_action_enum"], [3], "Int64") == OK  # discard
        assert raw.init() == ERROR and "refused when it was set" in raw.last()  # until a valid one is set
        assert raw.set(["internal_enum"], [3], "Int64") == OK and raw.call("fmi3ExitInitializationMode") == OK
        assert raw.get(["domain_action"], "String") == (OK, [b"discard"])
        assert raw.set(["domain_action"], ["warn"], "String") == ERROR and "fixed after initialisation" in raw.last()
    finally:
        raw.close()


# ----------------------------------------------------------------------------- builds

def test_build_command_fmi_option(tmp_path, capsys):
    from bearing_fmu.cli import main

    assert main(["build", "--fmi", "3", "-o", str(tmp_path / "x.fmu")]) == 2
    assert "add --native" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["build", "--native", "--fmi", "4", "--map", str(PAPER_MAP), "-o", str(tmp_path / "x.fmu")])
    assert not (tmp_path / "x.fmu").exists()


def test_fmpy_cmake_project_builds_the_same_binary(fmus, tmp_path):
    """fmpy's CMake project reads sources/buildDescription.xml (files, BN_FMI_VERSION=3) and builds
    into binaries/x86_64-linux an FMU that gives the same force bits."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    path = build_native_fmu(tmp_path / "cmake.fmu", "map", map=PAPER_MAP, cmake=True, fmi_version=3)
    f = fmus["map"]
    st = states("map", f["py"], f["params"], n=1, seed=9)[0]
    got = []
    for built in ((path, fmpy.extract(str(path))), f["fmu3"]):
        raw = Raw3(built)
        try:
            assert raw.init() == OK and raw.set(IN, st) == OK and raw.step()[0] == OK
            got.append(raw.get(OUT)[1])
        finally:
            raw.close()
    assert got[0] == got[1]


def test_thermal_ports_and_their_derivatives(fmus):
    """The thermal ports off (the map has the film's flows, but the paper bearing no oil law): T_eff =
    T_supply, mu_eff = mu; dT_eff/dT_supply = 1 directional and adjoint, the force not along
    T_supply; thermal = true refused, naming the missing law."""
    f = fmus["map"]
    raw = Raw3(f["fmu3"])
    try:
        assert raw.init() == OK
        assert raw.set(["T_supply"], [333.0]) == OK and raw.step()[0] == OK  # CS: the outputs of the step
        status, out = raw.get(["P_loss", "Q_side", "T_eff", "mu_eff"])
        assert status == OK and out[:3] == [0.0, 0.0, 333.0] and out[3] == raw.get(["mu"])[1][0]
        status, d = raw.derivative(["Fy", "Fz", "P_loss", "Q_side", "T_eff", "mu_eff"], ["T_supply"], [1.0])
        assert status == OK and list(d) == [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        status, row = raw.derivative(["T_eff", "Fy"], ["T_supply", "y"], [2.0, 0.0], adjoint=True)
        assert status == OK and list(row) == [2.0, 0.0]
    finally:
        raw.close()
    raw = Raw3(f["fmu3"])
    try:
        assert raw.set(["thermal"], [True], "Boolean") == OK and raw.enter() == OK
        assert (raw.call("fmi3ExitInitializationMode") == ERROR
                and "thermal = true needs the oil's viscosity law" in raw.last())
    finally:
        raw.close()
