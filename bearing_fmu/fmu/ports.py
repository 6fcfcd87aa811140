"""The bearing FMU's bore and oil parameters and its thermal ports (docs/fmu.md, docs/thermal.md).

* Geometry (issue 25): the bearing file's ``[geometry]`` as FMU parameters, in SI (angles in rad,
  pressure in Pa): ``groove_count`` and ``groove_1`` .. ``groove_8``, ``groove_width``,
  ``supply_pressure``, ``partial_arc`` with ``arc_start``, ``arc_end``, ``lobes``, ``preload``,
  ``lobe_offset``, ``lobe_angle``, ``circumferential_groove`` [m] (a 360 deg feed groove at mid-length,
  fed at the same ``supply_pressure``: one supply for the bore's grooves, as the bearing file's
  ``supply_pressure_kPa``) (``geometry_of``). An internal that takes any bore (Reynolds,
  linear from its load) computes that bore; one whose data were made for the full circle (a
  force map, a Taylor surrogate: ``Capabilities.any_geometry`` False) refuses any other by naming
  the parameters set away from it (``check_geometry``).
* Oil: the ``[oil]`` viscosity law as parameters (``oil_law`` none | walther | vogel; Walther
  through two points ``oil_nu_1`` at ``oil_T_1`` and ``oil_nu_2`` at ``oil_T_2`` [m^2/s, K]; Vogel
  ``oil_vogel_a`` [Pa s], ``oil_vogel_b``, ``oil_vogel_c`` [K]; ``oil_T_min``, ``oil_T_max``,
  ``oil_density``, ``oil_heat_capacity``, ``oil_rise_factor``; the heat balance's
  ``oil_outflow_share`` s, ``oil_ambient_loss`` h A [W/K], ``oil_T_ambient`` [K]: ``BALANCE_ROWS``),
  their defaults the bearing file's (``bearing-fmu build --bearing FILE``: ``port_defaults``).
* Thermal ports: the input ``T_supply`` [K] and the outputs ``P_loss`` [W], ``Q_side`` [m^3/s],
  ``T_eff`` [K], ``mu_eff`` [Pa s]. An FMI 2.0 FMU cannot tell whether a master connected an
  input, so the parameter ``thermal`` says it: false (the default) leaves the FMU isoviscous at
  ``mu`` whatever ``T_supply`` holds (then ``T_eff`` = T_supply, ``mu_eff`` = mu, ``P_loss`` and
  ``Q_side`` 0: not computed); true needs an oil law and an internal with the film's flows
  (``Capabilities.film_flow``), and then T_eff is a state: quasi-static at the inputs of
  Initialization Mode, lagged by the film's residence time over each step
  (``physics.thermal.film_temperature``), saved and restored with the FMU state; the force and
  its tangent are the internal's times mu_eff / mu (exact: F ~ mu at a fixed state).

Bundled into the Python FMU; nothing here imports pythonfmu.
"""

from __future__ import annotations

import math

from ..internals import registry
from ..physics.bore.geometry import FULL_BORE, MAX_LOBES, MAX_SUPPLY_KPA, Geometry
from ..physics.oil import DEFAULT_DENSITY, DEFAULT_HEAT_CAPACITY, DEFAULT_RANGE_C, KELVIN, Oil
from ..physics.bore.pads import MAX_PADS, MIN_PADS, PadGeometry

MAX_GROOVES = 8  # groove_1 .. groove_8: FMI parameters are scalars
OIL_LAWS = ("none", "walther", "vogel")
_VG46 = (46e-6, 40.0 + KELVIN, 6.8e-6, 100.0 + KELVIN)  # the Walther defaults: ISO VG 46 (physics/oil.py)
_SAE30 = (0.0141e-6 * 6894.757, 1360.0 / 1.8, KELVIN - 127.0 / 1.8)  # the Vogel defaults: SAE 30 (physics/oil.py)

P, IN, OUT = "parameter", "input", "output"
# rows as in variables.VARIABLES: name, type, causality, unit, default, description
GEOMETRY_ROWS = (
    ("groove_count", "Integer", P, None, 0, f"number of axial grooves (0 .. {MAX_GROOVES}); their centres are "
     "groove_1 .. groove_<count>"),
    *((f"groove_{k}", "Real", P, "rad", 0.0, f"centre of axial groove {k} (used when groove_count >= {k}), in the "
       "film's theta: 0 top, pi/2 and 3 pi/2 the horizontal split, increasing with the rotation")
      for k in range(1, MAX_GROOVES + 1)),
    ("groove_width", "Real", P, "rad", math.radians(20.0), "width of every axial groove (> 0 and < pi)"),
    ("supply_pressure", "Real", P, "Pa", 0.0, "oil pressure in the grooves above ambient: the axial grooves' or the "
     "circumferential groove's (> 0 needs groove_count >= 1 or circumferential_groove > 0)"),
    ("partial_arc", "Boolean", P, None, False, "the film only from arc_start to arc_end (increasing theta), "
     "ambient outside"),
    ("arc_start", "Real", P, "rad", 0.0, "start of the partial arc (with partial_arc)"),
    ("arc_end", "Real", P, "rad", math.pi, "end of the partial arc (with partial_arc; end - start in (0, 2 pi))"),
    ("lobes", "Integer", P, None, 1, f"number of lobes of the bore (1: circular; up to {MAX_LOBES})"),
    ("preload", "Real", P, "1", 0.0, "preload m = 1 - C_bearing / C_pad, 0 <= m < 1 (> 0 needs lobes >= 2); CR is "
     "C_bearing"),
    ("lobe_offset", "Real", P, "1", 0.5, "where a lobe's clearance is smallest, as a fraction of the lobe from its "
     "leading edge (0.5 symmetric, 1.0 offset halves)"),
    ("lobe_angle", "Real", P, "rad", 0.0, "theta of the middle of the first lobe"),
)
OIL_ROWS = (
    ("thermal", "Boolean", P, None, False, "thermal model on: the input T_supply is connected, the film runs at the "
     "viscosity of its effective temperature (needs oil_law and an internal with the film's flows: reynolds, a map "
     "with flow tables, a Taylor surrogate with its film fit); false: isoviscous at mu, T_supply ignored"),
    ("oil_law", "String", P, None, "none", "the oil's viscosity law: none | walther | vogel (or oil_law_enum)"),
    ("oil_nu_1", "Real", P, "m2/s", _VG46[0], "walther: kinematic viscosity at oil_T_1"),
    ("oil_T_1", "Real", P, "K", _VG46[1], "walther: temperature of oil_nu_1"),
    ("oil_nu_2", "Real", P, "m2/s", _VG46[2], "walther: kinematic viscosity at oil_T_2"),
    ("oil_T_2", "Real", P, "K", _VG46[3], "walther: temperature of oil_nu_2"),
    ("oil_vogel_a", "Real", P, "Pa.s", _SAE30[0], "vogel: a of mu = a exp(b / (T - c))"),
    ("oil_vogel_b", "Real", P, "K", _SAE30[1], "vogel: b"),
    ("oil_vogel_c", "Real", P, "K", _SAE30[2], "vogel: c (T must stay above it)"),
    ("oil_T_min", "Real", P, "K", DEFAULT_RANGE_C[0] + KELVIN, "lowest temperature the law may be used at"),
    ("oil_T_max", "Real", P, "K", DEFAULT_RANGE_C[1] + KELVIN, "highest temperature the law may be used at"),
    ("oil_density", "Real", P, "kg/m3", DEFAULT_DENSITY, "oil density (constant)"),
    ("oil_heat_capacity", "Real", P, "J/(kg.K)", DEFAULT_HEAT_CAPACITY, "oil specific heat capacity (constant)"),
    ("oil_rise_factor", "Real", P, "1", 0.5, "k in T_eff = T_supply + k dT (Shigley: 1/2)"),
)
THERMAL_ROWS = (
    ("T_supply", "Real", IN, "K", 40.0 + KELVIN, "oil supply temperature (used only with thermal = true: an FMU "
     "cannot see whether an input is connected)"),
    ("P_loss", "Real", OUT, "W", 0.0, "friction power of the film at T_eff (0 with thermal = false: not computed)"),
    ("Q_side", "Real", OUT, "m3/s", 0.0, "oil flow out of both ends of the film (0 with thermal = false: not "
     "computed)"),
    ("T_eff", "Real", OUT, "K", 40.0 + KELVIN, "effective film temperature: a state lagging the heat balance by the "
     "film's residence time (T_supply with thermal = false)"),
    ("mu_eff", "Real", OUT, "Pa.s", 0.05, "the viscosity the force is computed at: the oil's at T_eff (mu with "
     "thermal = false)"),
)
# a tilting-pad bore (``physics.bore.pads``; its preload is ``preload`` above): the pads' parameters and,
# per pad, its tilt and load after each step (0 for the pads a bore does not have; FMI variables are scalars)
PAD_ROWS = (
    ("pads", "Integer", P, None, 0, f"number of tilting pads (0: a fixed bore; {MIN_PADS} .. {MAX_PADS}); their "
     "pivots are pivot_1 .. pivot_<pads>, with the internal tilting_pad"),
    *((f"pivot_{k}", "Real", P, "rad", 0.0, f"pivot angle of tilting pad {k} (used when pads >= {k}), in the film's "
       "theta as groove_1 (0 top, increasing with the rotation)") for k in range(1, MAX_PADS + 1)),
    ("pad_arc", "Real", P, "rad", math.radians(60.0), "every tilting pad's arc (> 0; the pads may not overlap)"),
    ("pivot_offset", "Real", P, "1", 0.5, "the pivot's place on its pad as a fraction of the arc from the leading "
     "edge (0.5 centred; > 0 and < 1)"),
    ("pad_inertia", "Real", P, "kg.m2", 0.0, "each pad's moment of inertia about its pivot (0: massless pads, in "
     "moment equilibrium through their squeeze)"),
    *((f"pad_tilt_{k}", "Real", OUT, "rad", 0.0, f"tilt of pad {k} about its pivot at the end of the step (positive "
       f"about +x; 0 when pads < {k})") for k in range(1, MAX_PADS + 1)),
    *((f"pad_load_{k}", "Real", OUT, "N", 0.0, f"magnitude of pad {k}'s film force on the journal at the end of the "
       f"step (0 when pads < {k})") for k in range(1, MAX_PADS + 1)),
)
# the [oil] table's heat balance (``physics.thermal.heat_balance_rise``: P = rho c_p (Q - s Q_side) dT + h A (T_eff -
# T_ambient); after the rest in the FMU's variables: the value references stay)
OUTFLOW_SHARES = {0.5: "half", 0.0: "full"}  # s -> the bearing file's outflow_rise (``Oil.outflow_share``)
BALANCE_ROWS = (
    ("oil_outflow_share", "Real", P, "1", 0.5, "s in the heat the oil carries away, rho c_p (Q - s Q_side) dT: 0.5 the "
     "side flow leaves at half the rise (Raimondi & Boyd; the bearing file's [oil] outflow_rise = 'half'), 0 all the "
     "inflow at the full rise ('full'); no other value. With circumferential_groove > 0 the balance is the full rise "
     "whatever this says (all the lands' oil leaves by their ends)"),
    ("oil_ambient_loss", "Real", P, "W/K", 0.0, "h A: heat the bearing loses to the ambient per kelvin of T_eff above "
     "oil_T_ambient (the bearing file's [oil] ambient_W_K; 0: adiabatic, all the friction power into the oil)"),
    ("oil_T_ambient", "Real", P, "K", 0.0, "the ambient's temperature for oil_ambient_loss (the bearing file's [oil] "
     "ambient_C); 0: the supply temperature T_supply (a file without ambient_C)"),
)
# the circumferential (360 deg) feed groove at mid-length (``Geometry.circumferential_groove``; after the
# rest in the FMU's variables: the value references stay)
GROOVE_ROWS = (
    ("circumferential_groove", "Real", P, "m", 0.0, "width of a 360 deg feed groove at mid-length (0: none): the "
     "film is two lands of (L - width) / 2 fed along it at supply_pressure (the plain circular bore only: no axial "
     "grooves, partial arc, lobes or pads; < L); with the thermal model all the lands' oil leaves by their ends at "
     "the full rise"),
)
PAD_TILTS = tuple(f"pad_tilt_{k}" for k in range(1, MAX_PADS + 1))
PAD_LOADS = tuple(f"pad_load_{k}" for k in range(1, MAX_PADS + 1))
ROWS = GEOMETRY_ROWS + OIL_ROWS + THERMAL_ROWS
PARAMETER_NAMES = tuple(r[0] for r in GEOMETRY_ROWS + OIL_ROWS + PAD_ROWS + GROOVE_ROWS + BALANCE_ROWS if r[2] == P)
ROW_UNITS = {r[0]: r[3] for r in ROWS + BALANCE_ROWS}
# (min, max) of the Integer and Real parameters above, for the model description and the setters
BOUNDS = {"groove_count": (0, MAX_GROOVES), "lobes": (1, MAX_LOBES), "groove_width": (0.0, math.pi),
          "supply_pressure": (0.0, MAX_SUPPLY_KPA * 1e3), "preload": (0.0, 1.0), "lobe_offset": (0.0, 1.0),
          "oil_rise_factor": (0.0, 1.0), "pads": (0, MAX_PADS), "pad_arc": (0.0, 2.0 * math.pi / MIN_PADS),
          "pivot_offset": (0.0, 1.0), "pad_inertia": (0.0, None), "circumferential_groove": (0.0, None), "oil_density": (500.0, 2000.0), "oil_heat_capacity": (500.0, 5000.0),
          "oil_outflow_share": (0.0, 0.5),
          **{n: (0.0, None) for n in ("oil_nu_1", "oil_nu_2", "oil_vogel_a", "oil_vogel_b", "oil_vogel_c",
                                      "oil_T_1", "oil_T_2", "oil_T_min", "oil_T_max", "oil_ambient_loss",
                                      "oil_T_ambient")}}
_ANGLES = (tuple(f"groove_{k}" for k in range(1, MAX_GROOVES + 1)) + ("arc_start", "arc_end", "lobe_angle")
           + tuple(f"pivot_{k}" for k in range(1, MAX_PADS + 1)))


def check_value(name: str, value):
    """``value`` of parameter ``name`` (one of ``PARAMETER_NAMES``), or ValueError naming it and
    what is allowed; what depends on several is checked when the bearing is built."""
    if name in BOUNDS:
        lo, hi = BOUNDS[name]
        if not (math.isfinite(value) and lo <= value and (hi is None or value <= hi)):
            raise ValueError(f"{name} = {value!r} must be finite and in {lo:g} .. {'inf' if hi is None else f'{hi:g}'}")
        if name == "oil_outflow_share" and value not in OUTFLOW_SHARES:
            raise ValueError(f"oil_outflow_share = {value!r} must be 0.5 (the side flow leaves at half the rise: "
                             "outflow_rise 'half') or 0 (all the oil at the full rise: 'full')")
    elif name in _ANGLES and not math.isfinite(value):
        raise ValueError(f"{name} = {value!r} rad must be finite")
    return value


def geometry_of(v) -> Geometry:
    """The bore the parameters of ``v`` (an object with them as attributes) describe; ValueError
    naming the parameters when they do not fit together."""
    n = int(v.groove_count)
    if int(v.pads):
        return _pads_of(v)
    try:
        return Geometry(grooves=tuple(float(getattr(v, f"groove_{k}")) for k in range(1, n + 1)),
                        groove_width=float(v.groove_width), supply_pressure=float(v.supply_pressure),
                        arc=(float(v.arc_start), float(v.arc_end)) if v.partial_arc else None,
                        lobes=int(v.lobes), preload=float(v.preload), lobe_offset=float(v.lobe_offset),
                        lobe_angle=float(v.lobe_angle), circumferential_groove=float(v.circumferential_groove))
    except ValueError as exc:
        raise ValueError(f"the geometry parameters do not fit together (in the bearing file's words, degrees and "
                         f"kPa): {str(exc).removeprefix('Geometry: ')}") from None


def _pads_of(v) -> Geometry:
    """The tilting-pad bore of the parameters ``pads`` > 0 (``geometry_of``)."""
    n = int(v.pads)
    groove = float(getattr(v, "circumferential_groove", 0.0))  # the FMU has it; a bore's parameters without it: none
    fixed = ([f"groove_count = {int(v.groove_count)}"] if int(v.groove_count) else []) + (
        ["partial_arc = true"] if v.partial_arc else []) + ([f"lobes = {int(v.lobes)}"] if int(v.lobes) > 1 else []) + (
        [f"circumferential_groove = {groove:g}"] if groove else [])
    if fixed:
        raise ValueError(f"pads = {n}: a tilting-pad bore has no {', '.join(fixed)} (the pads are its arcs): set them "
                         "back to the full bore's (groove_count = 0, partial_arc = false, lobes = 1, "
                         "circumferential_groove = 0)")
    if n < MIN_PADS:
        raise ValueError(f"pads = {n} must be 0 (a fixed bore) or in {MIN_PADS} .. {MAX_PADS}")
    try:
        pads = PadGeometry(pivots=tuple(float(getattr(v, f"pivot_{k}")) for k in range(1, n + 1)),
                           arc=float(v.pad_arc), offset=float(v.pivot_offset), preload=float(v.preload),
                           inertia=float(v.pad_inertia))
    except ValueError as exc:  # in the bearing file's words: name the parameters
        words = str(exc).replace("pad_arc_deg", "pad_arc (in deg)").replace("pivots_deg", "pivot_1 .. pivot_N (in "
                                                                            "deg)").replace("pad_inertia_kg_m2",
                                                                                            "pad_inertia")
        raise ValueError(f"the tilting-pad parameters do not fit together: {words}") from None
    return Geometry(pads=pads)


def check_geometry(geometry: Geometry, spec) -> None:
    """ValueError naming the parameters that make ``geometry`` other than the full bore, when the
    internal ``spec`` (a registry ``InternalSpec``) computes the full bore only (its data were made
    for it)."""
    if spec.can.any_geometry or geometry.is_full_bore:
        return
    set_away = [f"groove_count = {len(geometry.grooves)}"] if geometry.grooves else []
    set_away += ["partial_arc = true"] if geometry.arc is not None else []
    set_away += [f"lobes = {geometry.lobes}"] if geometry.lobes > 1 else []
    c = geometry.circumferential_groove
    set_away += [f"circumferential_groove = {c:g}"] if c else []
    raise ValueError(f"internal = {spec.name!r} computes the full 360 deg bore only ({spec.can.geometry_why}); "
                     f"the geometry parameters describe another bore ({geometry.describe()}): set "
                     f"{', '.join(set_away)} back to the full bore's (groove_count = 0, partial_arc = false, lobes = 1, "
                     "circumferential_groove = 0) or choose internal = 'reynolds'")


def oil_of(v, law: str, grooved: bool = False) -> Oil | None:
    """The oil the parameters of ``v`` describe (``law`` the checked oil_law), None for none;
    ValueError naming the parameters. The heat balance: ``oil_outflow_share``, ``oil_ambient_loss``,
    ``oil_T_ambient`` (0: None, the supply temperature); ``grooved`` (a circumferential groove): all the
    oil leaves by the lands' ends at the full rise (``params.groove_problem``: outflow_rise "full")."""
    if law == "none":
        return None
    share = float(v.oil_outflow_share)
    if share not in OUTFLOW_SHARES:
        check_value("oil_outflow_share", share)  # its error names the parameter and the two values
    T_amb = float(v.oil_T_ambient)
    kw = dict(T_min=float(v.oil_T_min), T_max=float(v.oil_T_max), density=float(v.oil_density),
              heat_capacity=float(v.oil_heat_capacity), rise_factor=float(v.oil_rise_factor),
              outflow_rise="full" if grooved else OUTFLOW_SHARES[share], ambient_W_K=float(v.oil_ambient_loss),
              T_ambient=T_amb if T_amb != 0.0 else None, name="oil of the FMU parameters")
    kw["T_supply"] = min(max(40.0 + KELVIN, kw["T_min"]), kw["T_max"])  # not used: T_supply is an input
    try:
        if law == "walther":
            return Oil.walther(float(v.oil_nu_1) * 1e6, float(v.oil_T_1), float(v.oil_nu_2) * 1e6, float(v.oil_T_2),
                               **kw)
        return Oil.vogel(float(v.oil_vogel_a), float(v.oil_vogel_b), float(v.oil_vogel_c), **kw)
    except ValueError as exc:
        raise ValueError(f"the oil parameters (oil_law = {law!r}, oil_...) do not fit together: "
                         f"{str(exc).removeprefix('Oil oil of the FMU parameters: ')}") from None


def port_defaults(params, pads: bool = False) -> dict:
    """The FMU parameter values of a bearing's bore and oil (``BearingParams``: ``geometry``,
    ``oil``): what ``bearing-fmu build --bearing FILE`` makes the defaults. ``pads``: the FMU carries
    tilting pads (the Python FMU: their parameters, ``PAD_ROWS``); False refuses a tilting-pad bore by
    name (the native FMU does not carry the pads yet). A circumferential groove is its width
    ``circumferential_groove`` [m] with ``supply_pressure``."""
    g = params.geometry if params.geometry is not None else FULL_BORE
    if g.pads is not None and not pads:
        raise ValueError(f"the native bearing FMU does not carry tilting pads yet ({g.describe()}): use the Python "
                         "FMU (bearing-fmu build without --native; a scene's fmu_kind = 'python') or via = 'direct'")
    if g.pads is not None:
        return {**_pad_defaults(g.pads), **_oil_defaults(params)}
    out = {"groove_count": len(g.grooves), "groove_width": g.groove_width, "supply_pressure": g.supply_pressure,
           "partial_arc": g.arc is not None, "lobes": g.lobes, "preload": g.preload, "lobe_offset": g.lobe_offset,
           "lobe_angle": g.lobe_angle, "circumferential_groove": g.circumferential_groove}
    if len(g.grooves) > MAX_GROOVES:
        raise ValueError(f"the bearing FMU takes at most {MAX_GROOVES} grooves (groove_1 .. groove_{MAX_GROOVES}), "
                         f"this bore has {len(g.grooves)}")
    for k, angle in enumerate(g.grooves, start=1):
        out[f"groove_{k}"] = angle
    if g.arc is not None:
        out["arc_start"], out["arc_end"] = g.arc
    return {**out, **_oil_defaults(params)}


def _pad_defaults(pads: PadGeometry) -> dict:
    """The parameters of a tilting-pad bore (the fixed bores' at their defaults: the full bore's)."""
    if pads.pivot_stiffness is not None:
        raise ValueError(f"pivot_stiffness_N_m = {pads.pivot_stiffness:g}: a flexible pivot is not carried by the "
                         "bearing FMUs (the tilting_pad internal models it in run, stability and demo); leave the key "
                         "out (rigid pivots)")
    out = {"pads": pads.n, "pad_arc": pads.arc, "pivot_offset": pads.offset, "preload": pads.preload,
           "pad_inertia": pads.inertia}
    out.update((f"pivot_{k}", p) for k, p in enumerate(pads.pivots, start=1))
    return out


def _oil_defaults(params) -> dict:
    """The oil parameters of a bearing's [oil] ({} without one)."""
    out = {}
    oil = params.oil
    if oil is not None and oil.cavitated_shear != "full":
        raise ValueError(f"[oil] cavitated_shear = {oil.cavitated_shear!r}: the bearing FMUs shear the cavitated film "
                         "as a full film only; demo, stability and run with via = 'direct' take the others")
    if oil is not None:  # every heat balance (BALANCE_ROWS); a grooved bearing's file says 'full' (groove_problem)
        out.update(oil_law=oil.law, oil_T_min=oil.T_min, oil_T_max=oil.T_max, oil_density=oil.density,
                   oil_heat_capacity=oil.heat_capacity, oil_rise_factor=oil.rise_factor,
                   oil_outflow_share=oil.outflow_share, oil_ambient_loss=oil.ambient_W_K,
                   oil_T_ambient=0.0 if oil.T_ambient is None else oil.T_ambient)
        if oil.law == "walther":  # two points of the law: 40 and 100 C where the range holds them, else its ends
            t1, t2 = ((40.0 + KELVIN, 100.0 + KELVIN) if oil.T_min <= 40.0 + KELVIN and 100.0 + KELVIN <= oil.T_max
                      else (oil.T_min, oil.T_max))
            out.update(oil_nu_1=oil.nu(t1), oil_T_1=t1, oil_nu_2=oil.nu(t2), oil_T_2=t2)
        else:
            out.update(oil_vogel_a=oil.coefficients[0], oil_vogel_b=oil.coefficients[1],
                       oil_vogel_c=oil.coefficients[2])
    return out


START_NAMES = ("T_supply", "T_eff", "mu_eff")  # the thermal ports' starts a bearing file gives


def supply_starts(params) -> dict:
    """The thermal ports' start values of a bearing with an oil law (``BearingParams.oil``): T_supply
    and T_eff at the file's supply temperature [K], mu_eff the oil's viscosity there [Pa s] (the
    bearing's mu, which a file with [oil] takes from the law); {} without one (the rows' defaults)."""
    oil = params.oil
    if oil is None:
        return {}
    return {"T_supply": float(oil.T_supply), "T_eff": float(oil.T_supply), "mu_eff": float(oil.mu(oil.T_supply))}


def check_pad_thermal(thermal: bool, geometry: Geometry) -> None:
    """ValueError naming ``thermal`` and ``pad_inertia`` for tilting pads with inertia at a film
    temperature: their force at mu_eff is not the force at mu times mu_eff / mu (the pads' inertia
    does not scale), which is how the FMU applies the temperature; massless pads' is (their tilts
    do not depend on mu)."""
    pads = geometry.pads
    if thermal and pads is not None and pads.inertia > 0.0:
        raise ValueError(f"thermal = true with pad_inertia = {pads.inertia:g} kg.m2: the pads' motion at the film's "
                         "temperature is not modelled yet; massless pads (pad_inertia = 0) or thermal = false")


def check_thermal(thermal: bool, oil: Oil | None, spec, internal=None) -> None:
    """ValueError naming ``thermal`` when the thermal model cannot run: no oil law, or an internal
    without the film's flows (``Capabilities.film_flow``; with the built ``internal``, its own
    answer: a map file may lack the flow tables)."""
    if not thermal:
        return
    if oil is None:
        raise ValueError("thermal = true needs the oil's viscosity law: set oil_law = 'walther' or 'vogel' with its "
                         "parameters (or build the FMU with --bearing FILE whose [oil] gives them)")
    why = registry.film_flow_of(spec, internal)
    if why:
        raise ValueError(f"thermal = true needs the film's friction and flows, which internal = {spec.name!r} does not "
                         f"have ({why}); use internal = 'reynolds' or thermal = false")


def thermal_state(internal, params, oil: Oil, T_supply: float, state, T_old: float | None, dt: float):
    """(factor mu_eff / mu, T_eff [K], mu_eff [Pa s], P_loss [W], Q_side [m^3/s]) at the journal
    ``state`` (y, z, vy, vz, omega): quasi-static when ``T_old`` is None, else lagged over ``dt``
    [s] (``physics.thermal.film_temperature``). ValueError (a ThermalError) when the oil's range
    is left; the caller turns it into a refused state."""
    from ..physics.thermal import film_temperature

    report = internal.film_report(*state)
    try:
        T, mu_eff, _tau = film_temperature(params, report, oil, T_supply, T_old, dt)
    except ValueError as exc:  # in the FMU the law's range is two parameters, not the file's key
        raise ValueError(str(exc).replace("Oil oil of the FMU parameters: ", "").replace(
            "(the bearing file's [oil] range_C)", "(the parameters oil_T_min .. oil_T_max)")) from None
    factor = mu_eff / params.mu
    return factor, T, mu_eff, report.friction_power_W * factor, report.side_flow_m3_s
