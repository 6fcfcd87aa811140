"""Compile a native FMU's C sources into its binaries: every desktop platform from any machine
with zig (the ``ziglang`` pip package), or the host platform with the system C compiler or fmpy's
CMake project.

| platform | binaries/ folder | zig target(s) | file |
|---|---|---|---|
| linux64 | linux64 | x86_64-linux-gnu.2.17 (glibc 2.17, the manylinux2014 baseline) | .so |
| win64 | win64 | x86_64-windows-gnu (the Universal C Runtime) | .dll |
| darwin64 | darwin64 | x86_64-macos.11.0 and aarch64-macos.11.0 (macOS 11), joined into one universal binary | .dylib |

Every compiler gets ``-ffp-contract=off`` (no fused multiply-add: the sums round alike on every
platform, so the forces are bit for bit the same) and hides every symbol but the FMI functions.
After compiling, each binary is read back (``objfile``): it must export the FMI 2.0 functions
only and need nothing but the C runtime (and libm). A macOS dylib is named
``@rpath/<modelIdentifier>.dylib`` (its install name), so two builds of the same sources are the
same bytes on every platform (``tests/test_native_platforms.py``).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .objfile import exports_and_imports, fat_binary


class NativeBuildError(RuntimeError):
    """The binary could not be compiled (no compiler, a compiler error): one line saying what to install."""


@dataclass(frozen=True)
class Platform:
    name: str  # the binaries/ folder (FMI 2.0)
    targets: tuple[str, ...]  # zig's -target, one per slice
    ext: str


MACOS_MIN = "11.0"  # the oldest macOS the binaries load on (the deployment target, both slices)
PLATFORMS = {p.name: p for p in (
    Platform("linux64", ("x86_64-linux-gnu.2.17",), ".so"),
    Platform("win64", ("x86_64-windows-gnu",), ".dll"),
    Platform("darwin64", (f"x86_64-macos.{MACOS_MIN}", f"aarch64-macos.{MACOS_MIN}"), ".dylib"),
)}
COMPILERS = ("zig", "cc", "cmake")
C_FLAGS = ("-O2", "-ffp-contract=off", "-fvisibility=hidden", "-std=c99")
# what a binary may need: the C runtime and libm (Windows: the UCRT's api sets, and KERNEL32 for
# the start-up code of the C runtime that zig links in; macOS: libSystem, which holds both)
ALLOWED_LIBRARIES = {"linux64": ("libc.so.6", "libm.so.6"), "win64": ("api-ms-win-crt-", "kernel32.dll"),
                     "darwin64": ("/usr/lib/libSystem.B.dylib",)}
# symbols every macOS dylib exports, defined by the linker itself
LINKER_SYMBOLS = {"_mh_dylib_header", "__dso_handle"}


def parse_platforms(text: str | None, compiler: str = "zig") -> tuple[str, ...]:
    """``all`` (or None) or a comma-separated list of PLATFORMS; with cc or cmake only the host's.
    ValueError naming what is wrong."""
    if compiler not in COMPILERS:
        raise ValueError(f"compiler {compiler!r}: choose one of {', '.join(COMPILERS)}")
    host = host_platform()
    if text is None or str(text).strip() == "":
        return tuple(PLATFORMS) if compiler == "zig" else (host,)
    names = [t.strip() for t in str(text).split(",") if t.strip()]
    if names == ["all"]:
        names = list(PLATFORMS) if compiler == "zig" else [host]
    unknown = [n for n in names if n not in PLATFORMS]
    if unknown or not names:
        raise ValueError(f"platforms {text!r}: choose all or some of {', '.join(PLATFORMS)}")
    if compiler != "zig" and names != [host]:
        raise ValueError(f"--compiler {compiler} builds for this machine's platform ({host}) only; "
                         "use --compiler zig for " + ", ".join(n for n in names if n != host))
    return tuple(dict.fromkeys(names))


def host_platform() -> str:
    """This machine's binaries/ folder, as fmpy names it."""
    import fmpy

    return fmpy.platform


def fmi_headers() -> Path:
    """The FMI 2.0 headers fmpy ships (fmpy/c-code)."""
    import fmpy

    path = Path(fmpy.__file__).resolve().parent / "c-code"
    if not (path / "fmi2Functions.h").is_file():
        raise NativeBuildError(f"fmpy's FMI headers are not at {path} (fmpy/c-code/fmi2Functions.h): reinstall fmpy")
    return path


def find_compiler() -> str:
    """The system C compiler: $CC, else cc, gcc or clang on PATH; NativeBuildError saying what to install."""
    cc = os.environ.get("CC")
    if cc:
        return cc
    for name in ("cc", "gcc", "clang"):
        path = shutil.which(name)
        if path:
            return path
    raise NativeBuildError("no C compiler found (set CC, or install one: Debian/Ubuntu `apt-get install gcc`, "
                           "macOS `xcode-select --install`), or build with --compiler zig (pip install ziglang)")


def zig_cc() -> list[str]:
    """The command of zig's C compiler from the ``ziglang`` pip package."""
    if importlib.util.find_spec("ziglang") is None:
        raise NativeBuildError("the ziglang package is not installed (`pip install ziglang`, a dependency of "
                               "bearing-fmu): it compiles the binaries of every platform; or build for this "
                               "machine only with --compiler cc")
    return [sys.executable, "-m", "ziglang", "cc"]


_running: set = set()  # the compilers running now (run_compilers kills them on an interrupt)


def run_compiler(cmd: list[str], what: str) -> None:
    """Run a compiler command (its paths absolute) and raise NativeBuildError naming ``what`` if it
    fails. It runs in the system's temporary folder, whatever this process's: zig keys the C runtime
    it builds (MinGW's for Windows: ~2 min of one core) on the working folder when zig's own files
    lie below it (a virtual environment inside the project), so a build started in the project and
    one started elsewhere each built it (measured: 131 s in the project's folder, then 111 s again in
    /tmp, then 0.1 s in the project's), and the runtimes' set-up step (``build.prepare_zig_runtimes``)
    served only the builds started where it ran."""
    try:  # its own process group: zig's wrapper starts the compiler, which starts more
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=os.name == "posix", cwd=tempfile.gettempdir())
    except OSError as exc:
        raise NativeBuildError(f"cannot run the C compiler {cmd[0]!r}: {exc}") from None
    _running.add(proc)
    try:
        stdout, stderr = proc.communicate(timeout=900)
    except BaseException:  # a timeout, or an interrupt in this (main) thread
        _kill(proc)
        raise
    finally:
        _running.discard(proc)
    if proc.returncode != 0:
        tail = (stderr or stdout).strip().splitlines()[-12:]
        raise NativeBuildError(f"{what} failed (exit {proc.returncode}): {' '.join(cmd)}\n" + "\n".join(tail))


def _kill(proc) -> None:
    """End a compiler and whatever it started (its process group on POSIX)."""
    try:
        if os.name == "posix":
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            proc.kill()
    except (ProcessLookupError, PermissionError):
        pass
    proc.wait()


def run_compilers(jobs: list[tuple[list[str], str]]) -> None:
    """``run_compiler`` over (command, what) jobs, as many at once as this machine has cores (each
    zig target is its own process; a build of every platform is 4-5 of them); the first failure
    is raised once all have ended. An interrupt (which reaches the main thread only) kills the
    compilers at once, so the pool's threads end with them instead of after the whole build."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=max(1, min(len(jobs), os.cpu_count() or 1))) as pool:
        futures = [pool.submit(run_compiler, cmd, what) for cmd, what in jobs]
        try:
            for f in futures:
                f.result()
        except KeyboardInterrupt:
            for f in futures:
                f.cancel()
            for proc in list(_running):
                _kill(proc)
            raise


def zig_command(target: str, src: Path, sources: list[str], out: Path, defines: tuple[str, ...] = (),
                identifier: str = "") -> list[str]:
    """zig cc compiling ``sources`` (in ``src``) into the shared library ``out`` for ``target``;
    macOS: named ``@rpath/<identifier>.dylib`` (else the linker writes ``out``'s temporary path
    into the binary, and two builds differ)."""
    pic = () if "windows" in target else ("-fPIC",)
    libm = ("-lm",) if "linux" in target else ()
    name = (f"-Wl,-install_name,@rpath/{identifier or out.stem}.dylib",) if "macos" in target else ()
    return [*zig_cc(), "-target", target, *C_FLAGS, *pic, "-s", "-shared", *defines, "-I", str(src),
            "-I", str(fmi_headers()), *(str(src / f) for f in sources), "-o", str(out), *name, *libm]


def mac_flags(identifier: str) -> tuple[str, ...]:
    """The system compiler's flags on macOS: the deployment target and the install name zig gets."""
    if sys.platform != "darwin":
        return ()
    return (f"-mmacosx-version-min={MACOS_MIN}", f"-Wl,-install_name,@rpath/{identifier}.dylib")


# FMI 3.0 names a binaries/ folder per platform tuple, one architecture each (no universal file)
FMI3_FOLDERS = {"linux64": (("x86_64-linux", "x86_64-linux-gnu.2.17"), ("aarch64-linux", "aarch64-linux-gnu.2.17")),
                "win64": (("x86_64-windows", "x86_64-windows-gnu"),),
                "darwin64": (("x86_64-darwin", f"x86_64-macos.{MACOS_MIN}"),
                             ("aarch64-darwin", f"aarch64-macos.{MACOS_MIN}"))}
HOST_FMI3 = {"linux64": "x86_64-linux", "win64": "x86_64-windows", "darwin64": "x86_64-darwin"}


def compile_binaries(root: Path, identifier: str, sources: list[str], platforms=None,
                     compiler: str = "zig", fmi_version: int = 2, defines: tuple[str, ...] = ()) -> list[Path]:
    """Compile ``root``/sources into ``root``/binaries/<platform>/<identifier><ext> for each of
    ``platforms`` (default: all with zig, else the host's); each binary checked (``check_binary``).
    FMI 3.0 (``fmi_version=3``, with its ``defines``): one folder per platform tuple (FMI3_FOLDERS)."""
    platforms = parse_platforms(",".join(platforms) if platforms else None, compiler)
    if fmi_version == 3:
        return _compile_fmi3(root, identifier, sources, platforms, compiler, defines)
    src, out, zig_jobs = root / "sources", [], []
    for name in platforms:
        p = PLATFORMS[name]
        target = root / "binaries" / name / f"{identifier}{p.ext}"
        target.parent.mkdir(parents=True, exist_ok=True)
        if compiler == "cmake":
            _compile_cmake(root)
        elif compiler == "cc":
            if sys.platform == "win32":
                raise NativeBuildError("--compiler cc is for Linux and macOS; on Windows use --compiler cmake "
                                       "(fmpy's CMake project with Visual Studio) or zig")
            run_compiler([find_compiler(), *C_FLAGS, *mac_flags(identifier), "-fPIC", "-shared", "-I", str(src), "-I",
                          str(fmi_headers()), *(str(src / f) for f in sources), "-o", str(target), "-lm"],
                         "the C compiler")
        else:
            zig_jobs.append((name, target))
            continue
        if not target.is_file():
            raise NativeBuildError(f"the build wrote no {target.relative_to(root)}")
        check_binary(target, name)
        out.append(target)
    if zig_jobs:
        with tempfile.TemporaryDirectory(prefix="bearing_zig_") as tmp:  # zig writes .pdb, .lib beside a dll
            slices = {(name, t): Path(tmp) / f"{name}-{k}{PLATFORMS[name].ext}"
                      for name, _ in zig_jobs for k, t in enumerate(PLATFORMS[name].targets)}
            run_compilers([(zig_command(t, src, sources, one, identifier=identifier), f"zig cc -target {t}")
                           for (_, t), one in slices.items()])
            for name, target in zig_jobs:
                parts = [slices[name, t].read_bytes() for t in PLATFORMS[name].targets]
                target.write_bytes(fat_binary(parts) if len(parts) > 1 else parts[0])
                check_binary(target, name)
                out.append(target)
    return out


def _compile_fmi3(root: Path, identifier: str, sources: list[str], platforms, compiler: str,
                  defines: tuple[str, ...]) -> list[Path]:
    src, out, zig_jobs = root / "sources", [], []
    for name in platforms:
        p = PLATFORMS[name]
        if compiler == "zig":
            jobs = FMI3_FOLDERS[name]
        else:  # the system compiler or fmpy's CMake: this machine's tuple only
            jobs = ((HOST_FMI3[name], None),)
        for folder, target_triple in jobs:
            target = root / "binaries" / folder / f"{identifier}{p.ext}"
            target.parent.mkdir(parents=True, exist_ok=True)
            if compiler == "cmake":
                _compile_cmake(root)
            elif compiler == "cc":
                run_compiler([find_compiler(), *C_FLAGS, *mac_flags(identifier), *defines, "-fPIC", "-shared",
                              "-I", str(src), "-I", str(fmi_headers()), *(str(src / f) for f in sources),
                              "-o", str(target), "-lm"], "the C compiler")
            else:
                zig_jobs.append((name, target, target_triple))
                continue
            if not target.is_file():
                raise NativeBuildError(f"the build wrote no {target.relative_to(root)}")
            check_binary(target, name, prefix="fmi3")
            out.append(target)
    if zig_jobs:
        with tempfile.TemporaryDirectory(prefix="bearing_zig_") as tmp:
            ones = [Path(tmp) / f"{k}{PLATFORMS[name].ext}" for k, (name, _, _) in enumerate(zig_jobs)]
            run_compilers([(zig_command(t, src, sources, one, defines, identifier), f"zig cc -target {t}")
                           for (_, _, t), one in zip(zig_jobs, ones)])
            for (name, target, _), one in zip(zig_jobs, ones):
                target.write_bytes(one.read_bytes())
                check_binary(target, name, prefix="fmi3")
                out.append(target)
    return out


def check_binary(path: Path, platform: str, prefix: str = "fmi2") -> None:
    """NativeBuildError unless the binary exports only FMI functions and needs only the C runtime."""
    for link in exports_and_imports(Path(path).read_bytes()):
        extra = [s for s in link.exports if not s.startswith(prefix) and s not in LINKER_SYMBOLS]
        libs = [lib for lib in link.libraries
                if not any(lib.lower().startswith(a.lower()) for a in ALLOWED_LIBRARIES.get(platform, ()))]
        if extra or (platform in ALLOWED_LIBRARIES and libs):
            raise NativeBuildError(f"{path.name} ({platform}, {link.cpu}) exports {extra or 'the FMI functions only'} "
                                   f"and needs {libs or 'the C runtime only'}: only the FMI functions may be exported "
                                   "and only the C runtime needed")


def cmake_executable_dir() -> str | None:
    """The folder of the cmake executable of the ``cmake`` pip package (a dependency of fmpy), if installed."""
    try:
        import cmake  # noqa: PLC0415

        return str(cmake.CMAKE_BIN_DIR)
    except (ImportError, AttributeError):
        return None


def _compile_cmake(root: Path) -> None:
    from fmpy.build import build_platform_binary

    path = os.environ.get("PATH", "")
    bin_dir = cmake_executable_dir()
    env_path = (bin_dir + os.pathsep + path) if bin_dir else path
    if not shutil.which("cmake", path=env_path):
        raise NativeBuildError("cmake not found: `pip install cmake` (fmpy depends on it) or install it with the "
                               "system's packages; or build with --compiler zig or cc")
    old = os.environ.get("PATH")
    os.environ["PATH"] = env_path
    try:
        with tempfile.TemporaryDirectory(prefix="bearing_native_cmake_") as build_dir:
            build_platform_binary(root, build_dir, cmake_options={"CMAKE_C_FLAGS:STRING": "-ffp-contract=off -fvisibility=hidden"})
    except subprocess.CalledProcessError as exc:
        raise NativeBuildError(f"fmpy's CMake build failed ({exc}); see its output above") from None
    finally:
        if old is None:
            os.environ.pop("PATH", None)
        else:
            os.environ["PATH"] = old


__all__ = ["PLATFORMS", "COMPILERS", "C_FLAGS", "NativeBuildError", "run_compiler", "parse_platforms", "host_platform",
           "fmi_headers", "find_compiler", "zig_cc", "zig_command", "compile_binaries", "check_binary"]
