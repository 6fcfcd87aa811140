"""The native force map model (c/internal_map.c, c/map_flows.c): a force map file compiled in.

``map_model`` (the catalogue's generator) checks the map against the bearing (its L/D, a grooved
map's bore) and writes model_data.h (``map_data_h``).

model_data.h of a native map FMU: the force map's spline compiled in (c/internal_map.c).

The force: the knots and coefficients of the tensor spline the Python map evaluates
(``MapTable.spline``; a grooved bore's 3-D map adds the attitude's knots). The film's flows
(c/map_flows.c, a port of the map's ``film_report``): a full-bore map with flow tables (format
version 3) gives the spline of its flow table Q, (J_s, J_i) over the same (s, beta) axes
(``MapTable.flow_spline``); a grooved or partial-arc bore's with flow tables (version 4) the spline
of (J_s, P_1 .. P_E) over one period in phi (``GroovedMapTable.flow_spline``) and the edges'
renumbering for the other periods of the turn (``flow_images``), its supply
edges (theta, sign) in the order of the P_e and the film's segments (``Geometry.segments``, those
without a prescribed pressure: the Couette integral's, ``film.film_couette_integral``) of the
bearing's bore, as the Python map's ``params.geometry``. Those arrays sit inside ``#if
BN_FLOWS_MAP`` (model_config.h: the map's film report is compiled) and are map_flows.c's alone
(``BN_MAP_FLOW_UNIT``), the force's internal_map.c's alone: each unit holds the arrays it uses
(an unused static array is a warning).

A lobed bore with ambient grooves over its lobe boundaries (``internals.map.lobemap``): the map file is
its lobe arc's, and model_data.h adds MAP_LOBES, the preload (C_pad = CR / (1 - m) from the FMU's CR),
u(theta_p,0) and every lobe's turn (cos, sin) alpha_k, which internal_map.c sums the arc's map over and
map_flows.c the lobes' film reports (the arc's supply edges and film segments, the table's own bore).

A bore whose grooves are fed (``internals.map.supplymap``, the 4-D map): MAP_DIMS 4, the u axis's knots MAP_TU
and size MAP_NU, the kernel's constants, and the value reference of the FMU's supply_pressure (the bearing's
p_s, which initialisation holds: the map's W = S r + R L p_s reads it). Its film report has no C port
(``FED_NO_FLOWS_WHY``): thermal = true is refused naming it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ....internals import registry
from ....physics.params import BearingParams
from ..codegen import NativeModel, c_array, c_double, c_string, model_config, native_variables

__all__ = ["map_model", "map_data_h", "GROOVED_NO_OIL_WHY", "FED_NO_FLOWS_WHY"]


# c/map_flows.c reads the 2-D and 3-D maps' flow tables: a fed-groove map's (W / S for r, the fed edges' torque,
# supplymap.SupplyForceMap.film_report) has no port, so its FMU has the force and tangent only
FED_NO_FLOWS_WHY = ("a fed-groove map's film report (friction and flows, which thermal = true needs) is not in the "
                    "native map FMU, only its force and tangent: use the Python FMU (bearing-fmu build without "
                    "--native) or the native FMU with --internal reynolds")

# a grooved map's flow spline is 2.5 times its force's coefficients (docs/forcemap.md, "Cost"): left out when
# the bearing has no oil law, with which thermal = true is refused anyway
GROOVED_NO_OIL_WHY = ("the bearing has no [oil] viscosity law, so a grooved map's flow tables are not compiled in "
                      "(build with --bearing FILE whose [oil] gives the law)")


def map_model(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    """The native model of the force map file ``map_path`` (the catalogue's generator)."""
    from ....internals.map.supplymap import SupplyMapTable
    from ....internals.mapfile import load_any_map, map_internal

    if not map_path:
        raise ValueError("a native map FMU needs a force map file (--map FILE)")
    path = Path(map_path)
    table = load_any_map(path)
    # refuses another L/D or bore, as the FMU will (a grooved map's bore comes from --bearing; a fed-groove map's
    # bearing must have fed grooves: its supply pressure is the FMU's)
    fed = isinstance(table, SupplyMapTable)
    try:
        internal = map_internal(params, table, str(path), hint="for the native map FMU give the bearing file with --bearing")
    except ValueError as exc:
        if fed:  # map_internal's hint is a grooved map's
            raise ValueError(f"{exc}; for the native map FMU give the file of the bearing whose grooves are fed "
                             "(supply_pressure_kPa > 0) with --bearing") from None
        raise
    flows_why = FED_NO_FLOWS_WHY if fed else registry.film_flow_of(registry.get("map"), internal)  # '': flow tables
    if not flows_why and table.H.ndim == 4 and params.oil is None:  # no run could use them: not compiled in
        flows_why = GROOVED_NO_OIL_WHY
    lobes = lobe_data(internal)
    starts = {"map": path.name}
    # a nonzero speed: an omega a master forgets to connect still gives the film's force
    inputs = (0.0, 0.0, 0.0, 0.0, float(options.get("_omega", registry.DEFAULT_OMEGA_LIN)))
    shape = " x ".join(str(n) for n in table.H.shape[:-1])
    info = {"source": path.name, "table": shape, "eps_max": table.eps_max, "L_over_D": table.L_over_D,
            "reynolds": f"{table.n_theta} x {table.n_x} {table.cavitation}", "provenance": table.provenance}
    return NativeModel("map", params, native_variables("map", params, starts, inputs, flows_why),
                       model_config("map", params, starts, inputs, flows_why),
                       map_data_h(path, table, c_double, c_string, c_array, params.geometry if not lobes else None,
                                  not flows_why, lobes), path,
                       f"hydrodynamic journal bearing, force map {path.name} (L/D {table.L_over_D:.4g}, any speed, "
                       "load and velocity), compiled (no Python)", info, flows_why=flows_why)


def lobe_data(internal) -> dict | None:
    """A lobed bore's lobe sum (``lobemap.LobedForceMap``) as model_data.h takes it, or None: the preload m,
    u(theta_p,0) (lobe 0's centre is -(C_pad - CR) u) and (cos, sin) alpha_k of every lobe's turn."""
    turns = getattr(internal, "turns", None)
    if turns is None:
        return None
    g = internal.params.geometry
    tp0 = float(g.preload_points()[0])
    return {"preload": g.preload, "u": [-math.sin(tp0), math.cos(tp0)], "rot": np.ravel(turns)}


def map_data_h(path: Path, table, c_double, c_string, c_array, geometry=None, with_flows=True, lobes=None) -> str:
    """The header's text for the map file ``path`` read as ``table`` (``mapfile.load_any_map``;
    ``c_double``, ``c_string``, ``c_array``: codegen's exact literals; ``geometry``: the bearing's
    bore, for a grooved map's film segments, the table's own when None; ``with_flows``: False leaves
    the flow tables out, as if the file had none)."""
    from ....internals.map.tables import EPS_MIN, LD_RTOL

    shape = " x ".join(str(n) for n in table.H.shape[:-1])
    *knots, C = table.spline()  # (ts, tb); a grooved bore's 3-D map (ts, tp, tb); a fed-groove map (ts, tp, tb, tu)
    # a fed-groove map's flows have no C port (FED_NO_FLOWS_WHY)
    flows = table.flow_spline() if with_flows and len(knots) < 4 and getattr(table, "Q", None) is not None else None
    return "\n".join([
        "/* Generated by bearing_fmu.fmu.native.map_data from the force map file "
        f"{path.name} ({shape}). Do not edit. */",
        "#ifndef MODEL_DATA_H", "#define MODEL_DATA_H",
        f"#define MAP_SOURCE {c_string(path.name)}",
        f"#define MAP_DIMS {len(knots)}",
        f"#define MAP_NS {C.shape[0]}",
        *([f"#define MAP_NP {C.shape[1]}"] if len(knots) >= 3 else []),
        f"#define MAP_NB {C.shape[2 if len(knots) == 4 else -2]}",
        *(supply_lines(C, c_double) if len(knots) == 4 else []),
        f"#define MAP_WALL_EXPONENT {c_double(table.wall_exponent)}",
        f"#define MAP_EPS_MIN {c_double(EPS_MIN)}",
        f"#define MAP_EPS_MAX {c_double(table.eps_max)}",
        f"#define MAP_L_OVER_D {c_double(table.L_over_D)}",
        f"#define MAP_LD_RTOL {c_double(LD_RTOL)}",
        f"#define MAP_FLOWS {int(flows is not None)}",
        f"#define MAP_LOBES {len(lobes['rot']) // 2 if lobes else 1}",
        *([f"#define MAP_LOBE_PRELOAD {c_double(lobes['preload'])}", c_array("MAP_LOBE_U", np.array(lobes["u"])),
           c_array("MAP_LOBE_ROT", lobes["rot"])] if lobes else []),
        "#if !defined(BN_MAP_FLOW_UNIT) /* the force's spline (internal_map.c) */",
        *([c_array("MAP_TP", knots[1])] if len(knots) >= 3 else []),
        *([c_array("MAP_TU", knots[3])] if len(knots) == 4 else []),
        c_array("MAP_TS", knots[0]), c_array("MAP_TB", knots[2 if len(knots) == 4 else -1]), c_array("MAP_C", C),
        "#endif /* the force's spline */",
        *(flow_arrays(table, flows, geometry or table.geometry if len(knots) == 3 else None, c_array)
          if flows is not None else []),
        "#endif\n",
    ])


def supply_lines(C, c_double) -> list[str]:
    """model_data.h's lines of a fed-groove map (c/internal_map.c, supply_arc_force): its u axis's size (C: its
    coefficients), the kernel's constants (``supplykernels``) and the value reference of the FMU's supply_pressure."""
    from ....internals.map.supplykernels import N_HARMONIC, T_MIN
    from ..portgen import GEOMETRY_REALS

    return [f"#define MAP_NU {C.shape[3]}", f"#define MAP_T_MIN {c_double(T_MIN)}", f"#define MAP_N_HARMONIC {N_HARMONIC}",
            f"#define MAP_SUPPLY_VR (VR_GEOMETRY0 + {GEOMETRY_REALS.index('supply_pressure')}) /* p_s [Pa] */"]


def flow_arrays(table, flows, geometry, c_array) -> list[str]:
    """The lines of the flow table's spline (``flows``: ``table.flow_spline()``) and, for a grooved
    bore's map (``geometry`` not None), its supply edges and film segments."""
    out = ["#if BN_FLOWS_MAP && defined(BN_MAP_FLOW_UNIT) /* the flow table's spline (map_flows.c): its components "
           "per point, as MAP_C */"]
    if geometry is None:  # the full bore: (J_s, J_i) on (s, beta)
        out += [c_array("MAP_QTS", flows[0]), c_array("MAP_QTB", flows[1]), c_array("MAP_QC", flows[2])]
    else:  # (J_s, P_1 .. P_E) on (s, phi over one period, beta), renumbered in the others
        segs, fixed, _supply = geometry.segments()
        film = [x for (a, b), f in zip(segs, fixed) if not f for x in (a, b)]
        edges = [x for t, sg in table.edges for x in (t, sg)]
        images = table.flow_images()
        out += [f"#define MAP_NQ {flows[3].shape[3]}", f"#define MAP_NQP {flows[3].shape[1]}",
                f"#define MAP_N_EDGES {len(table.edges)}", f"#define MAP_N_FILM {len(film) // 2}",
                c_array("MAP_QTS", flows[0]), c_array("MAP_QTP", flows[1]), c_array("MAP_QTB", flows[2]),
                c_array("MAP_QC", flows[3]),
                "/* the periods of a turn and, per period j on, the component each of (J_s, P_1 .. P_E) reads */",
                f"#define MAP_QTURNS {len(images)}",
                f"static const int MAP_QIMG[{images.size}] = {{{', '.join(str(int(i)) for i in images.ravel())}}};",
                ("/* the supply edges (theta [rad], sign) in the order of P_1 .. P_E; the film's segments "
                 "(start, end) [rad] */"), c_array("MAP_EDGES", edges), c_array("MAP_FILM_SEGS", film)]
    return out + ["#endif /* BN_FLOWS_MAP (a comment: several.py drops the file's bare closing #endif) */"]
