"""What every bearing internal is, and how one is described and registered.

An internal computes the film force on the journal from its state. Every internal follows the
``Internal`` protocol (``force``; ``force_and_jacobian`` where it has analytic derivatives) and
refuses a state it cannot evaluate with ``BearingStateError`` (the state checks below), so the
statics, the FMU slave and the host treat them alike. An ``InternalSpec`` describes one: its
factory, its ``Option``s (type, default, unit, allowed range), its ``Capabilities``, its contract
case and compiled kernels; ``register`` adds it to ``REGISTRY``, ``get`` and ``having`` find it.

This module holds no internal: the built-in ones are registered in ``catalogue``, and
``registry`` is the module callers import (its docstring has the table of internals and the
checklist for adding one).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Protocol, runtime_checkable

from ..physics.params import BearingParams


class BearingStateError(ValueError):
    """A journal state an internal cannot evaluate (non-finite input, journal at the wall)."""


@runtime_checkable
class Internal(Protocol):
    params: BearingParams

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] on the journal at displacement (y, z) [m],
        velocity (vy, vz) [m/s] and shaft speed omega [rad/s]."""
        ...


@runtime_checkable
class DifferentiableInternal(Internal, Protocol):
    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """Return (F, dF_dq, dF_dv): F = (Fy, Fz) [N] as an array of shape (2,), and the raw
        derivatives dF_dq[i, j] = dF_i/dq_j [N/m] with q = (y, z) and dF_dv[i, j] = dF_i/dv_j
        [N s/m] with v = (vy, vz), each of shape (2, 2). Lund's coefficients are their negatives."""
        ...


# ----------------------------------------------------------------------------- state checks

STATE_NAMES = ("y", "z", "vy", "vz", "omega")


def check_finite(y: float, z: float, vy: float, vz: float, omega: float) -> None:
    """Raise BearingStateError naming the first non-finite input."""
    for name, value in zip(STATE_NAMES, (y, z, vy, vz, omega)):
        if not math.isfinite(value):
            raise BearingStateError(f"bearing input {name} = {value!r} is not finite")


STATE_UNITS = ("m", "m", "m/s", "m/s", "rad/s")


def overflow_error(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float,
                   what: str = "force") -> BearingStateError:
    """The error for finite inputs whose film ``what`` is beyond the float range (1e308 m/s):
    no finite value is the model's answer, so the state is refused rather than returned as inf
    or NaN. It names the input that drives it, the largest as a rate of the film: positions in
    CR, velocities as 2 v / CR and omega (the terms of the Reynolds source, all in 1/s)."""
    values = (y, z, vy, vz, omega)
    CR = params.CR
    sizes = (abs(y) / CR, abs(z) / CR, 2.0 * abs(vy) / CR, 2.0 * abs(vz) / CR, abs(omega))
    i = max(range(5), key=sizes.__getitem__)
    return BearingStateError(
        f"bearing input {STATE_NAMES[i]} = {values[i]!r} {STATE_UNITS[i]} is too large: it puts the film {what} "
        f"beyond the floating-point range (y = {y:.4g} m, z = {z:.4g} m, vy = {vy:.4g} m/s, vz = {vz:.4g} m/s, "
        f"omega = {omega:.4g} rad/s)")


def wall_error(params: BearingParams, y: float, z: float, why: str = "") -> BearingStateError:
    """The error for a journal at or beyond the wall (eccentricity ratio >= 1; for a bore that is
    not the full circle, the film closure ``Geometry.closure`` >= 1)."""
    eps = math.hypot(y, z) / params.CR
    geo = params.geometry
    if not geo.is_full_bore:
        return BearingStateError(
            f"film closure {geo.closure(y, z, params.CR):.4g} >= 1: the journal (y = {y:.4g} m, z = {z:.4g} m, "
            f"eccentricity ratio {eps:.4g}) is at or beyond the bore ({geo.describe()}; CR = {params.CR:.4g} m){why}")
    return BearingStateError(
        f"eccentricity ratio {eps:.4g} >= 1: the journal (y = {y:.4g} m, z = {z:.4g} m) "
        f"is at or beyond the bearing wall (CR = {params.CR:.4g} m){why}"
    )


def check_state(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float) -> float:
    """``check_finite``, then refuse a journal at or beyond the wall. Returns the eccentricity ratio
    (for a bore that is not the full circle, the film closure: its wall is its own)."""
    check_finite(y, z, vy, vz, omega)
    eps = params.geometry.closure(y, z, params.CR)
    if eps >= 1.0:
        raise wall_error(params, y, z)
    return eps


def file_format(path) -> str:
    """The "format" value of a JSON data file (surrogate, force map), or "" if it has none;
    ValueError naming the file (and line, column) when it is not JSON."""
    import json

    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: is not valid JSON (truncated or damaged?): line {exc.lineno}, "
                         f"column {exc.colno}: {exc.msg}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot be read as a JSON data file ({exc})") from None
    return str(data.get("format", "")) if isinstance(data, dict) else ""


def option_for_file(path) -> "Option":
    """The file option whose files look like ``path`` (by the JSON "format" key); ValueError
    naming the file and the formats known when none does."""
    fmt = file_format(path)
    opts = [o for o in all_options() if o.file and o.file_format]
    for o in opts:
        if o.file_format == fmt:
            return o
    raise ValueError(f"{path}: not a file any internal reads (its JSON 'format' is {fmt!r}; known: "
                     f"{', '.join(f'{o.file_format} ({o.name})' for o in opts)})")


# ----------------------------------------------------------------------------- options

_TYPE_WORD = {float: "a number", int: "an integer", str: "a string", bool: "true or false"}


@dataclass(frozen=True)
class Option:
    """One setting of an internal: a scene key in the internal's sub-table and an FMU parameter.

    type     : float | int | str | bool
    default  : the value when nobody sets it
    unit     : SI unit of a number (None for none)
    help     : one line: what it does
    choices  : allowed strings (compared lower-case)
    minimum, maximum : allowed range of a number (inclusive; ``exclusive_minimum`` for > minimum)
    even     : an integer must be even
    special  : values allowed besides the range, with their meaning (e.g. {0: "the solver's default"})
    file     : the value names a file (a scene resolves it relative to itself, the FMU bundles it)
    file_format : the "format" value inside such a (JSON) file: an FMU build sorts bundled files by it
    required : a scene using the internal must set it (the FMU's default may still serve)
    context  : fills the value from the run's ``Context`` when nobody set it (e.g. the static load)
    """

    name: str
    type: type
    default: Any
    help: str
    unit: str | None = None
    choices: tuple[str, ...] | None = None
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: bool = False
    even: bool = False
    special: Mapping[Any, str] = field(default_factory=dict)
    file: bool = False
    file_format: str = ""  # the "format" key of such a file's JSON: tells a bundled file's option
    required: bool = False
    context: Callable[["Context"], Any] | None = None

    def allowed(self) -> str:
        """The allowed values in words, for messages and the file-format reference."""
        if self.choices:
            return "one of " + ", ".join(self.choices)
        word = "an even integer" if self.even else _TYPE_WORD[self.type]
        if self.type is float:
            word = "a finite number"
        bounds = []
        if self.minimum is not None:
            bounds.append(f"{'>' if self.exclusive_minimum else '>='} {self.minimum:g}")
        if self.maximum is not None:
            bounds.append(f"<= {self.maximum:g}")
        text = word + (" " + " and ".join(bounds) if bounds else "")
        for value, meaning in self.special.items():
            text += f", or {value!r} ({meaning})"
        return text

    def check(self, value, where: str = "") -> Any:
        """The value converted to ``type``, or ValueError naming where, the option and what is allowed."""
        prefix = f"{where}: " if where else ""
        bad = ValueError(f"{prefix}{self.name} = {value!r} must be {self.allowed()}")
        if self.type is bool:
            if not isinstance(value, bool):
                raise bad
            return value
        if self.type is str:
            if not isinstance(value, str):
                raise bad
            if self.choices:
                v = value.strip().lower()
                if v not in self.choices:
                    raise ValueError(f"{prefix}unknown {self.name} {value!r}; choose one of {', '.join(self.choices)}")
                return v
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise bad
        if self.type is int:
            if isinstance(value, float) and not (math.isfinite(value) and value == int(value)):
                raise bad
            value = int(value)
        else:
            value = float(value)
            if not math.isfinite(value):
                raise bad
        if value in self.special:
            return value
        if self.minimum is not None and (value <= self.minimum if self.exclusive_minimum else value < self.minimum):
            raise bad
        if self.maximum is not None and value > self.maximum:
            raise bad
        if self.even and value % 2:
            raise bad
        return value


@dataclass(frozen=True)
class Context:
    """What the caller knows beyond the bearing and the options.

    load    : static load (Wy, Wz) [N] the journal carries (the scene's rotor statics)
    omega   : the run's shaft speed [rad/s]
    resolve : file option value -> path (the FMU: a file in its resources; default: the value as a path)
    warn    : sink for one-line warnings (the FMU's log; default: warnings.warn)
    """

    load: tuple[float, float] | None = None
    omega: float | None = None
    resolve: Callable[[str], Path] | None = None
    warn: Callable[[str], None] | None = None

    def path(self, value: str) -> Path:
        return self.resolve(value) if self.resolve is not None else Path(value)


# ----------------------------------------------------------------------------- registry

@dataclass(frozen=True)
class Capabilities:
    """What an internal can do: the host, the FMU builds and the docs ask this, never its name.

    any_state     : answers for any speed, load and journal state inside the clearance (the
                    Reynolds solver, the force map); False for a model made about one operating
                    point (linear, a fitted surrogate). ``rotor-host stability`` needs it.
    fixed_speed   : answers only at the one speed its data file was made for (a fitted
                    surrogate); the internal then has ``omega`` [rad/s]. A speed sweep refuses it.
    fitted_domain : has a fitted domain of journal states: the internal has
                    ``domain_distance(y, z, vy, vz)`` (<= 0 inside) and ``last_out_of_domain``
                    (the last evaluated state's), for the FMU's ``out_of_domain`` output and a
                    run's domain report.
    native        : compiles into the native C FMU (``bearing_fmu.fmu.native``).
    compare       : can be a variant of ``rotor-host compare`` (error and cost against the truth).
    truth         : a reference the others are measured against (the Reynolds solver).
    validity      : one paragraph for the FMU's documentation: where its force holds ({actions}
                    and {made}, if present, are filled per FMU kind by ``bearing_fmu.fmu.docs``).
    any_geometry  : takes a bore that is not the full circle (grooves, arc, lobes; physics.bore.geometry);
                    False: ``create`` refuses such a bearing by name, ``geometry_why`` says why.
    film_flow     : has ``film_report(y, z, vy, vz, omega)`` (``physics.solver.film.FilmReport``: friction power,
                    inflow, side flow at any state, its own bore included): what the FMU's thermal ports
                    need (``thermal = true``); False: the FMU refuses them, ``film_flow_why`` says why.
                    An internal whose data file may lack them (a map file without flow tables) has
                    film_flow True and says so per instance: ``film_flow_of(spec, internal)``.
    compiled      : has ``compiled_force()``: its force and Jacobian as a compiled kernel and its
                    data (``internals.compiled``), which a host's compiled loop calls with no
                    Python per evaluation (the rotor host's Newmark chunks); an instance may
                    still answer None, and the caller then uses ``force_and_jacobian``.
    pads          : takes a tilting-pad bore (``physics.bore.pads``); False: ``create`` refuses a bearing
                    with pads by name, naming the internals that take one.
    fmu           : the Python FMU can carry it; False: the FMU refuses it, ``fmu_why`` says why.
    whirl_reduced : its K, C depend on the whirl frequency (states of its own condensed, a tilting
                    pad's tilt): it has ``reduced_coefficients(y, z, omega, whirl) -> (K, C)`` (Lund's
                    signs), which a linear analysis takes instead of the Jacobian of its force, and
                    ``full_coefficients(y, z, omega) -> (K, C, inertia)``: the (2 + N) x (2 + N) coefficients
                    of the journal and its N own coordinates and their inertias (0: massless), which an
                    eigenproblem takes whole (``rotor_host.analyses.linear.pad_modes``).
    film_field    : has a film pressure field: ``peak_pressure(y, z, vy, vz, omega) -> (p [Pa], theta [rad])``,
                    its largest pressure and where (``physics.solver.film.peak_pressure``), which the FMU's outputs
                    peak_pressure and peak_pressure_angle report (0 for an internal without it).
    memoryless    : its answer follows the journal state and its parameters alone (no time, no earlier
                    call): its FMUs (thermal off) declare it (``fmu.meta.memoryless_annotation``), may
                    step from any currentCommunicationPoint and be iterated without FMU states.
    """

    any_state: bool = False
    fixed_speed: bool = False
    fitted_domain: bool = False
    native: bool = False
    compare: bool = True
    truth: bool = False
    validity: str = ""
    any_geometry: bool = True
    geometry_why: str = ""
    film_flow: bool = False
    film_flow_why: str = ""
    compiled: bool = False
    pads: bool = False
    fmu: bool = True
    fmu_why: str = ""
    whirl_reduced: bool = False
    memoryless: bool = False
    film_field: bool = False
    step_states: bool = False


@dataclass(frozen=True)
class InternalSpec:
    """One registered internal (see ``registry``'s docstring, "How to add an internal").

    name    : what scene files, the FMU parameter ``internal`` and the command lines call it
    factory : "module:Class.from_options" inside bearing_fmu (imported when built), or a
              callable (params, options, context) -> internal
    summary : one line for listings
    options : its ``Option``s
    uses    : other internals whose options it also reads (it builds one of them inside:
              linear and taylor's fallback build Reynolds), so one grid setting serves all
    can     : its ``Capabilities``
    kernels : modules inside bearing_fmu ("physics.solver.reynolds_kernels") holding the numba kernels its
              evaluation calls, loaded from their disk cache before a run's clock starts
              (``internals.warmup.warm_internal``); () for a pure-Python internal
    case    : its contract case for tests/test_internals.py: "module:function" or a callable
              (data_dir) -> ``cases.ContractCase`` (options that build a working instance for the
              paper bearing at 22 Hz, a state it answers for, what it does past the wall; data
              files written into data_dir); None: ``cases.default_case`` (its defaults)
    """

    name: str
    factory: str | Callable
    summary: str
    options: tuple[Option, ...] = ()
    uses: tuple[str, ...] = ()
    can: Capabilities = field(default_factory=Capabilities)
    case: str | Callable | None = None
    kernels: tuple[str, ...] = ()

    def file_options(self) -> tuple[Option, ...]:
        """Its own options that name a data file (the surrogate, the map)."""
        return tuple(o for o in self.options if o.file)

    def all_options(self) -> tuple[Option, ...]:
        """Its own options, then those of the internals it uses."""
        out = list(self.options)
        for other in self.uses:
            out += [o for o in get(other).all_options() if o.name not in {p.name for p in out}]
        return tuple(out)

    def check_options(self, values: Mapping[str, Any], where: str = "", *, complete: bool = True,
                      context: Context | None = None) -> dict:
        """Checked option values: unknown names refused with the allowed ones; with ``complete``
        every option present (explicit value, else from the context, else the default)."""
        opts = {o.name: o for o in self.all_options()}
        unknown = sorted(set(values) - set(opts))
        if unknown:
            allowed = ", ".join(opts) or "none"
            raise ValueError(f"{where + ': ' if where else ''}unknown option(s) {', '.join(unknown)} of the "
                             f"{self.name} internal; allowed: {allowed}")
        out = {}
        for name, o in opts.items():
            if name in values:
                out[name] = o.check(values[name], where)
            elif complete:
                v = o.context(context) if (o.context is not None and context is not None) else None
                out[name] = o.default if v is None else o.check(v, where)
        return out

    def create(self, params: BearingParams, options: Mapping[str, Any] | None = None,
               context: Context | None = None, where: str = ""):
        """The internal for this bearing, built from checked options."""
        context = context or Context()
        opts = self.check_options(options or {}, where or f"internal {self.name!r}", context=context)
        if not self.can.any_geometry:
            try:
                params.require_full_bore(f"the {self.name} internal", self.can.geometry_why)
            except ValueError as exc:
                raise ValueError(f"{where + ': ' if where else ''}{exc}") from None
        if params.geometry.pads is not None and not self.can.pads:
            raise ValueError(f"{where + ': ' if where else ''}the {self.name} internal does not take a tilting-pad "
                             f"bore ({params.geometry.describe()}); the internals that do: "
                             f"{', '.join(having(pads=True)) or 'none'}")
        return _resolve(self.factory)(params, opts, context)

    def contract_case(self, data_dir: Path):
        """Its ``cases.ContractCase`` (see ``case``), data files written into ``data_dir``."""
        return _resolve(self.case or "internals.cases:default_case")(Path(data_dir))


def _resolve(ref: str | Callable) -> Callable:
    """A callable, or "module:attr.attr" inside bearing_fmu imported now (not at registration)."""
    if callable(ref):
        return ref
    module, _, attr = ref.partition(":")
    obj = importlib.import_module(f"..{module}", __package__)  # relative to bearing_fmu (or its FMU copy)
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj


REGISTRY: dict[str, InternalSpec] = {}


def register(spec: InternalSpec) -> InternalSpec:
    """Add an internal. Refuses a taken name, and an option name that another internal
    defines differently (an option name is one FMU parameter)."""
    if spec.name in REGISTRY:
        raise ValueError(f"an internal named {spec.name!r} is already registered")
    for o in spec.options:
        other = next((p for s in REGISTRY.values() for p in s.options if p.name == o.name), None)
        if other is not None and other != o:
            raise ValueError(f"option {o.name!r} of internal {spec.name!r} differs from the registered option "
                             "of that name (one name is one FMU parameter): rename it")
    REGISTRY[spec.name] = spec
    return spec


def unregister(name: str) -> None:
    """Remove an internal (tests that register a temporary one)."""
    REGISTRY.pop(name, None)


def names() -> tuple[str, ...]:
    """The registered internals' names, in registration order."""
    return tuple(REGISTRY)


def get(name: str) -> InternalSpec:
    """The spec of internal ``name``, or ValueError listing the registered ones."""
    key = str(name).strip().lower()
    if key not in REGISTRY:
        raise ValueError(f"unknown internal {name!r}; choose one of {', '.join(REGISTRY)}")
    return REGISTRY[key]


def create(name: str, params: BearingParams, options: Mapping[str, Any] | None = None,
           context: Context | None = None, where: str = ""):
    """Build internal ``name`` for this bearing (imports only that internal's module)."""
    return get(name).create(params, options, context, where)


def having(**wanted: bool) -> tuple[str, ...]:
    """The names of the internals whose capabilities match, e.g. ``having(any_state=True)``."""
    for key in wanted:
        if not hasattr(Capabilities, key):
            raise TypeError(f"no capability {key!r}; known: {', '.join(Capabilities.__dataclass_fields__)}")
    return tuple(n for n, s in REGISTRY.items() if all(getattr(s.can, k) == v for k, v in wanted.items()))


def film_flow_of(spec: "InternalSpec", internal=None) -> str:
    """'' when the internal has the film's flows (``Capabilities.film_flow``), else why not. With the
    built ``internal`` its own answer counts: a data file may lack the tables (its ``film_flow_why``),
    or its kind have no ``film_report`` at all (then the capability's ``film_flow_why``)."""
    lacking = spec.can.film_flow_why or f"the {spec.name} internal has no film report"
    if not spec.can.film_flow:
        return lacking
    if internal is None:
        return ""
    if getattr(internal, "film_report", None) is None:
        return lacking
    return getattr(internal, "film_flow_why", "")


def all_options() -> list[Option]:
    """Every registered option once, in registration order: the FMU's internal parameters."""
    seen: dict[str, Option] = {}
    for spec in REGISTRY.values():
        for o in spec.options:
            seen.setdefault(o.name, o)
    return list(seen.values())
