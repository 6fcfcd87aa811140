"""Static evaluations in Initialization Mode, for bearing FMUs with states of their own over a step.

An FMU whose model description declares the internal chosen with states of its own over a step (a
tilting pad's tilts and rates: ``stepStates`` of the bearing_fmu vendor annotation,
``bearing_fmu.fmu.meta``) answers in Initialization Mode with those states at rest (the pads in
moment equilibrium at the inputs set), which is what a static evaluation (the rotor's static
equilibrium) asks; a static probe by a short doStep, as ``cosim.FMUBearings`` makes for the other
FMUs, would move the pads instead of settling them. So its instances wait in Initialization Mode
(``_in_init``) until the first time step: each static evaluation is setReal then getReal there, and
exitInitializationMode at the first time step starts the states at the last static evaluation's
inputs, where the in-process internal starts them too.
"""

from __future__ import annotations

from pathlib import Path

from bearing_fmu.io.interrupts import deferred


class InitStatics:
    """The Initialization-Mode part of ``cosim.FMUBearings`` (its instances, buffers and messages)."""

    _in_init = False  # the instances wait in Initialization Mode

    def _declared_stepped(self, md, parameters) -> bool:
        """Whether every instance's internal, as ``parameters`` choose it, has states of its own over a
        step (the model description's ``stepStates``): the instances then wait in Initialization Mode
        (module docstring)."""
        from bearing_fmu.fmu.meta import step_states_declaration

        declared = step_states_declaration((Path(self._unzip) / "modelDescription.xml").read_bytes())
        if not declared or md.coSimulation is None:
            return False
        return all(self._internal_chosen(k, p) in declared for k, p in enumerate(parameters))

    def _leave_init(self) -> None:
        """exitInitializationMode of every instance: the states of its own start at the inputs set last."""
        self._in_init = False
        with deferred():
            for k, fmu in enumerate(self.instances):
                self._check(k, "fmi2ExitInitializationMode", fmu.dll.fmi2ExitInitializationMode(fmu.component))
                self._initialised.add(k)

    def _init_bearing(self, k, y, z, vy, vz):
        """A static evaluation in Initialization Mode: setReal, then getReal computes the outputs at the
        inputs (quasi-static); a state the FMU refuses (an error status there: no doStep to discard) cuts
        the step as a discard does, with the FMU's words."""
        fmu = self.instances[k]
        c, dll = fmu.component, fmu.dll
        b = self._buf_in
        b[0], b[1], b[2], b[3], b[4] = y, z, vy, vz, self.omega
        self._check(k, "fmi2SetReal", dll.fmi2SetReal(c, self._vr_in, len(b), b))
        n_msg = len(self.messages[k])
        status = dll.fmi2GetReal(c, self._vr_out, len(self._buf_out), self._buf_out)
        if status > 1:
            new = self.messages[k][n_msg:]
            raise self._reject(k, new[-1] if new else f"fmi2GetReal returned {self._status_name(status)}")
        o = self._out
        if o[10] > self.max_eccentricity[k]:
            self.max_eccentricity[k] = o[10]
        if not self.with_jacobian:
            return self._f_view, None, None
        return self._f_view, self._dq_view, self._dv_view

