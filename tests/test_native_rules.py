"""FMI 2.0 rules the native FMU keeps (issue 23, item 3): directional derivatives of every
output (the K, C outputs too) against central differences of the FMU's own outputs, and of
the parameters in Initialization Mode; a model identifier and GUID per content; two native
FMUs linked into one C program (FMI2_FUNCTION_PREFIX); out_of_domain changing at events only
in Model Exchange; fmi2Discard without fmi2Terminated; a refused state logged once; the
warning at omega = 0; the Taylor guard's radius as the Python guard's.
"""

import ctypes
import math
import re
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi2 import FMU2Model, FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE  # noqa: E402
from fmpy.fmi2 import fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE  # noqa: E402
from fmpy import calloc, free  # noqa: E402

from bearing_fmu.internals import registry  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams  # noqa: E402

# FMUs compiled, linked into C hosts and checked: end to end, in CI (the whole suite)
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    """kind -> (fmu, extracted dir) for map, taylor and linear (this platform's binary)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    d = tmp_path_factory.mktemp("rules")
    out = {"map": build_native_fmu(d / "map.fmu", "map", map=PAPER_MAP, platforms=["linux64"]),
           "taylor": build_native_fmu(d / "taylor.fmu", "taylor", surrogate=SURROGATE, platforms=["linux64"]),
           "linear": build_native_fmu(d / "linear.fmu", "linear", platforms=["linux64"],
                                      options={"linear_from": "map", "map": str(PAPER_MAP)})}
    return {k: (f, fmpy.extract(str(f))) for k, f in out.items()}


class Inst:
    """One instance through fmpy's raw functions: every call's status, every log line."""

    def __init__(self, fmu, unzip, kind="CS"):
        md = fmpy.read_model_description(str(fmu))
        self.md = md
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.messages = []
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(lambda _e, _n, s, _c, msg: self.messages.append((s, msg.decode())))
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._cb = cb
        cls = FMU2Slave if kind == "CS" else FMU2Model
        self.f = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                     instanceName="rules")
        self.f.instantiate(callbacks=cb, loggingOn=True)

    def call(self, name, *args):
        return getattr(self.f.dll, name)(self.f.component, *args)

    def set(self, names, values):
        n = len(names)
        return self.call("fmi2SetReal", (ctypes.c_uint * n)(*[self.vr[k] for k in names]), n,
                         (ctypes.c_double * n)(*values))

    def get(self, names):
        n = len(names)
        buf = (ctypes.c_double * n)()
        s = self.call("fmi2GetReal", (ctypes.c_uint * n)(*[self.vr[k] for k in names]), n, buf)
        return s, np.array(buf[:])

    def get_bool(self, name):
        buf = (ctypes.c_int * 1)()
        s = self.call("fmi2GetBoolean", (ctypes.c_uint * 1)(self.vr[name]), 1, buf)
        return s, bool(buf[0])

    def dd(self, unknowns, knowns, direction):
        nu, nk = len(unknowns), len(knowns)
        out = (ctypes.c_double * nu)()
        s = self.call("fmi2GetDirectionalDerivative", (ctypes.c_uint * nu)(*[self.vr[k] for k in unknowns]), nu,
                      (ctypes.c_uint * nk)(*[self.vr[k] for k in knowns]), nk, (ctypes.c_double * nk)(*direction), out)
        return s, np.array(out[:])

    def enter(self):
        assert self.call("fmi2SetupExperiment", 0, ctypes.c_double(0), ctypes.c_double(0), 0, ctypes.c_double(0)) == OK
        assert self.call("fmi2EnterInitializationMode") == OK

    def init(self):
        self.enter()
        return self.call("fmi2ExitInitializationMode")

    def step(self, t=None):
        if t is None:  # where the last step ended (fmi2LastSuccessfulTime): a step must start there
            now = ctypes.c_double()
            self.call("fmi2GetRealStatus", 2, ctypes.byref(now))
            t = now.value
        return self.call("fmi2DoStep", ctypes.c_double(t), ctypes.c_double(1e-4), 1)

    def close(self):
        self.f.freeInstance()


def state_of(kind):
    """A journal state the internal evaluates, with velocity (and the scale of each input)."""
    if kind == "taylor":
        s = registry.create("taylor", PAPER_BEARING, {"surrogate": str(SURROGATE)}).taylor.surrogate
        p = s.neighbours.points[7]
        return tuple(float(v) for v in (s.y0 + p[0] * s.pos_scale, s.z0 + p[1] * s.pos_scale, p[2] * s.vel_scale,
                                        p[3] * s.vel_scale, s.omega))
    cr, w = PAPER_BEARING.CR, 2 * math.pi * 22.0
    if kind == "linear":
        lin = registry.create("linear", PAPER_BEARING, {"linear_from": "map", "map": str(PAPER_MAP)})
        return (lin.y0 + 0.05 * cr, lin.z0 - 0.03 * cr, 0.02 * w * cr, -0.01 * w * cr, lin.omega0)
    return (0.3 * cr, -0.5 * cr, 0.05 * w * cr, -0.08 * w * cr, w)


def fd_outputs(inst, x, j, h):
    """Central differences of the outputs along input j (doStep at x +- h e_j)."""
    rows = []
    for sign in (1, -1):
        xs = list(x)
        xs[j] += sign * h
        inst.set(IN, xs)
        assert inst.step() == OK, inst.messages[-1]
        rows.append(inst.get(OUT)[1])
    inst.set(IN, x)
    assert inst.step() == OK
    return (rows[0] - rows[1]) / (2 * h)


@pytest.mark.parametrize("kind", ["map", "taylor", "linear"])
def test_directional_derivatives_of_every_output_against_central_differences(fmus, kind):
    inst = Inst(*fmus[kind])
    try:
        x = state_of(kind)
        assert inst.init() == OK
        inst.set(IN, x)
        assert inst.step() == OK
        cr, w = PAPER_BEARING.CR, x[4]
        scale = (cr, cr, w * cr, w * cr, w)
        for j, name in enumerate(IN):
            s, got = inst.dd(OUT, [name], [1.0])
            assert s == OK, inst.messages[-1]
            if name == "omega" and kind != "map":
                assert np.all(got == 0.0)  # a model of one speed (any other refused)
                continue
            want = fd_outputs(inst, x, j, 1e-5 * scale[j])
            for block in (slice(0, 2), slice(2, 4), slice(4, 8), slice(8, 12)):
                tol = 2e-5 * max(np.max(np.abs(want[block])), 1e-300) + 1e-9 * np.max(np.abs(want))
                assert np.allclose(got[block], want[block], rtol=0, atol=tol), (kind, name, got[block], want[block])
    finally:
        inst.close()


def test_parameter_derivatives_in_initialization_mode(fmus):
    """Map: D, L together (its L/D is fixed), CR and mu against central differences of the outputs
    computed in Initialization Mode; D alone is 3 F / D (S = mu L D^3 / 8 CR^2). Taylor: its
    bearing is compiled in: 0 for the force, ecc and h_min follow CR. Linear: its coefficients.
    After initialisation a parameter is no known (fmi2Error)."""
    inst = Inst(*fmus["map"])
    x = state_of("map")
    p = {"D": PAPER_BEARING.D, "L": PAPER_BEARING.L, "CR": PAPER_BEARING.CR, "mu": PAPER_BEARING.mu}

    def outputs_at(q):
        inst.set(list(q), list(q.values()))
        return inst.get(OUT)[1]
    try:
        inst.enter()
        inst.set(IN, x)
        base = outputs_at(p)
        for knowns, dirs in ((["D", "L"], [p["D"], p["L"]]), (["CR"], [p["CR"]]), (["mu"], [p["mu"]])):
            s, got = inst.dd(OUT, knowns, dirs)
            assert s == OK, inst.messages[-1]
            h = 1e-6
            up = outputs_at({**p, **{k: p[k] * (1 + h) for k in knowns}})
            down = outputs_at({**p, **{k: p[k] * (1 - h) for k in knowns}})
            want = (up - down) / (2 * h)
            outputs_at(p)
            assert np.allclose(got, want, rtol=1e-5, atol=1e-6 * np.abs(want).max()), (knowns, got, want)
        s, got = inst.dd(["Fy", "Fz", "Kyy"], ["D"], [1.0])
        assert s == OK and np.allclose(got, 3 * base[[0, 1, 4]] / p["D"], rtol=1e-14)
        assert inst.call("fmi2ExitInitializationMode") == OK
        assert inst.dd(["Fy"], ["mu"], [1.0])[0] == ERROR and "Initialization Mode only" in inst.messages[-1][1]
    finally:
        inst.close()
    inst = Inst(*fmus["taylor"])
    try:
        inst.enter()
        inst.set(IN, state_of("taylor"))
        ecc = inst.get(["eccentricity"])[1][0]
        s, got = inst.dd(["Fy", "Fz", "Kyy", "eccentricity", "h_min"], ["CR"], [1.0])
        assert s == OK and np.array_equal(got[:3], np.zeros(3))
        assert got[3] == pytest.approx(-ecc / PAPER_BEARING.CR, rel=1e-14) and got[4] == pytest.approx(1.0, rel=1e-14)
    finally:
        inst.close()
    inst = Inst(*fmus["linear"])
    try:
        x = state_of("linear")
        inst.enter()
        inst.set(IN, x)
        for k in ("lin_Kyy", "lin_Czy", "lin_y0", "lin_Fz0"):
            v = next(float(w.start) for w in inst.md.modelVariables if w.name == k)
            s, got = inst.dd(OUT, [k], [1.0])
            assert s == OK
            h = 1e-6 * max(abs(v), 1e-9)
            inst.set([k], [v + h])
            up = inst.get(OUT)[1]
            inst.set([k], [v - h])
            down = inst.get(OUT)[1]
            inst.set([k], [v])
            assert np.allclose(got, (up - down) / (2 * h), rtol=1e-6, atol=1e-9), (k, got)
    finally:
        inst.close()


def test_identifier_and_guid_follow_the_content(fmus, tmp_path):
    from bearing_fmu.fmu.native.build import build_native_fmu

    md = {k: fmpy.read_model_description(str(f)) for k, (f, _u) in fmus.items()}
    idents = {k: m.coSimulation.modelIdentifier for k, m in md.items()}
    assert all(re.fullmatch(rf"bearing_{k}_[0-9a-f]{{6}}", v) for k, v in idents.items())
    again = fmpy.read_model_description(str(build_native_fmu(tmp_path / "again.fmu", "map", map=PAPER_MAP,
                                                              platforms=["linux64"])))
    assert (again.guid, again.coSimulation.modelIdentifier) == (md["map"].guid, idents["map"])  # the same build
    other = BearingParams(PAPER_BEARING.D, PAPER_BEARING.L, PAPER_BEARING.CR, 0.02)
    thin = fmpy.read_model_description(str(build_native_fmu(tmp_path / "mu.fmu", "map", map=PAPER_MAP,
                                                             bearing=other, platforms=["linux64"])))
    assert thin.guid != md["map"].guid  # another mu: another FMU
    config = zipfile.ZipFile(fmus["map"][0]).read("sources/model_config.h").decode()
    assert f"#define BN_GUID \"{md['map'].guid}\"" in config and f"#define BN_ID {idents['map']}" in config


TWO_HOST = r"""
#include <stdio.h>
#include <stdlib.h>
#include "fmi2FunctionTypes.h"
/* the two FMUs' functions, each under its prefix (A_, B_: replaced by the test) */
#define DECLARE(p) fmi2InstantiateTYPE p##fmi2Instantiate; fmi2SetupExperimentTYPE p##fmi2SetupExperiment; \
    fmi2EnterInitializationModeTYPE p##fmi2EnterInitializationMode; \
    fmi2ExitInitializationModeTYPE p##fmi2ExitInitializationMode; fmi2SetRealTYPE p##fmi2SetReal; \
    fmi2GetRealTYPE p##fmi2GetReal; fmi2DoStepTYPE p##fmi2DoStep; fmi2FreeInstanceTYPE p##fmi2FreeInstance;
DECLARE(A_)
DECLARE(B_)
static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {
    (void)e; (void)s; printf("log %s [%s] %s\n", n, c, m);
}
int main(int argc, char **argv) {
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    const fmi2ValueReference in[5] = {0, 1, 2, 3, 4}, out[2] = {5, 6};
    double xa[5], xb[5], fa[2], fb[2];
    (void)argc;
    for (int i = 0; i < 5; i++) { xa[i] = atof(argv[3 + i]); xb[i] = atof(argv[8 + i]); }
    fmi2Component a = A_fmi2Instantiate("a", fmi2CoSimulation, argv[1], "", &cb, 0, 1);
    fmi2Component b = B_fmi2Instantiate("b", fmi2CoSimulation, argv[2], "", &cb, 0, 1);
    if (!a || !b) return 4;
    A_fmi2SetupExperiment(a, 0, 0, 0, 0, 0); B_fmi2SetupExperiment(b, 0, 0, 0, 0, 0);
    A_fmi2EnterInitializationMode(a); B_fmi2EnterInitializationMode(b);
    A_fmi2ExitInitializationMode(a); B_fmi2ExitInitializationMode(b);
    A_fmi2SetReal(a, in, 5, xa); B_fmi2SetReal(b, in, 5, xb);
    int sa = A_fmi2DoStep(a, 0, 1e-4, 1), sb = B_fmi2DoStep(b, 0, 1e-4, 1);
    A_fmi2GetReal(a, out, 2, fa); B_fmi2GetReal(b, out, 2, fb);
    printf("a %d %.17g %.17g\nb %d %.17g %.17g\n", sa, fa[0], fa[1], sb, fb[0], fb[1]);
    A_fmi2FreeInstance(a); B_fmi2FreeInstance(b);
    return 0;
}
"""


def test_two_native_fmus_link_into_one_program(fmus, tmp_path):
    """The sources of the map and the Taylor FMU compiled with FMI2_FUNCTION_PREFIX = each one's
    "<modelIdentifier>_" and linked statically into one C host: no duplicate symbol (every
    helper carries its model identifier), and each gives its own force (that of its shared library)."""
    from bearing_fmu.fmu.native.compile import find_compiler, fmi_headers

    objs, guids, prefixes = [], [], []
    for kind in ("map", "taylor"):
        fmu, unzip = fmus[kind]
        md = fmpy.read_model_description(str(fmu))
        ident = md.coSimulation.modelIdentifier
        guids.append(md.guid)
        prefixes.append(ident + "_")
        for src in md.buildConfigurations[0].sourceFileSets[0].sourceFiles:
            obj = tmp_path / f"{kind}_{src}.o"
            subprocess.run([find_compiler(), "-std=c99", "-O2", "-ffp-contract=off", "-c",
                            f"-DFMI2_FUNCTION_PREFIX={ident}_", "-I", str(Path(unzip) / "sources"), "-I",
                            str(fmi_headers()), str(Path(unzip) / "sources" / src), "-o", str(obj)], check=True)
            objs.append(obj)
    host = tmp_path / "two.c"
    host.write_text(TWO_HOST.replace("A_", prefixes[0]).replace("B_", prefixes[1]))
    exe = tmp_path / "two"
    done = subprocess.run([find_compiler(), "-std=c99", "-I", str(fmi_headers()), str(host), *map(str, objs),
                           "-o", str(exe), "-lm"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    xa, xb = state_of("map"), state_of("taylor")
    args = [repr(float(v)) for v in (*xa, *xb)]
    run = subprocess.run([str(exe), *guids, *args], capture_output=True, text=True, env={})
    assert run.returncode == 0, run.stdout + run.stderr
    lines = {line.split()[0]: line.split()[1:] for line in run.stdout.splitlines() if line[:2] in ("a ", "b ")}
    for key, kind, x in (("a", "map", xa), ("b", "taylor", xb)):
        inst = Inst(*fmus[kind])
        try:
            assert inst.init() == OK and inst.set(IN, x) == OK and inst.step() == OK
            got = np.array(lines[key][1:], float)
            assert lines[key][0] == "0" and np.array_equal(got, inst.get(["Fy", "Fz"])[1]), run.stdout
        finally:
            inst.close()


def test_out_of_domain_changes_at_events_only_in_model_exchange(fmus):
    inst = Inst(*fmus["taylor"], kind="ME")
    s = registry.create("taylor", PAPER_BEARING, {"surrogate": str(SURROGATE)}).taylor.surrogate
    inside = (s.y0, s.z0, 0.0, 0.0, s.omega)
    outside = (s.y0 + 0.1 * s.params.CR, s.z0 - 0.1 * s.params.CR, 0.0, 0.0, s.omega)
    try:
        assert inst.init() == OK
        assert inst.call("fmi2EnterContinuousTimeMode") == OK
        inst.set(IN, outside)
        assert inst.get(["Fy"])[0] == OK and inst.get_bool("out_of_domain") == (OK, False)  # held
        enter, term = ctypes.c_int(), ctypes.c_int()
        assert inst.call("fmi2CompletedIntegratorStep", 1, ctypes.byref(enter), ctypes.byref(term)) == OK
        assert enter.value  # a step event
        assert inst.call("fmi2EnterEventMode") == OK
        info = fmpy.fmi2.fmi2EventInfo()
        assert inst.call("fmi2NewDiscreteStates", ctypes.byref(info)) == OK
        assert inst.get_bool("out_of_domain") == (OK, True)
        assert inst.call("fmi2EnterContinuousTimeMode") == OK
        inst.set(IN, inside)
        assert inst.get_bool("out_of_domain") == (OK, True)  # held until the next event
        assert inst.call("fmi2CompletedIntegratorStep", 1, ctypes.byref(enter), ctypes.byref(term)) == OK
        assert enter.value
    finally:
        inst.close()
    md = zipfile.ZipFile(fmus["taylor"][0]).read("modelDescription.xml").decode()
    assert 'completedIntegratorStepNotNeeded="false"' in md


def test_a_refused_state_is_logged_once_and_never_terminates(fmus):
    inst = Inst(*fmus["map"], kind="ME")
    try:
        assert inst.init() == OK and inst.call("fmi2EnterContinuousTimeMode") == OK
        inst.set(IN, (0.0, -0.999 * PAPER_BEARING.CR, 0.0, 0.0, 100.0))
        assert [inst.get(["Fy", "Fz"])[0] for _ in range(5)] == [DISCARD] * 5
        assert len([m for s, m in inst.messages if s == DISCARD]) == 1
        inst.set(IN, state_of("map"))
        assert inst.get(["Fy"])[0] == OK
    finally:
        inst.close()
    inst = Inst(*fmus["map"])
    try:
        assert inst.init() == OK
        inst.set(IN, (0.0, -1.01 * PAPER_BEARING.CR, 0.0, 0.0, 100.0))
        assert inst.step() == DISCARD
        flag = ctypes.c_int(7)
        assert inst.call("fmi2GetBooleanStatus", 3, ctypes.byref(flag)) == OK and flag.value == 0  # not terminated
        inst.set(IN, state_of("map"))
        assert inst.step() == OK  # another state: it goes on
    finally:
        inst.close()


def test_omega_starts_at_the_build_speed_and_zero_speed_warns(fmus, tmp_path):
    from bearing_fmu.fmu.native.build import build_native_fmu

    starts = {k: float(next(v.start for v in fmpy.read_model_description(str(f)).modelVariables
                            if v.name == "omega")) for k, (f, _u) in fmus.items()}
    s = registry.create("taylor", PAPER_BEARING, {"surrogate": str(SURROGATE)}).taylor.surrogate
    assert starts["taylor"] == s.omega and starts["map"] == starts["linear"] == 2 * math.pi * 22.0
    fast = build_native_fmu(tmp_path / "fast.fmu", "map", map=PAPER_MAP, speed_hz=50.0, platforms=["linux64"])
    assert float(next(v.start for v in fmpy.read_model_description(str(fast)).modelVariables
                      if v.name == "omega")) == 2 * math.pi * 50.0
    inst = Inst(*fmus["map"])
    try:
        assert inst.init() == OK
        inst.set(IN, (1e-5, -2e-5, 0.0, 0.0, 0.0))
        assert inst.step() == WARNING and "is the input omega connected" in inst.messages[-1][1]
        assert inst.get(["Fy", "Fz"])[1].tolist() == [0.0, 0.0]
        assert inst.step(1e-4) == OK  # warned once
        inst.set(IN, state_of("map"))
        assert inst.step(2e-4) == OK
    finally:
        inst.close()


def test_native_guard_uses_the_python_guards_radius_and_size(fmus):
    near = registry.create("taylor", PAPER_BEARING, {"surrogate": str(SURROGATE)}).taylor.neighbours
    text = zipfile.ZipFile(fmus["taylor"][0]).read("sources/model_data.h").decode()
    radius = float(re.search(r"#define TAY_NN_RADIUS (\S+)", text).group(1))
    size = float(re.search(r"#define TAY_NN_SIZE (\S+)", text).group(1))
    assert (radius, size) == (near.radius, near.size) and radius >= near.cv_radius


@pytest.mark.slow
def test_rotor_host_builds_the_native_fmu_for_the_scenes_bearing(tmp_path, monkeypatch):
    """rotor-host run --native on the Friswell machine with its own map (L/D 0.3): the FMU is built
    for the scene's bearing (the paper bearing's would refuse that map) and omega starts at 25 Hz."""
    from rotor_host.cli import main

    monkeypatch.setenv("BEARING_FMU_BUILD_CACHE", str(tmp_path / "fmus"))
    scene = ROOT / "rotor_host" / "bundled" / "scenes" / "friswell_25hz.toml"
    assert main(["run", str(scene), "--internal", "map", "--native", "--t-end", "0.002", "--out", str(tmp_path),
                 "--no-plots", "--quiet"]) == 0
    fmu = next((tmp_path / "fmus").glob("*.fmu"))
    starts = {v.name: v.start for v in fmpy.read_model_description(str(fmu)).modelVariables}
    assert float(starts["D"]) == 0.1 and float(starts["L"]) == 0.03
    assert float(starts["omega"]) == pytest.approx(2 * math.pi * 25.0, rel=1e-15)
