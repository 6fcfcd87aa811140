"""Drive the bearing FMU from fmpy, the way an fmpy user would.

1. ``simulate``: ``fmpy.simulate_fmu`` with an input table (a whirling journal orbit).
   fmpy applies the inputs at the *start* of each communication step and the FMU computes
   its outputs in doStep from the inputs it holds, so the row at t_k of the result is the
   force at the table's state at t_{k-1}.
2. ``BearingInstance``: one FMU instance through fmpy's ``FMU2Slave``, with the FMI 2.0
   conformant iteration inside a step that a co-simulation master with an implicit
   integrator needs: save the state once per step, then per iterate restore it, set the
   inputs, doStep, get the outputs.
3. ``--timing``: instantiate, initialisation, first step, per-step and per-iterate costs.

    python examples/drive_fmu_with_fmpy.py                    # builds the FMU into a temp dir
    python examples/drive_fmu_with_fmpy.py bearing.fmu --internal linear
    python examples/drive_fmu_with_fmpy.py bearing.fmu --timing
"""

from __future__ import annotations

import argparse
import ctypes
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

INPUTS = ("y", "z", "vy", "vz", "omega")
OUTPUTS = ("Fy", "Fz", "eccentricity", "h_min", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")
OMEGA = 2 * math.pi * 22.0  # the paper rotor's speed [rad/s]


def orbit_table(t_end: float = 0.02, dt: float = 1e-3, omega: float = OMEGA, e: float = 30e-6,
                z0: float = -45e-6):
    """Input table for simulate_fmu: a forward circular whirl of radius e about (0, z0)."""
    t = np.arange(0.0, t_end + 0.5 * dt, dt)
    w = omega / 2  # half-frequency whirl
    sig = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in INPUTS])
    sig["time"] = t
    sig["y"] = e * np.cos(w * t)
    sig["z"] = z0 + e * np.sin(w * t)
    sig["vy"] = -e * w * np.sin(w * t)
    sig["vz"] = e * w * np.cos(w * t)
    sig["omega"] = omega
    return sig


def simulate(fmu: str | Path, start_values: dict | None = None, t_end: float = 0.02, dt: float = 1e-3):
    """Run the FMU with fmpy.simulate_fmu on the orbit table; returns (table, result)."""
    import fmpy

    sig = orbit_table(t_end, dt)
    # debug_logging: without logging on, pythonfmu drops the FMU's messages (why a step was discarded)
    res = fmpy.simulate_fmu(str(fmu), start_time=0.0, stop_time=t_end, output_interval=dt, input=sig,
                            output=list(OUTPUTS), start_values=start_values or {}, debug_logging=True)
    return sig, res


class BearingInstance:
    """One bearing FMU instance via fmpy's FMU2Slave (extract once, reuse the folder).

    ``parameters``: FMU parameter name -> value, set before initialisation. Log lines of the
    FMU are collected in ``messages`` (instantiate with logging on, or they are lost).
    """

    def __init__(self, fmu: str | Path, parameters: dict | None = None, unzip_dir=None, name="bearing"):
        from fmpy import calloc, extract, free, read_model_description
        from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

        self.md = read_model_description(str(fmu))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.unzip_dir = unzip_dir or extract(str(fmu))
        self.messages: list[str] = []

        def logger(_env, _name, status, _category, message):
            self.messages.append(f"[{status}] {message.decode('utf-8', 'replace') if message else ''}")

        self._cb = fmi2CallbackFunctions()  # keep a reference: ctypes callbacks must outlive the instance
        self._cb.logger = fmi2CallbackLoggerTYPE(logger)
        self._cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self._cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        t0 = time.perf_counter()
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip_dir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=self._cb, loggingOn=True)
        t1 = time.perf_counter()
        for key, value in (parameters or {}).items():
            self.set(key, value)
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()  # the internal is built here
        t2 = time.perf_counter()
        self.times = {"instantiate": t1 - t0, "initialize": t2 - t1}
        self.t = 0.0
        # ctypes buffers for the hot path: no allocation per call
        self._vr_in = (ctypes.c_uint * 5)(*[self.vars[n].valueReference for n in INPUTS])
        self._vr_out = (ctypes.c_uint * len(OUTPUTS))(*[self.vars[n].valueReference for n in OUTPUTS])
        self._in = (ctypes.c_double * 5)()
        self._out = (ctypes.c_double * len(OUTPUTS))()

    def set(self, name, value):
        v = self.vars[name]
        vr = [v.valueReference]
        {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "Boolean": self.fmu.setBoolean,
         "String": self.fmu.setString}[v.type](vr, [value])

    def get(self, name):
        v = self.vars[name]
        vr = [v.valueReference]
        value = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger, "Boolean": self.fmu.getBoolean,
                 "String": self.fmu.getString}[v.type](vr)[0]
        return bool(value) if v.type == "Boolean" else value

    def step(self, h: float, y, z, vy, vz, omega) -> dict:
        """Set the state for the end of the step, doStep(t, h), read the outputs; t advances to
        t + h (a step starts where the last one ended: the FMU refuses another time).
        A discarded step raises fmpy's FMICallException (status 2); see ``messages``."""
        b = self._in
        b[0], b[1], b[2], b[3], b[4] = y, z, vy, vz, omega
        f = self.fmu
        f.fmi2SetReal(f.component, self._vr_in, 5, b)
        f.fmi2DoStep(f.component, self.t, h, 0)  # fmpy raises on status >= discard
        self.t += h
        f.fmi2GetReal(f.component, self._vr_out, len(OUTPUTS), self._out)
        return dict(zip(OUTPUTS, self._out))

    # the conformant iteration within one step t -> t + h
    def iterate(self, h: float, states) -> list[dict]:
        """Outputs for each trial end-of-step state of a Newton iteration, then leave the FMU
        at t + h with the last state (the accepted iterate)."""
        saved = self.fmu.getFMUstate()  # once per step
        t = self.t
        try:
            out = []
            for s in states:
                self.fmu.setFMUstate(saved)  # back to t
                self.t = t
                out.append(self.step(h, *s))
        finally:
            self.fmu.freeFMUstate(saved)
        return out

    def close(self):
        try:
            self.fmu.terminate()
        finally:
            self.fmu.freeInstance()


def timing(fmu, parameters: dict, state=(10e-6, -40e-6, 1e-3, 0.0, OMEGA), n=200) -> dict:
    """Costs of one internal (seconds): instantiate, initialise (builds the internal, evaluates
    at the initial inputs), first doStep, mean doStep, mean conformant iterate."""
    inst = BearingInstance(fmu, parameters)
    try:
        times = dict(inst.times)
        h = 1e-4
        t0 = time.perf_counter()
        inst.step(h, *state)
        times["first_step"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        for _ in range(n):
            inst.step(h, *state)
        times["step"] = (time.perf_counter() - t0) / n
        saved = inst.fmu.getFMUstate()
        t_saved = inst.t
        t0 = time.perf_counter()
        for _ in range(n):
            inst.fmu.setFMUstate(saved)
            inst.t = t_saved
            inst.step(h, *state)
        times["iterate"] = (time.perf_counter() - t0) / n
        # the FMI overhead alone: restore + setReal + doStep + getReal minus the internal
        t0 = time.perf_counter()
        for _ in range(n):
            s2 = inst.fmu.getFMUstate()
            inst.fmu.freeFMUstate(s2)
        times["get_free_state"] = (time.perf_counter() - t0) / n
        inst.fmu.freeFMUstate(saved)
        return times
    finally:
        inst.close()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("fmu", nargs="?", help="bearing FMU (default: build one into a temp dir)")
    ap.add_argument("--internal", default="reynolds", help="reynolds | linear | taylor")
    ap.add_argument("--surrogate", help="surrogate JSON to bundle when building the FMU here (taylor)")
    ap.add_argument("--timing", action="store_true", help="measure the costs instead of simulating")
    args = ap.parse_args(argv)
    fmu = args.fmu
    if fmu is None:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
        from bearing_fmu.fmu.build import build_fmu

        fmu = build_fmu(Path(tempfile.mkdtemp()) / "bearing.fmu", surrogate=args.surrogate)
    params = {"internal": args.internal}
    if args.timing:
        for k, v in timing(fmu, params).items():
            print(f"{k:>15s}: {v * 1e3:10.3f} ms")
        return 0
    sig, res = simulate(fmu, params)
    print(f"{'t [s]':>8s} {'y [um]':>8s} {'z [um]':>8s} {'Fy [N]':>10s} {'Fz [N]':>10s} {'eps':>6s}")
    for k in range(1, len(res)):  # row k: force at the inputs of row k - 1
        print(f"{res['time'][k]:8.4f} {sig['y'][k - 1] * 1e6:8.2f} {sig['z'][k - 1] * 1e6:8.2f} "
              f"{res['Fy'][k]:10.4f} {res['Fz'][k]:10.4f} {res['eccentricity'][k]:6.3f}")
    if len(res) < len(sig):
        print(f"simulation stopped at t = {res['time'][-1]:g} s: the FMU discarded a step (see its messages above)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
