"""The variables of the bearing FMU: the one table of its interface (``VARIABLES``).

The pythonfmu slave registers them (``slave.BearingFMU``); ``build.py`` writes units and
dependencies from the table, and the native FMU's code generation takes its variables from it
(``native/codegen.py``), so both FMUs declare the same interface. Nothing here imports pythonfmu.
"""

from __future__ import annotations

from ..internals import registry
from ..physics.params import PAPER_BEARING
from . import ports

# VARIABLES rows: name, type, causality, unit, default, description; the internals' parameters
# come from their registry options
INPUT, OUTPUT, PARAMETER = "input", "output", "parameter"  # the causalities
FMI_TYPE = {float: "Real", int: "Integer", bool: "Boolean", str: "String"}
DEFAULT_INTERNAL = "reynolds"
# Enumeration parameters: each String parameter with choices again as an FMI 2.0 enumeration (an
# Integer whose values are item k + 1 of the choices; build.py declares its TypeDefinition), for
# masters that show one as a drop-down. name -> (its String parameter, the items). Set either; a
# value away from its start wins, and if both are set away from their starts they must agree
# (BearingFMU._choices). New internals and choices go at the end: the numbers stay.
ENUMERATIONS = {"internal_enum": ("internal", registry.names()),
                **{f"{o.name}_enum": (o.name, o.choices) for o in registry.all_options() if o.choices},
                "oil_law_enum": ("oil_law", ports.OIL_LAWS)}
STRING_DEFAULTS = {"internal": DEFAULT_INTERNAL, **{o.name: o.default for o in registry.all_options()},
                   "oil_law": ports.OIL_LAWS[0]}


def enum_value(name: str, item: str) -> int:
    """The value of ``item`` in enumeration parameter ``name`` (1 for the first choice)."""
    return ENUMERATIONS[name][1].index(item) + 1


VARIABLES = (
    # inputs: the journal state at the end of the step
    ("y", "Real", INPUT, "m", 0.0, "journal centre displacement from the bearing centre, horizontal"),
    ("z", "Real", INPUT, "m", 0.0, "journal centre displacement from the bearing centre, vertical (up)"),
    ("vy", "Real", INPUT, "m/s", 0.0, "journal centre velocity, horizontal"),
    ("vz", "Real", INPUT, "m/s", 0.0, "journal centre velocity, vertical"),
    ("omega", "Real", INPUT, "rad/s", 0.0, "shaft speed, right-handed about the shaft axis x"),
    # outputs
    ("Fy", "Real", OUTPUT, "N", 0.0, "film force on the journal, horizontal"),
    ("Fz", "Real", OUTPUT, "N", 0.0, "film force on the journal, vertical"),
    ("eccentricity", "Real", OUTPUT, "1", 0.0, "eccentricity ratio sqrt(y^2 + z^2) / CR"),
    ("h_min", "Real", OUTPUT, "m", 0.0, "minimum film thickness CR - sqrt(y^2 + z^2) (negative beyond the wall)"),
    ("out_of_domain", "Boolean", OUTPUT, None, False,
     "true when the force is not the model's answer for this state: taylor outside the surrogate's fitted "
     "domain, linear at or past the clearance circle (it evaluates there, without physical meaning)"),
    ("Kyy", "Real", OUTPUT, "N/m", 0.0, "film stiffness -dFy/dy (Lund sign; 0 if compute_tangent is false)"),
    ("Kyz", "Real", OUTPUT, "N/m", 0.0, "film stiffness -dFy/dz (Lund sign; 0 if compute_tangent is false)"),
    ("Kzy", "Real", OUTPUT, "N/m", 0.0, "film stiffness -dFz/dy (Lund sign; 0 if compute_tangent is false)"),
    ("Kzz", "Real", OUTPUT, "N/m", 0.0, "film stiffness -dFz/dz (Lund sign; 0 if compute_tangent is false)"),
    ("Cyy", "Real", OUTPUT, "N.s/m", 0.0, "film damping -dFy/dvy (Lund sign; 0 if compute_tangent is false)"),
    ("Cyz", "Real", OUTPUT, "N.s/m", 0.0, "film damping -dFy/dvz (Lund sign; 0 if compute_tangent is false)"),
    ("Czy", "Real", OUTPUT, "N.s/m", 0.0, "film damping -dFz/dvy (Lund sign; 0 if compute_tangent is false)"),
    ("Czz", "Real", OUTPUT, "N.s/m", 0.0, "film damping -dFz/dvz (Lund sign; 0 if compute_tangent is false)"),
    # parameters: the bearing (paper Table 2)
    ("D", "Real", PARAMETER, "m", PAPER_BEARING.D, "bearing (journal) diameter"),
    ("L", "Real", PARAMETER, "m", PAPER_BEARING.L, "bearing length"),
    ("CR", "Real", PARAMETER, "m", PAPER_BEARING.CR, "radial clearance"),
    ("mu", "Real", PARAMETER, "Pa.s", PAPER_BEARING.mu, "dynamic viscosity of the oil"),
    # parameters: which internal, and whether the outputs K.., C.. are computed
    ("internal", "String", PARAMETER, None, DEFAULT_INTERNAL,
     "which internal computes the force: " + " | ".join(registry.names()) + " (or internal_enum)"),
    ("compute_tangent", "Boolean", PARAMETER, None, True,
     "compute the outputs K.., C.. from the internal's Jacobian at every step"),
    # parameters: every registered internal's options
    *((o.name, FMI_TYPE[o.type], PARAMETER, o.unit, o.default, o.help if o.type is str else f"{o.help} ({o.allowed()})")
      for o in registry.all_options()),
    # parameters: the choices again as enumerations (after the rest: the value references stay)
    *((name, "Integer", PARAMETER, None, enum_value(name, STRING_DEFAULTS[string]),
       f"{string} as an enumeration ({', '.join(f'{k + 1} = {c}' for k, c in enumerate(items))}): the same choice "
       f"as the String parameter {string}; set either (set both, they must agree)")
      for name, (string, items) in ENUMERATIONS.items()),
    # the bore, the oil and the thermal ports (ports.py; after the rest: the value references stay)
    *ports.ROWS,
    # the film's peak pressure (internals with a pressure field, Capabilities.film_field; after the rest)
    ("peak_pressure", "Real", OUTPUT, "Pa", 0.0, "largest film pressure, refined between cells (for the bearing "
     "metal's limit; internals with a pressure field: reynolds; 0 for the others)"),
    ("peak_pressure_angle", "Real", OUTPUT, "rad", 0.0, "theta of the peak pressure (0 top, increasing with the "
     "rotation; 0 for internals without a pressure field)"),
    # a tilting-pad bore's parameters and the pads' outputs (ports.PAD_ROWS; after the rest: the value references stay)
    *ports.PAD_ROWS,
    # the circumferential feed groove's width (ports.GROOVE_ROWS; after the rest: the value references stay)
    *ports.GROOVE_ROWS,
    # the oil's heat balance: outflow share, ambient loss (ports.BALANCE_ROWS; after the rest: the value references stay)
    *ports.BALANCE_ROWS,
)

INPUTS = tuple(v[0] for v in VARIABLES if v[2] == INPUT)
# the internals whose outputs follow the inputs and parameters alone when thermal is false
# (``Capabilities.memoryless``); the FMUs declare them (meta.memoryless_annotation)
MEMORYLESS = registry.having(memoryless=True)
# the internals with states of their own over a step (``Capabilities.step_states``: tilting pads), saved
# with the FMU state; the FMUs declare them too (meta.memoryless_annotation's stepStates)
STEPPED = registry.having(step_states=True)
OUTPUTS = tuple(v[0] for v in VARIABLES if v[2] == OUTPUT)
PARAMETERS = tuple(v[0] for v in VARIABLES if v[2] == PARAMETER)
