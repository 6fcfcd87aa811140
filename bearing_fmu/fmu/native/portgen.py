"""The native FMU's share of the Python FMU's thermal ports and bore parameters (``fmu/ports.py``):
their variables and their lines of model_config.h, for ``codegen``.

* Thermal ports: the input ``T_supply`` and the outputs ``P_loss``, ``Q_side``, ``T_eff``,
  ``mu_eff`` after the internal's Real options, the parameter ``thermal`` (Boolean 2). Whether
  the internal has the film's flows is its registry capability ``film_flow`` and, per data file,
  the Python internal's answer (``registry.film_flow_of``: a map file without flow tables, a
  version 1 surrogate file) (``BN_FILM_FLOW``; the Reynolds internal's report is
  c/reynolds_film.c, the map's c/map_flows.c from its flow table, ``map_data``, the Taylor
  surrogate's c/taylor_film.c from its film fit, ``taylor_data``); one without them refuses
  ``thermal = true`` at initialisation naming why (``BN_FILM_FLOW_WHY``). An FMU of several
  internals has the thermal model when one of them has the flows (``BN_FLOWS_<NAME>``: its
  bn_film, bn_parts.c dispatching); initialisation refuses thermal = true with the internal set
  to one without them, naming it and why (``BN_FLOW_WHY_<name>``).
* The oil: the bearing file's law (``BN_OIL_LAW``: none, walther, vogel) compiled in, as the
  bore is; its Real parameters (``fmu.ports.OIL_ROWS``: oil_nu_1 .. oil_rise_factor, and the heat
  balance's ``ports.BALANCE_ROWS``: oil_outflow_share, oil_ambient_loss, oil_T_ambient) after the
  bore's, their starts the file's (``ports.port_defaults``) and settable. No ``oil_law``
  parameter: another law is another build.
* The film's peak pressure: the outputs ``peak_pressure`` [Pa] and ``peak_pressure_angle`` [rad]
  after der(T_eff)'s value reference, the Reynolds internal's field (c/reynolds_peak.c
  rs_peak_pressure, a port of ``Reynolds.peak_pressure``), 0 for an internal without one (as the
  Python FMU: ``Capabilities.film_field``).
* The bore: the Reals ``groove_1`` .. ``lobe_angle``, ``circumferential_groove`` after the thermal ports, the Integers
  ``groove_count``, ``lobes`` after the enumerations, the Boolean ``partial_arc`` (3). The data hold
  one bore, so their starts are its values (``BN_GEOMETRY_*``) and another is refused at
  initialisation, naming each parameter set away from it (bearing_values.c, ``check_bore``).
"""

from __future__ import annotations

from ...physics.params import BearingParams
from ..variables import VARIABLES
from .catalogue import NATIVE

THERMAL_REALS = ("T_supply", "P_loss", "Q_side", "T_eff", "mu_eff")
GEOMETRY_REALS = tuple([f"groove_{k}" for k in range(1, 9)] + ["groove_width", "supply_pressure", "arc_start",
                                                                "arc_end", "preload", "lobe_offset", "lobe_angle",
                                                                "circumferential_groove"])
GEOMETRY_INTS = ("groove_count", "lobes")
PEAK_OUTPUTS = ("peak_pressure", "peak_pressure_angle")  # the film's (the Reynolds internal's field; else 0)


OIL_REALS = ("oil_nu_1", "oil_T_1", "oil_nu_2", "oil_T_2", "oil_vogel_a", "oil_vogel_b", "oil_vogel_c", "oil_T_min",
             "oil_T_max", "oil_density", "oil_heat_capacity", "oil_rise_factor", "oil_outflow_share",
             "oil_ambient_loss", "oil_T_ambient")


def bore_starts(params: BearingParams, internal=()) -> dict:
    """The geometry parameters' values for the bore ``params`` has (every one: the ports' defaults
    where the bore sets none). Tilting pads (an ``internal`` whose registry capability is ``pads``,
    generators/tilting_pad.py) are compiled in as pads, none of the fixed bores' parameters
    describes them: those keep the full bore's values (another is refused); any other internal
    refuses pads (``ports.port_defaults``)."""
    from dataclasses import replace

    from ...internals import registry
    from ...physics.bore.geometry import FULL_BORE
    from ..ports import BALANCE_ROWS, GEOMETRY_ROWS, GROOVE_ROWS, OIL_ROWS, port_defaults

    parts = parts_of(internal) if internal else ()
    if params.geometry is not None and params.geometry.pads is not None and parts and all(
            registry.get(p).can.pads for p in parts):
        params = replace(params, geometry=FULL_BORE)
    return {**{r[0]: r[4] for r in GEOMETRY_ROWS + GROOVE_ROWS + OIL_ROWS + BALANCE_ROWS}, **port_defaults(params)}


def parts_of(internal) -> tuple[str, ...]:
    """The internals of a native model: one name, or a tuple of them (an FMU of several, the first
    the start value of the parameter internal)."""
    return (internal,) if isinstance(internal, str) else tuple(internal)


def part_flows(internal, data_why="") -> dict[str, str]:
    """{internal: why its native model lacks the film's flows, '' when it has them} for ``internal``
    (a name, or a tuple of the names an FMU of several holds): the registry's capability
    ``film_flow``, a film report in C (its catalogue entry's ``film_report``: bn_film, e.g.
    reynolds_film.c; map_flows.c from a map file's flow table; taylor_film.c from a surrogate file's
    film fit) and, for the data file compiled in,
    ``data_why`` (the Python internal's ``registry.film_flow_of``: '' when the file has the flows; a
    version 1 or a grooved map, a version 1 surrogate: why not), for several internals {internal:
    its data's why}."""
    from ...internals import registry

    parts = parts_of(internal)
    files = data_why if isinstance(data_why, dict) else {parts[0]: data_why}
    out = {}
    for p in parts:
        can = registry.get(p).can
        if not can.film_flow:
            out[p] = can.film_flow_why or f"the {p} internal has no film report"
        elif not NATIVE[p].film_report:
            out[p] = (f"the native {p} FMU computes the force only: the film's flows of the Python {p} internal are "
                      "not compiled into it (use the Python FMU, or internal = 'reynolds')")
        else:
            out[p] = files.get(p, "")
    return out


def film_flow(internal, data_why="") -> tuple[bool, str]:
    """(has the film's flows, why not) of a native model of ``internal`` (``part_flows``' arguments):
    an FMU of several has them when one of its internals has (the one set is checked at
    initialisation, bn_film_why); why: each internal's without them."""
    whys = part_flows(internal, data_why)
    flows = any(not w for w in whys.values())
    if len(whys) == 1:
        return flows, next(iter(whys.values()))
    return flows, "; ".join(f"internal = {p!r}: {w}" for p, w in whys.items() if w)


def has_state(internal, params: BearingParams, data_why="") -> bool:
    """Model Exchange's continuous state T_eff (its derivative the local der(T_eff)): a build whose
    internal has the film's flows and whose bearing an oil law (thermal = true can be set)."""
    return film_flow(internal, data_why)[0] and params.oil is not None


def supply_start(params: BearingParams) -> float:
    """T_supply's start [K]: the bearing file's supply temperature (its [oil]'s supply_C, the
    temperature mu is the oil's viscosity at), else the ports' default."""
    if params.oil is not None:
        return float(params.oil.T_supply)
    return float(next(v[4] for v in VARIABLES if v[0] == "T_supply"))


def port_variables(internal, params: BearingParams, first_real: int, first_int: int, bool_base: int,
                   data_why="") -> list:
    """The variables of the thermal ports and the bore as ``codegen.Variable``'s fields (name, value
    reference, type, causality, start, unit, description): Reals from value reference ``first_real``,
    Integers from ``first_int``, Booleans 2 and 3 above ``bool_base``; ``data_why`` as ``film_flow``'s."""
    table = {v[0]: v for v in VARIABLES}
    out = []
    for k, name in enumerate(THERMAL_REALS):
        _n, typ, causality, unit, start, desc = table[name]
        out.append((name, first_real + k, typ, causality, supply_start(params) if causality == "input" else 0.0,
                    unit, desc))
    flows, why = film_flow(internal, data_why)
    law = params.oil.law if params.oil is not None else "none"
    if flows and law != "none":
        note = (f" (the oil's law is the bearing file's, {law}, its parameters oil_...; Model Exchange: T_eff "
                "is the continuous state, der(T_eff) its derivative" + (f"; refused with {why}" if why else "") + ")")
    else:
        note = (f": not in this native FMU ({why or 'the bearing file has no [oil] law'}); it stays false, T_eff "
                "reads T_supply, mu_eff mu, P_loss and Q_side 0")
    out.append(("thermal", bool_base + 2, "Boolean", "parameter", False, None,
                "thermal model on (T_supply connected, the film at the viscosity of its effective temperature)" + note))
    bore = bore_starts(params, internal)
    fixed = f"; this FMU's data hold one bore ({params.geometry.describe()}): another is refused"
    for k, name in enumerate(GEOMETRY_INTS):
        out.append((name, first_int + k, "Integer", "parameter", int(bore[name]), None, table[name][5] + fixed))
    for k, name in enumerate(GEOMETRY_REALS):
        _n, typ, causality, unit, _start, desc = table[name]
        out.append((name, first_real + len(THERMAL_REALS) + k, typ, causality, float(bore[name]), unit,
                            desc + fixed))
    out.append(("partial_arc", bool_base + 3, "Boolean", "parameter", bool(bore["partial_arc"]), None,
                        table["partial_arc"][5] + fixed))
    first_oil = first_real + len(THERMAL_REALS) + len(GEOMETRY_REALS)
    for k, name in enumerate(OIL_REALS):
        _n, typ, causality, unit, _start, desc = table[name]
        out.append((name, first_oil + k, typ, causality, float(bore[name]), unit, desc))
    if has_state(internal, params, data_why):  # its value reference is C's VR_DER_T_EFF
        desc = ("the film temperature's rate (Model Exchange: T_eff's derivative, T_eff the continuous state): the "
                "heat balance's (T*(T_eff) - T_eff) / t_res with thermal = true, 0 (T_eff holds) with thermal = false")
        out.append(("der(T_eff)", first_oil + len(OIL_REALS), "Real", "local", 0.0, "K/s", desc))
    # the film's peak pressure and its angle (C's VR_PEAK: after der(T_eff)'s value reference, declared or not)
    from ...internals import registry

    field = any(registry.get(p).can.film_field for p in parts_of(internal))  # Capabilities.film_field
    for k, name in enumerate(PEAK_OUTPUTS):
        _n, typ, causality, unit, _start, desc = table[name]
        note = "" if field else "; this FMU's internal has no pressure field: always 0"
        out.append((name, first_oil + len(OIL_REALS) + 1 + k, typ, causality, 0.0, unit, desc + note))
    return out


def thermal_start(model) -> None:
    """Make ``model`` (a ``codegen.NativeModel``) start with thermal = true (its variable's start and
    ``BN_THERMAL_START``); ValueError naming why when its internal (of several: the first, the one
    it starts with) has no film flows or its bearing no oil law."""
    first = model.all_parts[0]
    why = part_flows(model.all_parts, model.flows_why)[first]
    if why or model.params.oil is None:
        raise ValueError("a native FMU starting with thermal = true needs the film's flows and the bearing's oil "
                         f"law: {why or 'the bearing has no [oil] table (build with --bearing FILE whose [oil] gives it)'}")
    for v in model.variables:
        if v.name == "thermal":
            v.start = True
    model.config_h = model.config_h.replace("#define BN_FILM_FLOW 1", "#define BN_FILM_FLOW 1\n#define BN_THERMAL_START 1")


def port_config(internal, params: BearingParams, c_double, c_string, data_why="") -> list[str]:
    """model_config.h's lines of the thermal ports (the supply temperature's start [K], whether the
    internal has the film's flows and why not, the oil's law and its parameters' starts) and of
    the bore the data hold; ``c_double``, ``c_string``: codegen's literals; ``data_why`` as
    ``film_flow``'s."""
    from ..ports import OIL_LAWS

    bore = bore_starts(params, internal)
    flows, why = film_flow(internal, data_why)
    law = params.oil.law if params.oil is not None else "none"
    return [
        f"#define BN_START_T_SUPPLY {c_double(supply_start(params))}",
        f"#define BN_FILM_FLOW {int(flows)}",
        f"#define BN_N_STATES {int(has_state(internal, params, data_why))}",
        f"#define BN_FILM_FLOW_WHY {c_string(why)}",
        # per internal (an FMU of several: bn_parts.c): has it the flows in C, why not
        *(f"#define BN_FLOWS_{p.upper()} {int(w == '')}" for p, w in part_flows(internal, data_why).items()
          if NATIVE[p].film_report),
        *(f"#define BN_FLOW_WHY_{p} {c_string(w)}" for p, w in part_flows(internal, data_why).items()),
        f"#define BN_OIL_LAW {OIL_LAWS.index(law)}",
        f"#define BN_OIL_START {{{', '.join(c_double(float(bore[n])) for n in OIL_REALS)}}}",
        f"#define BN_GEOMETRY_REAL_START {{{', '.join(c_double(bore[n]) for n in GEOMETRY_REALS)}}}",
        f"#define BN_GEOMETRY_INT_START {{{', '.join(str(int(bore[n])) for n in GEOMETRY_INTS)}}}",
        f"#define BN_GEOMETRY_ARC_START {int(bool(bore['partial_arc']))}",
        f"#define BN_BORE_WORDS {c_string(params.geometry.describe())}",
    ]
