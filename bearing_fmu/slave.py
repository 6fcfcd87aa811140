"""The bearing as an FMI 2.0 co-simulation slave (pythonfmu), with a switchable internal.

Inputs ``y, z, vy, vz, omega`` (SI) go in; the film force ``Fy, Fz`` and a few diagnostics
come out, computed in ``do_step`` from the inputs set for the end of the step. Which
internal computes the force is a parameter (``internal``: a name of ``internals.REGISTRY``)
read once in ``exit_initialization_mode``; every registered internal's options are FMU
parameters, and only the chosen internal's module is imported, so an FMU running the
linear or Taylor internal never loads or compiles the Reynolds solver.

Errors never leave this class as exceptions: pythonfmu turns any Python exception into
fmi2Fatal and frees the Python object, after which the next call on the instance crashes
the host. Instead

* ``do_step`` logs the reason (e.g. "eccentricity ratio 1.03 >= 1 ... at t = 0.4123 s")
  and returns False, which the FMU reports as fmi2Discard; the outputs keep their last
  valid values and the instance stays usable (restore a state, set valid inputs, step on);
* a failed initialisation (unknown internal, missing surrogate file, bad parameter) is
  logged with status fmi2Error in ``exit_initialization_mode`` (pythonfmu 0.7 ignores that
  method's return value, so the call itself still reports fmi2OK), and every ``do_step``
  afterwards is discarded with the same message;
* getters and setters never raise; an unknown value reference is logged and ignored.

The FMU state (fmi2GetFMUstate) is a small tuple (tag, time, inputs and outputs); the
internal is not part of it (it is fixed after initialisation), so saving and restoring
costs a few microseconds. In the FMU this file is the pythonfmu slave module: ``build.py``
rewrites its relative imports to the uniquely named copy of the package (see there).
"""

import math
import operator
import os
import traceback
from pathlib import Path

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from . import __version__
from . import internals as registry
from .internals import BearingStateError, Context, check_finite
from .params import PAPER_BEARING, BearingParams

SURROGATE_DIR = "surrogates"  # inside the FMU's resources folder: the files of file options

# name, type, causality, unit, default, description. The one table of the FMU interface:
# the slave registers these, build.py writes units and dependencies from it. The internals'
# parameters come from their registry options.
_IN, _OUT, _PAR = "input", "output", "parameter"
_FMI_TYPE = {float: "Real", int: "Integer", bool: "Boolean", str: "String"}
VARIABLES = (
    # inputs: the journal state at the end of the step
    ("y", "Real", _IN, "m", 0.0, "journal centre displacement from the bearing centre, horizontal"),
    ("z", "Real", _IN, "m", 0.0, "journal centre displacement from the bearing centre, vertical (up)"),
    ("vy", "Real", _IN, "m/s", 0.0, "journal centre velocity, horizontal"),
    ("vz", "Real", _IN, "m/s", 0.0, "journal centre velocity, vertical"),
    ("omega", "Real", _IN, "rad/s", 0.0, "shaft speed, right-handed about the shaft axis x"),
    # outputs
    ("Fy", "Real", _OUT, "N", 0.0, "film force on the journal, horizontal"),
    ("Fz", "Real", _OUT, "N", 0.0, "film force on the journal, vertical"),
    ("eccentricity", "Real", _OUT, "1", 0.0, "eccentricity ratio sqrt(y^2 + z^2) / CR"),
    ("h_min", "Real", _OUT, "m", 0.0, "minimum film thickness CR - sqrt(y^2 + z^2) (negative beyond the wall)"),
    ("out_of_domain", "Boolean", _OUT, None, False,
     "true when the state lies outside the surrogate's fitted domain (taylor only; false otherwise)"),
    ("Kyy", "Real", _OUT, "N/m", 0.0, "film stiffness -dFy/dy (Lund sign; 0 if compute_tangent is false)"),
    ("Kyz", "Real", _OUT, "N/m", 0.0, "film stiffness -dFy/dz (Lund sign; 0 if compute_tangent is false)"),
    ("Kzy", "Real", _OUT, "N/m", 0.0, "film stiffness -dFz/dy (Lund sign; 0 if compute_tangent is false)"),
    ("Kzz", "Real", _OUT, "N/m", 0.0, "film stiffness -dFz/dz (Lund sign; 0 if compute_tangent is false)"),
    ("Cyy", "Real", _OUT, "N.s/m", 0.0, "film damping -dFy/dvy (Lund sign; 0 if compute_tangent is false)"),
    ("Cyz", "Real", _OUT, "N.s/m", 0.0, "film damping -dFy/dvz (Lund sign; 0 if compute_tangent is false)"),
    ("Czy", "Real", _OUT, "N.s/m", 0.0, "film damping -dFz/dvy (Lund sign; 0 if compute_tangent is false)"),
    ("Czz", "Real", _OUT, "N.s/m", 0.0, "film damping -dFz/dvz (Lund sign; 0 if compute_tangent is false)"),
    # parameters: the bearing (paper Table 2)
    ("D", "Real", _PAR, "m", PAPER_BEARING.D, "bearing (journal) diameter"),
    ("L", "Real", _PAR, "m", PAPER_BEARING.L, "bearing length"),
    ("CR", "Real", _PAR, "m", PAPER_BEARING.CR, "radial clearance"),
    ("mu", "Real", _PAR, "Pa.s", PAPER_BEARING.mu, "dynamic viscosity of the oil"),
    # parameters: which internal, and whether the outputs K.., C.. are computed
    ("internal", "String", _PAR, None, "reynolds",
     "which internal computes the force: " + " | ".join(registry.names())),
    ("compute_tangent", "Boolean", _PAR, None, True,
     "compute the outputs K.., C.. from the internal's Jacobian at every step"),
    # parameters: every registered internal's options
    *((o.name, _FMI_TYPE[o.type], _PAR, o.unit, o.default, o.help if o.type is str else f"{o.help} ({o.allowed()})")
      for o in registry.all_options()),
)

INPUTS = tuple(v[0] for v in VARIABLES if v[2] == _IN)
OUTPUTS = tuple(v[0] for v in VARIABLES if v[2] == _OUT)
PARAMETERS = tuple(v[0] for v in VARIABLES if v[2] == _PAR)
_REAL_OUTPUTS = tuple(v[0] for v in VARIABLES if v[2] == _OUT and v[1] == "Real")
_TANGENT = ("Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")
_STATE_TAG = "bearing_fmu.slave/2"  # /2: values as one tuple
_STATE_NAMES = INPUTS + OUTPUTS
_STATE_VALUES = operator.attrgetter(*_STATE_NAMES)
_VAR_CLASS = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}
_CAST = {"Real": float, "Integer": int, "Boolean": bool, "String": str}
_FILE_OPTIONS = {o.name for o in registry.all_options() if o.file}


def _default_file(resources) -> str:
    """The file bundled in the FMU when there is exactly one, else "" (the default of a file option)."""
    if not resources:
        return ""
    folder = Path(resources) / SURROGATE_DIR
    try:
        names = sorted(p.name for p in folder.iterdir() if p.is_file())
    except OSError:
        return ""
    return names[0] if len(names) == 1 else ""


class BearingFMU(Fmi2Slave):
    """Hydrodynamic journal bearing: film force from the journal state (see module docstring)."""

    description = ("Hydrodynamic journal bearing (plain cylindrical): film force on the journal from its "
                   "position, velocity and speed; internal: Reynolds solver, Taylor surrogate or linear")
    version = __version__
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=0.1, step_size=1e-4)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._kind = {}  # name -> type
        self._by_vr = {}  # value reference -> (name, type, causality)
        for name, typ, causality, _unit, default, desc in VARIABLES:
            if name in _FILE_OPTIONS:
                default = _default_file(self.resources)
            setattr(self, name, default)
            var = _VAR_CLASS[typ](
                name,
                causality=getattr(Fmi2Causality, causality),
                variability=(Fmi2Variability.fixed if causality == _PAR
                             else Fmi2Variability.discrete if typ != "Real"
                             else Fmi2Variability.continuous),
                description=desc,
                getter=(lambda n=name: getattr(self, n)),
                setter=(lambda v, n=name, c=_CAST[typ]: setattr(self, n, c(v))),
            )
            self.register_variable(var)
            self._by_vr[var.value_reference] = (name, typ, causality)
        self._real_names = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real"}
        self._real_inputs = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real" and e[2] == _IN}
        self._internal = None  # built in exit_initialization_mode
        self._internal_name = ""
        self._jacobian = None
        self._params = None
        self._initialized = False
        self._init_error = None
        self._t = 0.0

    # ------------------------------------------------------------------ logging
    def _log(self, msg: str, status: Fmi2Status) -> None:
        try:
            self.log(msg, status)
        except Exception:  # logging must never be the thing that fails
            pass

    # ------------------------------------------------------------------ initialisation
    def exit_initialization_mode(self):
        try:
            self._build_internal()
        except Exception as exc:  # noqa: BLE001 - turned into a logged error, never raised
            self._internal = None
            detail = "" if isinstance(exc, (ValueError, KeyError, FileNotFoundError, ImportError)) \
                else "\n" + traceback.format_exc()
            self._init_error = f"bearing FMU initialisation failed: {exc}{detail}"
            self._log(self._init_error, Fmi2Status.error)
            self._initialized = True
            return False
        self._initialized = True
        # outputs at the start time from the initial inputs, when they can be evaluated
        try:
            self._step_outputs()
        except BearingStateError as exc:
            self._log(f"outputs at initialisation left at 0: {exc}", Fmi2Status.warning)
        except Exception as exc:  # noqa: BLE001
            self._log(f"outputs at initialisation left at 0: unexpected {type(exc).__name__}: {exc}\n"
                      f"{traceback.format_exc()}", Fmi2Status.warning)
        return True

    def _build_internal(self) -> None:
        params = BearingParams(D=self.D, L=self.L, CR=self.CR, mu=self.mu)
        self._params = params
        spec = registry.get(self.internal)
        options = {o.name: getattr(self, o.name) for o in spec.all_options()}
        context = Context(resolve=self._resource_file,
                          warn=lambda msg: self._log(f"t = {self._t:.10g} s: {msg}", Fmi2Status.warning))
        internal = spec.create(params, options, context, where="FMU parameter")
        self._internal = internal
        self._internal_name = spec.name
        self._jacobian = getattr(internal, "force_and_jacobian", None)

    def _resource_file(self, name: str) -> Path:
        folder = Path(self.resources or ".") / SURROGATE_DIR
        try:
            bundled = sorted(p.name for p in folder.iterdir() if p.is_file())
        except OSError:
            bundled = []
        listing = ", ".join(bundled) if bundled else "none"
        if os.path.isabs(name) or ".." in Path(name).parts:
            raise ValueError(f"{name!r} must be a file name inside the FMU resources, not a path")
        path = folder / name
        if not path.is_file():
            raise FileNotFoundError(
                f"surrogate file {name!r} not found in the FMU resources folder {SURROGATE_DIR}/ "
                f"(bundled: {listing}); build the FMU with `bearing-fmu build --surrogate FILE`")
        return path

    # ------------------------------------------------------------------ stepping
    def do_step(self, current_time, step_size):
        t = current_time + step_size
        try:
            if self._internal is None:
                reason = self._init_error or "the FMU was not initialised (call exitInitializationMode first)"
                self._log(f"step to t = {t:.10g} s discarded: {reason}", Fmi2Status.error)
                return False
            self._step_outputs()
        except BearingStateError as exc:
            self._log(f"{exc} at t = {t:.10g} s", Fmi2Status.discard)
            return False
        except Exception as exc:  # noqa: BLE001 - never let an exception reach pythonfmu
            self._log(f"step to t = {t:.10g} s discarded: unexpected {type(exc).__name__} in the "
                      f"{self._internal_name} internal: {exc}\n{traceback.format_exc()}", Fmi2Status.error)
            return False
        self._t = t
        return True

    def _step_outputs(self) -> None:
        """Evaluate the internal at the current inputs and set the outputs, or raise
        BearingStateError (outputs untouched)."""
        y, z, vy, vz, omega = self.y, self.z, self.vy, self.vz, self.omega
        params = self._params
        check_finite(y, z, vy, vz, omega)  # the internals refuse the wall themselves where they must
        eps = math.hypot(y, z) / params.CR
        internal = self._internal
        if self.compute_tangent:
            if self._jacobian is not None:
                f, dq, dv = self._jacobian(y, z, vy, vz, omega)
            else:
                from .statics import film_jacobian

                f, dq, dv = film_jacobian(internal, y, z, vy, vz, omega)
            tangent = (-float(dq[0, 0]), -float(dq[0, 1]), -float(dq[1, 0]), -float(dq[1, 1]),
                       -float(dv[0, 0]), -float(dv[0, 1]), -float(dv[1, 0]), -float(dv[1, 1]))
        else:
            f = internal.force(y, z, vy, vz, omega)
            tangent = None
        fy, fz = float(f[0]), float(f[1])
        if not (math.isfinite(fy) and math.isfinite(fz)) or (tangent and not all(map(math.isfinite, tangent))):
            raise BearingStateError(
                f"the {self._internal_name} internal returned a non-finite force or tangent at "
                f"y = {y:.6g} m, z = {z:.6g} m, vy = {vy:.6g} m/s, vz = {vz:.6g} m/s, omega = {omega:.6g} rad/s")
        ood = getattr(internal, "last_out_of_domain", False)  # the domain guard's verdict on this state
        # all evaluated: commit the outputs
        self.Fy, self.Fz = fy, fz
        self.eccentricity = eps
        self.h_min = params.CR * (1.0 - eps)
        self.out_of_domain = ood
        if tangent is not None:
            (self.Kyy, self.Kyz, self.Kzy, self.Kzz, self.Cyy, self.Cyz, self.Czy, self.Czz) = tangent

    # ------------------------------------------------------------------ FMU state
    # A host iterating the FMI way saves the state once per step and restores it at every
    # iteration, so both run in C where they can (attrgetter, dict.update): a state this
    # class wrote holds the right types already.
    def _get_fmu_state(self):
        # a fresh immutable tuple: pythonfmu hands this very object back on fmi2SetFMUstate
        return (_STATE_TAG, self._t, _STATE_VALUES(self))

    def _set_fmu_state(self, state):
        try:
            if len(state) != 3 or state[0] != _STATE_TAG or len(state[2]) != len(_STATE_NAMES):
                raise ValueError(f"not a {_STATE_TAG} state")
            self._t = float(state[1])
            self.__dict__.update(zip(_STATE_NAMES, state[2]))
        except Exception as exc:  # noqa: BLE001
            self._log(f"fmi2SetFMUstate ignored: {exc}", Fmi2Status.error)

    # ------------------------------------------------------------------ getters / setters (never raise)
    def _get(self, vrs, typ, cast, bad):
        out = []
        for vr in vrs:
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                self._log(f"get{typ}: value reference {vr} is not a {typ} variable of this FMU", Fmi2Status.error)
                out.append(bad)
                continue
            try:
                out.append(cast(getattr(self, entry[0])))
            except Exception as exc:  # noqa: BLE001
                self._log(f"get{typ} {entry[0]}: {exc}", Fmi2Status.error)
                out.append(bad)
        return out

    def _set(self, vrs, values, typ, cast):
        for vr, value in zip(vrs, values):
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                self._log(f"set{typ}: value reference {vr} is not a {typ} variable of this FMU; ignored",
                          Fmi2Status.error)
                continue
            name, _, causality = entry
            if causality == _OUT:
                self._log(f"set{typ}: {name} is an output; ignored", Fmi2Status.error)
                continue
            if causality == _PAR and self._initialized:
                self._log(f"set{typ}: parameter {name} is fixed after initialisation; ignored",
                          Fmi2Status.error)
                continue
            try:
                setattr(self, name, cast(value))
            except Exception as exc:  # noqa: BLE001
                self._log(f"set{typ} {name} = {value!r}: {exc}; ignored", Fmi2Status.error)

    def get_real(self, vrs):
        try:  # fast path: every reference a Real variable (the host's per-iteration call)
            names = self._real_names
            return [float(getattr(self, names[vr])) for vr in vrs]
        except Exception:  # noqa: BLE001 - the checked path logs what was wrong
            return self._get(vrs, "Real", float, math.nan)

    def get_integer(self, vrs):
        return self._get(vrs, "Integer", int, 0)

    def get_boolean(self, vrs):
        return self._get(vrs, "Boolean", bool, False)

    def get_string(self, vrs):
        return self._get(vrs, "String", str, "")

    def set_real(self, vrs, values):
        try:  # fast path: Real inputs only (the host's per-iteration call); idempotent on fallback
            names = self._real_inputs
            for vr, value in zip(vrs, values):
                setattr(self, names[vr], float(value))
        except Exception:  # noqa: BLE001 - the checked path applies the rules and logs
            self._set(vrs, values, "Real", float)

    def set_integer(self, vrs, values):
        self._set(vrs, values, "Integer", int)

    def set_boolean(self, vrs, values):
        self._set(vrs, values, "Boolean", bool)

    def set_string(self, vrs, values):
        self._set(vrs, values, "String", str)
