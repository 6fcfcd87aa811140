"""C source of a native bearing FMU: the internal's data, its options, its model description's variables.

``native_model(internal, params, ...)`` gathers everything a native FMU of one internal is:
``NativeModel`` with its variables (the Python FMU's where they apply, ``fmu_variables.VARIABLES``),
its options (registry ``Option``s the native FMU keeps) and two generated headers:

* ``model_config.h``: the internal's name, the GUID, start values, one row per option (name,
  start, range or choices), the value references the C code uses (``VR_OPT_<NAME>``,
  ``S_OPT_<NAME>``) and the FMI 2.0 calling sequence (``fmi_order.c_defines``);
* ``model_data.h``: the internal's data. Taylor: the same arrays ``taylor.Taylor`` hands its
  numba kernels (meta, domain, only the kept terms), the polynomials as coefficient rows over
  their monomials (``taylor_polynomials``: the C kernel sums them as vectorised dot
  products), the stored training states, a version 2 file's film fit (``taylor_data``). Map: the
  spline's knots and coefficients, its flow table's too (``map_data``). Linear: nothing (its
  coefficients are parameters).

Every double is written as the shortest decimal literal that parses back to it (``repr``): exact.
"""

from __future__ import annotations

import hashlib
import math
import re
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...internals import registry
from ..order import c_defines
from ..variables import ENUMERATIONS, VARIABLES  # the one table of the FMU interface
from .portgen import parts_of, port_config, port_variables
from ...physics.params import BearingParams

ID_TOKEN, GUID_TOKEN = "BN_MODEL_IDENTIFIER", "{BN-GUID}"  # in model_config.h until assign_identity
INTERNALS = ("linear", "map", "taylor", "reynolds")  # what a native FMU can compute
# C files an internal's file includes (so that all of it stays static): staged beside it, not compiled alone
INCLUDED_SOURCES = {"reynolds": ("py_mod.h", "reynolds_solver.h", "film_friction.h"),
                    "map": ("py_mod.h", "film_friction.h", "map_spline.h"), "taylor": ("film_friction.h", "taylor_internal.h")}
# C files compiled beside an internal's, and those when its film report is (its data hold the film's flows)
PART_SOURCES = {"reynolds": ("reynolds_solver.c", "reynolds_kernels.c")}
FLOW_SOURCES = {"map": ("map_flows.c",), "taylor": ("taylor_film.c",), "reynolds": ("reynolds_film.c",)}
# the model layer (c/bearing_values.h), the same C files under the FMI 2.0 and the FMI 3.0 layer
MODEL_HEADERS = ("bearing_native.h", "bearing_values.h", "bearing_calls.h", "oil_thermal.h")
MODEL_SOURCES = ("bearing_calls.c", "bearing_log.c", "bearing_values.c", "bearing_model.c", "bearing_derivatives.c",
                 "bearing_thermal.c", "oil_thermal.c")
REAL_BASE, BOOL_BASE, STRING_BASE, ENUM_BASE = 0, 1000, 2000, 3000  # value references by type (bearing_native.h)
CORE_REALS = ("y", "z", "vy", "vz", "omega", "Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz",
              "Cyy", "Cyz", "Czy", "Czz", "D", "L", "CR", "mu")
FALLBACK_WHY = ("the fallback evaluates the Reynolds solver, which this native FMU does not hold; build one with it "
                "(bearing-fmu build --native --internal taylor,reynolds), use warn or discard, or the Python FMU")
# the native FMU's options per internal (registry names); the rest stay in the Python FMU
# does the internal's force depend on (the bearing D, L, CR, mu as set; the speed omega)? The
# Taylor surrogate holds its own bearing and speed (others refused), so does the linear model
FORCE_DEPENDS = {"map": (1, 1), "taylor": (0, 0), "linear": (0, 0), "reynolds": (2, 1)}  # 2: and on L/D
# native FMUs with the bearing's bore compiled in (any bore), or their data file's (a grooved bore's
# 3-D map, checked against the bearing's at build); the others take the full bore only
BORE_COMPILED_IN, BORE_FROM_DATA = ("reynolds",), ("map",)
NATIVE_OPTIONS = {
    "taylor": ("surrogate", "domain_action", "domain_limit"),
    "map": ("map",),
    "reynolds": ("n_theta", "n_x", "cavitation"),
    "linear": ("omega_lin", "lin_y0", "lin_z0", "lin_Fy0", "lin_Fz0", "lin_Kyy", "lin_Kyz", "lin_Kzy", "lin_Kzz",
               "lin_Cyy", "lin_Cyz", "lin_Czy", "lin_Czz"),
}


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

    taylor : ``surrogate`` (path) compiled in; params default to the surrogate's
    map    : ``map`` (path) compiled in; its L/D must be the bearing's
    linear : the coefficients' start values from the Python ``Linear`` internal built with
             ``options`` (registry options of "linear", e.g. linear_from, load_z, or a map)
    omega  : the start value of the input omega [rad/s] (map, linear: its omega_lin); the Taylor
             surrogate's speed is its own
    ValueError naming what is wrong otherwise."""
    internal = str(internal).strip().lower()
    if internal not in INTERNALS:
        raise ValueError(f"a native FMU computes one of {', '.join(INTERNALS)}; got internal {internal!r} "
                         "(an internal registered from outside the package: the Python FMU, `bearing-fmu build`)")
    options = dict(options or {})
    if omega is not None:
        if internal == "taylor":
            raise ValueError("a native taylor FMU's omega starts at the surrogate's speed (it refuses any other): "
                             "give no speed")
        if not (math.isfinite(omega) and omega > 0):
            raise ValueError(f"the start speed omega = {omega!r} rad/s must be finite and > 0")
        options["omega_lin" if internal == "linear" else "_omega"] = float(omega)
    return {"taylor": _taylor, "map": _map, "linear": _linear, "reynolds": _reynolds}[internal](
        params, surrogate, map, options)


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
            desc = ("taylor, state outside the fitted domain: warn (surrogate value, warned once per excursion) | "
                    + ("fallback (the Reynolds internal of this FMU, blended over the domain's edge) | " if
                       "reynolds" in parts else "") + "discard (refuse the step)"
                    + ("" if "reynolds" in parts else "; fallback needs the Reynolds internal in the FMU"))
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
    items it accepts (internal: its own; domain_action: fallback only with reynolds in the FMU)."""
    parts = parts_of(internal)
    strings = ["internal"] + [n for n in option_names(internal) if registry_option(n).choices]
    out = []
    for name, (string, items) in ENUMERATIONS.items():
        if string in strings:
            allowed = [c for c in items if c in parts] if string == "internal" else [c for c in items if not (
                string == "domain_action" and c == "fallback" and "reynolds" not in parts)]
            out.append((name, string, [(items.index(c) + 1, c) for c in allowed]))
    return out


def registry_option(name: str) -> registry.Option:
    return next(o for o in registry.all_options() if o.name == name)


def internal_sources(model: "NativeModel") -> tuple[list[str], list[str]]:
    """(the internals' C files the compiler builds, the files they include) of ``model``: each
    internal's file, and for several bn_parts.c, which dispatches among them."""
    parts = model.all_parts
    why = model.flows_why if isinstance(model.flows_why, dict) else {model.internal: model.flows_why}
    compiled = [f for p in parts for f in (f"internal_{p}.c", *PART_SOURCES.get(p, ()),
                                           *(FLOW_SOURCES.get(p, ()) if not why.get(p) else ()))]
    compiled += ["bn_parts.c", "bn_fallback.c"] if len(parts) > 1 else []
    return compiled, list(dict.fromkeys(f for p in parts for f in INCLUDED_SOURCES.get(p, ())))


def option_names(internal) -> tuple[str, ...]:
    """The native options of ``internal`` (a name or a tuple of names), each once, in order."""
    return tuple(dict.fromkeys(n for p in parts_of(internal) for n in NATIVE_OPTIONS[p]))


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
        f"#define BN_BEARING_IN_FORCE {max(FORCE_DEPENDS[p][0] for p in parts)}",
        f"#define BN_SPEED_IN_FORCE {max(FORCE_DEPENDS[p][1] for p in parts)}",
        f"#define BN_PARTS {len(parts)}",
        f"#define BN_INTERNALS {c_string('|'.join(parts))}",
        "#define BN_PART_LIST(X) " + " ".join(f"X({p}, {FORCE_DEPENDS[p][0]}, {FORCE_DEPENDS[p][1]})" for p in parts),
        *(f"#define BN_HOLDS_{p.upper()} {int(p in parts)}" for p in INTERNALS),
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
    for k, o in enumerate(strings):
        lines.append(f"#define S_OPT_{o.name.upper()} {1 + k}")
        if o.file:
            rows.append(f"    {{{c_string(o.name)}, {c_string(starts[o.name])}, NULL, 1, NULL, NULL}}")
        else:
            fallback = "reynolds" in parts  # taylor's fallback: the Reynolds internal of the same FMU
            choices = [c for c in o.choices if not (o.name == "domain_action" and c == "fallback" and not fallback)]
            refuse = ("fallback", FALLBACK_WHY) if o.name == "domain_action" and not fallback else None
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


# ----------------------------------------------------------------------------- taylor

def _rows(exps: np.ndarray, coef: np.ndarray, index: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The value rows (2, n) and gradient rows (8, n) of two polynomials (rows of coef over
    the exponents exps) on the monomials ``index`` (exponent tuple -> column): the gradient
    is a polynomial too, d/du_v sum_k c_k u^e_k = sum_k e_kv c_k u^(e_k - 1_v)."""
    val, grad = np.zeros((2, n)), np.zeros((8, n))
    for k, e in enumerate(np.asarray(exps, int)):
        c = coef[:, k]
        if not np.any(c):
            continue
        val[:, index[tuple(int(x) for x in e)]] += c
        for v in range(4):
            if e[v] > 0:
                low = tuple(int(x) - (1 if w == v else 0) for w, x in enumerate(e))
                grad[[v, 4 + v], index[low]] += e[v] * c
    return val, grad


def _monomials(*exponent_sets) -> list[tuple]:
    """Every monomial the polynomials and their gradients need, with the chain of parents to
    the constant, in graded order (constant first): each is its parent times one u_v."""
    needed = {(0, 0, 0, 0)}
    for exps in exponent_sets:
        for e in np.asarray(exps, int):
            e = tuple(int(x) for x in e)
            needed.add(e)
            for v in range(4):
                if e[v] > 0:
                    needed.add(tuple(x - (1 if w == v else 0) for w, x in enumerate(e)))
    for mono in list(needed):
        m = list(mono)
        while sum(m) > 0:
            v = next(i for i in range(4) if m[i] > 0)
            m[v] -= 1
            needed.add(tuple(m))
    return sorted(needed, key=lambda m: (sum(m), tuple(-x for x in m)))


def _used(rows: np.ndarray) -> int:
    """Columns up to the last non-zero one, rounded up to a multiple of 8 (the kernel's stride)."""
    nz = np.nonzero(np.any(rows != 0.0, axis=0))[0]
    n = int(nz[-1]) + 1 if nz.size else 0
    return -(-n // 8) * 8


def taylor_polynomials(exps, coef, shape_exps=None, shape_coef=None) -> str:
    """The polynomials of the Taylor internal as data for the C kernel (internal_taylor.c):
    the monomials (``monomials(u, M)``: m_j = m_parent * u_var, graded order, padded with
    zeros to TAY_NM, a multiple of 8) and the coefficient rows over them: TAY_VAL (Fy, Fz),
    TAY_GRAD (dFy/du_0..3, dFz/du_0..3) and, with shape columns, TAY_SVAL (the four M_l) and
    TAY_SGRAD (dM_l/du_v, l-major). Each group's rows are used up to its last non-zero column
    (TAY_N_VAL, ...). Summed as dot products, the force rounds differently from the Python
    kernels' term-by-term order: they agree to ~1e-15 relative (tests: 1e-12)."""
    sets = [exps] + ([shape_exps] if shape_exps is not None else [])
    monos = _monomials(*sets)
    nm = -(-len(monos) // 8) * 8
    index = {m: j for j, m in enumerate(monos)}
    val, grad = _rows(exps, np.asarray(coef, float), index, nm)
    parent, var = [0], [0]
    for m in monos[1:]:
        lst = list(m)
        v = next(i for i in range(4) if lst[i] > 0)
        lst[v] -= 1
        parent.append(index[tuple(lst)])
        var.append(v)
    lines = ["    M[0] = 1.0;"] + [f"    M[{j}] = M[{parent[j]}] * u[{var[j]}];" for j in range(1, len(monos))]
    lines += [f"    M[{j}] = 0.0;" for j in range(len(monos), nm)]
    out = [f"#define TAY_NMONO {len(monos)}", f"#define TAY_NM {nm}",
           f"#define TAY_N_VAL {_used(val)}", f"#define TAY_N_GRAD {_used(grad)}",
           "/* the monomials m_j = m_parent * u_v, graded order; zeros up to TAY_NM */",
           "static void monomials(const double u[4], double M[TAY_NM]) {\n" + "\n".join(lines) + "\n}",
           c_matrix("TAY_VAL", val), c_matrix("TAY_GRAD", grad)]
    if shape_exps is not None:
        sc = np.asarray(shape_coef, float)
        v01, g01 = _rows(shape_exps, sc[0:2], index, nm)
        v23, g23 = _rows(shape_exps, sc[2:4], index, nm)
        sval = np.vstack([v01, v23])  # M_0..M_3
        sgrad = np.vstack([g01[0:4], g01[4:8], g23[0:4], g23[4:8]])  # dM_l/du_v, l-major
        out += [f"#define TAY_N_SVAL {_used(sval)}", f"#define TAY_N_SGRAD {_used(sgrad)}",
                c_matrix("TAY_SVAL", sval), c_matrix("TAY_SGRAD", sgrad)]
    return "\n".join(out) + "\n"


def c_matrix(name: str, rows: np.ndarray) -> str:
    """A (R, n) matrix as a static, 32-byte aligned C array (the kernel loads 4 doubles at a time)."""
    rows = np.asarray(rows, float)
    body = ",\n    ".join("{" + ", ".join(c_double(x) for x in r) + "}" for r in rows)
    return (f"static const double {name}[{rows.shape[0]}][{rows.shape[1]}] BN_ALIGN32 = {{\n    {body}}};\n")


def _taylor(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    from ...surrogates.surrogate import load_surrogate
    from ...internals.taylor import Taylor
    from .taylor_data import film_data_lines, native_film_why

    if not surrogate:
        raise ValueError("a native taylor FMU needs a surrogate file (--surrogate FILE)")
    path = Path(surrogate)
    sur = load_surrogate(path, params) if params is not None else load_surrogate(path)
    tay = Taylor(sur, source=str(path))  # its film_flow_why names the file
    # the file's: '' with its film fit (a grooved bore's is not ported: native_film_why)
    flows_why = registry.film_flow_of(registry.get("taylor"), tay) or native_film_why(sur.film)
    # the surrogate's bearing, with the bearing file's oil law when given (the thermal model's)
    params = sur.params if params is None or params.oil is None else dataclasses.replace(sur.params, oil=params.oil)
    exps, coef = tay._exps, tay._coef  # the kept terms, exactly what the numba kernels evaluate
    shape = sur.shape_order is not None
    what = " and ".join(([f"wall factor (1 - eps^2)^-{sur.wall_power:g}"] if sur.wall_power else [])
                        + (["short-bearing shape columns"] if shape else []))
    wall_why = (f"; the surrogate's {what} {'are' if shape else 'is'} undefined there" if what else "")
    nb = sur.neighbours
    # the Python guard's radius max(r_cv, r_lin) and size (nearest.NearestTraining); the bounds
    # in tay._dom are widened by as much already: the native FMU flags what the Python one flags
    near = tay.neighbours
    radius, size = (near.radius, near.size) if near is not None else (1.0, 1.0)
    parts = [
        "/* Generated by bearing_fmu.fmu.native.codegen from the surrogate file "
        f"{path.name} ({sur.recipe}). Do not edit. */",
        "#ifndef MODEL_DATA_H", "#define MODEL_DATA_H",
        f"#define TAY_SOURCE {c_string(path.name)}",
        f"#define TAY_SHAPE {int(shape)}",
        f"#define TAY_NN {0 if nb is None else len(nb.points)}",
        f"#define TAY_NN_RADIUS {c_double(radius)}",
        f"#define TAY_NN_SIZE {c_double(size)}",
        f"#define TAY_CR2 {c_double(tay._cr2)}",
        f"#define TAY_WALL_WHY {c_string(wall_why)}",
        c_array("TAY_PARAMS", (params.D, params.L, params.CR, params.mu)),
        # the force's data, internal_taylor.c's alone (taylor_film.c, the film report, holds the film fit's)
        "#if !defined(BN_TAYLOR_FILM_UNIT)",
        c_array("TAY_META", tay._meta),
        c_array("TAY_DOM", tay._dom),
        # sorted by u_0: the C search sweeps outward from the query in that order (internal_taylor.c: nearest)
        c_array("TAY_NN_POINTS", nb.points[np.argsort(nb.points[:, 0], kind="stable")] if nb is not None
                else [0.0, 0.0, 0.0, 0.0]),
        taylor_polynomials(exps, coef, *((sur.shape_exponents, sur.shape_coef) if shape else ())),
        "#endif /* the force's data (a comment: several.py drops the file's bare closing #endif) */",
        *film_data_lines(sur.film, c_array),  # the film fit (format version 2): c/taylor_film.c
    ]
    parts.append("#endif\n")
    starts = {"surrogate": path.name, "domain_action": "warn", "domain_limit": registry.DEFAULT_DOMAIN_LIMIT}
    for name in ("domain_action", "domain_limit"):
        if name in options:
            starts[name] = registry_option(name).check(options[name], "native FMU option")
    if starts["domain_action"] == "fallback":
        raise ValueError(f"domain_action = 'fallback': {FALLBACK_WHY}")
    inputs = (sur.y0, sur.z0, 0.0, 0.0, sur.omega)
    data_h = "\n".join(parts)
    config_h = model_config("taylor", params, starts, inputs, flows_why)
    info = {"source": path.name, "recipe": sur.recipe, "order": sur.order, "terms": int(exps.shape[0]),
            "wall_power": sur.wall_power, "shape_order": sur.shape_order, "omega": sur.omega,
            "training_states": 0 if nb is None else len(nb.points),
            "provenance": sur.provenance}
    return NativeModel("taylor", params, native_variables("taylor", params, starts, inputs, flows_why), config_h, data_h,
                       path, f"hydrodynamic journal bearing, Taylor surrogate {path.name} ({sur.recipe}) at "
                       f"{sur.omega / (2 * math.pi):.6g} Hz, compiled (no Python)", info, flows_why=flows_why)


# ----------------------------------------------------------------------------- map

# a grooved map's flow spline is 2.5 times its force's coefficients (docs/forcemap.md, "Cost"): left out when
# the bearing has no oil law, with which thermal = true is refused anyway
GROOVED_NO_OIL_WHY = ("the bearing has no [oil] viscosity law, so a grooved map's flow tables are not compiled in "
                      "(build with --bearing FILE whose [oil] gives the law)")


def _map(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    from ...internals.mapfile import load_any_map, map_internal
    from .map_data import map_data_h

    if not map_path:
        raise ValueError("a native map FMU needs a force map file (--map FILE)")
    path = Path(map_path)
    table = load_any_map(path)
    # refuses another L/D or bore, as the FMU will (a grooved map's bore comes from --bearing)
    internal = map_internal(params, table, str(path), hint="for the native map FMU give the bearing file with --bearing")
    flows_why = registry.film_flow_of(registry.get("map"), internal)  # the file's: '' with its flow tables
    if not flows_why and table.H.ndim == 4 and params.oil is None:  # no run could use them: not compiled in
        flows_why = GROOVED_NO_OIL_WHY
    starts = {"map": path.name}
    # a nonzero speed: an omega a master forgets to connect still gives the film's force
    inputs = (0.0, 0.0, 0.0, 0.0, float(options.get("_omega", registry.DEFAULT_OMEGA_LIN)))
    shape = " x ".join(str(n) for n in table.H.shape[:-1])
    info = {"source": path.name, "table": shape, "eps_max": table.eps_max, "L_over_D": table.L_over_D,
            "reynolds": f"{table.n_theta} x {table.n_x} {table.cavitation}", "provenance": table.provenance}
    return NativeModel("map", params, native_variables("map", params, starts, inputs, flows_why),
                       model_config("map", params, starts, inputs, flows_why),
                       map_data_h(path, table, c_double, c_string, c_array, params.geometry, not flows_why), path,
                       f"hydrodynamic journal bearing, force map {path.name} (L/D {table.L_over_D:.4g}, any speed, "
                       "load and velocity), compiled (no Python)", info, flows_why=flows_why)


# ----------------------------------------------------------------------------- linear

def linear_starts(params: BearingParams, options: dict, context=None) -> dict:
    """The native linear FMU's parameter values (omega_lin, lin_*) of the Python ``Linear``
    internal built from ``options`` (registry options of "linear")."""
    lin = registry.create("linear", params, options, context)
    return {"omega_lin": lin.omega0, "lin_y0": lin.y0, "lin_z0": lin.z0, "lin_Fy0": lin.F0[0], "lin_Fz0": lin.F0[1],
            "lin_Kyy": lin.K[0, 0], "lin_Kyz": lin.K[0, 1], "lin_Kzy": lin.K[1, 0], "lin_Kzz": lin.K[1, 1],
            "lin_Cyy": lin.C[0, 0], "lin_Cyz": lin.C[0, 1], "lin_Czy": lin.C[1, 0], "lin_Czz": lin.C[1, 1]}


def _linear(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    if map_path and "linear_from" not in options:
        options = {"linear_from": "map", "map": str(map_path), **options}
    elif map_path:
        options = {"map": str(map_path), **options}
    starts = {k: float(v) for k, v in linear_starts(params, options).items()}
    data_h = "/* Generated by bearing_fmu.fmu.native.codegen: the linear internal has no data. */\n"
    inputs = (0.0, 0.0, 0.0, 0.0, starts["omega_lin"])
    config_h = model_config("linear", params, starts, inputs)
    info = {"from": options.get("linear_from", "load"), "omega_lin": starts["omega_lin"]}
    # the coefficients' source: a force map file when linearised on one (recorded with its hash)
    source = Path(options["map"]) if options.get("linear_from") == "map" and options.get("map") else None
    return NativeModel("linear", params, native_variables("linear", params, starts, inputs), config_h, data_h, source,
                       "hydrodynamic journal bearing, linear model F = F0 - K (q - q0) - C v (8 Lund coefficients as "
                       "parameters" + (f", linearised on the force map {source.name}" if source else "")
                       + "), compiled (no Python)", info)


# ----------------------------------------------------------------------------- reynolds

def _reynolds(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    from .reynolds_data import reynolds_data_h

    starts = {"n_theta": 0, "n_x": 0, "cavitation": "reynolds"}
    for name in starts:
        if name in options:
            starts[name] = registry_option(name).check(options[name], "native FMU option")
    # a nonzero speed: an omega a master forgets to connect still gives the film's force
    inputs = (0.0, 0.0, 0.0, 0.0, float(options.get("_omega", registry.DEFAULT_OMEGA_LIN)))
    grid = f"{starts['n_theta'] or 'default'} x {starts['n_x'] or 'default'}"
    info = {"bore": params.geometry.describe(), "grid": grid, "cavitation": starts["cavitation"]}
    return NativeModel("reynolds", params, native_variables("reynolds", params, starts, inputs),
                       model_config("reynolds", params, starts, inputs), reynolds_data_h(params, c_double, c_string),
                       None,
                       f"hydrodynamic journal bearing, finite-volume Reynolds solver ({params.geometry.describe()}; "
                       "any speed, load and velocity), compiled (no Python)", info)
