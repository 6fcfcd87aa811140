"""Write the bearing FMU: pythonfmu's builder plus what it leaves out.

``build_fmu(output, surrogate=None)`` produces a self-contained FMI 2.0 co-simulation FMU:

* state handling on (``canGetAndSetFMUstate``, ``canSerializeFMUstate``): the host iterates
  within a step the conformant way (restore state, set inputs, doStep, get outputs);
* the ``bearing_fmu`` code in ``resources/`` under a unique package name
  ``bearing_fmu_v<version>_<hash>`` (hash of the sources), every import rewritten to it, so
  the FMU never runs a different ``bearing_fmu`` that the host (or another FMU build) has
  imported into the same interpreter, and two builds coexist in one process;
* the slave module ``resources/<package>_slave.py``: a generated bootstrap followed by
  ``bearing_fmu/fmu/slave.py`` with its relative imports pointed at the bundled package. The
  bootstrap copies the package once into a per-user code cache keyed by that name (see
  ``code_cache_root``) and imports it from there: numba's on-disk cache then lives beside
  that stable copy and survives fresh extractions of the FMU (the extraction directory
  changes every time, and numba keys its cache on the source file's directory);
* the surrogate file(s) in ``resources/surrogates/``, each checked completely first
  (``check_surrogate_file``: the loader the FMU uses), so a truncated or inconsistent file is
  refused at build time, naming the file and the key, not when the FMU initialises;
* a modelDescription.xml that ``fmpy validate`` accepts: units, InitialUnknowns, output
  dependencies on the inputs, start values written to round-trip exactly;
* pythonfmu's Linux binary patched (``fmu_binary``): no crash at process exit, and honest FMI
  statuses (fmi2Error for a refused call, the instance kept; fmi2Terminated cleared by a good
  step or a restore); ``resources/pythonfmu_patches.json`` records what was applied.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path
from xml.dom.minidom import parseString
from xml.etree import ElementTree as ET

from .. import __version__
from .meta import UNITS  # noqa: F401 - the unit definitions (shared with the native build)

HERE = Path(__file__).resolve().parent
PACKAGE = HERE.parent  # bearing_fmu
# What the slave needs at run time: the package file, these folders (bearing physics,
# internals, the surrogate file) and the slave's own parts and helpers (pyslave/, call order,
# ports, resources, variables); not the fitting, the FMU build tooling or the command lines.
IN_FMU = ("__init__.py", "physics", "internals", "surrogates", "io/__init__.py", "io/schema.py", "fmu/__init__.py",
          "fmu/order.py", "fmu/ports.py", "fmu/pyslave", "fmu/resources.py", "fmu/variables.py")
MODEL_IDENTIFIER = "BearingFMU"
REQUIREMENTS = "numpy>=1.26\nscipy>=1.11\nnumba>=0.59\n"


_ABS_IMPORT = re.compile(r"^\s*import\s+bearing_fmu\b", re.M)
_ABS_FROM = re.compile(r"^(\s*)from\s+bearing_fmu(?=[.\s])", re.M)
_REL_FROM = re.compile(r"^(\s*)from\s+\.(\w*)", re.M)
_DYNAMIC = re.compile(r"""import_module\(\s*['"]bearing_fmu""")


def package_sources() -> dict[str, str]:
    """The package modules bundled in the FMU, name -> source text (sorted by name)."""
    files = []
    for entry in IN_FMU:
        path = PACKAGE / entry
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    return {p.relative_to(PACKAGE).as_posix(): p.read_text(encoding="utf-8") for p in sorted(files)}


def package_name(sources: dict[str, str] | None = None, slave_source: str | None = None) -> str:
    """The unique name the code is bundled under: version plus a hash of every source in it."""
    sources = package_sources() if sources is None else sources
    slave_source = (HERE / "slave.py").read_text(encoding="utf-8") if slave_source is None else slave_source
    h = hashlib.sha256()
    for name, text in [*sources.items(), ("slave.py", slave_source)]:
        h.update(name.encode() + b"\0" + text.encode("utf-8") + b"\0")
    version = re.sub(r"\W", "_", __version__)
    return f"bearing_fmu_v{version}_{h.hexdigest()[:12]}"


def _rewrite(text: str, name: str, pkg: str, top_level: bool) -> str:
    """Point the imports of one module at the bundled package ``pkg``."""
    if _ABS_IMPORT.search(text) or _DYNAMIC.search(text):
        raise ValueError(
            f"bearing_fmu/{name}: `import bearing_fmu...` or import_module('bearing_fmu...') cannot be "
            "bundled under a unique name; use relative imports (from .module import name)")
    text = _ABS_FROM.sub(lambda m: f"{m.group(1)}from {pkg}", text)
    if top_level:  # the slave module sits beside the package: relative -> absolute
        text = _REL_FROM.sub(lambda m: f"{m.group(1)}from {pkg}" + (f".{m.group(2)}" if m.group(2) else ""), text)
    return text


def _digest(files: dict[str, str]) -> str:
    h = hashlib.sha256()
    for name, text in files.items():
        h.update(name.encode() + b"\0" + text.encode("utf-8") + b"\0")
    return h.hexdigest()


_BOOTSTRAP = '''\
# Generated by bearing_fmu.fmu.build (bearing_fmu {version}) from bearing_fmu/fmu/slave.py. Do not edit.
#
# The bearing_fmu code is bundled beside this file as the package {pkg!r}: the version plus
# a hash of its sources, so it never mixes with another bearing_fmu (or another build of this
# FMU) imported into the same interpreter. It is copied once into a per-user code cache
# (BEARING_FMU_CACHE_DIR, default ~/.cache/bearing_fmu/fmu-code; "off" disables it) and
# imported from there, so numba's on-disk cache beside it survives fresh extractions.
import sys as _sys

_BUNDLED_PACKAGE = {pkg!r}
_CODE_FILES = {files!r}
_CODE_SHA256 = {digest!r}


def _bearing_fmu_bootstrap():
    import hashlib
    import importlib.util
    import os
    import shutil
    import tempfile
    from pathlib import Path

    if _BUNDLED_PACKAGE in _sys.modules:
        return

    def digest(folder):
        h = hashlib.sha256()
        for name in _CODE_FILES:
            h.update(name.encode() + b"\\0" + (folder / name).read_bytes() + b"\\0")
        return h.hexdigest()

    def valid(folder):
        try:
            return digest(folder) == _CODE_SHA256
        except OSError:
            return False

    def cache_root():
        env = os.environ.get("BEARING_FMU_CACHE_DIR")
        if env is not None:
            if env.strip().lower() in ("", "0", "off", "no", "none", "false"):
                return None
            return Path(env).expanduser()
        if _sys.platform == "win32":
            base = os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local"
        elif _sys.platform == "darwin":
            base = Path.home() / "Library" / "Caches"
        else:
            base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
        return Path(base) / "bearing_fmu" / "fmu-code"

    def install(bundled, root):
        target = root / _BUNDLED_PACKAGE
        if valid(target):
            return target
        root.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix="." + _BUNDLED_PACKAGE + ".", dir=root))
        try:
            for name in _CODE_FILES:
                (tmp / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(bundled / name, tmp / name)
            if target.exists():  # corrupt or tampered with: replace it
                shutil.rmtree(target, ignore_errors=True)
            try:
                os.rename(tmp, target)
            except OSError:
                pass  # another process installed it first
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        return target if valid(target) else None

    bundled = Path(__file__).resolve().parent / _BUNDLED_PACKAGE
    if not valid(bundled):
        raise ImportError(f"bearing FMU: the bundled code in {{bundled}} does not match its hash; "
                          "the FMU is damaged, rebuild it with `bearing-fmu build`")
    src = bundled
    root = cache_root()
    if root is not None:
        try:
            src = install(bundled, root) or bundled
        except OSError:
            src = bundled  # no writable cache: run from the extraction (numba compiles afresh)
    spec = importlib.util.spec_from_file_location(
        _BUNDLED_PACKAGE, src / "__init__.py", submodule_search_locations=[str(src)])
    module = importlib.util.module_from_spec(spec)
    _sys.modules[_BUNDLED_PACKAGE] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del _sys.modules[_BUNDLED_PACKAGE]
        raise


_bearing_fmu_bootstrap()
del _bearing_fmu_bootstrap
# ------------------------------------------------------------------ bearing_fmu/fmu/slave.py
'''


def _stage(stage: Path, surrogates: list[Path]) -> tuple[Path, str, list[Path]]:
    """Write the slave module, the package copy and the surrogates into ``stage``."""
    sources = package_sources()
    slave_source = (HERE / "slave.py").read_text(encoding="utf-8")
    pkg = package_name(sources, slave_source)
    files = {name: _rewrite(text, name, pkg, top_level=False) for name, text in sources.items()}
    pkg_dir = stage / pkg
    pkg_dir.mkdir()
    for name, text in files.items():
        (pkg_dir / name).parent.mkdir(parents=True, exist_ok=True)
        (pkg_dir / name).write_text(text, encoding="utf-8", newline="\n")
    slave = _rewrite(slave_source, "slave.py", pkg, top_level=True)
    header = _BOOTSTRAP.format(version=__version__, pkg=pkg, files=tuple(files), digest=_digest(files))
    script = stage / f"{pkg}_slave.py"
    script.write_text(header + slave, encoding="utf-8", newline="\n")
    (stage / "requirements.txt").write_text(REQUIREMENTS)
    project = [pkg_dir, stage / "requirements.txt"]
    if surrogates:
        sdir = stage / "surrogates"
        sdir.mkdir()
        for s in surrogates:
            shutil.copy2(s, sdir / s.name)
        project.append(sdir)
    return script, pkg, project


def _postprocess(xml_bytes: bytes, pkg: str, bearing: dict | None = None, record: dict | None = None) -> bytes:
    """The model description a system-simulation engineer expects (``fmu_meta``): start values
    that round-trip (the built-in bearing's D, L, CR, mu from ``bearing`` when given), units and
    display units, min / max / nominal, the choice parameters as enumerations, author and
    license, the model name and description of the build ``record``, InitialUnknowns and output
    dependencies."""
    from ..physics.params import BearingParams
    from . import meta as fmu_meta
    from .slave import ENUMERATIONS, VARIABLES, BearingFMU
    from .variables import MEMORYLESS, STEPPED

    table = {v[0]: v for v in VARIABLES}
    for k, v in (bearing or {}).items():
        if k in table:
            table[k] = (*table[k][:4], v, *table[k][5:])
    params = BearingParams(*(table[k][4] for k in ("D", "L", "CR", "mu")))
    omega_ref = fmu_meta.reference_speed(table["omega"][4])
    root = ET.fromstring(xml_bytes)
    fmu_meta.strip_whitespace(root)
    root.set("generationTool", f"bearing_fmu {__version__} build ({root.get('generationTool', 'PythonFMU')})")
    summary = BearingFMU.description
    if record is not None:
        root.set("modelName", record["model_name"])
        summary = fmu_meta.description_text(summary, record)
    root.set("description", summary + f" [code package {pkg}]")
    fmu_meta.set_author_and_license(root)

    mvars = root.find("ModelVariables")
    inputs, outputs, params_idx = [], [], []
    used_units = set()
    for index, sv in enumerate(mvars.findall("ScalarVariable"), start=1):
        name = sv.get("name")
        entry = table.get(name)
        causality = sv.get("causality")
        {"input": inputs, "output": outputs, "parameter": params_idx}.get(causality, []).append(index)
        real, integer = sv.find("Real"), sv.find("Integer")
        if entry is not None and name in (bearing or {}):  # a built-in bearing's bore and oil: their starts
            typed = sv.find(entry[1])
            if typed is not None and entry[1] != "Real":
                typed.set("start", {"Boolean": lambda x: "true" if x else "false", "Integer": lambda x: str(int(x)),
                                    "String": str}[entry[1]](entry[4]))
        if name in ENUMERATIONS and ENUMERATIONS[name][0] in (bearing or {}):  # the enumeration of such a choice
            string, items = ENUMERATIONS[name]
            sv.find("Integer").set("start", str(items.index(bearing[string]) + 1))
        if real is not None:
            if "start" in real.attrib:  # pythonfmu writes %.16g, which does not round-trip 9e-05
                start = entry[4] if entry is not None else real.get("start")
                real.set("start", repr(float(start)))
            if entry is not None:
                real.attrib.update(fmu_meta.real_attributes(name, entry[3], params, omega_ref))
                if entry[3]:
                    used_units.add(entry[3])
        elif integer is not None and name in ENUMERATIONS:  # FMI 2.0: an Integer-valued enumeration
            integer.tag = "Enumeration"
            integer.set("declaredType", fmu_meta.enum_type_name(ENUMERATIONS[name][0]))
        elif integer is not None:
            integer.attrib.update(fmu_meta.integer_attributes(name))

    if used_units:
        fmu_meta.place(root, fmu_meta.unit_definitions(used_units))
    fmu_meta.place(root, fmu_meta.type_definitions(
        [(string, list(enumerate(items, start=1))) for string, items in ENUMERATIONS.values()]))

    # map and linear (thermal off) are memoryless: a master may iterate them without FMU states;
    # tilting pads have states of their own: a static equilibrium is found in Initialization Mode
    fmu_meta.place(root, fmu_meta.memoryless_annotation(MEMORYLESS, stepped=STEPPED))

    structure = root.find("ModelStructure")
    for child in list(structure):
        structure.remove(child)
    deps = " ".join(map(str, inputs))
    kinds = " ".join(["dependent"] * len(inputs))
    out_node = ET.SubElement(structure, "Outputs")
    for i in outputs:
        ET.SubElement(out_node, "Unknown", index=str(i), dependencies=deps, dependenciesKind=kinds)
    # at initialisation the outputs are computed from the inputs and the parameters
    init_deps = sorted(inputs + params_idx)
    init_node = ET.SubElement(structure, "InitialUnknowns")
    for i in outputs:
        ET.SubElement(init_node, "Unknown", index=str(i), dependencies=" ".join(map(str, init_deps)),
                      dependenciesKind=" ".join(["dependent"] * len(init_deps)))
    # the GUID: a hash of this description (the code package's name hashes every bundled source,
    # the description names each data file's SHA-256), not pythonfmu's uuid1 of the build machine's
    # MAC address and time; pythonfmu's binary does not compare it
    root.set("guid", "")
    date = root.attrib.pop("generationDateAndTime", None)  # the same content: the same GUID
    g = hashlib.sha256(ET.tostring(root, encoding="UTF-8")).hexdigest()
    root.set("guid", "{" + f"{g[:8]}-{g[8:12]}-{g[12:16]}-{g[16:20]}-{g[20:32]}" + "}")
    if date is not None:
        root.set("generationDateAndTime", date)
    return parseString(ET.tostring(root, encoding="UTF-8")).toprettyxml(indent="  ", encoding="UTF-8")


def patch_linux_binary(data: bytes) -> tuple[bytes, str]:
    """pythonfmu 0.7.0's Linux binary with the bearing FMU's fixes (``fmu_binary``): the
    double release of its interpreter state at process exit, and the FMI statuses (a Python
    exception gives fmi2Error and keeps the instance; a discarded step leaves fmi2Terminated
    false). Returns (data, note): "already patched" when every patch was in,
    "patched" (plus what was left out, if anything) when the exit fix is in, else why not."""
    from .binary import patch_pythonfmu_binary

    data, notes = patch_pythonfmu_binary(data)
    if set(notes.values()) == {"already patched"}:
        return data, "already patched"
    left = "; ".join(f"{name}: {note}" for name, note in notes.items() if not note.endswith("patched"))
    if notes["exit-unload"].endswith("patched"):
        return data, "patched" + (f" (not: {left})" if left else "")
    return data, left


def _rewrite_zip(path: Path, pkg: str, bearing: dict | None = None, record: dict | None = None) -> None:
    import json

    from .binary import STATUS_PATCHES, patch_pythonfmu_binary, status_patched
    from .docs import documentation_html
    from .resources import PORT_DEFAULTS
    from .slave import BEARING_DEFAULTS, BUILD_INFO, PATCH_NOTES

    tmp = path.with_name(path.name + ".tmp")
    notes = {}
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "modelDescription.xml":
                data = _postprocess(data, pkg, bearing, record)
                if record is not None:  # the page is made from the model description just written
                    zout.writestr("documentation/index.html", documentation_html(data, record),
                                  compress_type=zipfile.ZIP_DEFLATED)
                    zout.writestr(f"resources/{BUILD_INFO}", json.dumps(record, indent=1, default=str) + "\n",
                                  compress_type=zipfile.ZIP_DEFLATED)
            elif item.filename.startswith("binaries/linux64/") and item.filename.endswith(".so"):
                data, notes["linux64"] = patch_pythonfmu_binary(data)
                _warn_unpatched(item.filename, notes["linux64"], STATUS_PATCHES, status_patched)
            elif "__pycache__" in item.filename:
                continue
            zout.writestr(item.filename, data, compress_type=zipfile.ZIP_DEFLATED)
        # the slave reads this to know whether a Python exception gives fmi2Error (patched) or
        # fmi2Fatal with a released instance (pythonfmu as is: then it never raises)
        zout.writestr(f"resources/{PATCH_NOTES}", json.dumps(notes, indent=1, sort_keys=True) + "\n",
                      compress_type=zipfile.ZIP_DEFLATED)
        if bearing:  # the slave's defaults for D, L, CR, mu (build --bearing), and for its bore and oil
            fields = ("D", "L", "CR", "mu", "source")
            zout.writestr(f"resources/{BEARING_DEFAULTS}",
                          json.dumps({k: bearing[k] for k in fields}, indent=1) + "\n", compress_type=zipfile.ZIP_DEFLATED)
            zout.writestr(f"resources/{PORT_DEFAULTS}",
                          json.dumps({k: v for k, v in bearing.items() if k not in fields}, indent=1) + "\n",
                          compress_type=zipfile.ZIP_DEFLATED)
    os.replace(tmp, path)


def _warn_unpatched(name: str, notes: dict, status_names, status_patched) -> None:
    import warnings

    if not notes.get("exit-unload", "").endswith("patched"):
        warnings.warn(f"bearing_fmu.fmu.build: {name}: {notes.get('exit-unload')}; the FMU may crash its host at "
                      "exit after all instances are freed (pythonfmu 0.7.0 bug)", stacklevel=4)
    if not status_patched(notes):
        why = "; ".join(f"{n}: {notes.get(n)}" for n in status_names if not notes.get(n, "").endswith("patched"))
        warnings.warn(f"bearing_fmu.fmu.build: {name}: the FMI status patches do not apply ({why}); the FMU reports "
                      "refused calls with fmi2OK and a logged error only (docs/fmu.md, FMI status)", stacklevel=4)


def check_surrogate_file(path) -> None:
    """Refuse a surrogate file the FMU could not use: read it with the FMU's own loader
    (``load_surrogate``: every key, type, shape, range and consistency; a JSON error with its
    line and column), build the Taylor internal behind its guard as the FMU does (with the
    stored training states' KD-tree). Raises ValueError / KeyError naming the file and key."""
    from ..internals.taylor.guard import DomainGuard
    from ..internals.taylor import Taylor
    from ..surrogates.surrogate import load_surrogate

    taylor = Taylor(load_surrogate(path))
    DomainGuard(taylor)
    if taylor.neighbours is not None:
        taylor.neighbours.nearest(taylor.surrogate.y0, taylor.surrogate.z0, 0.0, 0.0)


def check_data_file(path) -> None:
    """Refuse a data file (surrogate, force map) the FMU could not use, with the loader the FMU
    uses for the option that reads it (``internals.option_for_file``)."""
    from ..internals.registry import option_for_file

    option = option_for_file(path)
    if option.name == "surrogate":
        check_surrogate_file(path)
    elif option.name == "map":
        from ..internals.map.mapfile import load_any_map

        load_any_map(path).spline()
    else:  # pragma: no cover - a new file option adds its check here
        raise ValueError(f"{path}: no build check for the {option.name} option's files")


def build_fmu(output, surrogate=None, bearing=None, bearing_source: str = "") -> Path:
    """Write the bearing FMU to ``output`` (a ``.fmu`` path) and return its path.

    ``surrogate``: one path or a list of paths of surrogate JSON files to bundle in
    ``resources/surrogates/``; with exactly one, the parameter ``surrogate`` defaults to it.
    The default internal stays ``reynolds`` (at the solver's default grid); for a bearing with tilting
    pads, the internal that takes them (``Capabilities.pads``).
    ``bearing``: a BearingParams whose D, L, CR, mu, bore and oil (``ports.port_defaults``) become
    the FMU's defaults (the paper bearing's without), recorded with ``bearing_source`` (e.g. the
    bearing file) in the FMU.
    """
    from pythonfmu import FmuBuilder

    from ..internals import registry
    from ..io.outputs import write_bytes
    from ..physics.params import PAPER_BEARING
    from . import meta as fmu_meta

    output = Path(output)
    if output.suffix != ".fmu":
        raise ValueError(f"build_fmu: output {str(output)!r} must end in .fmu")
    if bearing is not None:
        from .ports import port_defaults, supply_starts

        bore_and_oil = port_defaults(bearing, pads=True)  # refuses what the parameters cannot hold, before building
        if bearing.geometry is not None and bearing.geometry.pads is not None:  # the internal that takes pads
            bore_and_oil["internal"] = registry.having(pads=True, fmu=True)[0]
    if surrogate is None:
        surrogates = []
    elif isinstance(surrogate, (str, os.PathLike)):
        surrogates = [Path(surrogate)]
    else:
        surrogates = [Path(s) for s in surrogate]
    for s in surrogates:
        if not s.is_file():
            raise FileNotFoundError(f"build_fmu: data file {str(s)!r} not found")
        check_data_file(s)
    names = [s.name for s in surrogates]
    if len(set(names)) != len(names):
        raise ValueError(f"build_fmu: surrogate file names must be distinct, got {names}")
    output.parent.mkdir(parents=True, exist_ok=True)

    before = set(sys.modules)
    old_path = list(sys.path)
    old_cache = os.environ.get("BEARING_FMU_CACHE_DIR")
    os.environ["BEARING_FMU_CACHE_DIR"] = "off"  # building imports the slave: no cache install
    try:
        with tempfile.TemporaryDirectory(prefix="bearing_fmu_build_") as tmp:
            stage = Path(tmp) / "stage"
            stage.mkdir()
            script, pkg, project = _stage(stage, surrogates)
            tmp_fmu = Path(tmp) / f"{MODEL_IDENTIFIER}.fmu"
            FmuBuilder.build_FMU(script, dest=tmp_fmu, project_files=project,
                                 canGetAndSetFMUstate=True, canSerializeFMUstate=True)
            defaults = None
            if bearing is not None:
                defaults = {**bearing.as_dict(), "source": str(bearing_source) or "given to build_fmu", **bore_and_oil,
                            **supply_starts(bearing)}
            first = bore_and_oil.get("internal", "reynolds") if bearing is not None else "reynolds"
            record = fmu_meta.build_record("python", registry.names(), first, bearing or PAPER_BEARING,
                                           bearing_source, surrogates)
            _rewrite_zip(tmp_fmu, pkg, defaults, record)
            # atomic: a parallel reader sees one whole FMU; a folder that refuses it (a full disk) has it
            # rescued beside it, and the path returned is where it is
            output = write_bytes(output, tmp_fmu.read_bytes())
    finally:
        # pythonfmu's builder imported the staged modules and left the stage on sys.path:
        # drop both, or a later FMU load in this process would reuse the deleted staging copy
        for name in set(sys.modules) - before:
            if name.startswith("bearing_fmu_v"):
                del sys.modules[name]
        sys.path[:] = old_path
        if old_cache is None:
            os.environ.pop("BEARING_FMU_CACHE_DIR", None)
        else:
            os.environ["BEARING_FMU_CACHE_DIR"] = old_cache
    return output
