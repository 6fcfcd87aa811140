"""The FMI 3.0 native FMU: what differs from the FMI 2.0 one, over the same internals and data.

``build.build_native_fmu(..., fmi_version=3)`` stages it with ``stage3`` and compiles
``source_files3`` with ``BN_FMI_VERSION=3`` into ``binaries/<platform tuple>/`` (x86_64-linux
here). Everything here is made from the ``codegen.NativeModel`` the FMI 2.0 build uses:

* ``ALLOWED3``: which FMI 3.0 function is allowed in which mode (the FMI 3.0.2 state machines of
  sections 2.3, 3.1 and 4.1), over the modes the FMI 2.0 FMU has (``order.MODES``: Instantiated,
  Initialization Mode, Step Mode, Event Mode, Continuous-Time Mode, Terminated), written into
  ``fmi3_config.h`` as one bit mask per function (``c_defines3``). This FMU has no Event Mode in
  Co-Simulation (hasEventMode false), no clocks, no structural parameters, no Scheduled Execution.
* ``model_description3``: the variables of the FMI 2.0 FMU, same names and value references,
  as Float64, Boolean, String and Enumeration (an Int64, FMI 3.0), the independent variable
  ``time`` (value reference ``VR_TIME``), units and display units (``fmu.meta``), ModelStructure
  with value references (Output, InitialUnknown);
* ``build_description3``: sources/buildDescription.xml, what fmpy's CMake project (and any FMI
  3.0 importer that compiles sources) needs: the C files, C99, ``BN_FMI_VERSION=3``;
* ``instantiation_token``: a hash of the model description (without its token and date), the
  C sources and the generated data: a binary refuses a description of another build.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import shutil
from pathlib import Path
from xml.dom.minidom import parseString
from xml.etree import ElementTree as ET

from ... import __version__
from ...internals import registry
from .. import meta as fmu_meta
from ..order import MODES
from .codegen import (MODEL_HEADERS, MODEL_SOURCES, NativeModel, assign_identity, internal_sources,
                      native_enumerations)
from .portgen import PEAK_OUTPUTS, has_state

C_DIR = Path(__file__).resolve().parent / "c"
VR_TIME = 4000  # the independent variable (FMI 3.0 only; the others keep the FMI 2.0 FMU's references)
# the C files compiled, with internal_<name>.c
SOURCES3 = ("fmi3_bearing.c", "fmi3_modes.c", *MODEL_SOURCES)
HEADERS3 = (*MODEL_HEADERS, "fmi3_layer.h")
DEFINES3 = {"BN_FMI_VERSION": "3"}  # bearing_native.h: the FMI 3.0 headers and instance fields
LOG_CATEGORIES = (("logStatusWarning", ("a state outside the fitted domain (once per excursion, counted at "
                                        "terminate), outputs left at their start values")),
                  ("logStatusDiscard", ("a state the internal refuses (the wall, a non-finite input, far outside "
                                        "the fitted domain)")),
                  ("logStatusError", ("a refused call (a bad value, a call out of the FMI 3.0 calling sequence); "
                                      "given to the logger even with logging off (FMI 3.0)")))

# ----------------------------------------------------------------------------- the calling sequence

INSTANTIATED, INIT, STEP, EVENT, CONTINUOUS, TERMINATED = (name for _c, name in MODES)
_ALL = frozenset(name for _c, name in MODES)
_TYPES = ("Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64",
          "Boolean", "String", "Binary")
# FMI 3.0 function without "fmi3" -> the modes it is allowed in. fmi3FreeInstance, fmi3GetVersion,
# the instantiation functions and what this FMU does not provide (clocks, configuration mode,
# Scheduled Execution) are not here: allowed always, or refused always.
ALLOWED3: dict[str, frozenset] = {
    "SetDebugLogging": _ALL,
    "Reset": _ALL,
    "EnterInitializationMode": frozenset({INSTANTIATED}),
    "ExitInitializationMode": frozenset({INIT}),
    "EnterEventMode": frozenset({CONTINUOUS}),  # Co-Simulation: no Event Mode here
    "Terminate": frozenset({EVENT, CONTINUOUS, STEP}),
    # getting: start values in Instantiated (an output there is refused by the variable), every
    # value after; setting: inputs and parameters before initialisation, inputs after (the
    # variable decides), only continuous-time inputs (Float64) in Continuous-Time Mode
    **{f"Get{t}": _ALL for t in _TYPES},
    **{f"Set{t}": frozenset({INSTANTIATED, INIT, EVENT, STEP})
       | ({CONTINUOUS} if t.startswith("Float") else set()) for t in _TYPES},
    "GetNumberOfVariableDependencies": _ALL,
    "GetVariableDependencies": _ALL,
    **{f: _ALL for f in ("GetFMUState", "SetFMUState", "FreeFMUState", "SerializedFMUStateSize",
                         "SerializeFMUState", "DeserializeFMUState")},
    "GetDirectionalDerivative": frozenset({INIT, EVENT, CONTINUOUS, STEP, TERMINATED}),
    "GetAdjointDerivative": frozenset({INIT, EVENT, CONTINUOUS, STEP, TERMINATED}),
    "EvaluateDiscreteStates": frozenset({EVENT}),
    "UpdateDiscreteStates": frozenset({EVENT}),
    # Model Exchange
    "EnterContinuousTimeMode": frozenset({EVENT}),
    "CompletedIntegratorStep": frozenset({CONTINUOUS}),
    "SetTime": frozenset({CONTINUOUS}),
    "SetContinuousStates": frozenset({CONTINUOUS}),
    **{f: frozenset({INIT, EVENT, CONTINUOUS, TERMINATED}) for f in (
        "GetContinuousStateDerivatives", "GetEventIndicators", "GetContinuousStates",
        "GetNominalsOfContinuousStates")},
    "GetNumberOfEventIndicators": _ALL,
    "GetNumberOfContinuousStates": _ALL,
    # Co-Simulation
    "EnterStepMode": frozenset({EVENT}),
    "DoStep": frozenset({STEP}),
    "GetOutputDerivatives": frozenset({STEP, TERMINATED}),
}
MODEL_EXCHANGE_ONLY = frozenset({"EnterEventMode", "UpdateDiscreteStates", "EvaluateDiscreteStates",
                                 "EnterContinuousTimeMode", "CompletedIntegratorStep", "SetTime",
                                 "SetContinuousStates", "GetContinuousStateDerivatives", "GetEventIndicators",
                                 "GetContinuousStates", "GetNominalsOfContinuousStates",
                                 "GetNumberOfEventIndicators", "GetNumberOfContinuousStates"})
CO_SIMULATION_ONLY = frozenset({"EnterStepMode", "DoStep", "GetOutputDerivatives"})


def c_defines3() -> list[str]:
    """``BN3_ALLOW_<function>``: bit k set when the function is allowed in the k-th of MODES."""
    out = []
    for call, allowed in ALLOWED3.items():
        mask = sum(1 << k for k, (_c, name) in enumerate(MODES) if name in allowed)
        out.append(f"#define BN3_ALLOW_{call} 0x{mask:02x}u")
    return out


# ----------------------------------------------------------------------------- the model description

def _attrs(v, model: NativeModel, omega_ref: float) -> dict:
    """One variable's attributes (FMI 3.0: on the typed element itself)."""
    attrs = {"name": v.name, "valueReference": str(v.vr), "description": v.description,
             "causality": v.causality, "variability": v.variability}
    if v.causality in ("output", "local"):
        attrs["initial"] = "calculated"
    if v.state:  # Model Exchange's state derivative (portgen.has_state; the pads' tilts and rates)
        attrs["derivative"] = str(next(w.vr for w in model.variables if w.name == v.state))
    if v.declared_type:
        attrs["declaredType"] = v.declared_type
    if v.type == "Real":
        attrs.update(fmu_meta.real_attributes(v.name, v.unit, model.params, omega_ref))
        if v.nominal:
            attrs["nominal"] = repr(float(v.nominal))
    elif v.type == "Integer":
        attrs.update(fmu_meta.integer_attributes(v.name))
    if v.causality not in ("output", "local") and v.type != "String":
        attrs["start"] = (repr(float(v.start)) if v.type == "Real" else
                          ("true" if v.start else "false") if v.type == "Boolean" else str(v.start))
    return attrs


def _type_definitions(model: NativeModel) -> ET.Element:
    types = ET.Element("TypeDefinitions")
    for _name, string, items in native_enumerations(model.all_parts):
        enum = ET.SubElement(types, "EnumerationType", name=fmu_meta.enum_type_name(string),
                             description=f"the choices of the parameter {string}")
        for value, item in items:
            attrs = {"name": item, "value": str(value)}
            if fmu_meta.item_description(string, item):
                attrs["description"] = fmu_meta.item_description(string, item)
            ET.SubElement(enum, "Item", attrs)
    return types


def output_dependencies(model: NativeModel) -> dict[str, list[str]]:
    """Output -> the inputs (and Model Exchange's state) it depends on after initialisation (fixed
    parameters cannot change then, so they are no knowns: FMI 3.0, section 2.2.11): the film force
    and its tangent on the whole journal state, the eccentricity and the minimum film on the
    position, out_of_domain on the state the fitted domain is drawn in (none for an internal
    without one: always false). A build with the state T_eff (``portgen.has_state``): the force,
    K, C and P_loss at the viscosity of T_eff, so on it too; Q_side on the journal state alone,
    mu_eff on T_eff alone; T_eff on itself and on T_supply (Co-Simulation with thermal = false:
    T_eff reads T_supply). T_supply reaches the others only through T_eff, a state (Model Exchange's,
    or held between Co-Simulation steps): no direct feedthrough, so an oil circuit that makes
    T_supply from P_loss is no algebraic loop (docs/thermal.md, "Directional derivatives")."""
    fitted = any(registry.get(p).can.fitted_domain for p in model.all_parts)
    thermal = has_state(model.all_parts, model.params, model.flows_why)  # thermal = true can be set (T_eff: ME's state)
    journal = ["y", "z", "vy", "vz", "omega"]
    pads = pad_states(model)  # the force and the pads' outputs at the pads' states too
    ports = ({"T_eff": ["T_supply", "T_eff"], "P_loss": journal + ["T_eff"], "Q_side": journal, "mu_eff": ["T_eff"]}
             if thermal else {"T_eff": ["T_supply"], "P_loss": [], "Q_side": [], "mu_eff": []})  # off: Ts, 0, 0, mu
    out = {}
    for v in model.variables:
        if v.causality != "output":
            continue
        if v.name in ("eccentricity", "h_min"):
            out[v.name] = ["y", "z"]
        elif v.name == "out_of_domain":
            out[v.name] = ["y", "z", "vy", "vz"] if fitted else []
        elif v.name in ports:
            out[v.name] = ports[v.name]
        elif v.name in PEAK_OUTPUTS and not any(registry.get(p).can.film_field for p in model.all_parts):  # always 0
            out[v.name] = []
        else:  # with the thermal model the force is at the viscosity of T_eff (Model Exchange: the state)
            out[v.name] = journal + (["T_eff"] if thermal else []) + pads
    return out


def pad_states(model: NativeModel) -> list[str]:
    """The pads' continuous states (generators/tilting_pad.py: the tilts, with inertia the rates)."""
    return [v.state for v in model.variables if v.state and v.state.startswith("pad_")]


def derivative_dependencies(model: NativeModel) -> dict[str, list[str]]:
    """Model Exchange's state derivative -> what it depends on: der(T_eff) on its state and every
    input; the pads' on the journal state and every pad state (the pads are coupled through it)."""
    inputs = [v.name for v in model.variables if v.causality == "input"]
    pads = pad_states(model)
    return {v.name: inputs + [v.state] if v.state == "T_eff" else ["y", "z", "vy", "vz", "omega"] + pads
            for v in model.variables if v.state}


def model_description3(model: NativeModel, record: dict, token: str, generated: str = "") -> bytes:
    """modelDescription.xml (FMI 3.0) of ``model``; ``generated``: its date and time (now if "")."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "3.0",
        "modelName": record["model_name"],
        "instantiationToken": token,
        "description": fmu_meta.description_text(model.description, record),
        "version": __version__,
        "generationTool": f"bearing_fmu {__version__} native build (FMI 3.0)",
        "generationDateAndTime": generated or _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "flat",
    })
    fmu_meta.set_author_and_license(root)
    common = {"modelIdentifier": model.model_identifier, "canGetAndSetFMUState": "true",
              "canSerializeFMUState": "true", "providesDirectionalDerivatives": "true",
              "providesAdjointDerivatives": "true", "providesPerElementDependencies": "true"}
    # out_of_domain is discrete: in Continuous-Time Mode it keeps its value of the last event, and
    # fmi3CompletedIntegratorStep asks for an event when the state crossed the domain's edge
    fitted = any(registry.get(p).can.fitted_domain for p in model.all_parts)
    ET.SubElement(root, "ModelExchange", {**common, "needsCompletedIntegratorStep": "true" if fitted else "false"})
    ET.SubElement(root, "CoSimulation", {**common, "canHandleVariableCommunicationStepSize": "true"})
    root.append(fmu_meta.unit_definitions({v.unit for v in model.variables if v.unit}))
    root.append(_type_definitions(model))
    cats = ET.SubElement(root, "LogCategories")
    for name, what in LOG_CATEGORIES:
        ET.SubElement(cats, "Category", name=name, description=what)
    ET.SubElement(root, "DefaultExperiment", startTime="0.0", stopTime="0.1", stepSize="0.0001")
    mvars = ET.SubElement(root, "ModelVariables")
    ET.SubElement(mvars, "Float64", name="time", valueReference=str(VR_TIME), causality="independent",
                  variability="continuous", description="simulation time [s]: the independent variable")
    omega_ref = fmu_meta.reference_speed(next(v.start for v in model.variables if v.name == "omega"))
    tag = {"Real": "Float64", "Boolean": "Boolean", "String": "String", "Enumeration": "Enumeration", "Integer": "Int64"}
    for v in model.variables:
        el = ET.SubElement(mvars, tag[v.type], _attrs(v, model, omega_ref))
        if v.type == "String":
            ET.SubElement(el, "Start", value=str(v.start))
    vr = {v.name: v.vr for v in model.variables}
    structure = ET.SubElement(root, "ModelStructure")
    for name, deps in output_dependencies(model).items():
        ET.SubElement(structure, "Output", valueReference=str(vr[name]),
                      dependencies=" ".join(str(vr[d]) for d in deps),
                      dependenciesKind=" ".join(["dependent"] * len(deps)))
    for name, names in derivative_dependencies(model).items():
        deps = sorted(vr[d] for d in names)
        ET.SubElement(structure, "ContinuousStateDerivative", valueReference=str(vr[name]),
                      dependencies=" ".join(map(str, deps)), dependenciesKind=" ".join(["dependent"] * len(deps)))
    # in Initialization Mode the knowns are the inputs and every parameter (initial = exact)
    knowns = sorted(v.vr for v in model.variables if v.causality in ("input", "parameter"))
    for v in model.variables:
        if v.causality == "output" or v.state:
            ET.SubElement(structure, "InitialUnknown", valueReference=str(v.vr),
                          dependencies=" ".join(map(str, knowns)),
                          dependenciesKind=" ".join(["dependent"] * len(knowns)))
    return parseString(ET.tostring(root, encoding="UTF-8")).toprettyxml(indent="  ", encoding="UTF-8")


def source_files3(model: NativeModel) -> list[str]:
    """The C files the compiler builds for the FMI 3.0 FMU (the headers are included by them)."""
    return [*SOURCES3, *internal_sources(model)[0]]


def build_description3(model: NativeModel) -> bytes:
    """sources/buildDescription.xml (FMI 3.0, section 2.5.1)."""
    root = ET.Element("fmiBuildDescription", fmiVersion="3.0")
    conf = ET.SubElement(root, "BuildConfiguration", modelIdentifier=model.model_identifier,
                         description="the FMI 3.0 layer over the bearing internal; compile without fused "
                                     "multiply-add (gcc, clang: -ffp-contract=off) for the same force bits as "
                                     "the Python internals")
    files = ET.SubElement(conf, "SourceFileSet", language="C99")
    for name in source_files3(model):
        ET.SubElement(files, "SourceFile", name=name)
    for name, value in DEFINES3.items():
        ET.SubElement(files, "PreprocessorDefinition", name=name, value=value,
                      description="bearing_native.h: the FMI 3.0 layer (fmi3Functions.h)")
    ET.SubElement(conf, "Library", name="m", external="true",
                  description="the C math library (libm on Linux; part of the C runtime elsewhere)")
    return parseString(ET.tostring(root, encoding="UTF-8")).toprettyxml(indent="  ", encoding="UTF-8")


def config3_h(model: NativeModel, token: str) -> str:
    """fmi3_config.h: the instantiation token, the independent variable, the calling sequence."""
    fitted = any(registry.get(p).can.fitted_domain for p in model.all_parts)
    lines = ["/* Generated by bearing_fmu.fmu.native.fmi3. Do not edit. */", "#ifndef FMI3_CONFIG_H",
             "#define FMI3_CONFIG_H", f'#define BN3_TOKEN "{token}"', f"#define BN3_VR_TIME {VR_TIME}",
             f"#define BN3_FITTED_DOMAIN {int(fitted)}", *c_defines3(), "#endif", ""]
    return "\n".join(lines)


def instantiation_token(model: NativeModel, record: dict) -> str:
    """A GUID-shaped hash of what the binary is: the model description without its token and
    date, the C sources, the generated data and the calling sequence."""
    h = hashlib.sha256()
    h.update(model_description3(model, record, "", "2000-01-01T00:00:00Z"))
    for name in (*HEADERS3, *source_files3(model)):
        h.update(name.encode() + b"\0" + (C_DIR / name).read_bytes())
    for text in (model.config_h, model.data_h, "\n".join(c_defines3())):
        h.update(text.encode() + b"\0")
    d = h.hexdigest()
    return "{" + f"{d[:8]}-{d[8:12]}-{d[12:16]}-{d[16:20]}-{d[20:32]}" + "}"


def stage3(model: NativeModel, root: Path, record: dict) -> None:
    """Write sources/ (with buildDescription.xml), modelDescription.xml, documentation/ and
    resources/build_info.json of the FMI 3.0 FMU of ``model`` under ``root``."""
    from ..docs import write_documentation

    record = {**record, "fmi_version": "3.0"}
    # the model identifier hashes the sources and data (as the FMI 2.0 build: codegen.assign_identity)
    names = (*HEADERS3, *internal_sources(model)[1], *source_files3(model))
    assign_identity(model, {n: (C_DIR / n).read_text(encoding="ascii") for n in names},
                    lambda: model_description3(model, record, "", "2000-01-01T00:00:00Z"))
    token = instantiation_token(model, record)
    src = root / "sources"
    src.mkdir(parents=True)
    for name in names:
        shutil.copyfile(C_DIR / name, src / name)
    (src / "model_config.h").write_text(model.config_h, encoding="ascii")
    (src / "model_data.h").write_text(model.data_h, encoding="ascii")
    (src / "fmi3_config.h").write_text(config3_h(model, token), encoding="ascii")
    (src / "buildDescription.xml").write_bytes(build_description3(model))
    (root / "binaries").mkdir()
    xml = model_description3(model, record, token)
    (root / "modelDescription.xml").write_bytes(xml)
    write_documentation(root / "documentation", xml, record)
    (root / "resources").mkdir()
    (root / "resources" / "build_info.json").write_text(json.dumps(record, indent=1, default=str) + "\n")


__all__ = ["ALLOWED3", "VR_TIME", "build_description3", "c_defines3", "derivative_dependencies", "instantiation_token",
           "model_description3", "output_dependencies", "pad_states", "source_files3", "stage3"]
