"""The native FMU's share of the Python FMU's thermal ports and bore parameters (``fmu/ports.py``):
their variables and their lines of model_config.h, for ``codegen``.

* Thermal ports: the input ``T_supply`` and the outputs ``P_loss``, ``Q_side``, ``T_eff``,
  ``mu_eff`` after the internal's Real options, the parameter ``thermal`` (Boolean 2). No native
  internal computes the film's flows yet (the C Reynolds solver gives the force and its
  derivatives, not ``film_report``), so the ports stay off: ``thermal = true`` is refused at
  initialisation naming why (``BN_FILM_FLOW_WHY``).
* The bore: the Reals ``groove_1`` .. ``lobe_angle`` after the thermal ports, the Integers
  ``groove_count``, ``lobes`` after the enumerations, the Boolean ``partial_arc`` (3). The data hold
  one bore, so their starts are its values (``BN_GEOMETRY_*``) and another is refused at
  initialisation, naming each parameter set away from it (bearing_values.c, ``check_bore``).
"""

from __future__ import annotations

from ...physics.params import BearingParams
from ..variables import VARIABLES

THERMAL_REALS = ("T_supply", "P_loss", "Q_side", "T_eff", "mu_eff")
GEOMETRY_REALS = tuple([f"groove_{k}" for k in range(1, 9)] + ["groove_width", "supply_pressure", "arc_start",
                                                                "arc_end", "preload", "lobe_offset", "lobe_angle"])
GEOMETRY_INTS = ("groove_count", "lobes")


def bore_starts(params: BearingParams) -> dict:
    """The geometry parameters' values for the bore ``params`` has (every one: the ports' defaults
    where the bore sets none)."""
    from ..ports import GEOMETRY_ROWS, port_defaults

    return {**{r[0]: r[4] for r in GEOMETRY_ROWS}, **port_defaults(params)}


NATIVE_FILM_FLOW_WHY = ("the native internals compute the force only, not the film's friction and flows "
                        "(the Python FMU's Reynolds internal has them)")


def port_variables(internal, params: BearingParams, first_real: int, first_int: int, bool_base: int) -> list:
    """The variables of the thermal ports and the bore as ``codegen.Variable``'s fields (name, value
    reference, type, causality, start, unit, description): Reals from value reference ``first_real``,
    Integers from ``first_int``, Booleans 2 and 3 above ``bool_base``."""
    table = {v[0]: v for v in VARIABLES}
    out = []
    for k, name in enumerate(THERMAL_REALS):
        _n, typ, causality, unit, start, desc = table[name]
        out.append((name, first_real + k, typ, causality, float(start) if causality == "input" else 0.0,
                            unit, desc))
    out.append(("thermal", bool_base + 2, "Boolean", "parameter", False, None,
                        "thermal model on (T_supply connected, the film at the viscosity of its effective temperature)"
                        + f": not in this native FMU ({NATIVE_FILM_FLOW_WHY}); it stays false, T_eff reads "
                          "T_supply, mu_eff mu, P_loss and Q_side 0"))
    bore = bore_starts(params)
    fixed = f"; this FMU's data hold one bore ({params.geometry.describe()}): another is refused"
    for k, name in enumerate(GEOMETRY_INTS):
        out.append((name, first_int + k, "Integer", "parameter", int(bore[name]), None, table[name][5] + fixed))
    for k, name in enumerate(GEOMETRY_REALS):
        _n, typ, causality, unit, _start, desc = table[name]
        out.append((name, first_real + len(THERMAL_REALS) + k, typ, causality, float(bore[name]), unit,
                            desc + fixed))
    out.append(("partial_arc", bool_base + 3, "Boolean", "parameter", bool(bore["partial_arc"]), None,
                        table["partial_arc"][5] + fixed))
    return out


def port_config(params: BearingParams, c_double, c_string) -> list[str]:
    """model_config.h's lines of the thermal ports (the supply temperature's start [K], whether the
    internal has the film's flows and why not) and of the bore the data hold; ``c_double``,
    ``c_string``: codegen's literals."""
    bore = bore_starts(params)
    return [
        f"#define BN_START_T_SUPPLY {c_double(next(v[4] for v in VARIABLES if v[0] == 'T_supply'))}",
        "#define BN_FILM_FLOW 0",
        f"#define BN_FILM_FLOW_WHY {c_string(NATIVE_FILM_FLOW_WHY)}",
        f"#define BN_GEOMETRY_REAL_START {{{', '.join(c_double(bore[n]) for n in GEOMETRY_REALS)}}}",
        f"#define BN_GEOMETRY_INT_START {{{', '.join(str(int(bore[n])) for n in GEOMETRY_INTS)}}}",
        f"#define BN_GEOMETRY_ARC_START {int(bool(bore['partial_arc']))}",
        f"#define BN_BORE_WORDS {c_string(params.geometry.describe())}",
    ]
