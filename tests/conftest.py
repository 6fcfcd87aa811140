"""Fixtures shared by the test modules: one bearing FMU per session (with a made-up surrogate
bundled), its extraction and instances, a scene writer, the central-difference Jacobian, and
file systems that refuse writes (a small tmpfs: full, or remounted read-only; as root). Also the
``native`` marker (set by hook on every test that builds or loads a native FMU; docs/development.md, *The edit
loop*) and the build caches, each keyed by the sources its build uses (``source_files``)."""

import fcntl
import hashlib
import json
import math
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

# One BLAS thread per process, set before numpy loads OpenBLAS (subprocesses inherit it). The
# tests' matrices are small (fits of a few hundred rows): a second thread gains nothing, and on a
# shared 2-core machine OpenBLAS's spinning threads collapse under load (the Taylor fit tests,
# then tests/test_taylor.py: 18-20 s with one thread, 46-79 s with the default two, side by side).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
# Bytecode caches written whatever PYTHONDONTWRITEBYTECODE says (set on this project's machines): without
# them every test process compiles the package's sources again, each CLI test's subprocess too, and
# pytest rewrites every test module's asserts in every run (the quick loop 42-47 s without, 34-38 s
# with, 2 cores, 2026-12-07). The caches go to __pycache__ folders (.gitignore) and change no result.
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

import numpy as np  # noqa: E402
import pytest


ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"
ROTOR = MODELS / "rotor_paper.toml"
OMEGA_22HZ = 2 * math.pi * 22.0


@pytest.fixture(scope="session", autouse=True)
def fmu_build_cache(tmp_path_factory):
    """The FMUs that scenes build and the maps of the map store (bearing_fmu.io.cache: the user's
    cache otherwise) go to folders of this session, shared by its tests and their subprocesses
    (inherited environment), so the tests neither read nor fill the user's cache."""
    path = tmp_path_factory.mktemp("fmu-builds")
    with pytest.MonkeyPatch.context() as mp:  # the session's: restored at its end
        mp.setenv("BEARING_FMU_BUILD_CACHE", str(path))
        mp.setenv("BEARING_FMU_MAP_STORE", str(tmp_path_factory.mktemp("map-store")))
        yield path


# ------------------------------------------------------------ the native marker

def _native_used(event: str, args) -> None:
    """An audit hook: a C compiler started from this process (cc, gcc, clang, zig, cmake), or a
    native library loaded (a native FMU's binary: its archive holds ``sources/``; or one kept in
    the tests' cache folder, the Reynolds solver's), is noted, so that a test doing either without
    the ``native`` marker is failed below, whether the build cache was cold or warm."""
    if event == "subprocess.Popen":
        argv = [str(a) for a in ([args[1]] if isinstance(args[1], (str, bytes, os.PathLike)) else args[1] or ())]
        if {Path(a).name for a in argv[:4]} & {"cc", "gcc", "clang", "zig", "cmake", "ziglang"}:
            _COMPILED.append(" ".join(argv[:6]))
    elif event == "ctypes.dlopen" and isinstance(args[0], str):
        lib = Path(args[0])
        if ".pytest_cache" in lib.parts or (len(lib.parents) > 2 and (lib.parents[2] / "sources").is_dir()):
            _COMPILED.append(f"loads {lib}")


_COMPILED: list[str] = []


def pytest_configure(config):
    import sys

    sys.addaudithook(_native_used)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Every test of a tests/test_native_*.py file and every test that uses the native build cache
    (itself or through a fixture) is ``native``: a new test of a native FMU is in the native loop
    without anyone marking it."""
    for item in items:
        if item.path.name.startswith("test_native_") or "native_build_cache" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.native)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """A test (or its fixtures) that compiled or loaded native code but is not marked ``native``
    fails, naming what: the edit loop (``-m "not slow and not native"``) stays free of C builds. A
    ``slow`` one (outside the edit loop either way) is warned about instead: ``-m native`` misses it."""
    outcome = yield
    report = outcome.get_result()
    compiled = list(_COMPILED)
    _COMPILED.clear()
    if compiled and report.passed and item.get_closest_marker("native") is None:
        why = (f"{item.nodeid} ({report.when}) built or loaded native code without the native marker "
               f"({compiled[0]}): mark it @pytest.mark.native, or build through native_build_cache")
        if item.get_closest_marker("slow") is not None:
            item.warn(pytest.PytestWarning(why))
        else:
            report.outcome = "failed"
            report.longrepr = why


@pytest.fixture(scope="session")
def code_cache(tmp_path_factory):
    """The FMU's code cache (BEARING_FMU_CACHE_DIR, where numba's cache of the bundled kernels
    lives): the user's own, as for any FMU run on this machine (``bearing_fmu.io.cache.fmu_code_cache``),
    so the kernels the main job compiled for this code's bundle (README's first command) are warm
    here too (a session folder of their own compiled them afresh in every fresh clone: 28-45 s, with
    the other workers waiting on its lock). Safe to share: each bundle's folder is named by a hash
    of its sources (changed code gets a new folder) and installed by rename. A session temp dir
    when the variable says "off"."""
    from bearing_fmu.io.cache import fmu_code_cache

    off = os.environ.get("BEARING_FMU_CACHE_DIR", "x").strip().lower() in ("", "0", "off", "no", "none", "false")
    path = tmp_path_factory.mktemp("fmu_code_cache") if off else fmu_code_cache()
    path.mkdir(parents=True, exist_ok=True)
    with pytest.MonkeyPatch.context() as mp:  # the session's: restored at its end
        mp.setenv("BEARING_FMU_CACHE_DIR", str(path))
        yield path


def _module_names(pkg: Path) -> dict[str, Path]:
    """Every module of the package folder ``pkg`` by dotted name (a package by its own name)."""
    out = {}
    for f in sorted(pkg.rglob("*.py")):
        if "__pycache__" not in f.parts:
            out[".".join(f.relative_to(pkg.parent).with_suffix("").parts).removesuffix(".__init__")] = f
    return out


def _uses(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The modules of ``modules`` that module ``name`` can run: its imports at any depth (inside
    functions too), the packages above each, and the modules named by a string constant (the
    registry's "internals.linear:create" references, imported when called)."""
    import ast

    top = name.split(".")[0]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_bytes())):
        if isinstance(node, ast.ImportFrom):
            base = (".".join(package.split(".")[: len(package.split(".")) - node.level + 1]) if node.level else "")
            mod = ".".join(p for p in (base, node.module or "") if p)
            found |= {mod, *(f"{mod}.{a.name}" for a in node.names)}
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and len(node.value) < 200:
            ref = node.value.partition(":")[0].lstrip(".")
            found |= {ref, f"{top}.{ref}"}
    out = set()
    for mod in found & modules.keys():
        parts = mod.split(".")
        out |= {".".join(parts[:i]) for i in range(1, len(parts) + 1)}
    return out


def source_files(*roots: str, root: Path = ROOT) -> list[Path]:
    """The source files that code under ``roots`` (dotted names: "bearing_fmu.fmu.native") can
    read, found from the sources as they are now (so a module moved or a C file split is followed,
    nothing listed by hand): the modules under the roots and every module they use (``_uses``,
    followed to the end), and the data beside them: a used package's files other than Python
    modules and its folders that are no package (bearing_fmu/fmu/native/c/), at any depth."""
    pkg = root / roots[0].split(".")[0]
    modules = _module_names(pkg)
    todo = [m for m in modules if any(m == r or m.startswith(r + ".") for r in roots)]
    seen: set[str] = set()
    while todo:
        m = todo.pop()
        if m not in seen:
            seen.add(m)
            todo += _uses(m, modules[m], modules) - seen
    files = {modules[m] for m in seen}
    for m in seen:
        if modules[m].name == "__init__.py":
            folder = modules[m].parent
            files |= {f for f in folder.iterdir() if f.is_file() and f.suffix not in (".py", ".pyc")}
            for sub in folder.iterdir():
                if sub.is_dir() and sub.name != "__pycache__" and not (sub / "__init__.py").exists():
                    files |= {f for f in sub.rglob("*") if f.is_file() and "__pycache__" not in f.parts}
    return sorted(files)


def sources_digest(*roots: str) -> str:
    """A hash of ``source_files(*roots)``: names and contents."""
    h = hashlib.sha256()
    for p in source_files(*roots):
        h.update(p.relative_to(ROOT).as_posix().encode() + b"\0" + p.read_bytes() + b"\0")
    return h.hexdigest()


# What a native build runs: the native package (its generators, its C), and whatever they use.
NATIVE_BUILD = ("bearing_fmu.fmu.native",)
# What the Taylor film fit runs: the fitting, and the surrogate file it is saved as.
TAYLOR_FIT = ("bearing_fmu.fitting", "bearing_fmu.surrogates.surrogate", "bearing_fmu.physics.params")


@pytest.fixture(scope="session")
def native_build_cache(request):
    """cached(target, build, inputs, settings) -> target: a native FMU built by ``build(target)``,
    or, when an earlier session built one from the same inputs, a copy of that one (kept in
    .pytest_cache/d/native-fmu). The key hashes everything a native build reads: the sources of
    bearing_fmu it uses (Python and C), the data files ``inputs``, the ``settings`` (internal, options, how
    it is built), the C compiler ($CC or cc, and its --version), fmpy's version (the FMI headers).
    Changed code or data builds afresh, so every test still checks what today's code builds; an
    unchanged build is not compiled again (7 compiles, 6-9 s of every run on 2 cores). Only the
    current sources' folder is kept. Without the cache plugin (-p no:cacheprovider) it builds.
    The sources hashed are the ones a native build uses (``source_files(*NATIVE_BUILD)``): an
    edit elsewhere (the rotor host, the fitting, the command lines, the pythonfmu slave) keeps
    every native FMU; every test using this fixture is marked ``native`` (``-m "not native"``
    skips them all)."""
    import shutil
    import subprocess

    import fmpy

    from bearing_fmu.fmu.native.build import NativeBuildError, find_compiler

    cache = getattr(request.config, "cache", None)
    root = None
    try:
        cc = find_compiler()
        version = subprocess.run([cc, "--version"], capture_output=True, text=True, timeout=30).stdout
    except (NativeBuildError, OSError):
        cache = None  # no compiler: the build says so itself
    if cache is not None:
        env = hashlib.sha256(f"{sources_digest(*NATIVE_BUILD)}|{cc}|{version}|fmpy {fmpy.__version__}"
                             .encode()).hexdigest()
        top = cache.mkdir("native-fmu")
        for old in top.iterdir():  # builds of other sources: never used again
            if old.name != env[:16]:
                shutil.rmtree(old, ignore_errors=True)
        root = top / env[:16]
        root.mkdir(exist_ok=True)

    def cached(target: Path, build, inputs=(), settings=(), code=()) -> Path:
        """``code``: modules beyond the native build that ``build`` runs, hashed by their own
        files (a build through the command line: ("bearing_fmu.cli",), its parsing)."""
        if root is None:
            return build(target)
        h = hashlib.sha256(repr((target.name, settings)).encode())
        for name in code:
            path = ROOT.joinpath(*name.split("."))
            for p in sorted(path.rglob("*.py")) if path.is_dir() else [path.with_suffix(".py")]:
                h.update(b"\0" + p.relative_to(ROOT).as_posix().encode() + b"\0" + p.read_bytes())
        for f in inputs:
            h.update(b"\0" + Path(f).name.encode() + b"\0" + Path(f).read_bytes())
        kept = root / f"{h.hexdigest()[:24]}.fmu"
        # one build per key: a second pytest-xdist worker asking for it waits for the first's
        with open(kept.with_suffix(".lock"), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if kept.is_file():
                shutil.copyfile(kept, target)
                return target
            build(target)
            tmp = kept.with_suffix(f".{os.getpid()}.tmp")
            shutil.copyfile(target, tmp)
            os.replace(tmp, kept)  # whole or not at all, if another session writes it too
        return target

    return cached


@pytest.fixture(scope="session")
def contract_data(tmp_path_factory):
    """The data files of the internals' contract cases (``bearing_fmu.internals.cases``), made
    once: the made-up surrogate and the coarse map, which the session FMU bundles too."""
    return tmp_path_factory.mktemp("contract_data")


@pytest.fixture(scope="session")
def surrogate_file(contract_data):
    """An order-2 surrogate of the paper bearing at 22 Hz with made-up coefficients: the FMU
    must reproduce the Taylor internal exactly, whatever the coefficients."""
    from bearing_fmu.internals.cases import surrogate_file

    return surrogate_file(contract_data)


@pytest.fixture(scope="session")
def taylor_film_file(request, tmp_path_factory):
    """A Taylor surrogate with its film fit (format version 2) of the ISO VG 46 paper bearing
    (rotor_host/bundled/bearing_paper_vg46.toml) at 44 Hz under 16.7 N: order 3 over a disc of 0.3 CR about the
    equilibrium, |v| <= 0.3 omega CR, 200 training states (the recipe of tests/test_taylor_flows.py,
    smaller: ~20 s). Kept in .pytest_cache/d/taylor-film under a hash of the sources the fit uses
    (``source_files(*TAYLOR_FIT)``; a second session, or pytest-xdist worker, reads it; changed
    code fits afresh)."""
    from bearing_fmu.fitting import FitRecipe, fit_condition
    from bearing_fmu.physics.params import BearingParams
    from bearing_fmu.surrogates.surrogate import save_surrogate

    bearing = MODELS / "bearing_paper_vg46.toml"
    cache = getattr(request.config, "cache", None)
    folder = cache.mkdir("taylor-film") if cache is not None else tmp_path_factory.mktemp("taylor_film")
    key = hashlib.sha256((sources_digest(*TAYLOR_FIT) + bearing.read_text()).encode()).hexdigest()[:16]
    kept = folder / f"vg46_44hz_{key}.json"
    with open(kept.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not kept.is_file():
            res = fit_condition(FitRecipe(load_y=0.0, load_z=-16.7, speed_hz=44.0, order=3, ecc_max=0.8, v_max=0.3,
                                          radius=0.3, n_train=200, n_test=100, prune=False),
                                params=BearingParams.from_toml(bearing), bias_variance=False)
            tmp = save_surrogate(res.surrogate, kept.with_suffix(f".{os.getpid()}.tmp"))
            os.replace(tmp, kept)
    target = tmp_path_factory.mktemp("taylor_film") / "vg46_44hz_film.json"
    target.write_bytes(kept.read_bytes())
    return target


@pytest.fixture(scope="session")
def map_file(contract_data):
    """A coarse force map of the paper bearing (Reynolds 32 x 4, table 12 x 16): quick to build;
    its accuracy is the business of tests/test_forcemap.py."""
    from bearing_fmu.internals.cases import map_file

    return map_file(contract_data)


@pytest.fixture(scope="session")
def fmu(tmp_path_factory, code_cache, contract_data, surrogate_file, map_file):
    """The bearing FMU, built once, with ``surrogate_file`` and ``map_file`` bundled; its bundled
    kernels compiled once for all workers (``_compile_bundle_once``)."""
    from bearing_fmu.fmu.build import build_fmu

    path = build_fmu(tmp_path_factory.mktemp("fmu") / "bearing.fmu", surrogate=[surrogate_file, map_file])
    _compile_bundle_once(path, code_cache, contract_data)
    return path


def _compile_bundle_once(fmu: Path, code_cache: Path, data_dir: Path) -> None:
    """numba's cache of the FMU's bundled code filled by one process: the first session or
    pytest-xdist worker to use this code steps the FMU once with each registered internal that has
    compiled kernels (from its contract case), under a lock, and the others then load the cache.
    After an edit of a module the FMU bundles, two workers would otherwise compile the same
    kernels side by side (twice the CPU; on a shared machine, twice the time)."""
    from bearing_fmu.fmu.build import package_name
    from bearing_fmu.internals import registry

    done = Path(code_cache) / f"{package_name()}.compiled"
    with open(done.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if done.exists():
            return
        drive = _example("drive_fmu_with_fmpy")
        for spec in registry.REGISTRY.values():
            if not spec.kernels or callable(spec.factory) or not spec.can.fmu:  # only what the FMU computes
                continue
            case = spec.contract_case(data_dir)
            options = {**case.options, **{key: Path(p).name for key, p in case.files.items()}}
            if case.params is not None:  # the case's own bearing (a bore the paper bearing lacks: tilting pads)
                from bearing_fmu.fmu.ports import port_defaults

                p = case.params
                options = {"D": p.D, "L": p.L, "CR": p.CR, "mu": p.mu, **port_defaults(p, pads=True), **options}
            inst = drive.BearingInstance(fmu, {"internal": spec.name, **options})
            try:
                inst.step(1e-4, *case.state, case.omega)
            finally:
                inst.close()
        done.touch()


@pytest.fixture(scope="session")
def unzip(fmu):
    import fmpy

    return fmpy.extract(str(fmu))


def _example(name: str):
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="session")
def fmu_instance(fmu, unzip):
    """fmu_instance(**parameters): an initialised instance of the session FMU through fmpy
    (examples/drive_fmu_with_fmpy.py's BearingInstance: set, step, get, messages, close)."""
    ex = _example("drive_fmu_with_fmpy")
    return lambda **params: ex.BearingInstance(fmu, params, unzip_dir=unzip)


def central_jacobian(force, x, omega, steps):
    """(dF/dq (2, 2), dF/dv (2, 2)) of ``force(y, z, vy, vz, omega)`` at x = (y, z, vy, vz) by
    central differences with one step per variable: independent of any analytic Jacobian."""
    x = np.asarray(x, float)
    cols = []
    for j, h in enumerate(steps):
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        cols.append((np.array(force(*xp, omega)) - np.array(force(*xm, omega))) / (2 * h))
    jac = np.column_stack(cols)
    return jac[:, :2], jac[:, 2:]


@pytest.fixture(name="central_jacobian")
def central_jacobian_fixture():
    return central_jacobian


def write_scene(folder: Path, body: str, name: str = "s.toml", rotor: Path = ROTOR) -> Path:
    """A scene file in ``folder`` on the paper rotor (unless the body names one) from TOML text."""
    text = textwrap.dedent(body)
    if "rotor =" not in text:
        text = f'rotor = "{rotor.as_posix()}"\n' + text
    p = Path(folder) / name
    p.write_text(text)
    return p


@pytest.fixture(name="write_scene")
def write_scene_fixture(tmp_path):
    """write_scene(body, name="s.toml"): a scene file in this test's tmp_path."""
    return lambda body, name="s.toml", **kw: write_scene(tmp_path, body, name, **kw)


# ------------------------------------------------------------ FMI 2.0 states, serialised

def serialised_state(raw) -> bytes:
    """The FMU's current state serialised (fmi2GetFMUstate, fmi2SerializedFMUstateSize,
    fmi2SerializeFMUstate, fmi2FreeFMUstate, each asserted OK), through ``raw.call(name, *args)``
    (the Python FMU's ``tests.test_fmi_status.Raw`` or the native FMU's ``test_native_fmu.Raw``)."""
    import ctypes

    state = ctypes.c_void_p()
    assert raw.call("fmi2GetFMUstate", ctypes.byref(state)) == 0
    size = ctypes.c_size_t()
    assert raw.call("fmi2SerializedFMUstateSize", state, ctypes.byref(size)) == 0
    buf = (ctypes.c_char * size.value)()
    assert raw.call("fmi2SerializeFMUstate", state, buf, size) == 0
    assert raw.call("fmi2FreeFMUstate", ctypes.byref(state)) == 0
    return bytes(buf)


def restore_state(raw, blob: bytes) -> int:
    """fmi2DeSerializeFMUstate of ``blob`` and, if that is OK, fmi2SetFMUstate of it (the copy freed
    after, asserted OK): the status of the first call that is not OK, or of the last."""
    import ctypes

    state = ctypes.c_void_p()
    status = raw.call("fmi2DeSerializeFMUstate", ctypes.create_string_buffer(blob, len(blob)), len(blob),
                      ctypes.byref(state))
    if status == 0:
        status = raw.call("fmi2SetFMUstate", state)
        assert raw.call("fmi2FreeFMUstate", ctypes.byref(state)) == 0
    return status


def logging_slave(fmu, unzip, name: str = "refused"):
    """(an instantiated FMI 2 Co-Simulation instance of ``fmu`` with logging on, the list its logger
    appends every message to, its variables by name): for the tests that read what an FMU says."""
    from fmpy import calloc, free, read_model_description
    from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                           fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

    md = read_model_description(str(fmu))
    log = []
    inst = FMU2Slave(guid=md.guid, unzipDirectory=str(unzip), modelIdentifier=md.coSimulation.modelIdentifier,
                     instanceName=name)
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(lambda *a: log.append(a[-1].decode()))
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    inst.instantiate(callbacks=cb, loggingOn=True)  # (fmpy keeps cb alive with the instance)
    return inst, log, {v.name: v for v in md.modelVariables}


# ------------------------------------------------------------ commands as subprocesses

def start_command(prog, *argv, pause=None, env=None, code_cache=None, new_session=False):
    """Start ``prog argv`` (rotor-host or bearing-fmu) in a subprocess of this checkout; with
    ``pause`` (MODULE:ATTR) through tests/pause_at.py, which holds that function (see there)."""
    import sys

    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", **(env or {})}
    if code_cache is not None:
        env["BEARING_FMU_CACHE_DIR"] = str(code_cache)
    cmd = ([sys.executable, str(ROOT / "tests" / "pause_at.py"), pause, prog] if pause else
           [sys.executable, "-m", {"rotor-host": "rotor_host.cli", "bearing-fmu": "bearing_fmu.cli"}[prog]])
    return subprocess.Popen(cmd + [str(a) for a in argv], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=new_session)


def wait_for(marker: Path, proc, timeout: float = 120.0) -> None:
    """Wait until the paused command wrote ``marker`` (failing if it ended first)."""
    t0 = time.monotonic()
    while not marker.exists():
        assert proc.poll() is None, f"the command ended before the pause: {proc.communicate()}"
        assert time.monotonic() - t0 < timeout, "the command did not reach the pause"
        time.sleep(0.02)


# ------------------------------------------------------------ file systems that refuse writes

@pytest.fixture
def tmpfs():
    """tmpfs(folder, size="64k"): a small tmpfs mounted at folder (made), unmounted after the test."""
    mounted = []

    def mount(folder, size="64k"):
        folder.mkdir(parents=True, exist_ok=True)
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)], check=True)
        mounted.append(folder)
        return folder

    yield mount
    for folder in reversed(mounted):
        subprocess.run(["umount", "-l", str(folder)], check=False)


def fill(folder, leave_bytes=0):
    """Fill the file system of ``folder`` up to ``leave_bytes`` free (tmpfs counts 4 kB pages)."""
    st = os.statvfs(folder)
    with open(folder / "filler", "wb") as f:
        f.write(b"\0" * max(0, st.f_bavail * st.f_frsize - leave_bytes))


def read_only(folder, timeout=10.0):
    """Remount ``folder``'s tmpfs read-only (retried while a file there is open for writing)."""
    t0 = time.monotonic()
    while subprocess.run(["mount", "-o", "remount,ro", str(folder)], capture_output=True).returncode != 0:
        assert time.monotonic() - t0 < timeout, f"cannot remount {folder} read-only"
        time.sleep(0.05)


# ----------------------------------------------------------------------------- the paper scene

PAPER_UNBALANCE_G = 8.5  # rotor_host/bundled/scenes/paper_22hz.toml: 8.5 g at 37 mm on the disk (node 6), phase 0


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, Path):
        value = value.as_posix()
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    raise TypeError(f"no TOML for {value!r}")


def paper_scene_text(*, name: str | None = None, internal: str = "reynolds", via: str | None = "direct",
                     t_end: float = 0.01, dt: float = 1e-4, grid: tuple[int, int] | None = None,
                     unbalance_g: float | None = PAPER_UNBALANCE_G, unbalance_node: int = 6, **more) -> str:
    """The TOML text of the paper's 22 Hz scene (rotor_host/bundled/scenes/paper_22hz.toml: the paper rotor at
    22 Hz, 8.5 g at 37 mm on the disk) in the form the tests run it: called directly, 10 ms at
    dt = 1e-4 s, the Reynolds solver's default grid. Each keyword changes one thing: ``internal``,
    ``via`` (None: the key left out, i.e. fmu), ``t_end``, ``dt`` [s], ``grid`` = (n_theta, n_x)
    (the [reynolds] table), ``unbalance_g`` (None or 0: no unbalance), ``unbalance_node``; any
    other keyword is a top-level key (``name``, ``fmu``, ``fmu_kind``, ``speed_hz``, ...; None
    leaves it out), a table when its value is a dict (``record={"nodes": [3, 6, 9]}``, ``map=``,
    ``taylor=``; merged into [reynolds] or [time] when those) or an array of tables when a list
    of dicts (``static_loads=[{"node": 9, "Fz_N": -1e9}]``; ``unbalance=[...]`` replaces the
    paper's)."""
    keys = {"name": name, "rotor": ROTOR, "internal": internal, "via": via, "speed_hz": 22.0}
    tables = {"reynolds": {"n_theta": grid[0], "n_x": grid[1]}} if grid else {}
    tables["time"] = {"t_end_s": t_end, "dt_s": dt}
    arrays = {}
    if unbalance_g:
        arrays["unbalance"] = [{"node": unbalance_node, "mass_kg": unbalance_g / 1000, "radius_mm": 37.0,
                                "phase_deg": 0.0}]
    for key, value in more.items():
        if isinstance(value, dict):
            tables[key] = {**tables.get(key, {}), **value}
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            arrays[key] = value
        else:
            keys[key] = value
    lines = [f"{k} = {_toml(v)}" for k, v in keys.items() if v is not None]
    for title, rows in [*((t, [d]) for t, d in tables.items()), *((f"[{t}]", ds) for t, ds in arrays.items())]:
        for d in rows:
            lines += ["", f"[{title}]", *(f"{k} = {_toml(v)}" for k, v in d.items() if v is not None)]
    return "\n".join(lines) + "\n"


@pytest.fixture
def paper_scene(tmp_path):
    """paper_scene(folder=tmp_path, file=None, **overrides) -> the path of the paper's 22 Hz scene
    written as ``paper_scene_text(**overrides)`` (see there: what each keyword changes) into
    ``folder``, as ``file`` (default: <name>.toml when a name is given, else s.toml)."""

    def write(folder: Path | None = None, file: str | None = None, **overrides) -> Path:
        name = overrides.get("name")
        p = Path(folder or tmp_path) / (file or (f"{name}.toml" if name else "s.toml"))
        p.write_text(paper_scene_text(**overrides))
        return p

    return write


def run_cli(prog: str, argv: list[str], capsys) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of ``prog``'s main(argv) in this process: argparse exits
    (SystemExit with its code), main returns its code."""
    from bearing_fmu.cli import main as bearing_fmu
    from rotor_host.cli import main as rotor_host

    try:
        code = {"rotor-host": rotor_host, "bearing-fmu": bearing_fmu}[prog](argv)
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def damaged_map_refused(data: dict, damage, expected: str, folder: Path, load) -> None:
    """A force map file's parsed JSON ``data`` changed by ``damage(data)`` and written to ``folder``:
    ``load`` (the loader) refuses it with one line naming the file and matching ``expected``."""
    damage(data)
    bad = folder / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=rf"force map file {bad}: .*{expected}"):
        load(bad)


def compliance_checker() -> Path:
    """The FMU Compliance Checker's Linux binary beside the repository (shared/tools/, see its
    README); in CI its absence fails the test, elsewhere it is one skip line (-rs) naming it."""
    for base in (ROOT.parent, ROOT.parent.parent):
        path = base / "shared" / "tools" / "fmu-compliance-checker" / "fmuCheck.linux64"
        if path.is_file():
            return path
    if os.environ.get("CI"):
        raise AssertionError("the FMU Compliance Checker is not in ../shared/tools/fmu-compliance-checker/")
    pytest.skip("the FMU Compliance Checker (../shared/tools/fmu-compliance-checker/) is not here")
