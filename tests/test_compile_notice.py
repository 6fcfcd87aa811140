"""The first compilation of the kernels is announced once on stderr, and never when numba's cache
has them (bearing_fmu.internals.warmup.announce_compiling).

A real cold compilation of the bearing kernels takes 10-60 s (tests/test_install.py does one, from
an installed wheel); here a two-function kernel module in a temporary folder, with its own numba
cache folder, stands in for them: its first process compiles (numba's "numba:compile" event), the
second loads it from the cache (no event). The same listener serves the commands."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from bearing_fmu.internals.warmup import NOTICE, CompileNotice

ROOT = Path(__file__).resolve().parents[1]

KERNELS = '''
from numba import njit

@njit(cache=True)
def _half(x):
    return 0.5 * x

@njit(cache=True)
def twice(x):
    return 4.0 * _half(x)
'''

SCRIPT = '''
import sys
from bearing_fmu.internals.warmup import announce_compiling
announce_compiling(packages=("tinykernels",))
announce_compiling(packages=("tinykernels",))  # a second call: still one notice
import tinykernels
print(tinykernels.twice(2.0))
print(tinykernels.twice(3))  # another signature: compiled, not announced again
'''


def _run(folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(folder), str(ROOT)]),
           "NUMBA_CACHE_DIR": str(folder / "numba-cache")}
    return subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=300,
                          cwd=folder)


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_announced_once_when_compiling_and_never_when_cached(tmp_path):
    (tmp_path / "tinykernels.py").write_text(KERNELS)
    cold = _run(tmp_path)
    assert cold.returncode == 0, cold.stderr
    assert cold.stdout.split() == ["4.0", "6.0"]  # stdout is the program's alone
    assert cold.stderr.count("compiling the bearing kernels, once per installation") == 1, cold.stderr
    assert NOTICE in cold.stderr
    warm = _run(tmp_path)  # the same source: numba's disk cache has both signatures
    assert warm.returncode == 0, warm.stderr
    assert warm.stdout.split() == ["4.0", "6.0"]
    assert "compiling" not in warm.stderr, warm.stderr


class _Event:
    def __init__(self, module: str, start: bool):
        def func():
            pass

        func.__module__ = module
        self.data = {"dispatcher": type("D", (), {"py_func": func})()}
        self.is_start, self.is_end = start, not start


def test_only_the_packages_kernels_and_the_outer_compilation_count():
    said = []
    notice = CompileNotice(said.append, packages=("bearing_fmu", "rotor_host"))
    for module in ("numba.np.arraymath", "scipy.something"):  # numba's own overloads, another library's kernels
        notice.notify(_Event(module, True))
        notice.notify(_Event(module, False))
    assert said == []
    notice.notify(_Event("bearing_fmu_v0_1_0_abc.physics.solver.reynolds_kernels", True))  # a Python FMU's copy
    notice.notify(_Event("bearing_fmu.physics.solver.reynolds_kernels", True))  # a callee, compiled inside it
    notice.notify(_Event("bearing_fmu.physics.solver.reynolds_kernels", False))
    notice.notify(_Event("bearing_fmu_v0_1_0_abc.physics.solver.reynolds_kernels", False))
    notice.notify(_Event("rotor_host.integrate.newmark_kernels", True))
    notice.notify(_Event("rotor_host.integrate.newmark_kernels", False))
    assert said == [NOTICE]


def test_the_commands_and_the_fmu_install_it():
    """Read from the sources (a cold run of each would take minutes): each entry point asks for it."""
    for path, call in (("bearing_fmu/cli.py", "announce_compiling()"), ("rotor_host/cli/__init__.py", "announce_compiling()"),
                       ("bearing_fmu/fmu/slave.py", "warmup.announce_compiling()")):
        text = textwrap.dedent((ROOT / path).read_text())
        assert call in text, f"{path} does not announce the kernels' first compilation"
