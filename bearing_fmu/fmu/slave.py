"""The bearing as an FMI 2.0 co-simulation slave (pythonfmu), with a switchable internal.

Inputs ``y, z, vy, vz, omega`` (SI) go in; the film force ``Fy, Fz`` and a few diagnostics
come out, computed in ``do_step`` from the inputs set for the end of the step. Which
internal computes the force is a parameter (``internal``: a name of ``internals.REGISTRY``)
read once in ``exit_initialization_mode``; every registered internal's options are FMU
parameters, and only the chosen internal's module is imported, so an FMU running the
linear or Taylor internal never loads or compiles the Reynolds solver.

FMI statuses (docs/fmu.md, "FMI status"). pythonfmu gives a Python slave three outcomes:
``do_step`` returning False is fmi2Discard, a normal return is fmi2OK, and an exception is
fmi2Fatal with the instance released. The build patches pythonfmu's binary
(``fmu_binary``) so that an exception is fmi2Error and leaves the instance intact; then

* a refused call raises ``FMIError`` with a one-line reason, which pythonfmu logs with status
  Error: an invalid parameter (in its setter and again in ``exit_initialization_mode``), an unknown
  value reference, a parameter set after initialisation, a non-positive or non-finite step
  size or time, doStep before a successful initialisation, any call out of the FMI 2.0 calling
  sequence (``fmi_order``), a freed FMU state;
* a state the internal cannot evaluate (journal at the wall, a non-finite input) discards
  the step: ``do_step`` logs why (status Discard) and returns False; the outputs keep their
  last valid values and the instance stays usable (restore a state, set valid inputs, step
  on). fmi2Terminated stays false (patched binary: pythonfmu set it at every discard); a
  doStep again at the same refused inputs raises (a master retrying unchanged would loop);
* outputs read in Initialization Mode are computed from the inputs and parameters set so far.

Without the patches (``resources/pythonfmu_patches.json`` says which are in; the Windows
binary is pythonfmu's as is) nothing raises: a refused call is logged with status Error and
returns fmi2OK, as pythonfmu allows. When the master has logging off, the first warning, the
first discard and the first error of an instance are also printed to stderr (``LoggingFlag``).

The FMU state (fmi2GetFMUstate) is a small list (tag, time, inputs and outputs;
``fmi_order.FMUState``: recognised once freed); the internal is not part of it (it is fixed
after initialisation), so saving and restoring costs a few microseconds. A Taylor internal's
domain warning comes once per excursion and the count at terminate (``_excursion``). In the
FMU this file is the pythonfmu slave module: ``build.py`` rewrites its relative imports to the
uniquely named copy of the package (see there).
"""

import json
import math
import operator
import os
from pathlib import Path

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from bearing_fmu import __version__
from bearing_fmu.internals import registry
from bearing_fmu.fmu.order import INIT, INSTANTIATED, STEP, TERMINATED, FMUState, is_freed, refusal
from bearing_fmu.fmu.resources import BEARING_DEFAULTS, BUILD_INFO, PATCH_NOTES  # noqa: F401 - build.py reads them here
from bearing_fmu.fmu.resources import (BEARING_FIELDS, SURROGATE_DIR, LoggingFlag, bearing_defaults, default_file,
                                       port_defaults, status_patched)
from bearing_fmu.fmu import ports
from bearing_fmu.fmu.variables import (ENUMERATIONS, INPUT, INPUTS, OUTPUT, OUTPUTS, PARAMETER, PARAMETERS,
                                       VARIABLES, enum_value)
from bearing_fmu.internals.registry import BearingStateError, Context, check_finite
from bearing_fmu.physics.params import BearingParams

_STATE_TAG = "bearing_fmu.fmu.slave/2"  # /2: values as one tuple
_STATE_NAMES = INPUTS + OUTPUTS
_STATE_VALUES = operator.attrgetter(*_STATE_NAMES)
_VAR_CLASS = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}
_CAST = {"Real": float, "Integer": int, "Boolean": bool, "String": str}
_FILE_OPTIONS = {o.name for o in registry.all_options() if o.file}
_OPTIONS = {o.name: o for o in registry.all_options()}
_UNITS = {v[0]: v[3] for v in VARIABLES}
_INF = math.inf
_ECHO_HINT = ("logging is off, so this FMU instance prints its first warning, discard and error here; "
              "instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to receive every message")


class FMIError(Exception):
    """Raised out of a pythonfmu entry point so that the call returns fmi2Error (patched binary).

    pythonfmu logs ``repr()`` of the exception after "fmi2Error from the Python slave [call]":
    the repr is the message itself, so that one line says what was refused and why."""

    def __repr__(self) -> str:
        return str(self)


class BearingFMU(Fmi2Slave):
    """Hydrodynamic journal bearing: film force from the journal state (see module docstring)."""

    description = ("Hydrodynamic journal bearing (plain cylindrical): film force on the journal from its "
                   "position, velocity and speed; internal: Reynolds solver, linear model, Taylor surrogate or "
                   "force map")
    version = __version__
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=0.1, step_size=1e-4)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._by_vr = {}  # value reference -> (name, type, causality)
        built_in = {**bearing_defaults(self.resources), **port_defaults(self.resources)}
        for name, typ, causality, _unit, default, desc in VARIABLES:
            if name in _FILE_OPTIONS:
                default = default_file(self.resources, _OPTIONS[name])
            elif name in built_in:
                default = built_in[name]
            setattr(self, name, default)
            var = _VAR_CLASS[typ](
                name,
                causality=getattr(Fmi2Causality, causality),
                variability=(Fmi2Variability.fixed if causality == PARAMETER
                             else Fmi2Variability.discrete if typ != "Real"
                             else Fmi2Variability.continuous),
                description=desc,
                getter=(lambda n=name: getattr(self, n)),
                setter=(lambda v, n=name, c=_CAST[typ]: setattr(self, n, c(v))),
            )
            self.register_variable(var)
            self._by_vr[var.value_reference] = (name, typ, causality)
        # the String choices' starts (a built-in bearing's oil law among them), their enumerations with them
        self._starts = {string: getattr(self, string) for string, _items in ENUMERATIONS.values()}
        for name, (string, _items) in ENUMERATIONS.items():
            setattr(self, name, enum_value(name, self._starts[string]))
        self._real_names = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real"}
        # getReal's fast path: outside Step Mode without the outputs, so reading them in
        # Initialization Mode takes the checked path, which computes them from the inputs
        self._real_no_outputs = {vr: n for vr, n in self._real_names.items() if self._by_vr[vr][2] != OUTPUT}
        self._all_inputs = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real" and e[2] == INPUT}
        self._internal = None  # built in exit_initialization_mode (or by an output read in Initialization Mode)
        self._built_from = None  # the parameter values it was built from
        self._internal_name = ""
        self._choices_built = {}  # the String choices the internal was built with (_choices)
        self._jacobian = None
        self._params = None
        self._oil = None  # the oil law of the thermal model, when thermal is true (ports.py)
        self._enter(INSTANTIATED)
        self._initialized = False  # exit_initialization_mode was called: parameters are fixed
        self._init_error = None
        self._refused = {}  # parameter name -> why its last set was refused (fails the initialisation)
        self._discarded = None  # the inputs of the last discarded step (None after a good one)
        self._t = 0.0
        self._raises = status_patched(self.resources)  # an exception gives fmi2Error, not fmi2Fatal
        # the logger's layout is known for the binary the patches verified, and only for that one
        self._logging = LoggingFlag(kwargs.get("logger") if self._raises else None, self.instance_name)
        self._echoed = set()
        self._guard = None  # the internal when it is a domain guard (excursions out of the fitted domain)
        self._pending = None  # during an evaluation: the domain guard's warnings, logged if it is committed
        self._excursions = (0, 0.0, 0.0)  # out of the fitted domain (one warning each): count, first t, last t

    # ------------------------------------------------------------------ logging and refusals
    def _log(self, msg: str, status: Fmi2Status) -> None:
        try:
            self.log(msg, status)
        except Exception:  # logging must never be the thing that fails
            pass
        self._echo(msg, status)

    def _echo(self, msg: str, status: Fmi2Status) -> None:
        """When the master has logging off, print the first message of each status to stderr."""
        if status == Fmi2Status.ok or status in self._echoed or not self._logging.off():
            return
        import sys

        self._echoed.add(status)
        hint = "" if len(self._echoed) > 1 else f"\n  ({_ECHO_HINT})"
        try:
            print(f"bearing FMU {self.instance_name!r} [{status.name}]: {msg}{hint}", file=sys.stderr, flush=True)
        except Exception:  # noqa: BLE001 - no stderr: nothing more to do
            pass

    def _fail(self, msg: str):
        """Refuse the current call with ``msg``: raise FMIError, which the patched binary
        returns as fmi2Error and logs as "fmi2Error from the Python slave [call] ... msg".
        Without the patches, log ``msg`` with status Error and return None: the caller goes on
        the way pythonfmu allows (the call returns fmi2OK)."""
        if not self._raises:
            self._log(msg, Fmi2Status.error)
            return None
        # pythonfmu hands the queued log lines to the master's logger before it fetches the
        # exception: a Python logger (fmpy) would run with the exception pending and lose it.
        # So this call's earlier lines travel in the exception's message instead.
        queued = [f"[{getattr(m.status, 'name', m.status)}] {m.msg}" for m in self.log_queue]
        self.log_queue.clear()  # the very list pythonfmu holds: cleared in place
        self._echo(msg, Fmi2Status.error)
        raise FMIError(msg + (f" (logged before it in this call: {' | '.join(queued)})" if queued else ""))

    # ------------------------------------------------------------------ the FMI 2.0 calling sequence
    def _order(self, call: str) -> None:
        """Refuse ``call`` (fmi_order's name) unless the current mode allows it: FMIError, i.e.
        fmi2Error naming the call. Without the status patches (or driven from Python, as tests and
        benchmarks do) the refusal is logged with status Error and the call goes on as before."""
        why = refusal(call, self._mode)
        if why is not None:
            self._fail(why)

    def _enter(self, mode: str) -> None:
        """Change the mode, and the fast paths with it: getReal's reads no output outside Step Mode
        and Terminated (Initialization Mode computes them first) and nothing in Instantiated;
        setReal's takes no input once terminated. What they skip takes the checked path."""
        self._mode = mode
        self._real_get = ({} if mode is INSTANTIATED else self._real_no_outputs if mode is INIT
                          else self._real_names)
        self._real_inputs = {} if mode is TERMINATED else self._all_inputs

    # ------------------------------------------------------------------ initialisation
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._order("setupExperiment")
        if not -_INF < start_time < _INF:
            return self._fail(f"setupExperiment: startTime = {start_time!r} s must be finite")
        if stop_time is not None and not start_time <= stop_time < _INF:
            return self._fail(f"setupExperiment: stopTime = {stop_time!r} s must be finite and >= "
                              f"startTime = {start_time!r} s")
        self._t = float(start_time)

    def enter_initialization_mode(self):
        self._order("enterInitializationMode")
        self._enter(INIT)

    def exit_initialization_mode(self):
        self._order("exitInitializationMode")
        self._initialized = True
        try:
            self._ensure_internal()
        except Exception as exc:  # noqa: BLE001 - refused with its message, never a bare exception
            self._internal = None
            self._init_error = f"bearing FMU initialisation failed: {self._describe(exc)}"
            return self._fail(self._init_error)
        self._enter(STEP)
        for name, (string, items) in ENUMERATIONS.items():  # both show the choice that counts
            choice = self._choices_built[string]
            setattr(self, string, choice)
            setattr(self, name, enum_value(name, choice))
        # outputs at the start time from the initial inputs, when they can be evaluated; a
        # master may set the inputs only before the first step, so a state the internal
        # refuses is not an initialisation error
        try:
            self._step_outputs()
        except BearingStateError as exc:
            self._log(f"outputs at the start time left at their start values: {exc}", Fmi2Status.warning)
        except Exception as exc:  # noqa: BLE001
            self._log(f"outputs at the start time left at their start values: {self._describe(exc)}",
                      Fmi2Status.warning)
        return True

    def terminate(self):
        self._order("terminate")
        self._enter(TERMINATED)
        n, first, last = self._excursions
        if n:  # the count of what was warned once per excursion
            self._log(f"terminate: the state left the surrogate's fitted domain {n} time(s) in this run (each "
                      f"excursion warned when it began; the first at t = {first:.10g} s, the last at "
                      f"t = {last:.10g} s)", Fmi2Status.warning)

    @staticmethod
    def _describe(exc: BaseException) -> str:
        """One line: the message of an expected failure; the type, message and place of anything
        else. Never a traceback: a log line is read in a master's message window."""
        from bearing_fmu.physics.statics import EquilibriumError

        if isinstance(exc, (ValueError, KeyError, FileNotFoundError, ImportError, EquilibriumError)):
            text = str(exc)
        else:
            tb = exc.__traceback__
            while tb is not None and tb.tb_next is not None:
                tb = tb.tb_next
            where = (f" (raised in {Path(tb.tb_frame.f_code.co_filename).name}, line {tb.tb_lineno})"
                     if tb is not None else "")
            text = f"unexpected {type(exc).__name__}: {exc}{where}"
        return " ".join(text.split())

    def _parameter_values(self) -> tuple:
        return tuple(getattr(self, n) for n in PARAMETERS)

    def _ensure_internal(self) -> None:
        """Build the internal from the parameters set so far, unless it already was (or raise)."""
        if self._refused:
            raise ValueError("; ".join(self._refused.values()))
        values = self._parameter_values()
        if self._internal is not None and self._built_from == values:
            return
        self._internal = None
        self._build_internal()
        self._built_from = values

    def _choices(self) -> dict:
        """The String choice parameters as they count: each one's value, or its enumeration's
        item where only the enumeration was set away from its start; ValueError naming both when
        both were and they disagree."""
        out = {}
        for name, (string, items) in ENUMERATIONS.items():
            value, text = getattr(self, name), str(getattr(self, string)).strip().lower()
            enum_set = value != enum_value(name, self._starts[string])
            if enum_set and text != self._starts[string] and text != items[value - 1]:
                raise ValueError(f"{string} = {getattr(self, string)!r} and {name} = {value} ({items[value - 1]}) "
                                 f"disagree: set one of them ({name} is the same choice as an enumeration)")
            out[string] = items[value - 1] if enum_set else text
        return out

    def _build_internal(self) -> None:
        choices = self._choices()
        spec = registry.get(choices["internal"])
        geometry = ports.geometry_of(self)
        ports.check_geometry(geometry, spec)
        oil = ports.oil_of(self, choices["oil_law"])
        ports.check_thermal(self.thermal, oil, spec)
        params = BearingParams(D=self.D, L=self.L, CR=self.CR, mu=self.mu, geometry=geometry, oil=oil)
        self._params = params
        self._oil = oil if self.thermal else None
        self._choices_built = choices
        options = {o.name: choices.get(o.name, getattr(self, o.name)) for o in spec.all_options()}
        context = Context(resolve=self._resource_file, warn=self._warn)
        internal = spec.create(params, options, context, where="FMU parameter")
        ports.check_thermal(self.thermal, oil, spec, internal)  # a map file may lack the flow tables
        self._internal = internal
        self._internal_name = spec.name
        self._jacobian = getattr(internal, "force_and_jacobian", None)
        self._guard = internal if hasattr(internal, "outside") else None  # a domain guard: its excursion flag

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
        option = next((o for o in sorted(_FILE_OPTIONS) if getattr(self, o, None) == name), "data")  # its parameter
        if not path.is_file():
            raise FileNotFoundError(
                f"{option} file {name!r} not found in the FMU resources folder {SURROGATE_DIR}/ "
                f"(bundled: {listing}); build the FMU with `bearing-fmu build --{option} FILE`")
        return path

    def _outputs_in_init(self, call: str) -> None:
        """Initialization Mode: compute the outputs from the inputs and parameters set so far
        (the model description declares them dependent on both), or refuse the read."""
        try:
            self._ensure_internal()
        except Exception as exc:  # noqa: BLE001
            return self._fail(f"{call} in {INIT}: the outputs cannot be computed: bearing FMU initialisation "
                              f"failed: {self._describe(exc)}")
        try:
            self._step_outputs()
        except BearingStateError as exc:
            return self._fail(f"{call} in {INIT}: the outputs cannot be computed at the inputs set: {exc} "
                              "(set valid inputs and read again)")
        except Exception as exc:  # noqa: BLE001
            return self._fail(f"{call} in {INIT}: the {self._internal_name} internal failed: {self._describe(exc)}")
        return None

    # ------------------------------------------------------------------ stepping
    def do_step(self, current_time, step_size):
        t = current_time + step_size
        if self._mode is not STEP:  # refused (without the patches: discarded), with the reason when there is one
            if self._mode is INIT and self._init_error:
                return self._fail(f"doStep: step to t = {t:.10g} s refused: {self._init_error}") or False
            return self._fail(refusal("doStep", self._mode)) or False
        if not (0.0 < step_size < _INF and -_INF < current_time < _INF and t < _INF):
            return self._bad_step(current_time, step_size)
        state = tuple(float(getattr(self, name)).hex() for name in INPUTS)  # T_supply too
        if state == self._discarded:  # no fmi2Terminated: a master retrying unchanged would loop forever
            return self._fail(f"doStep: step to t = {t:.10g} s refused: the inputs of the step discarded just before, "
                              "unchanged (the state is refused again whatever the step size); set other inputs or "
                              "restore an FMU state") or False
        try:
            self._step_outputs(step_size)
        except BearingStateError as exc:
            self._log(f"{exc} at t = {t:.10g} s", Fmi2Status.discard)
            self._discarded = state
            return False
        except Exception as exc:  # noqa: BLE001 - a failure of the internal itself, not of the state
            return self._fail(f"doStep: step to t = {t:.10g} s failed in the {self._internal_name} internal: "
                              f"{self._describe(exc)}") or False
        self._discarded = None
        self._t = t
        return True

    def _bad_step(self, current_time, step_size) -> bool:
        if not 0.0 < step_size < _INF:
            msg = (f"doStep: communicationStepSize = {step_size!r} s must be finite and > 0 "
                   f"(currentCommunicationPoint = {current_time!r} s)")
        elif not -_INF < current_time < _INF:
            msg = f"doStep: currentCommunicationPoint = {current_time!r} s must be finite"
        else:
            msg = (f"doStep: currentCommunicationPoint + communicationStepSize = {current_time!r} + "
                   f"{step_size!r} s is not finite")
        return self._fail(msg) or False

    def _step_outputs(self, dt: float | None = None) -> None:
        """Evaluate the internal at the current inputs and set the outputs, or raise
        BearingStateError (outputs untouched). With thermal on, T_eff lags over a step of ``dt``
        [s] from its committed value; ``dt`` None: quasi-static (Initialization Mode)."""
        y, z, vy, vz, omega = self.y, self.z, self.vy, self.vz, self.omega
        params = self._params
        check_finite(y, z, vy, vz, omega)  # the internals refuse the wall themselves where they must
        eps = math.hypot(y, z) / params.CR
        internal = self._internal
        if self._guard is not None:  # an excursion begins where the committed state (an FMU state's) was inside
            self._guard.outside = self.out_of_domain
        self._pending = []
        try:
            if self.compute_tangent:
                if self._jacobian is not None:
                    f, dq, dv = self._jacobian(y, z, vy, vz, omega)
                else:
                    from bearing_fmu.physics.statics import film_jacobian

                    f, dq, dv = film_jacobian(internal, y, z, vy, vz, omega)
                tangent = (-float(dq[0, 0]), -float(dq[0, 1]), -float(dq[1, 0]), -float(dq[1, 1]),
                           -float(dv[0, 0]), -float(dv[0, 1]), -float(dv[1, 0]), -float(dv[1, 1]))
            else:
                f = internal.force(y, z, vy, vz, omega)
                tangent = None
        finally:
            pending, self._pending = self._pending, None
        fy, fz = float(f[0]), float(f[1])
        if self._oil is not None:  # the film at its effective viscosity: F ~ mu at a fixed state
            try:
                factor, *heat = ports.thermal_state(internal, params, self._oil, self.T_supply, (y, z, vy, vz, omega),
                                                    None if dt is None else self.T_eff, dt or 0.0)
            except ValueError as exc:
                raise BearingStateError(f"thermal model: {exc}") from None
            fy, fz = fy * factor, fz * factor
            tangent = None if tangent is None else tuple(factor * t for t in tangent)
        else:
            heat = (self.T_supply, params.mu, 0.0, 0.0)
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
        self.T_eff, self.mu_eff, self.P_loss, self.Q_side = heat
        if tangent is not None:
            (self.Kyy, self.Kyz, self.Kzy, self.Kzz, self.Cyy, self.Cyz, self.Czy, self.Czz) = tangent
        if pending:
            self._excursion(pending[-1])

    def _warn(self, msg: str) -> None:
        """The internal's warnings: during an evaluation (the domain guard's, when an excursion
        begins) kept until the evaluation is committed, so a refused state warns nothing; else logged."""
        if self._pending is not None:
            self._pending.append(msg)
        else:
            self._log(f"t = {self._t:.10g} s: {msg}", Fmi2Status.warning)

    def _excursion(self, msg: str) -> None:
        """Log the warning of an excursion out of the fitted domain and count it; a host's Newton
        iterates of one step (each restored to the step's start) begin the same one."""
        n, first, last = self._excursions
        if n and last == self._t:
            return
        self._excursions = (n + 1, self._t if n == 0 else first, self._t)
        self._log(f"t = {self._t:.10g} s: {msg}", Fmi2Status.warning)

    # ------------------------------------------------------------------ FMU state
    # A host iterating the FMI way saves the state once per step and restores it at every
    # iteration, so both run in C where they can (attrgetter, dict.update): a state this
    # class wrote holds the right types already.
    def _get_fmu_state(self):
        # a new FMUState each time: pythonfmu hands this very object back on fmi2SetFMUstate, and
        # once the master frees it, it stays recognisable (fmi_order.FMUState)
        return FMUState((_STATE_TAG, self._t, _STATE_VALUES(self)))

    def _set_fmu_state(self, state):
        try:
            if is_freed(state):
                raise ValueError("this FMU state was freed (fmi2FreeFMUstate)")
            if len(state) != 3 or state[0] != _STATE_TAG or len(state[2]) != len(_STATE_NAMES):
                raise ValueError(f"not a {_STATE_TAG} state of this FMU")
            t = float(state[1])
        except Exception as exc:  # noqa: BLE001
            return self._fail(f"setFMUstate: {exc}; the instance keeps its state")
        self._t = t
        self.__dict__.update(zip(_STATE_NAMES, state[2]))
        self._discarded = None  # a restored state may be stepped with any inputs

    # pythonfmu calls these on the class (fmi2SerializedFMUstateSize, fmi2SerializeFMUstate,
    # fmi2DeSerializeFMUstate); a refusal raises (fmi2Error)
    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        if is_freed(state):
            raise FMIError("serializing an FMU state: this FMU state was freed (fmi2FreeFMUstate)")
        return json.dumps(list(state)).encode("utf-8")

    @staticmethod
    def _fmu_state_from_bytes(data: bytes):
        return FMUState(json.loads(data.decode("utf-8")))

    # ------------------------------------------------------------------ getters / setters
    def _get(self, vrs, typ, cast, bad):
        self._order(f"get{typ}")
        out, errors, computed = [], [], False
        for vr in vrs:
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                errors.append(f"value reference {vr} is not a {typ} variable of this FMU")
                out.append(bad)
                continue
            if entry[2] == OUTPUT and self._mode is INIT and not computed:
                self._outputs_in_init(f"get{typ} {entry[0]}")  # raises when they cannot be computed
                computed = True
            try:
                out.append(cast(getattr(self, entry[0])))
            except Exception as exc:  # noqa: BLE001
                errors.append(f"{entry[0]}: {exc}")
                out.append(bad)
        if errors:
            self._fail(f"get{typ}: {'; '.join(errors)}")
        return out

    def _set(self, vrs, values, typ, cast):
        self._order(f"set{typ}")
        errors = []
        for vr, value in zip(vrs, values):
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                errors.append(f"value reference {vr} is not a {typ} variable of this FMU")
                continue
            name, _, causality = entry
            if causality == OUTPUT:
                errors.append(f"{name} is an output and cannot be set")
                continue
            if causality == PARAMETER:
                if self._initialized:
                    errors.append(f"parameter {name} is fixed after initialisation (variability fixed); "
                                  f"it keeps {getattr(self, name)!r}")
                    continue
                try:
                    value = self._check_parameter(name, cast(value))
                except (ValueError, TypeError) as exc:
                    self._refused[name] = f"{exc} (refused when it was set)"
                    errors.append(f"{exc}; {name} keeps {getattr(self, name)!r}")
                    continue
                self._refused.pop(name, None)
            try:
                setattr(self, name, cast(value))
            except Exception as exc:  # noqa: BLE001
                errors.append(f"{name} = {value!r}: {exc}")
        if errors:
            self._fail(f"set{typ}: {'; '.join(errors)}")

    @staticmethod
    def _check_parameter(name: str, value):
        """The value of parameter ``name``, or ValueError naming it, the value and what is allowed.
        What one value can be checked alone is checked here; BearingParams and the internal
        check the whole set when it is built."""
        if name == "internal":
            registry.get(value)
        elif name in ENUMERATIONS:
            items = ENUMERATIONS[name][1]
            if not 1 <= value <= len(items):
                raise ValueError(f"{name} = {value!r} must be one of "
                                 + ", ".join(f"{k + 1} ({c})" for k, c in enumerate(items)))
        elif name in BEARING_FIELDS:  # BearingParams checks them together at initialisation
            if not (0.0 < value < _INF):
                raise ValueError(f"{name} = {value!r} {_UNITS[name]} must be finite and > 0")
        elif name in _OPTIONS:
            value = _OPTIONS[name].check(value)
        elif name == "oil_law":
            if str(value).strip().lower() not in ports.OIL_LAWS:
                raise ValueError(f"oil_law = {value!r} must be one of {', '.join(ports.OIL_LAWS)}")
        elif name in ports.PARAMETER_NAMES:
            value = ports.check_value(name, value)
        return value

    def get_real(self, vrs):
        try:  # fast path: every reference a Real variable (the host's per-iteration call)
            names = self._real_get
            return [float(getattr(self, names[vr])) for vr in vrs]
        except Exception:  # noqa: BLE001 - the checked path computes outputs in Initialization Mode, or refuses
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
        except Exception:  # noqa: BLE001 - the checked path applies the rules and refuses
            self._set(vrs, values, "Real", float)

    def set_integer(self, vrs, values):
        self._set(vrs, values, "Integer", int)

    def set_boolean(self, vrs, values):
        self._set(vrs, values, "Boolean", bool)

    def set_string(self, vrs, values):
        self._set(vrs, values, "String", str)
