"""The fmpy master: one bearing FMU instance per bearing, iterated the FMI 2.0 way.

Per time step each instance's state is saved once (fmi2GetFMUstate); every Newton iteration
then restores it (fmi2SetFMUstate), sets the journal state for the end of the step, calls
doStep and reads the force and the local tangent. FMI 2.0 co-simulation forbids reading
outputs after setting inputs without a doStep in between, so this is the conformant way to
iterate inside a step, and the force is always consistent with the iterate.

A discarded doStep (the FMU logs why, e.g. "eccentricity ratio 1.03 >= 1") becomes
``StepRejected`` so the integrator cuts the step; only fmi2Discard does: an error or fatal
status is an ``FMUError`` that stops the run, as is an FMU that cannot be instantiated (the
error quotes the FMU's own log lines: fmpy says only "Failed to instantiate model"). Every
instance is freed on success and on error (use ``FMUBearings`` as a context manager or call ``close``).

An FMU that declares itself memoryless (a vendor annotation in its model description,
``bearing_fmu.fmu.meta.memoryless_annotation``, written by the native and the Python builds for
the map and linear internals; not with the thermal model on) has no state worth restoring: for
it the iteration is setReal, doStep, getReal with no FMU state saved or restored, which gives the
same outputs, and the integrator's compiled loop makes these calls itself (``compiled``,
``rotor_host.coupling.fmu_kernel``; for the Python FMU its C entry points run the slave's Python).
A step the compiled loop hands back after a discard is asked again from Python at the same
inputs: each instance is restored to its own state first (``_leave_compiled``), since an FMU
refuses an unchanged retry after a discard. Any other FMU keeps the save and restore; when it can get and set its state and
needs no execution tool (a native Taylor or Reynolds FMU, a foreign compiled one) the compiled
loop makes those calls too, in the same order (the kernels hand each step's saved state to the
Python driver and back between chunks: ``compiled``); the Python FMU of another internal (it
needs an execution tool: Python) is iterated from Python.

An FMU that declares states of its own over a step for the internal chosen (a tilting pad's tilts and
rates) waits in Initialization Mode through the static equilibrium (``init_statics``).

A pythonfmu FMU runs its slave in this interpreter: a Ctrl-C raised inside it would come back
as an FMI error, so signals are held while an FMU call runs (``bearing_fmu.io.interrupts.deferred``)
and raised as ``Interrupted`` right after it.
"""

from __future__ import annotations

import atexit
import ctypes
import shutil
import tempfile
from pathlib import Path

import numpy as np

from bearing_fmu.io.interrupts import deferred, enter_deferred, leave_deferred

from .bearings import THERMAL_FIELDS, BearingSet
from .fmu_kernel import free_saved, fmu_force, restore_saved
from .init_statics import InitStatics

# what the host reads from every bearing FMU, in this order
_OUT = ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz", "eccentricity")
_IN = ("y", "z", "vy", "vz", "omega")
_STATIC_PROBE_S = 1e-9  # doStep length of a static evaluation [s], never committed
_FMI_STATUS = ("ok", "warning", "discard", "error", "fatal", "pending")


_EXTRACTED: dict[tuple, str] = {}  # (FMU file, modification time, size) -> its extraction


def extracted(fmu_path: Path) -> str:
    """The folder of the FMU extracted, once per process while the file is unchanged: a sweep's
    worker (or a script's loop) instantiates the same FMU for run after run, and extracting it
    and the slave reading its resources afresh each time cost ~0.1-0.3 s per run. The folders
    are removed when the process exits (``remove_extracted``)."""
    st = fmu_path.stat()
    key = (str(fmu_path.resolve()), st.st_mtime_ns, st.st_size)
    folder = _EXTRACTED.get(key)
    if folder is None or not Path(folder).is_dir():
        from fmpy import extract

        folder = tempfile.mkdtemp(prefix="bearing_fmu_")
        try:
            extract(str(fmu_path), folder)
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise
        if not _EXTRACTED:
            atexit.register(remove_extracted)
        _EXTRACTED[key] = folder
    return folder


def remove_extracted() -> None:
    """Remove every FMU extraction of this process (at its exit; the instances are freed by then)."""
    while _EXTRACTED:
        shutil.rmtree(_EXTRACTED.popitem()[1], ignore_errors=True)


class FMUError(RuntimeError):
    """A bearing FMU could not be loaded, set up or initialised."""


class FMUBearings(InitStatics, BearingSet):
    """Bearings as FMU instances (fmpy ``FMU2Slave``), conformant iteration per step.

    fmu_path      : the bearing .fmu (extracted once, shared by all instances)
    bearing_dofs  : (dof_y, dof_z) per bearing
    omega         : shaft speed [rad/s]
    parameters    : one dict per bearing, FMU parameter name -> value (D, L, CR, mu, internal,
                    surrogate, n_theta, ...); unknown names raise FMUError listing the known ones.
                    Inputs may be given too (T_supply, a start state): set in Initialization Mode,
                    where the thermal model's T_eff starts (docs/fmu.md)
    """

    lund_sign = True  # the FMU outputs K, C

    def __init__(self, fmu_path, bearing_dofs, omega: float, parameters, names=None,
                 start_time: float = 0.0, log=None, tangent: str = "bearing"):
        super().__init__(bearing_dofs, omega, names, tangent)
        from fmpy import calloc, free, read_model_description
        from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

        if len(parameters) != self.n:
            raise ValueError(f"FMUBearings: {len(parameters)} parameter sets for {self.n} bearings")
        if not self.with_jacobian:  # nobody reads K, C: the FMUs need not compute them
            parameters = [{"compute_tangent": False, **p} for p in parameters]
        self.clearances = [float(p["CR"]) if "CR" in p else None for p in parameters]
        self.fmu_path = Path(fmu_path)
        if not self.fmu_path.is_file():
            raise FileNotFoundError(f"bearing FMU {self.fmu_path} not found; build it with `bearing-fmu build -o PATH.fmu`")
        self.log = log  # optional callable(str) for every FMU log line
        self.messages: list[list[str]] = [[] for _ in range(self.n)]
        self._unzip = None
        self.instances = []
        self._states = [None] * self.n
        self._static = False
        self._h = 0.0
        self._fresh = [False] * self.n
        self.memoryless = False  # set below: the FMU declares no state worth restoring
        self._clock = np.zeros(2)  # (t, h) of the step, read by the compiled kernels
        self._kernels = None
        self._saved = None  # (n, 2): each stateful kernel's FMU state and the step it saved it for
        self.stateful_compiled = False  # set below: the compiled loop may save and restore its states
        self._initialised = set()  # instances past exitInitializationMode: only those are terminated (FMI 2.0)
        self._in_init = False  # the instances wait in Initialization Mode (init_statics)
        try:
            md = read_model_description(str(self.fmu_path))
            self._vars = {v.name: v for v in md.modelVariables}
            missing = [n for n in _IN + _OUT if n not in self._vars]
            if missing:
                raise FMUError(f"{self.fmu_path.name} lacks the variable(s) {', '.join(missing)}: not a bearing FMU?")
            self._unzip = extracted(self.fmu_path)

            def make_logger(k):
                def logger(component, instance_name, status, category, message):
                    text = message.decode("utf-8", "replace") if message else ""
                    label = _FMI_STATUS[status] if 0 <= status < len(_FMI_STATUS) else str(status)
                    self.messages[k].append(f"[{label}] {text}")
                    if self.log is not None:
                        self.log(f"{self.names[k]} [{label}] {text}")
                return logger

            # ctypes callbacks must outlive the instances: keep references
            self._callbacks = []
            for k in range(self.n):
                cb = fmi2CallbackFunctions()
                cb.logger = fmi2CallbackLoggerTYPE(make_logger(k))
                cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
                cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
                self._callbacks.append(cb)
                fmu = FMU2Slave(guid=md.guid, unzipDirectory=self._unzip,
                                modelIdentifier=md.coSimulation.modelIdentifier,
                                instanceName=self.names[k].replace(" ", "_"))
                with deferred():  # loading and initialising run the slave's Python
                    try:
                        fmu.instantiate(callbacks=cb, loggingOn=True)
                    except Exception as exc:  # noqa: BLE001 - fmpy says only "Failed to instantiate model"
                        raise FMUError(self._instantiate_failed(k, exc)) from None
                    self.instances.append(fmu)
                    try:
                        params = {n: v for n, v in parameters[k].items()
                                  if getattr(self._vars.get(n), "causality", None) != "input"}
                        self._set_parameters(k, fmu, params)
                        fmu.setupExperiment(startTime=start_time)
                        fmu.enterInitializationMode()
                        for n, v in parameters[k].items():
                            if n not in params:
                                fmu.setReal([self._vars[n].valueReference], [float(v)])
                        if k == 0:
                            self._in_init = self._declared_stepped(md, parameters)
                        if not self._in_init:
                            fmu.exitInitializationMode()
                            self._initialised.add(k)
                    except FMUError:
                        raise
                    except Exception as exc:  # noqa: BLE001 - fmpy raises on an error status; say why
                        errors = [m for m in self.messages[k] if m.startswith(("[error]", "[fatal]"))]
                        raise FMUError(f"{self.names[k]}: FMU initialisation failed: "
                                       f"{errors[-1] if errors else exc}") from None
                errors = [m for m in self.messages[k] if m.startswith(("[error]", "[fatal]"))]
                if errors:
                    raise FMUError(f"{self.names[k]}: FMU initialisation failed: {errors[-1]}")
            # value references and ctypes buffers, built once: no allocation per iteration
            self._vr_in = (ctypes.c_uint * len(_IN))(*[self._vars[n].valueReference for n in _IN])
            self._vr_out = (ctypes.c_uint * len(_OUT))(*[self._vars[n].valueReference for n in _OUT])
            self._buf_in = (ctypes.c_double * len(_IN))()
            self._buf_out = (ctypes.c_double * len(_OUT))()
            self._out = np.frombuffer(self._buf_out, dtype=np.float64)
            self._f_view = self._out[0:2]
            self._dq_view = self._out[2:6].reshape(2, 2)
            self._dv_view = self._out[6:10].reshape(2, 2)
            self.memoryless = self._declared_memoryless(parameters)
            cs = md.coSimulation
            self.stateful_compiled = bool(cs.canGetAndSetFMUstate and not cs.needsExecutionTool)
            if self.n and all(str(p.get("thermal", "")).strip().lower() in ("true", "1", "1.0") for p in parameters):
                # its thermal ports on: T_eff, mu_eff, P_loss, Q_side are outputs (no inflow)
                self.thermal_fields = THERMAL_FIELDS[:4]
                self._vr_thermal = (ctypes.c_uint * 4)(*[self._vars[n].valueReference for n in self.thermal_fields])
                self._buf_thermal = (ctypes.c_double * 4)()
        except BaseException:
            self.close()
            raise

    def _declared_memoryless(self, parameters) -> bool:
        """Whether every instance, as set up by ``parameters``, has no state worth restoring: the
        model description declares the chosen internal memoryless and none of the Boolean
        parameters it names in ``unless`` is true (``bearing_fmu.fmu.meta.memoryless_declaration``)."""
        from bearing_fmu.fmu.meta import memoryless_declaration

        declared = memoryless_declaration((Path(self._unzip) / "modelDescription.xml").read_bytes())
        if declared is None:
            return False
        internals, unless = declared
        for k, p in enumerate(parameters):
            if self._internal_chosen(k, p) not in internals:
                return False
            for name in unless:
                var = self._vars.get(name)
                value = p.get(name, var.start if var is not None else None)
                if str(value).strip().lower() in ("true", "1", "1.0"):
                    return False
        return True

    def _internal_chosen(self, k, p) -> str:
        """The internal bearing k computes: the parameter ``internal`` as set (else its start),
        a String, or an enumeration's number or item name."""
        var = self._vars.get("internal")
        if var is None:
            return ""
        value = p.get("internal", var.start)
        if var.type == "Enumeration":
            number = self._enum_value(k, var, value) if isinstance(value, str) and not value.strip().isdigit() \
                else int(value)
            return next((i.name.lower() for i in var.declaredType.items if int(i.value) == number), "")
        return str(value).strip().lower()

    def _instantiate_failed(self, k: int, exc: Exception) -> str:
        """Why fmi2Instantiate returned no instance: the FMU's own log lines of it (the logger got
        them; fmpy's exception does not carry them), else fmpy's words."""
        lines = [m for m in self.messages[k] if not m.startswith("[ok]")] or [f"{exc} (the FMU logged nothing)"]
        return (f"{self.names[k]}: {self.fmu_path.name} could not be instantiated (fmi2Instantiate returned no "
                f"instance): {' | '.join(lines)}")

    def _set_parameters(self, k, fmu, params: dict) -> None:
        for name, value in params.items():
            var = self._vars.get(name)
            if var is None or var.causality != "parameter":
                known = sorted(v.name for v in self._vars.values() if v.causality == "parameter")
                raise FMUError(f"{self.names[k]}: {name!r} is not a parameter of {self.fmu_path.name}; "
                               f"parameters: {', '.join(known)}")
            vr = [var.valueReference]
            if var.type == "Real":
                fmu.setReal(vr, [float(value)])
            elif var.type == "Integer":
                fmu.setInteger(vr, [int(value)])
            elif var.type == "Enumeration":  # FMI 2.0: Integer-valued; given by its number or its item's name
                fmu.setInteger(vr, [self._enum_value(k, var, value)])
            elif var.type == "Boolean":
                fmu.setBoolean(vr, [bool(value)])
            else:
                fmu.setString(vr, [str(value)])

    def _enum_value(self, k, var, value) -> int:
        """The number of an enumeration parameter's value (a number, or an item's name)."""
        if isinstance(value, str):
            items = {i.name.lower(): int(i.value) for i in var.declaredType.items}
            if value.strip().lower() not in items:
                raise FMUError(f"{self.names[k]}: {var.name} = {value!r} is not an item of {self.fmu_path.name}'s "
                               f"{var.declaredType.name}; items: {', '.join(f'{n} = {v}' for n, v in items.items())}")
            return items[value.strip().lower()]
        return int(value)

    # -- NodalForce protocol -----------------------------------------------------------
    def begin_step(self, t: float, dt: float) -> None:
        super().begin_step(t, dt)
        # dt = 0 marks static evaluations (the rotor's static equilibrium): FMI 2.0 wants a
        # positive step, so probe with a tiny one and never commit it (accept restores t)
        self._static = dt == 0.0
        self._h = _STATIC_PROBE_S if self._static else self.dt
        if self._in_init:
            if self._static:  # evaluated in Initialization Mode: nothing to save or restore
                return
            self._leave_init()
        if self.memoryless:  # nothing to save: every iterate is setReal, doStep, getReal
            return
        with deferred():
            for k, fmu in enumerate(self.instances):
                c, dll = fmu.component, fmu.dll
                if self._states[k] is not None:
                    self._check(k, "fmi2FreeFMUstate", dll.fmi2FreeFMUstate(c, ctypes.byref(self._states[k])))
                state = ctypes.c_void_p()
                self._check(k, "fmi2GetFMUstate", dll.fmi2GetFMUstate(c, ctypes.byref(state)))
                self._states[k] = state
                self._fresh[k] = True

    def _bearing(self, k, y, z, vy, vz):
        # The raw ctypes functions (fmpy sets their argtypes) with buffers built once: fmpy's
        # checking wrappers and per-call numpy temporaries cost about as much as the four FMI
        # calls themselves (benchmarks/bench_fmi_calls.py), so the status is checked here.
        fmu = self.instances[k]
        c, dll = fmu.component, fmu.dll
        enter_deferred()  # a signal waits until the FMU has returned (module docstring)
        try:
            if self._in_init:  # a static evaluation (begin_step leaves Initialization Mode for a time step)
                return self._init_bearing(k, y, z, vy, vz)
            if self._fresh[k] or self.memoryless:  # the instance is in the state saved, or has none
                self._fresh[k] = False
            else:
                self._check(k, "fmi2SetFMUstate", dll.fmi2SetFMUstate(c, self._states[k]))
            b = self._buf_in
            b[0], b[1], b[2], b[3], b[4] = y, z, vy, vz, self.omega
            self._check(k, "fmi2SetReal", dll.fmi2SetReal(c, self._vr_in, len(_IN), b))
            n_msg = len(self.messages[k])
            status = dll.fmi2DoStep(c, self.t, self._h, 0)
            if status == 2:  # discard: the FMU refused this state and logged why; cut the step
                new = self.messages[k][n_msg:]
                raise self._reject(k, new[-1] if new else "fmi2DoStep returned discard")
            self._check(k, "fmi2DoStep", status)  # error / fatal: not a refused step, a failure
            self._check(k, "fmi2GetReal", dll.fmi2GetReal(c, self._vr_out, len(_OUT), self._buf_out))
        finally:
            leave_deferred()
        o = self._out
        if o[10] > self.max_eccentricity[k]:
            self.max_eccentricity[k] = o[10]
        # Views of the output buffer, copied by the caller (BearingSet.evaluate) before the
        # next call; K, C in Lund's sign as the FMU gives them (lund_sign: evaluate negates).
        if not self.with_jacobian:
            return self._f_view, None, None
        return self._f_view, self._dq_view, self._dv_view

    def compiled(self):
        """(forces, omega, clock, handover) for the integrator's compiled loop: each instance's
        setReal, doStep, getReal (and, for an FMU that is not memoryless, its state saved and
        restored as in ``begin_step`` and ``_bearing``) as a compiled kernel
        (``fmu_kernel.fmu_force``), when the FMU is memoryless or ``stateful_compiled`` and each
        bearing's own tangent is used at a constant speed; else None (the Python driver).
        ``handover`` = (enter, leave): called by the compiled driver around every chunk."""
        if (not (self.memoryless or self.stateful_compiled) or self.speed is not None or self.tangent != "bearing"
                or not self.with_jacobian):
            return None
        if self._in_init:  # the kernels step: the instances leave Initialization Mode first
            self._leave_init()
        if self._kernels is None:
            vr_in = [self._vars[n].valueReference for n in _IN]
            vr_out = [self._vars[n].valueReference for n in _OUT]
            if not self.memoryless:
                self._saved = np.zeros((self.n, 2))
                self._saved[:, 1] = np.nan
            self._kernels = tuple(fmu_force(fmu.dll, self._address(fmu), vr_in, vr_out, self._clock,
                                            self.max_eccentricity, k, None if self._saved is None else self._saved[k])
                                  for k, fmu in enumerate(self.instances))
        return self._kernels, self.omega, self._clock, (self._enter_compiled, self._leave_compiled)

    @staticmethod
    def _address(fmu) -> int:
        return fmu.component.value if hasattr(fmu.component, "value") else fmu.component

    def _enter_compiled(self) -> None:
        """Before a compiled chunk: a step the Python driver opened (the run's first, whose bracket
        evaluated the initial state) is redone by the chunk from its start: its saved state
        restored and freed, so the kernels save the step's start themselves."""
        if self._saved is None:
            return
        with deferred():
            for k, fmu in enumerate(self.instances):
                if self._states[k] is not None and not self._fresh[k]:
                    self._check(k, "fmi2SetFMUstate", fmu.dll.fmi2SetFMUstate(fmu.component, self._states[k]))
            self._free_states()
            self._fresh = [False] * self.n

    def _leave_compiled(self, gave_back: bool) -> None:
        """After a compiled chunk: when it gave a step back (a discard, a Newton failure), each
        instance back at that step's start (the state its kernel saved), where the Python driver
        redoes the step from, with that state saved as ``begin_step`` saves it (the run's first
        step is redone without a ``begin_step``: its bracket was opened before the chunk); the
        kernels save afresh at their next step. A memoryless instance is restored to its own state
        (got and set back: nothing else changes for it): the Python driver asks the step again from
        its start at the same inputs, and an FMU refuses an unchanged retry after a discard unless
        a restored state says the master retries on purpose."""
        if self.memoryless:
            if gave_back:
                with deferred():
                    for k, fmu in enumerate(self.instances):
                        c, dll = fmu.component, fmu.dll
                        state = ctypes.c_void_p()
                        self._check(k, "fmi2GetFMUstate", dll.fmi2GetFMUstate(c, ctypes.byref(state)))
                        self._check(k, "fmi2SetFMUstate", dll.fmi2SetFMUstate(c, state))
                        self._check(k, "fmi2FreeFMUstate", dll.fmi2FreeFMUstate(c, ctypes.byref(state)))
            return
        if self._saved is None:
            return
        with deferred():
            for k, fmu in enumerate(self.instances):
                status = restore_saved(fmu.dll, fmu.component, self._saved[k], self._clock[0] if gave_back else None)
                self._check(k, "fmi2SetFMUstate", status)
        if gave_back:
            self.begin_step(self._clock[0], self._clock[1])

    def thermal_record(self) -> np.ndarray:
        """The thermal outputs of each instance's last doStep (an fmi2GetReal per instance)."""
        if not self.thermal_fields:
            return super().thermal_record()
        out = np.empty((self.n, len(self.thermal_fields)))
        with deferred():
            for k, fmu in enumerate(self.instances):
                status = fmu.dll.fmi2GetReal(fmu.component, self._vr_thermal, 4, self._buf_thermal)
                self._check(k, "fmi2GetReal", status)
                out[k] = self._buf_thermal
        return out

    @staticmethod
    def _status_name(status: int) -> str:
        return _FMI_STATUS[status] if 0 <= status < len(_FMI_STATUS) else str(status)

    def _check(self, k: int, call: str, status: int) -> None:
        if status > 1:
            new = self.messages[k][-1:] or [""]
            raise FMUError(f"{self.names[k]}: {call} returned {self._status_name(status)} at t = {self.t:.6g} s "
                           f"{new[0]}".rstrip())

    def accept_step(self) -> None:
        if self._static:
            self.reject_step()
        else:
            self._free_states()

    def reject_step(self) -> None:
        if self._in_init:  # nothing saved: each evaluation there stands alone
            return
        with deferred():
            for k, fmu in enumerate(self.instances):
                if self._states[k] is not None:
                    fmu.setFMUstate(self._states[k])
                self._fresh[k] = False
            self._free_states()

    def _free_states(self) -> None:
        if self.memoryless:  # its one state serves the whole run (begin_step); freed at close
            return
        with deferred():
            for k, fmu in enumerate(self.instances):
                if self._states[k] is not None:  # raw call, status checked here (once per step)
                    self._check(k, "fmi2FreeFMUstate",
                                fmu.dll.fmi2FreeFMUstate(fmu.component, ctypes.byref(self._states[k])))
                    self._states[k] = None

    def close(self) -> None:
        """Terminate and free every instance (idempotent; a second Ctrl-C waits until this is
        done). The extracted FMU stays for this process's next run of it (``extracted``)."""
        with deferred():
            self._close()

    def _close(self) -> None:
        for k, fmu in enumerate(self.instances):
            try:
                if self._saved is not None:  # a compiled kernel's FMU state
                    free_saved(fmu.dll, fmu.component, self._saved[k])
                if self._states[k] is not None:
                    fmu.freeFMUstate(self._states[k])
                    self._states[k] = None
                if k in self._initialised:  # else fmi2Terminate is out of order: an error in the log
                    fmu.terminate()
            except Exception:  # noqa: BLE001 - free what can be freed
                pass
            try:
                fmu.freeInstance()
            except Exception:  # noqa: BLE001
                pass
        self.instances = []
        self._unzip = None  # the extraction stays for this process's next run of the FMU (``extracted``)
