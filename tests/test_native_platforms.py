"""The native FMU's binaries for every desktop platform (bearing_fmu/fmu/native/compile.py):
what each binary exports and needs, read by our own reader and by binutils / LLVM; the Linux
binary's glibc baseline; the universal macOS binary; the sources clean under every compiler's
warnings; the data's decimal literals exact. One FMU of each kind (map, taylor, linear, reynolds) built
once per session with all three platforms.
"""

import math
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from conftest import compliance_checker

fmpy = pytest.importorskip("fmpy")

from bearing_fmu.fmu.native.compile import PLATFORMS, fmi_headers  # noqa: E402
from bearing_fmu.fmu.native.objfile import exports_and_imports, fat_slices, glibc_versions  # noqa: E402

# cross-compiles for every platform and runs wine: end to end, in CI (the whole suite)
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
FH = fmi_headers()
# the FMI 2.0 functions: what fmi2Functions.h declares
FMI2 = set(re.findall(r"#define (fmi2\w+)\s+fmi2FullName\(\1\)", (FH / "fmi2Functions.h").read_text()))


@pytest.fixture(scope="session")
def every_platform(tmp_path_factory):
    """kind -> (fmu, extracted dir): map, taylor, linear, reynolds, several (taylor and reynolds in one)
    and tilting_pad native FMUs with every platform's binary."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.physics.params import BearingParams

    folder = tmp_path_factory.mktemp("platforms")
    out = {"map": build_native_fmu(folder / "map.fmu", "map", map=PAPER_MAP),
           "taylor": build_native_fmu(folder / "taylor.fmu", "taylor", surrogate=SURROGATE),
           "linear": build_native_fmu(folder / "linear.fmu", "linear",
                                      options={"linear_from": "map", "map": str(PAPER_MAP)}),
           # the Reynolds solver on the lemon bore (grooves, lobes: every path of its grid), a 64 x 8 grid
           "reynolds": build_native_fmu(folder / "reynolds.fmu", "reynolds", options={"n_theta": 64, "n_x": 8},
                                        bearing=BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / "bearing_paper_lemon.toml")),
           # several internals in one binary (bn_parts.c), Taylor falling back to Reynolds; its surrogate
           # with a (made-up) film fit: the Taylor film report and its fallback compiled too (taylor_film.c)
           "several": build_native_fmu(folder / "several.fmu", "taylor,reynolds", surrogate=_with_film(folder),
                                       options={"domain_action": "fallback", "n_theta": 64, "n_x": 8}),
           # five tilting pads (c/internal_tilting_pad.c over the Reynolds solver; tests/test_native_pads.py)
           "tilting_pad": build_native_fmu(folder / "tilting_pad.fmu", "tilting_pad",
                                           bearing=BearingParams.from_toml(ROOT / "rotor_host" / "bundled" /
                                                                           "bearing_paper_5pad_lbp.toml"))}
    return {k: (fmu, Path(fmpy.extract(str(fmu)))) for k, fmu in out.items()}


def _with_film(folder: Path) -> Path:
    """SURROGATE with a made-up film fit (file version 2: J_s = 0.2, J_i = 0.3 cos beta), its force
    the file's."""
    from bearing_fmu.surrogates.film import FilmFit, n_features
    from bearing_fmu.surrogates.surrogate import load_surrogate, save_surrogate

    sur = load_surrogate(SURROGATE)
    coef = np.zeros((2, n_features(1, 1)))
    coef[0, 0], coef[1, 1] = 0.2, 0.3
    sur.film = FilmFit(1, 1, coef)
    return save_surrogate(sur, folder / "paper_22hz_film.json")


def binary(unzip: Path, platform: str) -> Path:
    return next((unzip / "binaries" / platform).glob("*" + PLATFORMS[platform].ext))


def test_every_fmu_has_every_platform(every_platform):
    for kind, (fmu, unzip) in every_platform.items():
        md = fmpy.read_model_description(str(fmu))
        ident = md.coSimulation.modelIdentifier
        names = set(zipfile.ZipFile(fmu).namelist())
        for p in PLATFORMS.values():
            assert f"binaries/{p.name}/{ident}{p.ext}" in names, (kind, p.name)


def test_exports_only_the_fmi_functions_and_needs_only_the_c_runtime(every_platform):
    allowed = {"linux64": lambda n: n in ("libc.so.6", "libm.so.6"),
               "win64": lambda n: n.lower().startswith("api-ms-win-crt-") or n.lower() == "kernel32.dll",
               "darwin64": lambda n: n == "/usr/lib/libSystem.B.dylib"}
    for kind, (_fmu, unzip) in every_platform.items():
        for name in PLATFORMS:
            links = exports_and_imports(binary(unzip, name).read_bytes())
            assert [link.cpu for link in links] == (["x86_64", "arm64"] if name == "darwin64" else ["x86_64"])
            for link in links:
                linker = {"_mh_dylib_header", "__dso_handle"} if link.format == "macho" else set()
                assert set(link.exports) - linker == FMI2, (kind, name, set(link.exports) ^ FMI2)
                assert link.libraries and all(allowed[name](n) for n in link.libraries), (kind, name, link.libraries)
                assert not any("python" in i.lower() for i in link.imports)


def test_linux_binary_needs_glibc_2_17_at_most(every_platform):
    for kind, (_fmu, unzip) in every_platform.items():
        link, = exports_and_imports(binary(unzip, "linux64").read_bytes())
        versions = glibc_versions(link)
        assert versions and max(versions) <= (2, 17), (kind, versions)


def _tool_exports(path: Path, fmt: str) -> set[str]:
    """The exported symbols as binutils (ELF: nm -D; PE: objdump -p) or LLVM (Mach-O) list them."""
    if fmt == "elf":
        out = subprocess.run(["nm", "-D", "--defined-only", str(path)], capture_output=True, text=True, check=True)
        return {line.split()[-1] for line in out.stdout.splitlines() if line.split()[1] in "TDBRW"}
    if fmt == "pe":
        out = subprocess.run(["objdump", "-p", str(path)], capture_output=True, text=True, check=True).stdout
        table = out.split("[Ordinal/Name Pointer] Table")[1].split("\n\n")[0]
        return {line.split()[-1] for line in table.splitlines() if line.strip().startswith("[")}
    out = subprocess.run(["llvm-objdump", "--macho", "--exports-trie", str(path)], capture_output=True, text=True,
                         check=True).stdout
    return {line.split()[-1].lstrip("_") if line.split()[-1].startswith("_fmi2") else line.split()[-1][1:]
            for line in out.splitlines() if line.startswith("0x")}


def test_our_reader_agrees_with_binutils_and_llvm(every_platform, tmp_path):
    """objfile's exports equal what nm / objdump (binutils) and llvm-objdump list (.ci/run installs them)."""
    for tool in ("nm", "objdump", "llvm-objdump"):
        assert shutil.which(tool), f"{tool} not installed (Debian: binutils, llvm)"
    _fmu, unzip = every_platform["map"]
    for name in PLATFORMS:
        data = binary(unzip, name).read_bytes()
        for k, piece in enumerate(fat_slices(data) if name == "darwin64" else [data]):
            path = tmp_path / f"{name}_{k}"
            path.write_bytes(piece)
            link, = exports_and_imports(piece)
            assert _tool_exports(path, link.format) == set(link.exports), name


def test_darwin_binary_is_universal(every_platform):
    _fmu, unzip = every_platform["taylor"]
    path = binary(unzip, "darwin64")
    out = subprocess.run(["llvm-objdump", "--macho", "--universal-headers", str(path)], capture_output=True,
                         text=True, check=True).stdout
    assert "nfat_arch 2" in out and "CPU_TYPE_X86_64" in out and "CPU_TYPE_ARM64" in out
    assert "align 2^14" in out  # arm64's 16 KiB pages


# ----------------------------------------------------------------------------- the sources

def _sources(unzip: Path) -> list[Path]:
    md = fmpy.read_model_description(str(unzip))
    return [unzip / "sources" / f for f in md.buildConfigurations[0].sourceFileSets[0].sourceFiles]


@pytest.mark.parametrize("kind", ["map", "taylor", "linear", "reynolds", "several", "tilting_pad"])
def test_sources_compile_without_a_warning(every_platform, kind, tmp_path):
    """gcc and clang (zig's, for Windows and arm64 macOS) with -Wall -Wextra -Wpedantic -Werror:
    what `fmpy compile --all-warnings --warning-as-error` asks, in ISO C99."""
    sources_compile_without_a_warning(every_platform[kind][1], tmp_path)


def sources_compile_without_a_warning(unzip: Path, tmp_path: Path) -> None:
    """test_sources_compile_without_a_warning's compiles of the extracted FMU ``unzip``'s sources."""
    from bearing_fmu.fmu.native.compile import NativeBuildError, run_compilers, zig_cc

    flags = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", "-I", str(unzip / "sources"),
             "-I", str(FH)]
    jobs = [([*cmd, *flags, str(src), "-o", str(tmp_path / f"{k}-{j}.o")], f"{cmd[-1]} {src.name}")
            for k, src in enumerate(_sources(unzip))
            for j, cmd in enumerate(([shutil.which("gcc") or "cc"], [*zig_cc(), "-target", "x86_64-windows-gnu"],
                                     [*zig_cc(), "-target", "aarch64-macos"]))]
    try:
        run_compilers(jobs)  # side by side, as many as there are cores
    except NativeBuildError as exc:
        pytest.fail(str(exc)[-3000:])


@pytest.mark.slow
def test_fmpy_compile_with_warnings_as_errors(every_platform, tmp_path):
    """`fmpy compile --all-warnings --warning-as-error`: fmpy's own CMake project, as a user rebuilds it."""
    from bearing_fmu.fmu.native.compile import cmake_executable_dir

    fmu = tmp_path / "map.fmu"
    shutil.copyfile(every_platform["map"][0], fmu)
    env_path = f"{cmake_executable_dir() or ''}:{Path(shutil.which('python3') or '/usr/bin').parent}"
    import os
    import sys

    done = subprocess.run([sys.executable, "-m", "fmpy.cli", "--all-warnings", "--warning-as-error",
                           "compile", str(fmu)], capture_output=True, text=True,
                          env={**os.environ, "PATH": env_path + ":" + os.environ.get("PATH", "")})
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]


def test_decimal_literals_parse_to_the_same_bits(every_platform, tmp_path):
    """The generated data is decimal (MSVC refuses C99 hex floats); the C compiler reads each
    literal back to exactly the double Python wrote (printed with %a and compared bit for bit)."""
    from bearing_fmu.internals.map.tablefile import load_map

    _fmu, unzip = every_platform["map"]
    text = (unzip / "sources" / "model_data.h").read_text()
    assert "0x1." not in text and "p-" not in text.replace("map", "")
    prog = tmp_path / "dump.c"
    prog.write_text('#include <stdio.h>\n#include "model_data.h"\nint main(void) {\n'
                    '    for (size_t i = 0; i < sizeof MAP_C / sizeof MAP_C[0]; i++) printf("%a\\n", MAP_C[i]);\n'
                    '    for (size_t i = 0; i < sizeof MAP_TS / sizeof MAP_TS[0]; i++) printf("%a\\n", MAP_TS[i]);\n'
                    '    return 0;\n}\n')
    exe = tmp_path / "dump"
    subprocess.run([shutil.which("gcc") or "cc", "-std=c99", "-I", str(unzip / "sources"), str(prog), "-o", str(exe)],
                   check=True)
    got = [float.fromhex(x) for x in subprocess.run([str(exe)], capture_output=True, text=True,
                                                      check=True).stdout.split()]
    ts, _tb, C = load_map(PAPER_MAP).spline()
    want = np.concatenate([np.asarray(C, float).ravel(), np.asarray(ts, float)])
    assert len(got) == len(want) and np.array_equal(np.array(got).view(np.int64), want.view(np.int64))


# ----------------------------------------------------------------------------- what a tool sees

def _input_file(fmu: Path, path: Path) -> Path:
    """A 10 ms input signal: the journal on a small circle (0.002 CR) about the start state at the
    start speed (the state each FMU evaluates without a warning)."""
    md = fmpy.read_model_description(str(fmu))
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("y", "z", "omega", "CR")}
    rows = ["time,y,z,vy,vz,omega"]
    for k in range(11):
        t = 1e-3 * k
        a = start["omega"] * t
        r = 0.002 * start["CR"]
        rows.append(f"{t!r},{start['y'] + r * math.cos(a)!r},{start['z'] + r * math.sin(a)!r},"
                    f"{-r * start['omega'] * math.sin(a)!r},{r * start['omega'] * math.cos(a)!r},{start['omega']!r}")
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("kind", ["map", "taylor", "linear", "reynolds", "several", "tilting_pad"])
@pytest.mark.parametrize("interface", ["me", "cs"])
def test_compliance_checker_reports_nothing(every_platform, kind, interface, tmp_path):
    """The Modelica Association's FMU Compliance Checker, started with an empty environment (no
    Python anywhere), simulates each FMU with an input signal: 0 warnings and 0 errors, from the
    FMU and from the checker (its summary counts, not only its exit code)."""
    fmu, _unzip = every_platform[kind]
    log = tmp_path / "check.log"
    done = subprocess.run(["env", "-i", str(compliance_checker()), "-h", "1e-4", "-s", "0.01", "-k", interface, "-i",
                           str(_input_file(fmu, tmp_path / "in.csv")), "-o", str(tmp_path / "out.csv"), "-e", str(log),
                           str(fmu)], capture_output=True, text=True, timeout=300)
    text = log.read_text()
    summary = text[text.index("FMU check summary:"):]
    assert done.returncode == 0, summary
    assert "Simulation finished successfully" in text
    assert "FMU reported:\n\t0 warning(s) and error(s)" in summary, summary
    assert "0 Warning(s)" in summary and "0 Error(s)" in summary, summary
    rows = (tmp_path / "out.csv").read_text().splitlines()
    assert len(rows) >= 100 and rows[0].startswith('"time","Fy","Fz"')


@pytest.mark.parametrize("fmi_type", ["ModelExchange", "CoSimulation"])
def test_fmpy_validates_and_simulates_every_kind(every_platform, fmi_type, tmp_path):
    from fmpy.validation import validate_fmu

    for kind, (fmu, _unzip) in every_platform.items():
        assert validate_fmu(str(fmu)) == [], kind
        rows = _input_file(fmu, tmp_path / f"{kind}.csv").read_text().splitlines()
        table = np.array([tuple(map(float, r.split(","))) for r in rows[1:]],
                         dtype=[(n, float) for n in rows[0].split(",")])
        res = fmpy.simulate_fmu(str(fmu), fmi_type=fmi_type, stop_time=0.01, output_interval=1e-3, input=table,
                                output=["Fy", "Fz", "out_of_domain"])
        assert len(res) >= 11 and np.all(np.isfinite(res["Fy"])) and not res["out_of_domain"].any(), kind


# ----------------------------------------------------------------------------- the Windows binary

def _wine() -> str:
    path = shutil.which("wine64") or ("/usr/lib/wine/wine64" if Path("/usr/lib/wine/wine64").is_file() else None)
    assert path, "wine64 not installed (Debian: apt-get install wine64; .ci/run installs it)"
    return path


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["map", "taylor", "linear", "reynolds", "several", "tilting_pad"])
def test_windows_binary_under_wine_gives_the_linux_binarys_forces(every_platform, kind, tmp_path_factory):
    """example_host.c cross-compiled for Windows with zig runs the win64 binary under wine; the
    same host compiled for Linux runs the linux64 binary: the outputs agree to 1e-13 relative (the
    arithmetic is the same, no fused multiply-add; the C runtimes' atan2, exp, log1p may differ in
    the last bit)."""
    from bearing_fmu.fmu.native.build import C_DIR
    from bearing_fmu.fmu.native.compile import run_compiler, zig_cc

    work = tmp_path_factory.mktemp(f"wine_{kind}")
    hosts = {}
    for name, target, exe in (("win64", "x86_64-windows-gnu", "host.exe"), ("linux64", "x86_64-linux-gnu.2.17", "host")):
        hosts[name] = work / exe
        # -s as the binaries' builds and run where they run (run_compiler): zig keys its C runtime on both,
        # and MinGW's was built again for the host (2 min of one core in a fresh CI, the other worker waiting)
        run_compiler([*zig_cc(), "-target", target, "-O2", "-ffp-contract=off", "-s", str(C_DIR / "example_host.c"),
                      "-I", str(FH), "-o", str(hosts[name])], f"zig cc -target {target} (the test host)")
    fmu, unzip = every_platform[kind]
    md = fmpy.read_model_description(str(fmu))
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("y", "z", "omega", "CR")}
    state = [start["y"] + 1e-3 * start["CR"], start["z"] - 2e-3 * start["CR"], 1e-4, -2e-4, start["omega"]]
    outputs = {}
    prefix = Path.home() / ".cache" / "bearing_fmu_wine"  # kept between runs: wine's first start takes seconds
    for name in ("linux64", "win64"):
        cmd = [str(hosts[name]), str(binary(unzip, name)), md.guid, *map(repr, state)]
        env = {}
        if name == "win64":
            cmd = [_wine(), *cmd]
            env = {"WINEPREFIX": str(prefix), "WINEDEBUG": "-all", "HOME": str(Path.home()),
                   "PATH": "/usr/bin:/bin"}
        done = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
        lines = dict(line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)
        assert done.returncode == 0 and lines.get("status") == "0", (name, done.stdout[-2000:], done.stderr[-2000:])
        outputs[name] = np.array(lines["outputs"].split(), float)
    lin, win = outputs["linux64"], outputs["win64"]
    assert np.all(np.abs(win - lin) <= 1e-13 * np.maximum(np.abs(lin), np.max(np.abs(lin[:2])) * 1e-3)), (lin, win)
