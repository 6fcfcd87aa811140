"""The native FMU (bearing_fmu/native): the linear, map and Taylor internals compiled to C.

Expected values come from the Python internals themselves (``bearing_fmu.internals.create``:
the Taylor internal behind its domain guard, the force map, the linear model), never from the
FMU; the statuses are the table of docs/fmu.md ("FMI status"). Every FMU is built once (one
compile each, again only when the sources or the data change: tests/conftest.py
``native_build_cache``); the map FMU through the command line.
"""

import ctypes
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import calloc, free  # noqa: E402
from fmpy.fmi2 import (  # noqa: E402
    FMU2Model,
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

from bearing_fmu.internals import registry  # noqa: E402
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams  # noqa: E402
from bearing_fmu.surrogates.surrogate import load_surrogate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SURROGATES = sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("*.json"))
MAPS = sorted((ROOT / "rotor_host" / "bundled" / "maps").glob("*.json"))
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"  # the paper bearing's L/D
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
FMI2_TERMINATED = 3
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")
RTOL = 1e-12  # the target: the C internal equals the Python one to 1e-12 relative

pytestmark = [pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None
                                 and not os.environ.get("CC"), reason="no C compiler"),
              # the Python guard warns once per internal for the moved training states outside the domain
              pytest.mark.filterwarnings("ignore:state outside the surrogate's fitted domain")]


# ----------------------------------------------------------------------------- the FMUs

@pytest.fixture(scope="session")
def native(tmp_path_factory, native_build_cache):
    """name -> (fmu path, extracted dir, python internal, params): every shipped surrogate and map,
    and the linear model linearised on the shipped map; built once (and compiled again only when
    the sources or the data change: ``native_build_cache`` in tests/conftest.py)."""
    from bearing_fmu.cli import main
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder = tmp_path_factory.mktemp("native")
    out = {}
    for path in MAPS:
        bearing = _map_bearing(path)  # a map serves its own L/D: the bearing it was built for
        extra = ["--bearing", str(bearing)] if bearing else []
        params = BearingParams.from_toml(bearing) if bearing else PAPER_BEARING
        argv = ["build", "--native", "--internal", "map", "--map", str(path), *extra, "--platforms", "linux64"]

        def cli(target, argv=argv):  # through the command line
            assert main([*argv, "-o", str(target)]) == 0
            return target

        fmu = native_build_cache(folder / f"map_{path.stem}.fmu", cli, [path] + ([bearing] if bearing else []),
                                 ("cli", *argv[1:]), code=("bearing_fmu.cli",))
        out[f"map:{path.stem}"] = (fmu, registry.create("map", params, {"map": str(path)}), params)
    for path in SURROGATES:
        fmu = native_build_cache(folder / f"taylor_{path.stem}.fmu",
                                 lambda target, path=path: build_native_fmu(target, "taylor", surrogate=path,
                                                                             platforms=["linux64"]),
                                 [path], ("taylor", "linux64"))
        params = load_surrogate(path).params
        out[f"taylor:{path.stem}"] = (fmu, registry.create("taylor", params, {"surrogate": str(path)}), params)
    lin_opts = {"linear_from": "map", "map": str(PAPER_MAP)}
    fmu = native_build_cache(folder / "linear.fmu", lambda target: build_native_fmu(target, "linear", options=lin_opts,
                                                                                             platforms=["linux64"]),
                             [PAPER_MAP], ("linear", "linear_from", "map", "linux64"))
    out["linear"] = (fmu, registry.create("linear", PAPER_BEARING, lin_opts), PAPER_BEARING)
    # the Reynolds solver: the paper bearing on a 32 x 8 grid (start values), and the lemon bore at
    # the default grid through the command line
    rey_opts = {"n_theta": 32, "n_x": 8}
    fmu = native_build_cache(folder / "reynolds.fmu", lambda target: build_native_fmu(
        target, "reynolds", options=rey_opts, platforms=["linux64"]), [], ("reynolds", "32 x 8", "linux64"))
    out["reynolds"] = (fmu, registry.create("reynolds", PAPER_BEARING, rey_opts), PAPER_BEARING)
    lemon = ROOT / "rotor_host" / "bundled" / "bearing_paper_lemon.toml"
    argv = ["build", "--native", "--internal", "reynolds", "--bearing", str(lemon), "--platforms", "linux64"]

    def cli_lemon(target):
        assert main([*argv, "-o", str(target)]) == 0
        return target

    fmu = native_build_cache(folder / "reynolds_lemon.fmu", cli_lemon, [lemon], ("cli", *argv[1:]),
                             code=("bearing_fmu.cli",))
    lemon_params = BearingParams.from_toml(lemon)
    out["reynolds:lemon"] = (fmu, registry.create("reynolds", lemon_params, {}), lemon_params)
    return {k: (fmu, fmpy.extract(str(fmu)), py, params) for k, (fmu, py, params) in out.items()}


def _map_bearing(path: Path) -> Path | None:
    """The bearing file a shipped map was built for (its provenance), None for the paper bearing."""
    import json

    name = json.loads(path.read_text()).get("provenance", {}).get("bearing_file", "")
    return ROOT / name if name.endswith(".toml") and (ROOT / name).is_file() else None


class Raw:
    """One instance through fmpy's raw ctypes functions (the exact fmi2Status of every call)."""

    _ARRAY = {"Real": ctypes.c_double, "Boolean": ctypes.c_int, "String": ctypes.c_char_p, "Integer": ctypes.c_int}

    def __init__(self, fmu, unzip, logging=True, kind="CS", name="native"):
        md = fmpy.read_model_description(str(fmu))
        self.vars = {v.name: v for v in md.modelVariables}
        self.messages = []
        self._cb = fmi2CallbackFunctions()
        self._cb.logger = fmi2CallbackLoggerTYPE(
            lambda _e, _n, status, _c, msg: self.messages.append((status, msg.decode() if msg else "")))
        self._cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self._cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        cls = FMU2Slave if kind == "CS" else FMU2Model
        ident = (md.coSimulation or md.modelExchange).modelIdentifier
        self.fmu = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName=name)
        self.fmu.instantiate(callbacks=self._cb, loggingOn=logging)

    def call(self, fname, *args) -> int:
        return getattr(self.fmu.dll, fname)(self.fmu.component, *args)

    def set(self, name, value) -> int:
        v = self.vars[name]
        typ = "Integer" if v.type == "Enumeration" else v.type  # FMI 2.0: an enumeration is set as an Integer
        value = value.encode() if typ == "String" else value
        return self.call(f"fmi2Set{typ}", (ctypes.c_uint * 1)(v.valueReference), 1, (self._ARRAY[typ] * 1)(value))

    def get(self, name):
        v = self.vars[name]
        typ = "Integer" if v.type == "Enumeration" else v.type
        out = (self._ARRAY[typ] * 1)()
        status = self.call(f"fmi2Get{typ}", (ctypes.c_uint * 1)(v.valueReference), 1, out)
        return status, (out[0].decode() if typ == "String" else out[0])

    def set_inputs(self, state) -> int:
        vrs = (ctypes.c_uint * 5)(*[self.vars[n].valueReference for n in IN])
        return self.call("fmi2SetReal", vrs, 5, (ctypes.c_double * 5)(*state))

    def outputs(self, names=OUT):
        vrs = (ctypes.c_uint * len(names))(*[self.vars[n].valueReference for n in names])
        buf = (ctypes.c_double * len(names))()
        status = self.call("fmi2GetReal", vrs, len(names), buf)
        return status, np.array(buf[:])

    def enter(self) -> None:
        assert self.call("fmi2SetupExperiment", 0, ctypes.c_double(0.0), ctypes.c_double(0.0), 0,
                         ctypes.c_double(0.0)) == OK
        assert self.call("fmi2EnterInitializationMode") == OK

    def init(self) -> int:
        self.enter()
        return self.call("fmi2ExitInitializationMode")

    def now(self) -> float:
        """The instance's time: where its last step ended (a step must start there)."""
        t = ctypes.c_double()
        status = self.call("fmi2GetRealStatus", 2, ctypes.byref(t))  # fmi2LastSuccessfulTime
        return t.value if status == OK else 0.0  # (refused before initialisation)

    def step(self, t=None, h=1e-4) -> int:
        t = self.now() if t is None else t
        return self.call("fmi2DoStep", ctypes.c_double(t), ctypes.c_double(h), 1)

    def last(self, status=None) -> str:
        msgs = [m for s, m in self.messages if status is None or s == status]
        return msgs[-1] if msgs else ""

    def close(self):
        self.fmu.freeInstance()


def states_for(key, py, params, n=40, seed=0):
    """Random journal states (y, z, vy, vz, omega) where the internal evaluates: for a surrogate
    its stored training states, slightly moved (inside and just outside its fitted domain); for the
    map anywhere up to eps 0.95 at any speed and velocity; for the linear model near its point."""
    rng = np.random.default_rng(seed)
    if key == "reynolds:lemon":  # the default grid, 128 x 16: fewer states (the quick loop's 0.3 s a test)
        n = min(n, 12)
    if key.startswith("taylor"):
        s = py.taylor.surrogate
        pts = s.neighbours.points[rng.choice(len(s.neighbours.points), n)] + rng.normal(0, 0.02, (n, 4))
        cr, vs = s.pos_scale, s.vel_scale
        return [(s.y0 + p[0] * cr, s.z0 + p[1] * cr, p[2] * vs, p[3] * vs, s.omega) for p in pts]
    if key.startswith(("map", "reynolds")):
        out = []
        for _ in range(n):
            e, a, w = rng.uniform(0, 0.95), rng.uniform(-math.pi, math.pi), rng.uniform(20, 400)
            v = rng.normal(0, 0.3, 2) * w * params.CR
            out.append((e * params.CR * math.cos(a), e * params.CR * math.sin(a), v[0], v[1], w))
        out.append((0.0, 0.0, 0.0, 0.0, 100.0))  # the centre, no film source (r = 0)
        return out
    q = rng.normal(0, 0.2, (n, 4))
    return [(py.y0 + p[0] * params.CR, py.z0 + p[1] * params.CR, p[2] * 0.01, p[3] * 0.01, py.omega0) for p in q]


def python_outputs(py, state):
    """(Fy, Fz, Kyy .. Czz) of the Python internal, K, C in Lund's sign as the FMU gives them."""
    F, dq, dv = py.force_and_jacobian(*state)
    return np.concatenate([np.asarray(F, float), -np.asarray(dq, float).ravel(), -np.asarray(dv, float).ravel()])


ULPS = 8 * np.finfo(float).eps  # two summation orders of one sum differ by a few ulps of its absolute terms


def rounding_scale(py, state) -> np.ndarray:
    """Per output (Fy, Fz, Kyy .. Czz): the sum of the absolute values of the terms a Taylor
    polynomial adds up to it, in SI. A floating-point sum is exact only to a few ulps of that
    (Higham, Accuracy and Stability of Numerical Algorithms, sec. 4.2), whatever the order: the
    C kernel sums the same terms in another order (dot products; the Python kernel term by
    term), so where the polynomial cancels strongly (terms of 1e6 N giving 70 N inside the 22 Hz
    domain) the two agree only to ~eps times this. Zeros for the other internals."""
    from bearing_fmu.surrogates.basis import design_matrix

    taylor = getattr(py, "taylor", None)
    if taylor is None:
        return np.zeros(10)
    s = taylor.surrogate
    u = s.scaled([state[:4]])
    c = np.abs(s.coef)
    h = 1.0 if not s.wall_power else (1.0 - (state[0] ** 2 + state[1] ** 2) / s.pos_scale ** 2) ** -s.wall_power
    out = np.zeros(10)
    out[:2] = (np.abs(design_matrix(u, s.exponents)) @ c.T)[0] * s.force_scale * h
    for v in range(4):  # d/du_v: the terms e_v c u^(e - 1_v)
        e = s.exponents.copy()
        keep = e[:, v] > 0
        e[keep, v] -= 1
        terms = np.abs(design_matrix(u, e))[0] * keep * s.exponents[:, v]
        scale = s.force_scale * h / (s.pos_scale if v < 2 else s.vel_scale)
        for i in range(2):
            out[2 + 4 * i + v] = (terms @ c[i]) * scale  # order of OUT: Kyy Kyz Kzy Kzz Cyy ..
    return out[[0, 1, 2, 3, 6, 7, 4, 5, 8, 9]]


def assert_close(got, want, what, cond=None):
    """Each block (force, stiffness, damping) to RTOL of its largest entry, plus a few ulps of
    the sums' absolute terms (``rounding_scale``) where given."""
    cond = np.zeros(10) if cond is None else cond
    for sl, name in ((slice(0, 2), "force"), (slice(2, 6), "stiffness"), (slice(6, 10), "damping")):
        tol = RTOL * max(np.max(np.abs(want[sl])), 1e-300) + ULPS * np.max(cond[sl])
        err = np.max(np.abs(got[sl] - want[sl]))
        assert err <= tol, (f"{what}: {name} differs by {err:.3g} (allowed {tol:.3g}, "
                            f"{err / np.max(np.abs(want[sl])):.3g} relative): {got[sl]} vs {want[sl]}")


# ----------------------------------------------------------------------------- equality

def test_every_shipped_file_has_a_native_fmu(native):
    assert SURROGATES and MAPS
    assert ({f"taylor:{p.stem}" for p in SURROGATES} | {f"map:{p.stem}" for p in MAPS}
            | {"linear", "reynolds", "reynolds:lemon"} == set(native))


@pytest.mark.parametrize("key", [f"taylor:{p.stem}" for p in SURROGATES] + [f"map:{p.stem}" for p in MAPS]
                         + ["linear", "reynolds", "reynolds:lemon"])
def test_cs_forces_and_jacobians_equal_the_python_internal(native, key):
    fmu, unzip, py, params = native[key]
    states = states_for(key, py, params)
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK
        n_out = 0
        for k, st in enumerate(states):
            assert raw.set_inputs(st) == OK
            assert raw.step(1e-4 * k) == OK, raw.last()
            status, got = raw.outputs()
            assert status == OK
            assert_close(got, python_outputs(py, st), f"{key} at {st}", rounding_scale(py, st))
            ood = raw.get("out_of_domain")[1]
            assert bool(ood) == bool(getattr(py, "last_out_of_domain", False))  # the guard's verdict, same state
            n_out += bool(ood)
            eps = math.hypot(st[0], st[1]) / params.CR
            assert raw.get("eccentricity")[1] == pytest.approx(eps, rel=1e-15)
            assert raw.get("h_min")[1] == pytest.approx(params.CR * (1 - eps), rel=1e-12, abs=1e-20)
        if key.startswith("taylor"):
            assert 0 < n_out < len(states)  # the moved training states lie on both sides of the domain's edge
    finally:
        raw.close()


@pytest.mark.parametrize("key", ["taylor:paper_44hz_16.7N", "taylor:paper_22hz_16.7N", "map:paper_bearing", "linear",
                                 "reynolds"])
def test_force_without_tangent_equals_the_python_force(native, key):
    """compute_tangent = false takes the force-only path (Taylor: its own kernel, like Taylor.force)."""
    fmu, unzip, py, params = native[key]
    raw = Raw(fmu, unzip)
    try:
        assert raw.set("compute_tangent", False) == OK
        assert raw.init() == OK
        for st in states_for(key, py, params, n=15, seed=3):
            raw.set_inputs(st)
            assert raw.step() == OK
            got = raw.outputs(("Fy", "Fz", "Kyy"))[1]
            want = np.array(py.force(*st))
            tol = RTOL * np.max(np.abs(want)) + ULPS * np.max(rounding_scale(py, st)[:2])
            assert np.max(np.abs(got[:2] - want)) <= tol
            assert got[2] == 0.0  # K, C not computed
    finally:
        raw.close()


@pytest.mark.parametrize("key", ["taylor:paper_44hz_16.7N", "map:paper_bearing", "linear", "reynolds:lemon"])
def test_model_exchange_outputs_and_directional_derivatives(native, key):
    """ME: the outputs are a direct feedthrough of the inputs; fmi2GetDirectionalDerivative is the
    force Jacobian (and, for the map and Reynolds, dF/domega: central differences of the Python force)."""
    fmu, unzip, py, params = native[key]
    raw = Raw(fmu, unzip, kind="ME")
    f = raw.fmu
    try:
        assert raw.init() == OK
        f.enterContinuousTimeMode()
        vr = {n: raw.vars[n].valueReference for n in (*IN, *OUT)}
        for st in states_for(key, py, params, n=8, seed=5):
            f.setReal([vr[n] for n in IN], list(st))
            got = np.array(f.getReal([vr[n] for n in OUT]))
            want = python_outputs(py, st)
            cond = rounding_scale(py, st)
            assert_close(got, want, f"ME {key}", cond)
            for j, name in enumerate(IN[:4]):
                d = f.getDirectionalDerivative([vr["Fy"], vr["Fz"]], [vr[name]], [1.0])
                col = [-want[2 + j], -want[4 + j]] if j < 2 else [-want[4 + j], -want[6 + j]]  # Lund sign
                # the directional derivative is computed as the K, C outputs are: the same bits
                assert d == [-got[2 + j], -got[4 + j]] if j < 2 else d == [-got[4 + j], -got[6 + j]]
                assert np.allclose(d, col, rtol=0, atol=RTOL * np.max(np.abs(want[2:])) + ULPS * np.max(cond[2:]))
            if key.startswith(("map", "reynolds")):
                h = 1e-4 * st[4]
                fd = (np.array(py.force(*st[:4], st[4] + h)) - np.array(py.force(*st[:4], st[4] - h))) / (2 * h)
                d = f.getDirectionalDerivative([vr["Fy"], vr["Fz"]], [vr["omega"]], [1.0])
                # a force of round-off (the lemon bore centred and still: 1e-14 N of 46 N's scale
                # mu R L (R / CR)^2 omega) has differences of noise: not compared there
                scale = params.mu * params.R * params.L * (params.R / params.CR) ** 2 * st[4]
                if np.max(np.abs(want[:2])) > 1e-9 * scale:
                    assert np.allclose(d, fd, rtol=1e-5, atol=1e-7 * np.max(np.abs(want[:2])) / st[4])
    finally:
        raw.close()


# ----------------------------------------------------------------------------- FMU files

def test_fmpy_validate_is_clean(native):
    from fmpy.validation import validate_fmu

    for key, (fmu, *_rest) in native.items():
        assert validate_fmu(str(fmu)) == [], key


def test_archive_holds_sources_documentation_and_both_interfaces(native):
    fmu = native["taylor:paper_44hz_16.7N"][0]
    names = zipfile.ZipFile(fmu).namelist()
    for f in ("sources/fmi2_bearing.c", "sources/bearing_calls.c", "sources/bearing_values.c", "sources/bearing_model.c",
              "sources/bearing_derivatives.c", "sources/internal_taylor.c", "sources/model_data.h",
              "sources/model_config.h", "sources/bearing_native.h", "documentation/index.html"):
        assert f in names
    md = fmpy.read_model_description(str(fmu))
    ident = md.coSimulation.modelIdentifier  # a content hash per build
    assert re.fullmatch(r"bearing_taylor_[0-9a-f]{6}", ident) and md.modelExchange.modelIdentifier == ident
    assert f"binaries/linux64/{ident}.so" in names
    md = fmpy.read_model_description(str(fmu))
    assert md.coSimulation.canGetAndSetFMUstate and md.modelExchange.providesDirectionalDerivative
    names = {v.name for v in md.modelVariables}
    # the Python FMU's variables where they apply (bearing_fmu/fmu/slave.py VARIABLES)
    assert {"y", "z", "vy", "vz", "omega", "Fy", "Fz", "eccentricity", "h_min", "out_of_domain", "Kyy", "Czz",
            "D", "L", "CR", "mu", "internal", "compute_tangent", "surrogate", "domain_action",
            "domain_limit"} <= names
    xml = zipfile.ZipFile(fmu).read("modelDescription.xml").decode()
    # display units for a system-simulation engineer: um for displacements, rpm for the speed
    assert '<DisplayUnit name="rpm" factor="9.549296585513721"/>' in xml and 'displayUnit="um"' in xml
    omega = next(v for v in md.modelVariables if v.name == "omega")
    s44 = load_surrogate(ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_44hz_16.7N.json")
    assert float(omega.start) == s44.omega  # the fitted speed: initialisation evaluates without a warning


def test_model_names_and_the_data_recorded(native):
    """A model name per build (the internal, the data file, the bearing); the data file's SHA-256
    in the description, resources/build_info.json and documentation/index.html."""
    import hashlib
    import json

    names = set()
    for key, (fmu, unzip, _py, _params) in native.items():
        md = fmpy.read_model_description(str(fmu))
        names.add(md.modelName)
        internal, _, stem = key.partition(":")
        if internal == "reynolds":  # no data file: the bearing (its bore) names it
            info = json.loads(Path(unzip, "resources", "build_info.json").read_text())
            assert info["data_files"] == [] and info["internals"] == ["reynolds"], key
            assert md.modelName == ("BearingFMU reynolds native (bearing_paper_lemon)" if stem else
                                    "BearingFMU reynolds native (paper bearing)"), md.modelName
            assert ("2 lobes, preload 0.5" in md.description) == bool(stem), md.description
            continue
        # linear was linearised on the paper map; a map built for another bearing names it
        stem = stem or PAPER_MAP.stem
        source = next(p for p in SURROGATES + MAPS if p.stem == stem)
        bearing = _map_bearing(source) if internal == "map" else None
        label = bearing.stem if bearing else "paper bearing"
        assert md.modelName == f"BearingFMU {internal} {stem} native ({label})", key
        sha = hashlib.sha256(source.read_bytes()).hexdigest()
        b = PAPER_BEARING if bearing is None else BearingParams.from_toml(bearing)
        geometry = f"D {b.D * 1e3:g} mm, L {b.L * 1e3:g} mm, CR {b.CR * 1e6:g} um"
        assert f"{source.name} sha256 {sha[:12]}" in md.description and geometry in md.description, key
        info = json.loads(Path(unzip, "resources", "build_info.json").read_text())
        assert [(f["name"], f["sha256"]) for f in info["data_files"]] == [(source.name, sha)]
        assert info["internals"] == [internal] and info["model_name"] == md.modelName
        page = Path(unzip, "documentation", "index.html").read_text()
        assert sha in page and all(f"<tr><td>{v.name}</td>" in page for v in md.modelVariables), key
    assert len(names) == len(native)


def _bounded(v) -> bool:
    """A variable's start value lies within its min and max (FMI 2.0: min <= start <= max)."""
    if v.start is None or v.type not in ("Real", "Integer"):
        return True
    x = float(v.start)
    return (v.min is None or float(v.min) <= x) and (v.max is None or x <= float(v.max))


def test_python_and_native_fmus_declare_the_same(native, fmu):
    """Both FMUs come from one definition (bearing_fmu/fmu/meta.py): every variable they share has the
    same type, causality, unit, display unit and bounds; the native enumerations are the Python
    FMU's items it accepts, with the same numbers; every start value is within its bounds."""
    py = {v.name: v for v in fmpy.read_model_description(str(fmu)).modelVariables}
    assert all(_bounded(v) for v in py.values())
    for key, (path, *_rest) in native.items():
        nat = {v.name: v for v in fmpy.read_model_description(str(path)).modelVariables}
        assert set(nat) <= set(py), (key, set(nat) - set(py))
        assert all(_bounded(v) for v in nat.values()), key
        for name, v in nat.items():
            w = py[name]
            assert (v.type, v.causality, v.unit, v.displayUnit, v.min, v.max) == \
                   (w.type, w.causality, w.unit, w.displayUnit, w.min, w.max), (key, name)
            if v.type == "Enumeration":
                items = {(i.name, i.value) for i in v.declaredType.items}
                assert v.declaredType.name == w.declaredType.name and items
                assert items <= {(i.name, i.value) for i in w.declaredType.items}, (key, name)
        internal = key.partition(":")[0]
        assert [i.name for i in nat["internal_enum"].declaredType.items] == [internal]


def test_enumerations_choose_like_their_string(native):
    fmu, unzip, py, params = native["taylor:paper_22hz_16.7N"]
    s = py.taylor.surrogate
    outside = (s.y0 + 0.1 * s.params.CR, s.z0 - 0.1 * s.params.CR, 0.0, 0.0, s.omega)  # just outside: warned
    raw = Raw(fmu, unzip)
    try:
        assert raw.get("internal_enum")[0] == ERROR and "getInteger in Instantiated" in raw.last()  # FMI 2.0
        raw.enter()
        assert raw.get("domain_action_enum") == (OK, 1) and raw.get("internal_enum") == (OK, 3)  # the starts
        assert raw.set("internal_enum", 4) == ERROR  # 4 = map: not what this FMU computes
        assert "internal_enum = 4 means internal = 'map': this native FMU computes the taylor internal only" \
            in raw.last()
        assert raw.set("domain_action_enum", 2) == ERROR and "means domain_action = 'fallback'" in raw.last()
        assert raw.set("domain_action_enum", 7) == ERROR
        assert "domain_action_enum = 7 must be one of 1 (warn), 3 (discard)" in raw.last()
        assert raw.set("domain_action_enum", 3) == OK  # discard, given as the enumeration alone
        assert raw.set("internal_enum", 3) == OK  # a valid value withdraws the refusal (else init fails)
        assert raw.call("fmi2ExitInitializationMode") == OK
        assert raw.get("domain_action") == (OK, "discard")  # both show the choice that counts
        raw.set_inputs(outside)
        assert raw.step() == DISCARD and "outside (domain_action = 'discard')" in raw.last(DISCARD)
        assert raw.call("fmi2GetInteger", (ctypes.c_uint * 1)(3999), 1, (ctypes.c_int * 1)()) == ERROR
        assert "value reference 3999 is not an Integer variable" in raw.last()
    finally:
        raw.close()
    raw = Raw(fmu, unzip)
    try:  # a master writing every start value: the String's start does not undo the enumeration
        assert raw.set("domain_action_enum", 3) == OK and raw.set("domain_action", "warn") == OK
        assert raw.init() == OK and raw.get("domain_action") == (OK, "discard")
    finally:
        raw.close()


@pytest.mark.parametrize("key", [f"taylor:{p.stem}" for p in SURROGATES] + [f"map:{p.stem}" for p in MAPS]
                         + ["linear"])
def test_nothing_set_initialises_and_steps_without_a_warning(native, key):
    """The start values (the surrogate's expansion point and fitted speed; the linear model's
    point and speed; the map: centred, at rest) are a state the internal evaluates."""
    fmu, unzip, *_ = native[key]
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK and raw.step() == OK
        assert [m for status, m in raw.messages if status != OK] == []
    finally:
        raw.close()


def _needed(path: Path) -> list[str]:
    """DT_NEEDED entries of an ELF shared library (its .dynamic section read with struct)."""
    from bearing_fmu.fmu.binary import _Elf

    data = path.read_bytes()
    elf = _Elf(data)
    out = []
    for sh in elf.sections:
        if sh[1] == 6:  # SHT_DYNAMIC: (d_tag, d_val) pairs; strings in the section it links
            strtab = elf.sections[sh[6]]
            for k in range(sh[5] // 16):
                tag, val = struct.unpack_from("<qQ", data, sh[4] + 16 * k)
                if tag == 1:  # DT_NEEDED
                    start = strtab[4] + val
                    out.append(data[start:data.index(b"\0", start)].decode())
    return out


def test_binary_links_no_python(native):
    for key, (_fmu, unzip, *_rest) in native.items():
        binary = next(Path(unzip, "binaries").rglob("*.so"))
        needed = _needed(binary)
        assert needed and all("python" not in n.lower() for n in needed), (key, needed)
        assert set(needed) <= {"libc.so.6", "libm.so.6"}, (key, needed)  # nothing else at run time


# ----------------------------------------------------------------------------- a plain C host

@pytest.fixture(scope="session")
def c_host(tmp_path_factory):
    """bearing_fmu/fmu/native/c/example_host.c compiled with the system compiler."""
    from bearing_fmu.fmu.native.build import C_DIR, find_compiler, fmi_headers

    exe = tmp_path_factory.mktemp("host") / "example_host"
    subprocess.run([find_compiler(), "-O2", str(C_DIR / "example_host.c"), "-I", str(fmi_headers()), "-o", str(exe),
                    "-ldl", "-lm"], check=True, capture_output=True)
    return exe


def run_host(c_host, native, key, state, steps=0):
    fmu, unzip, *_ = native[key]
    md = fmpy.read_model_description(str(fmu))
    binary = next(Path(unzip, "binaries").rglob("*.so"))
    done = subprocess.run([str(c_host), str(binary), md.guid, *(repr(float(x)) for x in state), str(steps)], env={},
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.mark.parametrize("key", ["taylor:paper_44hz_16.7N", "map:paper_bearing"])
def test_plain_c_host_with_an_empty_environment_runs_it(native, c_host, key):
    """A C program started with no environment at all (no Python on any path) loads, initialises
    and steps the FMU; its forces are the Python internal's."""
    _fmu, _unzip, py, params = native[key]
    st = states_for(key, py, params, n=1, seed=11)[0]
    out = run_host(c_host, native, key, st, steps=1000)
    lines = dict(line.split(" ", 1) for line in out.splitlines() if " " in line)
    assert lines["status"] == "0"
    got = np.array(lines["outputs"].split(), float)
    assert_close(got[:10], python_outputs(py, st), "C host", rounding_scale(py, st))
    assert "refused 0" in lines["doStep_us"]


def test_plain_c_host_sees_a_discard_at_the_wall(native, c_host):
    out = run_host(c_host, native, "map:paper_bearing", (0.0, -0.995 * PAPER_BEARING.CR, 0.0, 0.0, 100.0))
    assert "status 2" in out  # fmi2Discard
    assert "beyond the force map's last point" in out  # logged through the host's logger


# ----------------------------------------------------------------------------- statuses

def test_statuses_of_parameters_and_calls(native):
    """docs/fmu.md, FMI status: refused parameters, unknown value references, bad steps."""
    fmu, unzip, *_ = native["taylor:paper_22hz_16.7N"]
    raw = Raw(fmu, unzip)
    try:
        assert raw.step() == ERROR and "doStep in Instantiated: not allowed there" in raw.last()
        assert raw.set("D", -1.0) == ERROR and "D = -1 m must be finite and > 0; D keeps 0.031" in raw.last()
        assert raw.set("internal", "reynolds") == ERROR and "computes the taylor internal only" in raw.last()
        assert raw.set("domain_action", "fallback") == ERROR and "Reynolds solver" in raw.last()
        assert raw.set("domain_action", "maybe") == ERROR and "choose one of warn, discard" in raw.last()
        assert raw.set("surrogate", "other.json") == ERROR and "compiled in" in raw.last()
        assert raw.set("domain_limit", 0.0) == ERROR
        assert raw.set("Fy", 1.0) == ERROR and "output" in raw.last()
        assert raw.call("fmi2SetReal", (ctypes.c_uint * 1)(9999), 1, (ctypes.c_double * 1)(0.0)) == ERROR
        assert "value reference 9999" in raw.last()
        assert raw.init() == ERROR  # D refused when it was set, and not set validly since
        assert "refused when it was set" in raw.last() and "D = -1" in raw.last()
    finally:
        raw.close()
    raw = Raw(fmu, unzip)
    try:
        assert raw.set("D", -1.0) == ERROR
        assert raw.set("D", 0.031) == OK  # a valid value since: initialisation goes on
        raw.enter()
        assert raw.set("domain_action", "DISCARD") == OK and raw.get("domain_action")[1] == "discard"
        assert raw.set("mu", 0.06) == OK
        assert raw.call("fmi2ExitInitializationMode") == ERROR and "fitted for bearing mu = 0.05" in raw.last()
    finally:
        raw.close()
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK
        assert raw.set("D", 0.03) == ERROR and "fixed after initialisation" in raw.last()
        assert raw.step(0.0, 0.0) == ERROR and "communicationStepSize = 0 s must be finite and > 0" in raw.last()
        assert raw.step(0.0, math.nan) == ERROR
        assert raw.step(math.inf, 1e-4) == ERROR
    finally:
        raw.close()


def test_thermal_ports_are_there_and_off(native):
    """The Python FMU's thermal ports (docs/fmu.md): the shipped maps' bearings have no oil law, so
    thermal = true is refused at initialisation naming why: for the full bore's map, whose film
    flows are in C (tests/test_native_map_thermal.py), the missing law; for a grooved map, whose
    flow tables are compiled in only with an oil law (they are 2.5 times the force's;
    tests/test_native_groove_thermal.py), the flows left out. With thermal = false the outputs are the isoviscous film's: T_eff = T_supply,
    mu_eff = mu, P_loss and Q_side 0 (not computed); their directional derivatives say so
    (dT_eff/dT_supply = 1); T_supply is an input an FMU state restores; the force does not move with it."""
    for name, why in (("map:paper_2groove", "thermal = true needs the film's friction and flows, which internal = "
                       "'map' does not have (the bearing has no [oil] viscosity law, so a grooved map's flow tables "
                       "are not compiled in"),
                      ("map:paper_bearing", "thermal = true needs the oil's viscosity law: this native FMU was built "
                       "from a bearing without one")):
        raw = Raw(*native[name][:2])
        try:
            assert raw.set("thermal", True) == OK
            assert raw.init() == ERROR
            assert why in raw.last()
        finally:
            raw.close()
    fmu, unzip, *_ = native["map:paper_bearing"]
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK
        state = (10e-6, -40e-6, 1e-3, -2e-4, 2 * math.pi * 22.0)
        assert raw.set_inputs(state) == OK and raw.set("T_supply", 330.0) == OK
        assert raw.step() == OK
        names = ("Fy", "Fz", "P_loss", "Q_side", "T_eff", "mu_eff")
        status, out = raw.outputs(names)
        assert status == OK and list(out[2:]) == [0.0, 0.0, 330.0, raw.get("mu")[1]]
        saved = raw.fmu.getFMUstate()
        assert raw.set("T_supply", 380.0) == OK and raw.step(1e-4) == OK
        status, hot = raw.outputs(names)
        assert list(hot[:2]) == list(out[:2]) and hot[4] == 380.0  # the force is isoviscous
        raw.fmu.setFMUstate(saved)
        assert raw.get("T_supply")[1] == 330.0
        raw.fmu.freeFMUstate(saved)
        vr = {n: raw.vars[n].valueReference for n in (*names, "T_supply")}
        d = raw.fmu.getDirectionalDerivative([vr[n] for n in names[2:]], [vr["T_supply"]], [1.0])
        assert d == [0.0, 0.0, 1.0, 0.0]
    finally:
        raw.close()


def test_the_bore_is_the_datas(native):
    """The Python FMU's geometry parameters, at the bore the data were made for (the full one); another
    is refused at initialisation naming every parameter set away from it; an Integer out of its range
    when it is set."""
    fmu, unzip, *_ = native["taylor:paper_22hz_16.7N"]
    md = {v.name: v for v in fmpy.read_model_description(str(fmu)).modelVariables}
    assert (md["groove_count"].start, md["lobes"].start, md["partial_arc"].start) == ("0", "1", "false")
    raw = Raw(fmu, unzip)
    try:
        assert raw.set("groove_count", 9) == ERROR and "groove_count = 9 must be in 0 .. 8" in raw.last()
        assert raw.set("groove_count", 2) == OK and raw.set("groove_1", math.pi / 2) == OK
        assert raw.set("partial_arc", True) == OK
        assert raw.init() == ERROR
        assert ("this native FMU's taylor data were made for one bore (full 360 deg circular bore): the geometry "
                "parameters set away from it are groove_count = 2 (the data's: 0), partial_arc = true (the data's: "
                "false), groove_1 = 1.5707963267948966 (the data's: 0)") in raw.last()
    finally:
        raw.close()
    raw = Raw(fmu, unzip)
    try:
        assert raw.set("groove_width", float(md["groove_width"].start)) == OK and raw.init() == OK  # its own: fine
        assert raw.get("lobes") == (OK, 1)
    finally:
        raw.close()


def test_refused_states_discard_and_a_restore_recovers(native):
    fmu, unzip, py, params = native["taylor:paper_22hz_16.7N"]
    s = py.taylor.surrogate
    good = (s.y0, s.z0, 0.0, 0.0, s.omega)
    raw = Raw(fmu, unzip)
    try:
        assert py.taylor.domain_distance(s.y0, s.z0, 2 * s.domain.v_max * s.vel_scale, 0.0) > 0.5  # Python: refused
        assert raw.init() == OK
        raw.set_inputs(good)
        assert raw.step() == OK
        before = raw.outputs()[1]
        state = ctypes.c_void_p()
        assert raw.call("fmi2GetFMUstate", ctypes.byref(state)) == OK
        for bad, words in (((0.0, -1.01 * s.params.CR, 0.0, 0.0, s.omega), "at or beyond the wall"),
                           ((s.y0, s.z0, 0.0, 0.0, 1.5 * s.omega), "fitted at omega"),
                           ((s.y0, s.z0, 2 * s.domain.v_max * s.vel_scale, 0.0, s.omega),
                            "more than domain_limit = 0.5 beyond")):
            raw.set_inputs(bad)
            assert raw.step(1e-4) == DISCARD
            assert words in raw.last(DISCARD)
            assert np.array_equal(raw.outputs()[1], before)  # outputs keep their last values
            flag = ctypes.c_int()  # not terminated: another state (a restore, other inputs) can go on
            assert raw.call("fmi2GetBooleanStatus", FMI2_TERMINATED, ctypes.byref(flag)) == OK and not flag.value
            assert raw.call("fmi2SetFMUstate", state) == OK
            assert raw.call("fmi2GetBooleanStatus", FMI2_TERMINATED, ctypes.byref(flag)) == OK and not flag.value
        # the restored state holds the good inputs: stepping gives the same outputs
        assert raw.step(1e-4) == OK and np.array_equal(raw.outputs()[1], before)
        # serialise and restore through bytes
        size = ctypes.c_size_t()
        assert raw.call("fmi2SerializedFMUstateSize", state, ctypes.byref(size)) == OK
        buf = (ctypes.c_char * size.value)()
        assert raw.call("fmi2SerializeFMUstate", state, buf, size) == OK
        copy = ctypes.c_void_p()
        assert raw.call("fmi2DeSerializeFMUstate", buf, size, ctypes.byref(copy)) == OK
        assert raw.call("fmi2SetFMUstate", copy) == OK
        raw.call("fmi2FreeFMUstate", ctypes.byref(copy))
        raw.call("fmi2FreeFMUstate", ctypes.byref(state))
    finally:
        raw.close()


RETRY_WORDS = "was discarded and the inputs are unchanged"


@pytest.mark.parametrize("key", ["map:paper_bearing", "taylor:paper_22hz_16.7N"])
def test_a_discarded_step_retried_unchanged_is_an_error(native, key):
    """No fmi2Terminated after a discard (a restore or other inputs can go on), so a master that
    retries the same step with nothing changed would loop (fmpy 0.3's simulate_fmu does, setting
    the same inputs again before each retry): a retry at the discarded step's inputs, set again or
    not, is fmi2Error naming why (compared by value, bit for bit); other inputs, or a restored
    FMU state, step again."""
    fmu, unzip, py, params = native[key]
    omega = py.taylor.surrogate.omega if key.startswith("taylor") else 2 * math.pi * 22
    bad = (0.0, -1.01 * params.CR, 0.0, 0.0, omega)
    good = ((py.taylor.surrogate.y0, py.taylor.surrogate.z0, 0.0, 0.0, omega) if key.startswith("taylor")
            else (0.0, -0.5 * params.CR, 0.0, 0.0, omega))
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK
        state = ctypes.c_void_p()
        assert raw.call("fmi2GetFMUstate", ctypes.byref(state)) == OK
        raw.set_inputs(bad)
        assert raw.step() == DISCARD
        assert raw.step() == ERROR and RETRY_WORDS in raw.last(ERROR) and "from t = 0 s" in raw.last(ERROR)
        assert raw.set_inputs(bad) == OK  # set again, the same values: still the discarded step
        assert raw.step(h=5e-5) == ERROR and RETRY_WORDS in raw.last(ERROR)
        bad2 = (bad[0] + 1e-9, *bad[1:])  # another state (refused too: a discard, not the retry's error)
        assert raw.set_inputs(bad2) == OK and raw.step() == DISCARD
        assert raw.call("fmi2SetFMUstate", state) == OK  # a restore: the master knows; the same inputs may go
        raw.set_inputs(bad2)
        assert raw.step() == DISCARD
        raw.set_inputs(good)
        assert raw.step() == OK
        raw.call("fmi2FreeFMUstate", ctypes.byref(state))
    finally:
        raw.close()


@pytest.mark.slow
def test_fmpy_simulate_stops_at_a_state_it_cannot_step(native, tmp_path):
    """simulate_fmu from a start state beyond the wall raises with the FMU's reason instead of
    retrying the discarded step for ever (a subprocess, so a regression fails by its timeout)."""
    fmu, _unzip, _py, params = native["map:paper_bearing"]
    code = (f"import fmpy\ntry:\n    fmpy.simulate_fmu({str(fmu)!r}, stop_time=0.01, output_interval=1e-3, "
            f"start_values={{'z': {-1.01 * params.CR!r}}})\nexcept Exception as exc:\n    print('raised', exc)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert "raised" in out.stdout and "fmi2DoStep" in out.stdout, out.stdout + out.stderr
    assert RETRY_WORDS in out.stderr, out.stderr


def test_a_foreign_state_is_refused(native):
    a = Raw(*native["map:paper_bearing"][:2])
    b = Raw(*native["linear"][:2])
    try:
        assert a.init() == OK and b.init() == OK
        state = ctypes.c_void_p()
        assert a.call("fmi2GetFMUstate", ctypes.byref(state)) == OK
        assert b.call("fmi2SetFMUstate", state) == ERROR and "not a bearing-native/1 state of this FMU" in b.last()
        a.call("fmi2FreeFMUstate", ctypes.byref(state))
    finally:
        a.close()
        b.close()


def test_domain_warning_once_per_excursion_and_initialisation_at_a_refused_state(native):
    fmu, unzip, py, params = native["taylor:paper_22hz_16.7N"]
    s = py.taylor.surrogate
    outside = (s.y0 + 0.1 * s.params.CR, s.z0 - 0.1 * s.params.CR, 0.0, 0.0, s.omega)
    assert py.taylor.domain_distance(*outside[:4]) > 0  # the Python guard agrees it is outside
    raw = Raw(fmu, unzip)
    try:
        raw.set_inputs((0.0, 0.0, 0.0, 0.0, 1.0))  # wrong speed: refused at exitInitializationMode
        raw.call("fmi2SetupExperiment", 0, ctypes.c_double(0.0), ctypes.c_double(0.0), 0, ctypes.c_double(0.0))
        raw.call("fmi2EnterInitializationMode")
        status, _ = raw.get("Fy")  # outputs read in Initialization Mode at inputs it refuses
        assert status == ERROR and "cannot be computed at the inputs set" in raw.last()
        assert raw.call("fmi2ExitInitializationMode") == WARNING  # logged as a warning: returned as one
        assert "outputs at the start time left at their start values" in raw.last(WARNING)
        for k in range(3):
            raw.set_inputs(outside)
            assert raw.step(1e-4 * k) == OK
        warnings = [m for st, m in raw.messages if st == WARNING and "fitted domain" in m]
        assert len(warnings) == 1 and "excursion 1: warned once per excursion" in warnings[0]  # a refused state never counts
        assert raw.get("out_of_domain")[1]
    finally:
        raw.close()


def test_logging_off_echoes_the_first_error_to_stderr(native, capfd):
    raw = Raw(*native["map:paper_bearing"][:2], logging=False, name="quiet")
    try:
        assert raw.set("D", -1.0) == ERROR
        assert raw.set("D", -2.0) == ERROR
        err = capfd.readouterr().err
        assert err.count("bearing FMU 'quiet' [error]: setReal: D = -1 m") == 1 and "D = -2" not in err
        assert "loggingOn" in err
    finally:
        raw.close()


# ----------------------------------------------------------------------------- fmpy simulate

@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmpy_simulates_it(native, fmi_type):
    fmu, _unzip, py, params = native["map:paper_bearing"]
    st = (1e-5, -4e-5, 1e-3, -2e-3, 2 * math.pi * 22)
    table = np.array([(0.0, *st), (0.01, *st)],
                     dtype=[("time", float)] + [(n, float) for n in IN])
    res = fmpy.simulate_fmu(str(fmu), fmi_type=fmi_type, stop_time=0.01, output_interval=1e-3, input=table,
                            output=["Fy", "Fz"])
    want = py.force(*st)
    assert np.allclose(res["Fy"][1:], want[0], rtol=RTOL) and np.allclose(res["Fz"][1:], want[1], rtol=RTOL)


# ----------------------------------------------------------------------------- builds

@pytest.mark.slow
def test_fmpy_cmake_project_builds_the_same_binary(native, tmp_path):
    """The sources build with fmpy's CMake project (how a user rebuilds for another platform) into
    an FMU that gives the same force. Slow: end to end through cmake (configure, build: 2-3 s);
    the quick loop builds the same sources with the C compiler and checks every FMU's forces."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    fmu = build_native_fmu(tmp_path / "cmake.fmu", "map", map=PAPER_MAP, cmake=True)
    _f, _u, py, params = native["map:paper_bearing"]
    raw = Raw(fmu, fmpy.extract(str(fmu)))
    try:
        assert raw.init() == OK
        st = states_for("map", py, params, n=1, seed=2)[0]
        raw.set_inputs(st)
        assert raw.step() == OK
        assert_close(raw.outputs()[1], python_outputs(py, st), "cmake build")
    finally:
        raw.close()


@pytest.mark.parametrize("argv, words", [
    (["--native", "--internal", "taylor"], "needs --surrogate FILE"),
    (["--native", "--internal", "map", "--surrogate", str(SURROGATES[0])], "needs --map FILE"),
    (["--native"], "--native needs --internal"),
    (["--internal", "map"], "add --native"),
    (["--native", "--surrogate", str(SURROGATES[0]), "--surrogate", str(SURROGATES[1])], "once"),
])
def test_build_command_refuses_what_a_native_fmu_cannot_be(tmp_path, capsys, argv, words):
    from bearing_fmu.cli import main

    assert main(["build", *argv, "-o", str(tmp_path / "x.fmu")]) == 2
    assert words in capsys.readouterr().err
    assert not (tmp_path / "x.fmu").exists()


def test_a_map_for_another_length_to_diameter_is_refused(tmp_path):
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.physics.params import BearingParams

    with pytest.raises(ValueError, match="L/D"):
        build_native_fmu(tmp_path / "x.fmu", "map", map=PAPER_MAP, bearing=BearingParams(0.031, 0.031, 90e-6, 0.05))


# ----------------------------------------------------------------------------- the rotor host

def test_native_parameters_of_a_scene(paper_scene):
    """The host's parameters for a native FMU: the options it keeps; the linear model made per
    bearing by the Python Linear internal (its coefficients), fallback refused in one line."""
    from rotor_host.scenes.bearings import fmu_parameters
    from rotor_host.scenes.scene import load_scene

    sc = load_scene(paper_scene(internal="linear", via="fmu", fmu_kind="native", unbalance_g=None,
                                linear={"linear_from": "map"}, map={"map": PAPER_MAP},
                                taylor={"surrogate": SURROGATES[1], "domain_action": "fallback"}))
    assert sc.fmu_kind == "native"
    p = fmu_parameters(sc, PAPER_BEARING, (0.0, -16.7))
    lin = registry.create("linear", PAPER_BEARING, {"linear_from": "map", "map": str(PAPER_MAP)},
                          registry.Context(load=(0.0, -16.7), omega=sc.omega))
    assert p["lin_Kyz"] == lin.K[0, 1] and p["lin_Czz"] == lin.C[1, 1] and p["omega_lin"] == sc.omega
    assert "n_theta" not in p and "linear_from" not in p  # options a native FMU does not have
    # Taylor's fallback: its FMU holds the Reynolds internal too, with the scene's grid
    p = fmu_parameters(sc.with_internal("taylor"), PAPER_BEARING, (0.0, -16.7))
    assert p["domain_action"] == "fallback" and (p["n_theta"], p["n_x"], p["cavitation"]) == (0, 0, "reynolds")
    from bearing_fmu.fmu.native.host import fmu_internals

    assert fmu_internals("taylor", sc.with_internal("taylor").internal_options()) == "taylor,reynolds"
    assert fmu_internals("map", {}) == "map"


@pytest.mark.slow
@pytest.mark.parametrize("internal, scene", [("map", "paper_22hz"), ("taylor", "paper_22hz"),
                                             ("reynolds", "paper_22hz"), ("reynolds", "paper_lemon_22hz")])
def test_rotor_host_runs_native_fmus_like_the_direct_internal(tmp_path, internal, scene):
    """rotor-host run --native: the paper's 22 Hz scene (and for Reynolds the same on lemon-bore
    bearings, the bore compiled into the FMU) through native FMUs (fmpy, the conformant iteration of
    rotor_host/coupling/cosim.py) follows the run with the internal called in-process."""
    from rotor_host.cli import main
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene_file = ROOT / "rotor_host" / "bundled" / "scenes" / f"{scene}.toml"
    assert main(["run", str(scene_file), "--internal", internal, "--via", "fmu", "--native", "--t-end", "0.01", "--out",
                 str(tmp_path), "--no-plots", "--quiet"]) == 0
    native = np.load(tmp_path / f"{scene}_{internal}_native.npz")
    direct = run_scene(load_scene(scene_file).with_internal(internal, via="direct", t_end_s=0.01), tmp_path,
                       stem="direct")
    assert direct.ok and len(native["t"]) == len(direct.arrays["t"]) == 101
    CR = PAPER_BEARING.CR
    for key in ("y", "z"):  # forces equal to ~1e-14, so the same Newton iterates: orbits to 1e-9 CR
        assert np.max(np.abs(native[key] - direct.arrays[key])) < 1e-9 * CR


def test_a_native_reynolds_fmu_serves_one_bore(paper_scene, tmp_path, monkeypatch):
    """The native Reynolds FMU has the first bearing's bore compiled in: a rotor whose bearings have
    different bores is refused by name before anything is built (the lemon rotor's second bearing
    on the plain bore here)."""
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import SceneError, load_scene

    monkeypatch.setenv("BEARING_FMU_BUILD_CACHE", str(tmp_path / "fmus"))  # where a build would go
    text = (ROOT / "rotor_host" / "bundled" / "rotor_paper_lemon.toml").read_text()
    lemon, plain = ROOT / "rotor_host" / "bundled" / "bearing_paper_lemon.toml", ROOT / "rotor_host" / "bundled" / "bearing_paper.toml"
    head, _, tail = text.partition('bearing = "bearing_paper_lemon.toml"')
    rotor = tmp_path / "rotor_mixed.toml"
    rotor.write_text(head + f"bearing = {str(lemon)!r}" + tail.replace('"bearing_paper_lemon.toml"', repr(str(plain))))
    sc = load_scene(paper_scene(internal="reynolds", via="fmu", fmu_kind="native", rotor=str(rotor)))
    with pytest.raises(SceneError, match=r"the native FMU has the bore of bearing 1 \(node 3\) compiled in \(.*2 lobes"
                                         r".*\), bearing 2 \(node 9\) has another \(full 360 deg circular bore\)"):
        run_scene(sc, tmp_path / "out")
    assert not list(tmp_path.rglob("*.fmu"))


@pytest.mark.slow
def test_rotor_host_runs_taylor_with_its_fallback_natively(paper_scene, tmp_path):
    """A Taylor scene with domain_action = fallback through native FMUs: the host builds one FMU of
    taylor and reynolds (fmu_internals) and the run follows the direct one (300 g of unbalance: the
    orbit leaves the 22 Hz surrogate's fitted domain in 46 % of the steps, up to 8.9 % beyond it,
    inside the band where both blend the surrogate with Reynolds)."""
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    opts = {"surrogate": str(ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"), "domain_action": "fallback"}
    sc = load_scene(paper_scene(internal="taylor", via="fmu", fmu_kind="native", taylor=opts, grid=(32, 8),
                                unbalance_g=300.0))
    native = run_scene(sc, tmp_path, stem="native")
    direct = run_scene(sc.with_internal("taylor", via="direct"), tmp_path, stem="direct")
    assert native.ok and direct.ok and len(native.arrays["t"]) == 101
    assert direct.meta["out_of_domain_fraction"][0] > 0.3  # the fallback was used
    from bearing_fmu.io.cache import build_cache

    assert any(p.name.startswith("bearing_native_taylor") for p in build_cache().glob("*.fmu"))  # the FMU cache
    for key in ("y", "z"):
        assert np.max(np.abs(native.arrays[key] - direct.arrays[key])) < 1e-9 * PAPER_BEARING.CR
