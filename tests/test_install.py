"""The package works outside its checkout: its wheel, installed into a folder of its own, runs
the commands from an empty folder with empty caches (the bundled machines are package data).

The wheel is built by pip from this checkout (PEP 517, the backend of pyproject.toml) and
installed with ``--no-deps --target``: the dependencies are this interpreter's, and PYTHONPATH
puts the installed copy before any editable install of the checkout (checked, not assumed).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BUNDLED = ROOT / "rotor_host" / "bundled"


def _pip(*args: str, cwd: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "pip", *args], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"pip {' '.join(args)} failed:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}"


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(folder the wheel is installed into, the wheel): built from a copy of the checkout's
    tracked files, so a file left out of the package data is missing here as it would be on PyPI."""
    base = tmp_path_factory.mktemp("install")
    src = base / "src"
    src.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True, check=True).stdout
    for name in filter(None, archive.decode().split("\0")):
        f = ROOT / name
        if f.is_file():
            (src / name).parent.mkdir(parents=True, exist_ok=True)
            (src / name).write_bytes(f.read_bytes())
    _pip("wheel", "--no-deps", "-q", "-w", str(base / "dist"), str(src), cwd=base)
    (wheel,) = (base / "dist").glob("bearing_fmu-*.whl")
    _pip("install", "--no-deps", "-q", "--target", str(base / "site"), str(wheel), cwd=base)
    return base / "site", wheel


def _command(site: Path, name: str, *args: str, cwd: Path, cache: Path) -> subprocess.CompletedProcess:
    """An installed console script, run from ``cwd`` with the installed copy first on the path and
    empty caches (numba's, the FMU builds')."""
    env = {**os.environ, "PYTHONPATH": str(site), "MPLBACKEND": "Agg", "NUMBA_CACHE_DIR": str(cache / "numba"),
           "BEARING_FMU_BUILD_CACHE": str(cache / "fmus"), "XDG_CACHE_HOME": str(cache / "xdg")}
    return subprocess.run([str(site / "bin" / name), *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=900)


@pytest.mark.slow  # a wheel built and installed, the bearing kernels compiled once: 1-3 min
def test_the_wheel_runs_from_an_empty_folder(installed, tmp_path):
    site, wheel = installed
    shipped = {p.relative_to(BUNDLED).as_posix() for p in BUNDLED.rglob("*") if p.is_file() and p.suffix in
               (".toml", ".json")}
    inside = {n.removeprefix("rotor_host/bundled/") for n in zipfile.ZipFile(wheel).namelist()
              if n.startswith("rotor_host/bundled/")}
    assert shipped and shipped <= inside, f"bundled files missing from the wheel: {sorted(shipped - inside)}"

    empty = tmp_path / "empty"
    empty.mkdir()
    cache = tmp_path / "cache"
    which = _command(site, "rotor-host", "paper", "--help", cwd=empty, cache=cache)
    assert which.returncode == 0, which.stderr
    where = subprocess.run([sys.executable, "-c", "import rotor_host.bundled as b; print(b.folder())"], cwd=empty,
                           env={**os.environ, "PYTHONPATH": str(site)}, capture_output=True, text=True, check=True)
    assert Path(where.stdout.strip()).is_relative_to(site), f"imported the checkout, not the wheel: {where.stdout}"
    assert (Path(where.stdout.strip()) / "scenes" / "paper_22hz.toml").is_file()

    demo = _command(site, "bearing-fmu", "demo", "--json", cwd=empty, cache=cache)
    assert demo.returncode == 0, demo.stderr
    point = json.loads(demo.stdout)  # stdout is the JSON alone: the compile notice goes to stderr
    assert 0.0 < point["eccentricity"] < 1.0
    assert "compiling the bearing kernels" in demo.stderr, demo.stderr  # an empty numba cache: announced
    again = _command(site, "bearing-fmu", "demo", "--json", cwd=empty, cache=cache)
    assert again.returncode == 0 and json.loads(again.stdout) == point
    assert "compiling" not in again.stderr, again.stderr  # the kernels are in numba's cache now: silent

    run = _command(site, "rotor-host", "run", "paper_22hz", "--via", "direct", "--internal", "map", "--t-end",
                   "0.002", "--no-plots", "--quiet", "--out", "out", cwd=empty, cache=cache)
    assert run.returncode == 0, run.stderr
    assert (empty / "out" / "paper_22hz_map.json").is_file(), sorted(p.name for p in (empty / "out").iterdir())
    stab = _command(site, "rotor-host", "stability", "rotor_paper", "--speeds-hz", "20:21:1", "--internal", "map",
                    "--no-plots", "--out", "out", cwd=empty, cache=cache)  # the default map: the bundled one
    assert stab.returncode == 0, stab.stderr
    assert sorted(p.name for p in empty.iterdir()) == ["out"]  # nothing else written into the user's folder
