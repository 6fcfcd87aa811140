"""The native tilting-pad model (c/internal_tilting_pad.c over the C Reynolds solver): the pads of the
build's bearing compiled in, every pad the partial-arc solver in its own frame
(``internals.tilting_pad.assembly``: the same frame bore, grid, equations and Newton iterations
as the Python ``tilting_pad`` internal), the grid and cavitation parameters.

model_data.h holds the pad frame's bore (``reynolds_data_h`` of ``pad_frame_geometry``: its
segments and the wall's sample angles, the closure weights the tilt range is drawn from), the
pads' frame rotations (cos, sin of alpha_k = pi - theta_p,k), the preload, the pad inertia and
the cells outside a pad's arc that the frame's grid adds.

The pads' variables (after every other Real, value references from ``bearing_native.h``'s
VR_PAD0): ``pad_tilt_1 .. N`` [rad] (outputs; Model Exchange's continuous states), and massless
pads ``der(pad_tilt_k)`` [rad/s] (locals: the rate at which the squeeze balances the moment),
pads with inertia ``pad_rate_k`` [rad/s] (outputs and states, the tilts' derivatives) and
``der(pad_rate_k)`` [rad/s2] (locals, M_k / I).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

from ....internals import registry
from ....internals.tilting_pad.assembly import PadAssembly, pad_frame_geometry
from ....physics.params import BearingParams
from ..codegen import NativeModel, Variable, c_double, c_string, model_config, native_variables, registry_option
from ..portgen import part_flows
from .reynolds import reynolds_data_h

__all__ = ["tilting_pad_model", "pad_variables"]


def pad_variables(params: BearingParams, first_vr: int, omega: float) -> list[Variable]:
    """The pads' variables (module docstring) from value reference ``first_vr`` (VR_PAD0); the states'
    nominals CR / a [rad] and omega CR / a [rad/s] (a = R + C_pad; ``omega`` the start speed): a tilt
    of CR / a moves a pad's film by about CR, so an integrator's tolerance scales with the film."""
    pg = params.geometry.pads
    n = pg.n
    tilt = params.CR / (params.R + pg.pad_clearance(params.CR))
    out = []
    for k in range(n):
        out.append(Variable(f"pad_tilt_{k + 1}", first_vr + k, "Real", "output", 0.0, "rad",
                            f"tilt of the pad pivoted at {math.degrees(pg.pivots[k]):.6g} deg about its pivot (positive "
                            "about +x, the sense of positive omega; Model Exchange: a continuous state)", nominal=tilt))
    if pg.inertia > 0.0:
        for k in range(n):
            out.append(Variable(f"pad_rate_{k + 1}", first_vr + n + k, "Real", "output", 0.0, "rad/s",
                                f"tilt rate of pad {k + 1} (Model Exchange: a continuous state, der(pad_tilt_{k + 1}))",
                                derivative_of=f"pad_tilt_{k + 1}", nominal=abs(omega) * tilt or tilt))
        for k in range(n):
            out.append(Variable(f"der(pad_rate_{k + 1})", first_vr + 2 * n + k, "Real", "local", 0.0, "rad/s2",
                                f"tilt acceleration of pad {k + 1}: its film's moment about the pivot over "
                                f"pad_inertia_kg_m2 = {pg.inertia:g}"))
    else:
        for k in range(n):
            out.append(Variable(f"der(pad_tilt_{k + 1})", first_vr + n + k, "Real", "local", 0.0, "rad/s",
                                f"tilt rate of massless pad {k + 1}: the rate whose squeeze balances its film's moment"))
    return out


def tilting_pad_model(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    """The native tilting-pad model of the bearing ``params`` (the catalogue's generator)."""
    pg = params.geometry.pads if params.geometry is not None else None
    if pg is None:
        raise ValueError("the native tilting_pad FMU needs a bearing with tilting pads ([geometry] pads, "
                         "pad_arc_deg, pivots_deg): build with --bearing FILE")
    if pg.pivot_stiffness is not None:
        raise ValueError(f"[geometry] pivot_stiffness_N_m = {pg.pivot_stiffness:g}: a flexible pivot is not carried "
                         "by the bearing FMUs (the tilting_pad internal models it in run, stability and demo); leave "
                         "the key out (rigid pivots)")
    pad_map = Path(options["pad_map"]) if options.get("pad_map") else None
    starts = {"n_theta": 0, "n_x": 0, "cavitation": "reynolds", "pad_map": pad_map.name if pad_map else ""}
    for name in ("n_theta", "n_x", "cavitation"):
        if name in options:
            starts[name] = registry_option(name).check(options[name], "native FMU option")
    inputs = (0.0, 0.0, 0.0, 0.0, float(options.get("_omega", registry.DEFAULT_OMEGA_LIN)))
    flows_why = part_flows("tilting_pad", film_why(pg, pad_map))["tilting_pad"]  # the registry's, then this build's
    variables = native_variables("tilting_pad", params, starts, inputs, flows_why)
    first = max(v.vr for v in variables if v.type == "Real" and v.vr < 1000) + 1
    # VR_PAD0 = VR_DER_T_EFF + 3 (after the peak pressure's two) whether der(T_eff) is declared or not
    oil_last = max(v.vr for v in variables if v.name.startswith("oil_"))
    first = max(first, oil_last + 4)
    pads = pad_variables(params, first, inputs[4])
    n_states = pg.n * (2 if pg.inertia > 0.0 else 1)
    config = model_config("tilting_pad", params, starts, inputs, flows_why).replace(
        "#endif\n", "\n".join([
            f"#define BN_N_PADS {pg.n}",
            f"#define BN_N_PAD_REALS {len(pads)}",
            f"#define BN_N_PAD_STATES {n_states}",
            f"#define BN_N_PAD_OUTPUTS {n_states}",
            "#define BN_PAD_NAMES {" + ", ".join(c_string(v.name) for v in pads) + "}",
            "#define BN_PAD_UNITS {" + ", ".join(c_string(v.unit) for v in pads) + "}",
            "#define BN_PAD_NOMINALS {" + ", ".join(c_double(v.nominal) for v in pads[:n_states]) + "}",
            "#endif\n"]))
    grid = f"{starts['n_theta'] or 'default'} x {starts['n_x'] or 'default'}"
    info = {"bore": params.geometry.describe(), "grid": grid, "cavitation": starts["cavitation"]}
    if pad_map:
        info["pad_map"] = pad_map.name
    how = (f"every pad from the pads' force map {pad_map.name}" if pad_map else
           "every pad the finite-volume Reynolds solver")
    return NativeModel("tilting_pad", params, variables + pads, config, pads_data_h(params, pad_map), pad_map,
                       f"tilting-pad journal bearing ({pg.describe()}), {how} in its own frame, the pads' tilts (and "
                       "rates) states; compiled (no Python)", info, flows_why=flows_why)


def film_why(pads, pad_map: Path | None) -> str:
    """Why the pads' film report (the thermal model) is not in this build, '' when it is: the
    Reynolds pads sum each pad's report (TiltingPad.film_report); the pads' map has no friction or
    flows (the Python internal's words); pads with inertia would move at the isoviscous moments
    while the force is scaled to the film's viscosity (massless pads' tilts do not depend on it)."""
    if pad_map is not None:
        return (f"the pads' force map ({pad_map.name}) tabulates forces only, no friction or flows: the film "
                "temperature needs the Reynolds pads (no pad_map)")
    if pads.inertia > 0.0:
        return (f"pad_inertia_kg_m2 = {pads.inertia:g}: pads with inertia at the film's effective viscosity are not "
                "modelled (massless pads' tilts do not depend on it)")
    return ""


def pads_data_h(params: BearingParams, pad_map: Path | None = None) -> str:
    """model_data.h: the pad frame's bore (as the Reynolds model's) and the pads; with ``pad_map``
    (the pads' 3-D partial-arc map, ``padmap.build_pad_map``) its spline too (``map_data_h``, no
    flows), every pad then from it (``padmap.PadMapSolver``: the arc of clearance C_pad, the journal
    shifted by the preload d = C_pad - C_bearing)."""
    pg = params.geometry.pads
    frame = pad_frame_geometry(pg)
    bore = reynolds_data_h(replace(params, geometry=frame), c_double, c_string)
    extra = len(frame.segments()[0]) - 1
    rot = [(math.cos(pg.frame_angle(k)), math.sin(pg.frame_angle(k))) for k in range(pg.n)]
    lines = [
        f"#define TP_N {pg.n}",
        f"#define TP_DEFAULT_CELLS {PadAssembly.default_cells(pg)}",
        f"#define TP_EXTRA_CELLS {extra}",
        f"#define TP_PRELOAD {c_double(pg.preload)}",
        f"#define TP_INERTIA {c_double(pg.inertia)}",
        "#define TP_COS {" + ", ".join(c_double(c) for c, _s in rot) + "}",
        "#define TP_SIN {" + ", ".join(c_double(s) for _c, s in rot) + "}",
        "#define TP_PIVOT_DEG {" + ", ".join(c_double(math.degrees(p)) for p in pg.pivots) + "}",
        f"#define TP_PADS_TEXT {c_string(pg.describe())}",
        f"#define TP_MAP {int(pad_map is not None)}",
    ]
    if pad_map is not None:
        lines += _pad_map_lines(params, pad_map)
    return bore.replace("#endif\n", "\n".join([*lines, "#endif\n"]))


def _pad_map_lines(params: BearingParams, path: Path) -> list[str]:
    """The pads' map file compiled in: checked as the Python internal takes it (``PadMapSolver``:
    a 3-D map of the pads' arc and L/D), its spline's lines."""
    from ....internals.mapfile import load_any_map
    from ....internals.tilting_pad.padmap import PadMapSolver
    from ..codegen import c_array
    from .map import map_data_h

    table = load_any_map(path)
    try:
        PadMapSolver(params, table)
    except ValueError as exc:
        raise ValueError(f"pad_map {path.name}: {exc}") from None
    if table.H.ndim != 4:
        raise ValueError(f"pad_map {path.name}: not a partial-arc (3-D) map of the pads (padmap.build_pad_map)")
    text = map_data_h(path, table, c_double, c_string, c_array, None, with_flows=False)
    body = [ln for ln in text.splitlines() if ln not in ("#ifndef MODEL_DATA_H", "#define MODEL_DATA_H", "#endif")]
    return body
