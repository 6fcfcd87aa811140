"""Fixtures shared by the test modules: one bearing FMU per session (with a made-up surrogate
bundled), its extraction and instances, a scene writer, the central-difference Jacobian, and
file systems that refuse writes (a small tmpfs: full, or remounted read-only; as root)."""

import math
import os
import subprocess
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest


ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
ROTOR = MODELS / "rotor_paper.toml"
OMEGA_22HZ = 2 * math.pi * 22.0


@pytest.fixture(scope="session")
def code_cache(tmp_path_factory):
    """The FMU's code cache (BEARING_FMU_CACHE_DIR, where numba's cache lives too): a session temp dir."""
    path = tmp_path_factory.mktemp("fmu_code_cache")
    old = os.environ.get("BEARING_FMU_CACHE_DIR")
    os.environ["BEARING_FMU_CACHE_DIR"] = str(path)
    yield path
    if old is None:
        os.environ.pop("BEARING_FMU_CACHE_DIR", None)
    else:
        os.environ["BEARING_FMU_CACHE_DIR"] = old


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
def map_file(contract_data):
    """A coarse force map of the paper bearing (Reynolds 32 x 4, table 12 x 16): quick to build;
    its accuracy is the business of tests/test_forcemap.py."""
    from bearing_fmu.internals.cases import map_file

    return map_file(contract_data)


@pytest.fixture(scope="session")
def fmu(tmp_path_factory, code_cache, surrogate_file, map_file):
    """The bearing FMU, built once, with ``surrogate_file`` and ``map_file`` bundled."""
    from bearing_fmu.fmu.build import build_fmu

    return build_fmu(tmp_path_factory.mktemp("fmu") / "bearing.fmu", surrogate=[surrogate_file, map_file])


@pytest.fixture(scope="session")
def unzip(fmu):
    fmpy = pytest.importorskip("fmpy")
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
