"""What a system-simulation engineer reads in a bearing FMU's model description, one definition
for both builds (the Python FMU, ``bearing_fmu.fmu.build``; the native FMU, ``bearing_fmu.fmu.native.build``).

* units and the display units a user reads (um for displacements and the clearance, mm for D
  and L, mm/s for velocities, rpm for speeds): ``UNITS``, ``DISPLAY_UNITS``, ``DISPLAY``;
* min / max / nominal of each variable, from the physics: the bearing's ranges of
  ``params`` (the absolute envelope of every bearing, as D may change with L and CR), the
  registry options' ranges, the film's force scale for the nominals (``real_attributes``);
* the choice parameters (``internal``, ``domain_action``, ``cavitation``, ``linear_from``) as
  FMI 2.0 enumerations beside their String (``slave.ENUMERATIONS``; ``type_definitions``);
* author and license from the project's metadata (pyproject.toml), a model name per build
  (``model_name``), and the build record: the bearing's geometry and where it came from, the
  data files with their SHA-256 (``build_record``), written to ``resources/build_info.json``,
  into the description text and into ``documentation/index.html`` (``bearing_fmu.fmu.docs``).

Build tooling: not bundled into the Python FMU.
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path
from xml.etree import ElementTree as ET

from .. import __version__
from ..internals import registry
from . import ports
from ..physics.params import CR_OVER_R_RANGE, D_RANGE_M, L_OVER_D_RANGE, MU_RANGE_PA_S, PAPER_BEARING, BearingParams

# unit name -> SI base-unit exponents (FMI 2.0 BaseUnit attributes)
UNITS = {
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "rad/s": {"rad": 1, "s": -1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "Pa.s": {"kg": 1, "m": -1, "s": -1},
    "1": {},
    # the bore, the oil and the thermal ports (ports.py)
    "rad": {"rad": 1},
    "Pa": {"kg": 1, "m": -1, "s": -2},
    "K": {"K": 1},
    "K/s": {"K": 1, "s": -1},
    "W": {"kg": 1, "m": 2, "s": -3},
    "m3/s": {"m": 3, "s": -1},
    "m2/s": {"m": 2, "s": -1},
    "kg/m3": {"kg": 1, "m": -3},
    "J/(kg.K)": {"m": 2, "s": -2, "K": -1},
    "W/K": {"kg": 1, "m": 2, "s": -3, "K": -1},  # the housing's heat loss h A (ports.BALANCE_ROWS)
    "kg.m2": {"kg": 1, "m": 2},  # a tilting pad's moment of inertia (ports.PAD_ROWS)
    "rad/s2": {"rad": 1, "s": -2},  # the native FMU's tilting pads: der(pad_rate_k)
}
# display units (FMI 2.0 DisplayUnit: shown value = factor * value in the unit)
DISPLAY_UNITS = {"m": {"um": 1e6, "mm": 1e3}, "m/s": {"mm/s": 1e3}, "rad/s": {"rpm": 60.0 / (2.0 * math.pi)},
                 "Pa.s": {"mPa.s": 1e3}, "rad": {"deg": 180.0 / math.pi}, "Pa": {"kPa": 1e-3}, "K": {"degC": 1.0},
                 "m3/s": {"l/min": 6e4}, "m2/s": {"cSt": 1e6}}
DISPLAY_OFFSETS = {"degC": -273.15}  # shown value = factor * value + offset
# the display unit of each variable that has a natural one
DISPLAY = {"y": "um", "z": "um", "h_min": "um", "CR": "um", "lin_y0": "um", "lin_z0": "um", "D": "mm", "L": "mm",
           "vy": "mm/s", "vz": "mm/s", "omega": "rpm", "omega_lin": "rpm", "mu": "mPa.s",
           **{n: "deg" for n in ports.ROW_UNITS if ports.ROW_UNITS[n] == "rad"}, "supply_pressure": "kPa",
           **{r[0]: "deg" for r in ports.PAD_ROWS if r[3] == "rad"},
           **{n: "degC" for n in ports.ROW_UNITS if ports.ROW_UNITS[n] == "K"}, "Q_side": "l/min",
           "oil_nu_1": "cSt", "oil_nu_2": "cSt", "mu_eff": "mPa.s", "oil_vogel_a": "mPa.s",
           "peak_pressure": "kPa", "peak_pressure_angle": "deg", "circumferential_groove": "mm"}

PAPER_LABEL = "paper bearing (Table 2)"
FALLBACK_AUTHOR = "bearing_fmu maintainers"  # when the project's metadata names no author


# ----------------------------------------------------------------------------- units and ranges

def unit_definitions(used) -> ET.Element:
    """<UnitDefinitions> of the units ``used``, each with its display units."""
    units = ET.Element("UnitDefinitions")
    for u in sorted(used):
        unit = ET.SubElement(units, "Unit", name=u)
        ET.SubElement(unit, "BaseUnit", {k: str(v) for k, v in UNITS[u].items()})
        for name, factor in DISPLAY_UNITS.get(u, {}).items():
            attrs = {"name": name, "factor": repr(factor)}
            if name in DISPLAY_OFFSETS:
                attrs["offset"] = repr(DISPLAY_OFFSETS[name])
            ET.SubElement(unit, "DisplayUnit", attrs)
    return units


def bearing_envelope(name: str) -> tuple[float, float]:
    """(min, max) [SI] any bearing can have for D, L, CR, mu (params.py): L and CR scale with D,
    so their bounds are those of the smallest and the largest D (the ratio to D is checked at
    initialisation, params.BearingParams)."""
    d_lo, d_hi = D_RANGE_M
    return {"D": D_RANGE_M, "L": (L_OVER_D_RANGE[0] * d_lo, L_OVER_D_RANGE[1] * d_hi),
            "CR": (CR_OVER_R_RANGE[0] * d_lo / 2, CR_OVER_R_RANGE[1] * d_hi / 2), "mu": MU_RANGE_PA_S}[name]


def force_scale(params: BearingParams, omega: float) -> float:
    """mu R L (R / CR)^2 |omega| [N]: the film's force scale (the short-bearing and force-map scale)."""
    return params.mu * params.R * params.L * (params.R / params.CR) ** 2 * abs(omega)


def reference_speed(omega_start: float) -> float:
    """The speed the nominals are taken at [rad/s]: the start value of omega, or the paper rotor's
    22 Hz (the linear model's default) when it starts at rest."""
    return abs(omega_start) if omega_start else registry.DEFAULT_OMEGA_LIN


def _options() -> dict:
    return {o.name: o for o in registry.all_options()}


def real_attributes(name: str, unit: str | None, params: BearingParams, omega_ref: float) -> dict[str, str]:
    """unit, displayUnit, min, max, nominal of the Real variable ``name`` (strings, XML-ready)."""
    out = {}
    if unit:
        out["unit"] = unit
        if name in DISPLAY:
            out["displayUnit"] = DISPLAY[name]
    lo = hi = nominal = None
    force = force_scale(params, omega_ref)
    if name in ("D", "L", "CR", "mu"):
        (lo, hi), nominal = bearing_envelope(name), getattr(params, name)
    elif name in ("y", "z", "h_min"):
        nominal = params.CR
    elif name in ("vy", "vz"):
        nominal = params.CR * omega_ref
    elif name == "omega":
        nominal = omega_ref
    elif name == "eccentricity":
        lo = 0.0
    elif name in ("Fy", "Fz"):
        nominal = force
    elif name in ("Kyy", "Kyz", "Kzy", "Kzz"):
        nominal = force / params.CR
    elif name in ("Cyy", "Cyz", "Czy", "Czz"):
        nominal = force / (params.CR * omega_ref)
    elif name in _options():
        lo, hi = _option_bounds(_options()[name])
    elif name in ports.BOUNDS:
        lo, hi = ports.BOUNDS[name]
    elif name in ("T_eff", "mu_eff", "Q_side", "peak_pressure"):
        lo = 0.0
    for key, value in (("min", lo), ("max", hi), ("nominal", nominal)):
        if value is not None:
            out[key] = repr(float(value))
    return out


def _option_bounds(o: registry.Option) -> tuple:
    """(min, max) of a registry option; its special values (n_theta = 0: the solver's default)
    widen them. An exclusive minimum is written as the minimum (FMI's min is inclusive)."""
    lo, hi = o.minimum, o.maximum
    specials = [v for v in o.special if isinstance(v, (int, float))]
    if lo is not None and specials:
        lo = min(lo, *specials)
    if hi is not None and specials:
        hi = max(hi, *specials)
    return lo, hi


def integer_attributes(name: str) -> dict[str, str]:
    """min, max of an Integer parameter (a registry option)."""
    o = _options().get(name)
    if o is None and name not in ports.BOUNDS:
        return {}
    lo, hi = _option_bounds(o) if o is not None else ports.BOUNDS[name]
    return {k: str(int(v)) for k, v in (("min", lo), ("max", hi)) if v is not None}


# ----------------------------------------------------------------------------- enumerations

def enum_type_name(string_name: str) -> str:
    """The TypeDefinition of the enumeration of String parameter ``string_name``: internal ->
    BearingFMU.Internal, domain_action -> BearingFMU.DomainAction."""
    return "BearingFMU." + "".join(part.capitalize() for part in string_name.split("_"))


def item_description(string_name: str, item: str) -> str:
    """One line for an enumeration item: an internal's registry summary, else nothing."""
    if string_name == "internal" and item in registry.REGISTRY:
        return registry.REGISTRY[item].summary
    return ""


def type_definitions(enums) -> ET.Element:
    """<TypeDefinitions> for ``enums``: (String parameter name, [(value, item name), ...]) pairs."""
    types = ET.Element("TypeDefinitions")
    for string_name, items in enums:
        simple = ET.SubElement(types, "SimpleType", name=enum_type_name(string_name),
                               description=f"the choices of the parameter {string_name}")
        enum = ET.SubElement(simple, "Enumeration")
        for value, item in items:
            attrs = {"name": item, "value": str(value)}
            if item_description(string_name, item):
                attrs["description"] = item_description(string_name, item)
            ET.SubElement(enum, "Item", attrs)
    return types


# ----------------------------------------------------------------------------- who made it

def _pyproject() -> dict:
    path = Path(__file__).resolve().parents[2] / "pyproject.toml"
    try:
        import tomllib

        return tomllib.loads(path.read_text(encoding="utf-8")).get("project", {})
    except (OSError, ValueError):
        return {}


def project_meta() -> dict[str, str]:
    """{"author": ..., "license": ...} of the project: pyproject.toml's [project] authors and
    license (a source checkout), else the installed distribution's metadata; the author falls
    back to FALLBACK_AUTHOR, the license to "" (then the model description has none)."""
    project = _pyproject()
    authors = [a.get("name") or a.get("email", "") for a in project.get("authors", []) if isinstance(a, dict)]
    lic = project.get("license", "")
    lic = lic.get("text", lic.get("file", "")) if isinstance(lic, dict) else str(lic)
    if not project:
        try:
            from importlib.metadata import metadata

            md = metadata("bearing-fmu")
            authors = [md.get("Author") or md.get("Author-email") or ""]
            lic = md.get("License-Expression") or md.get("License") or ""
        except Exception:  # noqa: BLE001 - not installed: the fallbacks
            pass
    author = ", ".join(a for a in authors if a) or FALLBACK_AUTHOR
    return {"author": author, "license": str(lic or "")}


def set_author_and_license(root: ET.Element) -> None:
    meta = project_meta()
    root.set("author", meta["author"])
    if meta["license"]:
        root.set("license", meta["license"])
    elif "license" in root.attrib:
        del root.attrib["license"]


# ----------------------------------------------------------------------------- what it was built from

def sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def bearing_label(params: BearingParams, source: str = "") -> str:
    """The bearing in a few words: its file's name, else 'paper bearing', else its geometry."""
    if source:
        return Path(source).stem
    if params == PAPER_BEARING:
        return "paper bearing"
    return f"D {params.D * 1e3:.4g} mm L {params.L * 1e3:.4g} mm CR {params.CR * 1e6:.4g} um"


def bearing_record(params: BearingParams, source="", source_is_file: bool = True) -> dict:
    """The bearing's geometry [SI] and where it came from: a bearing file (its name and SHA-256),
    the data file it was fitted or tabulated for, or the paper bearing."""
    rec = {**params.as_dict(), "L_over_D": params.L / params.D, "CR_over_R": params.CR / params.R}
    if source and source_is_file and Path(source).is_file():
        rec["source"] = Path(source).name
        rec["sha256"] = sha256(source)
    else:
        rec["source"] = str(source) if source else (PAPER_LABEL if params == PAPER_BEARING else "given to the build")
    return rec


def data_file_record(path) -> dict:
    """A data file bundled or compiled in: name, size, SHA-256, its JSON "format" and what it
    holds (a surrogate's recipe, speed, order, provenance; a force map's table and truth)."""
    path = Path(path)
    rec = {"name": path.name, "bytes": path.stat().st_size, "sha256": sha256(path),
           "format": registry.file_format(path)}
    option = registry.option_for_file(path)
    if option.name == "surrogate":
        from ..surrogates.surrogate import load_surrogate

        s = load_surrogate(path)
        rec.update(holds="Taylor surrogate", recipe=s.recipe, order=s.order, omega=s.omega,
                   speed_hz=float(f"{s.omega / (2 * math.pi):.12g}"), expansion_point=[s.y0, s.z0], wall_power=s.wall_power,
                   shape_order=s.shape_order, bearing=s.params.as_dict(), provenance=s.provenance)
    elif option.name == "map":
        from ..internals.map.mapfile import load_any_map

        m = load_any_map(path)
        rec.update(holds="force map", table=" x ".join(str(n) for n in m.H.shape[:-1]), eps_max=m.eps_max, L_over_D=m.L_over_D,
                   reynolds=f"{m.n_theta} x {m.n_x} {m.cavitation}", provenance=m.provenance,
                   flow_tables=getattr(m, "Q", None) is not None)  # the film's flows: thermal ports (Python FMU)
    return rec


def model_name(kind: str, internal: str, files, bearing: str) -> str:
    """A model name per build: 'BearingFMU <what computes> <data files> (<bearing>)', e.g.
    'BearingFMU taylor paper_22hz_16.7N native (paper bearing)' or
    'BearingFMU python paper_22hz_16.7N paper_bearing (bearing_paper)'."""
    stems = [Path(f).stem for f in files]
    words = [internal, *stems, "native"] if kind == "native" else ["python", *stems]
    return f"BearingFMU {' '.join(words)} ({bearing})"


def build_record(kind: str, internals, default_internal: str, params: BearingParams, bearing_source="",
                 files=(), source_is_file: bool = True, extra: dict | None = None) -> dict:
    """What the FMU was built from (resources/build_info.json, the documentation): the builder,
    the internals it computes, the bearing, the data files with their hashes."""
    rec = {"generator": f"bearing_fmu {__version__} {kind} build", "kind": kind, "internals": list(internals),
           "default_internal": default_internal,
           "bearing": bearing_record(params, bearing_source, source_is_file),
           "data_files": [data_file_record(f) for f in files]}
    rec["model_name"] = model_name(kind, default_internal, files, bearing_label(
        params, rec["bearing"].get("source", "") if "sha256" in rec["bearing"] else ""))
    if extra:
        rec.update(extra)
    return rec


def description_text(summary: str, record: dict) -> str:
    """The model description's description: what it computes, the bearing's geometry and the
    files it came from (SHA-256 shortened to 12 hex digits; in full in resources/build_info.json)."""
    b = record["bearing"]
    geometry = (f"D {b['D'] * 1e3:.6g} mm, L {b['L'] * 1e3:.6g} mm, CR {b['CR'] * 1e6:.6g} um, "
                f"mu {b['mu']:.6g} Pa.s")
    origin = b["source"] + (f" sha256 {b['sha256'][:12]}" if "sha256" in b else "")
    text = f"{summary}; bearing {geometry} ({origin})"
    if record["data_files"]:
        text += "; data " + ", ".join(f"{f['name']} sha256 {f['sha256'][:12]}" for f in record["data_files"])
    return text


# ----------------------------------------------------------------------------- XML helpers

_ORDER = ("ModelExchange", "CoSimulation", "UnitDefinitions", "TypeDefinitions", "LogCategories",
          "DefaultExperiment", "VendorAnnotations", "ModelVariables", "ModelStructure")


def place(root: ET.Element, element: ET.Element) -> None:
    """Insert ``element`` among root's children in the order FMI 2.0's schema wants, replacing
    one of the same tag."""
    old = root.find(element.tag)
    if old is not None:
        root.remove(old)
    rank = _ORDER.index(element.tag)
    children = list(root)
    pos = next((i for i, c in enumerate(children) if c.tag in _ORDER and _ORDER.index(c.tag) > rank), len(children))
    root.insert(pos, element)


def strip_whitespace(root: ET.Element) -> None:
    """Drop whitespace-only text, so that re-indenting gives one clean layout."""
    for el in root.iter():
        if el.text is not None and not el.text.strip():
            el.text = None
        if el.tail is not None and not el.tail.strip():
            el.tail = None


# ----------------------------------------------------------------------------- memoryless

# The annotation by which a bearing FMU tells a master that it has no state worth restoring:
#   <VendorAnnotations><Tool name="bearing_fmu"><Memoryless internals="map linear" unless="thermal"/>
# With one of ``internals`` chosen (the parameter ``internal``) and none of the Boolean parameters
# ``unless`` true, a doStep's outputs depend on the inputs and parameters set alone (not on the
# time, an earlier step or an earlier state) and a doStep may start at any currentCommunicationPoint.
# A master may then iterate a step with setReal / doStep / getReal and no fmi2GetFMUstate /
# fmi2SetFMUstate around it: the outputs are those of the conformant iteration. An FMU without
# the annotation (a foreign one, the Python FMU) keeps the save and restore.
#
# Beside it, the internals with states of their own over a step (``Capabilities.step_states``: a
# tilting pad's tilts and rates), an attribute of the same element (FMI 2.0's Tool holds one element):
#   <Memoryless internals="map linear" unless="thermal" stepStates="tilting_pad"/>. With one of them chosen,
# the outputs read in Initialization Mode are the quasi-static answer at the inputs set (the pads in
# moment equilibrium), exitInitializationMode starts the states there, and each doStep advances them
# from the committed ones: a master finds a static equilibrium through the FMU in Initialization
# Mode (a short doStep would move the states, not settle them; rotor_host.coupling.cosim does so).
MEMORYLESS_TOOL = "bearing_fmu"


def memoryless_annotation(internals, unless=("thermal",), stepped=()) -> ET.Element:
    """The VendorAnnotations element declaring ``internals`` memoryless and ``stepped`` with states
    of their own over a step (see above)."""
    va = ET.Element("VendorAnnotations")
    tool = ET.SubElement(va, "Tool", name=MEMORYLESS_TOOL)
    el = ET.SubElement(tool, "Memoryless", internals=" ".join(internals), unless=" ".join(unless))
    if stepped:
        el.set("stepStates", " ".join(stepped))
    return va


def step_states_declaration(model_description_xml: bytes | str) -> set:
    """The internals a model description declares with states of their own over a step (empty: none)."""
    root = ET.fromstring(model_description_xml)
    for tool in root.iterfind("VendorAnnotations/Tool"):
        if tool.get("name") == MEMORYLESS_TOOL:
            el = tool.find("Memoryless")
            if el is not None:
                return set(el.get("stepStates", "").split())
    return set()


def memoryless_declaration(model_description_xml: bytes | str):
    """(internals, unless) declared memoryless by a model description (``memoryless_annotation``),
    or None when it declares nothing."""
    root = ET.fromstring(model_description_xml)
    for tool in root.iterfind("VendorAnnotations/Tool"):
        if tool.get("name") == MEMORYLESS_TOOL:
            el = tool.find("Memoryless")
            if el is not None:
                return set(el.get("internals", "").split()), set(el.get("unless", "").split())
    return None
