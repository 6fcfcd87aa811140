"""The edit loop's build cache keys (tests/conftest.py ``source_files``): a native build is keyed by
the sources it can run, found from the sources as they are (imports at any depth, the registry's
"module:attr" references, the data folders beside them), so an edit elsewhere keeps every
native FMU and an edit of what it runs builds it again."""

from pathlib import Path

from conftest import NATIVE_BUILD, ROOT, source_files


def _package(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)


def test_what_a_made_up_package_runs(tmp_path):
    # a made-up package: every kind of use once, and one module nothing uses
    _package(tmp_path, {
        "pkg/__init__.py": "",
        "pkg/gen/__init__.py": "from .top import build\n",
        "pkg/gen/top.py": "def build():\n    from ..deep.inner import f\n    return f()\n",
        "pkg/gen/c/model.c": "int x;\n",
        "pkg/gen/c/sub/unit.h": "int y;\n",
        "pkg/deep/__init__.py": "",
        "pkg/deep/inner.py": "import pkg.named\nFACTORY = 'plugin.impl:Thing.make'\ndef f():\n    return 1\n",
        "pkg/named.py": "",
        "pkg/plugin/__init__.py": "",
        "pkg/plugin/impl.py": "class Thing: ...\n",
        "pkg/unused.py": "import pkg.gen\n",
        "pkg/other/__init__.py": "",
        "pkg/other/data.txt": "x\n",
    })
    got = {p.relative_to(tmp_path).as_posix() for p in source_files("pkg.gen", root=tmp_path)}
    assert got == {"pkg/__init__.py", "pkg/gen/__init__.py", "pkg/gen/top.py", "pkg/gen/c/model.c",
                   "pkg/gen/c/sub/unit.h", "pkg/deep/__init__.py", "pkg/deep/inner.py", "pkg/named.py",
                   "pkg/plugin/__init__.py", "pkg/plugin/impl.py"}


def test_the_native_build_keeps_out_of_what_it_never_runs():
    files = {p.relative_to(ROOT).as_posix() for p in source_files(*NATIVE_BUILD)}
    native = ROOT / "bearing_fmu" / "fmu" / "native"
    # all of the native folder: its generators and every C source and header, whatever their names
    assert {p.relative_to(ROOT).as_posix() for p in native.rglob("*") if p.is_file() and p.suffix in
            (".py", ".c", ".h")} <= files
    # the internals it compiles, reached through the registry's references
    assert {"bearing_fmu/internals/registry.py", "bearing_fmu/physics/params.py"} <= files
    # nothing of the host, the fitting, the command line or the pythonfmu slave and its build
    assert not [f for f in files if f.startswith(("rotor_host/", "bearing_fmu/fitting/", "bearing_fmu/fmu/pyslave/"))
                or f in ("bearing_fmu/cli.py", "bearing_fmu/fmu/slave.py", "bearing_fmu/fmu/build.py")]
