"""C source of a native bearing FMU: the internal's data, its options, its model description's variables.

``native_model(internal, params, ...)`` gathers everything a native FMU of one internal is:
``NativeModel`` with its variables (the Python FMU's where they apply, ``fmu_variables.VARIABLES``),
its options (registry ``Option``s the native FMU keeps) and two generated headers:

* ``model_config.h``: the internal's name, the GUID, start values, one row per option (name,
  start, range or choices), the value references the C code uses (``VR_OPT_<NAME>``,
  ``S_OPT_<NAME>``) and the FMI 2.0 calling sequence (``fmi_order.c_defines``);
* ``model_data.h``: the internal's data, its generator's (``generators/``, one module per internal,
  named by its catalogue entry, ``catalogue.NATIVE``, which says what it compiles too).

Every double is written as the shortest decimal literal that parses back to it (``repr``): exact.
"""

from __future__ import annotations

import hashlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...internals import registry
from ..order import c_defines
from .catalogue import NATIVE, native_spec, refused_choices
from ..variables import ENUMERATIONS, VARIABLES  # the one table of the FMU interface
from .portgen import parts_of, port_config, port_variables
from ...physics.params import BearingParams

ID_TOKEN, GUID_TOKEN = "BN_MODEL_IDENTIFIER", "{BN-GUID}"  # in model_config.h until assign_identity
# the model layer (c/bearing_values.h), the same C files under the FMI 2.0 and the FMI 3.0 layer
MODEL_HEADERS = ("bearing_native.h", "bearing_values.h", "bearing_calls.h", "oil_thermal.h")
MODEL_SOURCES = ("bearing_calls.c", "bearing_state.c", "bearing_log.c", "bearing_values.c", "bearing_model.c",
                 "bearing_derivatives.c", "bearing_thermal.c", "oil_thermal.c")
# an FMU of several internals: the dispatch among them, Taylor's fallback to Reynolds
SEVERAL_SOURCES = ("bn_parts.c", "bn_fallback.c")
REAL_BASE, BOOL_BASE, STRING_BASE, ENUM_BASE = 0, 1000, 2000, 3000  # value references by type (bearing_native.h)
CORE_REALS = ("y", "z", "vy", "vz", "omega", "Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz",
              "Cyy", "Cyz", "Czy", "Czz", "D", "L", "CR", "mu")


def c_double(x: float) -> str:
    """A decimal C literal that parses to exactly the double x: Python's repr, the shortest decimal
    that rounds back to x (at most 17 significant digits). Decimal, not hexadecimal: older MSVC
    compilers refuse C99's hex floats."""
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"codegen: non-finite value {x!r} in the model data")
    return repr(x)


def c_string(s: str) -> str:
    """A C string literal (printable ASCII kept, the rest escaped)."""
    out = []
    for ch in str(s):
        if ch in '"\\':
            out.append("\\" + ch)
        elif 32 <= ord(ch) < 127 and ch != "%":
            out.append(ch)
        else:
            out.append("?" if ord(ch) > 255 else f"\\{ord(ch):03o}")
    return '"' + "".join(out) + '"'


def c_array(name: str, values, per_line: int = 4) -> str:
    vals = [c_double(v) for v in np.asarray(values, float).ravel()]
    lines = [", ".join(vals[i:i + per_line]) for i in range(0, len(vals), per_line)]
    body = ",\n    ".join(lines) if lines else "0"
    return f"static const double {name}[{max(len(vals), 1)}] = {{\n    {body}}};\n"


# ----------------------------------------------------------------------------- the model

@dataclass
class Variable:
    """One variable of the model description."""

    name: str
    vr: int
    type: str  # Real | Boolean | String | Enumeration (an Integer, FMI 2.0)
    causality: str  # input | output | parameter
    start: object
    unit: str | None
    description: str
    declared_type: str | None = None  # an Enumeration's TypeDefinition
    derivative_of: str | None = None  # Model Exchange: the state this variable is the derivative of
    nominal: float | None = None  # a continuous state's scale (the integrator's absolute tolerance), if not 1

    @property
    def state(self) -> str | None:
        """The continuous state this variable is the derivative of (``derivative_of``, or X of der(X)), or None."""
        return self.derivative_of or (self.name[4:-1] if self.name.startswith("der(") else None)

    @property
    def variability(self) -> str:
        if self.causality == "parameter":
            return "fixed"
        return "continuous" if self.type == "Real" else "discrete"


@dataclass
class NativeModel:
    """A native FMU of one internal: variables, options, generated C headers, provenance."""

    internal: str
    params: BearingParams
    variables: list[Variable]
    config_h: str
    data_h: str
    source: Path | None  # the data file compiled in (surrogate, map), if any
    description: str
    info: dict = field(default_factory=dict)  # what the documentation records (order, table size, ...)
    parts: tuple = ()  # an FMU of several internals: all of them (internal: the first, the start value)
    identifier: str = ""  # assign_identity: bearing_<internal>_<content hash>
    flows_why: str | dict = ""  # why its data lack the film's flows ('' if not; several: per internal; portgen)

    @property
    def all_parts(self) -> tuple[str, ...]:
        """The internals the FMU holds (one, or several)."""
        return self.parts or (self.internal,)

    @property
    def model_identifier(self) -> str:
        if not self.identifier:
            raise RuntimeError("codegen.assign_identity has not run: the model identifier hashes the sources")
        return self.identifier


def native_model(internal: str, params: BearingParams, *, surrogate=None, map=None, options=None,
                 omega: float | None = None) -> NativeModel:
    """The native model of ``internal`` for bearing ``params``.

    Its catalogue entry's generator (``catalogue.NATIVE``, ``generators/``) makes it, e.g.
    taylor : ``surrogate`` (path) compiled in; params default to the surrogate's
    map    : ``map`` (path) compiled in; its L/D must be the bearing's
    linear : the coefficients' start values from the Python ``Linear`` internal built with
             ``options`` (registry options of "linear", e.g. linear_from, load_z, or a map)
    omega  : the start value of the input omega [rad/s] (the option ``speed_start`` of its entry:
             map's, reynolds's; linear's omega_lin); refused by one with its data file's speed
    ValueError naming what is wrong otherwise (an internal without a native C model: why)."""
    spec = native_spec(internal, "native FMU")
    options = dict(options or {})
    if omega is not None:
        if not spec.speed_start:
            raise ValueError(spec.speed_why)
        if not (math.isfinite(omega) and omega > 0):
            raise ValueError(f"the start speed omega = {omega!r} rad/s must be finite and > 0")
        options[spec.speed_start] = float(omega)
    return spec.build(params, surrogate, map, options)


def native_variables(internal, params: BearingParams, starts: dict, inputs: tuple, flows_why="") -> list[Variable]:
    """The Python FMU's variables that apply, in value-reference order (bearing_native.h), for
    ``internal`` (a name, or a tuple of the names an FMU of several holds; ``flows_why``: why its
    data file lacks the film's flows, portgen.film_flow)."""
    parts = parts_of(internal)
    table = {v[0]: v for v in VARIABLES}
    out = []
    bearing = dict(zip(("D", "L", "CR", "mu"), (params.D, params.L, params.CR, params.mu)))
    for vr, name in enumerate(CORE_REALS):
        _n, typ, causality, unit, start, desc = table[name]
        start = dict(zip(("y", "z", "vy", "vz", "omega"), inputs)).get(name, bearing.get(name, start))
        if name in ("y", "z", "vy", "vz", "omega", "D", "L", "CR", "mu"):
            out.append(Variable(name, REAL_BASE + vr, typ, causality, float(start), unit, desc))
        else:
            out.append(Variable(name, REAL_BASE + vr, typ, causality, 0.0, unit, desc))
    opts = [registry_option(n) for n in option_names(internal)]
    reals = [o for o in opts if o.type is float]
    strings = [o for o in opts if o.type is str]
    for k, o in enumerate(reals):
        out.append(Variable(o.name, REAL_BASE + len(CORE_REALS) + k, "Real", "parameter", float(starts[o.name]),
                            o.unit, f"{o.help} ({o.allowed()})"))
    for name, k in (("out_of_domain", 0), ("compute_tangent", 1)):
        _n, typ, causality, unit, start, desc = table[name]
        out.append(Variable(name, BOOL_BASE + k, typ, causality, bool(start), None, desc))
    # the thermal ports and the bore (portgen.py): after the Real options, and after the
    # enumerations and the Integer options
    n_ints = len(native_enumerations(internal)) + sum(o.type is int for o in opts)
    out += [Variable(*v) for v in port_variables(internal, params, REAL_BASE + len(CORE_REALS) + len(reals),
                                                 ENUM_BASE + n_ints, BOOL_BASE, flows_why)]
    what = f"this native FMU computes {parts[0]} only" if len(parts) == 1 else " | ".join(parts)
    out.append(Variable("internal", STRING_BASE, "String", "parameter", parts[0], None,
                        f"which internal computes the force: {what}"))
    for k, o in enumerate(strings):
        desc = o.help
        if o.name == "domain_action":
            held = o.name not in refused_choices(parts)
            desc = ("taylor, state outside the fitted domain: warn (surrogate value, warned once per excursion) | "
                    + ("fallback (the Reynolds internal of this FMU, blended over the domain's edge) | " if
                       held else "") + "discard (refuse the step)"
                    + ("" if held else "; fallback needs the Reynolds internal in the FMU"))
        elif o.file:
            desc = f"{o.name} file compiled into this FMU ('' or its name)"
        out.append(Variable(o.name, STRING_BASE + 1 + k, "String", "parameter", str(starts[o.name]), None, desc))
    from ..meta import enum_type_name  # noqa: PLC0415

    for k, (name, string, items) in enumerate(native_enumerations(internal)):
        start = parts[0] if string == "internal" else str(starts[string])
        value = next(v for v, item in items if item == start)
        words = ", ".join(f"{v} = {item}" for v, item in items)
        out.append(Variable(name, ENUM_BASE + k, "Enumeration", "parameter", value, None,
                            f"{string} as an enumeration ({words}): the same choice as the String parameter {string}; "
                            "set either (set both, they must agree)", enum_type_name(string)))
    n_enums = len(native_enumerations(internal))
    for k, o in enumerate(o for o in opts if o.type is int):  # Integers after the enumerations
        out.append(Variable(o.name, ENUM_BASE + n_enums + k, "Integer", "parameter", int(starts[o.name]), o.unit,
                            f"{o.help} ({o.allowed()})"))
    return out


def native_enumerations(internal) -> list[tuple[str, str, list[tuple[int, str]]]]:
    """(enumeration parameter, its String parameter, [(value, item), ...]) of the native FMU of
    ``internal`` (a name, or a tuple of them): the Python FMU's enumerations
    (``fmu_variables.ENUMERATIONS``, the same numbers) of the String parameters it has, with the
    items it accepts (internal: its own; an option's: not a choice it refuses, ``catalogue.refused_choices``:
    domain_action's fallback only with reynolds in the FMU)."""
    parts = parts_of(internal)
    strings = ["internal"] + [n for n in option_names(internal) if registry_option(n).choices]
    refused = refused_choices(parts)
    out = []
    for name, (string, items) in ENUMERATIONS.items():
        if string in strings:
            allowed = [c for c in items if c in parts] if string == "internal" else [
                c for c in items if refused.get(string, (None,))[0] != c]
            out.append((name, string, [(items.index(c) + 1, c) for c in allowed]))
    return out


def registry_option(name: str) -> registry.Option:
    return next(o for o in registry.all_options() if o.name == name)


def internal_sources(model: "NativeModel") -> tuple[list[str], list[str]]:
    """(the internals' C files the compiler builds, the headers they include) of ``model``: each
    internal's (its catalogue entry's sources, its film report's when its data hold the flows), and
    for several the dispatch among them (SEVERAL_SOURCES)."""
    parts = model.all_parts
    why = model.flows_why if isinstance(model.flows_why, dict) else {model.internal: model.flows_why}
    compiled = [f for p in parts for f in (*NATIVE[p].sources, *(NATIVE[p].flow_sources if not why.get(p) else ()))]
    compiled += list(SEVERAL_SOURCES) if len(parts) > 1 else []
    return compiled, list(dict.fromkeys(f for p in parts for f in NATIVE[p].headers))


def option_names(internal) -> tuple[str, ...]:
    """The native options of ``internal`` (a name or a tuple of names), each once, in order."""
    return tuple(dict.fromkeys(n for p in parts_of(internal) for n in NATIVE[p].options))


def assign_identity(model: "NativeModel", sources: dict[str, str], describe) -> None:
    """The model identifier and the GUID of ``model``, from what it is made of, written into its
    model_config.h (which holds them as tokens until then):

    * identifier ``bearing_<internal>_<6 hex digits>``: a hash of the C sources (``sources``: file
      name -> text) and the generated headers, so two builds of different data never share the
      binary's name (two bearings in one simulator; FMI2_FUNCTION_PREFIX);
    * GUID: a hash of the same and of the model description (``describe()``: its XML bytes with
      the GUID still the token; its generation time left out), so anything that changes the FMU,
      a start value as much as a coefficient, changes the GUID; the same inputs give the same."""
    h = hashlib.sha256()
    for name in sorted(sources):
        h.update(name.encode() + b"\0" + sources[name].encode() + b"\0")
    h.update(model.config_h.encode() + b"\0" + model.data_h.encode() + b"\0")
    model.identifier = f"bearing_{'_'.join(model.parts or (model.internal,))}_{h.hexdigest()[:6]}"
    model.info["guid"] = GUID_TOKEN
    h.update(re.sub(rb'generationDateAndTime="[^"]*"', b"", describe()))
    g = h.hexdigest()
    model.info["guid"] = "{" + f"{g[:8]}-{g[8:12]}-{g[12:16]}-{g[16:20]}-{g[20:32]}" + "}"
    model.config_h = model.config_h.replace(ID_TOKEN, model.identifier).replace(GUID_TOKEN, model.info["guid"])


def model_config(internal, params: BearingParams, starts: dict, inputs, flows_why="") -> str:
    """model_config.h, the model identifier and GUID as tokens (``assign_identity``); ``internal``
    a name or a tuple of them (an FMU of several: bn_parts.c dispatches among them)."""
    parts = parts_of(internal)
    opts = [registry_option(n) for n in option_names(internal)]
    reals = [o for o in opts if o.type is float]
    strings = [o for o in opts if o.type is str]
    lines = [
        "/* Generated by bearing_fmu.fmu.native.codegen. Do not edit. */",
        "#ifndef MODEL_CONFIG_H", "#define MODEL_CONFIG_H",
        f"#define BN_INTERNAL {c_string(parts[0])}",
        f"#define BN_ID {ID_TOKEN}",  # names every symbol shared between the files (bearing_native.h)
        f"#define BN_GUID {c_string(GUID_TOKEN)}",
        # several internals: the largest (bearing_derivatives.c asks the one set, bn_force_depends)
        f"#define BN_BEARING_IN_FORCE {max(NATIVE[p].force_depends[0] for p in parts)}",
        f"#define BN_SPEED_IN_FORCE {max(NATIVE[p].force_depends[1] for p in parts)}",
        f"#define BN_PARTS {len(parts)}",
        f"#define BN_INTERNALS {c_string('|'.join(parts))}",
        # the memoryless ones (catalogue: outputs from the inputs alone), " map linear ": with one of them
        # set and thermal = false a doStep may start at any currentCommunicationPoint (bn_do_step)
        f"#define BN_MEMORYLESS {c_string(' ' + ' '.join(p for p in parts if NATIVE[p].memoryless) + ' ')}",
        "#define BN_PART_LIST(X) " + " ".join(f"X({p}, {NATIVE[p].force_depends[0]}, {NATIVE[p].force_depends[1]})"
                                              for p in parts),
        *(f"#define BN_HOLDS_{p.upper()} {int(p in parts)}" for p in NATIVE),
        f"#define BN_N_REAL_OPTIONS {len(reals)}",
        f"#define BN_N_STRING_OPTIONS {len(strings)}",
        f"#define BN_START_INPUTS {{{', '.join(c_double(v) for v in inputs)}}}",
        f"#define BN_START_BEARING {{{', '.join(c_double(v) for v in (params.D, params.L, params.CR, params.mu))}}}",
        *port_config(internal, params, c_double, c_string, flows_why),  # the thermal ports, the bore (portgen.py)
    ]
    rows = []
    for k, o in enumerate(reals):
        lines.append(f"#define VR_OPT_{o.name.upper()} {len(CORE_REALS) + k}")
        lo = "-INFINITY" if o.minimum is None else c_double(o.minimum)
        hi = "INFINITY" if o.maximum is None else c_double(o.maximum)
        rows.append(f"    {{{c_string(o.name)}, {c_double(starts[o.name])}, {lo}, {int(o.exclusive_minimum)}, {hi}, "
                    f"{c_string(o.allowed())}}}")
    lines.append("#define BN_REAL_OPTION_TABLE \\\n" + ", \\\n".join(rows) if rows else "#define BN_REAL_OPTION_TABLE")
    rows = []
    refused = refused_choices(parts)  # taylor's fallback without the Reynolds internal in the same FMU
    for k, o in enumerate(strings):
        lines.append(f"#define S_OPT_{o.name.upper()} {1 + k}")
        if o.file:
            rows.append(f"    {{{c_string(o.name)}, {c_string(starts[o.name])}, NULL, 1, NULL, NULL}}")
        else:
            refuse = refused.get(o.name)
            choices = [c for c in o.choices if not (refuse and c == refuse[0])]
            rows.append(f"    {{{c_string(o.name)}, {c_string(starts[o.name])}, {c_string('|'.join(choices))}, 0, "
                        + (f"{c_string(refuse[0])}, {c_string(refuse[1])}}}" if refuse else "NULL, NULL}"))
    lines.append("#define BN_STRING_OPTION_TABLE \\\n" + ", \\\n".join(rows) if rows else
                 "#define BN_STRING_OPTION_TABLE")
    # the enumerations: name, the String they mirror (index: 0 internal, 1 + k the k-th String
    # option), start value, every choice of the type ("a|b|c", value k + 1 for the k-th)
    rows = []
    string_names = ["internal"] + [o.name for o in strings]
    for name, string, items in native_enumerations(internal):
        start = parts[0] if string == "internal" else str(starts[string])
        value = next(v for v, item in items if item == start)
        rows.append(f"    {{{c_string(name)}, {string_names.index(string)}, {value}, "
                    f"{c_string('|'.join(ENUMERATIONS[name][1]))}}}")
    lines.append(f"#define BN_N_ENUMS {len(rows)}")
    lines.append("#define BN_ENUM_TABLE \\\n" + ", \\\n".join(rows))
    # the Integer options (after the enumerations): name, start, minimum, maximum, even, the
    # special value (0: the default) or -1, the allowed values in words
    ints = [o for o in opts if o.type is int]
    lines.append(f"#define BN_N_INT_OPTIONS {len(ints)}")
    rows = []
    for k, o in enumerate(ints):
        lines.append(f"#define I_OPT_{o.name.upper()} {k}")
        special = 0 if o.special else -1
        rows.append(f"    {{{c_string(o.name)}, {int(starts[o.name])}, {int(o.minimum)}, {int(o.maximum)}, "
                    f"{int(o.even)}, {special}, {c_string(o.allowed())}}}")
    lines.append("#define BN_INT_OPTION_TABLE \\\n" + ", \\\n".join(rows) if rows else "#define BN_INT_OPTION_TABLE")
    lines += c_defines()  # the FMI 2.0 calling sequence: the one table both FMUs check
    lines.append("#endif\n")
    return "\n".join(lines)
