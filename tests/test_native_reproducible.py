"""Two builds of the same inputs are the same bytes on every platform (Linux, Windows, macOS),
and the macOS binaries load on macOS 11 (issue 38 item 5): each slice's minimum-version load
command (LC_BUILD_VERSION's minos, read by our Mach-O reader, bearing_fmu/fmu/native/objfile.py)
is 11.0 and the install name is @rpath/<modelIdentifier>.dylib, not the build's temporary folder.
One small internal (linear), FMI 2.0 (a universal dylib) and 3.0 (one per architecture), built
twice with zig into two folders; no build cache (the point is to build twice). Cross-compiles
like tests/test_native_platforms.py (4-5 zig processes per build, about a minute warm on 2 busy
cores; zig's first run compiles its C runtimes for ten minutes more): slow."""

import shutil
import subprocess
import zipfile

import pytest

from bearing_fmu.fmu.native.compile import MACOS_MIN
from bearing_fmu.fmu.native.objfile import exports_and_imports

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
pytestmark = pytest.mark.slow


def _binaries(fmu: Path) -> dict[str, bytes]:
    with zipfile.ZipFile(fmu) as z:
        return {n: z.read(n) for n in z.namelist() if n.startswith("binaries/") and not n.endswith("/")}


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_two_builds_are_the_same_bytes_and_macos_11(tmp_path, fmi_version):
    pytest.importorskip("ziglang")
    from bearing_fmu.fmu.native.build import build_native_fmu

    opts = {"linear_from": "map", "map": str(PAPER_MAP)}
    builds = []
    for k in (1, 2):
        (tmp_path / str(k)).mkdir()
        fmu = build_native_fmu(tmp_path / str(k) / "linear.fmu", "linear", options=opts, compiler="zig",
                               platforms=["linux64", "win64", "darwin64"], fmi_version=fmi_version)
        builds.append(_binaries(fmu))
    a, b = builds
    assert sorted(a) == sorted(b)
    assert len(a) == (3 if fmi_version == 2 else 5), sorted(a)  # FMI 3.0: x86_64 and aarch64 Linux, macOS
    for name in a:
        assert a[name] == b[name], f"{name}: the two builds differ"
    macs = [n for n in a if n.endswith(".dylib")]
    assert macs
    for name in macs:
        identifier = Path(name).stem
        slices = exports_and_imports(a[name])
        assert len(slices) == (2 if fmi_version == 2 else 1)
        for s in slices:
            assert s.min_os == MACOS_MIN == "11.0", (name, s.cpu, s.min_os)
            assert s.install_name == f"@rpath/{identifier}.dylib", (name, s.install_name)
        assert b"bearing_zig_" not in a[name] and b"/tmp" not in a[name]
        objdump = shutil.which("llvm-objdump")
        if objdump:  # LLVM's reader agrees with ours
            path = tmp_path / Path(name).name
            path.write_bytes(a[name])
            text = subprocess.run([objdump, "--macho", "--private-headers", "--arch", "all", str(path)],
                                  capture_output=True, text=True, timeout=60).stdout
            assert text.count("minos 11.0") == len(slices) and f"name @rpath/{identifier}.dylib" in text, text[:2000]
