"""documentation/index.html of a bearing FMU, Python or native, FMI 2.0 or 3.0 (both recommend
``documentation/index.html``): what it computes, where each internal is valid, the bearing,
where the data came from, the variables and enumerations.

One generator for both builds, made from what the FMU declares: the variables, units, ranges
and enumerations are read back from the modelDescription.xml the build wrote (so the page and
the model description cannot differ), the rest from the build record (``fmu_meta.build_record``,
also in ``resources/build_info.json``). Build tooling: not bundled into the Python FMU.
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from xml.etree import ElementTree as ET

from ..internals import registry

_E = html.escape

_ACTIONS = {"python": "warns once (domain_action = warn), takes the Reynolds value for that call (fallback) or "
                      "refuses the step (discard)",
            "native": "warns once (domain_action = warn) or refuses the step (discard); fallback needs the Reynolds "
                      "solver, which only the Python FMU has"}
_LINEAR_MADE = {"python": " linear_from = load linearises the Reynolds solver at its equilibrium under (load_y, "
                          "load_z) at omega_lin at initialisation; map does the same on the force map; coefficients "
                          "takes the lin_* parameters as given.",
                "native": " Its coefficients are the lin_* parameters (start values: the model the build made)."}

_INTERFACE = {
    "python": "Co-Simulation (pythonfmu): the outputs of a doStep are those of the inputs set before it (the state at "
              "the end of the step); fmi2GetFMUstate / fmi2SetFMUstate save and restore the inputs and outputs, so a "
              "master may iterate within a step. The FMU embeds a Python interpreter: it runs where Python 3.11 with "
              "numpy, scipy and numba is installed (docs/fmu.md, What a non-Python simulator needs); the native FMU "
              "(bearing-fmu build --native) needs none.",
    "native": "Co-Simulation: the outputs of a doStep are those of the inputs set before it (the state at the end of "
              "the step). Model Exchange: the outputs are a direct feedthrough of the inputs (no states); "
              "fmi2GetDirectionalDerivative gives the force Jacobian. fmi2GetFMUstate / fmi2SetFMUstate save and "
              "restore the inputs and outputs, so a master may iterate within a step. Compiled C: no Python at run "
              "time; the C sources are in sources/ (rebuild for another platform with fmpy compile).",
    "native3": "FMI 3.0. Co-Simulation (no Event Mode): the outputs of a doStep are those of the inputs set before it "
               "(the state at the end of the step). Model Exchange: the outputs are a direct feedthrough of the "
               "inputs (no states); out_of_domain, a discrete output, changes at events only (a step event where the "
               "state crosses the fitted domain's edge). fmi3GetDirectionalDerivative and fmi3GetAdjointDerivative "
               "give the derivatives of every Float64 output along the inputs. fmi3GetFMUState / fmi3SetFMUState "
               "save and restore the inputs and outputs (serialisable), so a master may iterate within a step. "
               "Compiled C: no Python at run time; the C sources and buildDescription.xml are in sources/ (rebuild "
               "for another platform with fmpy compile).",
}
_STATUSES = {
    "2.0": "fmi2Discard with a logged reason for a state the internal refuses (the wall, a non-finite input, far "
           "outside a surrogate's fitted domain); the outputs keep their last values and a restored state or a good "
           "step goes on. fmi2Error for a refused call (a bad parameter, an unknown value reference, a bad step size, "
           "a call before initialisation); the instance stays usable. With logging off, the first warning, discard "
           "and error of each instance are printed to stderr.",
    "3.0": "fmi3Discard with a logged reason for a state the internal refuses (the wall, a non-finite input, far "
           "outside a surrogate's fitted domain); the outputs keep their last values, a discarded doStep leaves the "
           "instance as before it (terminateSimulation false) and a restored state or a good step goes on. fmi3Error "
           "for a refused call (a bad parameter, an unknown value reference, a bad step size, a call out of the FMI "
           "3.0 calling sequence), given to the logger even with logging off; the instance stays usable. With "
           "logging off, the first warning and discard of each instance are printed to stderr.",
}


_CHOICE = {"python": "The parameter internal (or internal_enum) chooses what computes the force.",
           "native": "This native FMU computes one internal, compiled in."}


def _variables(root: ET.Element) -> str:
    rows = []
    for sv in root.find("ModelVariables"):
        # FMI 2.0: <ScalarVariable><Real .../></ScalarVariable>; FMI 3.0: <Float64 .../>, a String's <Start/>
        typed = sv[0] if sv.tag == "ScalarVariable" else sv
        start = typed.get("start", "") if typed.find("Start") is None else typed.find("Start").get("value", "")
        kind = typed.tag + (f" ({typed.get('declaredType')})" if typed.get("declaredType") else "")
        unit = typed.get("unit", "") + (f" [{typed.get('displayUnit')}]" if typed.get("displayUnit") else "")
        cells = [sv.get("name"), sv.get("causality"), kind, unit, start, typed.get("min", ""),
                 typed.get("max", ""), typed.get("nominal", ""), sv.get("description", "")]
        rows.append("<tr>" + "".join(f"<td>{_E(str(c))}</td>" for c in cells) + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in ("name", "causality", "type", "unit [display unit]", "start", "min",
                                              "max", "nominal", "description"))
    return f'<table border="1" cellspacing="0" cellpadding="3">\n<tr>{head}</tr>\n' + "\n".join(rows) + "\n</table>"


def _enumerations(root: ET.Element) -> str:
    types = root.find("TypeDefinitions")
    if types is None:
        return "<p>none</p>"
    out = []
    for simple in types:
        items = ", ".join(f"{_E(i.get('value'))} = {_E(i.get('name'))}"
                          + (f" ({_E(i.get('description'))})" if i.get("description") else "")
                          for i in simple.iter("Item"))
        out.append(f"<li><b>{_E(simple.get('name'))}</b>: {items}</li>")
    return ("<p>Each choice parameter is declared twice: as a String (its name) and as an enumeration "
            "&lt;name&gt;_enum (its number; a drop-down in tools that show one). Set either: an enumeration set "
            "away from its start value wins over the String, and if both are set away from their start values "
            "they must agree (else the initialisation fails, naming both).</p>\n<ul>\n" + "\n".join(out)
            + "\n</ul>")


def _bearing(rec: dict) -> str:
    origin = _E(rec["source"]) + (f" (SHA-256 <code>{rec['sha256']}</code>)" if "sha256" in rec else "")
    return (f"<p>D = {rec['D'] * 1e3:.6g} mm, L = {rec['L'] * 1e3:.6g} mm, CR = {rec['CR'] * 1e6:.6g} um, "
            f"mu = {rec['mu']:.6g} Pa s (L/D = {rec['L_over_D']:.4g}, CR/R = {rec['CR_over_R']:.4g}): the start values "
            f"of D, L, CR, mu. From: {origin}.</p>")


def _data(files: list) -> str:
    if not files:
        return "<p>No data file: the internals compute from the bearing's parameters alone.</p>"
    out = []
    for f in files:
        facts = {k: v for k, v in f.items() if k not in ("name", "sha256", "provenance")}
        out.append(f"<h3>{_E(f['name'])}</h3>\n<p>SHA-256 <code>{f['sha256']}</code></p>\n"
                   f"<pre>{_E(json.dumps(facts, indent=1, default=str))}</pre>\n"
                   f"<p>Provenance (as the file records it):</p>\n"
                   f"<pre>{_E(json.dumps(f.get('provenance', {}), indent=1, default=str))}</pre>")
    return "\n".join(out)


def _validity(name: str, kind: str) -> str:
    """Where internal ``name``'s force holds (its registered capabilities), for FMU ``kind``."""
    spec = registry.get(name)
    return (spec.can.validity or spec.summary).format(actions=_ACTIONS[kind], made=_LINEAR_MADE[kind])


def documentation_html(model_description: bytes, record: dict) -> str:
    """The page for an FMU whose modelDescription.xml is ``model_description`` and whose build
    record (``fmu_meta.build_record``) is ``record``."""
    root = ET.fromstring(model_description)
    kind = record["kind"]
    version = root.get("fmiVersion", "2.0")
    interface = _INTERFACE[kind + ("3" if version == "3.0" else "")]
    token = (("instantiation token", root.get("instantiationToken", "")) if version == "3.0"
             else ("GUID", root.get("guid", "")))
    validity = "\n".join(
        f"<li><b>{_E(name)}</b>{' (default)' if name == record['default_internal'] else ''}: "
        + _E(_validity(name, kind)) + "</li>"
        for name in record["internals"] if name in registry.REGISTRY)
    extra = {k: v for k, v in record.items() if k not in ("bearing", "data_files", "internals", "kind",
                                                          "default_internal", "model_name", "generator")}
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{_E(root.get('modelName', ''))}</title></head>
<body>
<h1>{_E(root.get('modelName', ''))}</h1>
<p>{_E(root.get('description', ''))}.</p>
<p>Author: {_E(root.get('author', ''))}. License: {_E(root.get('license', 'none declared'))}. Version
{_E(root.get('version', ''))}, FMI {_E(version)}, {token[0]} <code>{_E(token[1])}</code>.</p>
<h2>What it computes</h2>
<p>The film force of a plain cylindrical hydrodynamic journal bearing on its journal. The inputs are the
journal centre's displacement (y, z) from the bearing centre [m], its velocity (vy, vz) [m/s] and the
shaft speed omega [rad/s] (right-handed about the shaft axis x, z up, gravity along -z); the outputs are
the film force on the journal (Fy, Fz) [N], the eccentricity ratio, the minimum film thickness and the
film stiffness and damping K<sub>ij</sub> = -dF<sub>i</sub>/dq<sub>j</sub>, C<sub>ij</sub> =
-dF<sub>i</sub>/dv<sub>j</sub> (Lund's sign). {_E(_CHOICE[kind])}</p>
<p>{_E(interface)}</p>
<h2>Internals and where each is valid</h2>
<ul>
{validity}
</ul>
<h2>Bearing</h2>
{_bearing(record['bearing'])}
<h2>Where the data came from</h2>
{_data(record['data_files'])}
{f"<pre>{_E(json.dumps(extra, indent=1, default=str))}</pre>" if extra else ""}
<h2>Variables</h2>
<p>Units are SI; the display unit in brackets is what a tool may show (um, mm, mm/s, rpm, mPa.s). The
bounds of D, L, CR and mu are those of any bearing (their ratios to D are checked at initialisation);
the nominals are the bearing's values and the film's force scale mu R L (R/CR)<sup>2</sup> omega at the
reference speed.</p>
{_variables(root)}
<h2>Enumerations</h2>
{_enumerations(root)}
<h2>Statuses</h2>
<p>{_E(_STATUSES[version])}</p>
<p>Generated by {_E(record['generator'])}; what it was built from is also in resources/build_info.json.</p>
</body></html>
"""


def write_documentation(folder: Path, model_description: bytes, record: dict) -> Path:
    """Write ``folder``/index.html (see ``documentation_html``)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "index.html"
    path.write_text(documentation_html(model_description, record), encoding="utf-8")
    return path
