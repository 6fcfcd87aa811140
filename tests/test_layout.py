"""The layout a newcomer can live in (docs/architecture.md): packages by concern, no folder over
15 modules, no module over 600 lines (the Reynolds kernels aside), no import circle (imports
inside functions included), no private name imported from another module, the bearing side
never importing the host, argparse only in the command-line modules.

Read from the sources with ``ast``, not by importing them: what is checked is what is written.
"""

import ast
import functools
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("bearing_fmu", "rotor_host")
MAX_MODULES = 15
MAX_LINES = 600
LONG_ALLOWED = {"bearing_fmu/physics/reynolds_kernels.py"}  # one numba kernel set, split it and it slows
CLI_MODULES = {"bearing_fmu/cli.py", "rotor_host/cli.py"}


@functools.lru_cache(maxsize=1)
def _modules() -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for f in sorted((ROOT / pkg).rglob("*.py")):
            name = ".".join(f.relative_to(ROOT).with_suffix("").parts)
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


@functools.lru_cache(maxsize=1)
def _graph():
    modules = _modules()
    return modules, {name: _imports(name, path, modules) for name, path in modules.items()}


def test_no_folder_holds_more_than_15_modules():
    for pkg in PACKAGES:
        for folder in [ROOT / pkg, *(d for d in (ROOT / pkg).rglob("*") if d.is_dir())]:
            if folder.name == "__pycache__":
                continue
            n = len([f for f in folder.glob("*.py") if f.name != "__init__.py"])
            assert n <= MAX_MODULES, f"{folder.relative_to(ROOT)} holds {n} modules (at most {MAX_MODULES})"


def test_no_module_over_600_lines():
    for name, path in _modules().items():
        rel = path.relative_to(ROOT).as_posix()
        n = len(path.read_text(encoding="utf-8").splitlines())
        assert rel in LONG_ALLOWED or n <= MAX_LINES, f"{rel} has {n} lines (at most {MAX_LINES})"


def test_every_package_says_what_it_holds():
    for name, path in _modules().items():
        if path.name == "__init__.py":
            doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
            assert doc and len(doc) > 40, f"{path.relative_to(ROOT)}: no docstring saying what the package holds"


def test_no_import_circle_even_inside_functions():
    modules, graph = _graph()
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
    assert not circles, f"import circles: {circles}"


def test_no_private_name_is_imported_from_another_module():
    _, graph = _graph()
    bad = [f"{m}:{line} imports {name} from {t}" for m, imps in graph.items() for t, name, line in imps
           if name.startswith("_") and not name.startswith("__")]
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
        assert rel in CLI_MODULES or not uses, f"{rel}: argparse at lines {uses}; parse in the cli modules"


def test_the_checks_fail_on_what_they_look_for(tmp_path):
    # the checker itself: a made-up module pair in a circle through a function-level import, and
    # a private import, are seen (else a green test would say nothing)
    a = tmp_path / "a.py"
    a.write_text("def f():\n    from rotor_host.b import _x\n")
    imps = _imports("rotor_host.a", a, {"rotor_host.a", "rotor_host.b"})
    assert imps == [("rotor_host.b", "_x", 2)]
