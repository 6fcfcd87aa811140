"""The slave's evaluation: the internal built from the parameters (once, at the end of
initialisation, or for an output read in Initialization Mode), doStep (a refused state
discards the step, a failure of the internal is an error), the outputs with the thermal ports
(``fmu.ports``: the film at its effective viscosity), and the domain guard's warnings, once per
excursion."""

import math
import os
from pathlib import Path

import numpy as np
from pythonfmu.enums import Fmi2Status

from ...internals import registry
from ...internals.registry import BearingStateError, Context
from ...physics.params import BearingParams
from .. import ports
from ..order import INIT, STEP, refusal
from ..resources import SURROGATE_DIR
from .access import FILE_OPTIONS
from ..variables import ENUMERATIONS, INPUTS, PARAMETERS, enum_value

_INF = math.inf


class Stepping:
    """The internal and the steps of ``slave.BearingFMU``."""

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
        ports.check_pad_thermal(self.thermal, geometry)
        oil = ports.oil_of(self, choices["oil_law"], grooved=bool(geometry.circumferential_groove))
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
        self._memoryless = spec.can.memoryless and not self.thermal  # any currentCommunicationPoint
        self._jacobian = getattr(internal, "force_and_jacobian", None)
        self._guard = internal if hasattr(internal, "outside") else None  # a domain guard: its excursion flag
        self._kernel = self._kernel_of(internal, spec)
        self._peak = internal.peak_pressure if spec.can.film_field else None  # Capabilities.film_field
        # states of its own over each doStep (a tilting pad's tilts and rates): stepped, saved with the FMU state
        self._stepped = internal if spec.can.step_states else None
        self._pad_report = getattr(internal, "pad_report", None) if spec.can.pads else None

    def _kernel_of(self, internal, spec):
        """(call, address, data, out, compiled force) of the internal's compiled kernel
        (``internals.compiled``: the same numbers as force_and_jacobian, a third of its cost from
        Python) when a step may use it: a memoryless internal (thermal off) keeping no flag of its
        own per call (``last_out_of_domain``) and counting nothing (``sync``); else None."""
        if not (self._memoryless and spec.can.compiled) or hasattr(internal, "last_out_of_domain"):
            return None
        cf = internal.compiled_force()
        if cf is None or cf.sync is not None:
            return None
        from ...internals.compiled import OUT_SIZE, call_kernel

        return call_kernel, cf.address, cf.data, np.zeros(OUT_SIZE), cf

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
        option = next((o for o in sorted(FILE_OPTIONS) if getattr(self, o, None) == name), "data")  # its parameter
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

    def do_step(self, current_time, step_size):
        t = current_time + step_size
        if self._mode is not STEP:  # refused (without the patches: discarded), with the reason when there is one
            if self._mode is INIT and self._init_error:
                return self._fail(f"doStep: step to t = {t:.10g} s refused: {self._init_error}") or False
            return self._fail(refusal("doStep", self._mode)) or False
        if not (0.0 < step_size < _INF and -_INF < current_time < _INF and t < _INF):
            return self._bad_step(current_time, step_size)
        # where the last step ended (or the start time): a step from elsewhere would skip or repeat
        # time the FMU's state went through (T_eff, Taylor's excursions); a memoryless internal
        # (variables.MEMORYLESS, thermal off) declares any point allowed (docs/fmu.md)
        if not self._memoryless and abs(current_time - self._t) > 1e-9 * max(1.0, abs(self._t)) + 1e-6 * step_size:
            return self._fail(f"doStep: currentCommunicationPoint = {current_time!r} s is not where the last step "
                              f"ended (t = {self._t!r} s; the start time before the first step): restore an FMU "
                              "state to step from another time") or False
        if self._discarded is not None:  # no fmi2Terminated: a master retrying unchanged would loop forever
            if self._step_inputs() == self._discarded:
                return self._fail(f"doStep: step to t = {t:.10g} s refused: the step from t = {self._refused_t:.10g} "
                                  "s was discarded and the inputs are unchanged (the state is refused again whatever "
                                  "the step size); set other inputs or restore an FMU state") or False
        try:
            self._step_outputs(step_size)
        except BearingStateError as exc:
            self._log(f"{exc} at t = {t:.10g} s", Fmi2Status.discard)
            self._discarded = self._step_inputs()
            self._refused_t = current_time
            return False
        except Exception as exc:  # noqa: BLE001 - a failure of the internal itself, not of the state
            return self._fail(f"doStep: step to t = {t:.10g} s failed in the {self._internal_name} internal: "
                              f"{self._describe(exc)}") or False
        self._discarded = None
        self._t = t
        return True

    def _step_inputs(self) -> tuple:
        """The inputs a step is taken at (T_supply too), bit for bit: what a retry is compared by."""
        return tuple(float(getattr(self, name)).hex() for name in INPUTS)

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
        params = self._params  # the inputs are finite: setReal refuses others, a state read back is checked
        eps = math.hypot(y, z) / params.CR
        internal = self._internal
        if self._guard is not None:  # an excursion begins where the committed state (an FMU state's) was inside
            self._guard.outside = self.out_of_domain
        stepped = self._stepped
        if stepped is not None:  # from the committed states over the step; dt None: at rest (they become the state)
            stepped.begin_step(0.0 if dt is None else dt)
        self._pending = []
        try:
            kernel = self._kernel
            if self.compute_tangent and kernel is not None and kernel[0](kernel[1], kernel[2], y, z, vy, vz, omega,
                                                                          kernel[3]) == 0:
                # out: F (2) and J (2, 4) = dF/d(y, z, vy, vz) row-major; a refused state (status
                # not 0) is asked again below, where force_and_jacobian raises with its message
                f0, f1, q00, q01, v00, v01, q10, q11, v10, v11 = kernel[3].tolist()
                f = (f0, f1)
                tangent = (-q00, -q01, -q10, -q11, -v00, -v01, -v10, -v11)
            elif self.compute_tangent:
                if self._jacobian is not None:
                    f, dq, dv = self._jacobian(y, z, vy, vz, omega)
                else:
                    from ...physics.statics import film_jacobian

                    f, dq, dv = film_jacobian(internal, y, z, vy, vz, omega)
                if type(dq) is not np.ndarray or type(dv) is not np.ndarray:
                    dq, dv = np.asarray(dq, dtype=float), np.asarray(dv, dtype=float)
                (q00, q01), (q10, q11) = dq.tolist()  # Python floats: the same values as float() of each
                (v00, v01), (v10, v11) = dv.tolist()
                tangent = (-q00, -q01, -q10, -q11, -v00, -v01, -v10, -v11)
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
        total = fy + fz + (sum(tangent) if tangent else 0.0)  # finite when every term is (else checked one by one)
        if total - total != 0.0 and (not (math.isfinite(fy) and math.isfinite(fz))
                                     or (tangent and not all(map(math.isfinite, tangent)))):
            raise BearingStateError(
                f"the {self._internal_name} internal returned a non-finite force or tangent at "
                f"y = {y:.6g} m, z = {z:.6g} m, vy = {vy:.6g} m/s, vz = {vz:.6g} m/s, omega = {omega:.6g} rad/s")
        ood = getattr(internal, "last_out_of_domain", False)  # the domain guard's verdict on this state
        # the film's peak pressure: read from the field of the force call just made (no second solve); at
        # the effective viscosity the field scales as the force does
        peak = self._peak(y, z, vy, vz, omega) if self._peak is not None else (0.0, 0.0)
        peak = (peak[0] * factor, peak[1]) if self._oil is not None else peak
        # all evaluated: commit the outputs
        self.Fy, self.Fz = fy, fz
        self.eccentricity = eps
        self.h_min = params.CR * (1.0 - eps)
        self.out_of_domain = bool(ood)
        self.T_eff, self.mu_eff, self.P_loss, self.Q_side = heat
        self.peak_pressure, self.peak_pressure_angle = float(peak[0]), float(peak[1])
        if tangent is not None:
            (self.Kyy, self.Kyz, self.Kzy, self.Kzz, self.Cyy, self.Cyz, self.Czy, self.Czz) = tangent
        if stepped is not None and dt is not None:
            stepped.accept_step()
        if self._pad_report is not None:
            tilts, loads = self._pad_report()
            self.__dict__.update(zip(ports.PAD_TILTS, tilts.tolist()))
            self.__dict__.update(zip(ports.PAD_LOADS, loads.tolist()))
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
