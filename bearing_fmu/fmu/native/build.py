"""Write a native bearing FMU: FMI 2.0 Model Exchange and Co-Simulation in one archive, C
sources in ``sources/``, the binary for this platform compiled from them, no Python inside.

``build_native_fmu(output, internal, ...)``:

1. ``codegen.native_model``: the internal's data as C headers, its variables and options (several
   internals: ``several.several_model``, one binary switching among them);
2. stage ``sources/`` (the FMI 2.0 layer ``fmi2_*.c``, the model layer ``bearing_*.c`` that the
   FMI 3.0 FMU shares, ``internal_<name>.c``, their headers, from ``bearing_fmu/fmu/native/c/``,
   and the two generated headers),
   ``modelDescription.xml`` (both interfaces, units, output dependencies, the source files; what
   a system-simulation engineer reads in it: ``bearing_fmu.fmu.meta``), ``documentation/``
   (``bearing_fmu.fmu.docs``) and ``resources/build_info.json`` (the bearing, the data file and
   its SHA-256);
3. compile ``binaries/<platform>/<modelIdentifier>.<so|dll|dylib>`` (``compile``): by default
   for linux64, win64 and darwin64 with zig (the ``ziglang`` pip package), from any machine; or
   for this machine's platform with the system C compiler (``compiler="cc"``) or fmpy's CMake
   project (``compiler="cmake"``, which is also how a user rebuilds the binary from the sources:
   ``fmpy compile X.fmu``); every binary read back: only the FMI functions exported, only the C
   runtime needed;
4. zip, written atomically.

Flags: ``-O2 -ffp-contract=off``: no fused multiply-add, so the sums round as the Python
kernels' do, and alike on every platform.
"""

from __future__ import annotations

import datetime as _dt
import math
import shutil
import tempfile
import zipfile
from pathlib import Path
from xml.dom.minidom import parseString
from xml.etree import ElementTree as ET

from ... import __version__
from ...physics.params import PAPER_BEARING, BearingParams
from ...internals import registry
from .catalogue import NATIVE
from .codegen import MODEL_HEADERS, MODEL_SOURCES, NativeModel, assign_identity, internal_sources
from .compile import (C_FLAGS, NativeBuildError, compile_binaries, find_compiler, fmi_headers,  # noqa: F401
                      parse_platforms)

C_DIR = Path(__file__).resolve().parent / "c"
# the FMI 2.0 layer over the model layer (codegen.MODEL_SOURCES)
HEADERS2 = MODEL_HEADERS
SOURCES2 = ("fmi2_bearing.c", *MODEL_SOURCES)


def build_native_fmu(output, internal: str, *, surrogate=None, map=None, bearing: BearingParams | None = None,
                     options: dict | None = None, cmake: bool = False, bearing_source="", platforms=None,
                     compiler: str | None = None, speed_hz: float | None = None, fmi_version: int = 2,
                     thermal: bool = False) -> Path:
    """Write the native FMU of ``internal`` (reynolds | taylor | map | linear | tilting_pad) to ``output`` (.fmu).

    surrogate : taylor: the surrogate JSON file compiled in (the bearing defaults to its own)
    map       : map: the force map JSON file; linear: linearise on this map (no Reynolds)
    bearing   : the bearing (default: the surrogate's for taylor, else the paper bearing); reynolds: any
                bore (its geometry compiled in); tilting_pad: a bearing with pads (compiled in); the
                others the full bore
    bearing_source : where ``bearing`` came from (its file: recorded with its SHA-256)
    options   : registry options: taylor's domain_action / domain_limit start values, linear's
                linear_from, load_y, load_z, omega_lin, lin_* (the coefficients' start values),
                reynolds's n_theta, n_x, cavitation (start values; parameters of the FMU)
    speed_hz  : map, linear: the start value of the input omega [Hz] (linear: its omega_lin); default
                the linear model's speed, map 22 Hz; taylor: always the surrogate's speed
    platforms : binaries/ folders to compile (compile.PLATFORMS; default: all with zig, else the host's)
    compiler  : zig (default: every platform), cc (the system C compiler) or cmake (fmpy's CMake
                project), the last two for this machine's platform only; ``cmake=True`` means cmake
    fmi_version : 2, or 3 for an FMI 3.0 FMU of the same internal (``fmi3``; binaries per platform
                tuple)
    thermal   : the start value of the parameter thermal: True starts the thermal model without a
                master setting it (a tool that sets no parameters, the Compliance Checker); needs the
                Reynolds internal or a map with flow tables, and a bearing with an [oil] law
                (``portgen.thermal_start``)
    """
    output = Path(output)
    if fmi_version not in (2, 3):
        raise ValueError(f"build_native_fmu: fmi_version {fmi_version!r} must be 2 or 3")
    if output.suffix != ".fmu":
        raise ValueError(f"build_native_fmu: output {str(output)!r} must end in .fmu")
    for label, path in (("surrogate", surrogate), ("map", map)):
        if path is not None and not Path(path).is_file():
            raise FileNotFoundError(f"build_native_fmu: {label} file {str(path)!r} not found")
    from .several import parse_internals, several_model

    parts = parse_internals(internal)
    # any bore compiled in (reynolds), or its data file's (a map FMU: a grooved bore's 3-D map, checked
    # against the bearing's by its generator); the others the full bore only
    if bearing is not None and any(NATIVE[p].bore == "full" or (NATIVE[p].bore == "data" and map is None)
                                   for p in parts):
        bearing.require_full_bore(f"the native bearing FMU ({bearing_source or 'build_native_fmu'})",
                                  "its parameters are D, L, CR and mu; the geometry parameters are a later step")
    compiler = compiler or ("cmake" if cmake else "zig")
    platforms = parse_platforms(",".join(platforms) if platforms else None, compiler)  # refused before any work
    own = any(NATIVE[p].own_bearing for p in parts)  # its data file's bearing (a Taylor surrogate's)
    params = bearing if bearing is not None else (None if own else PAPER_BEARING)
    model = several_model(parts, params, surrogate=surrogate, map=map, options=options,  # one, or several
                          omega=None if speed_hz is None else 2.0 * math.pi * float(speed_hz))
    if thermal:
        from .portgen import thermal_start

        thermal_start(model)
    from ...io.outputs import write_bytes

    record = build_record(model, bearing_source if bearing is not None else "")
    with tempfile.TemporaryDirectory(prefix="bearing_native_") as tmp:
        root = Path(tmp) / "fmu"
        if fmi_version == 3:
            from .fmi3 import DEFINES3, source_files3, stage3

            stage3(model, root, record)
            compile_binaries(root, model.model_identifier, source_files3(model), platforms, compiler, fmi_version=3,
                             defines=tuple(f"-D{k}={v}" for k, v in DEFINES3.items()))
        else:
            stage(model, root, record)
            compile_binaries(root, model.model_identifier, source_files(model), platforms, compiler)
        archive = Path(tmp) / "out.fmu"
        _zip(root, archive)
        output.parent.mkdir(parents=True, exist_ok=True)
        output = write_bytes(output, archive.read_bytes())  # where it is: rescued beside a full folder
    return output


def source_files(model: NativeModel) -> list[str]:
    """The C files the compiler builds (the headers are included by them)."""
    return [*SOURCES2, *internal_sources(model)[0]]


def build_record(model: NativeModel, bearing_source="") -> dict:
    """What the FMU was built from (``fmu_meta.build_record``): the bearing (its file, or the
    surrogate it was fitted for), the data file compiled in or linearised on, what was compiled."""
    from ..meta import build_record as record

    source, is_file = bearing_source, True
    if not bearing_source and any(NATIVE[p].own_bearing for p in model.all_parts):
        source, is_file = f"the bearing the surrogate {model.source.name} was fitted for", False
    compiled = {k: v for k, v in model.info.items() if k not in ("provenance", "source")}
    return record("native", list(model.all_parts), model.internal, model.params, source,
                  [model.source] if model.source else [], is_file, {"compiled": compiled})


def stage(model: NativeModel, root: Path, record: dict | None = None) -> None:
    """Write sources/, modelDescription.xml, documentation/ and resources/build_info.json of
    ``model`` under ``root``."""
    import json

    from ..docs import write_documentation

    record = record if record is not None else build_record(model)
    src = root / "sources"
    src.mkdir(parents=True)
    names = (*HEADERS2, *internal_sources(model)[1], *source_files(model))
    assign_identity(model, {n: (C_DIR / n).read_text(encoding="ascii") for n in names},
                    lambda: model_description(model, record))
    for name in names:
        shutil.copyfile(C_DIR / name, src / name)
    (src / "model_config.h").write_text(model.config_h, encoding="ascii")
    (src / "model_data.h").write_text(model.data_h, encoding="ascii")
    (root / "binaries").mkdir()
    xml = model_description(model, record)
    (root / "modelDescription.xml").write_bytes(xml)
    write_documentation(root / "documentation", xml, record)
    (root / "resources").mkdir()
    (root / "resources" / "build_info.json").write_text(json.dumps(record, indent=1, default=str) + "\n")


# ----------------------------------------------------------------------------- model description

def model_description(model: NativeModel, record: dict) -> bytes:
    """modelDescription.xml: FMI 2.0, Model Exchange and Co-Simulation, same variables; units,
    display units, ranges, enumerations, author, license, name and description (``fmu_meta``)."""
    from .. import meta as fmu_meta
    from .codegen import native_enumerations

    guid = model.info["guid"]
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0",
        "modelName": record["model_name"],
        "guid": guid,
        "description": fmu_meta.description_text(model.description, record),
        "version": __version__,
        "generationTool": f"bearing_fmu {__version__} native build",
        "generationDateAndTime": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "flat",
        "numberOfEventIndicators": "0",
    })
    fmu_meta.set_author_and_license(root)
    common = {"modelIdentifier": model.model_identifier, "canGetAndSetFMUstate": "true",
              "canSerializeFMUstate": "true", "providesDirectionalDerivative": "true",
              "canNotUseMemoryManagementFunctions": "false"}
    me = ET.SubElement(root, "ModelExchange", {**common, "completedIntegratorStepNotNeeded": "false"})
    cs = ET.SubElement(root, "CoSimulation", {**common, "canHandleVariableCommunicationStepSize": "true"})
    for node in (me, cs):
        files = ET.SubElement(node, "SourceFiles")
        for name in source_files(model):
            ET.SubElement(files, "File", name=name)
    root.append(fmu_meta.unit_definitions({v.unit for v in model.variables if v.unit}))
    enums = native_enumerations(model.all_parts)
    root.append(fmu_meta.type_definitions([(string, items) for _n, string, items in enums]))
    cats = ET.SubElement(root, "LogCategories")
    for name, what in (("warning", "a state outside the fitted domain (once per excursion, counted at terminate), "
                        "outputs left at their start values"),
                       ("discard", "a state the internal refuses (the wall, a non-finite input, far outside the "
                        "fitted domain)"),
                       ("error", "a refused call (a bad value, a call out of the FMI 2.0 calling sequence)")):
        ET.SubElement(cats, "Category", name=name, description=what)
    ET.SubElement(root, "DefaultExperiment", startTime="0.0", stopTime="0.1", stepSize="0.0001")
    # the internals whose outputs follow the inputs alone (fmu_meta.memoryless_annotation): a master
    # iterates them without saving and restoring FMU states; not the Reynolds solver (it warm-starts
    # from the previous call's film) nor the Taylor surrogate (its warnings count excursions from the
    # previous call's state, out_of_domain in the FMU state)
    memoryless = [p for p in model.all_parts if NATIVE[p].memoryless]
    # the internals with states of their own over a step (tilting pads): a host keeps the FMU in
    # Initialization Mode for its static equilibrium, where the pads answer in moment equilibrium
    stepped = [p for p in model.all_parts if registry.get(p).can.step_states]
    if memoryless or stepped:
        root.append(fmu_meta.memoryless_annotation(memoryless, stepped=stepped))
    mvars = ET.SubElement(root, "ModelVariables")
    omega_ref = fmu_meta.reference_speed(next(v.start for v in model.variables if v.name == "omega"))
    index = {}
    for k, v in enumerate(model.variables, start=1):
        index[v.name] = k
        attrs = {"name": v.name, "valueReference": str(v.vr), "description": v.description,
                 "causality": v.causality, "variability": v.variability}
        if v.causality in ("output", "local"):
            attrs["initial"] = "calculated"
        sv = ET.SubElement(mvars, "ScalarVariable", attrs)
        typed = {"declaredType": v.declared_type} if v.declared_type else {}
        if v.state:  # Model Exchange's state derivative (portgen.has_state; the pads' tilts and rates)
            typed["derivative"] = str(index[v.state])
        if v.causality not in ("output", "local"):
            typed["start"] = (repr(float(v.start)) if v.type == "Real" else
                              ("true" if v.start else "false") if v.type == "Boolean" else str(v.start))
        if v.type == "Real":
            typed.update(fmu_meta.real_attributes(v.name, v.unit, model.params, omega_ref))
            if v.nominal:
                typed["nominal"] = repr(float(v.nominal))
        elif v.type == "Integer":
            typed.update(fmu_meta.integer_attributes(v.name))
        ET.SubElement(sv, v.type, typed)
    inputs = [index[v.name] for v in model.variables if v.causality == "input"]
    outputs = [index[v.name] for v in model.variables if v.causality == "output"]
    params = [index[v.name] for v in model.variables if v.causality == "parameter"]
    structure = ET.SubElement(root, "ModelStructure")
    node = ET.SubElement(structure, "Outputs")
    from .fmi3 import derivative_dependencies, output_dependencies  # noqa: PLC0415 - one table, both versions

    depends = output_dependencies(model)
    for i, v in zip(outputs, [v for v in model.variables if v.causality == "output"]):
        own = [index[n] for n in depends[v.name]] if v.name in depends else inputs
        ET.SubElement(node, "Unknown", index=str(i), dependencies=" ".join(map(str, own)),
                      dependenciesKind=" ".join(["dependent"] * len(own)))
    derivatives = derivative_dependencies(model)
    if derivatives:  # der(T_eff): the state and every input; the pads': the journal and the pads' states
        node = ET.SubElement(structure, "Derivatives")
        for name, names in derivatives.items():
            own = sorted(index[n] for n in names)
            ET.SubElement(node, "Unknown", index=str(index[name]), dependencies=" ".join(map(str, own)),
                          dependenciesKind=" ".join(["dependent"] * len(own)))
    node = ET.SubElement(structure, "InitialUnknowns")
    deps = sorted(inputs + params)
    for i in sorted(set(outputs) | {index[n] for n in derivatives}):
        ET.SubElement(node, "Unknown", index=str(i), dependencies=" ".join(map(str, deps)),
                      dependenciesKind=" ".join(["dependent"] * len(deps)))
    return parseString(ET.tostring(root, encoding="UTF-8")).toprettyxml(indent="  ", encoding="UTF-8")


def _zip(root: Path, archive: Path) -> None:
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as z:
        for p in sorted(root.rglob("*")):
            if p.is_file():
                z.write(p, p.relative_to(root).as_posix())


def prepare_zig_runtimes() -> list[str]:
    """Have zig build the C runtime of every target platform into its cache (``~/.cache/zig``) now,
    by building the smallest native FMU (the linear internal of the paper bearing) for every
    platform, FMI 2.0 and 3.0, in a temporary folder: once per machine and zig version, the first
    Windows build compiles MinGW's runtime (~2 min of one core), each other target 5-15 s; every
    later build finds them (the compilers run in one folder whoever starts them:
    ``compile.run_compiler``). For a build machine's (or CI's) set-up step. Returns the binaries'
    folders built (FMI 2.0's and 3.0's)."""
    folders: set[str] = set()
    with tempfile.TemporaryDirectory(prefix="bearing_zig_prepare_") as tmp:
        for v in (2, 3):
            fmu = build_native_fmu(Path(tmp) / f"linear_fmi{v}.fmu", "linear", fmi_version=v, compiler="zig")
            with zipfile.ZipFile(fmu) as z:
                folders |= {str(Path(n).parent) for n in z.namelist() if n.startswith("binaries/")}
    return sorted(folders)

