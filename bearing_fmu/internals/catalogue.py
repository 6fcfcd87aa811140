"""The built-in internals: one ``InternalSpec`` each (reynolds, linear, taylor, map), registered
in this order (the order of listings, the FMU's parameters and the command lines' choices).

A spec names its module as a string ("<module>:<Class>.from_options", relative to bearing_fmu),
imported only when the internal is built, so this table costs no import of any internal. The
table of internals and the checklist for adding one: ``registry``'s docstring.
"""

from __future__ import annotations

import math

from .base import Capabilities, InternalSpec, Option, register

_GRID_DEFAULT = {0: "the solver's default"}
# The paper rotor's bearing load (half its weight) and speed, where the linear internal is
# made when nothing else says: Linear.at_load(Reynolds(paper bearing), (0, -16.7 N), 2 pi 22 rad/s).
DEFAULT_LOAD_Z = -16.7
DEFAULT_OMEGA_LIN = 2.0 * math.pi * 22.0
DOMAIN_ACTIONS = ("warn", "fallback", "discard")
DEFAULT_DOMAIN_LIMIT = 0.5  # relative excess over the fitted domain's bounds beyond which a state is refused


def _lund(name: str, unit: str, what: str) -> Option:
    return Option(f"lin_{name}", float, 0.0, f"linear, from coefficients: {what}", unit)


register(InternalSpec(
    "reynolds", "physics.solver.reynolds:Reynolds.from_options", "finite-volume Reynolds solver, Swift-Stieber cavitation (the truth)",
    options=(
        Option("n_theta", int, 0, "reynolds: circumferential grid cells", minimum=8, maximum=100_000,
               special=_GRID_DEFAULT),
        Option("n_x", int, 0, "reynolds: axial grid cells", minimum=2, maximum=100_000, even=True,
               special=_GRID_DEFAULT),
        Option("cavitation", str, "reynolds", "reynolds: cavitation model: reynolds (Swift-Stieber) | gumbel "
               "(half-Sommerfeld)", choices=("reynolds", "gumbel")),
    ),
    can=Capabilities(
        any_state=True, truth=True, film_flow=True, native=True, film_field=True,
        compiled=True,  # internals.reynolds.force
        validity="The finite-volume Reynolds solver evaluates any journal state inside the clearance circle at any "
                 "speed, load and velocity; it is the reference the other internals are measured against. Its "
                 "accuracy is set by the grid n_theta x n_x (0: the default 128 x 16, docs/reynolds.md). The journal "
                 "at or beyond the wall is refused (fmi2Discard)."),
    case="internals.cases:reynolds_case",
    kernels=("physics.solver.reynolds_kernels", "physics.solver.geometry_kernels"),
))

register(InternalSpec(
    "linear", "internals.linear.linear:Linear.from_options", "8 Lund coefficients about a static equilibrium (order-1 model)",
    options=(
        Option("linear_from", str, "load", "linear: 'load' = linearise Reynolds at its equilibrium under "
               "(load_y, load_z) at omega_lin; 'map' = the same from the force map (the map option's file; no "
               "Reynolds import or compile); 'coefficients' = use lin_* as given", choices=("load", "map", "coefficients")),
        Option("load_y", float, 0.0, "linear, from load: static external load on the journal, horizontal", "N",
               context=lambda c: None if c.load is None else float(c.load[0])),
        Option("load_z", float, DEFAULT_LOAD_Z, "linear, from load: static external load on the journal, vertical "
               "(weight is negative)", "N", context=lambda c: None if c.load is None else float(c.load[1])),
        Option("omega_lin", float, DEFAULT_OMEGA_LIN, "linear: shaft speed of the linear model (the input omega "
               "must equal it)", "rad/s", context=lambda c: c.omega),
        _lund("y0", "m", "expansion point y0"),
        _lund("z0", "m", "expansion point z0"),
        _lund("Fy0", "N", "film force Fy at the expansion point"),
        _lund("Fz0", "N", "film force Fz at the expansion point"),
        *(_lund(f"K{ij}", "N/m", f"Lund stiffness K{ij}") for ij in ("yy", "yz", "zy", "zz")),
        *(_lund(f"C{ij}", "N.s/m", f"Lund damping C{ij}") for ij in ("yy", "yz", "zy", "zz")),
    ),
    uses=("reynolds", "map"),
    can=Capabilities(
        native=True, compiled=True, memoryless=True,
        film_flow_why="a linear model holds the force about one point, not the film's flows",
        validity="The linear model holds near its expansion point at the speed omega_lin (any other omega is "
                 "refused); it evaluates beyond the clearance circle, where it means nothing physically (h_min < 0).{made}"),
    case="internals.cases:linear_case",
))

register(InternalSpec(
    "taylor", "internals.taylor.guard:DomainGuard.from_options", "fitted Taylor surrogate (the paper's method) behind its domain guard",
    options=(
        Option("surrogate", str, "", "taylor: the surrogate JSON file, fitted by `bearing-fmu fit` or `rotor-host "
               "fit` (in the FMU: a file name in its resources folder surrogates/)", file=True, required=True,
               file_format="bearing-fmu-taylor-surrogate"),
        Option("domain_action", str, "warn", "taylor, state outside the fitted domain: warn (surrogate value, "
               "warned once) | fallback (Reynolds value for that call) | discard (refuse the step)",
               choices=DOMAIN_ACTIONS),
        Option("domain_limit", float, DEFAULT_DOMAIN_LIMIT, "taylor: refuse states more than this far outside the "
               "fitted domain (relative excess over its bounds, or the distance to the nearest training state "
               "beyond the guard radius over the domain's size)", "1", minimum=0.0, exclusive_minimum=True),
    ),
    uses=("reynolds",),
    can=Capabilities(
        fixed_speed=True, fitted_domain=True, native=True, compiled=True, film_flow=True,  # per file: film_flow_of
        film_flow_why="a surrogate file of format version 1 fits the force only: fit it again for the film's flows",
        validity="The surrogate answers for the speed it was fitted at (any other omega is refused) and inside its "
                 "fitted domain of journal states; outside it the FMU {actions}, and beyond domain_limit it always "
                 "refuses. The journal at or beyond the wall is refused (fmi2Discard)."),
    case="internals.cases:taylor_case",
    kernels=("surrogates.taylor_kernels",),
))

register(InternalSpec(
    "map", "internals.map.mapfile:from_options", "force map: the Reynolds force reduced exactly to a 2-D table of "
    "eccentricity and one angle (full bore), 3-D with the attitude for grooves and partial arcs (any speed, load and "
    "velocity; docs/forcemap.md)",
    options=(
        Option("map", str, "", "map: the force map JSON file, built by `bearing-fmu map` for the bearing's L/D "
               "(in the FMU: a file name in its resources folder surrogates/)", file=True, required=True,
               file_format="bearing-fmu-force-map"),
    ),
    can=Capabilities(
        any_state=True, native=True, compiled=True, memoryless=True,  # the map file records its bore; the internal refuses another one
        film_flow=True,  # per file (film_flow_of): a map with its flow tables (version 3 full bore, 4 grooved)
        film_flow_why="a map file without flow tables (version 1 or 2, built before them) tabulates the force only: "
                      "rebuild it with `bearing-fmu map`",
        validity="The force map holds the Reynolds force for every speed, load and velocity of bearings with its "
                 "L/D; states beyond its last eccentricity (eps_max) are refused (fmi2Discard)."),
    case="internals.cases:map_case",
    kernels=("internals.map.kernels",),
))

register(InternalSpec(
    "tilting_pad", "internals.tilting_pad.tilting_pad:TiltingPad.from_options", "tilting-pad journal bearing: every "
    "pad the partial-arc Reynolds solver at its tilt, massless pads in moment equilibrium (docs/geometry.md)",
    options=(
        Option("pad_map", str, "", "tilting pads: every pad from this partial-arc force map of the pads' arc, built "
               "by `bearing-fmu map --bearing FILE` (in the FMU: a file name in its resources folder surrogates/) "
               "instead of the Reynolds solver; empty: Reynolds",
               file=True, file_format="bearing-fmu-force-map"),
    ),
    uses=("reynolds",),
    can=Capabilities(
        pads=True, compare=False, any_state=True, whirl_reduced=True, film_flow=True, step_states=True, native=True,
        validity="The tilting-pad internal evaluates any journal state that leaves every pad's film open at any "
                 "speed, the pads massless and quasi-static (each in moment equilibrium, its own rate 0); the "
                 "journal may pass C_bearing between pads. In a transient with the host's step hooks (in the FMU: over "
                 "each doStep) the pads' tilts (and rates, with pad inertia) are states carried from step to step, "
                 "in moment equilibrium at the inputs of Initialization Mode; rotor-host stability puts the pads' "
                 "coordinates into its eigenproblem. A journal state that closes a pad's film is refused "
                 "(fmi2Discard)."),
    case="internals.cases:tilting_pad_case",
    kernels=("physics.solver.reynolds_kernels", "physics.solver.geometry_kernels"),
))
