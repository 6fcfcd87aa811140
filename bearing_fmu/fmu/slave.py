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
* a non-finite input is refused by setReal (the input keeps its value); a doStep whose
  currentCommunicationPoint is not where the last step ended raises, unless the internal is
  memoryless (``variables.MEMORYLESS``, thermal off: any point, as the model description declares);
* a state the internal cannot evaluate (journal at the wall, another speed than a linear
  model's) discards the step: ``do_step`` logs why (status Discard) and returns False; the
  outputs keep their last valid values and the instance stays usable (restore a state, set
  valid inputs, step on). fmi2Terminated stays false (patched binary: pythonfmu set it at every
  discard); a doStep again at the same refused inputs, bit for bit, raises (a master retrying
  unchanged would loop);
* outputs read in Initialization Mode are computed from the inputs and parameters set so far.

Without the patches (``resources/pythonfmu_patches.json`` says which are in; the Windows
binary is pythonfmu's as is) nothing raises: a refused call is logged with status Error and
returns fmi2OK, as pythonfmu allows. When the master has logging off, the first warning, the
first discard and the first error of an instance are also printed to stderr (``LoggingFlag``).

The FMU state (fmi2GetFMUstate) is a small list (tag, time, inputs and outputs, and the internal's
states of its own over a step: a tilting pad's tilts and rates, ``Capabilities.step_states``;
``fmi_order.FMUState``: recognised once freed); the internal itself is not part of it (it is fixed
after initialisation), so saving and restoring costs a few microseconds; serialised, it carries a
checksum, and a state read back is checked (``pyslave/state.py``). Such an internal's states start
at rest at the inputs of Initialization Mode (its outputs there are the quasi-static answer) and each
doStep advances them from the committed ones (docs/fmu.md, *Tilting pads*). A memoryless internal with a
compiled kernel (``internals.compiled``) is evaluated through it in a step: the same numbers as
``force_and_jacobian`` at a third of its cost (``benchmarks/python_fmu_step.py``). A Taylor internal's
domain warning comes once per excursion and the count at terminate (``_excursion``).

This module is the class and its life cycle (instantiate, initialise, terminate); its parts are in
``fmu/pyslave/`` by responsibility: the calling sequence, refusals and logging (``calls``), the
variables (``access``), the internal and the steps with the thermal ports (``stepping``), the
FMU state (``state``). In the FMU this file is the pythonfmu slave module: ``build.py`` rewrites
its imports to the uniquely named copy of the package, which holds the parts (see there).
"""

import math

from pythonfmu import Fmi2Slave
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from bearing_fmu import __version__
from bearing_fmu.fmu.order import INIT, INSTANTIATED, STEP, TERMINATED
from bearing_fmu.fmu.pyslave.access import VariableAccess
from bearing_fmu.fmu.pyslave.calls import CallRules, FMIError  # noqa: F401 - FMIError: what a refusal raises
from bearing_fmu.fmu.pyslave.state import STATE_NAMES, StateSaving
from bearing_fmu.fmu.pyslave.stepping import Stepping
from bearing_fmu.fmu.resources import BEARING_DEFAULTS, BUILD_INFO, PATCH_NOTES  # noqa: F401 - build.py reads them here
from bearing_fmu.fmu.resources import LoggingFlag, status_patched
from bearing_fmu.fmu.variables import ENUMERATIONS, VARIABLES, enum_value  # noqa: F401 - VARIABLES: build.py's
from bearing_fmu.internals import warmup
from bearing_fmu.internals.registry import BearingStateError

_STATE_NAMES = STATE_NAMES  # the inputs and outputs an FMU state holds (tests read them here)
_INF = math.inf


class BearingFMU(VariableAccess, Stepping, StateSaving, CallRules, Fmi2Slave):
    """Hydrodynamic journal bearing: film force from the journal state (see module docstring)."""

    description = ("Hydrodynamic journal bearing (plain cylindrical, grooved, partial arc, lobed or tilting pads): "
                   "film force on the journal from its position, velocity and speed; internal: Reynolds solver, "
                   "linear model, Taylor surrogate, force map or tilting pads (their tilts states of the FMU)")
    version = __version__
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=0.1, step_size=1e-4)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        warmup.announce_compiling()  # the kernels' first compilation in this process: a line on stderr
        self._register_variables()
        self._internal = None  # built in exit_initialization_mode (or by an output read in Initialization Mode)
        self._built_from = None  # the parameter values it was built from
        self._internal_name = ""
        self._choices_built = {}  # the String choices the internal was built with (_choices)
        self._jacobian = None
        self._kernel = None  # the internal's compiled kernel, when a step may call it (stepping._kernel_of)
        self._peak = None  # the internal's peak_pressure (Capabilities.film_field), set with the internal
        self._stepped = None  # the internal when it has states of its own over a step (Capabilities.step_states)
        self._pad_report = None  # the internal's pad_report (tilts, loads) when it takes tilting pads
        self._params = None
        self._oil = None  # the oil law of the thermal model, when thermal is true (ports.py)
        self._enter(INSTANTIATED)
        self._initialized = False  # exit_initialization_mode was called: parameters are fixed
        self._init_error = None
        self._refused = {}  # parameter name -> why its last set was refused (fails the initialisation)
        self._discarded = None  # the inputs of the last discarded step (None after a good one)
        self._refused_t = 0.0  # where that step started [s]
        self._memoryless = False  # the internal built is memoryless (variables.MEMORYLESS) with thermal off
        self._t = 0.0
        self._raises = status_patched(self.resources)  # an exception gives fmi2Error, not fmi2Fatal
        # the logger's layout is known for the binary the patches verified, and only for that one
        self._logging = LoggingFlag(kwargs.get("logger") if self._raises else None, self.instance_name)
        self._echoed = set()
        self._guard = None  # the internal when it is a domain guard (excursions out of the fitted domain)
        self._pending = None  # during an evaluation: the domain guard's warnings, logged if it is committed
        self._excursions = (0, 0.0, 0.0)  # out of the fitted domain (one warning each): count, first t, last t

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
