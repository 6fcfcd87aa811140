"""The layout a newcomer can live in (docs/architecture.md): packages by concern, no folder over
15 modules (a warning from 12: split before the wall), no module over 600 lines (the Reynolds
kernels aside) and at most one within 30 lines of that cap (a cap is not a target), no import
circle (imports inside functions included), no import of a module that does not exist, no
private name imported from another module, the bearing side never importing the host, argparse
only in the command-line modules. A new internal added as docs/architecture.md says passes them
(checked on a copy of the tree with one added).

Read from the sources with ``ast``, not by importing them: what is checked is what is written.
"""

import ast
import functools
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("bearing_fmu", "rotor_host")
MAX_MODULES = 15
WARN_MODULES = 12  # a folder this full is warned of: split it by responsibility before the wall
MAX_LINES = 600
NEAR_CAP = 570  # modules of NEAR_CAP..MAX_LINES lines: at most one (besides LONG_ALLOWED)
LONG_ALLOWED = {"bearing_fmu/physics/solver/reynolds_kernels.py"}  # one numba kernel set, split it and it slows
CLI_MODULES = {"bearing_fmu/cli.py"}
CLI_PACKAGES = ("rotor_host/cli/",)  # a command line grown into a package: every module of it parses


@functools.lru_cache(maxsize=4)
def _modules(root: Path = ROOT) -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for f in sorted((root / pkg).rglob("*.py")):
            name = ".".join(f.relative_to(root).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = f
    return out


def _imports(name: str, path: Path, modules) -> list[tuple[str, str, int]]:
    """(imported module, imported name or "", line) of every import in the module, at any depth."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for alias in node.names:
                full = f"{mod}.{alias.name}"
                out.append((full, "", node.lineno) if full in modules else (mod, alias.name, node.lineno))
        elif isinstance(node, ast.Import):
            out += [(alias.name, "", node.lineno) for alias in node.names]
    return [(m, n, line) for m, n, line in out if m.split(".")[0] in PACKAGES]


@functools.lru_cache(maxsize=4)
def _graph(root: Path = ROOT):
    modules = _modules(root)
    return modules, {name: _imports(name, path, modules) for name, path in modules.items()}


def folder_sizes(root: Path = ROOT) -> dict[str, int]:
    """Folder (relative to root) -> how many modules it holds (``__init__.py`` not counted)."""
    out = {}
    for pkg in PACKAGES:
        for folder in [root / pkg, *(d for d in (root / pkg).rglob("*") if d.is_dir())]:
            if folder.name != "__pycache__":
                out[folder.relative_to(root).as_posix()] = len([f for f in folder.glob("*.py")
                                                                if f.name != "__init__.py"])
    return out


def module_lines(root: Path = ROOT) -> dict[str, int]:
    """Module file (relative to root) -> its number of lines."""
    return {p.relative_to(root).as_posix(): len(p.read_text(encoding="utf-8").splitlines())
            for p in _modules(root).values()}


def layout_problems(root: Path = ROOT) -> list[str]:
    """What breaks the house's rules of size in the tree at ``root`` (empty: none)."""
    lines = module_lines(root)
    near = sorted(f"{rel} ({n} lines)" for rel, n in lines.items()
                  if rel not in LONG_ALLOWED and NEAR_CAP <= n <= MAX_LINES)
    return ([f"{d} holds {n} modules (at most {MAX_MODULES})" for d, n in folder_sizes(root).items() if n > MAX_MODULES]
            + [f"{rel} has {n} lines (at most {MAX_LINES})" for rel, n in lines.items()
               if rel not in LONG_ALLOWED and n > MAX_LINES]
            + ([f"{len(near)} modules sit at {NEAR_CAP}-{MAX_LINES} lines (at most one; split by responsibility): "
                + ", ".join(near)] if len(near) > 1 else []))


def crowded_folders(root: Path = ROOT) -> dict[str, int]:
    """Folders of WARN_MODULES modules or more: the next split is due."""
    return {d: n for d, n in folder_sizes(root).items() if n >= WARN_MODULES}


def test_no_folder_holds_more_than_15_modules():
    for d, n in folder_sizes().items():
        assert n <= MAX_MODULES, f"{d} holds {n} modules (at most {MAX_MODULES})"


def test_a_folder_of_12_modules_or_more_is_warned_of():
    # a warning, not a failure: the folder still fits, but its next module should come with a split
    for d, n in crowded_folders().items():
        warnings.warn(f"{d} holds {n} modules ({MAX_MODULES} is the wall): split it by responsibility before "
                      "adding to it", UserWarning, stacklevel=1)


def test_no_module_over_600_lines():
    for rel, n in module_lines().items():
        assert rel in LONG_ALLOWED or n <= MAX_LINES, f"{rel} has {n} lines (at most {MAX_LINES})"


def test_at_most_one_module_sits_just_under_the_cap():
    near = {rel: n for rel, n in module_lines().items() if rel not in LONG_ALLOWED and NEAR_CAP <= n <= MAX_LINES}
    assert len(near) <= 1, (f"{len(near)} modules at {NEAR_CAP}-{MAX_LINES} lines (at most one): {near}; the cap "
                            "is a wall, not a target: split them by responsibility")


def test_every_import_names_a_module_that_exists():
    # a module moved and an import (often one inside a function) left pointing at its old place
    modules, graph = _graph()
    bad = [f"{m}:{line} imports {t}{'.' + n if n else ''}" for m, imps in graph.items() for t, n, line in imps
           if t not in modules]
    assert not bad, "\n".join(bad)


def test_every_package_says_what_it_holds():
    for name, path in _modules().items():
        if path.name == "__init__.py":
            doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
            assert doc and len(doc) > 40, f"{path.relative_to(ROOT)}: no docstring saying what the package holds"


def import_circles(root: Path = ROOT) -> list[list[str]]:
    modules, graph = _graph(root)
    edges = {m: {t for t, _, _ in imps if t in modules and t != m} for m, imps in graph.items()}
    # a package's __init__ importing its own modules is how a package re-exports, not a circle:
    # what counts is module -> module
    for m in list(edges):
        edges[m] = {t for t in edges[m] if not (modules[t].name == "__init__.py" and m.startswith(t + "."))}
    index, low, stack, on, circles = {}, {}, [], set(), []

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in edges:
        if v not in index:
            visit(v)
    return circles


def test_no_import_circle_even_inside_functions():
    circles = import_circles()
    assert not circles, f"import circles: {circles}"


def private_imports(root: Path = ROOT) -> list[str]:
    _, graph = _graph(root)
    return [f"{m}:{line} imports {name} from {t}" for m, imps in graph.items() for t, name, line in imps
            if name.startswith("_") and not name.startswith("__")]


def test_no_private_name_is_imported_from_another_module():
    bad = private_imports()
    assert not bad, "\n".join(bad)


def test_the_bearing_side_never_imports_the_host():
    _, graph = _graph()
    bad = [f"{m}:{line} imports {t}" for m, imps in graph.items() if m.startswith("bearing_fmu")
           for t, _, line in imps if t.startswith("rotor_host")]
    assert not bad, "\n".join(bad)


def test_argument_parsing_only_in_the_cli_modules():
    for name, path in _modules().items():
        rel = path.relative_to(ROOT).as_posix()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        uses = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr in
                ("ArgumentParser", "add_argument", "parse_args", "Namespace")]
        assert rel in CLI_MODULES or rel.startswith(CLI_PACKAGES) or not uses, f"{rel}: argparse at lines {uses}; parse in the cli modules"


def test_the_checks_fail_on_what_they_look_for(tmp_path):
    # the checker itself: a made-up module pair in a circle through a function-level import, and
    # a private import, are seen (else a green test would say nothing)
    a = tmp_path / "a.py"
    a.write_text("def f():\n    from rotor_host.b import _x\n")
    imps = _imports("rotor_host.a", a, {"rotor_host.a", "rotor_host.b"})
    assert imps == [("rotor_host.b", "_x", 2)]


def test_the_size_checks_fail_on_what_they_look_for(tmp_path):
    # two modules just under the cap, one over it and a folder of 16: each named
    pkg = tmp_path / "rotor_host" / "crowded"
    pkg.mkdir(parents=True)
    (tmp_path / "bearing_fmu").mkdir()
    for i in range(16):
        (pkg / f"m{i}.py").write_text("x = 1\n" * (575 if i < 2 else 601 if i == 2 else 1))
    problems = layout_problems(tmp_path)
    assert "rotor_host/crowded holds 16 modules (at most 15)" in problems
    assert "rotor_host/crowded/m2.py has 601 lines (at most 600)" in problems
    assert any(p.startswith("2 modules sit at 570-600 lines") for p in problems)
    assert crowded_folders(tmp_path) == {"rotor_host/crowded": 16}


# A newcomer's internal, written as docs/architecture.md ("Where to add what") and the checklist
# in bearing_fmu/internals/registry.py say: the Ocvirk short bearing (physics.solver.shortbearing's closed
# form) as an internal in a family folder of its own, its spec in the catalogue, its case.
NEWCOMER_INIT = '''"""The short-bearing family: the Ocvirk closed form as an internal.

=========  ==========================================================
module     what it holds
=========  ==========================================================
short      ``ShortBearing``: physics.solver.shortbearing's force and Jacobian
=========  ==========================================================
"""
'''
NEWCOMER = '''"""The Ocvirk short bearing as an internal: ``physics.solver.shortbearing``'s closed form."""

from __future__ import annotations

from ...physics.params import BearingParams
from ...physics.solver.shortbearing import short_bearing_force, short_bearing_force_and_jacobian


class ShortBearing:
    def __init__(self, params: BearingParams):
        self.params = params

    @classmethod
    def from_options(cls, params: BearingParams, options, context) -> "ShortBearing":
        return cls(params)

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        return short_bearing_force(self.params, y, z, vy, vz, omega)

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        return short_bearing_force_and_jacobian(self.params, y, z, vy, vz, omega)
'''
NEWCOMER_SPEC = '''

register(InternalSpec(
    "short", "internals.short.short:ShortBearing.from_options", "Ocvirk short bearing (closed form, L/D << 1)",
    can=Capabilities(
        any_state=True, any_geometry=False, geometry_why="the closed form is the full circular bore's",
        film_flow_why="the closed form gives the force only",
        validity="The short-bearing closed form holds for L/D well below 1, at any speed, load and velocity; the "
                 "journal at or beyond the wall is refused (fmi2Discard)."),
    case="internals.cases:short_case",
))
'''
NEWCOMER_CASE = '''

def short_case(data_dir: Path) -> ContractCase:
    return ContractCase()
'''


def where_a_new_internal_goes() -> dict[str, str]:
    """The places docs/architecture.md names for a new internal ("Where to add what"): its family
    folder, its module, the catalogue its spec goes in and the module of its contract case."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    bullet = re.search(r"^- \*\*A new bearing internal\*\*.*?(?=^- \*\*|\Z)", text, re.M | re.S)
    assert bullet, "docs/architecture.md: no 'A new bearing internal' item under 'Where to add what'"
    named = re.findall(r"`([^`]+)`", bullet.group(0))
    want = {"folder": "bearing_fmu/internals/<family>/", "module": "<family>/<name>.py",
            "catalogue": "bearing_fmu/internals/catalogue.py", "cases": "bearing_fmu/internals/cases.py"}
    missing = [p for p in want.values() if p not in named]
    assert not missing, f"docs/architecture.md no longer names {missing} for a new internal: update this test with it"
    return want


def test_a_new_internal_added_as_documented_fits_the_house(tmp_path):
    # the tree copied, the newcomer added where the docs say; then the layout rules on the copy
    # and, in a fresh process on the copy, the registry builds it from its spec string
    for pkg in PACKAGES:
        shutil.copytree(ROOT / pkg, tmp_path / pkg, ignore=shutil.ignore_patterns("__pycache__", "*.so", "*.dll",
                                                                                   "*.dylib", "*.fmu"))
    where = where_a_new_internal_goes()
    folder = tmp_path / where["folder"].replace("<family>", "short")
    folder.mkdir()
    (folder / "__init__.py").write_text(NEWCOMER_INIT)
    (folder.parent / where["module"].replace("<family>", "short").replace("<name>", "short")).write_text(NEWCOMER)
    for key, text in (("catalogue", NEWCOMER_SPEC), ("cases", NEWCOMER_CASE)):
        with open(tmp_path / where[key], "a", encoding="utf-8") as f:
            f.write(text)
    assert layout_problems(tmp_path) == [p for p in layout_problems() if "sit at" in p], \
        "the newcomer breaks a size rule"  # (the tree's own modules near the cap are another test's)
    crowded = {d: n for d, n in crowded_folders(tmp_path).items() if d.startswith("bearing_fmu/internals")}
    assert not crowded, f"a new internal lands in a crowded folder: {crowded}"
    assert not import_circles(tmp_path) and not private_imports(tmp_path)
    code = """
import sys
from bearing_fmu.internals import registry
from bearing_fmu.physics.params import PAPER_BEARING as P
from bearing_fmu.physics.solver.shortbearing import short_bearing_force
assert registry.__file__.startswith(sys.argv[1]), registry.__file__
state = (1e-5, -4e-5, 1e-3, -2e-4, 138.2)
assert registry.create("short", P).force(*state) == short_bearing_force(P, *state)
assert registry.get("short").contract_case(sys.argv[1]).beyond_wall == "refuses"
assert "short" in registry.having(any_state=True)
print("ok")
"""
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path)], cwd=tmp_path, capture_output=True, text=True,
                       timeout=300, env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stderr[-3000:]
