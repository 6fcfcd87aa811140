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

A pythonfmu FMU runs its slave in this interpreter: a Ctrl-C raised inside it would come back
as an FMI error, so signals are held while an FMU call runs (``bearing_fmu.io.exits.deferred``)
and raised as ``Interrupted`` right after it.
"""

from __future__ import annotations

import ctypes
import shutil
import tempfile
from pathlib import Path

import numpy as np

from bearing_fmu.io.exits import deferred, enter_deferred, leave_deferred

from .bearings import BearingSet

# what the host reads from every bearing FMU, in this order
_OUT = ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz", "eccentricity")
_IN = ("y", "z", "vy", "vz", "omega")
_STATIC_PROBE_S = 1e-9  # doStep length of a static evaluation [s], never committed
_FMI_STATUS = ("ok", "warning", "discard", "error", "fatal", "pending")


class FMUError(RuntimeError):
    """A bearing FMU could not be loaded, set up or initialised."""


class FMUBearings(BearingSet):
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
        from fmpy import calloc, extract, free, read_model_description
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
        self._unzip = tempfile.mkdtemp(prefix="bearing_fmu_")
        self.instances = []
        self._states = [None] * self.n
        self._static = False
        self._h = 0.0
        self._fresh = [False] * self.n
        self._initialised = set()  # instances past exitInitializationMode: only those are terminated (FMI 2.0)
        try:
            md = read_model_description(str(self.fmu_path))
            self._vars = {v.name: v for v in md.modelVariables}
            missing = [n for n in _IN + _OUT if n not in self._vars]
            if missing:
                raise FMUError(f"{self.fmu_path.name} lacks the variable(s) {', '.join(missing)}: not a bearing FMU?")
            extract(str(self.fmu_path), self._unzip)

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
        except BaseException:
            self.close()
            raise

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
            if self._fresh[k]:  # the instance still is in the state just saved: no restore needed
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
        with deferred():
            for k, fmu in enumerate(self.instances):
                if self._states[k] is not None:
                    fmu.setFMUstate(self._states[k])
                self._fresh[k] = False
            self._free_states()

    def _free_states(self) -> None:
        with deferred():
            for k, fmu in enumerate(self.instances):
                if self._states[k] is not None:  # raw call, status checked here (once per step)
                    self._check(k, "fmi2FreeFMUstate",
                                fmu.dll.fmi2FreeFMUstate(fmu.component, ctypes.byref(self._states[k])))
                    self._states[k] = None

    def close(self) -> None:
        """Terminate and free every instance and remove the extracted FMU (idempotent; a second
        Ctrl-C waits until this is done)."""
        with deferred():
            self._close()

    def _close(self) -> None:
        for k, fmu in enumerate(self.instances):
            try:
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
        if getattr(self, "_unzip", None):
            shutil.rmtree(self._unzip, ignore_errors=True)
            self._unzip = None
