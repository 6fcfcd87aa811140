"""A native FMU of several internals (bearing_fmu/fmu/native/several.py, c/bn_parts.c): the
parameter internal (or internal_enum) switches among them as in the Python FMU, and Taylor's
domain_action = fallback evaluates the Reynolds internal of the same FMU.

Expected values are the Python internals' at the same states (Taylor behind its domain guard with
the same options, fallback included; Reynolds on the same grid). The FMU is built once through
the command line (tests/conftest.py ``native_build_cache``).
"""

import ctypes
import warnings

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import calloc, free  # noqa: E402
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,  # noqa: E402
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

from bearing_fmu.internals import registry  # noqa: E402
from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402

from conftest import ROOT  # noqa: E402

SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")
GRID = {"n_theta": 32, "n_x": 8}

pytestmark = pytest.mark.filterwarnings("ignore:state outside the surrogate's fitted domain")


@pytest.fixture(scope="session")
def several(tmp_path_factory, native_build_cache):
    """(fmu, extracted dir): taylor and reynolds in one native FMU, through the command line."""
    from bearing_fmu.cli import main

    argv = ["build", "--native", "--internal", "taylor,reynolds", "--surrogate", str(SURROGATE),
            "--platforms", "linux64"]

    def cli(target):
        assert main([*argv, "-o", str(target)]) == 0
        return target

    fmu = native_build_cache(tmp_path_factory.mktemp("several") / "taylor_reynolds.fmu", cli, [SURROGATE],
                             ("cli", *argv[1:]), code=("bearing_fmu.cli",))
    return fmu, fmpy.extract(str(fmu))


class Instance:
    def __init__(self, several, **params):
        fmu, unzip = several
        md = fmpy.read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.types = {v.name: v.type for v in md.modelVariables}
        self.log = []
        self.f = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                           instanceName="several")
        self._cb = callbacks(self.log)
        self.f.instantiate(callbacks=self._cb, loggingOn=True)
        for name, value in params.items():
            kind = self.types[name]
            setter = {"String": self.f.setString, "Integer": self.f.setInteger, "Enumeration": self.f.setInteger,
                      "Real": self.f.setReal}[kind]
            setter([self.vr[name]], [value])
        self.f.setupExperiment(startTime=0.0)
        self.f.enterInitializationMode()
        self.f.exitInitializationMode()

    def outputs(self, state, k=0):
        self.f.setReal([self.vr[n] for n in IN], list(state))
        self.f.doStep(k * 1e-4, 1e-4)
        return np.array(self.f.getReal([self.vr[n] for n in OUT])), self.f.getBoolean([self.vr["out_of_domain"]])[0]

    def close(self):
        self.f.terminate()
        self.f.freeInstance()


def callbacks(log: list) -> fmi2CallbackFunctions:
    """The master's callbacks: every log line into ``log``; memory from fmpy's calloc and free."""
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(lambda _e, _n, _s, _c, msg: log.append(msg.decode() if msg else ""))
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    return cb


def states(n=40, seed=0):
    """The surrogate's training states moved (inside its domain, in the blending band beyond its
    edge and farther out, where the fallback is Reynolds alone)."""
    s = load_surrogate(SURROGATE)
    rng = np.random.default_rng(seed)
    pts = s.neighbours.points[rng.choice(len(s.neighbours.points), n)] + rng.normal(0, 0.05, (n, 4))
    return [(s.y0 + p[0] * s.pos_scale, s.z0 + p[1] * s.pos_scale, p[2] * s.vel_scale, p[3] * s.vel_scale, s.omega)
            for p in pts]


def python_outputs(py, state):
    F, dq, dv = py.force_and_jacobian(*state)
    return np.concatenate([np.asarray(F, float), -np.asarray(dq, float).ravel(), -np.asarray(dv, float).ravel()])


def worst(got, want):
    """The largest difference of the force, stiffness and damping blocks, each against its largest entry."""
    return max(np.max(np.abs(got[s] - want[s])) / np.max(np.abs(want[s]))
               for s in (slice(0, 2), slice(2, 6), slice(6, 10)))


@pytest.mark.parametrize("how", ["string", "enumeration"])
def test_the_parameter_internal_chooses(several, how):
    params = load_surrogate(SURROGATE).params
    for internal, options in (("reynolds", GRID), ("taylor", {"surrogate": str(SURROGATE)})):
        value = internal if how == "string" else registry.names().index(internal) + 1
        inst = Instance(several, **{"internal" if how == "string" else "internal_enum": value}, **GRID)
        py = registry.create(internal, params, options)
        try:
            for k, st in enumerate(states(12, seed=1)):
                got, _ood = inst.outputs(st, k)
                # Reynolds: the same operations (to a few ulps); Taylor: its polynomial's sums in another
                # order, terms of 1e6 N cancelling to 50 N (test_native_fmu.rounding_scale): 1e-10
                tol = 1e-14 if internal == "reynolds" else 1e-10
                assert worst(got, python_outputs(py, st)) <= tol, (internal, st)
        finally:
            inst.close()


def test_the_peak_pressure_is_the_reynolds_internals_field(several):
    """peak_pressure, peak_pressure_angle: with internal = reynolds the Python Reynolds internal's
    (``Reynolds.peak_pressure``, to round-off); with taylor 0 (no pressure field, as the Python FMU), also
    when its fallback evaluates the Reynolds internal of the FMU beyond the fitted domain."""
    params = load_surrogate(SURROGATE).params
    py = registry.create("reynolds", params, GRID)
    names = ("peak_pressure", "peak_pressure_angle")
    for internal, extra in (("reynolds", {}), ("taylor", {"domain_action": "fallback", "domain_limit": 100.0})):
        inst = Instance(several, internal=internal, **extra, **GRID)
        try:
            for k, st in enumerate(states(6, seed=2)):
                inst.outputs(st, k)
                got = inst.f.getReal([inst.vr[n] for n in names])
                want = py.peak_pressure(*st) if internal == "reynolds" else (0.0, 0.0)
                assert abs(got[0] - want[0]) <= 1e-12 * abs(want[0]) and abs(got[1] - want[1]) <= 1e-12, (internal, st)
            assert internal == "taylor" or got[0] > 0.0
        finally:
            inst.close()


def test_taylor_falls_back_to_the_reynolds_internal(several):
    """domain_action = fallback: inside the fitted domain the surrogate, beyond it Reynolds, blended
    over the band (guard.FALLBACK_BAND) with the weight's gradient in the tangent, as the Python
    guard. The force to the surrogate's round-off (its sums cancel: 1e-10, as above); the tangent in
    the band takes the weight's gradient by central differences of the domain distance (steps 1e-7
    of the scales), whose round-off the two codes make differently: 1e-9."""
    params = load_surrogate(SURROGATE).params
    py = registry.create("taylor", params, {"surrogate": str(SURROGATE), "domain_action": "fallback", **GRID})
    inst = Instance(several, domain_action="fallback", **GRID)
    outside = 0
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for k, st in enumerate(states(60)):
                got, ood = inst.outputs(st, k)
                want = python_outputs(py, st)
                assert bool(ood) == bool(py.last_out_of_domain)
                outside += bool(ood)
                assert np.max(np.abs(got[:2] - want[:2])) <= 1e-10 * np.max(np.abs(want[:2])), st
                assert worst(got, want) <= 1e-9, st
        assert 0 < outside < 60
        assert any("the Reynolds internal evaluates such states" in m for m in inst.log)
    finally:
        inst.close()


def test_fallback_far_out_is_reynolds(several):
    """Beyond the blending band the fallback is the Reynolds force itself (any speed: the
    surrogate is not evaluated there)."""
    s = load_surrogate(SURROGATE)
    rey = registry.create("reynolds", s.params, GRID)
    inst = Instance(several, domain_action="fallback", domain_limit=10.0, **GRID)
    try:
        st = (0.0, -0.8 * s.params.CR, 0.0, 0.0, s.omega)  # far below the expansion point
        got, ood = inst.outputs(st)
        assert ood and worst(got, python_outputs(rey, st)) <= 1e-14  # Reynolds alone, to a few ulps
    finally:
        inst.close()


def test_an_internal_it_does_not_hold_is_refused(several):
    fmu, unzip = several
    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    log = []
    f = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="x")
    cb = callbacks(log)
    f.instantiate(callbacks=cb, loggingOn=True)
    try:
        status = f.dll.fmi2SetString(f.component, (ctypes.c_uint * 1)(vr["internal"]), 1,
                                     (ctypes.c_char_p * 1)(b"map"))  # the raw call: its exact status
        assert status == 3 and "internal = 'map': this native FMU computes taylor, reynolds" in log[-1]
        items = [i.name for i in next(v for v in md.modelVariables if v.name == "internal_enum").declaredType.items]
        assert items == ["reynolds", "taylor"]
    finally:
        f.freeInstance()


@pytest.mark.slow
def test_fmi3_fmu_of_several_internals(tmp_path):
    """The FMI 3.0 FMU of all four internals (this machine's binary): fmpy validates it, and each
    internal chosen by its Int64 enumeration gives the FMI 2.0 route's force (here: the Python
    internals') at the start state, in Model Exchange and Co-Simulation."""
    from fmpy.validation import validate_fmu

    from bearing_fmu.fmu.native.build import build_native_fmu

    paper_map = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
    fmu = build_native_fmu(tmp_path / "all.fmu", "taylor,reynolds,map,linear", surrogate=SURROGATE, map=paper_map,
                           options={"linear_from": "map", "map": str(paper_map), **GRID}, fmi_version=3,
                           compiler="cc")
    assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(str(fmu))
    enum = next(v for v in md.modelVariables if v.name == "internal_enum")
    assert sorted(i.name for i in enum.declaredType.items) == ["linear", "map", "reynolds", "taylor"]
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in IN}
    st = tuple(start[n] for n in IN)
    params = load_surrogate(SURROGATE).params
    for internal, options in (("taylor", {"surrogate": str(SURROGATE)}), ("reynolds", GRID),
                              ("map", {"map": str(paper_map)})):
        want = registry.create(internal, params, options).force(*st)
        for fmi_type in ("ModelExchange", "CoSimulation"):
            res = fmpy.simulate_fmu(str(fmu), fmi_type=fmi_type, stop_time=1e-3, output_interval=1e-3,
                                    start_values={"internal_enum": registry.names().index(internal) + 1},
                                    output=["Fy", "Fz"])
            got = (res["Fy"][-1], res["Fz"][-1])
            assert np.allclose(got, want, rtol=1e-10, atol=1e-10 * np.max(np.abs(want))), (internal, fmi_type)
